//! The relaxation loop MESHGEN and VTM share: initial points, the boundary constraint, the
//! triangulate–move–repeat iteration and its convergence test. Only the vertex targets differ
//! between the two methods, so they are passed in as a function of the current mesh.
//!
//! The `vtm` crate calls [`relax`] with its own targets, so the two methods cannot drift apart
//! in how they treat the boundary. Another relaxation method (any rule that moves each vertex
//! to a target computed from the current mesh) can be built the same way.
//!
//! * **Initial points.** The corners; on every *side* (the stretch of a boundary loop between
//!   two consecutive corners, or a whole loop without corners) `n = round(L/h₀)` equal
//!   arc-length segments, i.e. `n − 1` points on the exact curve (at least 3 points on a
//!   corner-free loop, at least 3 vertices per loop, and more where a chord would cut more than
//!   0.1 of its length into a concave curve or cross another side's chord); inside, an
//!   equilateral lattice of spacing `h₀`, randomly shifted and jittered by up to ±0.15 h₀ per
//!   coordinate (seeded [`geometry::Rng`]), keeping points at least h₀/2 inside the polygon of
//!   the boundary points. `h₀` is found by bisection as the largest spacing giving at least K
//!   points; the few surplus interior points are dropped at random, so the total is exactly K.
//! * **Boundary.** Corners are fixed. A boundary vertex moves to the method's target projected
//!   onto its own side (the nearest point of the side's pieces; it may pass smooth junctions
//!   between pieces, never a corner). It keeps its order along the side: the move is clamped at
//!   0.1 h (arc length) from the side's corners and withdrawn (the vertex stays) if it would
//!   come within 0.1 h of a neighbour, make a chord cut more than 0.1 of its length into a
//!   concave curve, or make two boundary chords cross. Interior vertices stay 0.1 h inside Ω
//!   and inside the boundary polygon (a move that would leave is halved up to three times,
//!   then dropped).
//! * **Iteration.** Triangulate ([`tessellation::conforming_mesh`]: constrained Delaunay with
//!   the boundary vertices joined along each loop), compute targets, move; stop when the
//!   largest move is below `tol · h` (h = [`MeshRequest::spacing`]), converged = false if
//!   `max_iter` is reached first. The final mesh is checked with [`mesh::check_conforming`];
//!   a K too small to follow a thin or strongly curved part of the boundary is an error.
use geometry::predicates::{edge_crosses_ray, segment_distance, segments_cross};
use geometry::{DVec2, Density, Piece, PieceId, Region, Rng};
use mesh::{Mesh, MeshError, MeshRequest, MeshResult, Progress, VertexMarker};

/// Lattice points keep this many h₀ from the boundary polygon.
const LATTICE_MARGIN: f64 = 0.5;
/// Lattice jitter, in h₀, per coordinate.
const JITTER: f64 = 0.15;
/// Smallest arc-length gap, in h, between neighbouring vertices of a side.
const SIDE_GAP: f64 = 0.1;
/// Smallest distance, in h, of an interior vertex from the boundary polygon.
const INTERIOR_MARGIN: f64 = 0.1;
/// Largest distance a boundary chord may stray outside Ω (over a concave curve), as a fraction
/// of its length: below the 0.13 that `mesh::check_conforming` allows.
const CHORD_BULGE: f64 = 0.1;

/// True if the chord `a`–`b` stays within CHORD_BULGE·|ab| of Ω.
fn chord_ok(region: &Region, a: DVec2, b: DVec2) -> bool {
    let allowed = CHORD_BULGE * (b - a).length();
    (1..8).all(|k| region.signed_distance(a.lerp(b, k as f64 / 8.0)) <= allowed)
}

/// A method's rule for [`relax`]: from the current mesh and the density, the targets of one
/// iteration (one per vertex; corners' are ignored) and the method's objective at the current
/// mesh (NaN if none).
pub type TargetFn<'a> = dyn Fn(&Mesh, &Density) -> (Vec<DVec2>, f64) + 'a;

/// The stretch of a boundary loop between two consecutive corners (or a whole corner-free loop),
/// parametrised by arc length `s ∈ [0, length]` from its start corner.
struct Side {
    loop_index: usize,
    pieces: Vec<PieceId>,
    /// Arc length at the start of each piece.
    starts: Vec<f64>,
    length: f64,
    /// A whole loop without corners (cyclic parameter).
    closed: bool,
    /// Corner at s = 0 (`None` for a closed side).
    start_corner: Option<usize>,
    /// Start and end points (the corners of an open side).
    ends: (DVec2, DVec2),
    /// Only straight pieces: chords lie on the boundary.
    straight: bool,
}

/// A piece sampled finely, for placing points at a given arc length before snapping them onto
/// the exact curve.
struct Polyline {
    pts: Vec<DVec2>,
    /// Arc length at each point, rescaled so the last equals the piece's exact length.
    cum: Vec<f64>,
}

