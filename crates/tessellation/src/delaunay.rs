//! Delaunay triangulation of generators, built by inserting in Hilbert-curve order: each
//! point is then located by a short walk from the previously inserted one, where points in
//! input order would make every walk cross much of the triangulation.
use crate::topology::{Rings, Topology, NONE};
use geometry::DVec2;
use rayon::prelude::*;
use spade::handles::FixedVertexHandle;
use spade::{DelaunayTriangulation, Point2, Triangulation};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::OnceLock;

/// A rebuild by flips gives up (and triangulates afresh) beyond this many flips per triangle.
const MAX_FLIP_FRACTION: usize = 8;
/// From this many moved points on, `move_points` moves them together and tests the triangles
/// at them in parallel, rather than one by one.
const MOVE_TOGETHER_FROM: usize = 512;
/// Vertices of the frame around a framed triangulation.
const FRAME: usize = 8;

/// From this many points on, a fresh framed build triangulates the two halves of the points
/// (either side of their median abscissa) on two threads and joins them (`halves`): the same
/// triangulation, its triangles stored in another order.
const HALVES_FROM: usize = 50_000;

/// Delaunay triangulation of a point set. Vertex `i` is `points[i]` (duplicates are merged
/// onto the first occurrence; `vertex_of` maps each input point to its vertex).
///
/// Points with non-finite coordinates (or coordinates spade rejects) are not inserted: they have
/// no vertex, no neighbours and an empty Voronoi cell.
pub struct Delaunay {
    /// Every vertex's neighbours in CCW order, canonically rotated.
    pub(crate) rings: Rings,
    /// Triangles and their neighbours (vertex indices).
    topo: Topology,
    /// Every point is a vertex and there are triangles: the next rebuild may flip edges.
    flippable: bool,
    /// Spade vertex index → input index of the first point at that position.
    pub(crate) point_of_vertex: Vec<u32>,
    /// Input index → spade vertex index (`NONE` if not inserted).
    pub(crate) vertex_of_point: Vec<u32>,
    /// Position of each spade vertex (a compact copy for cache-friendly passes).
    pub(crate) pos: Vec<DVec2>,
    /// Start vertices for nearest-point walks, built by the first walk after a build or a
    /// repair by flips (and kept through local moves, whose vertices are still good starts):
    /// most runs never walk (only corners and embedded points are placed that way), and the
    /// grid costs a pass over every vertex.
    hints: OnceLock<HintGrid>,
    /// Hilbert keys of a fresh build (freed after it: most rebuilds repair).
    keys: Vec<u64>,
    /// A bit per vertex, set while `move_points` moves it with many others (all clear
    /// between calls).
    moving: Vec<u64>,
    /// A box to keep inside the frame (`Delaunay::framed`), or None for no frame.
    frame_box: Option<(DVec2, DVec2)>,
    /// Frame vertices of the current triangulation (numbered after the points' vertices).
    framed: usize,
    /// Points farther than `.1` from `.0` send a rebuild to a fresh build (with a new frame).
    frame_safe: (DVec2, f64),
    /// Scratch of rebuilds by flips: the previous positions.
    scratch: Vec<DVec2>,
    /// The last rebuild repaired the previous triangulation by flips.
    flipped: bool,
}

impl Delaunay {
    /// Triangulate `points`.
    ///
    /// ```
    /// use cvtmesh::tessellation::Delaunay;
    /// use cvtmesh::geometry::DVec2;
    /// // A unit square's corners around a point off its centre, and a duplicate of corner 0.
    /// let points = [
    ///     DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y,
    ///     DVec2::new(0.4, 0.55), DVec2::ZERO,
    /// ];
    /// let d = Delaunay::new(&points);
    /// assert_eq!(d.num_vertices(), 5); // the duplicate is merged onto point 0
    /// assert_eq!(d.vertex_of(5), Some(0));
    /// // The inner point is joined to all four corners: four CCW triangles.
    /// assert_eq!(d.triangles().len(), 4);
    /// let mut around = d.neighbors(4);
    /// around.sort();
    /// assert_eq!(around, [0, 1, 2, 3]);
    /// assert_eq!(d.nearest(DVec2::new(0.9, 0.8)), 2);
    /// ```
    pub fn new(points: &[DVec2]) -> Delaunay {
        let mut d = Delaunay {
            rings: Rings::default(),
            topo: Topology::default(),
            flippable: false,
            point_of_vertex: Vec::new(),
            vertex_of_point: Vec::new(),
            pos: Vec::new(),
            hints: OnceLock::new(),
            keys: Vec::new(),
            moving: Vec::new(),
            frame_box: None,
            framed: 0,
            frame_safe: (DVec2::ZERO, 0.0),
            scratch: Vec::new(),
            flipped: false,
        };
        d.rebuild(points);
        d
    }

    /// An empty triangulation whose rebuilds add a frame of 8 fixed vertices far around the
    /// points and the box `lo`–`hi` (where cells are wanted). The frame makes the hull fixed and
    /// convex, so rebuilds of moved points keep repairing by flips where the points' own hull
    /// (often slivers along a boundary layer) would turn over. Frame vertices are not in
    /// `triangles` or `neighbors`; within the box every Voronoi cell and edge is the frameless
    /// one (the frame's bisectors lie more than a box diagonal outside).
    pub fn framed(lo: DVec2, hi: DVec2) -> Delaunay {
        let mut d = Delaunay::new(&[]);
        d.frame_box = Some((lo, hi));
        d
    }

    /// Where cells are wanted from now on (a framed triangulation's next domain, e.g. the next
    /// phase of an iteration): the next fresh build frames this box; the current frame stays
    /// while the box lies within its safe disc, else the next rebuild triangulates afresh.
    pub fn set_frame_box(&mut self, lo: DVec2, hi: DVec2) {
        self.frame_box = Some((lo, hi));
        let (c, r) = self.frame_safe;
        let corners = [lo, hi, DVec2::new(lo.x, hi.y), DVec2::new(hi.x, lo.y)];
        if self.framed > 0 && corners.iter().any(|p| p.distance(c) > r) {
            self.flippable = false;
        }
    }

