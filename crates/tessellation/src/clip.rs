//! Geometric kernels: Sutherland–Hodgman passes, segment clipping, and the moments of
//! triangles fanned from an origin (exact polynomial formulas, or a degree-5 rule for ρ).
use geometry::{DVec2, Density};

/// Integrals over a signed region, in coordinates relative to an origin o:
/// ∫1, ∫x, ∫y, ∫x², ∫xy, ∫y², and with the density ∫ρ, ∫ρx, ∫ρy, ∫ρ|x|².
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Mom {
    pub a: f64,
    pub sx: f64,
    pub sy: f64,
    pub sxx: f64,
    pub sxy: f64,
    pub syy: f64,
    pub m: f64,
    pub mx: f64,
    pub my: f64,
    pub mr2: f64,
}

impl Mom {
    /// The geometric moments with the ρ-moments of a constant density `rho` filled in.
    pub fn with_density(mut self, rho: f64) -> Mom {
        self.m = rho * self.a;
        self.mx = rho * self.sx;
        self.my = rho * self.sy;
        self.mr2 = rho * (self.sxx + self.syy);
        self
    }
}

impl std::ops::AddAssign for Mom {
    fn add_assign(&mut self, o: Mom) {
        self.a += o.a;
        self.sx += o.sx;
        self.sy += o.sy;
        self.sxx += o.sxx;
        self.sxy += o.sxy;
        self.syy += o.syy;
        self.m += o.m;
        self.mx += o.mx;
        self.my += o.my;
        self.mr2 += o.mr2;
    }
}

impl std::ops::Sub for Mom {
    type Output = Mom;
    fn sub(self, o: Mom) -> Mom {
        self + o * -1.0
    }
}

impl std::ops::Add for Mom {
    type Output = Mom;
    fn add(mut self, o: Mom) -> Mom {
        self += o;
        self
    }
}

impl std::ops::Mul<f64> for Mom {
    type Output = Mom;
    fn mul(self, k: f64) -> Mom {
        Mom {
            a: self.a * k,
            sx: self.sx * k,
            sy: self.sy * k,
            sxx: self.sxx * k,
            sxy: self.sxy * k,
            syy: self.syy * k,
            m: self.m * k,
            mx: self.mx * k,
            my: self.my * k,
            mr2: self.mr2 * k,
        }
    }
}

/// Radon's 7-point rule, exact for polynomials of degree 5 on a triangle: barycentric points
/// (as (λ1, λ2) for the two non-origin corners) and weights summing to 1.
const RULE: [(f64, f64, f64); 7] = {
    // √15 to f64 precision; a1 = (6 − √15)/21, b1 = (9 + 2√15)/21, a2 = (6 + √15)/21,
    // b2 = (9 − 2√15)/21, weights (155 ∓ √15)/1200.
    const R15: f64 = 3.872_983_346_207_417;
    const A1: f64 = (6.0 - R15) / 21.0;
    const B1: f64 = (9.0 + 2.0 * R15) / 21.0;
    const W1: f64 = (155.0 - R15) / 1200.0;
    const A2: f64 = (6.0 + R15) / 21.0;
    const B2: f64 = (9.0 - 2.0 * R15) / 21.0;
    const W2: f64 = (155.0 + R15) / 1200.0;
    [
        (1.0 / 3.0, 1.0 / 3.0, 9.0 / 40.0),
        (A1, A1, W1),
        (A1, B1, W1),
        (B1, A1, W1),
        (A2, A2, W2),
        (A2, B2, W2),
        (B2, A2, W2),
    ]
};

/// Moments of the triangles (o, p, q) fanned from an origin o; p, q relative to o.
#[derive(Clone, Copy)]
pub(crate) struct Fan<'a> {
    /// Absolute origin (where ρ is evaluated from).
    pub origin: DVec2,
    /// `None` for ρ ≡ 1 (only the geometric moments are computed).
    pub density: Option<&'a Density>,
    /// Integrate ρ on the four half-size triangles of each fan triangle (cells that reach
    /// the boundary, where a size field toward a loop changes ρ most across a cell).
    pub fine: bool,
    /// ρ's value where it is known to be this constant over every triangle of the fan (a size
    /// field's plateau): the ρ-moments are then that multiple of the exact ones, no rule.
    pub constant: Option<f64>,
}

