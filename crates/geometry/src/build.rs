//! Validation and assembly of a `Region` from loops of pieces.
use crate::crossings::candidate_pairs;
use crate::error::GeometryError;
use crate::index::Index;
use crate::numeric::segment_segment_distance;
use crate::piece::Piece;
use crate::predicates::{point_in_ring, ring_signed_area};
use crate::region::Region;
use crate::types::{Corner, Loop, LoopRole};
use glam::DVec2;
use std::sync::Arc;

/// Relative tolerance (× diameter) for closing loops and matching corners to junctions.
pub(crate) const SNAP: f64 = 1e-9;
/// Relative tolerance (× diameter) below which two non-adjacent boundary parts "touch".
const TOUCH: f64 = 1e-11;
/// Relative chord tolerance (× diameter) of the polygonization used for validation.
const CHECK_TOL: f64 = 1e-6;
/// The region's diameter must lie within [1 / `EXTENT_LIMIT`, `EXTENT_LIMIT`]: the methods
/// square lengths and take their fourth powers (cell moments, CVT energies, Hessians), and
/// inside this range a region scaled by a power of two gives the same mesh scaled, bit for
/// bit; far outside it they overflow, underflow or leave the Delaunay triangulation's
/// coordinate range.
pub const EXTENT_LIMIT: f64 = 1e14;
/// The region's bounding box may lie at most this many diameters from the origin: a
/// coordinate's last bit is its magnitude × 1.1e-16, 1.1e-8 of the region at this offset,
/// where Voronoi vertices and moments (differences of nearby coordinates) keep few of the
/// digits convergence is judged by. A unit square 10⁸ from the origin at 2·10⁴ vertices
/// takes ten times the evaluations it takes at the origin; at 10¹⁰ the default method's mesh
/// is a fan of slivers.
pub const OFFSET_LIMIT: f64 = 1e8;
/// Turning angle (degrees) above which [`Region::with_default_corners`] keeps a computed
/// corner: the boundary's direction changes by more than 30° there (an interior angle below
/// 150° or above 210°). A square's, a hexagon's and an octagon's vertices stay corners; the
/// small turns of a digitized curve do not. It is the feature angle of VTK's feature-edge
/// filter, and the paper's regions list their corners, so they are not affected. A turn within
/// 10⁻⁹ of the threshold counts as above it, so that rounding treats a regular polygon's
/// vertices alike: a dodecagon's 30° turns are all corners.
pub const DEFAULT_CORNER_ANGLE: f64 = 30.0;
/// Turning angle (radians) above which a junction is a corner when none are listed.
pub(crate) const CORNER_ANGLE: f64 = 1e-6;

fn role_name(r: LoopRole) -> &'static str {
    match r {
        LoopRole::Outer => "outer",
        LoopRole::Hole => "hole",
    }
}

impl Region {
    /// Build from loops of pieces. Validates (closed, no self-intersection, no loops crossing,
    /// roles that agree with nesting, finite numbers), normalises orientation, and takes
    /// `corners` as given (`None`: every junction whose turning angle exceeds 1e-6 rad).
    ///
    /// Details:
    /// - a region may have several disjoint parts, each an outer loop with its holes. Nesting
    ///   decides which is which, and the roles given must agree: a loop inside no other loop,
    ///   or inside a hole (an island), is outer; a loop whose innermost enclosing loop is outer
    ///   is a hole of it. Loops are renumbered part by part: each outer loop, in the order
    ///   given, followed by its holes in the order given (one outer loop becomes loop 0).
    ///   Messages number loops as given;
    /// - a gap of at most 1e-9·diameter between consecutive pieces is closed by moving the
    ///   end of the straight piece (line or chain) onto its neighbour; a larger gap is an error;
    /// - duplicate consecutive vertices (an edge of length ≤ 1e-9·diameter) are **rejected**,
    ///   not removed, with their position in the message;
    /// - crossings and touchings (closer than 1e-11·diameter) within a loop or between loops
    ///   are found on a polygonization with chord error 1e-6·diameter (chains exactly) and
    ///   reported with the crossing point; loops closer than that tolerance may go unnoticed;
    /// - a loop with the wrong orientation is reversed (pieces reversed and in reverse order,
    ///   so it keeps its start point);
    /// - each listed corner must lie within 1e-8·diameter of a junction of two pieces (or the
    ///   start of a single-piece loop); its position becomes that junction exactly.
    pub fn new(
        name: &str,
        loops: Vec<(LoopRole, Vec<Piece>)>,
        corners: Option<Vec<DVec2>>,
    ) -> Result<Region, GeometryError> {
        let loops = loops.into_iter().map(|(r, p)| (Some(r), p)).collect();
        new_region(name, loops, corners)
    }

