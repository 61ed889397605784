//! Small geometric predicates and constructions on points of the plane, shared by every crate
//! of the workspace so that each formula has exactly one implementation (and one rounding
//! behaviour: the methods compare bit-identical results across runs).
//!
//! All of them are plain floating-point formulas, not exact predicates: a result near zero
//! (an orientation, an area) carries a rounding error of the order of the machine epsilon
//! times the squared coordinates.
use glam::DVec2;

/// Twice the signed area of the triangle (a, b, c):
/// `orient(a, b, c) = (b − a) × (c − a)` (the 2D cross product, `perp_dot`).
///
/// Positive when c lies left of the directed line a → b (the triangle is counter-clockwise),
/// negative when it lies right, zero when the three points are collinear.
///
/// ```
/// use cvtmesh::geometry::{predicates::orient, DVec2};
/// let (a, b) = (DVec2::ZERO, DVec2::new(2.0, 0.0));
/// assert_eq!(orient(a, b, DVec2::new(1.0, 3.0)), 6.0);
/// assert_eq!(orient(a, b, DVec2::new(1.0, -3.0)), -6.0);
/// assert_eq!(orient(a, b, DVec2::new(5.0, 0.0)), 0.0);
/// ```
#[inline]
pub fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Signed area of the triangle (a, b, c): `½ (b − a) × (c − a)`, positive when
/// counter-clockwise (see [`orient`]).
///
/// ```
/// use cvtmesh::geometry::{predicates::triangle_signed_area, DVec2};
/// let (a, b, c) = (DVec2::ZERO, DVec2::X, DVec2::Y);
/// assert_eq!(triangle_signed_area(a, b, c), 0.5);
/// assert_eq!(triangle_signed_area(a, c, b), -0.5);
/// ```
#[inline]
pub fn triangle_signed_area(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    0.5 * orient(a, b, c)
}

/// Circumcenter of the triangle (a, b, c), the point equidistant from its three vertices.
///
/// With u = b − a, v = c − a and d = 2 u × v, it is computed relative to `a` (which keeps
/// the rounding error proportional to the triangle's size rather than to its distance from
/// the origin):
///
/// `a + ( v_y |u|² − u_y |v|² ,  u_x |v|² − v_x |u|² ) / d`.
///
/// The result is not finite when the triangle is degenerate (d = 0). The result depends on
/// which vertex comes first in the last bits only; callers that need the same bits for the
/// same triangle whatever its orientation must pass the vertices in a canonical order.
///
/// ```
/// use cvtmesh::geometry::{predicates::circumcenter, DVec2};
/// // The right triangle's circumcenter is the midpoint of its hypotenuse.
/// let c = circumcenter(DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 2.0));
/// assert_eq!(c, DVec2::new(2.0, 1.0));
/// assert!(!circumcenter(DVec2::ZERO, DVec2::X, 2.0 * DVec2::X).is_finite());
/// ```
#[inline]
pub fn circumcenter(a: DVec2, b: DVec2, c: DVec2) -> DVec2 {
    let (u, v) = (b - a, c - a);
    let d = 2.0 * u.perp_dot(v);
    let (uu, vv) = (u.length_squared(), v.length_squared());
    a + DVec2::new(v.y * uu - u.y * vv, u.x * vv - v.x * uu) / d
}

/// Signed area of a closed ring of points (the last point joins the first), by the shoelace
/// formula `½ Σᵢ pᵢ × pᵢ₊₁` (about the first point, so that a small ring far from the origin
/// keeps its precision): positive for a counter-clockwise ring, negative for a clockwise one,
/// 0 for fewer than three points.
///
/// ```
/// use cvtmesh::geometry::{predicates::ring_signed_area, DVec2};
/// let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
/// assert_eq!(ring_signed_area(&square), 1.0);
/// let mut clockwise = square;
/// clockwise.reverse();
/// assert_eq!(ring_signed_area(&clockwise), -1.0);
/// ```
pub fn ring_signed_area(points: &[DVec2]) -> f64 {
    let Some(&o) = points.first() else {
        return 0.0;
    };
    let n = points.len();
    (0..n)
        .map(|i| (points[i] - o).perp_dot(points[(i + 1) % n] - o))
        .sum::<f64>()
        * 0.5
}