impl Fan<'_> {
    /// Signed moments of the triangle (o, p, q).
    #[inline]
    pub fn tri(&self, p: DVec2, q: DVec2) -> Mom {
        const SIXTH: f64 = 1.0 / 6.0;
        const TWELFTH: f64 = 1.0 / 12.0;
        const TWENTYFOURTH: f64 = 1.0 / 24.0;
        let cr = p.perp_dot(q);
        let mut m = Mom {
            a: 0.5 * cr,
            sx: cr * (p.x + q.x) * SIXTH,
            sy: cr * (p.y + q.y) * SIXTH,
            sxx: cr * (p.x * p.x + p.x * q.x + q.x * q.x) * TWELFTH,
            sxy: cr * (2.0 * p.x * p.y + p.x * q.y + q.x * p.y + 2.0 * q.x * q.y) * TWENTYFOURTH,
            syy: cr * (p.y * p.y + p.y * q.y + q.y * q.y) * TWELFTH,
            ..Mom::default()
        };
        if let Some(c) = self.constant.filter(|_| self.density.is_some()) {
            return m.with_density(c);
        }
        if let Some(rho) = self.density {
            let area = 0.5 * cr;
            if area != 0.0 {
                if self.fine {
                    // The four halves-of-sides triangles, each with a quarter of the area.
                    let (hp, hq, hpq) = (0.5 * p, 0.5 * q, 0.5 * (p + q));
                    for (a, b, c) in [
                        (DVec2::ZERO, hp, hq),
                        (hp, p, hpq),
                        (hq, hpq, q),
                        (hpq, hq, hp),
                    ] {
                        self.rule(rho, a, b - a, c - a, 0.25 * area, &mut m);
                    }
                } else {
                    self.rule(rho, DVec2::ZERO, p, q, area, &mut m);
                }
            }
        }
        m
    }

    /// The ρ-moments of the triangle (a, a + u, a + v) of signed area `area` by [`RULE`].
    #[inline]
    fn rule(&self, rho: &Density, a: DVec2, u: DVec2, v: DVec2, area: f64, m: &mut Mom) {
        let xs = RULE.map(|(l1, l2, _)| a + u * l1 + v * l2);
        let rhos = rho.at7(&xs.map(|x| self.origin + x));
        for ((&(_, _, w), x), rho) in RULE.iter().zip(xs).zip(rhos) {
            let r = rho * w * area;
            m.m += r;
            m.mx += r * x.x;
            m.my += r * x.y;
            m.mr2 += r * x.length_squared();
        }
    }

    /// Moments of a closed polygon (signed by orientation).
    pub fn polygon(&self, pts: &[DVec2]) -> Mom {
        let mut m = Mom::default();
        let Some(&last) = pts.last() else { return m };
        let mut p = last;
        for &q in pts {
            m += self.tri(p, q);
            p = q;
        }
        m
    }
}

#[inline]
fn cut(p: DVec2, q: DVec2, fp: f64, fq: f64) -> DVec2 {
    p + (q - p) * (fp / (fp - fq))
}

/// One Sutherland–Hodgman pass of a closed polygon: keep where `f ≥ 0`.
pub(crate) fn clip_closed(input: &[DVec2], out: &mut Vec<DVec2>, f: impl Fn(DVec2) -> f64) {
    out.clear();
    let Some(&last) = input.last() else { return };
    let (mut p, mut fp) = (last, f(last));
    for &q in input {
        let fq = f(q);
        clip_edge(out, p, q, fp, fq);
        (p, fp) = (q, fq);
    }
}

/// One Sutherland–Hodgman pass of an open polyline: keep where `f ≥ 0`. Outside stretches
/// between an exit and the next entry become the straight segment joining them (on f = 0).
pub(crate) fn clip_open(input: &[DVec2], out: &mut Vec<DVec2>, f: impl Fn(DVec2) -> f64) {
    out.clear();
    let Some(&first) = input.first() else { return };
    let (mut p, mut fp) = (first, f(first));
    if fp >= 0.0 {
        out.push(p);
    }
    for &q in &input[1..] {
        let fq = f(q);
        clip_edge(out, p, q, fp, fq);
        (p, fp) = (q, fq);
    }
}