    /// The same region with only the corners whose turning angle exceeds `degrees` (or lies
    /// within 10⁻⁹ of it: a regular polygon's turns all at once); pieces joined at the dropped
    /// corners merge into `Piece::Chain`s.
    ///
    /// The turning angle of a corner is the angle between the incoming and outgoing
    /// tangents (0° = straight on, 180° = turning back). Runs of pieces between kept corners
    /// (and junctions that never were corners, such as tangent line–arc joins) become one
    /// `Chain`: lines and chains contribute their points exactly; an arc in such a run is
    /// sampled with chord error 1e-7·diameter. A loop left with no corner at all becomes a
    /// single closed chain. The geometry is otherwise unchanged (no re-validation), `degrees`
    /// is recorded in `corner_threshold`, and a NaN threshold counts as 0.
    pub fn with_corner_angle(&self, degrees: f64) -> Region {
        let degrees = if degrees.is_nan() { 0.0 } else { degrees };
        // The turns of a regular polygon differ by rounding: one rule for all of them.
        let threshold = degrees.to_radians() * (1.0 - 1e-9);
        let arc_tol = 1e-7 * self.diameter();
        let mut lps = Vec::with_capacity(self.loops.len());
        let mut flags = Vec::with_capacity(self.loops.len());
        let mut markers = Vec::new();
        for lp in &self.loops {
            let n = lp.pieces.len();
            // keep[k]: the junction at the start of piece k stays a corner; cut[k]: pieces
            // are not merged across it.
            let keep: Vec<bool> = lp
                .pieces
                .iter()
                .map(|&p| {
                    self.corner_at_start[p].is_some_and(|c| {
                        let c = &self.corners[c];
                        turning_angle(&self.pieces[c.piece_in], &self.pieces[c.piece_out])
                            > threshold
                            || self.markers.get(c.piece_in) != self.markers.get(c.piece_out)
                            || self.is_marked_vertex(c.pos)
                            || self.is_line_vertex(c.pos)
                    })
                })
                .collect();
            let cut: Vec<bool> = (0..n)
                .map(|k| keep[k] || self.corner_at_start[lp.pieces[k]].is_none())
                .collect();
            let first = (0..n).find(|&k| cut[k]).unwrap_or(0);
            let (mut pieces, mut f) = (Vec::new(), Vec::new());
            let mut m: Vec<i64> = Vec::new();
            let mut k = 0;
            while k < n {
                // One run: from a cut up to (not including) the next cut.
                let start = (first + k) % n;
                let mut run = vec![start];
                k += 1;
                while k < n && !cut[(first + k) % n] {
                    run.push((first + k) % n);
                    k += 1;
                }
                f.push(keep[start]);
                // A run never crosses a change of marker (those junctions are kept).
                m.extend(self.markers.get(lp.pieces[start]));
                if run.len() == 1 {
                    pieces.push(self.pieces[lp.pieces[start]].clone());
                } else {
                    let mut pts: Vec<DVec2> = Vec::new();
                    for &r in &run {
                        let piece = &self.pieces[lp.pieces[r]];
                        let sample = match piece {
                            Piece::Line { a, b } => vec![*a, *b],
                            Piece::Chain(c) => c.clone(),
                            other => other.polygonize(arc_tol),
                        };
                        let skip = usize::from(!pts.is_empty());
                        pts.extend_from_slice(&sample[skip..]);
                    }
                    pieces.push(Piece::Chain(pts));
                }
            }
            lps.push((lp.role, pieces));
            flags.push(f);
            markers.extend(m);
        }
        let mut merged = assemble(self.name.clone(), lps, &flags, Some(degrees));
        merged.corners_computed = self.corners_computed;
        merged.markers = markers;
        merged.marker_names = self.marker_names.clone();
        merged.vertex_markers = self.vertex_markers.clone();
        merged.embedded = self.embedded.clone();
        merged.lines = self.lines.clone();
        merged.subdomains = self.subdomains.clone();
        merged.subdomain_names = self.subdomain_names.clone();
        merged.notes = self.notes.clone();
        merged.surface_group = self.surface_group.clone();
        merged
    }

