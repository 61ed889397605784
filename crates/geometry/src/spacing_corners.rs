//! Corners a mesh of a given spacing needs beyond the region's own: where a polyline piece
//! bends, or faces another part of the boundary across a gap, within about one spacing.
//!
//! A digitized outline thinned to its real corners ([`Region::with_default_corners`]) is
//! smooth at the scale of its vertices but not at the scale of a coarse mesh:
//! - **bends**: an airfoil's nose or a coastline's headland is skipped by a chord one spacing
//!   long. A corner at the bend puts a vertex on it;
//! - **gaps**: across a hole or an inlet thinner than the spacing (an airfoil's trailing
//!   half), the Voronoi cells of boundary vertices on one side reach over to the other, and the
//!   vertices of one side drift off it. Corners one spacing apart along such a stretch hold
//!   its vertices in place, as Triangle and Gmsh hold every boundary vertex.
//!
//! Only polyline pieces (chains and lines) get corners: arcs and closed curves are followed
//! by construction.
use crate::build::assemble;
use crate::piece::Piece;
use crate::region::Region;
use crate::types::{LoopRole, PieceId};
use glam::DVec2;

/// Lengths, in local spacings, of the chords of the stretches of boundary examined (a stretch
/// ends where it is this far from its start): boundary vertices settle about 1.04 spacings
/// apart, and an edge spans 0.75 to 1.3 of them.
pub const CHORDS: [f64; 4] = [0.75, 1.0, 1.25, 1.5];

/// Largest distance between a stretch of boundary and its chord, as a share of the chord,
/// that is followed without a corner. A conforming mesh's boundary edge may stray 0.13 of
/// its length from the boundary (the sagitta of a curved piece). Across a stretch centred on
/// a turn of θ between straight sides the chord strays tan(θ/2)/2 of its length, whatever
/// the stretch's length: 0.12 is a turn of 27°, so a single vertex turning by the default
/// corner angle (30°) is a bend at every spacing, and one turning by 15° never is.
pub const BEND_TOLERANCE: f64 = 0.12;

/// A boundary point faces a gap when the region comes back within this many local spacings
/// along its outward normal.
pub const GAP_SPACINGS: f64 = 1.5;

/// Longest stretch examined, in longest chords of arc length.
const MAX_ARC: f64 = 4.0;

/// Stretches per shortest chord: they start every 1/8 of it along a piece.
const WINDOW_STEPS: f64 = 8.0;

/// Rounds of adding corners: each round splits the pieces at the worst bends, and the next
/// looks again at the shorter pieces.
const MAX_ROUNDS: usize = 64;

/// Points per local spacing at which a line is tested for a gap.
const GAP_SAMPLES: f64 = 4.0;

/// Most points at which one line is tested for a gap (and so most corners added on it).
const MAX_LINE_SAMPLES: f64 = 100_000.0;

/// Distances, as shares of the gap, tested along the outward normal.
const GAP_PROBES: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

/// A region with the corners a spacing needs ([`Region::with_spacing_corners`]), and the maps
/// from its pieces and corners back to the region it came from.
#[derive(Clone, Debug)]
pub struct SpacingCorners {
    /// The region with the added corners; the same geometry, loops and loop starts.
    pub region: Region,
    /// The original piece each piece of `region` is part of.
    pub pieces: Vec<PieceId>,
    /// The original corner each corner of `region` is, or `None` for an added one.
    pub corners: Vec<Option<usize>>,
    /// Corners added at bends.
    pub bends: usize,
    /// Corners added along gaps.
    pub gaps: usize,
}

impl SpacingCorners {
    /// Corners added, at bends and along gaps.
    pub fn added(&self) -> usize {
        self.bends + self.gaps
    }
}

