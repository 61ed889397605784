//! Super-ellipse |x/a|^n + |y/b|^n = 1 (n ≥ 2): points, closest point, arc length, sampling.
//!
//! The angle parametrisation (cos^{2/n}, sin^{2/n}) has unbounded speed at the axes for n > 2,
//! so each quarter is split at the diagonal point (a·m, b·m), m = 2^{-1/n}, into two *graph*
//! octants: octant 0 is x = a·g(y/b) for y/b ∈ [0, m], octant 1 is y = b·g(x/a) for
//! x/a ∈ [0, m], with g(v) = (1 − vⁿ)^{1/n}. On both, 1 − vⁿ ≥ 1/2, so the parametrisation
//! is smooth and every point computed from it lies on the curve to rounding.
//!
//! The loop parameter t ∈ [0, 8] runs over the eight octants in traversal order from the
//! start point (center + (a, 0)).
use crate::numeric::integrate;
use glam::DVec2;

/// A super-ellipse with its derived constants.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SuperEllipse {
    pub c: DVec2,
    pub a: f64,
    pub b: f64,
    pub n: f64,
    pub ccw: bool,
    /// 2^{-1/n}: the diagonal point is (a·m, b·m).
    m: f64,
    /// n as an integer when it is one (fast powers).
    ni: Option<i32>,
}

/// For octant k of the loop: (canonical octant, traversed forward, sign of x, sign of y).
const OCTANTS: [(usize, bool, f64, f64); 8] = [
    (0, true, 1.0, 1.0),
    (1, true, 1.0, 1.0),
    (1, false, -1.0, 1.0),
    (0, false, -1.0, 1.0),
    (0, true, -1.0, -1.0),
    (1, true, -1.0, -1.0),
    (1, false, 1.0, -1.0),
    (0, false, 1.0, -1.0),
];

/// Samples per canonical octant for the global stage of the closest-point search.
const SAMPLES: usize = 8;

/// The closest-point search's sample points of one curve ([`SuperEllipse::samples`]).
#[derive(Clone, Debug)]
pub(crate) struct Samples([DVec2; 2 * SAMPLES + 2]);

impl SuperEllipse {
    pub fn new(c: DVec2, a: f64, b: f64, n: f64, ccw: bool) -> Self {
        let ni = (n.fract() == 0.0 && (2.0..=64.0).contains(&n)).then_some(n as i32);
        SuperEllipse {
            c,
            a,
            b,
            n,
            ccw,
            m: 0.5f64.powf(1.0 / n),
            ni,
        }
    }

    /// vⁿ⁻² for v ≥ 0.
    #[inline]
    fn pow_nm2(&self, v: f64) -> f64 {
        match self.ni {
            Some(k) => v.powi(k - 2),
            None => v.powf(self.n - 2.0),
        }
    }

    /// s^{1/n} for s ≥ 0.
    #[inline]
    fn root(&self, s: f64) -> f64 {
        match self.ni {
            Some(2) => s.sqrt(),
            Some(4) => s.sqrt().sqrt(),
            _ => s.powf(1.0 / self.n),
        }
    }

    /// g(v) = (1 − vⁿ)^{1/n}, g'(v), g''(v).
    #[inline]
    fn g3(&self, v: f64) -> (f64, f64, f64) {
        let vn2 = self.pow_nm2(v);
        let vn1 = vn2 * v;
        let s = 1.0 - vn1 * v;
        let g = self.root(s);
        let g1 = -vn1 * g / s;
        let g2 = -(self.n - 1.0) * vn2 * g / (s * s);
        (g, g1, g2)
    }

    #[inline]
    fn g(&self, v: f64) -> f64 {
        let vn = self.pow_nm2(v) * v * v;
        self.root(1.0 - vn)
    }