/// The Sutherland–Hodgman step for the edge p → q (f values `fp`, `fq`), p already handled:
/// push the crossing with f = 0 if the edge crosses it, then q if it is kept.
#[inline]
fn clip_edge(out: &mut Vec<DVec2>, p: DVec2, q: DVec2, fp: f64, fq: f64) {
    if fq >= 0.0 {
        if fp < 0.0 {
            out.push(cut(p, q, fp, fq));
        }
        out.push(q);
    } else if fp >= 0.0 {
        out.push(cut(p, q, fp, fq));
    }
}

/// Inside function of the edge u → v of a CCW convex polygon (≥ 0 on the left).
#[inline]
pub(crate) fn edge_fn(u: DVec2, v: DVec2) -> impl Fn(DVec2) -> f64 {
    let d = v - u;
    move |p| d.perp_dot(p - u)
}

/// Clip the segment a → b to the CCW convex polygon `k` grown by `tol` (a length):
/// the parameter interval [t0, t1] inside, or `None`.
pub(crate) fn clip_segment(a: DVec2, b: DVec2, k: &[DVec2], tol: f64) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let n = k.len();
    for i in 0..n {
        let (u, v) = (k[i], k[(i + 1) % n]);
        let d = v - u;
        let slack = tol * d.length();
        let fa = d.perp_dot(a - u) + slack;
        let fb = d.perp_dot(b - u) + slack;
        if fa < 0.0 && fb < 0.0 {
            return None;
        }
        if fa < 0.0 {
            t0 = t0.max(fa / (fa - fb));
        } else if fb < 0.0 {
            t1 = t1.min(fa / (fa - fb));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Signed angle from u to w, in (−π, π].
#[inline]
pub(crate) fn angle(u: DVec2, w: DVec2) -> f64 {
    u.perp_dot(w).atan2(u.dot(w))
}

/// Does the closed segment a–b meet the closed box [lo, hi]?
///
/// ```
/// use cvtmesh::tessellation::segment_meets_box;
/// use cvtmesh::geometry::DVec2;
/// let (lo, hi) = (DVec2::ZERO, DVec2::ONE);
/// assert!(segment_meets_box(DVec2::new(-1.0, 0.5), DVec2::new(2.0, 0.5), lo, hi));
/// // Beside a corner: the bounding boxes overlap, the segment does not meet the box.
/// assert!(!segment_meets_box(DVec2::new(0.5, 2.0), DVec2::new(2.0, 0.5), lo, hi));
/// ```
pub fn segment_meets_box(a: DVec2, b: DVec2, lo: DVec2, hi: DVec2) -> bool {
    if a.x.max(b.x) < lo.x || a.x.min(b.x) > hi.x || a.y.max(b.y) < lo.y || a.y.min(b.y) > hi.y {
        return false;
    }
    // The box lies on one side of the segment's line iff all four corners do.
    let d = b - a;
    let s = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)].map(|c| d.perp_dot(c - a));
    !(s.iter().all(|&v| v > 0.0) || s.iter().all(|&v| v < 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn factorial(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    fn binomial(n: u32, k: u32) -> f64 {
        factorial(n) / (factorial(k) * factorial(n - k))
    }

    /// Exact ∫ x^i y^j over the triangle (0, p, q): expand in barycentrics and use
    /// ∫ λ1^α λ2^β dA = 2·area·α!β!/(α+β+2)!.
    fn exact_monomial(p: DVec2, q: DVec2, i: u32, j: u32) -> f64 {
        let area = 0.5 * p.perp_dot(q);
        let mut sum = 0.0;
        for a in 0..=i {
            for b in 0..=j {
                // (λ1 p.x + λ2 q.x)^i (λ1 p.y + λ2 q.y)^j: take λ1^a of the first, λ1^b of the second.
                let coef = binomial(i, a)
                    * p.x.powi(a as i32)
                    * q.x.powi((i - a) as i32)
                    * binomial(j, b)
                    * p.y.powi(b as i32)
                    * q.y.powi((j - b) as i32);
                let (al, be) = (a + b, i - a + j - b);
                sum += coef * factorial(al) * factorial(be) / factorial(al + be + 2);
            }
        }
        2.0 * area * sum
    }

    #[test]
    fn radon_rule_is_exact_to_degree_five() {
        let (p, q) = (DVec2::new(1.3, 0.2), DVec2::new(0.4, 0.9));
        for i in 0..=5u32 {
            for j in 0..=(5 - i) {
                let rho = Density::Function(Arc::new(move |x: DVec2| {
                    x.x.powi(i as i32) * x.y.powi(j as i32)
                }));
                let got = Fan {
                    origin: DVec2::ZERO,
                    density: Some(&rho),
                    fine: false,
                    constant: None,
                }
                .tri(p, q)
                .m;
                let exact = exact_monomial(p, q, i, j);
                assert!((got - exact).abs() < 1e-14, "x^{i} y^{j}: {got} vs {exact}");
            }
        }
        // Degree 6 is not integrated exactly (the rule is not of higher order than claimed).
        let rho = Density::Function(Arc::new(|x: DVec2| x.x.powi(6)));
        let got = Fan {
            origin: DVec2::ZERO,
            density: Some(&rho),
            fine: false,
            constant: None,
        }
        .tri(p, q)
        .m;
        assert!((got - exact_monomial(p, q, 6, 0)).abs() > 1e-6);
    }

    #[test]
    fn uniform_moments_of_unit_square() {
        let sq = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        let m = Fan {
            origin: DVec2::ZERO,
            density: None,
            fine: false,
            constant: None,
        }
        .polygon(&sq);
        assert!((m.a - 1.0).abs() < 1e-15);
        assert!((m.sx - 0.5).abs() < 1e-15 && (m.sy - 0.5).abs() < 1e-15);
        assert!((m.sxx - 1.0 / 3.0).abs() < 1e-15 && (m.syy - 1.0 / 3.0).abs() < 1e-15);
        assert!((m.sxy - 0.25).abs() < 1e-15);
        // Density 1 by quadrature agrees with the exact moments.
        let one = Density::Function(Arc::new(|_| 1.0));
        let q = Fan {
            origin: DVec2::ZERO,
            density: Some(&one),
            fine: false,
            constant: None,
        }
        .polygon(&sq);
        assert!((q.m - 1.0).abs() < 1e-14 && (q.mx - 0.5).abs() < 1e-14);
        assert!((q.mr2 - 2.0 / 3.0).abs() < 1e-14);
        // A density known to be 3 there: three times the exact moments, the rule not read.
        let wrong = Density::Function(Arc::new(|_| f64::NAN));
        let c = Fan {
            origin: DVec2::ZERO,
            density: Some(&wrong),
            fine: true,
            constant: Some(3.0),
        }
        .polygon(&sq);
        assert_eq!((c.m, c.mx, c.my, c.mr2), (3.0, 1.5, 1.5, 2.0));
        assert_eq!((c.a, c.sx, c.sxx), (m.a, m.sx, m.sxx));
    }

    #[test]
    fn segment_clipping_and_box_test() {
        let k = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        let (t0, t1) = clip_segment(DVec2::new(-1.0, 0.5), DVec2::new(3.0, 0.5), &k, 0.0).unwrap();
        assert!((t0 - 0.25).abs() < 1e-15 && (t1 - 0.5).abs() < 1e-15);
        assert!(clip_segment(DVec2::new(-1.0, 2.0), DVec2::new(3.0, 2.0), &k, 0.0).is_none());
        assert!(clip_segment(
            DVec2::new(-1.0, 1.0 + 1e-12),
            DVec2::new(3.0, 1.0 + 1e-12),
            &k,
            1e-9
        )
        .is_some());
        assert!(segment_meets_box(
            DVec2::new(-0.5, 1.0),
            DVec2::new(1.0, -0.5),
            DVec2::ZERO,
            DVec2::ONE
        ));
        assert!(!segment_meets_box(
            DVec2::new(-1.0, 0.5),
            DVec2::new(0.4, -1.0),
            DVec2::ZERO,
            DVec2::ONE
        ));
    }
}
