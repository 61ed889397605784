//! The triangulation as flat arrays (triangles, their neighbours across each edge, every
//! vertex's ring of neighbours) and the Lawson flips that make it Delaunay again after the
//! generators move. Between two Lloyd or Newton steps few edges change: testing every edge and
//! flipping the few that fail costs a fraction of building the triangulation again. The few
//! vertices whose move would turn a triangle over are removed and inserted again instead.
use geometry::DVec2;
use rayon::prelude::*;
use robust::{incircle, Coord};

/// No triangle (across a hull edge) or no vertex.
pub(crate) const NONE: u32 = u32::MAX;

/// Vertices per parallel chunk of ring passes.
const CHUNK: usize = 4096;
/// Room for this many more neighbours in every ring, so that after a few flips only the rings
/// of the flipped quadrilaterals' corners are rewritten, in place.
const SLACK: usize = 3;

/// Every vertex's Delaunay neighbours in CCW order. An interior vertex's ring starts at the
/// neighbour with the smallest key (its input index), a hull vertex's right after the outer
/// face, so the same triangulation gives the same rings however it was built or numbered.
#[derive(Debug, Default)]
pub(crate) struct Rings {
    /// Ring of vertex v: `nb[start[v]..start[v] + len[v]]`, with room for `room[v]`
    /// (contiguous after a fill; a ring that outgrows its room moves to the end).
    pub start: Vec<usize>,
    pub len: Vec<u32>,
    pub room: Vec<u32>,
    pub nb: Vec<u32>,
    /// `outer[k]`: the face between `nb[k]` and the next neighbour (cyclically) is the outer face.
    pub outer: Vec<bool>,
}

impl Rings {
    /// Neighbours of vertex `v` and the outer-face flags after each.
    pub fn of(&self, v: usize) -> (&[u32], &[bool]) {
        let r = self.start[v]..self.start[v] + self.len[v] as usize;
        (&self.nb[r.clone()], &self.outer[r])
    }

    /// Rebuild from per-vertex degrees and a writer of each ring (in any rotation), in parallel.
    pub fn fill(
        &mut self,
        degree: impl Fn(usize) -> usize + Sync,
        key: &(impl Fn(u32) -> u32 + Sync),
        n: usize,
        write: impl Fn(usize, &mut [u32], &mut [bool]) + Sync,
    ) {
        (0..n)
            .into_par_iter()
            .map(|v| degree(v) as u32)
            .collect_into_vec(&mut self.len);
        self.start.clear();
        self.start.reserve(n + 1);
        self.start.push(0);
        let mut total = 0;
        for &d in &self.len {
            total += d as usize + SLACK;
            self.start.push(total);
        }
        self.nb.clear();
        self.outer.clear();
        self.nb.resize(total, NONE);
        self.outer.resize(total, false);
        self.room.clear();
        self.room.extend(self.len.iter().map(|&d| d + SLACK as u32));
        crate::sparse::par_rows(
            &self.start,
            &mut self.len,
            &mut self.nb,
            &mut self.outer,
            CHUNK,
            || (),
            |_, v, len, nb, outer| {
                let l = *len as usize;
                let (nb, outer) = (&mut nb[..l], &mut outer[..l]);
                write(v, nb, outer);
                canonical(nb, outer, key);
            },
        );
    }

    /// Rewrite the rings of `touched` vertices from `topo`: in place, or at the end of the
    /// arrays for a ring that outgrew its room (a full refill would cost O(n) per update).
    pub fn update(&mut self, topo: &Topology, touched: &[u32], key: &impl Fn(u32) -> u32) {
        for &v in touched {
            let v = v as usize;
            if v >= self.room.len() {
                continue;
            }
            let n = topo.walk(v as u32, |_, _| {});
            if n > self.room[v] as usize {
                self.start[v] = self.nb.len();
                self.room[v] = (n + SLACK) as u32;
                self.nb.resize(self.start[v] + n + SLACK, NONE);
                self.outer.resize(self.start[v] + n + SLACK, false);
            }
            let s = self.start[v];
            let (nb, outer) = (&mut self.nb[s..s + n], &mut self.outer[s..s + n]);
            let mut k = 0;
            topo.walk(v as u32, |u, o| {
                nb[k] = u;
                outer[k] = o;
                k += 1;
            });
            self.len[v] = n as u32;
            canonical(nb, outer, key);
        }
    }
}