    /// Point of canonical octant `o` (first quadrant, relative to the centre) at u ∈ [0, 1].
    #[inline]
    fn canon(&self, o: usize, u: f64) -> DVec2 {
        if o == 0 {
            let v = self.m * u;
            DVec2::new(self.a * self.g(v), self.b * v)
        } else {
            let w = self.m * (1.0 - u);
            DVec2::new(self.a * w, self.b * self.g(w))
        }
    }

    /// Point, first and second derivative in u of canonical octant `o`.
    #[inline]
    fn canon3(&self, o: usize, u: f64) -> (DVec2, DVec2, DVec2) {
        let m = self.m;
        if o == 0 {
            let v = m * u;
            let (g, g1, g2) = self.g3(v);
            (
                DVec2::new(self.a * g, self.b * v),
                DVec2::new(m * self.a * g1, m * self.b),
                DVec2::new(m * m * self.a * g2, 0.0),
            )
        } else {
            let w = m * (1.0 - u);
            let (g, g1, g2) = self.g3(w);
            (
                DVec2::new(self.a * w, self.b * g),
                DVec2::new(-m * self.a, -m * self.b * g1),
                DVec2::new(0.0, m * m * self.b * g2),
            )
        }
    }

    /// Speed |dP/du| in canonical octant `o`.
    fn speed(&self, o: usize, u: f64) -> f64 {
        self.canon3(o, u).1.length()
    }

    /// Maps a first-quadrant canonical point to the actual plane point for loop octant k.
    #[inline]
    fn place(&self, k: usize, q: DVec2) -> DVec2 {
        let (_, _, sx, sy) = OCTANTS[k];
        let sy = if self.ccw { sy } else { -sy };
        self.c + DVec2::new(sx * q.x, sy * q.y)
    }

    /// The point at loop parameter t ∈ [0, 8].
    pub fn point(&self, t: f64) -> DVec2 {
        let t = t.clamp(0.0, 8.0);
        let k = (t.floor() as usize).min(7);
        let f = t - k as f64;
        let (o, fwd, _, _) = OCTANTS[k];
        self.place(k, self.canon(o, if fwd { f } else { 1.0 - f }))
    }

    /// Length of canonical octant `o`.
    fn octant_length(&self, o: usize) -> f64 {
        self.partial(o, 1.0)
    }

    /// Arc length of canonical octant `o` from u = 0 to u.
    fn partial(&self, o: usize, u: f64) -> f64 {
        let tol = 1e-15 * (self.a + self.b);
        integrate(|s| self.speed(o, s), 0.0, u, tol)
    }

    /// Total length.
    pub fn length(&self) -> f64 {
        4.0 * (self.octant_length(0) + self.octant_length(1))
    }

    /// Lengths of the two canonical octants (what `arc_length_with` needs).
    pub fn octant_lengths(&self) -> (f64, f64) {
        (self.octant_length(0), self.octant_length(1))
    }

    /// Arc length from the start to loop parameter t.
    pub fn arc_length(&self, t: f64) -> f64 {
        self.arc_length_with(t, self.octant_lengths())
    }

    /// Arc length from the start to loop parameter t, given `octant_lengths()`.
    pub fn arc_length_with(&self, t: f64, (l0, l1): (f64, f64)) -> f64 {
        let t = t.clamp(0.0, 8.0);
        let k = (t.floor() as usize).min(7);
        let f = t - k as f64;
        let whole = |o: usize| if o == 0 { l0 } else { l1 };
        let before: f64 = OCTANTS[..k].iter().map(|&(o, ..)| whole(o)).sum();
        let (o, fwd, _, _) = OCTANTS[k];
        let within = if fwd {
            self.partial(o, f)
        } else {
            whole(o) - self.partial(o, 1.0 - f)
        };
        before + within
    }

    /// Area 4ab Γ(1+1/n)² / Γ(1+2/n).
    pub fn area(&self) -> f64 {
        let g1 = crate::numeric::gamma(1.0 + 1.0 / self.n);
        4.0 * self.a * self.b * g1 * g1 / crate::numeric::gamma(1.0 + 2.0 / self.n)
    }