    /// The same region with the default corners of a region whose corners were computed
    /// rather than listed ([`Region::corners_computed`]): only the junctions turning by more
    /// than [`DEFAULT_CORNER_ANGLE`] stay corners, so that a digitized outline is not cornered
    /// at every vertex a digitizer put down. A region with listed corners (every built-in
    /// region), or one a threshold was already applied to, comes back unchanged.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, LoopRole, Region, DEFAULT_CORNER_ANGLE};
    /// use std::f64::consts::TAU;
    /// // A square whose bottom side is digitized with 200 slightly wiggling points.
    /// let mut pts: Vec<DVec2> = (0..200)
    ///     .map(|i| DVec2::new(i as f64 / 200.0, 0.002 * (TAU * i as f64 / 20.0).sin()))
    ///     .collect();
    /// pts.extend([DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)]);
    /// let raw = Region::from_loops("square", vec![(LoopRole::Outer, pts)])?;
    /// assert!(raw.corners().len() > 150);
    /// let r = raw.with_default_corners();
    /// assert_eq!(r.corners().len(), 4);
    /// assert_eq!(r.corner_threshold(), Some(DEFAULT_CORNER_ANGLE));
    /// // Listed corners are kept: the lake has 101.
    /// assert_eq!(Region::builtin("lake")?.with_default_corners().corners().len(), 101);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn with_default_corners(&self) -> Region {
        if self.corners_computed && self.corner_threshold.is_none() {
            self.with_corner_angle(DEFAULT_CORNER_ANGLE)
        } else {
            self.clone()
        }
    }
}

