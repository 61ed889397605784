//! Ruppert/Shewchuk Delaunay refinement in the manner of Triangle 1.6 (`triangle -q -a`):
//!
//! * encroached subsegments are split before any triangle (diametral-circle test against the
//!   apex of the triangle inside the domain, i.e. visible encroachment);
//! * bad triangles (smallest angle below the bound, or area above the bound) are taken
//!   worst-first; the new vertex is Üngör's off-center when that is closer to the shortest
//!   edge than the circumcenter (Triangle's default), otherwise the circumcenter;
//! * a new vertex that would encroach a subsegment (it would become the apex of a triangle on
//!   it with an angle > 90°) or that lies beyond a boundary segment is not inserted: the
//!   subsegment is split instead and the triangle retried;
//! * a subsegment whose triangle meets another segment at one of its ends is split at a power
//!   of two from that end (concentric shells), otherwise at its middle; a skinny triangle whose
//!   shortest edge joins two input segments that meet at a vertex, at equal distances from it
//!   (the same shell), is not split for its angle (it is forced by a small input angle);
//! * curved pieces: a split point is placed on the exact curve (the chord point projected onto
//!   the piece), so every boundary vertex lies on ∂Ω.
//!
//! The triangulation is spade's constrained Delaunay triangulation of the convex hull; faces
//! outside Ω are told apart by the orientation of an adjacent subsegment or by an even-odd
//! ray cast through the subsegment grid.
use crate::boundary::{farthest_between, is_curved, Pslg, VKind, CHAIN_BEND};
use crate::grid::{SegGrid, SegKey};
use crate::queue::BadQueue;
use geometry::predicates::{circumcenter, segment_distance, triangle_signed_area};
use geometry::{DVec2, Density, Piece, PieceId, Region};
use mesh::MeshError;
use robust::Coord;
use spade::handles::{FixedDirectedEdgeHandle, FixedFaceHandle, FixedVertexHandle, InnerTag};
use spade::{ConstrainedDelaunayTriangulation, Point2, PositionInTriangulation, Triangulation};
use std::collections::{BTreeMap, HashSet, VecDeque};

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// A queued triangle: its vertices (CCW) and the face that held them when it was queued.
type Queued = ([u32; 3], FixedFaceHandle<InnerTag>);

/// Refinement bounds.
#[derive(Clone, Debug)]
pub(crate) struct Bounds {
    /// Minimum angle (degrees); 0 disables the angle test.
    pub min_angle_deg: f64,
    /// Maximum triangle area (scaled by ρ(centroid)^(-1/2) for a non-uniform density).
    pub max_area: f64,
    /// Use off-centers (Triangle's default) instead of plain circumcenters.
    pub off_centers: bool,
    /// Stop (incomplete) when the triangulation reaches this many vertices.
    pub max_vertices: usize,
    /// Stop (incomplete) after this many steps: splits, give-ups and sweeps. Each step either
    /// adds a vertex or retires a queued element, so this bounds a run whose queues refill
    /// without end.
    pub max_steps: usize,
}

/// What one refinement run produced.
pub(crate) struct Refined {
    pub points: Vec<DVec2>,
    pub kinds: Vec<VKind>,
    /// CCW triangles inside the region.
    pub triangles: Vec<[u32; 3]>,
    /// False if the vertex budget ran out.
    pub complete: bool,
    /// Triangles that could not be improved (their new vertex coincided with an old one, or a
    /// boundary subsegment became too short to split).
    pub given_up: usize,
}

/// What a subsegment is part of.
#[derive(Clone, Copy, Debug, PartialEq)]
enum On {
    /// A boundary piece: the region lies on the subsegment's left only.
    Piece(PieceId),
    /// An embedded line: the region lies on both sides.
    Line,
}

#[derive(Clone, Copy, Debug)]
struct Seg {
    from: u32,
    to: u32,
    on: On,
    /// The input (PSLG) segment this subsegment is part of.
    input: u32,
    frozen: bool,
}

fn key(a: u32, b: u32) -> SegKey {
    if a < b {
        (a, b)
    } else {
        (b, a)
    }
}

fn vh(i: u32) -> FixedVertexHandle {
    FixedVertexHandle::from_index(i as usize)
}

fn pt(p: DVec2) -> Point2<f64> {
    Point2::new(p.x, p.y)
}

fn coord(p: DVec2) -> Coord<f64> {
    Coord { x: p.x, y: p.y }
}

fn failed(message: String) -> MeshError {
    MeshError::Failed {
        method: "refine".into(),
        message,
    }
}

struct Engine<'a> {
    region: &'a Region,
    density: &'a Density,
    bounds: Bounds,
    sin_bound: f64,
    off_constant: f64,
    cdt: Cdt,
    kinds: Vec<VKind>,
    segs: BTreeMap<SegKey, Seg>,
    /// End points (origin, destination) of each input segment.
    inputs: Vec<(u32, u32)>,
    grid: SegGrid,
    bad: BadQueue<Queued>,
    enc: VecDeque<(SegKey, bool)>,
    min_seg: f64,
    given_up: usize,
    dropped: HashSet<[u32; 3]>,
}