    /// |x/a|ⁿ + |y/b|ⁿ − 1 (negative inside).
    pub fn implicit(&self, p: DVec2) -> f64 {
        let r = p - self.c;
        (r.x / self.a).abs().powf(self.n) + (r.y / self.b).abs().powf(self.n) - 1.0
    }

    /// The points of the closest-point search's global stage: both canonical octants of the
    /// first quadrant at u = i / SAMPLES.
    pub fn samples(&self) -> Samples {
        let mut s = [DVec2::ZERO; 2 * SAMPLES + 2];
        for o in 0..2 {
            for i in 0..=SAMPLES {
                s[o * (SAMPLES + 1) + i] = self.canon(o, i as f64 / SAMPLES as f64);
            }
        }
        Samples(s)
    }

    /// Nearest point to p: (point, squared distance, loop parameter t).
    pub fn closest(&self, p: DVec2) -> (DVec2, f64, f64) {
        self.closest_sampled(p, &self.samples())
    }

    /// [`closest`](Self::closest) with the curve's `samples()` made beforehand: a curve
    /// queried many times makes them once (each costs two powers at a non-integer exponent).
    pub fn closest_sampled(&self, p: DVec2, samples: &Samples) -> (DVec2, f64, f64) {
        let mut r = p - self.c;
        if !self.ccw {
            r.y = -r.y;
        }
        let (sx, sy) = (r.x >= 0.0, r.y >= 0.0);
        let q = r.abs();
        // Global stage: samples along both canonical octants of the first quadrant (the
        // nearest point of a point in the closed first quadrant lies in it, by symmetry).
        let d = samples.0.map(|s| (s - q).length_squared());
        // Local minima of the sampled squared distance, best first (up to three).
        let nseq = d.len();
        let mut minima: Vec<usize> = (0..nseq)
            .filter(|&j| (j == 0 || d[j] <= d[j - 1]) && (j + 1 == nseq || d[j] <= d[j + 1]))
            .collect();
        minima.sort_by(|&x, &y| d[x].total_cmp(&d[y]));
        minima.truncate(3);
        let h = 1.0 / SAMPLES as f64;
        let mut best = (f64::INFINITY, 0usize, 0.0f64, DVec2::ZERO);
        let mut consider = |o: usize, lo: f64, mid: f64, hi: f64| {
            let (u, pt, d2) = self.refine(o, lo, mid, hi, q);
            if d2 < best.0 {
                best = (d2, o, u, pt);
            }
        };
        for j in minima {
            let (o, i) = (j / (SAMPLES + 1), j % (SAMPLES + 1));
            let u = i as f64 * h;
            consider(o, (u - h).max(0.0), u, (u + h).min(1.0));
            // The diagonal point ends octant 0 and starts octant 1: look on both sides.
            if o == 0 && i == SAMPLES {
                consider(1, 0.0, 0.0, h);
            }
            if o == 1 && i == 0 {
                consider(0, 1.0 - h, 1.0, 1.0);
            }
        }
        let (d2, o, u, pt) = best;
        // Back to the loop: which octant k holds this quadrant's canonical octant o.
        let k = match (sx, sy, o) {
            (true, true, 0) => 0,
            (true, true, _) => 1,
            (false, true, 1) => 2,
            (false, true, _) => 3,
            (false, false, 0) => 4,
            (false, false, _) => 5,
            (true, false, 1) => 6,
            (true, false, _) => 7,
        };
        let fwd = OCTANTS[k].1;
        let t = k as f64 + if fwd { u } else { 1.0 - u };
        let mut rel = DVec2::new(if sx { pt.x } else { -pt.x }, if sy { pt.y } else { -pt.y });
        if !self.ccw {
            rel.y = -rel.y;
        }
        (self.c + rel, d2, t)
    }

