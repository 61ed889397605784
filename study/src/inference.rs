//! Inference over seeds: Student-t confidence intervals, the Friedman test, Wilcoxon
//! signed-rank tests and Holm's step-down correction, with the special functions they need
//! (log-gamma, regularized incomplete gamma and beta, the normal, t and χ² distributions).
//!
//! Written here rather than taken from a crate so that every number in the study's report
//! can be traced to code the tests check against published reference values.

const EPS: f64 = 1e-15;
const TINY: f64 = 1e-300;
const MAX_ITER: usize = 10_000;

/// ln Γ(x) for x > 0: the geometry crate's Lanczos approximation (about 15 significant digits).
pub use cvtmesh::geometry::ln_gamma;

/// The regularized lower incomplete gamma function P(a, x) = γ(a, x) / Γ(a), a > 0, x ≥ 0.
pub fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x.is_infinite() {
        return 1.0;
    }
    if x < a + 1.0 {
        gamma_series(a, x)
    } else {
        1.0 - gamma_cf(a, x)
    }
}

/// The regularized upper incomplete gamma function Q(a, x) = 1 − P(a, x), computed directly
/// in the upper tail so that small survival probabilities keep their relative precision.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    if x.is_infinite() {
        return 0.0;
    }
    if x < a + 1.0 {
        1.0 - gamma_series(a, x)
    } else {
        gamma_cf(a, x)
    }
}

fn gamma_prefactor(a: f64, x: f64) -> f64 {
    (-x + a * x.ln() - ln_gamma(a)).exp()
}

/// P(a, x) by its power series (converges fast for x < a + 1).
fn gamma_series(a: f64, x: f64) -> f64 {
    let mut ap = a;
    let mut del = 1.0 / a;
    let mut sum = del;
    for _ in 0..MAX_ITER {
        ap += 1.0;
        del *= x / ap;
        sum += del;
        if del.abs() < sum.abs() * EPS {
            break;
        }
    }
    (sum * gamma_prefactor(a, x)).min(1.0)
}

/// One step of the modified Lentz method for a continued fraction with partial numerator
/// `an` and denominator `bn`: updates C and D (kept away from zero) and returns the factor
/// C·D that multiplies the running value.
fn lentz(an: f64, bn: f64, c: &mut f64, d: &mut f64) -> f64 {
    *d = bn + an * *d;
    if d.abs() < TINY {
        *d = TINY;
    }
    *c = bn + an / *c;
    if c.abs() < TINY {
        *c = TINY;
    }
    *d = 1.0 / *d;
    *d * *c
}

/// Q(a, x) by its continued fraction, evaluated with the modified Lentz method (x ≥ a + 1).
fn gamma_cf(a: f64, x: f64) -> f64 {
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / TINY;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..MAX_ITER {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        let del = lentz(an, b, &mut c, &mut d);
        h *= del;
        if (del - 1.0).abs() < EPS {
            break;
        }
    }
    (gamma_prefactor(a, x) * h).clamp(0.0, 1.0)
}

/// The regularized incomplete beta function I_x(a, b), a, b > 0, 0 ≤ x ≤ 1.
pub fn beta_inc(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front =
        (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    // The continued fraction converges fast on this side of the mean; use symmetry otherwise.
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_cf(a, b, x) / a
    } else {
        1.0 - front * beta_cf(b, a, 1.0 - x) / b
    }
}

fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..MAX_ITER {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        h *= lentz(aa, 1.0, &mut c, &mut d);
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        let del = lentz(aa, 1.0, &mut c, &mut d);
        h *= del;
        if (del - 1.0).abs() < EPS {
            break;
        }
    }
    h
}

/// The complementary error function erfc(x) = 2/√π ∫ₓ^∞ e^(−t²) dt, via Q(½, x²).
pub fn erfc(x: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x >= 0.0 {
        gamma_q(0.5, x * x)
    } else {
        2.0 - gamma_q(0.5, x * x)
    }
}