impl Polyline {
    fn at(&self, t: f64) -> DVec2 {
        let n = self.pts.len();
        if n == 1 {
            return self.pts[0];
        }
        let i = self.cum.partition_point(|&c| c <= t).clamp(1, n - 1);
        let (c0, c1) = (self.cum[i - 1], self.cum[i]);
        let f = if c1 > c0 {
            ((t - c0) / (c1 - c0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.pts[i - 1].lerp(self.pts[i], f)
    }
}

/// The boundary of a region cut into sides.
struct Frame<'a> {
    region: &'a Region,
    sides: Vec<Side>,
    /// Sides of each loop, in traversal order.
    loop_sides: Vec<Vec<usize>>,
    /// Loop arc length at the start of each piece.
    piece_offset: Vec<f64>,
    lines: Vec<Polyline>,
}

/// What a vertex is constrained to.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    Corner(usize),
    /// On `side` at arc length `s` (unwrapped on closed sides), on `piece` at its own arc
    /// length `t`.
    Side {
        side: usize,
        s: f64,
        piece: PieceId,
        t: f64,
    },
    Interior,
}

impl<'a> Frame<'a> {
    fn new(region: &'a Region, h: f64) -> Result<Frame<'a>, MeshError> {
        let fail = |m: String| MeshError::Failed {
            method: "boundary".into(),
            message: m,
        };
        let pieces = region.pieces();
        let mut piece_offset = vec![0.0; pieces.len()];
        for lp in region.loops() {
            for (k, &p) in lp.pieces.iter().enumerate() {
                piece_offset[p] = lp.offsets[k];
            }
        }
        let lines = pieces
            .iter()
            .map(|piece| {
                let pts = piece.polygonize(1e-4 * h);
                let mut cum = Vec::with_capacity(pts.len());
                let mut acc = 0.0;
                for (i, p) in pts.iter().enumerate() {
                    if i > 0 {
                        acc += (*p - pts[i - 1]).length();
                    }
                    cum.push(acc);
                }
                let scale = if acc > 0.0 { piece.length() / acc } else { 1.0 };
                cum.iter_mut().for_each(|c| *c *= scale);
                Polyline { pts, cum }
            })
            .collect();
        let mut sides = Vec::new();
        let mut loop_sides = Vec::new();
        for (l, lp) in region.loops().iter().enumerate() {
            let m = lp.pieces.len();
            let mut starts: Vec<(usize, usize)> = Vec::new();
            for (ci, c) in region
                .corners()
                .iter()
                .enumerate()
                .filter(|(_, c)| c.loop_index == l)
            {
                let pos = lp
                    .pieces
                    .iter()
                    .position(|&p| p == c.piece_out)
                    .ok_or_else(|| {
                        fail(format!(
                            "corner {ci} starts piece {} outside its loop {l}",
                            c.piece_out
                        ))
                    })?;
                starts.push((pos, ci));
            }
            starts.sort();
            let runs: Vec<(usize, usize, Option<usize>)> = if starts.is_empty() {
                vec![(0, m, None)]
            } else {
                (0..starts.len())
                    .map(|i| {
                        let (p0, ci) = starts[i];
                        let p1 = starts[(i + 1) % starts.len()].0;
                        let count = match (p1 + m - p0) % m {
                            0 => m,
                            c => c,
                        };
                        (p0, count, Some(ci))
                    })
                    .collect()
            };
            let mut ids = Vec::new();
            for (p0, count, start_corner) in runs {
                let ps: Vec<PieceId> = (0..count).map(|k| lp.pieces[(p0 + k) % m]).collect();
                let mut st = Vec::with_capacity(ps.len());
                let mut acc = 0.0;
                for &p in &ps {
                    st.push(acc);
                    acc += pieces[p].length();
                }
                let ends = (pieces[ps[0]].start(), pieces[ps[ps.len() - 1]].end());
                let straight = ps.iter().all(|&p| matches!(pieces[p], Piece::Line { .. }));
                ids.push(sides.len());
                sides.push(Side {
                    loop_index: l,
                    pieces: ps,
                    starts: st,
                    length: acc,
                    closed: start_corner.is_none(),
                    start_corner,
                    ends,
                    straight,
                });
            }
            loop_sides.push(ids);
        }
        Ok(Frame {
            region,
            sides,
            loop_sides,
            piece_offset,
            lines,
        })
    }

    /// The point of side `si` at arc length `s`, on the exact curve.
    fn point_at(&self, si: usize, s: f64) -> (DVec2, PieceId, f64) {
        let side = &self.sides[si];
        let s = if side.closed {
            s.rem_euclid(side.length)
        } else {
            s.clamp(0.0, side.length)
        };
        let j = side.starts.partition_point(|&x| x <= s).max(1) - 1;
        let piece = side.pieces[j];
        let t = (s - side.starts[j]).clamp(0.0, self.region.pieces()[piece].length());
        let (p, t) = self.region.pieces()[piece].closest_point(self.lines[piece].at(t));
        (p, piece, t)
    }

    /// Nearest point of side `si` to `x`: (point, piece, piece arc length, side arc length).
    fn project(&self, si: usize, x: DVec2) -> (DVec2, PieceId, f64, f64) {
        let side = &self.sides[si];
        let mut best = (f64::INFINITY, DVec2::ZERO, 0, 0.0, 0.0);
        for (j, &piece) in side.pieces.iter().enumerate() {
            let (p, t) = self.region.pieces()[piece].closest_point(x);
            let d = (p - x).length_squared();
            if d < best.0 {
                best = (d, p, piece, t, side.starts[j] + t);
            }
        }
        (best.1, best.2, best.3, best.4)
    }

    fn marker(&self, slot: Slot) -> VertexMarker {
        match slot {
            Slot::Corner(c) => {
                let corner = &self.region.corners()[c];
                VertexMarker::Corner {
                    loop_index: corner.loop_index,
                    corner: c,
                    loop_param: corner.loop_param,
                }
            }
            Slot::Side { side, piece, t, .. } => {
                let l = self.sides[side].loop_index;
                let len = self.region.loops()[l].length;
                let mut lp = self.piece_offset[piece] + t;
                if lp >= len {
                    lp -= len;
                }
                VertexMarker::Boundary {
                    loop_index: l,
                    piece,
                    loop_param: lp.max(0.0),
                }
            }
            Slot::Interior => VertexMarker::Interior,
        }
    }

    /// The points of side `si` (without its start corner) dividing it into `n` equal arcs.
    fn side_points(&self, si: usize, n: usize) -> Vec<(DVec2, Slot)> {
        let side = &self.sides[si];
        let first = usize::from(!side.closed);
        (first..n)
            .map(|j| {
                let s = side.length * j as f64 / n as f64;
                let (p, piece, t) = self.point_at(si, s);
                (
                    p,
                    Slot::Side {
                        side: si,
                        s,
                        piece,
                        t,
                    },
                )
            })
            .collect()
    }

    /// True if no chord joining consecutive `points` of side `si` (with its corners at the ends
    /// of an open side) leaves Ω by more than [`CHORD_BULGE`] of its length.
    fn chords_ok(&self, si: usize, points: impl Iterator<Item = DVec2>) -> bool {
        let side = &self.sides[si];
        let mut ring: Vec<DVec2> = Vec::new();
        if !side.closed {
            ring.push(side.ends.0);
        }
        ring.extend(points);
        if side.closed {
            let first = ring[0];
            ring.push(first);
        } else {
            ring.push(side.ends.1);
        }
        side.straight || ring.windows(2).all(|w| chord_ok(self.region, w[0], w[1]))
    }

    /// Corners and boundary points for spacing `h0`, in loop order.
    fn boundary_layout(&self, h0: f64) -> Vec<(DVec2, Slot)> {
        let mut counts = vec![0usize; self.sides.len()];
        for ids in &self.loop_sides {
            for &si in ids {
                let side = &self.sides[si];
                let n = (side.length / h0).round() as usize;
                counts[si] = if side.closed { n.max(3) } else { n.max(1) };
            }
            // Every loop needs at least a triangle's worth of vertices.
            let total: usize = ids.iter().map(|&si| counts[si]).sum();
            if total < 3 {
                let longest = ids
                    .iter()
                    .copied()
                    .max_by(|&a, &b| self.sides[a].length.total_cmp(&self.sides[b].length));
                if let Some(si) = longest {
                    counts[si] += 3 - total;
                }
            }
        }
        let caps: Vec<usize> = counts.iter().map(|&n| 4 * n + 16).collect();
        // More points on a side whose chords cut too deep into a concave curve (a small hole
        // needs about seven points to be meshed at all) ...
        let mut points: Vec<Vec<(DVec2, Slot)>> = (0..self.sides.len())
            .map(|si| loop {
                let pts = self.side_points(si, counts[si]);
                if counts[si] >= caps[si] || self.chords_ok(si, pts.iter().map(|(p, _)| *p)) {
                    break pts;
                }
                counts[si] += 1;
            })
            .collect();
        // ... or whose chords cross another side's (a thin part of the region).
        loop {
            let crossing = self.crossing_sides(&points);
            let mut changed = false;
            for si in crossing {
                if counts[si] < caps[si] {
                    counts[si] += 1;
                    points[si] = self.side_points(si, counts[si]);
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let mut out = Vec::new();
        for &si in self.loop_sides.iter().flatten() {
            if let Some(c) = self.sides[si].start_corner {
                out.push((self.region.corners()[c].pos, Slot::Corner(c)));
            }
            out.append(&mut points[si]);
        }
        out
    }

    /// The chords of every side, from its start corner through its points to its end corner
    /// (cyclically for a closed side), each with its side and its two end vertices (`None`
    /// for a corner). `points[si]` are side `si`'s points in order, with their vertex ids.
    fn chords(&self, points: &[Vec<(DVec2, Option<usize>)>]) -> Vec<Chord> {
        let mut out = Vec::new();
        for (si, side) in self.sides.iter().enumerate() {
            let mut ring = points[si].clone();
            if side.closed {
                if let Some(&first) = ring.first() {
                    ring.push(first);
                }
            } else {
                ring.insert(0, (side.ends.0, None));
                ring.push((side.ends.1, None));
            }
            out.extend(ring.windows(2).map(|w| Chord {
                a: w[0].0,
                b: w[1].0,
                side: si,
                ends: [w[0].1, w[1].1],
            }));
        }
        out
    }

    /// Sides with a chord that properly crosses another chord.
    fn crossing_sides(&self, points: &[Vec<(DVec2, Slot)>]) -> Vec<usize> {
        let points: Vec<Vec<(DVec2, Option<usize>)>> = points
            .iter()
            .map(|ps| ps.iter().map(|(p, _)| (*p, None)).collect())
            .collect();
        let chords = self.chords(&points);
        let mut hit = vec![false; self.sides.len()];
        for (i, j) in crossing_pairs(&chords) {
            hit[chords[i].side] = true;
            hit[chords[j].side] = true;
        }
        (0..self.sides.len()).filter(|&si| hit[si]).collect()
    }
}

/// A segment of the boundary polygon.
#[derive(Clone, Copy, Debug)]
struct Chord {
    a: DVec2,
    b: DVec2,
    side: usize,
    /// Vertex ids of `a` and `b` (`None` for corners).
    ends: [Option<usize>; 2],
}

/// Pairs of chords that properly cross, found through a grid of cells the size of the longest
/// chord so that the cost stays linear in the number of chords.
fn crossing_pairs(chords: &[Chord]) -> Vec<(usize, usize)> {
    let cell = chords
        .iter()
        .map(|c| (c.b - c.a).length())
        .fold(0.0, f64::max);
    if cell <= 0.0 || !cell.is_finite() {
        return Vec::new();
    }
    let key = |p: DVec2| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64);
    let mut grid: std::collections::BTreeMap<(i64, i64), Vec<usize>> = Default::default();
    for (i, c) in chords.iter().enumerate() {
        let (lo, hi) = (key(c.a.min(c.b)), key(c.a.max(c.b)));
        for x in lo.0..=hi.0 {
            for y in lo.1..=hi.1 {
                grid.entry((x, y)).or_default().push(i);
            }
        }
    }
    let mut out = Vec::new();
    for bucket in grid.values() {
        for (n, &i) in bucket.iter().enumerate() {
            for &j in &bucket[n + 1..] {
                let (c, d) = (&chords[i], &chords[j]);
                if segments_cross(c.a, c.b, d.a, d.b) {
                    out.push((i.min(j), i.max(j)));
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// The polygon through the boundary vertices (what the constrained triangulation meshes).
struct Outline {
    segs: Vec<(DVec2, DVec2)>,
    /// Largest distance of a polygon edge from ∂Ω (the sagitta of curved sides), with margin.
    sag: f64,
}

impl Outline {
    fn new(region: &Region, loops: &[Vec<DVec2>]) -> Outline {
        let mut segs = Vec::new();
        let mut sag: f64 = 0.0;
        for ring in loops {
            for i in 0..ring.len() {
                let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                for f in [0.25, 0.5, 0.75] {
                    sag = sag.max(region.signed_distance(a.lerp(b, f)).abs());
                }
                segs.push((a, b));
            }
        }
        Outline {
            segs,
            sag: 1.5 * sag + 1e-9 * region.diameter(),
        }
    }

    /// True if `p` lies at least `margin` inside Ω and inside the polygon.
    fn admits(&self, region: &Region, p: DVec2, margin: f64) -> bool {
        if !p.is_finite() {
            return false;
        }
        let sd = region.signed_distance(p);
        if sd >= -margin {
            return false;
        }
        if sd < -(self.sag + margin) {
            // Deeper than any polygon edge strays from ∂Ω.
            return true;
        }
        let mut inside = false;
        let mut dmin = f64::INFINITY;
        for &(a, b) in &self.segs {
            if edge_crosses_ray(p, a, b) {
                inside = !inside;
            }
            dmin = dmin.min(segment_distance(p, a, b));
        }
        inside && dmin >= margin
    }

    /// `p` moved to `margin` inside the nearest polygon edge (left of it: Ω is left of every
    /// loop, outer CCW and holes CW).
    fn push_inside(&self, p: DVec2, margin: f64) -> DVec2 {
        let mut best = (f64::INFINITY, p, DVec2::ZERO);
        for &(a, b) in &self.segs {
            let ab = b - a;
            let len2 = ab.length_squared();
            if len2 == 0.0 {
                continue;
            }
            let q = a + ab * ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
            let d = (p - q).length();
            if d < best.0 {
                best = (d, q, ab.perp() / len2.sqrt());
            }
        }
        best.1 + best.2 * margin
    }
}

/// Vertices and what each is constrained to.
struct State {
    points: Vec<DVec2>,
    slots: Vec<Slot>,
    /// Vertex indices of each side in order along it (fixed: vertices never overtake).
    side_vertices: Vec<Vec<usize>>,
}

impl State {
    fn new(frame: &Frame, layout: Vec<(DVec2, Slot)>) -> State {
        let mut side_vertices = vec![Vec::new(); frame.sides.len()];
        for (i, (_, slot)) in layout.iter().enumerate() {
            if let Slot::Side { side, .. } = slot {
                side_vertices[*side].push(i);
            }
        }
        let (points, slots) = layout.into_iter().unzip();
        State {
            points,
            slots,
            side_vertices,
        }
    }

    fn markers(&self, frame: &Frame) -> Vec<VertexMarker> {
        self.slots.iter().map(|&s| frame.marker(s)).collect()
    }

    /// The boundary vertices of each loop in traversal order.
    fn outline(&self, frame: &Frame) -> Outline {
        let loops: Vec<Vec<DVec2>> = frame
            .loop_sides
            .iter()
            .map(|ids| {
                let mut ring = Vec::new();
                for &si in ids {
                    if let Some(c) = frame.sides[si].start_corner {
                        ring.push(frame.region.corners()[c].pos);
                    }
                    ring.extend(self.side_vertices[si].iter().map(|&v| self.points[v]));
                }
                ring
            })
            .collect();
        Outline::new(frame.region, &loops)
    }

    /// Where each vertex of side `si` would go: its target projected onto the side, kept
    /// SIDE_GAP·h from the side's corners.
    fn propose(&self, frame: &Frame, si: usize, targets: &[DVec2], h: f64) -> Vec<(DVec2, Slot)> {
        let side = &frame.sides[si];
        // A side shorter than two gaps (a short coastline segment between corners at a coarse
        // spacing) keeps its vertices at its middle.
        let gap = (SIDE_GAP * h).min(0.5 * side.length);
        self.side_vertices[si]
            .iter()
            .map(|&v| {
                let old_s = side_param(self.slots[v]);
                let target = if targets[v].is_finite() {
                    targets[v]
                } else {
                    self.points[v]
                };
                let (mut p, mut piece, mut t, s_proj) = frame.project(si, target);
                let s = if side.closed {
                    // Unwrapped: the shortest way round from the old position.
                    let d = (s_proj - old_s).rem_euclid(side.length);
                    old_s
                        + if d > 0.5 * side.length {
                            d - side.length
                        } else {
                            d
                        }
                } else {
                    let c = s_proj.clamp(gap, side.length - gap);
                    if c != s_proj {
                        (p, piece, t) = frame.point_at(si, c);
                    }
                    c
                };
                (
                    p,
                    Slot::Side {
                        side: si,
                        s,
                        piece,
                        t,
                    },
                )
            })
            .collect()
    }

    /// Move every vertex towards its target under the constraints; returns the largest move.
    fn advance(&mut self, frame: &Frame, targets: &[DVec2], h: f64) -> f64 {
        let old = self.points.clone();
        let old_slots = self.slots.clone();
        let proposals: Vec<Vec<(DVec2, Slot)>> = (0..frame.sides.len())
            .map(|si| self.propose(frame, si, targets, h))
            .collect();
        // Vertices held at their old position because a move made two chords cross.
        let mut held = vec![false; self.points.len()];
        loop {
            for (si, verts) in self.side_vertices.iter().enumerate() {
                let accepted = settle(frame, si, verts, &proposals[si], &old, &old_slots, &held, h);
                for (k, &v) in verts.iter().enumerate() {
                    (self.points[v], self.slots[v]) = if accepted[k] {
                        proposals[si][k]
                    } else {
                        (old[v], old_slots[v])
                    };
                }
            }
            let per_side: Vec<Vec<(DVec2, Option<usize>)>> = self
                .side_vertices
                .iter()
                .map(|verts| verts.iter().map(|&v| (self.points[v], Some(v))).collect())
                .collect();
            let chords = frame.chords(&per_side);
            let mut more = false;
            for (i, j) in crossing_pairs(&chords) {
                for v in chords[i].ends.iter().chain(&chords[j].ends).flatten() {
                    if !held[*v] && self.points[*v] != old[*v] {
                        held[*v] = true;
                        more = true;
                    }
                }
            }
            if !more {
                break;
            }
        }
        let outline = self.outline(frame);
        let margin = INTERIOR_MARGIN * h;
        for v in 0..self.points.len() {
            if self.slots[v] != Slot::Interior {
                continue;
            }
            let d = if targets[v].is_finite() {
                targets[v] - old[v]
            } else {
                DVec2::ZERO
            };
            let region = frame.region;
            let moved = [1.0, 0.5, 0.25, 0.125]
                .into_iter()
                .map(|f| old[v] + d * f)
                .find(|&p| outline.admits(region, p, margin));
            self.points[v] = match moved {
                Some(p) => p,
                // Stay unless the boundary moved over the vertex; then step back inside.
                None if outline.admits(region, old[v], 0.0) => old[v],
                None => {
                    let p = outline.push_inside(old[v], 2.0 * margin);
                    if outline.admits(region, p, 0.0) {
                        p
                    } else {
                        old[v]
                    }
                }
            };
        }
        largest_move(frame.region, &old, &self.points)
    }
}

/// The largest vertex move from `old` to `new`. On a rotationally symmetric region a rotation
/// of the whole point set about the centre costs no energy, and the boundary rule (not an
/// energy gradient) drives one that never dies out (about 1e-4 of the spacing per iteration):
/// the best-fitting rotation, ω = Σ rᵢ × dᵢ / Σ |rᵢ|², is taken out of the moves first, so
/// that the stopping rule measures the mesh's change of shape.
fn largest_move(region: &Region, old: &[DVec2], new: &[DVec2]) -> f64 {
    region
        .moves_without_rotation(old, new)
        .iter()
        .map(|d| d.length())
        .fold(0.0, f64::max)
}

/// Arc length along its side of a side vertex (0 for others).
fn side_param(slot: Slot) -> f64 {
    match slot {
        Slot::Side { s, .. } => s,
        _ => 0.0,
    }
}

/// Which proposals of side `si` are taken (`verts` its vertices in order): all but the `held`
/// ones, then, until none is left, withdraw any that comes within SIDE_GAP·h of a neighbour
/// (at its new or kept position) or of a corner, or whose chord to a neighbour cuts deep into
/// a concave curve. The old positions satisfy all this, so the order along the side is kept.
#[allow(clippy::too_many_arguments)]
fn settle(
    frame: &Frame,
    si: usize,
    verts: &[usize],
    proposals: &[(DVec2, Slot)],
    old: &[DVec2],
    old_slots: &[Slot],
    held: &[bool],
    h: f64,
) -> Vec<bool> {
    let side = &frame.sides[si];
    let n = verts.len();
    let (gap, slack) = (SIDE_GAP * h, 1e-9 * h);
    let mut accepted: Vec<bool> = verts.iter().map(|&v| !held[v]).collect();
    if side.closed && n == 1 {
        return accepted;
    }
    loop {
        let s = |k: usize| {
            side_param(if accepted[k] {
                proposals[k].1
            } else {
                old_slots[verts[k]]
            })
        };
        let pos = |k: usize| {
            if accepted[k] {
                proposals[k].0
            } else {
                old[verts[k]]
            }
        };
        let withdraw: Vec<usize> = (0..n)
            .filter(|&k| accepted[k])
            .filter(|&k| {
                let (first, last) = (k == 0, k + 1 == n);
                let (lo, hi, before, after) = if side.closed {
                    (
                        if first {
                            s(n - 1) - side.length
                        } else {
                            s(k - 1)
                        },
                        if last { s(0) + side.length } else { s(k + 1) },
                        pos((k + n - 1) % n),
                        pos((k + 1) % n),
                    )
                } else {
                    (
                        if first { 0.0 } else { s(k - 1) },
                        if last { side.length } else { s(k + 1) },
                        if first { side.ends.0 } else { pos(k - 1) },
                        if last { side.ends.1 } else { pos(k + 1) },
                    )
                };
                let spaced = s(k) - lo >= gap - slack && hi - s(k) >= gap - slack;
                let chords_fine = side.straight
                    || (chord_ok(frame.region, before, pos(k))
                        && chord_ok(frame.region, pos(k), after));
                !(spaced && chords_fine)
            })
            .collect();
        if withdraw.is_empty() {
            return accepted;
        }
        withdraw.into_iter().for_each(|k| accepted[k] = false);
    }
}

/// The K initial vertices (see the module documentation) and the lattice spacing h₀ used.
fn initial_state(frame: &Frame, k: usize, h: f64, seed: u64) -> Result<(State, f64), MeshError> {
    let region = frame.region;
    let layout = |h0: f64| {
        let boundary = frame.boundary_layout(h0);
        let mut rings: Vec<Vec<DVec2>> = vec![Vec::new(); region.loops().len()];
        for (p, slot) in &boundary {
            match *slot {
                Slot::Corner(c) => rings[region.corners()[c].loop_index].push(*p),
                Slot::Side { side, .. } => rings[frame.sides[side].loop_index].push(*p),
                Slot::Interior => {}
            }
        }
        let outline = Outline::new(region, &rings);
        let interior = lattice(region, &outline, h0, seed);
        (boundary, interior, outline)
    };
    let count = |h0: f64| {
        let (b, i, _) = layout(h0);
        b.len() + i.len()
    };
    let diameter = region.diameter();
    let (mut lo, mut hi);
    if count(h) >= k {
        lo = h;
        hi = 2.0 * h;
        while count(hi) >= k && hi < 4.0 * diameter {
            lo = hi;
            hi *= 2.0;
        }
        if count(hi) >= k {
            lo = hi;
        }
    } else {
        hi = h;
        lo = 0.5 * h;
        let mut halvings = 0;
        while count(lo) < k {
            hi = lo;
            lo *= 0.5;
            halvings += 1;
            if halvings > 40 {
                return Err(MeshError::Failed {
                    method: "initial points".into(),
                    message: format!("could not place {k} points in the region"),
                });
            }
        }
    }
    for _ in 0..40 {
        if hi - lo <= 1e-9 * lo {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if count(mid) >= k {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (mut boundary, mut interior, _) = layout(lo);
    let mut h0 = lo;
    if boundary.len() > k {
        // At the spacing that gives K points the boundary alone has more than K (near the
        // smallest K, or a part of a region meshed with its share of K): take the finest
        // boundary that fits, and draw the points its coarser lattice lacks at random inside.
        let fits = |h0: f64| frame.boundary_layout(h0).len() <= k;
        let (mut fine, mut coarse) = (lo, 2.0 * lo);
        while !fits(coarse) && coarse < 4.0 * diameter {
            fine = coarse;
            coarse *= 2.0;
        }
        if !fits(coarse) {
            return Err(MeshError::BadRequest(format!(
                "K = {k} is too small for region '{}': its boundary alone needs {} vertices",
                region.name(),
                frame.boundary_layout(coarse).len()
            )));
        }
        for _ in 0..40 {
            let mid = 0.5 * (fine + coarse);
            if fits(mid) {
                coarse = mid;
            } else {
                fine = mid;
            }
        }
        let hi = coarse;
        let (b, mut i, outline) = layout(hi);
        let mut rng = Rng::new(seed ^ 0x7265_7374_6f66_6b21);
        let (blo, bhi) = region.bbox();
        let mut tries = 0usize;
        while b.len() + i.len() < k {
            tries += 1;
            if tries > 1000 * k + 10_000 {
                return Err(MeshError::Failed {
                    method: "initial points".into(),
                    message: format!(
                        "could not place {k} points in the region: at the boundary spacing \
                         {hi:.3e} that K = {k} allows, almost none of it lies {:.3e} inside \
                         the boundary; a larger K would mesh it",
                        INTERIOR_MARGIN * hi
                    ),
                });
            }
            let p = DVec2::new(rng.range(blo.x, bhi.x), rng.range(blo.y, bhi.y));
            if outline.admits(region, p, INTERIOR_MARGIN * hi) {
                i.push(p);
            }
        }
        (boundary, interior, h0) = (b, i, hi);
    }
    let surplus = boundary.len() + interior.len() - k;
    // Drop `surplus` distinct interior points chosen at random (partial Fisher–Yates).
    let mut rng = Rng::new(seed ^ 0xD1B5_4A32_D192_ED03);
    let m = interior.len();
    let mut order: Vec<usize> = (0..m).collect();
    for i in 0..surplus {
        let j = i + rng.below(m - i);
        order.swap(i, j);
    }
    let mut dropped = vec![false; m];
    order[..surplus].iter().for_each(|&i| dropped[i] = true);
    let mut all = boundary;
    all.extend(
        interior
            .into_iter()
            .zip(dropped)
            .filter(|(_, d)| !d)
            .map(|(p, _)| (p, Slot::Interior)),
    );
    Ok((State::new(frame, all), h0))
}

/// The boundary vertices of the coarsest layout [`relax`] makes on `region`: every corner, at
/// least three per loop, and more where a chord would cut into a concave curve or cross
/// another side's chord. No K below it can be met; [`relax`] refuses it.
pub fn min_boundary_points(region: &Region) -> usize {
    let d = region.diameter();
    match Frame::new(region, 1e-2 * d) {
        Ok(frame) => frame.boundary_layout(4.0 * d).len(),
        Err(_) => mesh::boundary_points_needed(region),
    }
}

/// Jittered equilateral lattice of spacing `h0`, kept LATTICE_MARGIN·h0 inside the outline.
fn lattice(region: &Region, outline: &Outline, h0: f64, seed: u64) -> Vec<DVec2> {
    let mut rng = Rng::new(seed);
    let (lo, hi) = region.bbox();
    let dy = h0 * 3f64.sqrt() / 2.0;
    let origin = DVec2::new(
        lo.x - h0 + rng.range(0.0, h0),
        lo.y - dy + rng.range(0.0, dy),
    );
    let rows = ((hi.y - origin.y) / dy).ceil() as usize + 1;
    let cols = ((hi.x - origin.x) / h0).ceil() as usize + 1;
    let mut out = Vec::new();
    for r in 0..rows {
        let shift = if r % 2 == 1 { 0.5 * h0 } else { 0.0 };
        for c in 0..cols {
            let jitter = DVec2::new(rng.range(-JITTER, JITTER), rng.range(-JITTER, JITTER)) * h0;
            let p = origin + DVec2::new(c as f64 * h0 + shift, r as f64 * dy) + jitter;
            if outline.admits(region, p, LATTICE_MARGIN * h0) {
                out.push(p);
            }
        }
    }
    out
}

/// Run a relaxation method: initial points, then triangulate / move to `targets` / repeat,
/// as described in the [module documentation](self).
///
/// `method` names the method in errors. `targets` is called once per iteration with the
/// current mesh and the request's density; it returns one target per vertex (corners' are
/// ignored; boundary vertices' are projected onto their side) and the method's objective,
/// recorded in [`MeshResult::energy_history`] (NaN if the method has none).
///
/// ```
/// use cvtmesh::meshgen::relax::relax;
/// use cvtmesh::geometry::{DVec2, Density, Region};
/// use cvtmesh::{Mesh, MeshRequest};
///
/// // Laplacian smoothing: every vertex moves to the mean of its neighbours.
/// let laplace = |mesh: &Mesh, _: &Density| {
///     let mut sum = vec![(DVec2::ZERO, 0.0); mesh.points.len()];
///     for t in &mesh.triangles {
///         for k in 0..3 {
///             let (v, w) = (t[k] as usize, t[(k + 1) % 3] as usize);
///             sum[v].0 += mesh.points[w];
///             sum[v].1 += 1.0;
///             sum[w].0 += mesh.points[v];
///             sum[w].1 += 1.0;
///         }
///     }
///     let targets = sum.iter().map(|&(s, n)| s / n).collect();
///     (targets, f64::NAN)
/// };
/// let region = Region::builtin("square_hole")?;
/// let request = MeshRequest::points(150).max_iter(20);
/// let result = relax("laplace", &region, &request, &mut |_| {}, &laplace)?;
/// assert_eq!(result.mesh.num_vertices(), 150);
/// assert!(result.iterations <= 20);
/// cvtmesh::check_conforming(&result.mesh, &region)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn relax(
    method: &'static str,
    region: &Region,
    request: &MeshRequest,
    progress: &mut dyn FnMut(Progress),
    targets: &TargetFn,
) -> Result<MeshResult, MeshError> {
    mesh::refuse_embedded(region, method)?;
    let k = request.validate(region)?;
    let h = request.spacing(region);
    let fail = |e: MeshError, when: &str| match e {
        MeshError::Failed { message, .. } => MeshError::Failed {
            method: method.into(),
            message: format!("{when}: {message}"),
        },
        other => other,
    };
    let frame = Frame::new(region, h).map_err(|e| fail(e, "boundary"))?;
    let (mut state, h0) =
        initial_state(&frame, k, h, request.seed).map_err(|e| fail(e, "initial points"))?;
    let n_boundary = state.slots.iter().filter(|s| **s != Slot::Interior).count();
    let mut result = MeshResult {
        mesh: Mesh::default(),
        iterations: 0,
        converged: false,
        energy_history: Vec::new(),
        move_history: Vec::new(),
        notes: vec![format!(
            "initial points: lattice spacing {h0:.4e} (h = {h:.4e}), {n_boundary} on the boundary, {} inside",
            k - n_boundary
        )],
    };
    for it in 1..=request.max_iter {
        let mesh = tessellation::conforming_mesh(&state.points, &state.markers(&frame), region)
            .map_err(|e| fail(e, &format!("iteration {it}")))?;
        // Targets are indexed by vertex: a triangulation that dropped a point would misalign them.
        if mesh.num_vertices() != state.points.len() {
            return Err(MeshError::Failed {
                method: method.into(),
                message: format!(
                    "iteration {it}: {} of {} points could not be triangulated (coincident or outside the boundary chords)",
                    state.points.len() - mesh.num_vertices(),
                    state.points.len()
                ),
            });
        }
        let (goal, energy) = targets(&mesh, &request.density);
        let max_move = state.advance(&frame, &goal, h) / h;
        result.iterations = it;
        if energy.is_finite() {
            result.energy_history.push(energy);
        }
        result.move_history.push(max_move);
        progress(Progress {
            iteration: it,
            max_iter: request.max_iter,
            energy,
            max_move,
        });
        request.check_cancel(method, it)?;
        if max_move < request.tol {
            result.converged = true;
            break;
        }
        if request.out_of_time() {
            break;
        }
    }
    if !result.converged {
        let last = result.move_history.last().copied().unwrap_or(f64::NAN);
        result.notes.push(format!(
            "not converged: {} iterations, last max move {last:.3e}·h > tol {:.1e}",
            result.iterations, request.tol
        ));
    }
    result.mesh = tessellation::conforming_mesh(&state.points, &state.markers(&frame), region)
        .map_err(|e| fail(e, "final mesh"))?;
    // Too few points cannot follow a thin or strongly curved part of the boundary: say so
    // rather than hand back a mesh that leaves the region.
    mesh::check_conforming(&result.mesh, region).map_err(|cause| MeshError::NotConforming {
        method: method.into(),
        cause,
        hint: format!("K = {k} is too few points to follow the boundary; try a larger K"),
    })?;
    Ok(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(n: usize, radius: f64, turn: f64) -> Vec<DVec2> {
        (0..n)
            .map(|i| DVec2::from_angle(turn + i as f64 * std::f64::consts::TAU / n as f64) * radius)
            .collect()
    }

    #[test]
    fn a_rotation_of_the_whole_set_is_no_move_on_a_disc_but_is_on_a_square() {
        let (old, turned) = (ring(12, 0.5, 0.0), ring(12, 0.5, 1e-3));
        let circle = Region::builtin("circle").unwrap();
        // What is left is second order: the chord against the tangent, r θ² / 2.
        assert!(
            largest_move(&circle, &old, &turned) < 0.5 * 1e-6,
            "{}",
            largest_move(&circle, &old, &turned)
        );
        // The same rotation is a real move where the region is not symmetric about the centre.
        let square = Region::builtin("square_hole").unwrap();
        let moved = largest_move(&square, &old, &turned);
        assert!((moved - 0.5 * 1e-3).abs() < 1e-6, "{moved}");
        // A change of shape on top of the rotation is still seen on the disc.
        let mut shaped = turned.clone();
        shaped[3] += DVec2::new(2e-3, 0.0);
        let seen = largest_move(&circle, &old, &shaped);
        assert!(seen > 1.5e-3, "{seen}");
    }
}