/// Refine the constrained Delaunay triangulation of `pslg` inside `region`; `None` when a
/// segment crosses another or runs through a vertex, as a chord of a curved piece split too
/// coarsely can (it cuts across, or runs along, a neighbouring piece where the curve bends
/// towards it).
pub(crate) fn refine(
    region: &Region,
    pslg: Pslg,
    density: &Density,
    bounds: Bounds,
) -> Result<Option<Refined>, MeshError> {
    let n = pslg.points.len();
    let verts: Vec<Point2<f64>> = pslg.points.iter().map(|p| pt(*p)).collect();
    let edges: Vec<[usize; 2]> = pslg
        .segments
        .iter()
        .map(|s| [s.0, s.1])
        .chain(pslg.lines.iter().map(|&(a, b, _)| [a, b]))
        .collect();
    // spade's `bulk_load_cdt` panics on crossing segments; this one reports them.
    let mut crossing = false;
    let cdt = Cdt::try_bulk_load_cdt(verts, edges.clone(), |_| crossing = true)
        .map_err(|e| failed(format!("initial triangulation: {e:?}")))?;
    if cdt.num_vertices() != n {
        return Err(failed(
            "boundary vertices coincide or boundary segments cross".into(),
        ));
    }
    // A segment through another's vertex is split there by spade without a report, and one
    // along another merges with it: the refinement would then chase a sliver of zero width
    // until its vertex budget ran out. Neither is an edge of the triangulation, nor is either
    // of two that cross. In a valid region only the chords of curved pieces, which a finer
    // spacing moves, can do that.
    let missing = edges.iter().any(|&[a, b]| {
        !cdt.get_edge_from_neighbors(vh(a as u32), vh(b as u32))
            .is_some_and(|e| e.is_constraint_edge())
    });
    if crossing || missing {
        let chords = pslg
            .segments
            .iter()
            .any(|&(_, _, piece)| is_curved(&region.pieces()[piece]));
        if chords {
            return Ok(None);
        }
        return Err(failed(
            "boundary segments cross or run through a boundary vertex".into(),
        ));
    }
    if cdt.num_constraints() != edges.len() {
        return Err(failed(
            "boundary vertices coincide or boundary segments cross".into(),
        ));
    }
    let (lo, hi) = region.bbox();
    let pad = 1e-6 * region.diameter();
    let mut grid = SegGrid::new(
        lo - DVec2::splat(pad),
        hi + DVec2::splat(pad),
        4 * pslg.segments.len().max(16),
    );
    let mut segs = BTreeMap::new();
    // A boundary segment is its own input; a line's piece is part of the line's own segment.
    let n_boundary = pslg.segments.len();
    let inputs: Vec<(u32, u32)> = pslg
        .segments
        .iter()
        .map(|&(a, b, _)| (a, b))
        .chain(pslg.line_inputs.iter().copied())
        .map(|(a, b)| (a as u32, b as u32))
        .collect();
    let owners = pslg
        .segments
        .iter()
        .enumerate()
        .map(|(i, &(_, _, piece))| (On::Piece(piece), i))
        .chain(
            pslg.lines
                .iter()
                .map(|&(_, _, own)| (On::Line, n_boundary + own)),
        );
    for (&[a, b], (on, input)) in edges.iter().zip(owners) {
        let (a, b) = (a as u32, b as u32);
        segs.insert(
            key(a, b),
            Seg {
                from: a,
                to: b,
                on,
                input: input as u32,
                frozen: false,
            },
        );
        // The even-odd test counts the boundary only.
        if on != On::Line {
            grid.insert(key(a, b), pslg.points[a as usize], pslg.points[b as usize]);
        }
    }
    let theta = bounds.min_angle_deg.to_radians();
    let cos = theta.cos();
    let off_constant = if bounds.off_centers && bounds.min_angle_deg > 0.0 {
        0.475 * ((1.0 + cos) / (1.0 - cos)).sqrt()
    } else {
        0.0
    };
    let mut e = Engine {
        region,
        density,
        sin_bound: theta.sin(),
        off_constant,
        bounds,
        cdt,
        kinds: pslg.kinds,
        segs,
        inputs,
        grid,
        bad: BadQueue::default(),
        enc: VecDeque::new(),
        min_seg: 1e-9 * region.diameter(),
        given_up: 0,
        dropped: HashSet::new(),
    };
    let complete = e.run()?;
    let triangles = e.inside_triangles();
    let points = e
        .cdt
        .vertices()
        .map(|v| DVec2::new(v.position().x, v.position().y))
        .collect();
    Ok(Some(Refined {
        points,
        kinds: e.kinds,
        triangles,
        complete,
        given_up: e.given_up,
    }))
}