/// Rotate a ring to its canonical start: the neighbour with the smallest key that follows an
/// outer face, or with the smallest key if there is none.
fn canonical(nb: &mut [u32], outer: &mut [bool], key: &impl Fn(u32) -> u32) {
    let n = nb.len();
    if n == 0 {
        return;
    }
    let after_outer = (0..n).filter(|&k| outer[(k + n - 1) % n]);
    let start = match after_outer.min_by_key(|&k| key(nb[k])) {
        Some(k) => k,
        None => (0..n).min_by_key(|&k| key(nb[k])).unwrap_or(0),
    };
    nb.rotate_left(start);
    outer.rotate_left(start);
}

/// What [`Topology::moved_stars`] finds around vertices moved together.
#[derive(Default)]
pub(crate) struct MovedStars {
    /// The vertices with a triangle that turned over, on the hull or in no triangle: Lawson
    /// flips cannot repair their moves (nothing below is listed for them).
    pub blocked: Vec<u32>,
    /// Edges (triangle, slot of the opposite vertex) at the others that stopped being locally
    /// Delaunay; only edges of triangles at a moved vertex can have.
    pub illegal: Vec<(u32, u8)>,
    /// Their neighbours that did not move, with repeats.
    pub halo: Vec<u32>,
}

/// Triangles with their neighbours, for Lawson flips.
#[derive(Clone, Debug, Default)]
pub(crate) struct Topology {
    /// CCW vertex triples.
    pub tri: Vec<[u32; 3]>,
    /// `adj[t][k]`: the triangle across the edge opposite `tri[t][k]` (`NONE` on the hull).
    pub adj: Vec<[u32; 3]>,
    /// One triangle of each vertex (`NONE` for a vertex in no triangle).
    pub v2t: Vec<u32>,
    /// Corners of the quadrilaterals flipped by the last `flip_to_delaunay` (sorted, unique;
    /// possibly unsorted and repeated when it gave up).
    pub touched: Vec<u32>,
    /// Slots of `tri` freed by a vertex removal, for the next insertion.
    pub free: Vec<u32>,
    /// Scratch of insertions: edges to test.
    stack: Vec<(u32, u8)>,
}

/// Two triangles sharing the edge b–c (see `Topology::quad`).
struct Quad {
    a: u32,
    b: u32,
    c: u32,
    d: u32,
    n_ab: u32,
    n_ca: u32,
    n_dc: u32,
    n_bd: u32,
}

/// Where a point lies in the triangulation.
enum Location {
    /// Strictly inside triangle t.
    Inside(u32),
    /// On the edge opposite `tri[t][k]`, strictly between its ends.
    OnEdge(u32, u8),
    /// At vertex v.
    Vertex(u32),
}

pub(crate) fn coord(p: DVec2) -> Coord<f64> {
    Coord { x: p.x, y: p.y }
}

/// `robust::orient2d(a, b, c)` (positive when counter-clockwise), with its floating-point stage
/// written out here (the same operations, bound and value) and its exact stage called only
/// where that stage cannot decide: the walks and the repairs' orientation tests inline it.
#[inline(always)]
fn orient2d(a: Coord<f64>, b: Coord<f64>, c: Coord<f64>) -> f64 {
    // robust's bound for this stage (Ozaki et al.).
    const THETA: f64 = 3.3306690621773722e-16;
    let detleft = (a.x - c.x) * (b.y - c.y);
    let detright = (a.y - c.y) * (b.x - c.x);
    let det = detleft - detright;
    let bound = THETA * (detleft + detright).abs();
    if det >= bound || -det >= bound {
        det
    } else {
        robust::orient2d(a, b, c)
    }
}

