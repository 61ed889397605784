//! The input PSLG handed to the refinement: the region's boundary loops as vertices and
//! directed segments (domain on the left), with every curved piece pre-split into chords whose
//! end points lie on the exact curve, and its embedded lines as segments inside.
use crate::grid::SegGrid;
use geometry::predicates::{closest_on_segment, ring_signed_area, segment_distance};
use geometry::{DVec2, Density, LoopRole, Piece, PieceId, Region};
use mesh::MeshError;
use std::collections::HashMap;

/// What a vertex is, as far as the refinement needs to know.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum VKind {
    /// A region corner (index into `Region::corners()`); never moves.
    Corner(usize),
    /// A point on the given boundary piece.
    Boundary(PieceId),
    /// A point on an embedded line, inside the region.
    Line,
    /// A Steiner point inside the region.
    Interior,
}

/// A planar straight-line graph: the boundary loops of the region and its embedded lines.
pub(crate) struct Pslg {
    pub points: Vec<DVec2>,
    pub kinds: Vec<VKind>,
    /// Directed segments `(from, to, piece)` in loop order, so the region is on their left.
    pub segments: Vec<(usize, usize, PieceId)>,
    /// Segments of the embedded lines `(from, to, own)`, the region on both sides; `own`
    /// indexes `line_inputs`.
    pub lines: Vec<(usize, usize, usize)>,
    /// The lines' own segments, between their vertices (and crossings): the input segments
    /// whose meeting makes the small angles the refinement leaves as they are, however the
    /// pieces along them were split.
    pub line_inputs: Vec<(usize, usize)>,
}

/// True for pieces that are not straight: their subsegments are chords and split points are
/// placed on the curve itself.
pub(crate) fn is_curved(piece: &Piece) -> bool {
    !matches!(piece, Piece::Line { .. })
}

