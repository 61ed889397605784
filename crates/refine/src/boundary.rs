//! The input PSLG handed to the refinement: the region's boundary loops as vertices and
//! directed segments (domain on the left), with every curved piece pre-split into chords whose
//! end points lie on the exact curve.
use geometry::predicates::segment_distance;
use geometry::{DVec2, Density, Piece, PieceId, Region};
use mesh::MeshError;

/// What a vertex is, as far as the refinement needs to know.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum VKind {
    /// A region corner (index into `Region::corners()`); never moves.
    Corner(usize),
    /// A point on the given boundary piece.
    Boundary(PieceId),
    /// A Steiner point inside the region.
    Interior,
}

/// A planar straight-line graph: the boundary loops of the region.
pub(crate) struct Pslg {
    pub points: Vec<DVec2>,
    pub kinds: Vec<VKind>,
    /// Directed segments `(from, to, piece)` in loop order, so the region is on their left.
    pub segments: Vec<(usize, usize, PieceId)>,
}

/// True for pieces that are not straight: their subsegments are chords and split points are
/// placed on the curve itself.
pub(crate) fn is_curved(piece: &Piece) -> bool {
    !matches!(piece, Piece::Line { .. })
}

/// Build the PSLG: straight pieces enter as single segments (Triangle's input; the refinement
/// splits them when encroached), curved pieces are pre-split into chords of length ≈ `spacing`
/// (locally `spacing · ρ^(-1/4)`), every split point projected onto the exact curve.
pub(crate) fn build(region: &Region, spacing: f64, density: &Density) -> Result<Pslg, MeshError> {
    let diam = region.diameter();
    let mut pslg = Pslg {
        points: Vec::new(),
        kinds: Vec::new(),
        segments: Vec::new(),
    };
    for lp in region.loops() {
        let first = pslg.points.len();
        let mut piece_of = Vec::new();
        for &pid in &lp.pieces {
            let piece = &region.pieces()[pid];
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
                for p in split_curve(region, pid, spacing, density) {
                    pslg.points.push(p);
                    pslg.kinds.push(VKind::Boundary(pid));
                    piece_of.push(pid);
                }
            }
        }
        let n = pslg.points.len() - first;
        if n < 3 {
            return Err(MeshError::Failed {
                method: "refine".into(),
                message: format!("boundary loop with only {n} vertices"),
            });
        }
        for (i, &pid) in piece_of.iter().enumerate() {
            pslg.segments.push((first + i, first + (i + 1) % n, pid));
        }
    }
    Ok(pslg)
}

/// Interior split points of a curved piece (start and end excluded), at equal steps of
/// ∫ ρ^{1/4} ds, each projected onto the piece. The count is raised until every chord stays
/// within a quarter of its length of the curve, so each curve arc lies inside its chord's
/// diametral circle (the refinement relies on that to keep Steiner points inside Ω).
fn split_curve(region: &Region, pid: PieceId, spacing: f64, density: &Density) -> Vec<DVec2> {
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
    let min_n = if piece.is_closed() { 8 } else { 1 };
    let mut n = ((total / spacing).round() as usize).max(min_n);
    loop {
        let mut pts = Vec::with_capacity(n.saturating_sub(1));
        // seg[k]: the dense segment holding split point k (k = 1..n-1).
        let mut seg = Vec::with_capacity(n + 1);
        seg.push(usize::MAX);
        let mut j = 0;
        for k in 1..n {
            let s = total * k as f64 / n as f64;
            while j + 1 < cum.len() - 1 && cum[j + 1] < s {
                j += 1;
            }
            let t = if cum[j + 1] > cum[j] {
                (s - cum[j]) / (cum[j + 1] - cum[j])
            } else {
                0.0
            };
            let q = dense[j].lerp(dense[j + 1], t.clamp(0.0, 1.0));
            pts.push(region.project_onto_piece(q, pid).point);
            seg.push(j);
        }
        // Chord check against the dense samples strictly between consecutive split points.
        let mut ends = vec![piece.start()];
        ends.extend(pts.iter().copied());
        ends.push(piece.end());
        let ok = (0..n).all(|k| {
            let (a, b) = (ends[k], ends[k + 1]);
            let len = (b - a).length();
            let first = if k == 0 { 1 } else { seg[k] + 1 };
            let last = if k + 1 == n {
                dense.len() - 2
            } else {
                seg[k + 1]
            };
            (first..=last).all(|i| segment_distance(dense[i], a, b) <= 0.25 * len)
        });
        if ok || n > 1 << 16 {
            return pts;
        }
        n *= 2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curved_pieces_are_split_on_the_curve() {
        let region = Region::builtin("horn").unwrap();
        let h = 0.05;
        let g = build(&region, h, &Density::Uniform).unwrap();
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

    #[test]
    fn polygons_enter_unsplit() {
        let region = Region::builtin("square_two_hex").unwrap();
        let g = build(&region, 0.01, &Density::Uniform).unwrap();
        assert_eq!(g.points.len(), region.corners().len());
        assert!(g.kinds.iter().all(|k| matches!(k, VKind::Corner(_))));
    }
}