    /// The canonical ring key of vertex `u`: its input index; frame vertices come last.
    fn key(&self) -> impl Fn(u32) -> u32 + Sync + '_ {
        let nv = self.point_of_vertex.len();
        move |u| match self.point_of_vertex.get(u as usize) {
            Some(&i) => i,
            None => u32::MAX - (FRAME + nv) as u32 + u,
        }
    }

    /// Triangulate `points` in this triangulation's memory: the same result as
    /// [`Delaunay::new`] (up to the choice of diagonal between exactly cocircular points),
    /// without the large allocations. When `points` are the previous points moved (the same
    /// number, all distinct vertices, no triangle turned over, every ring winding once, the hull
    /// still strictly convex — directly or in 4 substeps), the previous triangulation is
    /// repaired by Lawson flips, whose cost grows with the number of flips needed (few for
    /// small moves) instead of with a full insertion of every point.
    /// A framed triangulation also repairs moves that turn triangles over, by removing and
    /// reinserting the vertices that moved farthest. Otherwise it is built afresh.
    pub fn rebuild(&mut self, points: &[DVec2]) {
        self.flipped = self.flip_to(points);
        if !self.flipped {
            self.build(points);
        }
    }

    /// Whether this triangulation is already the one [`Delaunay::rebuild`] would repair it to
    /// for `points`: every point a vertex of the last triangulation built or repaired, and each
    /// at its vertex's position to the bit. Such a rebuild would flip no edge (every repair
    /// ends legal) and costs a pass over every edge: a caller holding the last iterate's
    /// triangulation can skip it.
    ///
    /// ```
    /// use cvtmesh::geometry::DVec2;
    /// use cvtmesh::tessellation::Delaunay;
    /// let mut pts = vec![DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::new(1.0, 1.2)];
    /// let mut del = Delaunay::new(&pts);
    /// assert!(del.is_at(&pts));
    /// pts[3].x += 0.1;
    /// assert!(!del.is_at(&pts));
    /// del.rebuild(&pts);
    /// assert!(del.is_at(&pts));
    /// ```
    pub fn is_at(&self, points: &[DVec2]) -> bool {
        let of = &self.point_of_vertex;
        self.flippable
            && points.len() == self.num_points()
            && of.len() == points.len()
            && (0..of.len()).into_par_iter().with_min_len(4096).all(|v| {
                let (p, q) = (self.pos[v], points[of[v] as usize]);
                p.x.to_bits() == q.x.to_bits() && p.y.to_bits() == q.y.to_bits()
            })
    }

    /// Move only the points `moved` (input indices) to their positions in `points`; every other
    /// point must be where it was. Each moved vertex is repaired by Lawson flips around it when
    /// its triangles stay upright, else removed and inserted again: O(its degree) instead of a
    /// pass over every edge, for active-set iterations where a few hundred to a few tens of
    /// thousands of 10⁵–10⁶ generators move. From `MOVE_TOGETHER_FROM` points on they are
    /// moved together, the triangles at them tested in parallel, which gives the same
    /// triangulation (up to the diagonals of cocircular quadrilaterals) with its triangles
    /// possibly stored in another order. Returns the vertices whose Voronoi cells may have changed
    /// (the moved ones and their neighbours before and after, sorted), or None when the
    /// triangulation is not framed or a move cannot be done locally (a duplicate, a point
    /// outside the frame): it is then rebuilt from `points` by [`Delaunay::rebuild`].
    pub fn move_points(&mut self, points: &[DVec2], moved: &[u32]) -> Option<Vec<u32>> {
        let mut affected = Vec::new();
        if self.framed > 0 && points.len() == self.num_points() && self.flippable {
            let done = if moved.len() >= MOVE_TOGETHER_FROM {
                self.move_together(points, moved, &mut affected)
            } else {
                self.move_each(points, moved, &mut affected)
            };
            if done {
                self.flipped = true;
                return Some(affected);
            }
            self.flippable = false;
        }
        self.rebuild(points);
        None
    }

    /// `move_points` for many points at once: all are moved, those whose triangles stay upright
    /// are repaired together (their stars tested in parallel by [`Topology::moved_stars`],
    /// the edges found illegal flipped), and the rest (a triangle turned over, e.g. a thin one
    /// to the frame) go back and are then moved one by one ([`Delaunay::move_each`]). False
    /// when the topology is unusable.
    fn move_together(&mut self, points: &[DVec2], moved: &[u32], affected: &mut Vec<u32>) -> bool {
        let nv = self.point_of_vertex.len();
        let mut verts = Vec::with_capacity(moved.len());
        for &i in moved {
            let Some(v) = self.movable(points, i) else {
                return false;
            };
            if points[i as usize] != self.pos[v as usize] {
                verts.push(v);
            }
        }
        verts.par_sort_unstable();
        verts.dedup();
        let old: Vec<DVec2> = verts.iter().map(|&v| self.pos[v as usize]).collect();
        for &v in &verts {
            self.pos[v as usize] = points[self.point_of_vertex[v as usize] as usize];
        }
        // Which vertices move together: a bit each (left all clear after).
        let mut bits = std::mem::take(&mut self.moving);
        bits.resize(self.pos.len().div_ceil(64), 0);
        let flip_bit = |bits: &mut [u64], v: u32| bits[v as usize / 64] ^= 1 << (v % 64);
        for &v in &verts {
            flip_bit(&mut bits, v);
        }
        // Send back the vertices of turned-over triangles until every triangle is upright (at
        // worst all of them: the triangulation before the move).
        let mut together = verts.clone();
        let mut one_by_one: Vec<u32> = Vec::new();
        let stars = loop {
            // `blocked` comes in the order of `together`: sorted.
            let stars = self.topo.moved_stars(&self.pos, &together, |u| {
                bits.get(u as usize / 64)
                    .is_some_and(|b| b >> (u % 64) & 1 == 1)
            });
            if stars.blocked.is_empty() {
                break stars;
            }
            together.retain(|v| stars.blocked.binary_search(v).is_err());
            for &v in &stars.blocked {
                flip_bit(&mut bits, v);
                let k = verts.binary_search(&v).expect("a moved vertex");
                self.pos[v as usize] = old[k];
                one_by_one.push(self.point_of_vertex[v as usize]);
            }
        };
        for &v in &together {
            flip_bit(&mut bits, v);
        }
        self.moving = bits;
        self.topo.touched.clear();
        let mut budget = self.topo.tri.len() / MAX_FLIP_FRACTION + 64 * moved.len();
        let mut stack = stars.illegal;
        if self
            .topo
            .lawson(&self.pos, &mut stack, &mut budget)
            .is_none()
        {
            return false;
        }
        // Cells that can have changed: the moved vertices', their neighbours' before the flips
        // (`halo`), and those of every vertex a flip gave or took a neighbour (`touched`).
        affected.extend_from_slice(&together);
        affected.extend(stars.halo);
        self.topo.touched.sort_unstable();
        self.topo.touched.dedup();
        affected.extend_from_slice(&self.topo.touched);
        self.update_rings();
        if !one_by_one.is_empty() {
            return self.move_each(points, &one_by_one, affected);
        }
        affected.retain(|&u| (u as usize) < nv);
        affected.par_sort_unstable();
        affected.dedup();
        true
    }

    /// The vertex of point `i` if it can move to `points[i]` locally: a vertex of its own (not
    /// a duplicate), a finite position within the frame's safe disc.
    fn movable(&self, points: &[DVec2], i: u32) -> Option<u32> {
        let v = self.vertex_of_point[i as usize];
        let p = points[i as usize];
        let (c, r) = self.frame_safe;
        (v != NONE && self.point_of_vertex[v as usize] == i && p.is_finite() && p.distance(c) <= r)
            .then_some(v)
    }

    /// `move_points` by removal and insertion; false (the topology is then unusable) when a
    /// vertex cannot be moved so.
    fn move_each(&mut self, points: &[DVec2], moved: &[u32], affected: &mut Vec<u32>) -> bool {
        let nv = self.point_of_vertex.len();
        // A removal and an insertion take about twice the vertex's degree in flips.
        let mut budget = self.topo.tri.len() / MAX_FLIP_FRACTION + 64 * moved.len();
        self.topo.touched.clear();
        for &i in moved {
            let Some(v) = self.movable(points, i) else {
                return false;
            };
            let p = points[i as usize];
            if p == self.pos[v as usize] {
                continue;
            }
            self.topo.walk(v, |u, _| affected.push(u));
            // A small move keeps v's triangles upright: flips around v suffice. Otherwise v is
            // removed and inserted at its new position.
            let old = std::mem::replace(&mut self.pos[v as usize], p);
            match self.topo.move_in_place(&self.pos, v, &mut budget) {
                Some(true) => {}
                Some(false) => {
                    self.pos[v as usize] = old;
                    let Some(hint) = self.topo.remove(&self.pos, v, &mut budget) else {
                        return false;
                    };
                    self.pos[v as usize] = p;
                    if self.topo.insert(&self.pos, v, hint, &mut budget).is_err() {
                        return false;
                    }
                }
                None => return false,
            }
            self.topo.walk(v, |u, _| affected.push(u));
            affected.push(v);
        }
        if !self.topo.free.is_empty() {
            return false;
        }
        let mut touched = std::mem::take(&mut self.topo.touched);
        touched.sort_unstable();
        touched.dedup();
        affected.extend_from_slice(&touched);
        self.topo.touched = touched;
        self.update_rings();
        affected.retain(|&u| (u as usize) < nv);
        affected.sort_unstable();
        affected.dedup();
        true
    }

    /// Whether the last rebuild repaired the previous triangulation by flips (rather than
    /// building afresh).
    pub fn flipped(&self) -> bool {
        self.flipped
    }

    /// Rebuild by flips; false when that is not possible (the state is then rebuilt by `build`).
    /// A move that turns a triangle over is repaired by reinsertions when framed; unframed, it
    /// is retried in `SUBSTEPS` straight-line steps, flipping after each: a vertex heading for
    /// an edge enters its neighbours' circumcircles, and is flipped past, before it reaches the
    /// edge.
    fn flip_to(&mut self, points: &[DVec2]) -> bool {
        const SUBSTEPS: usize = 4;
        if !self.flippable || points.len() != self.num_points() {
            return false;
        }
        self.flippable = false;
        let nv = self.point_of_vertex.len();
        let (c, r) = self.frame_safe;
        let framed = self.framed > 0;
        let of = &self.point_of_vertex;
        let safe = (0..nv).into_par_iter().all(|v| {
            let p = points[of[v] as usize];
            p.is_finite() && (!framed || p.distance(c) <= r)
        });
        if !safe {
            return false;
        }
        let max_flips = self.topo.tri.len() / MAX_FLIP_FRACTION;
        let mut old = std::mem::take(&mut self.scratch);
        old.clear();
        old.extend_from_slice(&self.pos[..nv]);
        let done = match self.step(points, &old, 1, 1, max_flips) {
            Some(done) => done,
            // A triangle turned over (nothing changed yet).
            None if framed => self.reinsert(points, &old, max_flips),
            None => (1..=SUBSTEPS)
                .all(|step| self.step(points, &old, step, SUBSTEPS, max_flips) == Some(true)),
        };
        self.scratch = old;
        if !done {
            return false;
        }
        self.hints = OnceLock::new();
        self.flippable = true;
        true
    }

    /// Move the vertices `step / steps` of the way from `old` to `points` and flip: Some(true)
    /// when that made a Delaunay triangulation, None when it failed without changing the
    /// topology (a triangle turned over, a ring wound twice), Some(false) otherwise.
    fn step(
        &mut self,
        points: &[DVec2],
        old: &[DVec2],
        step: usize,
        steps: usize,
        max_flips: usize,
    ) -> Option<bool> {
        let nv = old.len();
        self.topo.touched.clear();
        let t = step as f64 / steps as f64;
        let of = &self.point_of_vertex;
        self.pos[..nv]
            .par_iter_mut()
            .enumerate()
            .for_each(|(v, p)| {
                let to = points[of[v] as usize];
                *p = if step < steps { old[v].lerp(to, t) } else { to };
            });
        // Positively oriented triangles can still fold over (a ring winding twice): only a
        // ring winding once around each vertex makes a triangulation. Not within a frame: its
        // fixed convex hull covered by upright triangles is covered once (a degree argument),
        // so a fold would turn a triangle over.
        if self.framed == 0 && !self.rings_wind_once(nv) {
            return None;
        }
        match self.topo.flip_to_delaunay(&self.pos, max_flips) {
            Some(_) => {
                self.update_rings();
                Some(true)
            }
            None if self.topo.touched.is_empty() => None,
            None => Some(false),
        }
    }

    /// Rewrite the rings around the vertices the last flips or reinsertions touched.
    fn update_rings(&mut self) {
        let mut rings = std::mem::take(&mut self.rings);
        rings.update(&self.topo, &self.topo.touched, &self.key());
        self.rings = rings;
    }

    /// Repair a framed triangulation where moving every vertex to `points` turns triangles
    /// over: the vertices of turned-over triangles go back to `old` (repeatedly, until every
    /// triangle is upright), the rest is flipped to Delaunay, and then each vertex sent back is
    /// removed and inserted at its new position. The frame keeps the hull fixed, so upright
    /// triangles make a triangulation (no ring can wind twice). False when more than an eighth
    /// of the vertices would go back or an insertion fails (a duplicate point): the topology is
    /// then left for a fresh build.
    fn reinsert(&mut self, points: &[DVec2], old: &[DVec2], max_flips: usize) -> bool {
        let nv = old.len();
        let mut back = vec![false; nv];
        let mut sent: Vec<u32> = Vec::new();
        loop {
            // Of each turned-over triangle, the vertex that moved farthest goes back.
            let mut turned: Vec<u32> = self
                .topo
                .turned_over(&self.pos)
                .into_iter()
                .filter_map(|t| {
                    let moved = |v: u32| match old.get(v as usize) {
                        Some(&o) if !back[v as usize] => self.pos[v as usize].distance_squared(o),
                        _ => -1.0,
                    };
                    let v = t
                        .into_iter()
                        .max_by(|&a, &b| moved(a).total_cmp(&moved(b)))?;
                    (moved(v) >= 0.0).then_some(v)
                })
                .collect();
            if turned.is_empty() {
                break;
            }
            turned.sort_unstable();
            turned.dedup();
            for v in turned {
                back[v as usize] = true;
                self.pos[v as usize] = old[v as usize];
                sent.push(v);
            }
            if sent.len() > nv / MAX_FLIP_FRACTION {
                return false;
            }
        }
        if self.topo.flip_to_delaunay(&self.pos, max_flips).is_none() {
            return false;
        }
        let mut touched = std::mem::take(&mut self.topo.touched);
        let mut budget = max_flips;
        for v in sent {
            self.topo.touched.clear();
            let Some(hint) = self.topo.remove(&self.pos, v, &mut budget) else {
                return false;
            };
            self.pos[v as usize] = points[self.point_of_vertex[v as usize] as usize];
            if self.topo.insert(&self.pos, v, hint, &mut budget).is_err() {
                return false;
            }
            touched.append(&mut self.topo.touched);
        }
        if !self.topo.free.is_empty() {
            return false;
        }
        touched.sort_unstable();
        touched.dedup();
        self.topo.touched = touched;
        self.update_rings();
        true
    }

    /// Every point vertex's ring winds once around it (an open fan, on an unframed hull, turns
    /// less than half a turn): counted as the ring's passages through the direction +x, with
    /// exact comparisons of coordinates.
    fn rings_wind_once(&self, nv: usize) -> bool {
        let pos = &self.pos;
        (0..nv).into_par_iter().all(|v| {
            let (nb, outer) = self.rings.of(v);
            let z = pos[v];
            // Angle of the direction to u in [0, π).
            let above = |u: u32| {
                let p = pos[u as usize];
                p.y > z.y || (p.y == z.y && p.x > z.x)
            };
            let m = nb.len();
            if outer.contains(&true) {
                (1..m).filter(|&k| above(nb[k - 1]) != above(nb[k])).count() <= 1
            } else {
                (0..m)
                    .filter(|&k| !above(nb[k]) && above(nb[(k + 1) % m]))
                    .count()
                    == 1
            }
        })
    }

    /// Triangulate afresh, inserting along a Hilbert curve: into the frame by our own
    /// insertions when framed, else (or if that fails) with spade. Vertex `v` is the `v`-th
    /// point inserted.
    fn build(&mut self, points: &[DVec2]) {
        assert!(
            points.len() < NONE as usize,
            "at most 2^32 - 1 points are supported"
        );
        hilbert_keys(points, &mut self.keys);
        // The old rings and the flips' scratch go first, to keep the peak down.
        self.rings = Rings::default();
        self.scratch = Default::default();
        if !self
            .frame_box
            .is_some_and(|b| self.insert_framed(points, b))
        {
            self.build_spade(points);
        } else {
            self.finish(points.len());
        }
        self.keys = Vec::new();
    }

    /// Hints, rings and whether the next rebuild may flip, once `topo` and `pos` are set.
    fn finish(&mut self, n_points: usize) {
        let nv = self.point_of_vertex.len();
        self.hints = OnceLock::new();
        let mut rings = std::mem::take(&mut self.rings);
        self.topo.rings(nv, &self.key(), &mut rings);
        self.rings = rings;
        self.flippable = nv == n_points && !self.topo.tri.is_empty();
    }

    /// Insert the finite points, in Hilbert order, into the fan of the frame around them and
    /// `lo`–`hi`. False (to be built by spade) when an insertion fails, which exact predicates
    /// leave to coordinates too large for them.
    fn insert_framed(&mut self, points: &[DVec2], (lo, hi): (DVec2, DVec2)) -> bool {
        let (plo, phi) = points
            .iter()
            .filter(|p| p.is_finite())
            .fold((lo, hi), |(a, b), p| (a.min(*p), b.max(*p)));
        let m = points.iter().filter(|p| p.is_finite()).count();
        if m == 0 || m + FRAME >= NONE as usize {
            return false;
        }
        let (c, diag) = frame_around(plo, phi);
        self.pos.clear();
        self.pos.resize(m, DVec2::ZERO);
        self.pos.extend(frame(c, diag));
        self.point_of_vertex.clear();
        self.vertex_of_point.clear();
        self.vertex_of_point.resize(points.len(), NONE);
        if m == points.len() && m >= HALVES_FROM {
            // Vertex v is the v-th point in Hilbert order, as one-by-one insertion numbers
            // them when every point is finite and none is a duplicate.
            let keys = &self.keys;
            self.pos[..m]
                .par_iter_mut()
                .zip(keys.par_iter())
                .for_each(|(p, &key)| *p = points[key as u32 as usize]);
            if let Some(topo) = crate::halves::triangulate_in_halves(&self.pos, m) {
                self.topo = topo;
                self.point_of_vertex
                    .extend(keys.iter().map(|&key| key as u32));
                for (v, &i) in self.point_of_vertex.iter().enumerate() {
                    self.vertex_of_point[i as usize] = v as u32;
                }
                self.framed = FRAME;
                self.frame_safe = (c, diag);
                return true;
            }
        }
        let fan: Vec<u32> = (m..m + FRAME).map(|v| v as u32).collect();
        self.topo.convex_fan(&fan, m + FRAME);
        let (mut hint, mut budget) = (0, usize::MAX);
        for &key in &self.keys {
            let i = key as u32;
            let p = points[i as usize];
            if !p.is_finite() {
                continue;
            }
            let v = self.point_of_vertex.len() as u32;
            self.pos[v as usize] = p;
            match self.topo.insert(&self.pos, v, hint, &mut budget) {
                Ok(()) => {
                    self.point_of_vertex.push(i);
                    self.vertex_of_point[i as usize] = v;
                    hint = self.topo.v2t[v as usize];
                }
                Err(Some(u)) if (u as usize) < m => self.vertex_of_point[i as usize] = u,
                Err(_) => return false,
            }
        }
        // Duplicates left the frame's numbers too high: number it right after the points.
        let nv = self.point_of_vertex.len();
        if nv < m {
            let shift = (m - nv) as u32;
            self.topo.tri.par_iter_mut().flatten().for_each(|x| {
                if *x as usize >= m {
                    *x -= shift;
                }
            });
            self.pos.copy_within(m..m + FRAME, nv);
            self.pos.truncate(nv + FRAME);
            self.topo.index_vertices(nv + FRAME);
        }
        self.framed = FRAME;
        self.frame_safe = (c, diag);
        true
    }

    /// Triangulate afresh with spade. Spade's triangulation lives only while its topology is
    /// copied out, so its memory is not held between rebuilds (the flips do not need it).
    fn build_spade(&mut self, points: &[DVec2]) {
        let mut dt: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::with_capacity(
            points.len() + FRAME,
            3 * points.len(),
            2 * points.len(),
        );
        self.point_of_vertex.clear();
        self.vertex_of_point.clear();
        self.vertex_of_point.resize(points.len(), NONE);
        for &key in &self.keys {
            let i = key as u32;
            let p = points[i as usize];
            let before = dt.num_vertices();
            // Errors are NaN/infinite/out-of-range coordinates: such points stay un-inserted.
            if let Ok(h) = dt.insert(Point2::new(p.x, p.y)) {
                if dt.num_vertices() > before {
                    self.point_of_vertex.push(i);
                }
                self.vertex_of_point[i as usize] = h.index() as u32;
            }
        }
        self.pos.clear();
        self.pos
            .extend(self.point_of_vertex.iter().map(|&i| points[i as usize]));
        let nv = self.pos.len();
        self.framed = 0;
        if let (Some((lo, hi)), true) = (self.frame_box, nv > 0) {
            let (plo, phi) = self
                .pos
                .iter()
                .fold((lo, hi), |(a, b), p| (a.min(*p), b.max(*p)));
            let (c, diag) = frame_around(plo, phi);
            for p in frame(c, diag) {
                if dt.insert(Point2::new(p.x, p.y)).is_ok() {
                    self.pos.push(p);
                    self.framed += 1;
                }
            }
            self.frame_safe = (c, diag);
        }
        self.topo.tri.clear();
        self.topo.adj.clear();
        self.topo.free.clear();
        // In chunks of faces, in parallel within each (a handle per face at once would be
        // another 32 MB at 10⁶).
        let mut faces = dt.inner_faces();
        loop {
            let chunk: Vec<_> = faces.by_ref().take(1 << 16).collect();
            if chunk.is_empty() {
                break;
            }
            let (mut tri, mut adj) = (Vec::new(), Vec::new());
            chunk
                .par_iter()
                .map(|f| {
                    let e = f.adjacent_edges();
                    let mut adj = [NONE; 3];
                    for k in 0..3 {
                        let r = e[k].rev().face();
                        // Inner faces are numbered from 1 (0 is the outer face).
                        adj[(k + 2) % 3] = if r.is_outer() {
                            NONE
                        } else {
                            r.fix().index() as u32 - 1
                        };
                    }
                    (e.map(|e| e.from().fix().index() as u32), adj)
                })
                .unzip_into_vecs(&mut tri, &mut adj);
            self.topo.tri.append(&mut tri);
            self.topo.adj.append(&mut adj);
        }
        self.topo.index_vertices(self.pos.len());
        if self.topo.tri.is_empty() {
            // No triangles (fewer than three vertices, or all collinear): spade's edges.
            self.hints = OnceLock::new();
            let out_edges = |v: usize| dt.vertex(FixedVertexHandle::from_index(v)).out_edges();
            self.rings.fill(
                |v| out_edges(v).count(),
                &|u| u,
                nv,
                |v, nb, outer| {
                    for (k, e) in out_edges(v).enumerate() {
                        nb[k] = e.to().fix().index() as u32;
                        outer[k] = e.face().is_outer();
                    }
                },
            );
            self.flippable = false;
        } else {
            drop(dt);
            self.finish(points.len());
        }
    }

    /// Number of input points (including duplicates and rejected points).
    pub fn num_points(&self) -> usize {
        self.vertex_of_point.len()
    }

    /// Number of distinct vertices.
    pub fn num_vertices(&self) -> usize {
        self.point_of_vertex.len()
    }

    /// The input index of the vertex that point `i` was merged onto: `Some(i)` for the first
    /// point at a position, the first occurrence for a duplicate, `None` for a point that was not
    /// inserted (non-finite coordinates) or an out-of-range `i`.
    pub fn vertex_of(&self, i: usize) -> Option<usize> {
        let v = *self.vertex_of_point.get(i)?;
        (v != NONE).then(|| self.point_of_vertex[v as usize] as usize)
    }

    /// The input index of vertex `v` (vertices are numbered `0..num_vertices()` along a Hilbert
    /// curve, so passes in vertex order are cache-friendly).
    pub fn point_of_vertex(&self, v: usize) -> usize {
        self.point_of_vertex[v] as usize
    }

    /// The vertex of point `i` if `i` is the first point at its position (`None` for a
    /// duplicate, a point that was not inserted, or an out-of-range `i`).
    pub fn vertex_index(&self, i: usize) -> Option<usize> {
        let v = *self.vertex_of_point.get(i)?;
        (v != NONE && self.point_of_vertex[v as usize] as usize == i).then_some(v as usize)
    }

    /// The triangles with their neighbours (vertex indices; a frame's vertices numbered from
    /// `num_vertices()`), or None while slots freed by a removal are still unfilled.
    pub(crate) fn topology(&self) -> Option<&Topology> {
        self.topo.free.is_empty().then_some(&self.topo)
    }

    /// All finite triangles as CCW index triples into the input points.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        let nv = self.num_vertices() as u32;
        self.topo
            .tri
            .iter()
            .filter(|t| t.iter().all(|&v| v < nv))
            .map(|t| t.map(|v| self.point_of_vertex[v as usize]))
            .collect()
    }

    /// Neighbours of vertex `v` in CCW order, as vertices (a frame's vertices, numbered from
    /// `num_vertices()`, included).
    pub fn ring(&self, v: usize) -> &[u32] {
        self.rings.of(v).0
    }

    /// Delaunay neighbours of input point `i`, in CCW order (empty for a point without vertex).
    pub fn neighbors(&self, i: usize) -> Vec<usize> {
        match self.vertex_of_point.get(i) {
            Some(&v) if v != NONE => self
                .rings
                .of(v as usize)
                .0
                .iter()
                .filter_map(|&u| self.point_of_vertex.get(u as usize).map(|&i| i as usize))
                .collect(),
            _ => Vec::new(),
        }
    }

    /// Index of the input point nearest to `p` (`usize::MAX` if there is no vertex or `p` is
    /// not finite; see [`Delaunay::try_nearest`]).
    pub fn nearest(&self, p: DVec2) -> usize {
        self.try_nearest(p).unwrap_or(usize::MAX)
    }

    /// Index of the input point nearest to `p`, or `None` for an empty triangulation or a
    /// non-finite `p`. Deterministic: a greedy walk over Delaunay edges (which always ends at a
    /// nearest vertex) from a start vertex looked up in a fixed grid.
    pub fn try_nearest(&self, p: DVec2) -> Option<usize> {
        if !p.is_finite() || self.num_vertices() == 0 {
            return None;
        }
        let nv = self.point_of_vertex.len();
        let hints = self.hints.get_or_init(|| HintGrid::new(&self.pos[..nv]));
        let mut v = hints.start(p) as usize;
        let dist = |u: usize| self.pos[u].distance_squared(p);
        let mut d = dist(v);
        loop {
            let mut best = (v, d);
            for &u in self.rings.of(v).0 {
                if u as usize >= self.point_of_vertex.len() {
                    continue;
                }
                let du = dist(u as usize);
                if du < best.1 {
                    best = (u as usize, du);
                }
            }
            if best.0 == v {
                return Some(self.point_of_vertex[v] as usize);
            }
            (v, d) = best;
        }
    }
}