/// The standard normal survival function P(Z > z).
pub fn normal_sf(z: f64) -> f64 {
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// The χ² survival function P(X > x) with `df` degrees of freedom.
pub fn chi2_sf(x: f64, df: f64) -> f64 {
    gamma_q(0.5 * df, 0.5 * x)
}

/// The Student-t distribution function P(T ≤ t) with `df` > 0 degrees of freedom.
pub fn t_cdf(t: f64, df: f64) -> f64 {
    if t.is_nan() {
        return f64::NAN;
    }
    if t.is_infinite() {
        return if t > 0.0 { 1.0 } else { 0.0 };
    }
    let tail = 0.5 * beta_inc(0.5 * df, 0.5, df / (df + t * t));
    if t > 0.0 {
        1.0 - tail
    } else {
        tail
    }
}

/// The Student-t quantile: the t with P(T ≤ t) = p, for 0 < p < 1 (NaN outside).
pub fn t_quantile(p: f64, df: f64) -> f64 {
    if !(p > 0.0 && p < 1.0 && df > 0.0) {
        return f64::NAN;
    }
    if p == 0.5 {
        return 0.0;
    }
    // The distribution function is monotone: bracket, then bisect to full precision.
    let (mut lo, mut hi) = (-1.0f64, 1.0f64);
    while t_cdf(hi, df) < p {
        hi *= 2.0;
    }
    while t_cdf(lo, df) > p {
        lo *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if t_cdf(mid, df) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * mid.abs().max(1.0) {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// A mean with its two-sided Student-t confidence interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanCi {
    /// Arithmetic mean.
    pub mean: f64,
    /// Half-width of the interval: t(1 − (1 − level)/2, n − 1) · s / √n; NaN when n < 2.
    pub half_width: f64,
    /// Number of values.
    pub n: usize,
}

impl MeanCi {
    /// Lower end of the interval.
    pub fn low(&self) -> f64 {
        self.mean - self.half_width
    }
    /// Upper end of the interval.
    pub fn high(&self) -> f64 {
        self.mean + self.half_width
    }
}

/// Half-width of the `level` confidence interval of a mean from n values of sample standard
/// deviation `std`; NaN when n < 2.
pub fn ci_half_width(std: f64, n: usize, level: f64) -> f64 {
    if n < 2 {
        return f64::NAN;
    }
    if std == 0.0 {
        return 0.0;
    }
    let t = t_quantile(0.5 + 0.5 * level, (n - 1) as f64);
    t * std / (n as f64).sqrt()
}

/// The mean of `values` with its `level` (e.g. 0.95) Student-t confidence interval; `None`
/// if empty.
pub fn mean_ci(values: &[f64], level: f64) -> Option<MeanCi> {
    let s = crate::stats::mean_std(values)?;
    Some(MeanCi {
        mean: s.mean,
        half_width: ci_half_width(s.std, s.n, level),
        n: s.n,
    })
}

/// Average ranks (1-based; tied values share the mean of their ranks) and the sizes of the
/// tie groups with more than one member. Values must not be NaN (they sort last).
pub fn ranks(values: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let mut idx: Vec<usize> = (0..values.len()).collect();
    idx.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut r = vec![0.0; values.len()];
    let mut ties = Vec::new();
    let mut i = 0;
    while i < idx.len() {
        let mut j = i + 1;
        while j < idx.len() && values[idx[j]] == values[idx[i]] {
            j += 1;
        }
        // Positions i..j (0-based) share ranks i+1..=j.
        let avg = 0.5 * ((i + 1 + j) as f64);
        for &k in &idx[i..j] {
            r[k] = avg;
        }
        if j - i > 1 {
            ties.push(j - i);
        }
        i = j;
    }
    (r, ties)
}

fn tie_sum(ties: &[usize]) -> f64 {
    ties.iter().map(|&t| (t as f64).powi(3) - t as f64).sum()
}

/// Up to this many non-zero differences the Wilcoxon p-value is exact; above, normal.
pub const WILCOXON_EXACT_MAX: usize = 25;

/// Result of a Wilcoxon signed-rank test of paired samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedRank {
    /// W⁺: the sum of the ranks of |xᵢ − yᵢ| over the pairs with xᵢ > yᵢ.
    pub w_plus: f64,
    /// Number of non-zero differences (zero differences are dropped, Wilcoxon's rule).
    pub n: usize,
    /// Two-sided p-value.
    pub p_value: f64,
    /// True if `p_value` is the exact permutation probability (n ≤ [`WILCOXON_EXACT_MAX`]).
    pub exact: bool,
}

impl SignedRank {
    /// True if x tends to be below y: W⁺ is less than its null mean n(n+1)/4.
    pub fn x_lower(&self) -> bool {
        self.w_plus < (self.n * (self.n + 1)) as f64 / 4.0
    }
}

/// The difference x − y as a rank test sees it: equal values (infinities too) give 0, and an
/// infinite value against a finite one gives an infinite difference of the right sign.
fn difference(x: f64, y: f64) -> f64 {
    if x == y {
        0.0
    } else {
        x - y
    }
}

/// Two-sided Wilcoxon signed-rank test of the pairs (xᵢ, yᵢ). Zero differences are dropped;
/// tied |differences| get average ranks. Up to [`WILCOXON_EXACT_MAX`] non-zero differences the
/// p-value is exact: every assignment of signs to the (average) ranks is counted, so ties are
/// handled exactly, not approximately. Above, the normal approximation with the tie-corrected
/// variance and no continuity correction (scipy's `wilcoxon(..., correction=False)`).
/// `None` if the lengths differ or a difference is NaN.
pub fn wilcoxon(x: &[f64], y: &[f64]) -> Option<SignedRank> {
    if x.len() != y.len() {
        return None;
    }
    let d: Vec<f64> = x.iter().zip(y).map(|(&a, &b)| difference(a, b)).collect();
    if d.iter().any(|v| v.is_nan()) {
        return None;
    }
    let d: Vec<f64> = d.into_iter().filter(|&v| v != 0.0).collect();
    let n = d.len();
    if n == 0 {
        return Some(SignedRank {
            w_plus: 0.0,
            n: 0,
            p_value: 1.0,
            exact: true,
        });
    }
    let abs: Vec<f64> = d.iter().map(|v| v.abs()).collect();
    let (r, ties) = ranks(&abs);
    let w_plus: f64 = d
        .iter()
        .zip(&r)
        .filter(|(v, _)| **v > 0.0)
        .map(|(_, r)| r)
        .sum();
    if n <= WILCOXON_EXACT_MAX {
        // Average ranks are multiples of ½: count sign assignments by doubled rank sum.
        let doubled: Vec<usize> = r.iter().map(|v| (2.0 * v).round() as usize).collect();
        let total: usize = doubled.iter().sum();
        let mut count = vec![0.0f64; total + 1];
        count[0] = 1.0;
        let mut reach = 0;
        for &w in &doubled {
            reach += w;
            for s in (w..=reach).rev() {
                count[s] += count[s - w];
            }
        }
        let all = 2f64.powi(n as i32);
        let observed = (2.0 * w_plus).round() as usize;
        let lower: f64 = count[..=observed].iter().sum::<f64>() / all;
        let upper: f64 = count[observed..].iter().sum::<f64>() / all;
        return Some(SignedRank {
            w_plus,
            n,
            p_value: (2.0 * lower.min(upper)).min(1.0),
            exact: true,
        });
    }
    let nf = n as f64;
    let mean = nf * (nf + 1.0) / 4.0;
    let var = nf * (nf + 1.0) * (2.0 * nf + 1.0) / 24.0 - tie_sum(&ties) / 48.0;
    let p_value = if var > 0.0 {
        let z = (w_plus - mean) / var.sqrt();
        (2.0 * normal_sf(z.abs())).min(1.0)
    } else {
        1.0
    };
    Some(SignedRank {
        w_plus,
        n,
        p_value,
        exact: false,
    })
}

/// Result of a Friedman test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friedman {
    /// The tie-corrected Friedman χ² statistic.
    pub statistic: f64,
    /// Degrees of freedom, k − 1.
    pub df: usize,
    /// P(χ²(k − 1) > statistic), the usual large-sample p-value.
    pub p_value: f64,
}

/// Friedman's test that k treatments (columns) are alike, from n blocks (rows) of k values:
/// each block is ranked (ties averaged), and the rank sums R_j give
/// χ² = [12 / (n k (k+1)) Σ R_j² − 3 n (k+1)] / [1 − Σ (t³ − t) / (n k (k² − 1))]
/// (scipy's `friedmanchisquare`). `None` with fewer than 2 treatments, no block, blocks of
/// unequal length or a NaN value.
pub fn friedman(blocks: &[Vec<f64>]) -> Option<Friedman> {
    let n = blocks.len();
    let k = blocks.first()?.len();
    if k < 2
        || blocks
            .iter()
            .any(|b| b.len() != k || b.iter().any(|v| v.is_nan()))
    {
        return None;
    }
    let mut sums = vec![0.0; k];
    let mut ties = 0.0;
    for b in blocks {
        let (r, t) = ranks(b);
        for (s, v) in sums.iter_mut().zip(r) {
            *s += v;
        }
        ties += tie_sum(&t);
    }
    let (nf, kf) = (n as f64, k as f64);
    let ss: f64 = sums.iter().map(|r| r * r).sum();
    let raw = 12.0 / (nf * kf * (kf + 1.0)) * ss - 3.0 * nf * (kf + 1.0);
    let denom = 1.0 - ties / (nf * kf * (kf * kf - 1.0));
    let statistic = if denom > 1e-12 {
        (raw / denom).max(0.0)
    } else {
        0.0
    };
    Some(Friedman {
        statistic,
        df: k - 1,
        p_value: chi2_sf(statistic, (k - 1) as f64),
    })
}

/// Holm's step-down adjustment of `p` (in the input order): with the p-values sorted
/// ascending, p̃₍ᵢ₎ = max over j ≤ i of min(1, (m − j + 1) p₍ⱼ₎). Rejecting p̃ < α controls the
/// family-wise error rate at α.
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut idx: Vec<usize> = (0..m).collect();
    idx.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut out = vec![0.0; m];
    let mut running: f64 = 0.0;
    for (i, &j) in idx.iter().enumerate() {
        running = running.max(((m - i) as f64 * p[j]).min(1.0));
        out[j] = running;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-300)
    }

    #[test]
    fn gamma_functions_match_known_values() {
        // Γ(5) = 24, Γ(½) = √π, Γ(0.1) = 9.513507698668732.
        assert!(close(ln_gamma(5.0), 24f64.ln(), 1e-14));
        assert!(close(
            ln_gamma(0.5),
            std::f64::consts::PI.sqrt().ln(),
            1e-13
        ));
        assert!(close(ln_gamma(0.1), 9.513_507_698_668_732f64.ln(), 1e-13));
        assert!(close(ln_gamma(100.0), 359.134_205_369_575_4, 1e-14));
        // P(1, x) = 1 − e^(−x); P(a, x) + Q(a, x) = 1 on both sides of x = a + 1.
        for x in [0.1, 1.0, 2.5, 10.0] {
            assert!(close(gamma_p(1.0, x), 1.0 - (-x).exp(), 1e-13), "{x}");
        }
        // Q(n, x) = e^(−x) Σ_{k<n} x^k / k! for whole n, on both sides of x = a + 1 (series
        // and continued fraction); Q(½, x) = erfc(√x), here from an independent value.
        assert!(close(gamma_q(3.0, 2.0), 5.0 * (-2f64).exp(), 1e-13));
        assert!(close(gamma_q(3.0, 8.0), 41.0 * (-8f64).exp(), 1e-13));
        assert!(close(gamma_q(0.5, 0.3), 0.438_578_026_080_999_9, 1e-13));
        for (a, x) in [(0.5, 0.3), (3.0, 2.0), (3.0, 8.0), (12.5, 30.0)] {
            assert!((gamma_p(a, x) + gamma_q(a, x) - 1.0).abs() < 1e-14);
        }
        // erfc(1) = 0.15729920705028513, erfc(3) = 2.209049699858544e-05.
        assert!(close(erfc(1.0), 0.157_299_207_050_285_13, 1e-13));
        assert!(close(erfc(3.0), 2.209_049_699_858_544e-5, 1e-12));
        assert!(close(erfc(-1.0), 2.0 - 0.157_299_207_050_285_13, 1e-14));
        // The normal distribution's two-sided 5 % point, from below and from above.
        assert!(close(normal_sf(-1.959_963_984_540_054), 0.975, 1e-12));
        assert!(close(normal_sf(1.959_963_984_540_054), 0.025, 1e-12));
    }

    #[test]
    fn distribution_tails_match_tables() {
        // χ² critical values at 5 %: 3.841458820694124 (df 1), 11.070497693516351 (df 5).
        assert!(close(chi2_sf(3.841_458_820_694_124, 1.0), 0.05, 1e-10));
        assert!(close(chi2_sf(11.070_497_693_516_351, 5.0), 0.05, 1e-10));
        // df 2: the survival function is e^(−x/2).
        assert!(close(chi2_sf(10.0, 2.0), (-5.0f64).exp(), 1e-13));
        assert!(close(
            chi2_sf(100.0, 3.0),
            1.554_159_431_389_602_6e-21,
            1e-9
        ));
        assert_eq!(chi2_sf(0.0, 4.0), 1.0);
        // Φ(−1.959963984540054) = 0.025.
        assert!(close(normal_sf(1.959_963_984_540_054), 0.025, 1e-12));
        assert!(close(normal_sf(0.0), 0.5, 1e-15));
        // t(1) is Cauchy: P(T ≤ 1) = ¾.
        assert!(close(t_cdf(1.0, 1.0), 0.75, 1e-14));
        assert!(close(t_cdf(-2.0, 3.0), 0.069_662_984_279_421_18, 1e-12));
    }

    #[test]
    fn t_quantiles_match_tables() {
        // 97.5 % points of Student's t (any statistics table; scipy.stats.t.ppf).
        for (df, t) in [
            (1.0, 12.706_204_736_174_707),
            (2.0, 4.302_652_729_749_464),
            (4.0, 2.776_445_105_197_793_4),
            (9.0, 2.262_157_162_798_205),
            (29.0, 2.045_229_642_132_703),
            (1000.0, 1.962_339_080_826_408_3),
        ] {
            let q = t_quantile(0.975, df);
            assert!(close(q, t, 1e-11), "df {df}: {q} vs {t}");
            assert!(close(t_quantile(0.025, df), -t, 1e-11));
        }
        assert!(close(t_quantile(0.95, 5.0), 2.015_048_373_333_023_3, 1e-11));
        assert_eq!(t_quantile(0.5, 7.0), 0.0);
        assert!(t_quantile(0.0, 3.0).is_nan() && t_quantile(1.0, 3.0).is_nan());
    }

    #[test]
    fn confidence_interval_of_a_mean() {
        // 2, 4, 4, 4, 5, 5, 7, 9: mean 5, s = √(32/7), t(0.975, 7) = 2.364624251592784.
        let ci = mean_ci(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0], 0.95).unwrap();
        let hw = 2.364_624_251_592_784 * (32.0f64 / 7.0).sqrt() / 8f64.sqrt();
        assert!(close(ci.half_width, hw, 1e-11), "{ci:?}");
        assert!(close(ci.low(), 5.0 - hw, 1e-12) && close(ci.high(), 5.0 + hw, 1e-12));
        assert!(mean_ci(&[1.0], 0.95).unwrap().half_width.is_nan());
        assert_eq!(mean_ci(&[3.0, 3.0, 3.0], 0.95).unwrap().half_width, 0.0);
        assert!(mean_ci(&[], 0.95).is_none());
    }

    #[test]
    fn average_ranks_and_ties() {
        let (r, t) = ranks(&[10.0, 20.0, 10.0, 30.0, 20.0, 20.0]);
        assert_eq!(r, vec![1.5, 4.0, 1.5, 6.0, 4.0, 4.0]);
        assert_eq!(t, vec![2, 3]);
        let (r, t) = ranks(&[3.0, f64::INFINITY, 1.0]);
        assert_eq!(r, vec![2.0, 3.0, 1.0]);
        assert!(t.is_empty());
    }

    #[test]
    fn wilcoxon_matches_scipy_documentation() {
        // Fisher's Zea mays differences, scipy.stats.wilcoxon's example: T = min(W⁺, W⁻) = 24,
        // two-sided exact p = 0.041259765625.
        let d = [
            6.0, 8.0, 14.0, 16.0, 23.0, 24.0, 28.0, 29.0, 41.0, -48.0, 49.0, 56.0, 60.0, -67.0,
            75.0,
        ];
        let zero = [0.0; 15];
        let w = wilcoxon(&d, &zero).unwrap();
        assert!(w.exact);
        assert_eq!(w.n, 15);
        assert_eq!(w.w_plus, 120.0 - 24.0);
        assert!(close(w.p_value, 0.041_259_765_625, 1e-12), "{w:?}");
        assert!(!w.x_lower());
        // Swapping the samples mirrors W⁺ and keeps p.
        let m = wilcoxon(&zero, &d).unwrap();
        assert_eq!(m.w_plus, 24.0);
        assert_eq!(m.p_value, w.p_value);
        assert!(m.x_lower());
    }

    #[test]
    fn wilcoxon_exact_small_cases() {
        // n = 8, all differences of one sign: p = 2 / 2⁸.
        let x: Vec<f64> = (1..=8).map(f64::from).collect();
        let y: Vec<f64> = x.iter().map(|v| v + 0.5 * v).collect();
        let w = wilcoxon(&x, &y).unwrap();
        assert_eq!((w.w_plus, w.n), (0.0, 8));
        assert!(close(w.p_value, 2.0 / 256.0, 1e-15));
        // Zero differences are dropped; all-zero gives p = 1.
        let w = wilcoxon(&[1.0, 2.0, 3.0], &[1.0, 2.0, 3.0]).unwrap();
        assert_eq!((w.n, w.p_value), (0, 1.0));
        let w = wilcoxon(&[1.0, 2.0, 5.0], &[1.0, 3.0, 7.0]).unwrap();
        assert_eq!(w.n, 2);
        // Two negative differences, ranks 1 and 2: P(W⁺ ≤ 0) = ¼, two-sided ½.
        assert!(close(w.p_value, 0.5, 1e-15));
        // Tied |d| = 1, 1, 2 (ranks 1.5, 1.5, 3), signs +, −, +: W⁺ = 4.5. The eight sign
        // assignments give W⁺ = 0, 1.5, 1.5, 3, 3, 4.5, 4.5, 6: P(W⁺ ≥ 4.5) = 3/8, p = ¾.
        let w = wilcoxon(&[1.0, 0.0, 2.0], &[0.0, 1.0, 0.0]).unwrap();
        assert_eq!(w.w_plus, 4.5);
        assert!(close(w.p_value, 0.75, 1e-15), "{w:?}");
        // Infinite values rank above every finite one; equal infinities are zero differences.
        let w = wilcoxon(
            &[f64::INFINITY, f64::INFINITY, 1.0],
            &[1.0, f64::INFINITY, 0.0],
        )
        .unwrap();
        assert_eq!((w.n, w.w_plus), (2, 3.0));
        assert!(wilcoxon(&[f64::NAN], &[1.0]).is_none());
        assert!(wilcoxon(&[1.0], &[1.0, 2.0]).is_none());
    }

    #[test]
    fn wilcoxon_normal_approximation() {
        // n = 30 differences 1..=30, the first 10 negative: W⁺ = 465 − 55 = 410, mean 232.5,
        // variance 30·31·61/24 = 2363.75: z = 3.6509..., p = 2·Φ(−z).
        let x: Vec<f64> = (1..=30)
            .map(|i| if i <= 10 { -f64::from(i) } else { f64::from(i) })
            .collect();
        let w = wilcoxon(&x, &[0.0; 30]).unwrap();
        assert!(!w.exact);
        assert_eq!(w.w_plus, 410.0);
        let z: f64 = (410.0 - 232.5) / 2363.75f64.sqrt();
        assert!(close(w.p_value, 2.0 * normal_sf(z), 1e-14));
        // scipy.stats.wilcoxon(x, method="approx"): p = 0.00026134309226671514.
        assert!(
            close(w.p_value, 2.613_430_922_667_151_4e-4, 1e-9),
            "{}",
            w.p_value
        );
        // Ties shrink the variance: 26 differences, |d| all equal, 20 positive.
        let x: Vec<f64> = (0..26).map(|i| if i < 20 { 1.0 } else { -1.0 }).collect();
        let w = wilcoxon(&x, &[0.0; 26]).unwrap();
        // Every rank is 13.5: W⁺ = 270, mean 175.5, variance 26·27·53/24 − (26³ − 26)/48.
        let var: f64 = 26.0 * 27.0 * 53.0 / 24.0 - (26f64.powi(3) - 26.0) / 48.0;
        assert_eq!(w.w_plus, 270.0);
        assert!(close(
            w.p_value,
            2.0 * normal_sf((270.0 - 175.5) / var.sqrt()),
            1e-14
        ));
        // scipy.stats.wilcoxon(x, method="approx"): p = 0.006039559048656822.
        assert!(close(w.p_value, 0.006_039_559_048_656_822, 1e-9));
    }

    #[test]
    fn friedman_matches_scipy_documentation() {
        // scipy.stats.friedmanchisquare's example (three measurements on seven subjects):
        // statistic 10.571428571428571, p = 0.005063414171757498.
        let before = [72.0, 96.0, 88.0, 92.0, 74.0, 76.0, 82.0];
        let after = [120.0, 120.0, 132.0, 120.0, 101.0, 96.0, 112.0];
        let five = [76.0, 95.0, 104.0, 96.0, 84.0, 72.0, 76.0];
        let blocks: Vec<Vec<f64>> = (0..7).map(|i| vec![before[i], after[i], five[i]]).collect();
        let f = friedman(&blocks).unwrap();
        assert_eq!(f.df, 2);
        assert!(close(f.statistic, 10.571_428_571_428_571, 1e-13));
        assert!(close(f.p_value, 0.005_063_414_171_757_498, 1e-11));
    }

    #[test]
    fn friedman_ties_and_degenerate_input() {
        // Blocks (1, 1, 2) and (1, 2, 3): rank sums 2.5, 3.5, 6; raw 12/24 · 54.5 − 24 = 3.25,
        // tie term (2³ − 2) = 6 over n k (k² − 1) = 48: statistic 3.25 / 0.875 = 3.7142857
        // (scipy: 3.7142857142857144, p = 0.15611804531597104).
        let f = friedman(&[vec![1.0, 1.0, 2.0], vec![1.0, 2.0, 3.0]]).unwrap();
        assert!(close(f.statistic, 3.25 / 0.875, 1e-14), "{f:?}");
        assert!(close(f.p_value, 0.156_118_045_315_971_04, 1e-11));
        // Identical treatments: statistic 0, p = 1.
        let f = friedman(&[vec![5.0, 5.0, 5.0], vec![2.0, 2.0, 2.0]]).unwrap();
        assert_eq!((f.statistic, f.p_value), (0.0, 1.0));
        assert!(friedman(&[]).is_none());
        assert!(friedman(&[vec![1.0]]).is_none());
        assert!(friedman(&[vec![1.0, 2.0], vec![1.0]]).is_none());
        assert!(friedman(&[vec![1.0, f64::NAN]]).is_none());
    }

    #[test]
    fn holm_matches_a_hand_computation() {
        // Sorted 0.005, 0.01, 0.03, 0.04 times 4, 3, 2, 1 = 0.02, 0.03, 0.06, 0.04 → the last
        // is raised to 0.06 (monotone); statsmodels' multipletests(method="holm") agrees.
        let adj = holm(&[0.01, 0.04, 0.03, 0.005]);
        let want = [0.03, 0.06, 0.06, 0.02];
        for (a, w) in adj.iter().zip(want) {
            assert!(close(*a, w, 1e-14), "{adj:?}");
        }
        assert_eq!(holm(&[0.9, 0.8]), vec![1.0, 1.0]);
        assert!(holm(&[]).is_empty());
    }

    /// A small deterministic generator for the property tests (no extra dependency).
    fn lcg(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn property_p_values_are_probabilities_and_invariant() {
        let mut s = 42u64;
        for case in 0..300 {
            let n = 2 + case % 35;
            let k = 2 + case % 6;
            // Coarse values make ties and zero differences common.
            let coarse = case % 3 == 0;
            let draw = |s: &mut u64| {
                let v = lcg(s) * 10.0;
                if coarse {
                    v.round()
                } else {
                    v
                }
            };
            let blocks: Vec<Vec<f64>> = (0..n)
                .map(|_| (0..k).map(|_| draw(&mut s)).collect())
                .collect();
            let f = friedman(&blocks).unwrap();
            assert!((0.0..=1.0).contains(&f.p_value), "{f:?}");
            assert!(f.statistic >= 0.0);
            // Relabelling the treatments (reversing the columns) changes nothing.
            let rev: Vec<Vec<f64>> = blocks
                .iter()
                .map(|b| b.iter().rev().copied().collect())
                .collect();
            let fr = friedman(&rev).unwrap();
            assert!((f.statistic - fr.statistic).abs() <= 1e-9 * f.statistic.max(1.0));
            // Reordering the blocks changes nothing either.
            let mut shuffled = blocks.clone();
            shuffled.reverse();
            assert!(
                (friedman(&shuffled).unwrap().statistic - f.statistic).abs()
                    <= 1e-9 * f.statistic.max(1.0)
            );
            // A monotone transform of every value keeps the ranks, so the statistic.
            let cubed: Vec<Vec<f64>> = blocks
                .iter()
                .map(|b| b.iter().map(|v| v.powi(3) + 1.0).collect())
                .collect();
            assert!(
                (friedman(&cubed).unwrap().statistic - f.statistic).abs()
                    <= 1e-9 * f.statistic.max(1.0)
            );

            let x: Vec<f64> = blocks.iter().map(|b| b[0]).collect();
            let y: Vec<f64> = blocks.iter().map(|b| b[1]).collect();
            let w = wilcoxon(&x, &y).unwrap();
            assert!((0.0..=1.0).contains(&w.p_value), "{w:?}");
            // Swapping the samples mirrors the statistic and keeps the two-sided p-value.
            let ws = wilcoxon(&y, &x).unwrap();
            let total = (w.n * (w.n + 1)) as f64 / 2.0;
            assert!((ws.w_plus - (total - w.w_plus)).abs() < 1e-9);
            assert!((ws.p_value - w.p_value).abs() < 1e-12);
            // Scaling both samples by a positive factor changes nothing.
            let x3: Vec<f64> = x.iter().map(|v| 3.0 * v).collect();
            let y3: Vec<f64> = y.iter().map(|v| 3.0 * v).collect();
            assert!((wilcoxon(&x3, &y3).unwrap().p_value - w.p_value).abs() < 1e-12);

            let ps: Vec<f64> = blocks[0].iter().map(|v| v / 10.0).collect();
            let adj = holm(&ps);
            for (a, p) in adj.iter().zip(&ps) {
                assert!(*a >= *p && *a <= 1.0);
            }
        }
    }

    #[test]
    fn exact_and_normal_wilcoxon_agree_near_the_switch() {
        // At n = 25 without ties the exact and the normal p-values differ by little.
        let x: Vec<f64> = (1..=25)
            .map(|i| {
                if i % 3 == 0 {
                    -f64::from(i)
                } else {
                    f64::from(i)
                }
            })
            .collect();
        let w = wilcoxon(&x, &[0.0; 25]).unwrap();
        assert!(w.exact);
        let total = 25.0 * 26.0 / 2.0;
        let mean = total / 2.0;
        let var: f64 = 25.0 * 26.0 * 51.0 / 24.0;
        let approx = 2.0 * normal_sf((w.w_plus - mean).abs() / var.sqrt());
        assert!(
            (w.p_value - approx).abs() < 0.01,
            "{} vs {approx}",
            w.p_value
        );
    }
}