/// Closest point of the segment \[a, b\] to `p`: returns (point, parameter t ∈ \[0, 1\],
/// squared distance), with t = (p − a)·(b − a) / |b − a|² clamped to \[0, 1\] (0 for a
/// degenerate segment).
///
/// When the projection is clamped, t is exactly 0 or 1 and the point is exactly `a` or `b`.
///
/// ```
/// use cvtmesh::geometry::{predicates::closest_on_segment, DVec2};
/// let (a, b) = (DVec2::ZERO, DVec2::new(4.0, 0.0));
/// assert_eq!(closest_on_segment(a, b, DVec2::new(1.0, 2.0)), (DVec2::X, 0.25, 4.0));
/// assert_eq!(closest_on_segment(a, b, DVec2::new(7.0, 4.0)), (b, 1.0, 25.0));
/// ```
#[inline]
pub fn closest_on_segment(a: DVec2, b: DVec2, p: DVec2) -> (DVec2, f64, f64) {
    let d = b - a;
    let l2 = d.length_squared();
    let t = if l2 > 0.0 { (p - a).dot(d) / l2 } else { 0.0 };
    let (q, t) = if t <= 0.0 {
        (a, 0.0)
    } else if t >= 1.0 {
        (b, 1.0)
    } else {
        (a + d * t, t)
    };
    (q, t, (p - q).length_squared())
}

/// Euclidean distance from `p` to the segment \[a, b\]: `|p − (a + t (b − a))|` with
/// t = (p − a)·(b − a) / |b − a|² clamped to \[0, 1\] (the distance to `a` when a = b).
///
/// Unlike [`closest_on_segment`] the clamped foot is computed as `a + t (b − a)` also for
/// t = 1, so the last bit may differ from `|p − b|` there; the methods' results were
/// recorded with this formula.
///
/// ```
/// use cvtmesh::geometry::{predicates::segment_distance, DVec2};
/// let (a, b) = (DVec2::ZERO, DVec2::new(4.0, 0.0));
/// assert_eq!(segment_distance(DVec2::new(1.0, 2.0), a, b), 2.0);
/// assert_eq!(segment_distance(DVec2::new(7.0, 4.0), a, b), 5.0);
/// assert_eq!(segment_distance(DVec2::new(3.0, 4.0), a, a), 5.0);
/// ```
#[inline]
pub fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let l2 = d.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * t)).length()
}

/// True if the segments \[a, b\] and \[c, d\] cross at a point interior to both: each
/// segment's end points lie strictly on opposite sides of the other's line,
/// `orient(a, b, c) · orient(a, b, d) < 0` and `orient(c, d, a) · orient(c, d, b) < 0`.
/// Touching (an end point on the other segment) and collinear overlap are not crossings.
///
/// ```
/// use cvtmesh::geometry::{predicates::segments_cross, DVec2};
/// let (a, b) = (DVec2::ZERO, DVec2::ONE);
/// assert!(segments_cross(a, b, DVec2::X, DVec2::Y));
/// // Meeting at an end point is not a crossing.
/// assert!(!segments_cross(a, b, DVec2::new(0.5, 0.5), DVec2::new(1.0, 0.0)));
/// ```
#[inline]
pub fn segments_cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    orient(a, b, c) * orient(a, b, d) < 0.0 && orient(c, d, a) * orient(c, d, b) < 0.0
}

/// True if the edge \[a, b\] crosses the ray from `p` in the +x direction: the edge straddles
/// the line y = p.y (one end point strictly above, the other on or below it) and meets it
/// right of `p`, at x = a.x + (p.y − a.y)(b.x − a.x)/(b.y − a.y) > p.x.
///
/// Counting half-open in y makes a ray through a vertex cross exactly one of the two edges
/// at that vertex, so the parity over a closed ring is the even-odd rule ([`point_in_ring`]).
///
/// ```
/// use cvtmesh::geometry::{predicates::edge_crosses_ray, DVec2};
/// let p = DVec2::new(0.0, 0.5);
/// assert!(edge_crosses_ray(p, DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0)));
/// assert!(!edge_crosses_ray(p, DVec2::new(-1.0, 0.0), DVec2::new(-1.0, 1.0)));
/// ```
#[inline]
pub fn edge_crosses_ray(p: DVec2, a: DVec2, b: DVec2) -> bool {
    (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)
}