/// Whether `d` lies strictly inside the circle through the counter-clockwise `a`, `b`, `c`:
/// `robust::incircle(a, b, c, d) > 0`, with its floating-point stage written out here (the same
/// operations in the same order and the same error bound, so the same answer) and its exact
/// stages called only where that bound cannot decide. Nearly every test of a build or a repair
/// is decided by the first stage, which the call into `robust` (not inlined: its exact stages
/// make it large) wrapped in a call of its own.
#[inline(always)]
fn in_circle(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    // Shewchuk's bound for this stage (robust's ICCERRBOUND_A).
    const BOUND: f64 = (10.0 + 96.0 * f64::EPSILON / 2.0) * (f64::EPSILON / 2.0);
    let (adx, bdx, cdx) = (a.x - d.x, b.x - d.x, c.x - d.x);
    let (ady, bdy, cdy) = (a.y - d.y, b.y - d.y, c.y - d.y);
    let bdxcdy = bdx * cdy;
    let cdxbdy = cdx * bdy;
    let alift = adx * adx + ady * ady;
    let cdxady = cdx * ady;
    let adxcdy = adx * cdy;
    let blift = bdx * bdx + bdy * bdy;
    let adxbdy = adx * bdy;
    let bdxady = bdx * ady;
    let clift = cdx * cdx + cdy * cdy;
    let det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * alift
        + (cdxady.abs() + adxcdy.abs()) * blift
        + (adxbdy.abs() + bdxady.abs()) * clift;
    let bound = BOUND * permanent;
    if det > bound {
        true
    } else if -det > bound {
        false
    } else {
        incircle(coord(a), coord(b), coord(c), coord(d)) > 0.0
    }
}

fn slot(t: &[u32; 3], v: u32) -> usize {
    if t[0] == v {
        0
    } else if t[1] == v {
        1
    } else {
        2
    }
}

impl Topology {
    /// Set `v2t` from `tri` for `n` vertices.
    pub fn index_vertices(&mut self, n: usize) {
        self.v2t.clear();
        self.v2t.resize(n, NONE);
        for (t, tri) in self.tri.iter().enumerate() {
            for &v in tri {
                self.v2t[v as usize] = t as u32;
            }
        }
    }

    /// Calls `f(neighbour, outer_after)` for the neighbours of `v` in CCW order (a hull
    /// vertex's starting after the outer face); returns how many.
    pub fn walk(&self, v: u32, mut f: impl FnMut(u32, bool)) -> usize {
        let t0 = self.v2t[v as usize];
        if t0 == NONE {
            return 0;
        }
        // Around v counter-clockwise from t0: all of the ring for an interior vertex.
        let (mut t, mut i) = (t0 as usize, slot(&self.tri[t0 as usize], v));
        let mut n = 0;
        loop {
            let u = self.adj[t][(i + 1) % 3];
            if u == NONE {
                break;
            }
            n += 1;
            t = u as usize;
            i = slot(&self.tri[t], v);
            if t == t0 as usize {
                // Interior: emit the ring from t0.
                for _ in 0..n {
                    f(self.tri[t][(i + 1) % 3], false);
                    t = self.adj[t][(i + 1) % 3] as usize;
                    i = slot(&self.tri[t], v);
                }
                return n;
            }
        }
        // On the hull: from the clockwise-most triangle to the counter-clockwise-most.
        loop {
            let u = self.adj[t][(i + 2) % 3];
            if u == NONE {
                break;
            }
            t = u as usize;
            i = slot(&self.tri[t], v);
        }
        let mut n = 0;
        loop {
            f(self.tri[t][(i + 1) % 3], false);
            n += 1;
            let u = self.adj[t][(i + 1) % 3];
            if u == NONE {
                f(self.tri[t][(i + 2) % 3], true);
                return n + 1;
            }
            t = u as usize;
            i = slot(&self.tri[t], v);
        }
    }

    /// Rings of the vertices `0..n` (`key`: a vertex's input index, for the canonical start).
    pub fn rings(&self, n: usize, key: &(impl Fn(u32) -> u32 + Sync), rings: &mut Rings) {
        // Degree: the triangles at a vertex, one more on the hull (each hull vertex starts one
        // hull edge).
        let mut degree = vec![0u32; self.v2t.len()];
        for (t, adj) in self.tri.iter().zip(&self.adj) {
            for k in 0..3 {
                degree[t[k] as usize] += 1;
                if adj[k] == NONE {
                    degree[t[(k + 1) % 3] as usize] += 1;
                }
            }
        }
        rings.fill(
            |v| degree[v] as usize,
            key,
            n,
            |v, nb, outer| {
                let mut k = 0;
                self.walk(v as u32, |u, o| {
                    nb[k] = u;
                    outer[k] = o;
                    k += 1;
                });
            },
        );
    }

    /// The fan from `vs[0]` over a convex polygon `vs` (CCW, no three collinear): a start for
    /// insertions.
    pub fn convex_fan(&mut self, vs: &[u32], n: usize) {
        self.tri.clear();
        self.adj.clear();
        self.free.clear();
        let m = vs.len() - 2;
        for j in 0..m {
            self.tri.push([vs[0], vs[j + 1], vs[j + 2]]);
            let next = if j + 1 < m { j as u32 + 1 } else { NONE };
            let prev = if j > 0 { j as u32 - 1 } else { NONE };
            self.adj.push([NONE, next, prev]);
        }
        self.index_vertices(n);
    }