/// Centre and size of the frame around the box `lo`–`hi`: points stay safe while within one
/// diagonal of the centre (then the frame's bisectors are 1.5 diagonals out, beyond the box).
pub(crate) fn frame_around(lo: DVec2, hi: DVec2) -> (DVec2, f64) {
    let diag = (hi - lo).length().max(f64::MIN_POSITIVE.sqrt());
    (0.5 * (lo + hi), diag)
}

/// The frame: a regular octagon of radius 4 diagonals, CCW.
pub(crate) fn frame(c: DVec2, diag: f64) -> impl Iterator<Item = DVec2> {
    (0..FRAME).map(move |k| {
        let a = std::f64::consts::TAU * k as f64 / FRAME as f64;
        c + DVec2::from_angle(a) * (4.0 * diag)
    })
}

/// A coarse grid of start vertices for nearest-point walks.
struct HintGrid {
    lo: DVec2,
    inv: DVec2,
    nx: usize,
    ny: usize,
    cells: Vec<u32>,
}

impl HintGrid {
    fn new(pos: &[DVec2]) -> HintGrid {
        let n = pos.len();
        // Built after every rebuild: in parallel, with the same grid as one thread would build
        // (minima and maxima do not depend on the order, nor does each cell's smallest vertex).
        let far = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        let (lo, hi) = pos
            .par_iter()
            .fold(|| far, |(lo, hi), p| (lo.min(*p), hi.max(*p)))
            .reduce(|| far, |a, b| (a.0.min(b.0), a.1.max(b.1)));
        if n == 0 {
            return HintGrid {
                lo: DVec2::ZERO,
                inv: DVec2::ZERO,
                nx: 1,
                ny: 1,
                cells: vec![0],
            };
        }
        // About four vertices per grid cell.
        let ext = (hi - lo).max(DVec2::splat(1e-300));
        let target = (n / 4).clamp(1, 1 << 20) as f64;
        let s = (ext.x * ext.y / target)
            .sqrt()
            .max(ext.x.max(ext.y) / 1024.0);
        let nx = ((ext.x / s).ceil() as usize).clamp(1, 1024);
        let ny = ((ext.y / s).ceil() as usize).clamp(1, 1024);
        let inv = DVec2::new(nx as f64 / ext.x, ny as f64 / ext.y);
        let mut grid = HintGrid {
            lo,
            inv,
            nx,
            ny,
            cells: Vec::new(),
        };
        // Each cell's first vertex: the smallest index that falls in it.
        let first: Vec<AtomicU32> = (0..nx * ny)
            .into_par_iter()
            .map(|_| AtomicU32::new(NONE))
            .collect();
        pos.par_iter().enumerate().for_each(|(v, p)| {
            first[grid.cell(*p)].fetch_min(v as u32, Ordering::Relaxed);
        });
        grid.cells = first.into_iter().map(AtomicU32::into_inner).collect();
        // Empty cells borrow the previous filled cell's vertex (any start is correct).
        let first = grid.cells.iter().copied().find(|&c| c != NONE).unwrap_or(0);
        let mut last = first;
        for c in grid.cells.iter_mut() {
            if *c == NONE {
                *c = last;
            } else {
                last = *c;
            }
        }
        grid
    }