impl Region {
    /// The region with the corners a mesh of local spacing `spacing(x)` needs to follow its
    /// polyline pieces (chains and lines):
    /// - along a stretch whose outward normal meets the region again within
    ///   [`GAP_SPACINGS`] spacings (a thin hole or inlet), corners about one spacing apart;
    /// - where a stretch of a chain whose chord is 0.75 to 1.5 spacings long ([`CHORDS`])
    ///   strays from it by more than [`BEND_TOLERANCE`] of the chord's length, a corner at the
    ///   vertex farthest from the chord, until no such stretch is left between corners.
    ///
    /// Corners on chains are chain vertices; a line is split at new points on it. Arcs and
    /// closed curves are left as they are. The geometry, the loops and where each loop
    /// starts are unchanged, so arc-length positions along a loop mean the same in both
    /// regions. The work per round is linear in the number of chain vertices (stretches
    /// start every 1/8 of the shortest chord), with at most 64 rounds, plus four point-in-region tests per
    /// vertex for the gaps.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, LoopRole, Region};
    /// use std::f64::consts::PI;
    /// // A square with a round bump of radius 0.05 on its top side, finely digitized: no
    /// // vertex of the bump turns by more than the default corner angle.
    /// let mut pts = vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0)];
    /// pts.extend((0..=40).map(|i| {
    ///     let t = PI * i as f64 / 40.0;
    ///     DVec2::new(0.5 + 0.05 * t.cos(), 1.0 + 0.05 * t.sin())
    /// }));
    /// pts.insert(3, DVec2::new(0.6, 1.0));
    /// pts.push(DVec2::new(0.4, 1.0));
    /// pts.push(DVec2::new(0.0, 1.0));
    /// let region = Region::from_loops("bump", vec![(LoopRole::Outer, pts)])?.with_default_corners();
    /// // The square's four, and the bump's foot on either side.
    /// assert_eq!(region.corners().len(), 6);
    /// // At spacing 0.02 the bump is followed as it is; at 0.2 a chord would cut it off.
    /// assert_eq!(region.with_spacing_corners(&|_| 0.02).added(), 0);
    /// let fitted = region.with_spacing_corners(&|_| 0.2);
    /// assert!(fitted.bends >= 1);
    /// assert!(fitted.region.corners().iter().any(|c| c.pos.y > 1.04));
    /// assert_eq!(fitted.region.area(), region.area());
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn with_spacing_corners(&self, spacing: &dyn Fn(DVec2) -> f64) -> SpacingCorners {
        let mut lps: Vec<(LoopRole, Vec<Piece>)> = Vec::with_capacity(self.loops.len());
        let mut flags = Vec::with_capacity(self.loops.len());
        let mut origin_piece = Vec::with_capacity(self.pieces.len());
        let mut origin_corner = Vec::new();
        let (mut bends_added, mut gaps_added) = (0, 0);
        for lp in &self.loops {
            let (mut pieces, mut f) = (Vec::new(), Vec::new());
            for &p in &lp.pieces {
                let corner = self.corner_at_start[p];
                // The piece as a polyline, and the vertices that become corners.
                let (pts, cuts) = match &self.pieces[p] {
                    Piece::Chain(pts) => {
                        let gaps = gap_cuts(self, pts, spacing);
                        // A whole loop from its only corner back to it: the corner is a cut.
                        let mut seed = gaps.clone();
                        if corner.is_some() && pts.first() == pts.last() {
                            seed.insert(0, 0);
                        }
                        let cuts = bends(pts, &seed, spacing);
                        gaps_added += gaps.len();
                        bends_added += cuts.len() - seed.len();
                        (pts.clone(), cuts)
                    }
                    &Piece::Line { a, b } => {
                        let pts = line_gap_points(self, a, b, spacing);
                        gaps_added += pts.len() - 2;
                        let cuts = (1..pts.len() - 1).collect();
                        (pts, cuts)
                    }
                    _ => (Vec::new(), Vec::new()),
                };
                if cuts.is_empty() {
                    pieces.push(self.pieces[p].clone());
                    f.push(corner.is_some());
                    origin_piece.push(p);
                    if corner.is_some() {
                        origin_corner.push(corner);
                    }
                    continue;
                }
                // A cut at 0 (a closed chain's start) makes the loop's start a corner.
                let start_cut = cuts.first() == Some(&0);
                let mut bounds = vec![0];
                bounds.extend(cuts.iter().filter(|&&c| c != 0));
                bounds.push(pts.len() - 1);
                for (k, w) in bounds.windows(2).enumerate() {
                    let sub = &pts[w[0]..=w[1]];
                    pieces.push(if sub.len() == 2 {
                        Piece::Line {
                            a: sub[0],
                            b: sub[1],
                        }
                    } else {
                        Piece::Chain(sub.to_vec())
                    });
                    let is_corner = k > 0 || corner.is_some() || start_cut;
                    f.push(is_corner);
                    origin_piece.push(p);
                    if is_corner {
                        origin_corner.push(if k == 0 { corner } else { None });
                    }
                }
            }
            lps.push((lp.role, pieces));
            flags.push(f);
        }
        if bends_added + gaps_added == 0 {
            return SpacingCorners {
                region: self.clone(),
                pieces: (0..self.pieces.len()).collect(),
                corners: (0..self.corners.len()).map(Some).collect(),
                bends: 0,
                gaps: 0,
            };
        }
        let mut region = assemble(self.name.clone(), lps, &flags, self.corner_threshold);
        region.corners_computed = self.corners_computed;
        region.embedded = self.embedded.clone();
        region.lines = self.lines.clone();
        region.notes = self.notes.clone();
        region.surface_group = self.surface_group.clone();
        SpacingCorners {
            region,
            pieces: origin_piece,
            corners: origin_corner,
            bends: bends_added,
            gaps: gaps_added,
        }
    }
}