/// Build the PSLG: straight pieces enter as single segments (Triangle's input; the refinement
/// splits them when encroached), curved pieces are pre-split into chords of length ≈ `spacing`
/// (locally `spacing · ρ^(-1/4)`), every split point projected onto the exact curve; the
/// region's embedded points are vertices inside. `None` when the spacing is so coarse that a
/// loop's polygon keeps fewer than three vertices or no area on the region's side (a thin
/// triangle whose bent side is one chain, at a spacing longer than that chain), which the area
/// bound's search counts as too coarse.
/// `phases[i]` (a fraction of one chord, in [0, 1)) moves where the split of loop `i` starts
/// when that loop is one closed curve (a circle, a super-ellipse), which has no corner to
/// start from; missing entries are 0, a split from the piece's own start.
pub(crate) fn build(
    region: &Region,
    spacing: f64,
    density: &Density,
    phases: &[f64],
) -> Result<Option<Pslg>, MeshError> {
    let diam = region.diameter();
    let mut pslg = Pslg {
        points: Vec::new(),
        kinds: Vec::new(),
        segments: Vec::new(),
        lines: Vec::new(),
        line_inputs: Vec::new(),
    };
    for (li, lp) in region.loops().iter().enumerate() {
        let first = pslg.points.len();
        let mut piece_of = Vec::new();
        let phase = phases.get(li).copied().unwrap_or(0.0);
        for &pid in &lp.pieces {
            let piece = &region.pieces()[pid];
            if piece.is_closed() && phase > 0.0 {
                // Every point of the split, none at the piece's start.
                for p in split_at(region, pid, spacing, density, phase) {
                    pslg.points.push(p);
                    pslg.kinds.push(VKind::Boundary(pid));
                    piece_of.push(pid);
                }
                continue;
            }
            let start = piece.start();
            let corner = region
                .corners()
                .iter()
                .position(|c| (c.pos - start).length() <= 1e-9 * diam);
            pslg.points.push(start);
            pslg.kinds
                .push(corner.map_or(VKind::Boundary(pid), VKind::Corner));
            piece_of.push(pid);
            if is_curved(piece) {
                let mut split = split_curve(region, pid, spacing, density);
                if let Piece::Chain(chain) = piece {
                    split = follow_bends(chain, split);
                }
                for p in split {
                    pslg.points.push(p);
                    pslg.kinds.push(VKind::Boundary(pid));
                    piece_of.push(pid);
                }
            }
        }
        let n = pslg.points.len() - first;
        // A chain cut to one chord can lie along the loop's other side (a thin triangle whose
        // third corner was dropped as a bend): the loop's polygon must keep the region on its
        // left with some area, or the refinement would mesh a sliver of zero area.
        let area = ring_signed_area(&pslg.points[first..]);
        let sign = if lp.role == LoopRole::Hole { -1.0 } else { 1.0 };
        if n < 3 || sign * area <= 1e-9 * lp.length * lp.length {
            return Ok(None);
        }
        for (i, &pid) in piece_of.iter().enumerate() {
            pslg.segments.push((first + i, first + (i + 1) % n, pid));
        }
    }
    // Points embedded in the region are input vertices inside, as Triangle takes a `.poly`'s
    // vertices on no segment. One between a curved piece and its chords would be outside the
    // polygon that is meshed; a chord strays from its curve by at most half its length, so
    // only points that near a curved piece need the test against every segment (straight
    // pieces are their own segments).
    let reach = pslg
        .segments
        .iter()
        .filter(|&&(_, _, piece)| is_curved(&region.pieces()[piece]))
        .map(|&(a, b, _)| (pslg.points[b] - pslg.points[a]).length())
        .fold(0.0, f64::max);
    let chords: Vec<(DVec2, DVec2)> = pslg
        .segments
        .iter()
        .map(|&(a, b, _)| (pslg.points[a], pslg.points[b]))
        .collect();
    let outside_chords = |p: DVec2| {
        let mut crossings = 0;
        for &(a, b) in &chords {
            if geometry::predicates::orient(a, b, p) == 0.0 && (p - a).dot(p - b) <= 0.0 {
                return true;
            }
            if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) {
                crossings += 1;
            }
        }
        crossings % 2 == 0
    };
    let between_chords = |p: DVec2| region.signed_distance(p) >= -reach && outside_chords(p);
    let off = 1e-9 * diam;
    // Every boundary vertex by its bits, and a line's by its bits once placed: a line's end on
    // ∂Ω is the corner there, and lines share their crossings' bits.
    let mut at: HashMap<(u64, u64), usize> = pslg
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| (bits(*p), i))
        .collect();
    // The lines' own segments, between their own vertices.
    let mut own: Vec<(usize, usize)> = Vec::new();
    for (i, line) in region.embedded_lines().iter().enumerate() {
        let mut previous = None;
        for &p in &line.points {
            let v = match at.get(&bits(p)) {
                Some(&v) => v,
                None => {
                    if let Some(c) = region
                        .corners()
                        .iter()
                        .position(|c| c.pos.distance(p) <= off)
                    {
                        pslg.kinds
                            .iter()
                            .position(|k| *k == VKind::Corner(c))
                            .expect("every corner is a vertex of the boundary")
                    } else {
                        if between_chords(p) {
                            return Err(MeshError::Failed {
                                method: "refine".into(),
                                message: format!(
                                    "embedded line {i} has its point ({}, {}) between a curved \
                                     boundary and its chords at this spacing; move it inward, or \
                                     use ccvt or distmesh",
                                    p.x, p.y
                                ),
                            });
                        }
                        pslg.points.push(p);
                        pslg.kinds.push(VKind::Line);
                        pslg.points.len() - 1
                    }
                }
            };
            at.insert(bits(p), v);
            // A piece of a line running along a wall is that wall's segment already.
            let on_boundary = |w: usize| !matches!(pslg.kinds[w], VKind::Line | VKind::Interior);
            if let Some(u) = previous.filter(|&u| u != v) {
                let along_wall = on_boundary(u)
                    && on_boundary(v)
                    && region
                        .signed_distance(0.5 * (pslg.points[u] + pslg.points[v]))
                        .abs()
                        <= off;
                if !along_wall {
                    own.push((u, v));
                }
            }
            previous = Some(v);
        }
    }
    // Embedded points on a line split it there (found through a grid of the line segments).
    let grid = (!own.is_empty()).then(|| {
        let (lo, hi) = region.bbox();
        let pad = DVec2::splat(1e-6 * diam);
        let mut g = SegGrid::new(lo - pad, hi + pad, 4 * own.len());
        for (s, &(a, b)) in own.iter().enumerate() {
            let (pa, pb) = (pslg.points[a], pslg.points[b]);
            let slack = DVec2::splat(2.0 * off);
            g.insert((s as u32, s as u32), pa.min(pb) - slack, pa.max(pb) + slack);
        }
        g
    });
    // (own segment, parameter along it, vertex) for each point that splits a line.
    let mut splits: Vec<(usize, f64, usize)> = Vec::new();
    for &(p, _) in region.embedded_points() {
        if at
            .get(&bits(p))
            .is_some_and(|&v| pslg.kinds[v] == VKind::Line)
        {
            continue;
        }
        if between_chords(p) {
            return Err(MeshError::Failed {
                method: "refine".into(),
                message: format!(
                    "the embedded point ({}, {}) lies between a curved boundary and its chords \
                     at this spacing; move it inward, or use ccvt or distmesh",
                    p.x, p.y
                ),
            });
        }
        let on = grid.as_ref().and_then(|g| {
            g.near(p).iter().find_map(|&(s, _)| {
                let (a, b) = own[s as usize];
                let (q, t, _) = closest_on_segment(pslg.points[a], pslg.points[b], p);
                (q.distance(p) <= off && t > 0.0 && t < 1.0).then_some((s as usize, t))
            })
        });
        at.insert(bits(p), pslg.points.len());
        pslg.points.push(p);
        pslg.kinds.push(if on.is_some() {
            VKind::Line
        } else {
            VKind::Interior
        });
        if let Some((s, t)) = on {
            splits.push((s, t, pslg.points.len() - 1));
        }
    }
    splits.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    // Each own segment through the points on it, and between those split at the boundary's
    // spacing, as the curved pieces are: the refinement splits further only where something
    // encroaches.
    let local = |q: DVec2| {
        if density.is_uniform() {
            spacing
        } else {
            spacing / density.at(q).max(1e-300).powf(0.25)
        }
    };
    let mut next = 0;
    for (s, &(a, b)) in own.iter().enumerate() {
        let mut chain = vec![a];
        while next < splits.len() && splits[next].0 == s {
            chain.push(splits[next].2);
            next += 1;
        }
        chain.push(b);
        for w in chain.windows(2) {
            let mut from = w[0];
            for q in mesh::split_at_spacing(pslg.points[w[0]], pslg.points[w[1]], local) {
                pslg.points.push(q);
                pslg.kinds.push(VKind::Line);
                pslg.lines.push((from, pslg.points.len() - 1, s));
                from = pslg.points.len() - 1;
            }
            pslg.lines.push((from, w[1], s));
        }
    }
    pslg.line_inputs = own;
    Ok(Some(pslg))
}