    /// Triangles not strictly positively oriented at `pos`.
    pub fn turned_over(&self, pos: &[DVec2]) -> Vec<[u32; 3]> {
        let p = |v: u32| coord(pos[v as usize]);
        self.tri
            .par_iter()
            .filter(|t| orient2d(p(t[0]), p(t[1]), p(t[2])) <= 0.0)
            .copied()
            .collect()
    }

    /// Make the triangulation Delaunay for the moved vertices `pos` by Lawson flips; returns
    /// how many it took, or None when flips cannot do it: a triangle turned over or the hull
    /// stopped being strictly convex (nothing was changed), or more than `max_flips` flips were
    /// needed (the triangulation is valid but not Delaunay). The caller also checks that no ring
    /// winds twice. With exact predicates the result is the Delaunay triangulation (the same
    /// one as any other construction when no four vertices are cocircular).
    pub fn flip_to_delaunay(&mut self, pos: &[DVec2], max_flips: usize) -> Option<usize> {
        self.touched.clear();
        let (tri, adj) = (&self.tri, &self.adj);
        if tri.is_empty() {
            return None;
        }
        let p = |v: u32| coord(pos[v as usize]);
        let upright = tri
            .par_iter()
            .all(|t| orient2d(p(t[0]), p(t[1]), p(t[2])) > 0.0);
        // Each hull edge a→b (the triangle on its left) and the next hull edge b→c must turn left.
        let convex = upright
            && (0..tri.len()).into_par_iter().all(|t| {
                (0..3).all(|k| {
                    adj[t][k] != NONE || {
                        let (a, b) = (tri[t][(k + 1) % 3], tri[t][(k + 2) % 3]);
                        let c = self.hull_next(b);
                        orient2d(p(a), p(b), p(c)) > 0.0
                    }
                })
            });
        if !convex {
            return None;
        }
        let this = &*self;
        let mut stack: Vec<(u32, u8)> = (0..tri.len())
            .into_par_iter()
            .flat_map_iter(|t| {
                (0..3u8).filter_map(move |k| {
                    let u = adj[t][k as usize];
                    (u != NONE && (t as u32) < u && this.illegal(pos, t as u32, k))
                        .then_some((t as u32, k))
                })
            })
            .collect();
        let mut budget = max_flips;
        let flips = self.lawson(pos, &mut stack, &mut budget)?;
        self.touched.sort_unstable();
        self.touched.dedup();
        Some(flips)
    }

    /// Flip the stacked edges (triangle, slot of the opposite vertex) and the edges their flips
    /// expose until all are locally Delaunay; None after `budget` flips.
    pub(crate) fn lawson(
        &mut self,
        pos: &[DVec2],
        stack: &mut Vec<(u32, u8)>,
        budget: &mut usize,
    ) -> Option<usize> {
        let mut flips = 0;
        while let Some((t, k)) = stack.pop() {
            if self.adj[t as usize][k as usize] == NONE || !self.illegal(pos, t, k) {
                continue;
            }
            if *budget == 0 {
                return None;
            }
            *budget -= 1;
            flips += 1;
            let (t2, u2) = self.flip(t, k as usize);
            stack.extend([(t2.0, t2.1), (t2.0, t2.2), (u2.0, u2.1), (u2.0, u2.2)]);
        }
        Some(flips)
    }

    /// Where `p` lies, by a visibility walk from triangle `t` (which terminates on a Delaunay
    /// triangulation), or None when `p` is outside the hull.
    fn locate(&self, pos: &[DVec2], p: DVec2, mut t: u32) -> Option<Location> {
        let q = coord(p);
        let mut from = NONE;
        for _ in 0..self.tri.len() + 1 {
            let tri = self.tri[t as usize];
            let mut zero = None;
            let mut next = None;
            for k in 0..3 {
                let (a, b) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let u = self.adj[t as usize][k];
                let o = orient2d(coord(pos[a as usize]), coord(pos[b as usize]), q);
                if o < 0.0 && u != from {
                    next = Some(u);
                    break;
                } else if o == 0.0 {
                    if let Some(j) = zero {
                        // On two edges' lines: at their common vertex.
                        return Some(Location::Vertex(tri[3 - k - j as usize]));
                    }
                    zero = Some(k as u8);
                }
            }
            match next {
                Some(u) if u == NONE => return None,
                Some(u) => (from, t) = (t, u),
                None => {
                    // The edge back to `from` was skipped: it cannot separate p (we crossed it).
                    return Some(match zero {
                        Some(k) => Location::OnEdge(t, k),
                        None => Location::Inside(t),
                    });
                }
            }
        }
        None
    }