impl Engine<'_> {
    fn pos(&self, v: u32) -> DVec2 {
        let p = self.cdt.vertex(vh(v)).position();
        DVec2::new(p.x, p.y)
    }

    /// Main loop: encroached subsegments first, then the worst bad triangle; when both queues
    /// are empty a full sweep re-checks everything (cheap insurance against missed updates).
    fn run(&mut self) -> Result<bool, MeshError> {
        let mut steps = 0usize;
        loop {
            steps += 1;
            if !self.sweep() {
                return Ok(true);
            }
            loop {
                steps += 1;
                if self.cdt.num_vertices() >= self.bounds.max_vertices
                    || steps > self.bounds.max_steps
                {
                    return Ok(false);
                }
                if let Some((k, forced)) = self.enc.pop_front() {
                    self.split_segment(k, forced)?;
                } else if let Some(t) = self.bad.pop() {
                    self.split_triangle(t)?;
                } else {
                    break;
                }
            }
        }
    }

    /// Queue every encroached subsegment and every bad triangle; true if anything was queued.
    fn sweep(&mut self) -> bool {
        let keys: Vec<SegKey> = self.segs.keys().copied().collect();
        for k in keys {
            if self.encroached(k) {
                self.enc.push_back((k, false));
            }
        }
        let faces: Vec<Queued> = self
            .cdt
            .inner_faces()
            .map(|f| (f.vertices().map(|v| v.fix().index() as u32), f.fix()))
            .collect();
        for f in faces {
            self.consider(f);
        }
        !self.enc.is_empty() || !self.bad.is_empty()
    }

    /// Is subsegment `k` encroached by the apex of a triangle on its domain side (either side
    /// of a line's)?
    fn encroached(&self, k: SegKey) -> bool {
        let Some(s) = self.segs.get(&k) else {
            return false;
        };
        if s.frozen {
            return false;
        }
        let (a, b) = (self.pos(s.from), self.pos(s.to));
        self.apexes(s).into_iter().flatten().any(|x| {
            let p = self.pos(x);
            (a - p).dot(b - p) < 0.0
        })
    }

    /// Does subsegment `k` of a polyline piece stray from it by more than [`CHAIN_BEND`] of
    /// its length? Halving a chord that hugs the polyline can double a dent's share, and such
    /// a half is split at the dent whether or not anything encroaches on it.
    fn strays(&self, k: SegKey) -> bool {
        let Some(s) = self.segs.get(&k) else {
            return false;
        };
        let On::Piece(piece) = s.on else {
            return false;
        };
        let Piece::Chain(pts) = &self.region.pieces()[piece] else {
            return false;
        };
        let (a, b) = (self.pos(s.from), self.pos(s.to));
        farthest_between(pts, a, b).is_some_and(|(_, d)| d > CHAIN_BEND * a.distance(b))
    }

    /// Apexes of the triangles on the subsegment inside the domain: the one on its left, and
    /// for a line's the one on its right as well.
    fn apexes(&self, s: &Seg) -> [Option<u32>; 2] {
        let Some(e) = self.cdt.get_edge_from_neighbors(vh(s.from), vh(s.to)) else {
            return [None, None];
        };
        let apex = |e: spade::handles::DirectedEdgeHandle<_, _, _, _>| {
            e.opposite_vertex().map(|v| v.fix().index() as u32)
        };
        [apex(e), (s.on == On::Line).then(|| apex(e.rev())).flatten()]
    }

    /// Is the CCW face (a, b, c) inside the region's current subsegment polygon?
    ///
    /// Decided topologically wherever possible: a face with a Steiner vertex inside Ω is inside
    /// (its star cannot cross a subsegment), a face on a subsegment is inside iff it lies left of
    /// the subsegment's loop direction, and any other face takes the class of the first such face
    /// a short walk across non-subsegment edges reaches (reaching the convex hull means outside).
    /// Only if the walk finds nothing is the centroid ray-cast: then it is far from ∂Ω, where
    /// rounding cannot flip the answer (unlike for the slivers between nearly collinear
    /// boundary vertices).
    fn inside(&self, f: [u32; 3]) -> bool {
        if let Some(c) = self.classify_local(f) {
            return c;
        }
        let mut seen = vec![canonical(f)];
        let mut queue = VecDeque::from([f]);
        while let Some(g) = queue.pop_front() {
            if seen.len() > 64 {
                break;
            }
            for i in 0..3 {
                let (a, b) = (g[i], g[(i + 1) % 3]);
                let Some(e) = self.cdt.get_edge_from_neighbors(vh(b), vh(a)) else {
                    continue;
                };
                let Some(o) = e.opposite_vertex() else {
                    // Across (a, b) is the outside of the convex hull.
                    return false;
                };
                let h = [b, a, o.fix().index() as u32];
                if seen.contains(&canonical(h)) {
                    continue;
                }
                if let Some(c) = self.classify_local(h) {
                    return c;
                }
                seen.push(canonical(h));
                queue.push_back(h);
            }
        }
        let g = (self.pos(f[0]) + self.pos(f[1]) + self.pos(f[2])) / 3.0;
        self.grid.contains(g, |v| self.pos(v))
    }

    /// The class of a face from its own vertices and edges, if they decide it.
    fn classify_local(&self, f: [u32; 3]) -> Option<bool> {
        if f.iter()
            .any(|&v| matches!(self.kinds[v as usize], VKind::Interior | VKind::Line))
        {
            return Some(true);
        }
        for i in 0..3 {
            let (a, b) = (f[i], f[(i + 1) % 3]);
            if let Some(s) = self.segs.get(&key(a, b)).filter(|s| s.on != On::Line) {
                // The region lies left of each boundary subsegment's loop direction.
                return Some(s.from == a);
            }
        }
        None
    }

    fn max_area_at(&self, g: DVec2) -> f64 {
        if self.density.is_uniform() {
            self.bounds.max_area
        } else {
            self.bounds.max_area / self.density.at(g).max(1e-300).sqrt()
        }
    }

    /// If the face is inside and bad, the sine of its smallest angle (its priority).
    fn badness(&self, f: [u32; 3]) -> Option<f64> {
        let p = f.map(|v| self.pos(v));
        let area = triangle_signed_area(p[0], p[1], p[2]);
        // Edge i is opposite vertex i.
        let l2 = [
            (p[2] - p[1]).length_squared(),
            (p[0] - p[2]).length_squared(),
            (p[1] - p[0]).length_squared(),
        ];
        let short = (0..3).min_by(|&i, &j| l2[i].total_cmp(&l2[j])).unwrap();
        let (o1, o2) = ((short + 1) % 3, (short + 2) % 3);
        let sin_min = 2.0 * area / (l2[o1] * l2[o2]).sqrt();
        let mut bad_angle = sin_min < self.sin_bound;
        if bad_angle && self.input_angle_forced(f[o1], f[o2]) {
            bad_angle = false;
        }
        let g = (p[0] + p[1] + p[2]) / 3.0;
        let bad_area = area > self.max_area_at(g);
        (bad_angle || bad_area).then_some(sin_min)
    }

    /// Triangle's exemption for small input angles: the shortest edge (b1, b2) of a skinny
    /// triangle is not a subsegment but joins vertices on two input segments that meet at a
    /// common end point, at equal distances (within 0.1% squared) from it. Splitting such a
    /// triangle would only cascade towards the input angle.
    fn input_angle_forced(&self, b1: u32, b2: u32) -> bool {
        if self.segs.contains_key(&key(b1, b2))
            || self.kinds[b1 as usize] == VKind::Interior
            || self.kinds[b2 as usize] == VKind::Interior
        {
            return false;
        }
        let (in1, in2) = (self.inputs_at(b1), self.inputs_at(b2));
        let (p1, p2) = (self.pos(b1), self.pos(b2));
        for &s1 in &in1 {
            for &s2 in &in2 {
                if s1 == s2 {
                    continue;
                }
                let ((o1, d1), (o2, d2)) = (self.inputs[s1 as usize], self.inputs[s2 as usize]);
                // Consecutive along a loop, or lines (and a line and a wall) that meet at an end
                // or a crossing, which they share in either direction.
                let join = if d1 == o2 || d1 == d2 {
                    d1
                } else if o1 == d2 || o1 == o2 {
                    o1
                } else {
                    continue;
                };
                let j = self.pos(join);
                let (e1, e2) = ((p1 - j).length_squared(), (p2 - j).length_squared());
                if e1 < 1.001 * e2 && e1 > 0.999 * e2 {
                    return true;
                }
            }
        }
        false
    }

    /// Input segments through boundary vertex `v` (one, or two at an input vertex).
    fn inputs_at(&self, v: u32) -> Vec<u32> {
        let mut out = Vec::with_capacity(2);
        for e in self.cdt.vertex(vh(v)).out_edges() {
            let w = e.to().fix().index() as u32;
            if let Some(s) = self.segs.get(&key(v, w)) {
                if !out.contains(&s.input) {
                    out.push(s.input);
                }
            }
        }
        out
    }

    fn consider(&mut self, (f, face): Queued) {
        // Hashing every considered face for a set that is almost always empty cost more than
        // the test itself.
        if (!self.dropped.is_empty() && self.dropped.contains(&canonical(f))) || !self.inside(f) {
            return;
        }
        if let Some(sin_min) = self.badness(f) {
            self.bad.push(sin_min, (f, face));
        }
    }

    fn consider_star(&mut self, v: u32) {
        let faces: Vec<Queued> = self
            .cdt
            .vertex(vh(v))
            .out_edges()
            .filter_map(|e| {
                e.face()
                    .as_inner()
                    .map(|f| (f.vertices().map(|x| x.fix().index() as u32), f.fix()))
            })
            .collect();
        for f in faces {
            self.consider(f);
        }
    }

    /// After a boundary vertex was added: queue the subsegments it may encroach (those
    /// opposite it in its star).
    fn check_encroached_near(&mut self, v: u32) {
        let opposite: Vec<SegKey> = self
            .cdt
            .vertex(vh(v))
            .out_edges()
            .filter(|e| e.face().as_inner().is_some())
            .map(|e| {
                let n = e.next();
                key(n.from().fix().index() as u32, n.to().fix().index() as u32)
            })
            .collect();
        for k in opposite {
            if self.encroached(k) {
                self.enc.push_back((k, false));
            }
        }
    }

    /// The edge from `f[0]` to `f[1]` of the face queued as `(f, face)`, if the triangulation
    /// still has that triangle. A triangle that was never destroyed keeps its face, so the
    /// queued face answers most pops without walking around a vertex. A triangle can also be
    /// destroyed and made again in another face (a subsegment's constraint lifted, its edge
    /// flipped, then forced back), so a face that no longer holds it is not the last word:
    /// the triangle is then looked up by its vertices.
    fn queued_edge(&self, (f, face): Queued) -> Option<FixedDirectedEdgeHandle> {
        #[cfg(test)]
        if tests::LOOKUP_ONLY.with(std::cell::Cell::get) {
            return self.lookup(f);
        }
        self.cdt
            .face(face)
            .adjacent_edges()
            .into_iter()
            .find(|e| e.from().fix().index() as u32 == f[0])
            .filter(|e| {
                e.to().fix().index() as u32 == f[1] && e.next().to().fix().index() as u32 == f[2]
            })
            .map(|e| e.fix())
            .or_else(|| self.lookup(f))
    }

    /// The edge from `f[0]` to `f[1]` if the triangulation has the triangle `f`, found by
    /// walking around `f[0]`.
    fn lookup(&self, f: [u32; 3]) -> Option<FixedDirectedEdgeHandle> {
        self.cdt
            .get_edge_from_neighbors(vh(f[0]), vh(f[1]))
            .filter(|e| {
                e.opposite_vertex()
                    .is_some_and(|v| v.fix().index() as u32 == f[2])
            })
            .map(|e| e.fix())
    }

    fn split_triangle(&mut self, t: (f64, Queued)) -> Result<(), MeshError> {
        let f = t.1 .0;
        let first = self.queued_edge(t.1);
        #[cfg(test)]
        tests::POPS.with(|p| p.borrow_mut().push(first.is_some()));
        let Some(first) = first else {
            return Ok(());
        };
        if !self.inside(f) || self.badness(f).is_none() {
            return Ok(());
        }
        let p = f.map(|v| self.pos(v));
        let c = self.steiner_point(p);
        // Simulate the insertion: the cavity of faces whose circumcircle holds c, grown from
        // the bad triangle (whose circumcircle holds c) and bounded by subsegments. Every
        // triangle the segment from the bad triangle to c crosses has c in its circumcircle, so
        // c is visible from the triangle iff the face holding c is in the cavity.
        // Its faces are walked along their edges, each held with the edge from its first
        // vertex to its second, so no neighbour has to be looked up by its vertices.
        let mut cavity = Listed::from(canonical(f));
        let mut stack = vec![(f, first)];
        let mut walls: Listed<SegKey> = Listed::default();
        while let Some((fc, edge)) = stack.pop() {
            let mut e = self.cdt.directed_edge(edge);
            for i in 0..3 {
                if i > 0 {
                    e = e.next();
                }
                let (a, b) = (fc[i], fc[(i + 1) % 3]);
                let k = key(a, b);
                if e.is_constraint_edge() {
                    debug_assert!(self.segs.contains_key(&k));
                    if !walls.contains(&k) {
                        walls.push(k);
                    }
                    continue;
                }
                debug_assert!(!self.segs.contains_key(&k));
                let r = e.rev();
                let Some(o) = r.opposite_vertex() else {
                    continue;
                };
                let nb = [b, a, o.fix().index() as u32];
                let cn = canonical(nb);
                if cavity.contains(&cn) {
                    continue;
                }
                let q = nb.map(|v| self.pos(v));
                if robust::incircle(coord(q[0]), coord(q[1]), coord(q[2]), coord(c)) > 0.0 {
                    cavity.push(cn);
                    stack.push((nb, r.fix()));
                }
            }
        }
        let holder: Vec<[u32; 3]> = match self.cdt.locate_with_hint(pt(c), vh(f[0])) {
            PositionInTriangulation::OnFace(face) => vec![self
                .cdt
                .face(face)
                .vertices()
                .map(|v| v.fix().index() as u32)],
            PositionInTriangulation::OnEdge(e) => {
                let e = self.cdt.directed_edge(e);
                [e, e.rev()]
                    .iter()
                    .filter_map(|h| {
                        h.face()
                            .as_inner()
                            .map(|fc| fc.vertices().map(|v| v.fix().index() as u32))
                    })
                    .collect()
            }
            _ => Vec::new(),
        };
        let walls = walls.items;
        let on_wall = walls.iter().copied().find(|k| {
            let (a, b) = (self.pos(k.0), self.pos(k.1));
            robust::orient2d(coord(a), coord(b), coord(c)) == 0.0 && (a - c).dot(b - c) <= 0.0
        });
        if let Some(k) = on_wall {
            return self.force_split(&[k], t);
        }
        if holder.is_empty() || !holder.iter().all(|h| cavity.contains(&canonical(*h))) {
            // c lies beyond a subsegment of the cavity's wall: split the first one the segment
            // from the triangle's centroid to c crosses (or, failing that, the nearest).
            let g = (p[0] + p[1] + p[2]) / 3.0;
            let crossing = walls
                .iter()
                .filter_map(|k| crossing_param(g, c, self.pos(k.0), self.pos(k.1)).map(|s| (s, *k)))
                .min_by(|x, y| x.0.total_cmp(&y.0))
                .map(|x| x.1);
            let nearest = || {
                walls
                    .iter()
                    .filter(|k| self.segs.get(k).is_some_and(|s| !s.frozen))
                    .min_by(|x, y| {
                        let dx = segment_distance(c, self.pos(x.0), self.pos(x.1));
                        let dy = segment_distance(c, self.pos(y.0), self.pos(y.1));
                        dx.total_cmp(&dy)
                    })
                    .copied()
            };
            return match crossing.or_else(nearest) {
                Some(k) => self.force_split(&[k], t),
                None => {
                    self.give_up(f);
                    Ok(())
                }
            };
        }
        // c would encroach a wall subsegment if the angle it makes there exceeds 90°.
        let encroached: Vec<SegKey> = walls
            .into_iter()
            .filter(|k| {
                let (a, b) = (self.pos(k.0), self.pos(k.1));
                (a - c).dot(b - c) < 0.0
            })
            .collect();
        if !encroached.is_empty() {
            return self.force_split(&encroached, t);
        }
        let n = self.cdt.num_vertices();
        let v = self
            .cdt
            .insert_with_hint(pt(c), vh(f[0]))
            .map_err(|e| failed(format!("insertion: {e:?}")))?;
        if v.index() < n {
            self.give_up(f);
            return Ok(());
        }
        self.kinds.push(VKind::Interior);
        self.consider_star(v.index() as u32);
        Ok(())
    }

    /// Triangle's new vertex for a bad triangle: the off-center on the shortest edge's
    /// bisector when it is nearer to that edge than the circumcenter, else the circumcenter.
    fn steiner_point(&self, p: [DVec2; 3]) -> DVec2 {
        let cc = circumcenter(p[0], p[1], p[2]);
        if self.off_constant <= 0.0 {
            return cc;
        }
        // Shortest edge (p[i], p[i+1]): the triangle lies to its left (CCW order).
        let i = (0..3)
            .min_by(|&i, &j| {
                let li = (p[(i + 1) % 3] - p[i]).length_squared();
                let lj = (p[(j + 1) % 3] - p[j]).length_squared();
                li.total_cmp(&lj)
            })
            .unwrap();
        let (o, d) = (p[i], p[(i + 1) % 3]);
        let e = d - o;
        let off = o + 0.5 * e + self.off_constant * e.perp();
        if (off - o).length_squared() < (cc - o).length_squared() {
            off
        } else {
            cc
        }
    }

    fn force_split(&mut self, keys: &[SegKey], t: (f64, Queued)) -> Result<(), MeshError> {
        let mut any = false;
        for &k in keys {
            if self.segs.get(&k).is_some_and(|s| !s.frozen) {
                self.enc.push_front((k, true));
                any = true;
            }
        }
        if any {
            self.bad.push(t.0, t.1);
        } else {
            self.give_up(t.1 .0);
        }
        Ok(())
    }

    fn give_up(&mut self, f: [u32; 3]) {
        self.given_up += 1;
        self.dropped.insert(canonical(f));
    }

    /// Split subsegment `k` (if it still exists and, unless forced, is still encroached).
    fn split_segment(&mut self, k: SegKey, forced: bool) -> Result<(), MeshError> {
        let Some(&s) = self.segs.get(&k) else {
            return Ok(());
        };
        if s.frozen || (!forced && !self.encroached(k)) {
            return Ok(());
        }
        let (a, b) = (s.from, s.to);
        let (pa, pb) = (self.pos(a), self.pos(b));
        let len = (pb - pa).length();
        if len < self.min_seg {
            self.freeze(k);
            return Ok(());
        }
        // Concentric shells: if the domain triangle on this subsegment has another segment at
        // one end, split at a power of two from that end (Triangle's rule).
        let apexes = self.apexes(&s);
        let acute_a = apexes
            .iter()
            .flatten()
            .any(|&x| self.segs.contains_key(&key(a, x)));
        let acute_b = apexes
            .iter()
            .flatten()
            .any(|&x| self.segs.contains_key(&key(b, x)));
        let mut split = 0.5;
        if acute_a || acute_b {
            let mut p2 = 1.0f64;
            while len > 3.0 * p2 {
                p2 *= 2.0;
            }
            while len < 1.5 * p2 {
                p2 *= 0.5;
            }
            split = p2 / len;
            if acute_b {
                split = 1.0 - split;
            }
        }
        let m = match s.on {
            On::Line => pa.lerp(pb, split),
            On::Piece(piece) => self.split_point_on_piece(piece, pa, pb, split, acute_b),
        };
        let (dm_a, dm_b) = ((m - pa).length(), (m - pb).length());
        if !m.is_finite() || dm_a < 0.05 * len || dm_b < 0.05 * len {
            self.freeze(k);
            return Ok(());
        }
        let edge = self
            .cdt
            .get_edge_from_neighbors(vh(a), vh(b))
            .ok_or_else(|| failed("subsegment missing from the triangulation".into()))?
            .fix()
            .as_undirected();
        self.cdt.remove_constraint_edge(edge);
        let conflict = self
            .cdt
            .get_conflicting_edges_between_points(pt(pa), pt(m))
            .next()
            .is_some()
            || self
                .cdt
                .get_conflicting_edges_between_points(pt(m), pt(pb))
                .next()
                .is_some();
        let n = self.cdt.num_vertices();
        let v = if conflict {
            None
        } else {
            let v = self
                .cdt
                .insert_with_hint(pt(m), vh(a))
                .map_err(|e| failed(format!("insertion: {e:?}")))?;
            (v.index() == n).then_some(v)
        };
        let Some(v) = v else {
            // Another boundary runs through the lens of this chord, or m hit a vertex:
            // restore the subsegment and leave it as it is.
            self.cdt.add_constraint(vh(a), vh(b));
            self.freeze(k);
            return Ok(());
        };
        self.kinds.push(match s.on {
            On::Piece(piece) => VKind::Boundary(piece),
            On::Line => VKind::Line,
        });
        let vi = v.index() as u32;
        let e1 = self.cdt.try_add_constraint(vh(a), v);
        let e2 = self.cdt.try_add_constraint(v, vh(b));
        if e1.len() != 1 || e2.len() != 1 {
            return Err(failed(format!(
                "could not split boundary segment at ({}, {})",
                m.x, m.y
            )));
        }
        self.segs.remove(&k);
        if s.on != On::Line {
            self.grid.remove(k, pa, pb);
        }
        for (x, y) in [(a, vi), (vi, b)] {
            self.segs.insert(
                key(x, y),
                Seg {
                    from: x,
                    to: y,
                    frozen: false,
                    ..s
                },
            );
            if s.on != On::Line {
                self.grid.insert(key(x, y), self.pos(x), self.pos(y));
            }
        }
        for kk in [key(a, vi), key(vi, b)] {
            if self.strays(kk) {
                self.enc.push_back((kk, true));
            } else if self.encroached(kk) {
                self.enc.push_back((kk, false));
            }
        }
        self.check_encroached_near(vi);
        for w in [vi, a, b] {
            self.consider_star(w);
        }
        Ok(())
    }

    /// Where a subsegment of boundary piece `piece` from `pa` to `pb` is split: at `split` of
    /// its length (from `pb`'s end when `from_b`, a concentric shell there), on the curve for
    /// a curved piece, at a polyline's farthest vertex when the chord strays from it.
    fn split_point_on_piece(
        &self,
        piece: PieceId,
        pa: DVec2,
        pb: DVec2,
        split: f64,
        from_b: bool,
    ) -> DVec2 {
        let len = pa.distance(pb);
        let curve = &self.region.pieces()[piece];
        let bend = match curve {
            Piece::Chain(pts) => farthest_between(pts, pa, pb)
                .filter(|&(_, d)| d > CHAIN_BEND * len)
                .map(|(v, _)| v),
            _ => None,
        };
        if let Some(v) = bend {
            v
        } else if !is_curved(curve) {
            pa.lerp(pb, split)
        } else if split == 0.5 {
            self.region
                .project_point_onto_piece(pa.lerp(pb, 0.5), piece)
        } else {
            // On the curve at the shell's Euclidean distance from the shell's centre end.
            let (centre, other, r) = if from_b {
                (pb, pa, (1.0 - split) * len)
            } else {
                (pa, pb, split * len)
            };
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                let q = self
                    .region
                    .project_point_onto_piece(centre.lerp(other, mid), piece);
                if (q - centre).length() < r {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            self.region
                .project_point_onto_piece(centre.lerp(other, 0.5 * (lo + hi)), piece)
        }
    }

    fn freeze(&mut self, k: SegKey) {
        if let Some(s) = self.segs.get_mut(&k) {
            s.frozen = true;
            self.given_up += 1;
        }
    }

    /// The faces inside the region: flood fill from the domain side of every subsegment,
    /// never crossing a boundary subsegment (topological, so exact).
    fn inside_triangles(&self) -> Vec<[u32; 3]> {
        let mut seen = vec![false; self.cdt.num_all_faces()];
        let mut stack = Vec::new();
        for s in self.segs.values() {
            if let Some(e) = self.cdt.get_edge_from_neighbors(vh(s.from), vh(s.to)) {
                if let Some(f) = e.face().as_inner() {
                    if !std::mem::replace(&mut seen[f.fix().index()], true) {
                        stack.push(f.fix());
                    }
                }
            }
        }
        while let Some(f) = stack.pop() {
            for e in self.cdt.face(f).adjacent_edges() {
                // The region lies on both sides of a line.
                if e.is_constraint_edge()
                    && self
                        .segs
                        .get(&key(
                            e.from().fix().index() as u32,
                            e.to().fix().index() as u32,
                        ))
                        .is_none_or(|s| s.on != On::Line)
                {
                    continue;
                }
                if let Some(g) = e.rev().face().as_inner() {
                    if !std::mem::replace(&mut seen[g.fix().index()], true) {
                        stack.push(g.fix());
                    }
                }
            }
        }
        self.cdt
            .inner_faces()
            .filter(|f| seen[f.fix().index()])
            .map(|f| f.vertices().map(|v| v.fix().index() as u32))
            .collect()
    }
}

