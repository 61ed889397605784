//! Features thinner than the spacing: where the region is narrower than the edges a request
//! asks for, no triangle fits across and the mesh there is slivers. Found before any work, so
//! that the user learns the size that would resolve it.
use crate::MeshRequest;
use geometry::{DVec2, Region};
use rayon::prelude::*;
use std::fmt;

/// Most boundary samples [`thin_feature`] casts a ray from.
const MAX_SAMPLES: usize = 4000;
/// Most boundary segments [`thin_feature`] tests rays against (beyond, it does not look).
const MAX_SEGMENTS: usize = 200_000;
/// Most ray–segment tests: on a long boundary fewer rays are cast, so the look stays under
/// about a second.
const MAX_TESTS: usize = 200_000_000;
/// A place counts as thin when it is narrower than this share of the spacing: a triangle of
/// edge h is 0.87 h high, so below half the spacing none fits across and the mesh there is
/// slivers. (The paper's horn narrows to 0.55 of its spacing at K = 138 and meshes well.)
const THIN_RATIO: f64 = 0.5;
/// The K advised for a thin place makes its width this many spacings there (the spacing the
/// width over this): one edge across. Half a spacing across, where a place stops counting as thin, still leaves slivers
/// in a long channel: a comb of teeth 0.02 wide (area 0.52) gave CCVT 144 triangles under 1°
/// at K = 376 (0.5 of the spacing across), 64 at K = 800 (0.73), a smallest angle of 1.1° at
/// K = 1200 (0.89) and 27.8° at K = 1600 (1.03).
const RESOLVED_RATIO: f64 = 1.0;
/// A ray that comes back to its own loop within this many widths of arc length only crossed a
/// corner's wedge (a 30° corner gives 3.7), not a feature.
const WEDGE_RATIO: f64 = 4.0;

/// ... and more than this many spacings of arc length away: a wedge sharper than about 28°
/// passes the width test near its tip, where every wedge is thinner than any spacing.
const WEDGE_SPACINGS: f64 = 2.0;

/// The narrowest place where the region is thinner than the requested spacing.
#[derive(Clone, Debug, PartialEq)]
pub struct ThinFeature {
    /// A boundary point there.
    pub at: DVec2,
    /// The region's width there (along the boundary's inward normal).
    pub width: f64,
    /// The spacing the request asks for there.
    pub spacing: f64,
    /// The K asked for.
    pub points: usize,
    /// The K at which the spacing there would equal the width (one edge across, which meshes
    /// without slivers; at twice the width the place stops counting as thin).
    pub points_needed: usize,
    /// Length of the boundary where the region is thinner than half the spacing.
    pub thin_length: f64,
    /// Where the only thin places are the sides of sharp corners, the sharpest such corner:
    /// its tip and interior angle in degrees. Every wedge is thinner than any spacing near its
    /// tip, so no K resolves it (`points_needed` only moves the place toward the tip).
    pub corner: Option<(DVec2, f64)>,
}

impl fmt::Display for ThinFeature {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some((tip, angle)) = self.corner {
            return write!(
                f,
                "the region narrows to a {angle:.1}° corner at ({:.6}, {:.6}): its sides are \
                 closer than half the spacing {:.3e} of K = {} over {:.3e} of the boundary, \
                 where the mesh has slivers; a corner this sharp stays thinner than the \
                 spacing near its tip at any K",
                tip.x, tip.y, self.spacing, self.points, self.thin_length
            );
        }
        write!(
            f,
            "the region is {:.3e} wide near ({:.6}, {:.6}) ({:.3e} of its boundary is that thin), \
             {:.1}× thinner than the spacing {:.3e} of K = {}: K ≥ {} (or an edge length of {:.3e}: size, --size) would resolve it \
             with one edge across",
            self.width,
            self.at.x,
            self.at.y,
            self.thin_length,
            self.spacing / self.width,
            self.spacing,
            self.points,
            self.points_needed,
            self.width / RESOLVED_RATIO
        )
    }
}