    /// Minimises |P(u) − q|² near the sample `mid` in canonical octant o, where
    /// d(mid) ≤ d(lo) and d(mid) ≤ d(hi), so [lo, hi] holds a local minimum. Safeguarded
    /// Newton on the derivative, falling back to the octant's end (once) or golden-section
    /// steps, keeps that bracket; a short Newton step is taken even where rounding hides its
    /// gain. Returns (u, point, squared distance).
    fn refine(&self, o: usize, lo: f64, mid: f64, hi: f64, q: DVec2) -> (f64, DVec2, f64) {
        let (mut a, mut b, mut x) = (lo, hi, mid);
        // The point and its derivatives at x, kept until x moves: each evaluation costs two
        // powers at a non-integer exponent.
        let mut at_x = self.canon3(o, x);
        let mut fx = (at_x.0 - q).length_squared();
        let (mut tried_lo, mut tried_hi) = (false, false);
        for _ in 0..100 {
            let (p, d1, d2) = at_x;
            let r = p - q;
            let (f1, f2) = (r.dot(d1), d1.length_squared() + r.dot(d2));
            // At an end of the octant with the distance growing inwards: that end is it.
            if (x <= lo && f1 >= 0.0) || (x >= hi && f1 <= 0.0) {
                break;
            }
            let newton = if f2 > 0.0 { x - f1 / f2 } else { f64::NAN };
            let newton_ok = newton > a && newton < b;
            let trial = if newton_ok {
                newton
            } else if f1 < 0.0 && b == hi && !tried_hi {
                // The distance falls toward an end of the octant past Newton's reach: try the
                // end itself once (a nearest point at the diagonal point or on an axis is
                // common, and golden sections would only creep toward it).
                tried_hi = true;
                hi
            } else if f1 > 0.0 && a == lo && !tried_lo {
                tried_lo = true;
                lo
            } else if x - a > b - x {
                x - 0.381_966_011_250_105 * (x - a)
            } else {
                x + 0.381_966_011_250_105 * (b - x)
            };
            if trial == x || b - a <= 1e-15 {
                break;
            }
            let at_trial = self.canon3(o, trial);
            let ft = (at_trial.0 - q).length_squared();
            let tiny = newton_ok && (trial - x).abs() < 1e-14;
            if ft <= fx {
                if trial < x {
                    b = x;
                } else {
                    a = x;
                }
                (x, at_x, fx) = (trial, at_trial, ft);
            } else if newton_ok && (trial - x).abs() < 1e-6 {
                // Newton's steps shrink quadratically, and one this short changes the squared
                // distance by less than its rounding: the comparison says nothing, the step
                // is the more accurate point, and the next would be below resolution.
                (x, at_x, fx) = (trial, at_trial, ft);
                break;
            } else if trial < x {
                a = trial;
            } else {
                b = trial;
            }
            if tiny {
                break;
            }
        }
        (x, at_x.0, fx)
    }

    /// Points from the start round to the start (inclusive) with chord error ≤ tol.
    pub fn polygonize(&self, tol: f64) -> Vec<DVec2> {
        let mut out = vec![self.point(0.0)];
        for (k, &(o, fwd, _, _)) in OCTANTS.iter().enumerate() {
            // Sample the canonical octant adaptively, then walk it in traversal order.
            let mut us = vec![0.0];
            self.subdivide(o, 0.0, 1.0, tol, 0, &mut us);
            if !fwd {
                us.reverse();
            }
            for &u in &us[1..] {
                out.push(self.place(k, self.canon(o, u)));
            }
        }
        // Close exactly on the start point.
        let first = out[0];
        if let Some(last) = out.last_mut() {
            *last = first;
        }
        out
    }