/// Implements `Region::new` and the readers whose formats leave roles to nesting (`None`).
pub(crate) fn new_region(
    name: &str,
    loops: Vec<(Option<LoopRole>, Vec<Piece>)>,
    corners: Option<Vec<DVec2>>,
) -> Result<Region, GeometryError> {
    let err = |m: String| GeometryError::Invalid {
        region: name.to_string(),
        message: m,
    };
    if !loops.is_empty() && loops.iter().all(|l| l.0 == Some(LoopRole::Hole)) {
        return Err(err(
            "no outer loop (a region needs at least one loop with role 'outer')".into(),
        ));
    }
    // `label[i]` names loop i as the caller numbered it.
    let label: Vec<String> = loops
        .iter()
        .enumerate()
        .map(|(i, l)| match l.0 {
            Some(r) => format!("loop {i} ({})", role_name(r)),
            None => format!("loop {i}"),
        })
        .collect();
    let given: Vec<Option<LoopRole>> = loops.iter().map(|l| l.0).collect();
    let mut lps: Vec<Vec<Piece>> = loops.into_iter().map(|l| l.1).collect();
    if lps.is_empty() {
        return Err(err("no outer loop (no loops given)".into()));
    }

    // Numbers and per-piece parameters.
    for (l, pieces) in lps.iter().enumerate() {
        if pieces.is_empty() {
            return Err(err(format!("{} has no segments", label[l])));
        }
        for (k, p) in pieces.iter().enumerate() {
            p.check()
                .map_err(|m| err(format!("{}, piece {k}: {m}", label[l])))?;
        }
    }
    if let Some(c) = corners.iter().flatten().find(|c| !c.is_finite()) {
        return Err(err(format!("corner ({}, {}) is not finite", c.x, c.y)));
    }

    let (lo, hi) = bbox_of(lps.iter().flatten());
    let diam = (hi - lo).length();
    if !(diam > 0.0 && diam.is_finite()) {
        return Err(err("the boundary has zero or non-finite extent".into()));
    }
    if !(1.0 / EXTENT_LIMIT..=EXTENT_LIMIT).contains(&diam) {
        return Err(err(format!(
            "the region's diameter {diam:e} is outside [{:e}, {EXTENT_LIMIT:e}]: \
             scale its coordinates (a change of units) into that range",
            1.0 / EXTENT_LIMIT
        )));
    }
    let centre = 0.5 * (lo + hi);
    if centre.length() > OFFSET_LIMIT * diam {
        return Err(err(format!(
            "the region lies {:e} from the origin, {:e} times its diameter {diam:e} \
             (at most {OFFSET_LIMIT:e}): at that offset double precision keeps too few \
             digits of the region; translate its coordinates, e.g. subtract ({}, {})",
            centre.length(),
            centre.length() / diam,
            centre.x,
            centre.y
        )));
    }
    let snap = SNAP * diam;

    // Closed loops (snapping gaps below `snap`), no zero-length edges.
    for (l, pieces) in lps.iter_mut().enumerate() {
        close_loop(pieces, snap).map_err(|m| err(format!("{} {m}", label[l])))?;
        for p in pieces.iter() {
            let pts: &[DVec2] = match p {
                Piece::Line { a, b } => &[*a, *b],
                Piece::Chain(c) => c,
                _ => &[],
            };
            if let Some(w) = pts.windows(2).find(|w| w[0].distance(w[1]) <= snap) {
                return Err(err(format!(
                    "{} has duplicate consecutive vertices at ({}, {}) (a zero-length edge)",
                    label[l], w[1].x, w[1].y
                )));
            }
        }
    }

    // Simple, non-crossing loops (checked on a fine polygonization that keeps every chain point).
    let rings: Vec<Vec<DVec2>> = lps
        .iter()
        .map(|ps| ring_points(ps, CHECK_TOL * diam))
        .collect();
    for (l, r) in rings.iter().enumerate() {
        if r.len() < 3 {
            return Err(err(format!("{} encloses no area", label[l])));
        }
        let n = r.len();
        for k in 0..n {
            let (a, b, c) = (r[(k + n - 1) % n], r[k], r[(k + 1) % n]);
            let (u, v) = (b - a, c - b);
            if u.perp_dot(v).abs() <= 1e-12 * u.length() * v.length() && u.dot(v) < 0.0 {
                return Err(err(format!(
                    "{} folds back on itself at ({}, {}) (a zero-width spike)",
                    label[l], b.x, b.y
                )));
            }
        }
    }
    check_crossings(&rings, TOUCH * diam).map_err(|(a, b, x, crossing)| {
        let how = if crossing { "cross" } else { "touch" };
        if a == b {
            err(format!("{} {how}es itself at ({}, {})", label[a], x.x, x.y))
        } else {
            err(format!(
                "{} and {} {how} at ({}, {})",
                label[a], label[b], x.x, x.y
            ))
        }
    })?;

    // Orientation: outer CCW, holes CW (roles from nesting, checked against the given ones).
    let parent = nesting(&rings);
    let depth: Vec<usize> = (0..rings.len())
        .map(|l| std::iter::successors(parent[l], |&p| parent[p]).count())
        .collect();
    let role: Vec<LoopRole> = depth
        .iter()
        .map(|d| {
            if d % 2 == 0 {
                LoopRole::Outer
            } else {
                LoopRole::Hole
            }
        })
        .collect();
    for l in 0..rings.len() {
        let Some(want) = given[l] else { continue };
        if want == role[l] {
            continue;
        }
        let x = rings[l][0];
        return Err(err(match (want, parent[l]) {
            (LoopRole::Hole, None) => format!(
                "{} is not inside the outer loop (its point ({}, {}) is outside every loop)",
                label[l], x.x, x.y
            ),
            (LoopRole::Hole, Some(p)) => format!(
                "{} lies inside {} (holes must be disjoint; a loop inside a hole is an outer loop, an island)",
                label[l], label[p]
            ),
            (LoopRole::Outer, Some(p)) => format!(
                "{} lies inside {}, an outer loop, with no hole between them: a loop inside an outer loop is one of its holes",
                label[l], label[p]
            ),
            // A loop inside no other loop is outer, so this role always agrees.
            (LoopRole::Outer, None) => format!("{} has no consistent role", label[l]),
        }));
    }
    for (l, pieces) in lps.iter_mut().enumerate() {
        let a: f64 = pieces.iter().map(Piece::area_integral).sum();
        if a.is_nan() || a.abs() <= 1e-14 * diam * diam {
            return Err(err(format!("{} encloses no area", label[l])));
        }
        if (a > 0.0) != (role[l] == LoopRole::Outer) {
            pieces.reverse();
            for p in pieces.iter_mut() {
                *p = p.reversed();
            }
        }
    }

    // Loops part by part: each outer loop (in the order given) followed by its holes (in the
    // order given), so that a region of one part keeps its outer loop as loop 0.
    let mut order = Vec::with_capacity(lps.len());
    for o in (0..lps.len()).filter(|&l| role[l] == LoopRole::Outer) {
        order.push(o);
        order.extend((0..lps.len()).filter(|&h| role[h] == LoopRole::Hole && parent[h] == Some(o)));
    }
    let mut slots: Vec<Option<Vec<Piece>>> = lps.into_iter().map(Some).collect();
    let lps: Vec<(LoopRole, Vec<Piece>)> = order
        .iter()
        .map(|&l| (role[l], slots[l].take().unwrap_or_default()))
        .collect();

    // Corners: given positions matched to junctions, or every junction that turns.
    let computed = corners.is_none();
    let flags = match corners {
        None => lps
            .iter()
            .map(|(_, ps)| {
                (0..ps.len())
                    .map(|k| {
                        turning_angle(&ps[(k + ps.len() - 1) % ps.len()], &ps[k]) > CORNER_ANGLE
                    })
                    .collect()
            })
            .collect(),
        Some(list) => {
            let mut flags: Vec<Vec<bool>> =
                lps.iter().map(|(_, ps)| vec![false; ps.len()]).collect();
            // Junctions by exact position: a polygon file lists its vertices as corners, and
            // a search of every junction per corner is quadratic (30 s at 10⁵ vertices).
            let key = |p: DVec2| (p.x.to_bits(), p.y.to_bits());
            let mut at: std::collections::HashMap<(u64, u64), (usize, usize)> =
                std::collections::HashMap::new();
            for (l, (_, ps)) in lps.iter().enumerate() {
                for (k, p) in ps.iter().enumerate() {
                    at.entry(key(p.start())).or_insert((l, k));
                }
            }
            for c in list {
                let best = match at.get(&key(c)) {
                    Some(&(l, k)) => (0.0, l, k),
                    None => {
                        let mut best = (f64::INFINITY, 0, 0);
                        for (l, (_, ps)) in lps.iter().enumerate() {
                            for (k, p) in ps.iter().enumerate() {
                                let d = p.start().distance(c);
                                if d < best.0 {
                                    best = (d, l, k);
                                }
                            }
                        }
                        best
                    }
                };
                let (d, l, k) = best;
                if d > SNAP * 10.0 * diam {
                    let j = lps[l].1[k].start();
                    return Err(err(format!(
                        "corner ({}, {}) is not at a junction of two boundary pieces (nearest junction ({}, {}) is {d:e} away)",
                        c.x, c.y, j.x, j.y
                    )));
                }
                if flags[l][k] {
                    return Err(err(format!("corner ({}, {}) is listed twice", c.x, c.y)));
                }
                flags[l][k] = true;
            }
            flags
        }
    };
    let mut region = assemble(name.to_string(), lps, &flags, None);
    region.corners_computed = computed;
    Ok(region)
}