fn bits(p: DVec2) -> (u64, u64) {
    (p.x.to_bits(), p.y.to_bits())
}

/// `split` (a chain's interior split points, in order) with the chain's vertices added where
/// a chord would stray more than [`CHAIN_BEND`] of its length from it, each at the farthest
/// vertex, until none does: the mesh's boundary edges then follow the chain's dents as the
/// conformity check asks, whether or not the refinement later splits them.
fn follow_bends(chain: &[DVec2], split: Vec<DVec2>) -> Vec<DVec2> {
    let mut ends = Vec::with_capacity(split.len() + 2);
    ends.push(chain[0]);
    ends.extend(split);
    ends.push(chain[chain.len() - 1]);
    let mut out = Vec::with_capacity(ends.len());
    for w in ends.windows(2) {
        // Depth first with a stack of its own (a long spiral could nest as deep as it has
        // vertices): the chord's right half waits while the left one is followed.
        let mut todo = vec![(w[0], w[1])];
        while let Some((a, b)) = todo.pop() {
            match farthest_between(chain, a, b).filter(|&(_, d)| d > CHAIN_BEND * a.distance(b)) {
                Some((v, _)) => {
                    todo.push((v, b));
                    todo.push((a, v));
                }
                None => out.push(b),
            }
        }
    }
    // Interior points only: the last one pushed is the chain's end.
    out.pop();
    out
}

