//! Validation and assembly of a `Region` from loops of pieces.
use crate::crossings::candidate_pairs;
use crate::error::GeometryError;
use crate::index::Index;
use crate::numeric::segment_segment_distance;
use crate::piece::Piece;
use crate::predicates::point_in_ring;
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
/// Turning angle (radians) above which a junction is a corner when none are listed.
pub(crate) const CORNER_ANGLE: f64 = 1e-6;

fn role_name(r: LoopRole) -> &'static str {
    match r {
        LoopRole::Outer => "outer",
        LoopRole::Hole => "hole",
    }
}

impl Region {
    /// Build from loops of pieces (outer first). Validates (closed, no self-intersection, no
    /// loops crossing, holes inside the outer loop, finite numbers), normalises orientation,
    /// and takes `corners` as given (`None`: every junction whose turning angle exceeds 1e-6 rad).
    ///
    /// Details:
    /// - exactly one loop must be `Outer`; it becomes loop 0 even if it is not listed first
    ///   (the holes keep their relative order). Messages number loops as given;
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
        new_region(name, loops, corners)
    }

    /// The same region with only the corners whose turning angle exceeds `degrees`; pieces
    /// joined at the dropped corners merge into `Piece::Chain`s.
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
        let threshold = degrees.to_radians();
        let arc_tol = 1e-7 * self.diameter();
        let mut lps = Vec::with_capacity(self.loops.len());
        let mut flags = Vec::with_capacity(self.loops.len());
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
                    })
                })
                .collect();
            let cut: Vec<bool> = (0..n)
                .map(|k| keep[k] || self.corner_at_start[lp.pieces[k]].is_none())
                .collect();
            let first = (0..n).find(|&k| cut[k]).unwrap_or(0);
            let (mut pieces, mut f) = (Vec::new(), Vec::new());
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
        }
        assemble(self.name.clone(), lps, &flags, Some(degrees))
    }
}

/// Implements `Region::new`.
fn new_region(
    name: &str,
    loops: Vec<(LoopRole, Vec<Piece>)>,
    corners: Option<Vec<DVec2>>,
) -> Result<Region, GeometryError> {
    let err = |m: String| GeometryError::Invalid {
        region: name.to_string(),
        message: m,
    };

    // Exactly one outer loop; it goes first. `label[i]` names loop i as the caller numbered it.
    let outers: Vec<usize> = loops
        .iter()
        .enumerate()
        .filter(|(_, l)| l.0 == LoopRole::Outer)
        .map(|(i, _)| i)
        .collect();
    match outers.len() {
        0 => return Err(err("no outer loop (a region needs exactly one loop with role 'outer')".into())),
        1 => {}
        k => return Err(err(format!("{k} outer loops (loops {outers:?}); a region has exactly one, the others must be holes"))),
    }
    let mut order: Vec<usize> = outers.clone();
    order.extend((0..loops.len()).filter(|i| *i != outers[0]));
    let mut slots: Vec<Option<(LoopRole, Vec<Piece>)>> = loops.into_iter().map(Some).collect();
    let mut lps: Vec<(LoopRole, Vec<Piece>)> = Vec::with_capacity(order.len());
    let mut label: Vec<String> = Vec::with_capacity(order.len());
    for &i in &order {
        if let Some(l) = slots[i].take() {
            label.push(format!("loop {i} ({})", role_name(l.0)));
            lps.push(l);
        }
    }

    // Numbers and per-piece parameters.
    for (l, (_, pieces)) in lps.iter().enumerate() {
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

    let (lo, hi) = bbox_of(lps.iter().flat_map(|l| &l.1));
    let diam = (hi - lo).length();
    if !(diam > 0.0 && diam.is_finite()) {
        return Err(err("the boundary has zero or non-finite extent".into()));
    }
    let snap = SNAP * diam;

    // Closed loops (snapping gaps below `snap`), no zero-length edges.
    for (l, (_, pieces)) in lps.iter_mut().enumerate() {
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
        .map(|(_, ps)| ring_points(ps, CHECK_TOL * diam))
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

    // Orientation: outer CCW, holes CW.
    for (l, (role, pieces)) in lps.iter_mut().enumerate() {
        let a: f64 = pieces.iter().map(Piece::area_integral).sum();
        if a.is_nan() || a.abs() <= 1e-14 * diam * diam {
            return Err(err(format!("{} encloses no area", label[l])));
        }
        if (a > 0.0) != (*role == LoopRole::Outer) {
            pieces.reverse();
            for p in pieces.iter_mut() {
                *p = p.reversed();
            }
        }
    }

    // Holes inside the outer loop and outside each other.
    for h in 1..rings.len() {
        let x = rings[h][0];
        if !point_in_ring(x, &rings[0]) {
            return Err(err(format!(
                "{} is not inside the outer loop (its point ({}, {}) is outside)",
                label[h], x.x, x.y
            )));
        }
        for g in 1..rings.len() {
            if g != h && point_in_ring(x, &rings[g]) {
                return Err(err(format!(
                    "{} lies inside {} (holes must be disjoint)",
                    label[h], label[g]
                )));
            }
        }
    }

    // Corners: given positions matched to junctions, or every junction that turns.
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
            for c in list {
                let mut best = (f64::INFINITY, 0, 0);
                for (l, (_, ps)) in lps.iter().enumerate() {
                    for (k, p) in ps.iter().enumerate() {
                        let d = p.start().distance(c);
                        if d < best.0 {
                            best = (d, l, k);
                        }
                    }
                }
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
    Ok(assemble(name.to_string(), lps, &flags, None))
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
        bbox,
        index,
        corner_at_start,
        corner_at_end,
        piece_offset,
    }
}