    /// A slot for a new triangle.
    fn new_triangle(&mut self) -> u32 {
        self.free.pop().unwrap_or_else(|| {
            self.tri.push([NONE; 3]);
            self.adj.push([NONE; 3]);
            (self.tri.len() - 1) as u32
        })
    }

    /// Point `n`'s pointer to `from` at `to` instead.
    fn relink(&mut self, n: u32, from: u32, to: u32) {
        if n != NONE {
            for s in self.adj[n as usize].iter_mut() {
                if *s == from {
                    *s = to;
                }
            }
        }
    }

    /// Insert vertex `v` (not yet in a triangle) at `pos[v]`, starting the walk at triangle
    /// `hint`, and make the triangulation Delaunay again. Fails with the vertex already at
    /// `pos[v]` (nothing changed), or with None when `pos[v]` is outside the hull or the flips
    /// exceed `budget` (the triangulation is then unusable).
    pub fn insert(
        &mut self,
        pos: &[DVec2],
        v: u32,
        hint: u32,
        budget: &mut usize,
    ) -> Result<(), Option<u32>> {
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        match self.locate(pos, pos[v as usize], hint) {
            None => return Err(None),
            Some(Location::Vertex(u)) => return Err(Some(u)),
            Some(Location::Inside(t)) => {
                let [a, b, c] = self.tri[t as usize];
                let [n_bc, n_ca, n_ab] = self.adj[t as usize];
                let (t1, t2) = (self.new_triangle(), self.new_triangle());
                self.tri[t as usize] = [a, b, v];
                self.adj[t as usize] = [t1, t2, n_ab];
                self.tri[t1 as usize] = [b, c, v];
                self.adj[t1 as usize] = [t2, t, n_bc];
                self.tri[t2 as usize] = [c, a, v];
                self.adj[t2 as usize] = [t, t1, n_ca];
                self.relink(n_bc, t, t1);
                self.relink(n_ca, t, t2);
                for (x, s) in [(a, t), (b, t1), (c, t2), (v, t)] {
                    self.v2t[x as usize] = s;
                }
                self.touched.extend([a, b, c, v]);
                stack.extend([(t, 2), (t1, 2), (t2, 2)]);
            }
            Some(Location::OnEdge(t, k)) => {
                // t = (a, b, c) with p on b–c; u = (d, c, b) across it.
                let (ti, k) = (t as usize, k as usize);
                let u = self.adj[ti][k];
                if u == NONE {
                    return Err(None);
                }
                let ui = u as usize;
                let Quad {
                    a,
                    b,
                    c,
                    d,
                    n_ab,
                    n_ca,
                    n_dc,
                    n_bd,
                } = self.quad(t, k);
                let (t2, u2) = (self.new_triangle(), self.new_triangle());
                self.tri[ti] = [a, b, v];
                self.adj[ti] = [u2, t2, n_ab];
                self.tri[t2 as usize] = [a, v, c];
                self.adj[t2 as usize] = [u, n_ca, t];
                self.tri[ui] = [d, c, v];
                self.adj[ui] = [t2, u2, n_dc];
                self.tri[u2 as usize] = [d, v, b];
                self.adj[u2 as usize] = [t, n_bd, u];
                self.relink(n_ca, t, t2);
                self.relink(n_bd, u, u2);
                for (x, s) in [(a, t), (b, t), (c, u), (d, u), (v, t)] {
                    self.v2t[x as usize] = s;
                }
                self.touched.extend([a, b, c, d, v]);
                stack.extend([(t, 2), (t2, 1), (u, 2), (u2, 1)]);
            }
        }
        let done = self.lawson(pos, &mut stack, budget);
        self.stack = stack;
        done.map(|_| ()).ok_or(None)
    }