    fn subdivide(&self, o: usize, u0: f64, u1: f64, tol: f64, depth: u32, us: &mut Vec<f64>) {
        let (p0, p1) = (self.canon(o, u0), self.canon(o, u1));
        let dev = (1..6)
            .map(|i| {
                let p = self.canon(o, u0 + (u1 - u0) * i as f64 / 6.0);
                crate::predicates::closest_on_segment(p0, p1, p).2.sqrt()
            })
            .fold(0.0, f64::max);
        if (dev <= tol && depth >= 1) || depth >= 40 {
            us.push(u1);
        } else {
            let m = 0.5 * (u0 + u1);
            self.subdivide(o, u0, m, tol, depth + 1, us);
            self.subdivide(o, m, u1, tol, depth + 1, us);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_lie_on_the_curve_and_octants_join() {
        for &(a, b, n) in &[
            (1.0, 1.0, 4.0),
            (2.0, 0.5, 2.0),
            (1.0, 3.0, 2.5),
            (0.5, 0.5, 10.0),
        ] {
            for ccw in [true, false] {
                let s = SuperEllipse::new(DVec2::new(0.3, -0.2), a, b, n, ccw);
                for i in 0..=160 {
                    let t = i as f64 / 20.0;
                    let p = s.point(t);
                    assert!(
                        s.implicit(p).abs() < 1e-14,
                        "{a} {b} {n} t={t}: {}",
                        s.implicit(p)
                    );
                }
                for k in 1..8 {
                    let (l, r) = (s.point(k as f64 - 1e-12), s.point(k as f64));
                    assert!((l - r).length() < 1e-9);
                }
                assert!((s.point(8.0) - s.point(0.0)).length() < 1e-15);
            }
        }
    }

    #[test]
    fn area_and_length_of_the_paper_superellipse() {
        let s = SuperEllipse::new(DVec2::ZERO, 1.0, 1.0, 4.0, true);
        assert!((s.area() - 3.708_149_354_602_743_8).abs() < 1e-13);
        assert!(
            (s.length() - 7.017_697_943_564_042).abs() < 1e-12,
            "{}",
            s.length()
        );
        // An ellipse (n = 2): area πab.
        let e = SuperEllipse::new(DVec2::ZERO, 2.0, 0.5, 2.0, true);
        assert!((e.area() - std::f64::consts::PI).abs() < 1e-13);
        // Arc length is monotone and ends at the total.
        let mut last = -1.0;
        for i in 0..=80 {
            let l = s.arc_length(i as f64 / 10.0);
            assert!(l > last);
            last = l;
        }
        assert!((last - s.length()).abs() < 1e-12);
    }

    #[test]
    fn closest_point_beats_dense_sampling() {
        let s = SuperEllipse::new(DVec2::new(0.1, 0.2), 1.0, 0.7, 4.0, false);
        let dense: Vec<DVec2> = (0..=80_000).map(|i| s.point(i as f64 / 10_000.0)).collect();
        let mut rng = crate::rng::Rng::new(3);
        for _ in 0..200 {
            let p = DVec2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            let (q, d2, t) = s.closest(p);
            assert!(s.implicit(q).abs() < 1e-14);
            assert!((s.point(t) - q).length() < 1e-13, "t={t}");
            let best = dense
                .iter()
                .map(|x| (*x - p).length_squared())
                .fold(f64::INFINITY, f64::min);
            assert!(
                d2.sqrt() <= best.sqrt() + 1e-13,
                "{p}: {} vs {}",
                d2.sqrt(),
                best.sqrt()
            );
            // Stationarity: the offset is normal to the curve.
            let h = 1e-6;
            let tan = s.point(t + h) - s.point((t - h).max(0.0));
            if p.distance(q) > 1e-6 {
                assert!(((p - q).normalize().dot(tan.normalize())).abs() < 1e-6);
            }
        }
    }

    /// The nearest point to q (first quadrant, centre at the origin, counter-clockwise) by
    /// brute force: every sign change of the distance's derivative along both octants,
    /// bisected to the last bit, and both ends.
    fn nearest_by_bisection(s: &SuperEllipse, q: DVec2) -> DVec2 {
        let slope = |o: usize, u: f64| {
            let (p, d1, _) = s.canon3(o, u);
            (p - q).dot(d1)
        };
        let mut best = (f64::INFINITY, DVec2::ZERO);
        let mut keep = |p: DVec2| {
            if p.distance_squared(q) < best.0 {
                best = (p.distance_squared(q), p);
            }
        };
        const N: usize = 4000;
        for o in 0..2 {
            keep(s.canon(o, 0.0));
            keep(s.canon(o, 1.0));
            for i in 0..N {
                let (mut a, mut b) = (i as f64 / N as f64, (i + 1) as f64 / N as f64);
                if !(slope(o, a) < 0.0 && slope(o, b) >= 0.0) {
                    continue;
                }
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    if m <= a || m >= b {
                        break;
                    }
                    if slope(o, m) < 0.0 {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                keep(s.canon(o, a));
            }
        }
        best.1
    }

    #[test]
    fn closest_point_is_the_stationary_point_to_rounding() {
        // Near the minimum the squared distance is flat below its rounding, so a search that
        // compares values alone stalls up to ~1e-8 along the curve from the true foot.
        for &(a, b, n) in &[
            (1.0, 0.7, 4.5),
            (1.0, 1.0, 4.0),
            (0.5, 0.5, 2.5),
            (1.0, 0.6, 9.75),
        ] {
            let s = SuperEllipse::new(DVec2::ZERO, a, b, n, true);
            let samples = s.samples();
            for i in 0..=24 {
                for j in 0..=24 {
                    let p = DVec2::new(a * i as f64 / 16.0, b * j as f64 / 16.0);
                    let (q, d2, _) = s.closest_sampled(p, &samples);
                    let r = nearest_by_bisection(&s, p);
                    // Off the diagonal's ties (two feet as near), the same foot to rounding.
                    let tie = q.distance(r) > 1e-6 && d2 <= r.distance_squared(p) + 1e-15;
                    assert!(
                        q.distance(r) < 1e-12 || tie,
                        "{a} {b} {n} {p}: {q} against {r} ({:e})",
                        q.distance(r)
                    );
                }
            }
        }
    }

    #[test]
    fn closest_point_inside_beyond_the_centre_of_curvature() {
        // Inside, past the centre of curvature of the diagonal point, that point is a local
        // maximum of the distance and the nearest points lie on either side of it.
        for &(a, b, n) in &[(0.5, 0.5, 4.0), (1.0, 0.6, 6.0), (1.0, 1.0, 2.5)] {
            let s = SuperEllipse::new(DVec2::ZERO, a, b, n, false);
            let dense: Vec<DVec2> = (0..=160_000)
                .map(|i| s.point(i as f64 / 20_000.0))
                .collect();
            for i in 0..=20 {
                for j in 0..=20 {
                    let p =
                        DVec2::new(a * (i as f64 / 10.0 - 1.0), b * (j as f64 / 10.0 - 1.0)) * 0.95;
                    let (q, d2, _) = s.closest(p);
                    let best = dense
                        .iter()
                        .map(|x| x.distance(p))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        d2.sqrt() <= best + 1e-12,
                        "{a} {b} {n} {p}: {} vs {best}",
                        d2.sqrt()
                    );
                    assert!((q.distance(p) - d2.sqrt()).abs() < 1e-15);
                }
            }
        }
    }

    #[test]
    fn polygonize_respects_the_chord_tolerance() {
        let s = SuperEllipse::new(DVec2::ZERO, 1.0, 1.0, 4.0, true);
        for tol in [1e-2, 1e-4] {
            let pts = s.polygonize(tol);
            // Every dense curve point is within tol of the polyline.
            for i in 0..4000 {
                let p = s.point(i as f64 * 8.0 / 4000.0);
                let d = pts
                    .windows(2)
                    .map(|w| crate::predicates::closest_on_segment(w[0], w[1], p).2)
                    .fold(f64::INFINITY, f64::min)
                    .sqrt();
                assert!(d <= tol * 1.0001, "tol {tol}: {d}");
            }
        }
    }
}