/// The innermost loop containing each loop (None: inside no other loop). The loops must be
/// simple and disjoint, so one point of a loop decides which loops contain it.
fn nesting(rings: &[Vec<DVec2>]) -> Vec<Option<usize>> {
    let boxes: Vec<(DVec2, DVec2)> = rings
        .iter()
        .map(|r| {
            r.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            )
        })
        .collect();
    let area: Vec<f64> = rings.iter().map(|r| ring_signed_area(r).abs()).collect();
    (0..rings.len())
        .map(|l| {
            let x = rings[l][0];
            // Of the loops that contain this one, the innermost is the smallest.
            (0..rings.len())
                .filter(|&o| {
                    o != l
                        && x.cmpge(boxes[o].0).all()
                        && x.cmple(boxes[o].1).all()
                        && point_in_ring(x, &rings[o])
                })
                .min_by(|&a, &b| area[a].total_cmp(&area[b]))
        })
        .collect()
}

/// Angle (radians, in [0, π]) between the end tangent of `a` and the start tangent of `b`.
pub(crate) fn turning_angle(a: &Piece, b: &Piece) -> f64 {
    let (t1, t2) = (a.end_tangents().1, b.end_tangents().0);
    t1.perp_dot(t2).atan2(t1.dot(t2)).abs()
}