/// Interior split points of a curved piece (start and end excluded), at equal steps of
/// ∫ ρ^{1/4} ds, each projected onto the piece. The count is raised until every chord stays
/// within a quarter of its length of the curve, so each curve arc lies inside its chord's
/// diametral circle (the refinement relies on that to keep Steiner points inside Ω).
fn split_curve(region: &Region, pid: PieceId, spacing: f64, density: &Density) -> Vec<DVec2> {
    let mut pts = split_at(region, pid, spacing, density, 0.0);
    // The first point is the piece's start, which the caller adds as the loop's vertex.
    pts.remove(0);
    pts
}

/// The points at ∫ ρ^{1/4} ds = (k + `phase`) · total / n, k = 0 … n − 1, along the piece
/// (with `phase` = 0 the first is the piece's start), n raised until every chord between
/// consecutive points (and, for a closed piece, from the last back to the first) stays within
/// a quarter of its length of the curve.
fn split_at(
    region: &Region,
    pid: PieceId,
    spacing: f64,
    density: &Density,
    phase: f64,
) -> Vec<DVec2> {
    let piece = &region.pieces()[pid];
    let dense = piece.polygonize(
        (1e-3 * spacing)
            .min(1e-3 * piece.length())
            .max(1e-12 * region.diameter()),
    );
    // Cumulative weighted length along the dense polyline.
    let mut cum = vec![0.0];
    for w in dense.windows(2) {
        let rho = if density.is_uniform() {
            1.0
        } else {
            density.at(0.5 * (w[0] + w[1])).max(1e-300).powf(0.25)
        };
        cum.push(cum.last().unwrap() + rho * (w[1] - w[0]).length());
    }
    let total = *cum.last().unwrap();
    let closed = piece.is_closed();
    let min_n = if closed { 8 } else { 1 };
    let mut n = ((total / spacing).round() as usize).max(min_n);
    let last_seg = dense.len() - 2;
    loop {
        let mut pts = Vec::with_capacity(n);
        // seg[k]: the dense segment holding point k (the piece's start: before segment 0).
        let mut seg = Vec::with_capacity(n);
        let mut j = 0;
        for k in 0..n {
            let s = total * (k as f64 + phase) / n as f64;
            if k == 0 && phase == 0.0 {
                pts.push(piece.start());
                seg.push(usize::MAX);
                continue;
            }
            while j < last_seg && cum[j + 1] < s {
                j += 1;
            }
            let t = if cum[j + 1] > cum[j] {
                (s - cum[j]) / (cum[j + 1] - cum[j])
            } else {
                0.0
            };
            let q = dense[j].lerp(dense[j + 1], t.clamp(0.0, 1.0));
            pts.push(region.project_point_onto_piece(q, pid));
            seg.push(j);
        }
        // Dense samples strictly after point k's own segment start, up to and including the
        // start of the segment holding point k + 1; the last chord runs to the piece's end and,
        // when the first point is not the start, on from the start to it.
        let after = |k: usize| if seg[k] == usize::MAX { 1 } else { seg[k] + 1 };
        let ok = (0..n).all(|k| {
            let a = pts[k];
            if k + 1 < n {
                let b = pts[k + 1];
                let len = (b - a).length();
                return (after(k)..=seg[k + 1])
                    .all(|i| segment_distance(dense[i], a, b) <= 0.25 * len);
            }
            let b = if phase == 0.0 { piece.end() } else { pts[0] };
            let len = (b - a).length();
            let wrap = if phase == 0.0 { 0..0 } else { 0..seg[0] + 1 };
            (after(k)..=last_seg)
                .chain(wrap)
                .all(|i| segment_distance(dense[i], a, b) <= 0.25 * len)
        });
        // A chain's chords are followed to its bends by `follow_bends`, at its own vertices.
        // Doubling cannot serve a chain with a sharp turn inside it (a corner dropped by the
        // corner angle): no equal steps put a point on the turn, and the count would run to
        // the cap whatever the spacing.
        if ok || n > 1 << 16 || matches!(piece, Piece::Chain(_)) {
            return pts;
        }
        n *= 2;
    }
}