/// Even-odd point-in-polygon test for one closed ring (the last point joins the first): the
/// parity of the ring's edges that cross the +x ray from `p` ([`edge_crosses_ray`]). Either
/// orientation; a point exactly on an edge may come out either way.
///
/// ```
/// use cvtmesh::geometry::{predicates::point_in_ring, DVec2};
/// let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
/// assert!(point_in_ring(DVec2::splat(0.5), &square));
/// assert!(!point_in_ring(DVec2::new(1.5, 0.5), &square));
/// ```
pub fn point_in_ring(p: DVec2, ring: &[DVec2]) -> bool {
    let n = ring.len();
    let mut inside = false;
    for i in 0..n {
        if edge_crosses_ray(p, ring[i], ring[(i + 1) % n]) {
            inside = !inside;
        }
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn point() -> impl Strategy<Value = DVec2> {
        (-100.0..100.0f64, -100.0..100.0f64).prop_map(|(x, y)| DVec2::new(x, y))
    }

    /// Three points whose triangle is not close to degenerate (area ≥ 1e-3 of the squared
    /// longest side), so that the circumcenter is well conditioned.
    fn triangle() -> impl Strategy<Value = (DVec2, DVec2, DVec2)> {
        (point(), point(), point()).prop_filter("well-shaped triangle", |&(a, b, c)| {
            let l2 = (b - a)
                .length_squared()
                .max((c - b).length_squared())
                .max((a - c).length_squared());
            l2 > 1e-6 && orient(a, b, c).abs() > 1e-3 * l2
        })
    }

    #[test]
    fn hand_computed_values() {
        let (a, b, c) = (
            DVec2::new(1.0, 1.0),
            DVec2::new(3.0, 1.0),
            DVec2::new(1.0, 5.0),
        );
        assert_eq!(orient(a, b, c), 8.0);
        assert_eq!(triangle_signed_area(a, b, c), 4.0);
        assert_eq!(circumcenter(a, b, c), DVec2::new(2.0, 3.0));
        assert_eq!(ring_signed_area(&[a, b, c]), 4.0);
        assert_eq!(ring_signed_area(&[a, b]), 0.0);
        assert_eq!(ring_signed_area(&[]), 0.0);
        // Equilateral triangle: the circumcenter is the centroid.
        let e = [DVec2::ZERO, DVec2::X, DVec2::new(0.5, 3f64.sqrt() / 2.0)];
        let g = (e[0] + e[1] + e[2]) / 3.0;
        assert!((circumcenter(e[0], e[1], e[2]) - g).length() < 1e-15);
        assert_eq!(segment_distance(DVec2::new(2.0, -3.0), a, b), 4.0);
        assert_eq!(segment_distance(DVec2::new(-2.0, 5.0), a, b), 5.0);
        assert!(!segments_cross(a, b, c, DVec2::new(3.0, 5.0)));
        assert!(segments_cross(a, DVec2::new(3.0, 5.0), b, c));
        // A ray through a vertex of the ring counts once.
        let diamond = [
            DVec2::new(0.0, -1.0),
            DVec2::X,
            DVec2::Y,
            DVec2::new(-1.0, 0.0),
        ];
        assert!(point_in_ring(DVec2::new(-0.5, 0.0), &diamond));
        assert!(!point_in_ring(DVec2::new(-1.5, 0.0), &diamond));
        assert!(!point_in_ring(DVec2::new(0.5, 0.9), &diamond));
    }

    #[test]
    fn closest_point_clamps_exactly_to_the_end_points() {
        let (a, b) = (DVec2::new(0.1, 0.7), DVec2::new(0.3, 0.9));
        let (q, t, d2) = closest_on_segment(a, b, DVec2::new(5.0, 5.0));
        assert_eq!((q, t), (b, 1.0));
        assert_eq!(d2, (DVec2::new(5.0, 5.0) - b).length_squared());
        let (q, t, _) = closest_on_segment(a, b, DVec2::new(-5.0, -5.0));
        assert_eq!((q, t), (a, 0.0));
        let (q, t, d2) = closest_on_segment(a, a, DVec2::ZERO);
        assert_eq!((q, t, d2), (a, 0.0, a.length_squared()));
    }

    proptest! {
        #[test]
        fn circumcenter_is_equidistant((a, b, c) in triangle()) {
            let o = circumcenter(a, b, c);
            let (ra, rb, rc) = (o.distance(a), o.distance(b), o.distance(c));
            let scale = a.length().max(b.length()).max(c.length()).max(ra);
            prop_assert!((ra - rb).abs() <= 1e-9 * scale, "{ra} {rb}");
            prop_assert!((ra - rc).abs() <= 1e-9 * scale, "{ra} {rc}");
            // Any vertex order gives the same point up to rounding.
            let o2 = circumcenter(b, c, a);
            prop_assert!((o - o2).length() <= 1e-9 * scale);
        }

        #[test]
        fn areas_flip_sign_with_orientation(a in point(), b in point(), c in point()) {
            prop_assert_eq!(orient(a, b, c), -orient(a, c, b));
            prop_assert_eq!(triangle_signed_area(a, b, c), -triangle_signed_area(a, c, b));
            // Another first vertex rounds differently.
            let t = triangle_signed_area(b, a, c);
            prop_assert!((triangle_signed_area(a, b, c) + t).abs() <= 1e-8, "{t}");
            let ring = [a, b, c];
            let rev = [c, b, a];
            let s = ring_signed_area(&ring);
            // Coordinates below 100: products below 1e4, rounding errors below ~1e-11.
            prop_assert!((s + ring_signed_area(&rev)).abs() <= 1e-8);
            // The shoelace ring area and the triangle area agree.
            let t = triangle_signed_area(a, b, c);
            prop_assert!((s - t).abs() <= 1e-8, "{s} vs {t}");
        }

        #[test]
        fn segment_distance_is_at_most_the_end_point_distances(
            p in point(), a in point(), b in point()
        ) {
            let d = segment_distance(p, a, b);
            prop_assert!(d <= p.distance(a) * (1.0 + 1e-12) + 1e-12);
            prop_assert!(d <= p.distance(b) * (1.0 + 1e-12) + 1e-12);
            // The closest point realises the same distance.
            let (q, t, d2) = closest_on_segment(a, b, p);
            prop_assert!((0.0..=1.0).contains(&t));
            prop_assert!((d2.sqrt() - d).abs() <= 1e-9 * (1.0 + d));
            prop_assert!((q.distance(p) - d).abs() <= 1e-9 * (1.0 + d));
            // The closest point lies on the segment, and no point of it is closer.
            prop_assert!(q.distance(a.lerp(b, t)) <= 1e-9 * (1.0 + a.distance(b)));
            for k in 0..=16 {
                let r = a.lerp(b, f64::from(k) / 16.0);
                prop_assert!(d <= r.distance(p) * (1.0 + 1e-12) + 1e-12);
            }
        }

        #[test]
        fn everything_is_invariant_under_translation(
            (a, b, c) in triangle(), p in point(), shift in point()
        ) {
            let scale = 1.0 + a.length() + b.length() + c.length() + p.length() + shift.length();
            let tol = 1e-9 * scale * scale;
            let (a2, b2, c2, p2) = (a + shift, b + shift, c + shift, p + shift);
            prop_assert!((orient(a, b, c) - orient(a2, b2, c2)).abs() <= tol);
            prop_assert!(
                (ring_signed_area(&[a, b, c, p]) - ring_signed_area(&[a2, b2, c2, p2])).abs()
                    <= tol
            );
            let o = circumcenter(a, b, c);
            prop_assert!((o + shift - circumcenter(a2, b2, c2)).length() <= 1e-9 * scale * 10.0);
            prop_assert!(
                (segment_distance(p, a, b) - segment_distance(p2, a2, b2)).abs() <= 1e-9 * scale
            );
        }
    }
}