/// Where `region` is narrower than half the spacing `request` asks for, the narrowest place;
/// `None` where it is wide enough everywhere (or has more than 200 000 boundary segments).
///
/// Rays are cast along the inward normal from up to 4000 points spread along the boundary
/// (fewer on a boundary of more than 50 000 segments, at most 2·10⁸ ray–segment tests);
/// the width is the distance to the boundary they first meet, counted when that is another
/// loop or a part of the same loop more than 4 widths of arc length away (so that the wedge
/// of a sharp corner is not a feature). A place whose two sides meet at one vertex between
/// them, the sides of a corner sharper than about 28°, is reported only where no other place
/// is thin, with that corner in [`ThinFeature::corner`]: no K resolves a wedge. The spacing is
/// the request's mean spacing, scaled by ρ^(-1/4) against its mean for a graded request.
///
/// ```
/// use cvtmesh::{thin_feature, MeshRequest};
/// let channel = cvtmesh::geometry::formats::loops_from_str("0 0\n10 0\n10 0.001\n0 0.001\n", "c", "c")?;
/// let t = thin_feature(&channel, &MeshRequest::points(300)).expect("a thin channel");
/// assert!((t.width - 0.001).abs() < 1e-9);
/// assert!(t.spacing / t.width > 6.0);
/// assert!((11_400..11_800).contains(&t.points_needed));
/// let circle = cvtmesh::geometry::Region::builtin("circle")?;
/// assert!(thin_feature(&circle, &MeshRequest::points(300)).is_none());
/// # Ok::<(), cvtmesh::geometry::GeometryError>(())
/// ```
pub fn thin_feature(region: &Region, request: &MeshRequest) -> Option<ThinFeature> {
    let k = request.size.points(region);
    if k == 0 {
        return None;
    }
    let mean_spacing = request.spacing(region);
    let diam = region.diameter();
    let poly = region.polygonize(1e-4 * mean_spacing.min(diam));
    let nseg: usize = poly.rings.iter().map(|r| r.points.len()).sum();
    if nseg > MAX_SEGMENTS || nseg == 0 {
        return None;
    }
    // Segments of every ring with their ring and arc length at their start.
    let mut segs: Vec<(DVec2, DVec2, usize, f64)> = Vec::with_capacity(nseg);
    let mut lengths = Vec::with_capacity(poly.rings.len());
    let mut ring_start = Vec::with_capacity(poly.rings.len());
    for (r, ring) in poly.rings.iter().enumerate() {
        ring_start.push(segs.len());
        let n = ring.points.len();
        let mut s = 0.0;
        for i in 0..n {
            let (a, b) = (ring.points[i], ring.points[(i + 1) % n]);
            segs.push((a, b, r, s));
            s += a.distance(b);
        }
        lengths.push(s);
    }
    let perimeter: f64 = lengths.iter().sum();
    let samples = MAX_SAMPLES.min(MAX_TESTS / nseg).max(1);
    let step = (perimeter / samples as f64).max(f64::MIN_POSITIVE);
    let spacing_at = request.spacing_at(region);
    // Hits closer than rounding at the region's coordinates are the ray's own segment.
    let (lo, hi) = region.bbox();
    let magnitude = lo.abs().max(hi.abs()).max_element();
    let tiny = (1e-12 * diam).max(1e-12 * magnitude);
    let mut worst: Option<(f64, DVec2, f64, f64)> = None; // (width / spacing, at, width, spacing)
    let mut thin_length = 0.0;
    // The same for places whose two sides meet at one vertex between them (a wedge), with
    // the sharpest such corner.
    let mut worst_wedge: Option<(f64, DVec2, f64, f64)> = None;
    let mut wedge_length = 0.0;
    let mut sharpest: Option<(DVec2, f64)> = None;
    // The one ring vertex strictly between arc positions `a` and `b` of ring `r` along the
    // shorter way, if there is exactly one.
    let single_vertex = |r: usize, a: f64, b: f64| -> Option<usize> {
        let ring = &segs[ring_start[r]..ring_start[r] + poly.rings[r].points.len()];
        let (lo, hi) = (a.min(b), a.max(b));
        // Vertices sit at increasing arc positions: those in (lo, hi) are one index range.
        let first_after = |x: f64| ring.partition_point(|seg| seg.3 <= x);
        let first_at = |x: f64| ring.partition_point(|seg| seg.3 < x);
        let (i, j) = (first_after(lo), first_at(hi));
        if hi - lo <= 0.5 * lengths[r] {
            (j == i + 1).then_some(i)
        } else {
            // The other way round: after hi to the ring's end, then from its start to lo.
            let (after, before) = (ring.len() - first_after(hi), first_at(lo));
            match (after, before) {
                (1, 0) => Some(ring.len() - 1),
                (0, 1) => Some(0),
                _ => None,
            }
        }
    };
    // The samples: point, inward normal, ring, arc length.
    let mut rays: Vec<(DVec2, DVec2, usize, f64)> = Vec::with_capacity(samples + nseg);
    let mut next = 0.0;
    for &(a, b, r, s0) in &segs {
        let len = a.distance(b);
        if len <= 0.0 {
            continue;
        }
        let dir = (b - a) / len;
        // The interior lies left of every ring (outer loops CCW, holes CW).
        let normal = dir.perp();
        while next < s0 + len {
            let t = (next - s0).max(0.0);
            next += step;
            rays.push((a + dir * t, normal, r, s0 + t));
        }
        if next < s0 + len {
            next = s0 + len;
        }
        // Rings restart their arc length: carry the sampling position over.
        if (s0 + len - lengths[r]).abs() <= tiny {
            next = 0.0;
        }
    }
    // The rays in parallel (each meets every segment), their verdicts in sample order.
    let hits: Vec<Option<(f64, usize, f64)>> = rays
        .par_iter()
        .map(|&(q, normal, _, _)| cast(q, normal, &segs, tiny))
        .collect();
    for (&(q, _, r, sq), hit) in rays.iter().zip(hits) {
        let Some((width, hit_ring, hit_s)) = hit else {
            continue;
        };
        let h = spacing_at(q);
        if width >= THIN_RATIO * h {
            continue;
        }
        // The two sides must lie a few spacings apart along the boundary: any wedge is
        // arbitrarily thin near its tip (a 26° corner gave 7e-7 "wide" at 1e-6 from it).
        let feature = hit_ring != r || {
            let d = (sq - hit_s).abs();
            d.min(lengths[r] - d) > (WEDGE_RATIO * width).max(WEDGE_SPACINGS * h)
        };
        if !feature {
            continue;
        }
        let tip = (hit_ring == r)
            .then(|| single_vertex(r, sq, hit_s))
            .flatten();
        if let Some(i) = tip {
            let pts = &poly.rings[r].points;
            let n = pts.len();
            let (v, prev, next) = (pts[i], pts[(i + n - 1) % n], pts[(i + 1) % n]);
            let angle = (prev - v).angle_to(next - v).abs().to_degrees();
            if sharpest.is_none_or(|c| angle < c.1) {
                sharpest = Some((v, angle));
            }
            wedge_length += step;
            if worst_wedge.is_none_or(|w| width / h < w.0) {
                worst_wedge = Some((width / h, q, width, h));
            }
            continue;
        }
        thin_length += step;
        if worst.is_none_or(|w| width / h < w.0) {
            worst = Some((width / h, q, width, h));
        }
    }
    let (corner, (_, at, width, spacing)) = match (worst, worst_wedge) {
        (Some(w), _) => (None, w),
        (None, Some(w)) => {
            thin_length = wedge_length;
            (sharpest, w)
        }
        (None, None) => return None,
    };
    // The K at which the spacing there is the width: K grows as the spacing's inverse square.
    let needed = (k as f64 * (RESOLVED_RATIO * spacing / width).powi(2)).ceil();
    Some(ThinFeature {
        at,
        width,
        spacing,
        points: k,
        points_needed: if needed.is_finite() && needed < usize::MAX as f64 {
            needed as usize
        } else {
            usize::MAX
        },
        thin_length: thin_length.min(perimeter),
        corner,
    })
}