/// True where the region comes back within [`GAP_SPACINGS`] local spacings of boundary point
/// `x` along its outward normal `normal` (unit).
fn faces_gap(region: &Region, x: DVec2, normal: DVec2, spacing: f64) -> bool {
    let gap = GAP_SPACINGS * spacing;
    gap.is_finite()
        && gap > 0.0
        && GAP_PROBES
            .iter()
            .any(|&t| region.contains(x + normal * (t * gap)))
}

/// Corners about one local spacing apart along the stretches of the chain `pts` that face a
/// gap: vertex indices strictly between its ends, increasing.
fn gap_cuts(region: &Region, pts: &[DVec2], spacing: &dyn Fn(DVec2) -> f64) -> Vec<usize> {
    let n = pts.len();
    if n < 3 {
        return Vec::new();
    }
    // The interior lies left of every loop, so the outward normal is the direction turned
    // clockwise.
    let facing: Vec<bool> = (0..n)
        .map(|i| {
            let d = (pts[(i + 1).min(n - 1)] - pts[i.saturating_sub(1)]).normalize_or_zero();
            d != DVec2::ZERO && faces_gap(region, pts[i], DVec2::new(d.y, -d.x), spacing(pts[i]))
        })
        .collect();
    let mut arc = vec![0.0; n];
    for i in 1..n {
        arc[i] = arc[i - 1] + pts[i - 1].distance(pts[i]);
    }
    let mut cuts = Vec::new();
    let mut i = 0;
    while i < n {
        if !facing[i] {
            i += 1;
            continue;
        }
        let start = i;
        while i + 1 < n && facing[i + 1] {
            i += 1;
        }
        // One run [start, i]: corners at its middle points one spacing apart, each at the
        // nearest vertex, none at the chain's ends.
        let (s0, s1) = (arc[start], arc[i]);
        let h = spacing(pts[(start + i) / 2]);
        // No more corners than the run has vertices (a spacing far below the vertex spacing).
        let count = ((s1 - s0) / h).round().clamp(1.0, (i - start + 1) as f64) as usize;
        let mut v = start;
        for k in 0..count {
            let target = s0 + (s1 - s0) * (k as f64 + 0.5) / count as f64;
            while v + 1 < n && arc[v + 1] <= target {
                v += 1;
            }
            let near = if v + 1 < n && arc[v + 1] - target < target - arc[v] {
                v + 1
            } else {
                v
            };
            if near > 0 && near < n - 1 && cuts.last() != Some(&near) {
                cuts.push(near);
            }
        }
        i += 1;
    }
    cuts
}