/// Parameter along g→c where it crosses segment ab (None if it does not).
fn crossing_param(g: DVec2, c: DVec2, a: DVec2, b: DVec2) -> Option<f64> {
    let (r, q) = (c - g, b - a);
    let den = r.perp_dot(q);
    if den == 0.0 {
        return None;
    }
    let s = (a - g).perp_dot(q) / den;
    let u = (a - g).perp_dot(r) / den;
    ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&u)).then_some(s)
}

/// A list in insertion order that answers membership in constant time once it grows. A
/// cavity is a handful of faces, where a list is cheaper than hashing; but in a sliver with a
/// small input angle, refined down to the vertex budget, a cavity held nearly a thousand
/// faces and its wall as many subsegments, and searching the lists made each insertion
/// quadratic.
struct Listed<T> {
    items: Vec<T>,
    index: Option<HashSet<T>>,
}

impl<T> Default for Listed<T> {
    fn default() -> Self {
        Listed {
            items: Vec::new(),
            index: None,
        }
    }
}

impl<T: Copy + Eq + std::hash::Hash> Listed<T> {
    /// Past this many items, membership goes through a hash set.
    const INDEX_FROM: usize = 32;

    fn from(first: T) -> Self {
        Listed {
            items: vec![first],
            index: None,
        }
    }