    /// Vertex `v` has moved to `pos[v]` (every other vertex staying): if all its triangles are
    /// still upright, make the triangulation Delaunay again by Lawson flips of their edges
    /// (only edges of triangles at `v` can have stopped being locally Delaunay) and return
    /// Some(true); Some(false) when a triangle turned over (nothing changed: remove and insert
    /// instead); None when the flips exceed `budget` (the triangulation is then unusable).
    pub fn move_in_place(&mut self, pos: &[DVec2], v: u32, budget: &mut usize) -> Option<bool> {
        let p = |x: u32| coord(pos[x as usize]);
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        // False also for v on the hull: left to removal and insertion.
        let upright = self.around(v, &mut |t, i| {
            let [a, b, c] = self.tri[t as usize];
            if orient2d(p(a), p(b), p(c)) <= 0.0 {
                return false;
            }
            stack.extend([(t, i as u8), (t, ((i + 1) % 3) as u8)]);
            true
        });
        if !upright {
            self.stack = stack;
            return Some(false);
        }
        let done = self.lawson(pos, &mut stack, budget);
        self.stack = stack;
        done.map(|_| true)
    }

    /// Calls `f(t, slot of v in t)` for every triangle t at `v` until it returns false; false
    /// when it did, or when `v` has no triangle or lies on the hull.
    fn around(&self, v: u32, f: &mut dyn FnMut(u32, usize) -> bool) -> bool {
        let t0 = self.v2t[v as usize];
        if t0 == NONE {
            return false;
        }
        let mut t = t0;
        loop {
            let i = slot(&self.tri[t as usize], v);
            if !f(t, i) {
                return false;
            }
            t = self.adj[t as usize][(i + 1) % 3];
            if t == NONE {
                return false;
            }
            if t == t0 {
                return true;
            }
        }
    }

    /// One pass over the triangles at each vertex of `moved` (moved to their `pos` together,
    /// every other vertex staying), in parallel: see [`MovedStars`].
    pub fn moved_stars(
        &self,
        pos: &[DVec2],
        moved: &[u32],
        in_moved: impl Fn(u32) -> bool + Sync,
    ) -> MovedStars {
        let p = |x: u32| coord(pos[x as usize]);
        let parts: Vec<MovedStars> = moved
            .par_chunks(256)
            .map(|chunk| {
                let mut out = MovedStars::default();
                for &v in chunk {
                    let (illegal, halo) = (out.illegal.len(), out.halo.len());
                    let upright = self.around(v, &mut |t, i| {
                        let tri = self.tri[t as usize];
                        if orient2d(p(tri[0]), p(tri[1]), p(tri[2])) <= 0.0 {
                            return false;
                        }
                        // The far edge and one of the two edges at v (the other is the next
                        // triangle's), as `move_in_place` stacks them; each edge from one star
                        // only: an edge at v from the lesser of its ends that moved, the far
                        // edge where neither of its ends did (else it is an edge at one).
                        let w = tri[(i + 2) % 3];
                        let far_own = !in_moved(tri[(i + 1) % 3]) && !in_moved(w);
                        let near_own = v < w || !in_moved(w);
                        for (k, own) in [(i, far_own), ((i + 1) % 3, near_own)] {
                            if own
                                && self.adj[t as usize][k] != NONE
                                && self.illegal(pos, t, k as u8)
                            {
                                out.illegal.push((t, k as u8));
                            }
                        }
                        let u = tri[(i + 1) % 3];
                        if !in_moved(u) {
                            out.halo.push(u);
                        }
                        true
                    });
                    if !upright {
                        out.blocked.push(v);
                        out.illegal.truncate(illegal);
                        out.halo.truncate(halo);
                    }
                }
                out
            })
            .collect();
        let mut all = MovedStars::default();
        for part in parts {
            all.blocked.extend(part.blocked);
            all.illegal.extend(part.illegal);
            all.halo.extend(part.halo);
        }
        all
    }