/// A chord of a polyline piece farther than this share of its length from the polyline is
/// split at the polyline's farthest vertex rather than at its midpoint: a digitized
/// coastline's dent between two boundary vertices is kept under the 0.13 a conforming mesh's
/// boundary edge may stray (halving a chord without looking doubles the dent's share).
pub(crate) const CHAIN_BEND: f64 = 0.1;

/// The vertex of the chain `pts` strictly between its points `a` and `b` (both on it, `a`
/// first along it) that lies farthest from the chord `ab`, with that distance.
pub(crate) fn farthest_between(pts: &[DVec2], a: DVec2, b: DVec2) -> Option<(DVec2, f64)> {
    let param = |p: DVec2| {
        // Arc length of the chain's nearest point to p.
        let (mut best, mut at, mut s) = (f64::INFINITY, 0.0, 0.0);
        for w in pts.windows(2) {
            let (u, v) = (w[0], w[1]);
            let len = u.distance(v);
            let t = if len > 0.0 {
                ((p - u).dot(v - u) / (len * len)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let d = p.distance(u.lerp(v, t));
            if d < best {
                (best, at) = (d, s + t * len);
            }
            s += len;
        }
        at
    };
    // The chain's own ends by position: a closed chain's end is its start, which the nearest
    // point would put at arc length 0.
    let total: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
    let sa = if a == pts[0] { 0.0 } else { param(a) };
    let sb = if b == pts[pts.len() - 1] {
        total
    } else {
        param(b)
    };
    let (lo, hi) = (sa.min(sb), sa.max(sb));
    let chord = b - a;
    let len = chord.length();
    if len <= 0.0 {
        return None;
    }
    let mut s = 0.0;
    let mut best: Option<(DVec2, f64)> = None;
    for (i, &v) in pts.iter().enumerate() {
        if i > 0 {
            s += pts[i - 1].distance(v);
        }
        if s <= lo || s >= hi {
            continue;
        }
        let d = chord.perp_dot(v - a).abs() / len;
        if best.is_none_or(|(_, bd)| d > bd) {
            best = Some((v, d));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chord_over_a_dent_is_split_at_the_dent() {
        // A straight chain with a dent of depth 0.2 at x = 0.3: the chord from (0, 0) to
        // (1, 0) is split at the dent's tip, not at its midpoint.
        let v = |x: f64, y: f64| DVec2::new(x, y);
        let pts = vec![
            v(0.0, 0.0),
            v(0.2, 0.0),
            v(0.3, 0.2),
            v(0.4, 0.0),
            v(1.0, 0.0),
        ];
        let (at, d) = farthest_between(&pts, v(0.0, 0.0), v(1.0, 0.0)).unwrap();
        assert_eq!(at, v(0.3, 0.2));
        assert!((d - 0.2).abs() < 1e-12);
        // Between (0.4, 0) and (1, 0) there is no vertex.
        assert!(farthest_between(&pts, v(0.4, 0.0), v(1.0, 0.0)).is_none());
        // Only vertices strictly between the two points count.
        let (at, _) = farthest_between(&pts, v(0.25, 0.1), v(1.0, 0.0)).unwrap();
        assert_eq!(at, v(0.3, 0.2));
    }

    #[test]
    fn chords_follow_a_chains_bends() {
        // A straight chain with a dent of depth 0.2 at x = 0.3 and a split point at x = 0.6:
        // the chord from the start to the split point strays 0.2 / 0.6 of its length, so the
        // dent's tip is added; the chord from there to the end does not stray.
        let v = |x: f64, y: f64| DVec2::new(x, y);
        let chain = vec![
            v(0.0, 0.0),
            v(0.3, 0.2),
            v(0.6, 0.0),
            v(0.8, 0.01),
            v(1.0, 0.0),
        ];
        assert_eq!(
            follow_bends(&chain, vec![v(0.6, 0.0)]),
            vec![v(0.3, 0.2), v(0.6, 0.0)]
        );
        // A closed chain: its end is its start, and the chord back to it is examined too.
        let ring = vec![
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(1.0, 1.0),
            v(0.5, 1.2),
            v(0.0, 1.0),
            v(0.0, 0.0),
        ];
        let split = follow_bends(&ring, vec![v(1.0, 1.0)]);
        assert_eq!(
            split,
            vec![v(1.0, 0.0), v(1.0, 1.0), v(0.5, 1.2), v(0.0, 1.0)]
        );
    }

    #[test]
    fn curved_pieces_are_split_on_the_curve() {
        let region = Region::builtin("horn").unwrap();
        let h = 0.05;
        let g = build(&region, h, &Density::Uniform, &[]).unwrap().unwrap();
        assert_eq!(g.points.len(), g.segments.len());
        for p in &g.points {
            assert!(region.signed_distance(*p).abs() < 1e-12, "{p}");
        }
        // Every corner is a vertex with its corner kind.
        for (ci, c) in region.corners().iter().enumerate() {
            let i = g
                .points
                .iter()
                .position(|p| (*p - c.pos).length() < 1e-12)
                .unwrap();
            assert_eq!(g.kinds[i], VKind::Corner(ci));
        }
        // Chords on curved pieces are about h long; straight pieces are single segments.
        for &(a, b, piece) in &g.segments {
            let len = (g.points[b] - g.points[a]).length();
            if is_curved(&region.pieces()[piece]) {
                assert!(len > 0.7 * h && len < 1.3 * h, "{len}");
            } else {
                assert!((len - region.pieces()[piece].length()).abs() < 1e-12);
            }
        }
        // Loop direction keeps the region on the left: the shoelace sum is the chord polygon's area.
        let area: f64 = g
            .segments
            .iter()
            .map(|&(a, b, _)| 0.5 * g.points[a].perp_dot(g.points[b]))
            .sum();
        assert!(
            (area - region.area()).abs() < 0.01 * region.area(),
            "{area}"
        );
    }

    /// A line from a corner of the square through the end of another, and a point placed on
    /// the second: the line's end is the corner's vertex, the other's end one vertex of both,
    /// the point splits the second line, and every piece is about the spacing long.
    #[test]
    fn lines_enter_as_segments_split_at_the_spacing_through_their_points() {
        let v = DVec2::new;
        let square = vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)];
        let line = |pts: &[(f64, f64)]| geometry::EmbeddedLine {
            points: pts.iter().map(|&(x, y)| v(x, y)).collect(),
            marker: 1,
        };
        let region = Region::from_loops("square", vec![(LoopRole::Outer, square)])
            .unwrap()
            .with_embedded_lines([
                line(&[(1.0, 0.0), (0.5, 0.5)]),
                line(&[(0.2, 0.8), (0.8, 0.8), (0.8, 0.2)]),
            ])
            .unwrap()
            .with_embedded_points([(v(0.8, 0.5), 3)])
            .unwrap();
        let h = 0.1;
        let g = build(&region, h, &Density::Uniform, &[]).unwrap().unwrap();
        let at = |p: DVec2| g.points.iter().position(|q| *q == p).unwrap();
        let corner = at(v(1.0, 0.0));
        assert!(matches!(g.kinds[corner], VKind::Corner(_)));
        assert_eq!(g.points.iter().filter(|q| **q == v(1.0, 0.0)).count(), 1);
        let point = at(v(0.8, 0.5));
        assert_eq!(g.kinds[point], VKind::Line);
        // Each vertex's pieces: two along a line, one at a line's end.
        let degree = |i: usize| {
            g.lines
                .iter()
                .filter(|&&(a, b, _)| a == i || b == i)
                .count()
        };
        assert_eq!(degree(corner), 1);
        assert_eq!(degree(point), 2);
        assert_eq!(degree(at(v(0.8, 0.8))), 2);
        assert_eq!(degree(at(v(0.2, 0.8))), 1);
        let total: f64 = region.embedded_lines().iter().map(|l| l.length()).sum();
        let pieces: Vec<f64> = g
            .lines
            .iter()
            .map(|&(a, b, _)| g.points[a].distance(g.points[b]))
            .collect();
        assert!((pieces.iter().sum::<f64>() - total).abs() < 1e-12);
        assert!(
            pieces.iter().all(|&l| (0.6 * h..1.5 * h).contains(&l)),
            "{pieces:?}"
        );
        assert_eq!(degree(at(v(0.8, 0.2))), 3);
    }

    #[test]
    fn polygons_enter_unsplit() {
        let region = Region::builtin("square_two_hex").unwrap();
        let g = build(&region, 0.01, &Density::Uniform, &[])
            .unwrap()
            .unwrap();
        assert_eq!(g.points.len(), region.corners().len());
        assert!(g.kinds.iter().all(|k| matches!(k, VKind::Corner(_))));
    }

    #[test]
    fn a_phase_turns_a_closed_curves_chords_and_nothing_else() {
        let region = Region::builtin("annulus").unwrap();
        let h = 0.1;
        let plain = build(&region, h, &Density::Uniform, &[]).unwrap().unwrap();
        let turned = build(&region, h, &Density::Uniform, &[0.3, 0.75])
            .unwrap()
            .unwrap();
        // The same number of chords per loop, every vertex on the circles, the same chord
        // length on each circle (equal steps of arc length), and no vertex at angle 0.
        assert_eq!(plain.points.len(), turned.points.len());
        assert_eq!(plain.segments.len(), turned.segments.len());
        for g in [&plain, &turned] {
            let mut by_piece = std::collections::BTreeMap::<usize, Vec<f64>>::new();
            for &(a, b, piece) in &g.segments {
                by_piece
                    .entry(piece)
                    .or_default()
                    .push((g.points[b] - g.points[a]).length());
            }
            for lens in by_piece.values() {
                let (lo, hi) = lens
                    .iter()
                    .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
                assert!(hi - lo < 1e-4 * hi, "{lo} .. {hi}");
            }
            for p in &g.points {
                assert!(region.signed_distance(*p).abs() < 1e-12, "{p}");
            }
        }
        // Each loop's first vertex sits at its phase of one step past angle 0 (the outer circle
        // runs counter-clockwise from (1, 0), the hole clockwise from (0.4, 0)).
        let outer = plain.segments.iter().filter(|s| s.2 == 0).count();
        let step = std::f64::consts::TAU / outer as f64;
        let first = turned.points[0];
        assert!(
            (first.y.atan2(first.x) - 0.3 * step).abs() < 1e-5 * step,
            "{first}"
        );
        let inner_first = turned.points[outer];
        let inner = turned.points.len() - outer;
        let inner_step = std::f64::consts::TAU / inner as f64;
        assert!(
            (inner_first.y.atan2(inner_first.x) + 0.75 * inner_step).abs() < 1e-5 * inner_step,
            "{inner_first}"
        );
        assert!(turned
            .points
            .iter()
            .all(|p| p.y.abs() > 1e-3 || p.x.abs() < 0.3));
        // A polygon has no phase: its loops are the same for any.
        let square = Region::builtin("square_two_hex").unwrap();
        let a = build(&square, 0.05, &Density::Uniform, &[])
            .unwrap()
            .unwrap();
        let b = build(&square, 0.05, &Density::Uniform, &[0.5, 0.5, 0.5])
            .unwrap()
            .unwrap();
        assert_eq!(a.points, b.points);
    }
}
