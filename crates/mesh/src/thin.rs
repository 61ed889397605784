//! Features thinner than the spacing: where the region is narrower than the edges a request
//! asks for, no triangle fits across and the mesh there is slivers. Found before any work, so
//! that the user learns the size that would resolve it.
use crate::MeshRequest;
use geometry::{DVec2, Polygon, Region};
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
    let (segs, lengths, ring_start) = segments(&poly);
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
    // The rays in parallel, each through the cells of a grid of the segments, their verdicts
    // in sample order.
    let grid = SegmentGrid::new(&segs, diam);
    let hits: Vec<Option<(f64, usize, f64)>> = rays
        .par_iter()
        .map(|&(q, normal, _, _)| grid.cast(q, normal, &segs, tiny))
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

/// A boundary segment: its ends, ring, and arc length at its start.
type Seg = (DVec2, DVec2, usize, f64);

/// The segments of every ring of `poly` in order, each ring's length, and where each ring's
/// segments start.
fn segments(poly: &Polygon) -> (Vec<Seg>, Vec<f64>, Vec<usize>) {
    let mut segs = Vec::with_capacity(poly.rings.iter().map(|r| r.points.len()).sum());
    let (mut lengths, mut ring_start) = (Vec::new(), Vec::new());
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
    (segs, lengths, ring_start)
}

/// Where the ray `o + t·d` meets segment `seg` (t > `tiny`): t, and the arc length of the hit.
#[inline]
fn meet(o: DVec2, d: DVec2, &(a, b, _, s0): &Seg, tiny: f64) -> Option<(f64, f64)> {
    let e = b - a;
    let den = d.perp_dot(e);
    if den.abs() <= f64::MIN_POSITIVE {
        return None;
    }
    let w = a - o;
    let t = w.perp_dot(e) / den;
    let u = w.perp_dot(d) / den;
    (t > tiny && (0.0..=1.0).contains(&u)).then(|| (t, s0 + u * e.length()))
}

/// The first boundary segment the ray `o + t·d` (t > `tiny`, `d` a unit vector) meets:
/// distance, ring, arc length of the hit; of segments met at the same distance, the first
/// listed. Every segment tested: what [`SegmentGrid::cast`] must find.
#[cfg(test)]
fn cast(o: DVec2, d: DVec2, segs: &[Seg], tiny: f64) -> Option<(f64, usize, f64)> {
    let mut best: Option<(f64, usize, f64)> = None;
    for seg in segs {
        if let Some((t, s)) = meet(o, d, seg, tiny) {
            if best.is_none_or(|x| t < x.0) {
                best = Some((t, seg.2, s));
            }
        }
    }
    best
}

/// The segments on a uniform grid of about one cell per segment, each listed in every cell its
/// box overlaps once grown by `margin` (far above the rounding of a ray's walk through the
/// cells): a ray tests the segments of the cells it passes, nearest first, instead of all of
/// them (on the circle at 10⁵ points, 4000 rays against 3000 segments each).
struct SegmentGrid {
    lo: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    margin: f64,
    /// Cell c's segments are `items[start[c]..start[c + 1]]`, in list order.
    start: Vec<usize>,
    items: Vec<u32>,
}