    /// Remove interior vertex `v`: the hole (star-shaped around `pos[v]`) is cut into ears and
    /// flipped to Delaunay. Returns a triangle of the hole, or None when `v` is on the hull, no
    /// ear is found (degenerate hole) or the flips exceed `budget`.
    pub fn remove(&mut self, pos: &[DVec2], v: u32, budget: &mut usize) -> Option<u32> {
        // The ring: for each neighbour u_i (CCW), the triangle (v, u_i, u_i+1), and across its
        // far edge the outside triangle with the slot pointing back.
        let t0 = self.v2t[v as usize];
        if t0 == NONE {
            return None;
        }
        let mut ring: Vec<(u32, (u32, u8))> = Vec::new();
        let mut slots: Vec<u32> = Vec::new();
        let mut t = t0;
        loop {
            let ti = t as usize;
            let i = slot(&self.tri[ti], v);
            let out = self.adj[ti][i];
            let back = if out == NONE {
                0
            } else {
                (0..3).find(|&j| self.adj[out as usize][j] == t)? as u8
            };
            ring.push((self.tri[ti][(i + 1) % 3], (out, back)));
            slots.push(t);
            t = self.adj[ti][(i + 1) % 3];
            if t == NONE {
                return None;
            }
            if t == t0 {
                break;
            }
            if ring.len() > self.tri.len() {
                return None;
            }
        }
        self.v2t[v as usize] = NONE;
        self.free.extend(slots.iter().rev());
        let p = |x: u32| coord(pos[x as usize]);
        // Polygon vertices with the outside of the edge to the next one.
        let mut stack = Vec::new();
        let mut last = NONE;
        while ring.len() >= 3 {
            let m = ring.len();
            let ear = (0..m).find(|&i| {
                let (a, b, c) = (ring[(i + m - 1) % m].0, ring[i].0, ring[(i + 1) % m].0);
                orient2d(p(a), p(b), p(c)) > 0.0
                    && ring.iter().all(|&(x, _)| {
                        x == a
                            || x == b
                            || x == c
                            || orient2d(p(a), p(b), p(x)) < 0.0
                            || orient2d(p(b), p(c), p(x)) < 0.0
                            || orient2d(p(c), p(a), p(x)) < 0.0
                    })
            })?;
            let h = (ear + m - 1) % m;
            let (a, b, c) = (ring[h].0, ring[ear].0, ring[(ear + 1) % m].0);
            let (oab, obc) = (ring[h].1, ring[ear].1);
            let n = self.new_triangle();
            self.tri[n as usize] = [a, b, c];
            self.adj[n as usize] = [obc.0, NONE, oab.0];
            for o in [obc, oab] {
                if o.0 != NONE {
                    self.adj[o.0 as usize][o.1 as usize] = n;
                }
            }
            stack.extend([(n, 0), (n, 2)]);
            for x in [a, b, c] {
                self.v2t[x as usize] = n;
            }
            self.touched.extend([a, b, c]);
            if m == 3 {
                // The last ear closes the hole: its third edge c–a is the outside of ring[ear+1].
                let oca = ring[(ear + 1) % m].1;
                self.adj[n as usize][1] = oca.0;
                if oca.0 != NONE {
                    self.adj[oca.0 as usize][oca.1 as usize] = n;
                }
                stack.push((n, 1));
                last = n;
                break;
            }
            // The new diagonal a–c: its outside is n, slot 1 (opposite b).
            ring[h].1 = (n, 1);
            ring.remove(ear);
        }
        self.touched.push(v);
        self.lawson(pos, &mut stack, budget)?;
        Some(last)
    }

    /// The hull vertex after `b` going CCW along the hull (b must be on the hull).
    fn hull_next(&self, b: u32) -> u32 {
        // b's CW-most triangle has the hull edge b → next on its CW side.
        let t0 = self.v2t[b as usize];
        let (mut t, mut i) = (t0 as usize, slot(&self.tri[t0 as usize], b));
        loop {
            let u = self.adj[t][(i + 2) % 3];
            if u == NONE {
                return self.tri[t][(i + 1) % 3];
            }
            if u == t0 {
                return b;
            }
            t = u as usize;
            i = slot(&self.tri[t], b);
        }
    }

    /// Edge opposite `tri[t][k]` is not locally Delaunay: the far vertex of the neighbour lies
    /// strictly inside the circumcircle of t.
    fn illegal(&self, pos: &[DVec2], t: u32, k: u8) -> bool {
        let (t, k) = (t as usize, k as usize);
        let u = self.adj[t][k] as usize;
        let j = (0..3).find(|&j| self.adj[u][j] == t as u32).unwrap_or(0);
        let [a, b, c] = self.tri[t];
        let d = self.tri[u][j];
        let p = |v: u32| pos[v as usize];
        in_circle(p(a), p(b), p(c), p(d))
    }