fn bbox_of<'a>(pieces: impl Iterator<Item = &'a Piece>) -> (DVec2, DVec2) {
    pieces.map(Piece::bbox).fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), (l, h)| (lo.min(l), hi.max(h)),
    )
}

fn is_flexible(p: &Piece) -> bool {
    matches!(p, Piece::Line { .. } | Piece::Chain(_))
}

fn set_start(p: &mut Piece, x: DVec2) {
    match p {
        Piece::Line { a, .. } => *a = x,
        Piece::Chain(c) => c[0] = x,
        _ => {}
    }
}

fn set_end(p: &mut Piece, x: DVec2) {
    match p {
        Piece::Line { b, .. } => *b = x,
        Piece::Chain(c) => {
            if let Some(l) = c.last_mut() {
                *l = x;
            }
        }
        _ => {}
    }
}

/// Checks that each piece ends where the next starts (within `tol`) and snaps the ends of
/// straight pieces onto the exact ends of their neighbours.
fn close_loop(pieces: &mut [Piece], tol: f64) -> Result<(), String> {
    let n = pieces.len();
    if n > 1 {
        if let Some(k) = pieces.iter().position(Piece::is_closed) {
            return Err(format!("has a closed curve (piece {k}) together with other pieces; a circle or super-ellipse must be a loop on its own"));
        }
    }
    if n == 1 && matches!(pieces[0], Piece::Line { .. }) {
        return Err("is a single straight segment, which cannot close".into());
    }
    for i in 0..n {
        let j = (i + 1) % n;
        let (e, s) = (pieces[i].end(), pieces[j].start());
        let gap = e.distance(s);
        if gap > tol {
            return Err(if n == 1 {
                format!(
                    "is not closed: it starts at ({}, {}) but ends at ({}, {})",
                    s.x, s.y, e.x, e.y
                )
            } else {
                format!(
                    "is not closed: piece {i} ends at ({}, {}) but piece {j} starts at ({}, {}) (gap {gap:e})",
                    e.x, e.y, s.x, s.y
                )
            });
        }
        if gap > 0.0 {
            if is_flexible(&pieces[j]) {
                set_start(&mut pieces[j], e);
            } else if is_flexible(&pieces[i]) {
                set_end(&mut pieces[i], s);
            }
        }
    }
    Ok(())
}

/// Polygon of one loop: each piece polygonized to `tol` with its last point dropped; chains
/// keep all their points (no simplification), so the check sees the exact chain.
fn ring_points(pieces: &[Piece], tol: f64) -> Vec<DVec2> {
    let mut out = Vec::new();
    for p in pieces {
        let pts = match p {
            Piece::Chain(c) => c.clone(),
            _ => p.polygonize(tol),
        };
        out.extend_from_slice(&pts[..pts.len().saturating_sub(1)]);
    }
    out
}