/// The first boundary segment the ray `o + t·d` (t > `tiny`) meets: distance, ring, arc
/// length of the hit.
fn cast(
    o: DVec2,
    d: DVec2,
    segs: &[(DVec2, DVec2, usize, f64)],
    tiny: f64,
) -> Option<(f64, usize, f64)> {
    let mut best: Option<(f64, usize, f64)> = None;
    for &(a, b, r, s0) in segs {
        let e = b - a;
        let den = d.perp_dot(e);
        if den.abs() <= f64::MIN_POSITIVE {
            continue;
        }
        let w = a - o;
        let t = w.perp_dot(e) / den;
        let u = w.perp_dot(d) / den;
        if t > tiny && (0.0..=1.0).contains(&u) && best.is_none_or(|x| t < x.0) {
            best = Some((t, r, s0 + u * e.length()));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_regions_at_the_papers_k_have_no_thin_features() {
        for (name, k) in Region::paper_cases() {
            let r = Region::builtin(name).unwrap();
            assert_eq!(
                thin_feature(&r, &MeshRequest::points(k)),
                None,
                "{name} K={k}"
            );
        }
    }

    #[test]
    fn a_gap_between_a_hole_and_the_outer_loop_is_found() {
        // A 1 × 1 square with a hole 0.002 from its right side.
        let text = "0 0\n1 0\n1 1\n0 1\n\n0.2 0.2\n0.998 0.2\n0.998 0.8\n0.2 0.8\n";
        let r = geometry::formats::loops_from_str(text, "gap", "gap").unwrap();
        let t = thin_feature(&r, &MeshRequest::points(200)).unwrap();
        assert!((t.width - 0.002).abs() < 1e-9, "{t}");
        assert!(t.at.x > 0.99, "{t}");
        assert!(thin_feature(&r, &MeshRequest::points(t.points_needed)).is_none());
    }

    #[test]
    fn a_sharp_corner_is_not_a_thin_feature_even_far_from_the_origin() {
        // A 20° wedge closed by an arc-like cap: thinner than any spacing near its tip, which
        // is a corner, not a feature; the same shifted to 1e6, where rounding is 1e-10.
        for offset in [0.0, 1e6] {
            let tan = 20f64.to_radians().tan();
            let text = format!(
                "{o} {o}\n{a} {o}\n{a} {b}\n",
                o = offset,
                a = offset + 1.0,
                b = offset + tan
            );
            let r = geometry::formats::loops_from_str(&text, "wedge", "wedge").unwrap();
            // At most the stretch a spacing or two from the tip, where a few times the points
            // resolve it (before: widths of 1e-7 and K ≥ 10¹² at 1e-6 from the tip).
            for k in [30, 300, 3000] {
                if let Some(t) = thin_feature(&r, &MeshRequest::points(k)) {
                    assert!(t.width > 0.25 * t.spacing, "{offset} K={k}: {t}");
                    assert!(t.points_needed < 16 * k, "{offset} K={k}: {t}");
                }
            }
        }
    }

    #[test]
    fn a_one_degree_wedge_is_named_as_a_corner_no_k_resolves() {
        // Its sides are closer than half of any spacing over a long stretch from the tip: a
        // "K ≥ …" would only move the place toward the tip (2·10⁶ at K = 3000).
        let tan = 1f64.to_radians().tan();
        let text = format!("0 0\n1 0\n1 {tan}\n");
        let r = geometry::formats::loops_from_str(&text, "wedge", "wedge").unwrap();
        for k in [300, 3000] {
            let t = thin_feature(&r, &MeshRequest::points(k)).expect("a thin wedge");
            let (tip, angle) = t.corner.expect("named as a corner");
            assert!(tip.length() < 1e-12 && (angle - 1.0).abs() < 1e-6, "{t}");
            let text = t.to_string();
            assert!(
                text.contains("1.0° corner at (0.000000, 0.000000)"),
                "{text}"
            );
            assert!(!text.contains("would resolve"), "{text}");
        }
        // A channel of constant width is not a corner, and says what K resolves it.
        let channel = "0 0\n10 0\n10 0.001\n0 0.001\n";
        let r = geometry::formats::loops_from_str(channel, "c", "c").unwrap();
        let t = thin_feature(&r, &MeshRequest::points(300)).unwrap();
        assert_eq!(t.corner, None);
        assert!(t.to_string().contains("would resolve it"), "{t}");
    }
}