    fn cell(&self, p: DVec2) -> usize {
        let q = (p - self.lo) * self.inv;
        let i = (q.x.max(0.0) as usize).min(self.nx - 1);
        let j = (q.y.max(0.0) as usize).min(self.ny - 1);
        j * self.nx + i
    }

    fn start(&self, p: DVec2) -> u32 {
        self.cells[self.cell(p)]
    }
}

/// Input indices sorted along a Hilbert curve on a 2^16 × 2^16 grid over the bounding box of
/// the finite points (non-finite points go last). Ties keep index order, so the order is a pure
/// function of the input. Points listed in this order lie near the points listed next to them,
/// which is also the order [`Delaunay`] inserts them in. O(n log n).
///
/// ```
/// use cvtmesh::tessellation::hilbert_order;
/// use cvtmesh::geometry::DVec2;
/// // The four corners of a square, listed crosswise: the curve visits them around the square.
/// let corners = [(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)].map(|(x, y)| DVec2::new(x, y));
/// let order = hilbert_order(&corners);
/// let around = |i: usize| (corners[order[i] as usize] - corners[order[i + 1] as usize]).length();
/// assert!((0..3).all(|i| around(i) == 1.0));
/// ```
pub fn hilbert_order(points: &[DVec2]) -> Vec<u32> {
    let mut keys = Vec::new();
    hilbert_keys(points, &mut keys);
    keys.into_iter().map(|k| k as u32).collect()
}