    /// The quadrilateral of triangle t = (a, b, c), a = `tri[t][k]`, and its neighbour
    /// u = (d, c, b) across b–c, with the triangles outside its four sides.
    fn quad(&self, t: u32, k: usize) -> Quad {
        let (ti, ui) = (t as usize, self.adj[t as usize][k] as usize);
        let j = (0..3).find(|&j| self.adj[ui][j] == t).unwrap_or(0);
        Quad {
            a: self.tri[ti][k],
            b: self.tri[ti][(k + 1) % 3],
            c: self.tri[ti][(k + 2) % 3],
            d: self.tri[ui][j],
            n_ab: self.adj[ti][(k + 2) % 3],
            n_ca: self.adj[ti][(k + 1) % 3],
            n_dc: self.adj[ui][(j + 2) % 3],
            n_bd: self.adj[ui][(j + 1) % 3],
        }
    }

    /// Flip the edge opposite `tri[t][k]`. Returns the two new triangles with the slots of their
    /// two edges that were on the quadrilateral's boundary: (t, 0, 2) and (u, 0, 1).
    fn flip(&mut self, t: u32, k: usize) -> ((u32, u8, u8), (u32, u8, u8)) {
        let (ti, u) = (t as usize, self.adj[t as usize][k]);
        let ui = u as usize;
        let Quad {
            a,
            b,
            c,
            d,
            n_ab,
            n_ca,
            n_dc,
            n_bd,
        } = self.quad(t, k);
        // t = (a, b, d), u = (a, d, c).
        self.tri[ti] = [a, b, d];
        self.adj[ti] = [n_bd, u, n_ab];
        self.tri[ui] = [a, d, c];
        self.adj[ui] = [n_dc, n_ca, t];
        self.relink(n_bd, u, t);
        self.relink(n_ca, t, u);
        for v in [a, b, d] {
            self.v2t[v as usize] = t;
        }
        self.v2t[c as usize] = u;
        self.touched.extend([a, b, c, d]);
        ((t, 0, 2), (u, 0, 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::Rng;

    /// The inlined first stage decides as `robust::incircle` does: on random points, on points
    /// of an integer lattice (exactly cocircular squares, decided by the exact stages), on
    /// lattices jittered by rounding-level amounts, and on points near a common circle.
    #[test]
    fn in_circle_answers_as_the_exact_predicate() {
        let mut rng = Rng::new(5);
        let exact = |a: DVec2, b: DVec2, c: DVec2, d: DVec2| {
            incircle(coord(a), coord(b), coord(c), coord(d)) > 0.0
        };
        let mut near = 0;
        for round in 0..200_000 {
            let pick = |rng: &mut Rng| match round % 4 {
                0 => DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
                1 => DVec2::new(rng.below(4) as f64, rng.below(4) as f64),
                2 => {
                    DVec2::new(rng.below(4) as f64, rng.below(4) as f64) * 0.1
                        + DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 1e-17
                }
                _ => {
                    DVec2::from_angle(rng.range(0.0, std::f64::consts::TAU)) * 3.0
                        + DVec2::splat(1e3)
                }
            };
            let (a, b, c, d) = (
                pick(&mut rng),
                pick(&mut rng),
                pick(&mut rng),
                pick(&mut rng),
            );
            let (b, c) = if (b - a).perp_dot(c - a) < 0.0 {
                (c, b)
            } else {
                (b, c)
            };
            let fast = in_circle(a, b, c, d);
            assert_eq!(fast, exact(a, b, c, d), "{a} {b} {c} {d}");
            near += usize::from(incircle(coord(a), coord(b), coord(c), coord(d)) == 0.0);
        }
        // The exact stages were reached: cocircular and coincident quadruples were drawn.
        assert!(near > 1000, "{near}");
    }

    /// The inlined orientation gives `robust::orient2d`'s value, bit for bit, on random,
    /// lattice (exactly collinear) and rounding-level jittered lattice points.
    #[test]
    fn orient2d_gives_the_exact_predicates_value() {
        let mut rng = Rng::new(9);
        let mut zero = 0;
        for round in 0..200_000 {
            let pick = |rng: &mut Rng| match round % 3 {
                0 => DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
                1 => DVec2::new(rng.below(4) as f64, rng.below(4) as f64),
                _ => {
                    DVec2::new(rng.below(4) as f64, rng.below(4) as f64) * 0.1
                        + DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 1e-17
                }
            };
            let (a, b, c) = (
                coord(pick(&mut rng)),
                coord(pick(&mut rng)),
                coord(pick(&mut rng)),
            );
            let (ours, theirs) = (orient2d(a, b, c), robust::orient2d(a, b, c));
            assert_eq!(ours.to_bits(), theirs.to_bits());
            zero += usize::from(theirs == 0.0);
        }
        assert!(zero > 1000, "{zero}");
    }
}