/// The line from `a` to `b` with points added about one local spacing apart where it faces a
/// gap: `[a, …, b]`.
fn line_gap_points(
    region: &Region,
    a: DVec2,
    b: DVec2,
    spacing: &dyn Fn(DVec2) -> f64,
) -> Vec<DVec2> {
    let len = a.distance(b);
    let h = spacing(a.lerp(b, 0.5));
    if !(len > 0.0 && h.is_finite() && h > 0.0) || len < h {
        return vec![a, b];
    }
    let d = (b - a) / len;
    let normal = DVec2::new(d.y, -d.x);
    let samples = ((len / h) * GAP_SAMPLES).ceil().min(MAX_LINE_SAMPLES) as usize;
    let facing: Vec<bool> = (0..=samples)
        .map(|k| {
            let x = a.lerp(b, k as f64 / samples as f64);
            faces_gap(region, x, normal, spacing(x))
        })
        .collect();
    let mut out = vec![a];
    let mut i = 0;
    while i <= samples {
        if !facing[i] {
            i += 1;
            continue;
        }
        let start = i;
        while i < samples && facing[i + 1] {
            i += 1;
        }
        let (t0, t1) = (start as f64 / samples as f64, i as f64 / samples as f64);
        let count = ((t1 - t0) * len / h)
            .round()
            .clamp(1.0, (i - start + 1) as f64) as usize;
        for k in 0..count {
            let t = t0 + (t1 - t0) * (k as f64 + 0.5) / count as f64;
            // Not within half a spacing of either end (a corner or junction is there).
            if t * len > 0.5 * h && (1.0 - t) * len > 0.5 * h {
                out.push(a.lerp(b, t));
            }
        }
        i += 1;
    }
    out.push(b);
    out
}

/// Indices of the vertices of the chain `pts` that become corners at local spacing `spacing`
/// (increasing): `seed` (increasing; strictly between the ends, or 0 for a closed chain's
/// corner) and the bends. An open chain
/// runs from corner to corner and its ends are not returned; a closed chain (first point =
/// last, a whole loop without corners) is examined around its start too, and its start, 0,
/// may be returned.
fn bends(pts: &[DVec2], seed: &[usize], spacing: &dyn Fn(DVec2) -> f64) -> Vec<usize> {
    let n = pts.len();
    if n < 3 {
        return seed.to_vec();
    }
    let closed = n > 3 && pts[0] == pts[n - 1];
    // Distinct vertices; in a closed chain, vertex n − 1 is vertex 0.
    let m = if closed { n - 1 } else { n };
    let mut arc = Vec::with_capacity(n);
    let mut s = 0.0;
    arc.push(0.0);
    for w in pts.windows(2) {
        s += w[0].distance(w[1]);
        arc.push(s);
    }
    let length = s;
    let mut is_cut = vec![false; m];
    for &c in seed {
        is_cut[c % m] = true;
    }
    if !closed {
        is_cut[0] = true;
        is_cut[m - 1] = true;
    }
    // Cuts taken in the last round: only the runs they end are examined again; the others
    // keep their scores (a candidate held back by a corner nearby stays a candidate).
    let mut fresh = vec![true; m];
    // The worst stretch's score and farthest vertex, per vertex.
    let mut score = vec![0.0f64; m];
    for _ in 0..MAX_ROUNDS {
        // Runs between cuts, as ranges of vertex numbers taken modulo m: a closed chain
        // without cuts is examined twice, from its start and from halfway, so that no stretch
        // is missed for crossing a run's end.
        let cuts: Vec<usize> = (0..m).filter(|&i| is_cut[i]).collect();
        let runs: Vec<(usize, usize)> = if cuts.is_empty() {
            vec![(0, m), (m / 2, m / 2 + m)]
        } else if closed {
            (0..cuts.len())
                .map(|k| (cuts[k], cuts.get(k + 1).copied().unwrap_or(cuts[0] + m)))
                .collect()
        } else {
            cuts.windows(2).map(|w| (w[0], w[1])).collect()
        };
        let runs: Vec<(usize, usize)> = runs
            .into_iter()
            .filter(|&(a, b)| cuts.is_empty() || fresh[a % m] || fresh[b % m])
            .collect();
        for &(a, b) in &runs {
            for i in a..=b {
                score[i % m] = 0.0;
            }
        }
        for (a, b) in runs {
            let index: Vec<usize> = (a..=b).map(|i| i % m).collect();
            let run: Vec<DVec2> = index.iter().map(|&i| pts[i]).collect();
            let mut run_arc = Vec::with_capacity(run.len());
            let mut s = 0.0;
            run_arc.push(0.0);
            for w in run.windows(2) {
                s += w[0].distance(w[1]);
                run_arc.push(s);
            }
            let mut run_score = vec![0.0f64; run.len()];
            worst_in_run(&run, &run_arc, 0, run.len() - 1, spacing, &mut run_score);
            for (&i, &r) in index.iter().zip(&run_score) {
                score[i] = score[i].max(r);
            }
        }
        let mut candidates: Vec<usize> = (0..m)
            .filter(|&i| score[i] > BEND_TOLERANCE && !is_cut[i])
            .collect();
        if candidates.is_empty() {
            break;
        }
        candidates.sort_by(|&a, &b| score[b].total_cmp(&score[a]).then(a.cmp(&b)));
        // One corner per bend and round: a candidate within a quarter of the longest chord of
        // a corner taken this round waits for the next round, which sees the split pieces.
        let along = |a: usize, b: usize| {
            let d = (arc[a] - arc[b]).abs();
            if closed {
                d.min(length - d)
            } else {
                d
            }
        };
        let mut taken: Vec<usize> = Vec::new();
        for i in candidates {
            let near = 0.25 * CHORDS[CHORDS.len() - 1] * spacing(pts[i]);
            if taken.iter().all(|&t| along(t, i) > near) {
                taken.push(i);
            }
        }
        fresh.fill(false);
        for i in taken {
            is_cut[i] = true;
            fresh[i] = true;
        }
    }
    if !closed {
        is_cut[0] = false;
        is_cut[m - 1] = false;
    }
    (0..m).filter(|&i| is_cut[i]).collect()
}