/// Finds two non-adjacent edges of the rings closer than `touch`: (ring a, ring b, point,
/// whether they properly cross).
fn check_crossings(rings: &[Vec<DVec2>], touch: f64) -> Result<(), (usize, usize, DVec2, bool)> {
    let mut segs = Vec::new();
    let mut meta = Vec::new();
    for (l, r) in rings.iter().enumerate() {
        let n = r.len();
        for k in 0..n {
            segs.push((r[k], r[(k + 1) % n]));
            meta.push((l, k, n));
        }
    }
    // Report a proper crossing if there is one (a vertex exactly on the other loop looks
    // like a touch on one of its two edges), else the first touch.
    let mut found: Option<(usize, usize, DVec2, bool)> = None;
    candidate_pairs(&segs, touch, |i, j| {
        let ((li, ki, n), (lj, kj, _)) = (meta[i], meta[j]);
        if li == lj && (kj == ki + 1 || (ki == 0 && kj == n - 1)) {
            return true;
        }
        let (d, x) = segment_segment_distance(segs[i].0, segs[i].1, segs[j].0, segs[j].1);
        if d <= touch {
            let crossing =
                crate::numeric::segment_crossing(segs[i].0, segs[i].1, segs[j].0, segs[j].1)
                    .is_some();
            if crossing || found.is_none() {
                found = Some((li, lj, x, crossing));
            }
            return !crossing;
        }
        true
    });
    match found {
        Some(f) => Err(f),
        None => Ok(()),
    }
}

/// Builds the region's tables from validated, oriented loops (outer first) and per-junction
/// corner flags (`flags[l][k]`: the junction at the start of piece k of loop l is a corner).
pub(crate) fn assemble(
    name: String,
    lps: Vec<(LoopRole, Vec<Piece>)>,
    flags: &[Vec<bool>],
    corner_threshold: Option<f64>,
) -> Region {
    let mut pieces = Vec::new();
    let mut piece_loop = Vec::new();
    let mut piece_offset = Vec::new();
    let mut loops = Vec::new();
    let mut ids = Vec::new();
    for (l, (role, ps)) in lps.into_iter().enumerate() {
        let mut loop_ids = Vec::with_capacity(ps.len());
        let mut offsets = Vec::with_capacity(ps.len());
        let mut s = 0.0;
        for p in ps {
            let id = pieces.len();
            offsets.push(s);
            piece_offset.push(s);
            s += p.length();
            pieces.push(p);
            piece_loop.push(l);
            loop_ids.push(id);
        }
        ids.push(loop_ids.clone());
        loops.push(Loop {
            role,
            pieces: loop_ids,
            offsets,
            length: s,
        });
    }
    let mut corners = Vec::new();
    let mut corner_at_start = vec![None; pieces.len()];
    let mut corner_at_end = vec![None; pieces.len()];
    for (l, lp) in loops.iter().enumerate() {
        let n = lp.pieces.len();
        for (k, _) in flags[l].iter().enumerate().filter(|(_, f)| **f) {
            let (pin, pout) = (lp.pieces[(k + n - 1) % n], lp.pieces[k]);
            corner_at_start[pout] = Some(corners.len());
            corner_at_end[pin] = Some(corners.len());
            corners.push(Corner {
                pos: pieces[pout].start(),
                loop_index: l,
                piece_in: pin,
                piece_out: pout,
                loop_param: lp.offsets[k],
            });
        }
    }
    let area = pieces.iter().map(Piece::area_integral).sum();
    let bbox = bbox_of(pieces.iter());
    let index = Arc::new(Index::build(&pieces, &ids));
    Region {
        name,
        pieces,
        piece_loop,
        loops,
        corners,
        area,
        corner_threshold,
        corners_computed: false,
        bbox,
        index,
        corner_at_start,
        corner_at_end,
        piece_offset,
        markers: Vec::new(),
        marker_names: Default::default(),
        vertex_markers: Vec::new(),
        embedded: Vec::new(),
        lines: Vec::new(),
        subdomains: Vec::new(),
        subdomain_names: std::collections::BTreeMap::new(),
        inside_grid: Default::default(),
        notes: Vec::new(),
        surface_group: None,
    }
}