impl SegmentGrid {
    fn new(segs: &[Seg], diam: f64) -> SegmentGrid {
        let margin = 1e-9 * diam.max(f64::MIN_POSITIVE);
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for &(a, b, _, _) in segs {
            lo = lo.min(a.min(b));
            hi = hi.max(a.max(b));
        }
        lo -= DVec2::splat(2.0 * margin);
        hi += DVec2::splat(2.0 * margin);
        let size = (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
        let cell = (size.x * size.y / segs.len().max(1) as f64)
            .sqrt()
            .max(size.max_element() / 1024.0);
        let nx = ((size.x / cell).ceil() as usize).clamp(1, 1024);
        let ny = ((size.y / cell).ceil() as usize).clamp(1, 1024);
        let mut grid = SegmentGrid {
            lo,
            cell,
            nx,
            ny,
            margin,
            start: vec![0; nx * ny + 1],
            items: Vec::new(),
        };
        let cells_of = |g: &SegmentGrid, &(a, b, _, _): &Seg| {
            let (i0, j0) = g.at(a.min(b) - DVec2::splat(margin));
            let (i1, j1) = g.at(a.max(b) + DVec2::splat(margin));
            let nx = g.nx;
            (j0..=j1).flat_map(move |j| (i0..=i1).map(move |i| j * nx + i))
        };
        for seg in segs {
            for c in cells_of(&grid, seg) {
                grid.start[c + 1] += 1;
            }
        }
        for c in 0..nx * ny {
            grid.start[c + 1] += grid.start[c];
        }
        let mut fill = grid.start.clone();
        let mut items = vec![0u32; grid.start[nx * ny]];
        for (k, seg) in segs.iter().enumerate() {
            for c in cells_of(&grid, seg) {
                items[fill[c]] = k as u32;
                fill[c] += 1;
            }
        }
        grid.items = items;
        grid
    }

    /// The cell of `p`, clamped to the grid.
    fn at(&self, p: DVec2) -> (usize, usize) {
        let q = (p - self.lo) / self.cell;
        let clamp = |x: f64, n: usize| (x.max(0.0) as usize).min(n - 1);
        (clamp(q.x, self.nx), clamp(q.y, self.ny))
    }

    /// [`cast`] through the cells the ray passes (Amanatides and Woo's walk), stopping once the
    /// nearest hit lies a margin before the next cell: the same segment, as the least
    /// (distance, list index) over the segments tested.
    fn cast(&self, o: DVec2, d: DVec2, segs: &[Seg], tiny: f64) -> Option<(f64, usize, f64)> {
        let (mut i, mut j) = self.at(o);
        let mut best: Option<(f64, u32, f64)> = None;
        // Ray parameter of the next vertical and horizontal cell side, and between sides.
        let side = |x: f64, lo: f64, k: usize, dx: f64| {
            if dx > 0.0 {
                (lo + (k + 1) as f64 * self.cell - x) / dx
            } else if dx < 0.0 {
                (lo + k as f64 * self.cell - x) / dx
            } else {
                f64::INFINITY
            }
        };
        let (mut tx, mut ty) = (side(o.x, self.lo.x, i, d.x), side(o.y, self.lo.y, j, d.y));
        let (dtx, dty) = (self.cell / d.x.abs(), self.cell / d.y.abs());
        loop {
            let c = j * self.nx + i;
            for &k in &self.items[self.start[c]..self.start[c + 1]] {
                if let Some((t, s)) = meet(o, d, &segs[k as usize], tiny) {
                    if best.is_none_or(|(bt, bk, _)| t < bt || (t == bt && k < bk)) {
                        best = Some((t, k, s));
                    }
                }
            }
            let exit = tx.min(ty);
            if best.is_some_and(|(bt, _, _)| bt + self.margin < exit) || !exit.is_finite() {
                break;
            }
            if tx <= ty {
                if (d.x > 0.0 && i + 1 == self.nx) || (d.x < 0.0 && i == 0) {
                    break;
                }
                i = if d.x > 0.0 { i + 1 } else { i - 1 };
                tx += dtx;
            } else {
                if (d.y > 0.0 && j + 1 == self.ny) || (d.y < 0.0 && j == 0) {
                    break;
                }
                j = if d.y > 0.0 { j + 1 } else { j - 1 };
                ty += dty;
            }
        }
        best.map(|(t, k, s)| (t, segs[k as usize].2, s))
    }
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

    /// The grid's walk finds the segment testing every segment finds (the same distance,
    /// ring and arc length bit for bit): from boundary points along their inward normals, as
    /// `thin_feature` casts, from their vertices (rays through segments' shared ends, met at
    /// equal distances) and from random points in random directions, on every built-in region.
    #[test]
    fn the_grid_finds_what_testing_every_segment_finds() {
        let mut rng = geometry::Rng::new(23);
        for name in Region::builtin_names() {
            let region = Region::builtin(name).unwrap();
            let diam = region.diameter();
            for tol in [1e-2, 1e-4] {
                let (segs, _, _) = segments(&region.polygonize(tol * diam));
                let grid = SegmentGrid::new(&segs, diam);
                let tiny = 1e-12 * diam;
                let (lo, hi) = region.bbox();
                let mut rays: Vec<(DVec2, DVec2)> = Vec::new();
                for &(a, b, _, _) in segs.iter().step_by(3) {
                    let dir = (b - a).normalize_or_zero();
                    rays.push((a.lerp(b, rng.uniform()), dir.perp()));
                    rays.push((a, dir.perp()));
                    rays.push((a, -dir.perp()));
                }
                for _ in 0..500 {
                    let o = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
                    rays.push((o, DVec2::from_angle(rng.range(0.0, std::f64::consts::TAU))));
                }
                for (o, d) in rays {
                    let (fast, every) = (grid.cast(o, d, &segs, tiny), cast(o, d, &segs, tiny));
                    let bits = |h: Option<(f64, usize, f64)>| {
                        h.map(|(t, r, s)| (t.to_bits(), r, s.to_bits()))
                    };
                    assert_eq!(
                        bits(fast),
                        bits(every),
                        "{name} tol {tol}: ray from {o} along {d}"
                    );
                }
            }
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