/// `hilbert_order` as sorted (key << 32 | index) words, written into `keys`.
fn hilbert_keys(points: &[DVec2], keys: &mut Vec<u64>) {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in points.iter().filter(|p| p.is_finite()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let scale = 65535.0 / (hi - lo).max_element().max(f64::MIN_POSITIVE);
    points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            let key = if p.is_finite() {
                let q = (*p - lo) * scale;
                hilbert_key(q.x as u32, q.y as u32)
            } else {
                u32::MAX
            };
            (u64::from(key) << 32) | i as u64
        })
        .collect_into_vec(keys);
    keys.par_sort_unstable();
}

/// Position of (x, y) along the Hilbert curve filling [0, 2^16)².
fn hilbert_key(mut x: u32, mut y: u32) -> u32 {
    const N: u32 = 1 << 16;
    let mut d = 0u32;
    let mut s = N / 2;
    while s > 0 {
        let rx = u32::from(x & s > 0);
        let ry = u32::from(y & s > 0);
        d += s * s * ((3 * rx) ^ ry);
        if ry == 0 {
            if rx == 1 {
                x = N - 1 - x;
                y = N - 1 - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s /= 2;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::Rng;

    fn lattice(n: usize) -> Vec<DVec2> {
        let mut pts = Vec::new();
        for j in 0..n {
            for i in 0..n {
                pts.push(DVec2::new(i as f64, j as f64));
            }
        }
        pts
    }

    /// A framed build of enough points to be triangulated in two halves gives every point the
    /// neighbours spade's build gives it (away from the hull, where the frame's triangles
    /// differ), and repairs by flips from it after the points move do as well.
    #[test]
    fn a_build_in_halves_gives_the_neighbours_a_build_by_spade_gives() {
        let mut rng = Rng::new(11);
        let h = 0.0075;
        let (u, v) = (DVec2::new(h, 0.0), DVec2::new(0.5 * h, 0.75f64.sqrt() * h));
        let mut pts = Vec::new();
        for i in -160..=160 {
            for j in -160..=160 {
                let p = u * i as f64 + v * j as f64;
                if p.length() < 1.0 {
                    pts.push(p + DVec2::new(rng.range(-0.2, 0.2), rng.range(-0.2, 0.2)) * h);
                }
            }
        }
        assert!(pts.len() >= HALVES_FROM, "{} points", pts.len());
        let mut framed = Delaunay::framed(DVec2::splat(-1.0), DVec2::splat(1.0));
        for round in 0..2 {
            framed.rebuild(&pts);
            assert_eq!(framed.flipped(), round == 1, "fresh, then repaired");
            let spade = Delaunay::new(&pts);
            for (i, p) in pts.iter().enumerate() {
                if p.length() < 1.0 - 4.0 * h {
                    let (mut a, mut b) = (framed.neighbors(i), spade.neighbors(i));
                    a.sort_unstable();
                    b.sort_unstable();
                    assert_eq!(a, b, "round {round}, point {i}");
                }
            }
            for p in pts.iter_mut() {
                *p += DVec2::new(rng.range(-0.1, 0.1), rng.range(-0.1, 0.1)) * h;
            }
        }
    }

    /// Builds and repairs leave the hint grid to the first nearest-point walk, which builds it
    /// from the positions of the moment and finds the nearest point, as after local moves.
    #[test]
    fn the_hint_grid_waits_for_the_first_walk() {
        let mut rng = Rng::new(9);
        let mut pts = crate::unit_square_points(&mut rng, 3000);
        let brute = |pts: &[DVec2], q: DVec2| {
            (0..pts.len())
                .min_by(|&a, &b| pts[a].distance(q).total_cmp(&pts[b].distance(q)))
                .unwrap()
        };
        let mut del = Delaunay::framed(DVec2::splat(-0.5), DVec2::splat(1.5));
        for round in 0..3 {
            del.rebuild(&pts);
            assert!(
                del.hints.get().is_none(),
                "round {round}: built before a walk"
            );
            let q = DVec2::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            assert_eq!(del.nearest(q), brute(&pts, q));
            assert!(del.hints.get().is_some());
            let moved: Vec<u32> = (0..40).map(|i| i * 61).collect();
            for &i in &moved {
                pts[i as usize] += DVec2::new(rng.range(-0.02, 0.02), rng.range(-0.02, 0.02));
            }
            del.move_points(&pts, &moved).expect("a local repair");
            for _ in 0..50 {
                let q = DVec2::new(rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
                assert_eq!(del.nearest(q), brute(&pts, q));
            }
            for p in pts.iter_mut() {
                *p += DVec2::new(rng.range(-0.002, 0.002), rng.range(-0.002, 0.002));
            }
        }
    }

    /// `is_at` holds after every build and repair, at the same positions only, and where it
    /// holds a rebuild leaves the triangles as they are.
    #[test]
    fn is_at_holds_exactly_where_a_rebuild_would_change_nothing() {
        let mut rng = Rng::new(3);
        let mut pts = crate::unit_square_points(&mut rng, 2000);
        let mut del = Delaunay::framed(DVec2::splat(-0.5), DVec2::splat(1.5));
        del.rebuild(&pts);
        assert!(del.is_at(&pts));
        let built = triangle_set(&del);
        del.rebuild(&pts);
        assert_eq!(triangle_set(&del), built);
        let moved: Vec<u32> = (0..50).map(|i| i * 37).collect();
        for &i in &moved {
            pts[i as usize] += DVec2::new(rng.range(-0.01, 0.01), rng.range(-0.01, 0.01));
        }
        assert!(!del.is_at(&pts));
        del.move_points(&pts, &moved).expect("a local repair");
        assert!(del.is_at(&pts));
        let repaired = triangle_set(&del);
        assert_ne!(repaired, built);
        del.rebuild(&pts);
        assert_eq!(triangle_set(&del), repaired);
        // One bit off, or a duplicate without a vertex of its own: not at them.
        pts[5].y = f64::from_bits(pts[5].y.to_bits() + 1);
        assert!(!del.is_at(&pts));
        pts.push(pts[0]);
        assert!(!Delaunay::new(&pts).is_at(&pts));
    }

    /// The hint grid built in parallel is the one a single pass in vertex order builds: each
    /// cell starts at the first vertex that falls in it, an empty cell at the last filled
    /// cell's.
    #[test]
    fn the_hint_grid_is_the_serial_one() {
        let mut rng = Rng::new(7);
        let pos: Vec<DVec2> = (0..50_000)
            .map(|i| {
                let p = DVec2::new(rng.range(-1.0, 3.0), rng.range(0.5, 1.5));
                // Clustered and duplicated points leave cells empty and crowd others.
                if i % 3 == 0 {
                    p * 0.1
                } else {
                    p
                }
            })
            .collect();
        let g = HintGrid::new(&pos);
        let mut serial = vec![NONE; g.nx * g.ny];
        for (v, p) in pos.iter().enumerate() {
            let c = g.cell(*p);
            if serial[c] == NONE {
                serial[c] = v as u32;
            }
        }
        assert!(serial.contains(&NONE), "some cells empty");
        let mut last = serial.iter().copied().find(|&c| c != NONE).unwrap();
        for c in serial.iter_mut() {
            if *c == NONE {
                *c = last;
            } else {
                last = *c;
            }
        }
        assert_eq!(g.cells, serial);
        let lo = pos
            .iter()
            .fold(DVec2::splat(f64::INFINITY), |a, p| a.min(*p));
        assert_eq!(g.lo, lo);
    }

    #[test]
    fn hilbert_key_is_a_bijection_on_a_small_grid() {
        // On the 2^16 grid the low corner block [0,4)² maps onto keys 0..16.
        let mut keys: Vec<u32> = (0..4)
            .flat_map(|x| (0..4).map(move |y| hilbert_key(x, y)))
            .collect();
        keys.sort_unstable();
        assert_eq!(keys, (0..16).collect::<Vec<_>>());
        // Consecutive keys are grid neighbours (the curve is continuous).
        let mut inv = [(0u32, 0u32); 16];
        for x in 0..4 {
            for y in 0..4 {
                inv[hilbert_key(x, y) as usize] = (x, y);
            }
        }
        for w in inv.windows(2) {
            let d = w[0].0.abs_diff(w[1].0) + w[0].1.abs_diff(w[1].1);
            assert_eq!(d, 1, "{:?}", w);
        }
    }

    #[test]
    fn lattice_triangle_count_and_orientation() {
        // A square lattice (exact coordinates, four cocircular points per square): every
        // boundary point is on the hull, h = 4(k - 1), and Euler gives 2n - 2 - h triangles.
        let k = 12;
        let pts = lattice(k);
        let d = Delaunay::new(&pts);
        let hull = 4 * (k - 1);
        let hull_edges = d.topo.adj.iter().flatten().filter(|&&a| a == NONE).count();
        assert_eq!(hull_edges, hull);
        let tris = d.triangles();
        assert_eq!(tris.len(), 2 * pts.len() - 2 - hull);
        for t in &tris {
            let [a, b, c] = t.map(|i| pts[i as usize]);
            assert!(
                geometry::predicates::orient(a, b, c) > 0.0,
                "triangle {t:?} not CCW"
            );
        }
    }

    #[test]
    fn neighbors_are_ccw_and_symmetric() {
        let mut rng = Rng::new(3);
        let pts: Vec<DVec2> = (0..500)
            .map(|_| DVec2::new(rng.uniform(), rng.uniform()))
            .collect();
        let d = Delaunay::new(&pts);
        for i in 0..pts.len() {
            let nb = d.neighbors(i);
            for &j in &nb {
                assert!(d.neighbors(j).contains(&i));
            }
            // CCW: angles around i increase (with one wrap-around) for an interior vertex.
            let ang: Vec<f64> = nb.iter().map(|&j| (pts[j] - pts[i]).to_angle()).collect();
            let wraps = (0..ang.len())
                .filter(|&k| ang[(k + 1) % ang.len()] < ang[k])
                .count();
            assert!(wraps <= 1, "neighbours of {i} not in angular order");
        }
    }

    #[test]
    fn duplicates_and_non_finite_points() {
        let pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(f64::NAN, 0.0),
            DVec2::new(1.0, 1.0),
        ];
        let d = Delaunay::new(&pts);
        assert_eq!(d.num_points(), 6);
        assert_eq!(d.num_vertices(), 4);
        assert_eq!(d.vertex_of(3), Some(1));
        assert_eq!(d.vertex_of(1), Some(1));
        assert_eq!(d.vertex_of(4), None);
        assert!(d.neighbors(4).is_empty());
        assert_eq!(d.triangles().len(), 2);
        assert!(d.triangles().iter().flatten().all(|&i| i != 3 && i != 4));
        assert_eq!(d.nearest(DVec2::new(0.9, 0.2)), 1);
        assert_eq!(d.nearest(DVec2::NAN), usize::MAX);
        assert_eq!(Delaunay::new(&[]).try_nearest(DVec2::ZERO), None);
    }

    #[test]
    fn nearest_matches_brute_force() {
        let mut rng = Rng::new(11);
        let pts: Vec<DVec2> = (0..2000)
            .map(|_| DVec2::new(rng.uniform(), rng.range(0.0, 3.0)))
            .collect();
        let d = Delaunay::new(&pts);
        for _ in 0..2000 {
            let q = DVec2::new(rng.range(-0.5, 1.5), rng.range(-0.5, 3.5));
            let brute = (0..pts.len())
                .min_by(|&a, &b| {
                    pts[a]
                        .distance_squared(q)
                        .total_cmp(&pts[b].distance_squared(q))
                })
                .unwrap();
            let got = d.nearest(q);
            assert_eq!(pts[got].distance_squared(q), pts[brute].distance_squared(q));
        }
    }

    #[test]
    fn collinear_points_have_neighbours_and_no_triangles() {
        let pts: Vec<DVec2> = (0..10)
            .map(|i| DVec2::new(i as f64, 2.0 * i as f64))
            .collect();
        let d = Delaunay::new(&pts);
        assert!(d.triangles().is_empty());
        let mut nb = d.neighbors(4);
        nb.sort_unstable();
        assert_eq!(nb, vec![3, 5]);
        assert_eq!(d.nearest(DVec2::new(7.2, 13.0)), 7);
    }

    #[test]
    fn rebuild_equals_a_fresh_triangulation() {
        let mut rng = Rng::new(23);
        let mut random = |n: usize| -> Vec<DVec2> {
            (0..n)
                .map(|_| DVec2::new(rng.uniform(), rng.uniform()))
                .collect()
        };
        let (a, mut b) = (random(500), random(300));
        b[7] = b[3]; // a duplicate
        b[11] = DVec2::NAN; // a point without vertex
        let mut d = Delaunay::new(&a);
        d.rebuild(&b);
        let fresh = Delaunay::new(&b);
        assert_eq!(d.num_points(), 300);
        assert_eq!(d.num_vertices(), fresh.num_vertices());
        assert_eq!(d.triangles(), fresh.triangles());
        for i in 0..b.len() {
            assert_eq!(d.vertex_of(i), fresh.vertex_of(i));
            assert_eq!(d.neighbors(i), fresh.neighbors(i));
        }
        for q in random(50) {
            assert_eq!(d.nearest(q), fresh.nearest(q));
        }
        // Back to the larger set: nothing of the smaller one remains.
        d.rebuild(&a);
        assert_eq!(d.triangles(), Delaunay::new(&a).triangles());
    }

    /// Triangles as sorted triples, sorted: the triangulation without its numbering.
    fn triangle_set(d: &Delaunay) -> Vec<[u32; 3]> {
        let mut t: Vec<[u32; 3]> = d
            .triangles()
            .into_iter()
            .map(|mut t| {
                t.sort_unstable();
                t
            })
            .collect();
        t.sort_unstable();
        t
    }

    /// A jittered hexagonal lattice in the unit disc (a CVT-like set) and a random set.
    fn point_sets(rng: &mut Rng) -> Vec<Vec<DVec2>> {
        let h = 0.05;
        let mut hex = Vec::new();
        for j in -25..=25 {
            for i in -25..=25 {
                let p = DVec2::new(i as f64 + 0.5 * j as f64, j as f64 * 0.75f64.sqrt()) * h;
                if p.length() < 1.0 {
                    hex.push(p + DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 1e-3 * h);
                }
            }
        }
        let random = (0..800)
            .map(|_| DVec2::new(rng.uniform(), rng.uniform()))
            .collect();
        vec![hex, random]
    }

    #[test]
    fn rebuild_by_flips_equals_a_fresh_triangulation() {
        let mut rng = Rng::new(5);
        for pts in point_sets(&mut rng) {
            let n = pts.len();
            // Small moves (flips only), larger ones (many flips) and a shuffle (turned-over
            // triangles: a fresh build).
            for (scale, steps) in [(1e-3, 5), (0.02, 5), (0.3, 2)] {
                let mut d = Delaunay::new(&pts);
                let mut moved = pts.clone();
                for _ in 0..steps {
                    for p in moved.iter_mut() {
                        *p += DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * scale * 0.05;
                    }
                    d.rebuild(&moved);
                    let fresh = Delaunay::new(&moved);
                    assert_eq!(
                        triangle_set(&d),
                        triangle_set(&fresh),
                        "{n} points, {scale}"
                    );
                    // The same rings, each from the same neighbour, in input numbering.
                    for i in 0..n {
                        assert_eq!(d.neighbors(i), fresh.neighbors(i), "{n} points, {scale}");
                        let outer =
                            |d: &Delaunay| d.rings.of(d.vertex_index(i).unwrap()).1.to_vec();
                        assert_eq!(outer(&d), outer(&fresh));
                    }
                    for q in [DVec2::new(0.3, 0.2), DVec2::new(-0.5, 0.1)] {
                        assert_eq!(d.nearest(q), fresh.nearest(q));
                    }
                }
            }
        }
    }

    #[test]
    fn flips_repair_what_small_moves_break_and_give_up_on_turned_over_triangles() {
        let mut rng = Rng::new(9);
        let pts = point_sets(&mut rng).remove(1);
        let mut d = Delaunay::new(&pts);
        let moved_to = |d: &Delaunay, moved: &[DVec2]| -> Vec<DVec2> {
            (0..d.num_vertices())
                .map(|v| moved[d.point_of_vertex(v)])
                .collect()
        };
        // Pull a vertex towards a neighbour past the circumcircles around it but not past any
        // opposite edge: flips repair it, without a fresh build.
        let mut repaired = 0;
        for i in 0..pts.len() {
            let mut moved = pts.clone();
            moved[i] = pts[i].lerp(pts[d.neighbors(i)[0]], 0.3);
            let flips = d
                .topo
                .clone()
                .flip_to_delaunay(&moved_to(&d, &moved), usize::MAX);
            if flips > Some(0) {
                repaired += 1;
                let mut e = Delaunay::new(&pts);
                e.rebuild(&moved);
                assert!(e.flippable);
                assert_eq!(triangle_set(&e), triangle_set(&Delaunay::new(&moved)));
            }
        }
        assert!(repaired > 10, "{repaired}");
        // Past a neighbour: a triangle turns over, flips refuse, the fresh build answers.
        let mut moved = pts.clone();
        moved[400] = pts[400].lerp(pts[d.neighbors(400)[0]], 1.5);
        let pos = moved_to(&d, &moved);
        assert_eq!(d.topo.clone().flip_to_delaunay(&pos, usize::MAX), None);
        d.rebuild(&moved);
        assert_eq!(triangle_set(&d), triangle_set(&Delaunay::new(&moved)));
        assert!(d.flippable, "the fresh build can flip again");
    }

    /// Every triangle upright and every edge locally Delaunay (exact predicates), and the
    /// triangle count of a triangulation of the points' hull.
    fn assert_delaunay(d: &Delaunay) {
        let p = |v: u32| crate::topology::coord(d.pos[v as usize]);
        for (t, tri) in d.topo.tri.iter().enumerate() {
            assert!(robust::orient2d(p(tri[0]), p(tri[1]), p(tri[2])) > 0.0);
            for k in 0..3 {
                let u = d.topo.adj[t][k];
                if u != NONE {
                    let u = u as usize;
                    let j = (0..3).find(|&j| d.topo.adj[u][j] == t as u32).unwrap();
                    let far = d.topo.tri[u][j];
                    assert!(robust::incircle(p(tri[0]), p(tri[1]), p(tri[2]), p(far)) <= 0.0);
                }
            }
        }
        let hull = d.topo.adj.iter().flatten().filter(|&&a| a == NONE).count();
        assert_eq!(d.topo.tri.len(), 2 * d.pos.len() - 2 - hull);
    }

    #[test]
    fn framed_rebuilds_reinsert_vertices_that_turn_triangles_over() {
        let mut rng = Rng::new(17);
        let pts = point_sets(&mut rng).remove(0);
        let n = pts.len();
        let (lo, hi) = (DVec2::splat(-1.1), DVec2::splat(1.1));
        let mut d = Delaunay::framed(lo, hi);
        d.rebuild(&pts);
        // One vertex past its neighbours; a twentieth of them by 1–3 spacings with the rest
        // jittered; everything jittered again (flips alone).
        let mut moved = pts.clone();
        moved[300] = pts[300].lerp(pts[d.neighbors(300)[0]], 2.5);
        let mut sets = vec![moved.clone()];
        for (i, p) in moved.iter_mut().enumerate() {
            let r = if i % 20 == 0 { 0.1 } else { 0.005 };
            *p += DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * r;
        }
        sets.push(moved.clone());
        for p in moved.iter_mut() {
            *p += DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 1e-3;
        }
        sets.push(moved);
        for m in &sets {
            d.rebuild(m);
            assert!(d.flipped(), "repaired without a fresh build");
            assert_delaunay(&d);
            // Against a fresh framed triangulation (the same frame: the box holds the points).
            let mut fresh = Delaunay::framed(lo, hi);
            fresh.rebuild(m);
            assert!(triangle_set(&d) == triangle_set(&fresh));
            assert!((0..n).all(|i| d.neighbors(i) == fresh.neighbors(i)));
        }
        // Onto the middle of an edge (exact on an integer lattice: the edge is split), and
        // onto another vertex (a duplicate: a fresh build merges it).
        let pts = lattice(12);
        let mut d = Delaunay::framed(DVec2::ZERO, DVec2::splat(11.0));
        d.rebuild(&pts);
        let mut m = pts.clone();
        m[5 * 12 + 5] = DVec2::new(2.5, 2.0);
        d.rebuild(&m);
        assert!(d.flipped());
        assert_delaunay(&d);
        assert_eq!(d.num_vertices(), pts.len());
        m[5 * 12 + 5] = pts[3];
        d.rebuild(&m);
        assert!(!d.flipped());
        assert_eq!(d.num_vertices(), pts.len() - 1);
        assert_eq!(d.vertex_of(5 * 12 + 5), d.vertex_of(3));
        assert_delaunay(&d);
    }

    #[test]
    fn framed_builds_merge_duplicates_skip_non_finite_points_and_agree_with_spade() {
        let mut rng = Rng::new(31);
        let mut pts: Vec<DVec2> = (0..1000)
            .map(|_| DVec2::new(rng.uniform(), rng.uniform()))
            .collect();
        pts[10] = pts[500];
        pts[20] = DVec2::new(f64::NAN, 0.5);
        let mut d = Delaunay::framed(DVec2::ZERO, DVec2::ONE);
        d.rebuild(&pts);
        assert_delaunay(&d);
        let spade = Delaunay::new(&pts);
        assert_eq!(d.num_vertices(), 998);
        assert_eq!(d.framed, FRAME);
        for (i, p) in pts.iter().enumerate() {
            assert_eq!(d.vertex_of(i).is_some(), spade.vertex_of(i).is_some());
            // Away from the hull the frame changes no edge.
            if p.cmpgt(DVec2::splat(0.2)).all() && p.cmplt(DVec2::splat(0.8)).all() {
                assert_eq!(d.neighbors(i), spade.neighbors(i), "point {i}");
            }
        }
        assert_eq!(d.vertex_of(10), d.vertex_of(500));
        assert!(d.neighbors(20).is_empty());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]
        /// Random points, a random share of them moved far (up to twice the box), the rest a
        /// little: the framed rebuild repairs (flips and reinsertions) to exactly the fresh
        /// framed triangulation.
        #[test]
        fn framed_rebuilds_equal_fresh_framed_triangulations(
            seed in 0u64..1_000_000, n in 4usize..300, share in 0.0f64..0.5, far in 0.01f64..2.0
        ) {
            let mut rng = Rng::new(seed);
            let pts: Vec<DVec2> = (0..n).map(|_| DVec2::new(rng.uniform(), rng.uniform())).collect();
            let (lo, hi) = (DVec2::splat(-1.0), DVec2::splat(2.0));
            let mut d = Delaunay::framed(lo, hi);
            d.rebuild(&pts);
            let mut moved = pts.clone();
            for p in moved.iter_mut() {
                let r = if rng.uniform() < share { far } else { 1e-3 };
                *p = (*p + DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * r)
                    .clamp(lo, hi);
            }
            d.rebuild(&moved);
            assert_delaunay(&d);
            let mut fresh = Delaunay::framed(lo, hi);
            fresh.rebuild(&moved);
            proptest::prop_assert!(triangle_set(&d) == triangle_set(&fresh));
            proptest::prop_assert!((0..n).all(|i| d.neighbors(i) == fresh.neighbors(i)));
            proptest::prop_assert!(d.topo.free.is_empty());
        }
    }

    /// Many points moved at once ([`Delaunay::move_together`]) give the triangulation of a fresh
    /// framed build and report every vertex whose cell can have changed (moved, a moved
    /// neighbour before or after, or other neighbours): interior points alone (all repaired
    /// together), every point (the thin triangles to the frame turn over: those points go one
    /// by one), and every point with one sent across its neighbours.
    #[test]
    fn many_points_moved_together_give_the_fresh_triangulation() {
        let mut rng = Rng::new(23);
        for (pts, step) in point_sets(&mut rng).into_iter().zip([0.01, 0.002]) {
            let n = pts.len();
            let (lo, hi) = (DVec2::splat(-1.5), DVec2::splat(1.5));
            let mut d = Delaunay::framed(lo, hi);
            d.rebuild(&pts);
            let nv = d.num_vertices() as u32;
            let beside_frame = |i: u32| {
                let v = d.vertex_index(i as usize).unwrap();
                d.ring(v).iter().any(|&u| u >= nv)
            };
            let interior: Vec<u32> = (0..n as u32)
                .filter(|&i| i % 5 != 0 && !beside_frame(i))
                .collect();
            let all: Vec<u32> = (0..n as u32).filter(|i| i % 5 != 0).collect();
            let mut to = pts.clone();
            for (stage, moved) in [&interior, &all, &all].into_iter().enumerate() {
                assert!(moved.len() >= MOVE_TOGETHER_FROM, "{n} points");
                let from = to.clone();
                for &i in moved {
                    to[i as usize] += DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * step;
                }
                if stage == 2 {
                    to[all[0] as usize] += DVec2::new(0.5, 0.0);
                }
                let before: Vec<Vec<usize>> = (0..n).map(|i| d.neighbors(i)).collect();
                let mut affected = Vec::new();
                assert!(d.move_together(&to, moved, &mut affected), "{n} points");
                if stage == 0 {
                    assert!(
                        !d.topo.touched.is_empty(),
                        "{n} points: edges flipped together"
                    );
                }
                let mut fresh = Delaunay::framed(lo, hi);
                fresh.rebuild(&to);
                assert!(
                    (0..n).all(|i| d.neighbors(i) == fresh.neighbors(i)),
                    "{n} points, stage {stage}"
                );
                assert!(affected.windows(2).all(|w| w[0] < w[1]), "sorted, unique");
                for i in 0..n {
                    let mut was = before[i].clone();
                    let mut is = d.neighbors(i);
                    was.sort_unstable();
                    is.sort_unstable();
                    let must = to[i] != from[i]
                        || was != is
                        || was.iter().chain(&is).any(|&j| to[j] != from[j]);
                    let v = d.vertex_index(i).unwrap() as u32;
                    assert!(
                        !must || affected.binary_search(&v).is_ok(),
                        "{n} points, stage {stage}: {i}"
                    );
                }
            }
        }
    }
}