/// For the stretches of the run of `pts` from vertex `a` to vertex `b`, raise `score` at each
/// stretch's vertex farthest from its chord to that distance over the chord's length. The
/// stretches start every 1/8 of the shortest chord along the run and end where they are
/// [`CHORDS`] × the local spacing from their start, as the crow flies (a rough boundary is
/// longer than its chords) and along the boundary (a hairpin is shorter), within [`MAX_ARC`]
/// longest chords of arc and the run; a stretch shorter than the shortest chord both ways is
/// not examined unless it is the whole run.
fn worst_in_run(
    pts: &[DVec2],
    arc: &[f64],
    a: usize,
    b: usize,
    spacing: &dyn Fn(DVec2) -> f64,
    score: &mut [f64],
) {
    if b < a + 2 {
        return;
    }
    let (s0, s1) = (arc[a], arc[b]);
    // The point at arc length s, searching forward from vertex `from`, and the index of the
    // last vertex at or before s.
    let at = |s: f64, from: usize| -> (DVec2, usize) {
        let mut i = from;
        while i + 1 < b && arc[i + 1] <= s {
            i += 1;
        }
        let len = arc[i + 1] - arc[i];
        let t = if len > 0.0 {
            ((s - arc[i]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (pts[i].lerp(pts[i + 1], t), i)
    };
    let (shortest, longest) = (CHORDS[0], CHORDS[CHORDS.len() - 1]);
    let mut start = s0;
    let mut i0 = a;
    while start < s1 {
        let (p, i) = at(start, i0);
        i0 = i;
        let h = spacing(p);
        if !(h.is_finite() && h > 0.0) {
            return;
        }
        let limit = (start + MAX_ARC * longest * h).min(s1);
        // Ends of the stretches, in arc length: where the distance from p first reaches each
        // chord, else the limit.
        let mut ends = [limit; CHORDS.len()];
        let mut next = 0;
        let mut k = i + 1;
        while next < CHORDS.len() && k <= b && arc[k] < limit {
            while next < CHORDS.len() && pts[k].distance(p) >= CHORDS[next] * h {
                let reach = CHORDS[next] * h;
                // On the segment from k − 1 to k: bisect for the distance `reach`.
                let (mut lo, mut hi) = (0.0, 1.0);
                for _ in 0..30 {
                    let mid = 0.5 * (lo + hi);
                    if pts[k - 1].lerp(pts[k], mid).distance(p) >= reach {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                ends[next] = (arc[k - 1] + hi * (arc[k] - arc[k - 1])).max(start);
                next += 1;
            }
            k += 1;
        }
        // And where the arc length reaches each chord: around a hairpin (an airfoil's nose)
        // boundary vertices one spacing apart along the boundary are close as the crow flies.
        let arc_ends = CHORDS.map(|c| (start + c * h).min(s1));
        for &end in ends.iter().chain(&arc_ends) {
            let (q, j) = at(end, i0);
            let chord = q - p;
            let len = chord.length();
            // A run shorter than that is one edge: examined whole.
            let whole = start <= s0 && end >= s1;
            if len.max(end - start) < shortest * h && !whole {
                continue;
            }
            let mut worst = (0.0, usize::MAX);
            for (k, &v) in pts.iter().enumerate().take(j + 1).skip(i + 1) {
                if arc[k] <= start || arc[k] >= end || k == a || k == b {
                    continue;
                }
                let d = if len > 0.0 {
                    chord.perp_dot(v - p).abs() / len
                } else {
                    v.distance(p)
                };
                if d > worst.0 {
                    worst = (d, k);
                }
            }
            if worst.1 != usize::MAX {
                let ratio = if len > 0.0 {
                    worst.0 / len
                } else {
                    f64::INFINITY
                };
                score[worst.1] = score[worst.1].max(ratio);
            }
        }
        start += shortest * h / WINDOW_STEPS;
        // Where the spacing is far below the vertex spacing, stretches that hold no vertex are
        // skipped: the next one examined reaches the next vertex.
        let mut next_vertex = i0;
        while next_vertex < b && arc[next_vertex] <= start {
            next_vertex += 1;
        }
        start = start.max(arc[next_vertex] - MAX_ARC * longest * h);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::LoopRole;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    /// A chain along the x axis with a turn of `deg` degrees at x = 1, sides 1 long, sampled
    /// every 0.01.
    fn turn(deg: f64) -> Vec<DVec2> {
        let dir = DVec2::from_angle(deg.to_radians());
        let mut pts: Vec<DVec2> = (0..=100).map(|i| v(i as f64 * 0.01, 0.0)).collect();
        pts.extend((1..=100).map(|i| v(1.0, 0.0) + dir * (i as f64 * 0.01)));
        pts
    }

    #[test]
    fn a_turn_becomes_a_corner_above_the_tolerance_only() {
        // Across a window centred on a turn of θ the chord strays tan(θ/2)/2 of its length.
        assert_eq!(bends(&turn(15.0), &[], &|_| 0.2), Vec::<usize>::new());
        assert_eq!(bends(&turn(30.0), &[], &|_| 0.2), vec![100]);
        // A turn is scale-free: the same at a spacing far below the samples' and far above.
        assert_eq!(bends(&turn(30.0), &[], &|_| 0.001), vec![100]);
        assert!(bends(&turn(15.0), &[], &|_| 0.001).is_empty());
        assert_eq!(bends(&turn(30.0), &[], &|_| 1.0), vec![100]);
    }

    #[test]
    fn straight_and_gently_curved_chains_have_no_bends() {
        let line: Vec<DVec2> = (0..=50).map(|i| v(i as f64, 2.0 * i as f64)).collect();
        assert!(bends(&line, &[], &|_| 3.0).is_empty());
        // An arc of radius 10 at spacing 1: its chords stray 1/80 of their length.
        let arc: Vec<DVec2> = (0..=200)
            .map(|i| 10.0 * DVec2::from_angle(i as f64 * 0.01))
            .collect();
        assert!(bends(&arc, &[], &|_| 1.0).is_empty());
    }

    #[test]
    fn a_tight_curve_gets_corners_until_every_chord_follows_it() {
        // A half circle of radius 0.1 at spacing 1: corners until each stretch between them
        // is an arc of less than about 45°.
        let pts: Vec<DVec2> = (0..=180)
            .map(|i| 0.1 * DVec2::from_angle(i as f64 * std::f64::consts::PI / 180.0))
            .collect();
        let cuts = bends(&pts, &[], &|_| 1.0);
        assert!((3..=8).contains(&cuts.len()), "{cuts:?}");
        let mut ends = vec![0];
        ends.extend(&cuts);
        ends.push(180);
        for w in ends.windows(2) {
            assert!(w[1] - w[0] <= 50, "{ends:?}");
        }
    }

    #[test]
    fn a_closed_chain_is_examined_across_its_start() {
        // A 24-gon of radius 0.2 (turns of 15°) closed at (0.2, 0): at spacing 0.2 a chord
        // strays more than the tolerance wherever it is, the start included.
        let mut pts: Vec<DVec2> = (0..24)
            .map(|i| 0.2 * DVec2::from_angle(std::f64::consts::TAU * i as f64 / 24.0))
            .collect();
        pts.push(pts[0]);
        let cuts = bends(&pts, &[], &|_| 0.2);
        assert!(cuts.len() >= 6, "{cuts:?}");
        // No stretch of more than 60° (4 sides) between corners, across the start too.
        let mut gaps: Vec<usize> = cuts.windows(2).map(|w| w[1] - w[0]).collect();
        gaps.push(cuts[0] + 24 - cuts[cuts.len() - 1]);
        assert!(gaps.iter().all(|&g| g <= 4), "{cuts:?}");
        // As a hole in a square, meshed at that spacing: its start is a corner of its own.
        let square = [v(-1.0, -1.0), v(1.0, -1.0), v(1.0, 1.0), v(-1.0, 1.0)];
        let hole: Vec<DVec2> = pts[..24].to_vec();
        let region = Region::from_loops(
            "ring",
            vec![(LoopRole::Outer, square.to_vec()), (LoopRole::Hole, hole)],
        )
        .unwrap()
        .with_default_corners();
        assert_eq!(region.corners().len(), 4);
        let fitted = region.with_spacing_corners(&|_| 0.2);
        assert_eq!(fitted.region.corners().len(), 4 + fitted.bends);
        assert!((fitted.region.area() - region.area()).abs() < 1e-12);
        assert!((fitted.region.loops()[1].length - region.loops()[1].length).abs() < 1e-12);
    }

    #[test]
    fn bent_region_keeps_geometry_and_maps_back() {
        // The bump of the doc example, on a square with a hole, so that loop 1 is untouched.
        let mut pts = vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.6, 1.0)];
        pts.extend((0..=40).map(|i| {
            let t = std::f64::consts::PI * i as f64 / 40.0;
            v(0.5 + 0.05 * t.cos(), 1.0 + 0.05 * t.sin())
        }));
        pts.extend([v(0.4, 1.0), v(0.0, 1.0)]);
        let hole = vec![v(0.4, 0.4), v(0.4, 0.6), v(0.6, 0.6), v(0.6, 0.4)];
        let region =
            Region::from_loops("bump", vec![(LoopRole::Outer, pts), (LoopRole::Hole, hole)])
                .unwrap()
                .with_default_corners();
        let bent = region.with_spacing_corners(&|_| 0.2);
        let r = &bent.region;
        assert!(bent.bends > 0);
        assert_eq!(r.corners().len(), region.corners().len() + bent.added());
        assert_eq!(r.area(), region.area());
        assert_eq!(r.loops().len(), 2);
        for (l, lp) in r.loops().iter().enumerate() {
            assert!((lp.length - region.loops()[l].length).abs() < 1e-12);
            assert_eq!(
                r.pieces()[lp.pieces[0]].start(),
                region.pieces()[region.loops()[l].pieces[0]].start()
            );
        }
        for (c, corner) in r.corners().iter().enumerate() {
            match bent.corners[c] {
                Some(o) => {
                    assert_eq!(region.corners()[o].pos, corner.pos);
                    assert!((region.corners()[o].loop_param - corner.loop_param).abs() < 1e-12);
                }
                None => {
                    let piece = bent.pieces[corner.piece_out];
                    let (foot, _) = region.pieces()[piece].closest_point(corner.pos);
                    assert!(foot.distance(corner.pos) < 1e-12);
                }
            }
        }
        // Every point of the bent region's boundary is on the original piece its piece maps to.
        for (p, piece) in r.pieces().iter().enumerate() {
            let orig = &region.pieces()[bent.pieces[p]];
            for x in piece.polygonize(1e-3) {
                assert!(orig.closest_point(x).0.distance(x) < 1e-12);
            }
        }
    }
}