    fn contains(&self, x: &T) -> bool {
        match &self.index {
            Some(set) => set.contains(x),
            None => self.items.contains(x),
        }
    }

    fn push(&mut self, x: T) {
        self.items.push(x);
        match &mut self.index {
            Some(set) => {
                set.insert(x);
            }
            None if self.items.len() > Self::INDEX_FROM => {
                self.index = Some(self.items.iter().copied().collect());
            }
            None => {}
        }
    }
}

/// Rotation-invariant key of a CCW triangle.
fn canonical(f: [u32; 3]) -> [u32; 3] {
    let i = (0..3).min_by_key(|&i| f[i]).unwrap();
    [f[i], f[(i + 1) % 3], f[(i + 2) % 3]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Refine;
    use geometry::LoopRole;
    use mesh::{MeshRequest, Mesher};

    thread_local! {
        /// Pops decided by the vertex lookup alone (the plain test the queued face speeds up).
        pub(super) static LOOKUP_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
        /// Whether each pop found its triangle, in order.
        pub(super) static POPS: std::cell::RefCell<Vec<bool>> = const { std::cell::RefCell::new(Vec::new()) };
    }

    /// The queued face is only a shortcut: every pop must find its triangle exactly when the
    /// lookup by vertices does, and the meshes must be the same. The first region is a fuzzed
    /// pentagon where a split subsegment's lifted constraint let a queued triangle be flipped
    /// away and forced back in another face (queued again there, so the mesh comes out the
    /// same either way: only the pops tell).
    #[test]
    fn pops_decide_as_the_lookup_by_vertices_does() {
        let pentagon = Region::from_loops(
            "fuzzed",
            vec![(
                LoopRole::Outer,
                [(1.0, 0.0), (0.0, 13.0), (5.0, 11.0), (1.0, 1.0), (4.0, 8.0)]
                    .map(|(x, y)| DVec2::new(x, y))
                    .to_vec(),
            )],
        )
        .unwrap()
        .with_default_corners();
        let cases = [
            (pentagon, MeshRequest::points(28).tol(1e-2).max_iter(4)),
            (
                Region::builtin("pie_hole").unwrap(),
                MeshRequest::points(287),
            ),
            (Region::builtin("lake").unwrap(), MeshRequest::points(1109)),
        ];
        for (region, request) in cases {
            let mesh = |lookup_only: bool| {
                LOOKUP_ONLY.with(|l| l.set(lookup_only));
                let r = Refine::default().mesh_parts(&region, &request, &mut |_| {});
                LOOKUP_ONLY.with(|l| l.set(false));
                (
                    r.unwrap(),
                    POPS.with(|p| std::mem::take(&mut *p.borrow_mut())),
                )
            };
            let ((fast, pops_fast), (plain, pops_plain)) = (mesh(false), mesh(true));
            assert!(
                pops_fast == pops_plain,
                "{}: a pop found its triangle in one and not the other",
                region.name()
            );
            assert_eq!(fast.mesh.points, plain.mesh.points, "{}", region.name());
            assert_eq!(
                fast.mesh.triangles,
                plain.mesh.triangles,
                "{}",
                region.name()
            );
            // The notes count the triangles given up on.
            assert_eq!(fast.notes, plain.notes, "{}", region.name());
        }
    }

    #[test]
    fn circumcenter_is_equidistant() {
        let (a, b, c) = (
            DVec2::new(0.3, -1.2),
            DVec2::new(2.5, 0.1),
            DVec2::new(-0.7, 1.9),
        );
        let o = circumcenter(a, b, c);
        let r = (a - o).length();
        assert!(((b - o).length() - r).abs() < 1e-12 && ((c - o).length() - r).abs() < 1e-12);
    }

    #[test]
    fn crossing_parameter() {
        let (g, c) = (DVec2::ZERO, DVec2::new(4.0, 0.0));
        let s = crossing_param(g, c, DVec2::new(1.0, -1.0), DVec2::new(1.0, 1.0)).unwrap();
        assert!((s - 0.25).abs() < 1e-15);
        assert!(crossing_param(g, c, DVec2::new(5.0, -1.0), DVec2::new(5.0, 1.0)).is_none());
        assert!(crossing_param(g, c, DVec2::new(1.0, 1.0), DVec2::new(2.0, 1.0)).is_none());
    }

    #[test]
    fn a_listed_set_keeps_its_order_and_answers_membership_past_its_index_size() {
        let mut l: Listed<u32> = Listed::default();
        for i in (0..100).rev() {
            assert!(!l.contains(&i));
            l.push(i);
            assert!(l.contains(&i) && l.contains(&99));
        }
        assert!(l.index.is_some() && !l.contains(&100));
        assert_eq!(l.items, (0..100).rev().collect::<Vec<_>>());
    }

    #[test]
    fn canonical_is_rotation_invariant() {
        assert_eq!(canonical([5, 2, 9]), [2, 9, 5]);
        assert_eq!(canonical([9, 5, 2]), [2, 9, 5]);
        assert_ne!(canonical([2, 5, 9]), [2, 9, 5]);
    }
}
