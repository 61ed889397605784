//! The [`Measures`] record and its CSV form.
use crate::MetricsError;

/// K, K̃ and the 12 quality measures of Section 3 of the paper, for one mesh.
///
/// Every measure is non-negative with ideal value 0. λ, γ, h, μ, χ, ν, α, β, q, p are
/// dimensionless (invariant under rotation, translation and uniform scaling); τ is a
/// length² and d a length⁴.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measures {
    /// K: number of points (mesh vertices / generators).
    pub k: usize,
    /// K̃: number of triangles.
    pub k_tilde: usize,
    /// λ: coefficient of variation of the nearest-neighbour distances γ_k (population std).
    pub lambda: f64,
    /// γ: max_k γ_k / min_k γ_k − 1.
    pub gamma: f64,
    /// h: max_k h_k / h* − 1 with h* = (√12 |Ω| / (9K))^{1/2}.
    pub h: f64,
    /// μ: max_k h_k / min_k h_k − 1.
    pub mu: f64,
    /// χ: max_k √3 h_k / γ_k − 1.
    pub chi: f64,
    /// ν: max_k |V_k| / min_k |V_k| − 1 (boundary cells included).
    pub nu: f64,
    /// τ: max_k |τ_k − τ̄|, τ_k = trace of the cell's second-moment tensor (a length²).
    pub tau: f64,
    /// d: max_k |det(M_k − (τ_k/2) I)| (a length⁴).
    pub d: f64,
    /// α: (K̃/|Ω|) max_j |Δ_j| − 1.
    pub alpha: f64,
    /// β: (π/3) / min_j (smallest angle of Δ_j) − 1.
    pub beta: f64,
    /// q: max_j R_j/(2 r_j) − 1.
    pub q: f64,
    /// p: population standard deviation of the circumradii R_j over their mean.
    pub p: f64,
}

impl Measures {
    /// Column names, in the paper's table order (also the CSV header).
    pub const NAMES: [&'static str; 14] = [
        "K", "Ktilde", "lambda", "gamma", "h", "mu", "chi", "nu", "tau", "d", "alpha", "beta", "q",
        "p",
    ];

    /// All 14 values in [`Measures::NAMES`] order (K and K̃ as floats).
    pub fn values(&self) -> [f64; 14] {
        [
            self.k as f64,
            self.k_tilde as f64,
            self.lambda,
            self.gamma,
            self.h,
            self.mu,
            self.chi,
            self.nu,
            self.tau,
            self.d,
            self.alpha,
            self.beta,
            self.q,
            self.p,
        ]
    }

    /// The value named `name` (one of [`Measures::NAMES`]).
    pub fn get(&self, name: &str) -> Option<f64> {
        Self::NAMES
            .iter()
            .position(|n| *n == name)
            .map(|i| self.values()[i])
    }

    /// Build from values in [`Measures::NAMES`] order; K and K̃ must be non-negative integers.
    pub fn from_values(v: [f64; 14]) -> Result<Measures, MetricsError> {
        let count = |x: f64, name: &str| {
            if x >= 0.0 && x.fract() == 0.0 && x <= u32::MAX as f64 {
                Ok(x as usize)
            } else {
                Err(MetricsError::Parse(format!("{name} = {x} is not a count")))
            }
        };
        Ok(Measures {
            k: count(v[0], "K")?,
            k_tilde: count(v[1], "Ktilde")?,
            lambda: v[2],
            gamma: v[3],
            h: v[4],
            mu: v[5],
            chi: v[6],
            nu: v[7],
            tau: v[8],
            d: v[9],
            alpha: v[10],
            beta: v[11],
            q: v[12],
            p: v[13],
        })
    }

    /// `K,Ktilde,lambda,gamma,h,mu,chi,nu,tau,d,alpha,beta,q,p`.
    pub fn csv_header() -> String {
        Self::NAMES.join(",")
    }

    /// One CSV row matching [`Measures::csv_header`]. Each float is the shortest text that
    /// parses back to the identical `f64`: Rust's `{}` for magnitudes in [1e-4, 1e15) and
    /// zero, `{:e}` otherwise (so d ≈ 1e-7 prints as `1.0e-7`, not 25 characters of zeros);
    /// `inf`/`NaN` for degenerate input. [`Measures::parse_csv_row`] round-trips exactly.
    pub fn csv_row(&self) -> String {
        let mut s = format!("{},{}", self.k, self.k_tilde);
        for v in &self.values()[2..] {
            s.push(',');
            s.push_str(&format_f64(*v));
        }
        s
    }

    /// Parse a row written by [`Measures::csv_row`].
    pub fn parse_csv_row(line: &str) -> Result<Measures, MetricsError> {
        let fields: Vec<&str> = line.trim().split(',').collect();
        if fields.len() != 14 {
            return Err(MetricsError::Parse(format!(
                "expected 14 fields, got {}",
                fields.len()
            )));
        }
        let mut v = [0.0; 14];
        for (i, f) in fields.iter().enumerate() {
            v[i] = f
                .trim()
                .parse::<f64>()
                .map_err(|e| MetricsError::Parse(format!("{} = '{f}': {e}", Self::NAMES[i])))?;
        }
        Self::from_values(v)
    }
}

/// Shortest round-trip text of `v`, in scientific notation for very small or large magnitudes.
fn format_f64(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trip_is_exact() {
        let m = Measures {
            k: 88,
            k_tilde: 146,
            lambda: 0.1 + 0.2,
            gamma: 1.0 / 3.0,
            h: std::f64::consts::PI,
            mu: 1e-300,
            chi: 2.5e-17,
            nu: f64::INFINITY,
            tau: 6.87e-4,
            d: 2.29e-7,
            alpha: 0.0,
            beta: 1.01,
            q: 123_456_789.123_456_79,
            p: 0.123,
        };
        assert_eq!(
            Measures::csv_header(),
            "K,Ktilde,lambda,gamma,h,mu,chi,nu,tau,d,alpha,beta,q,p"
        );
        let row = m.csv_row();
        assert!(row.starts_with("88,146,0.30000000000000004,"));
        assert!(
            row.contains(",1e-300,2.5e-17,inf,0.000687,2.29e-7,0,"),
            "{row}"
        );
        let back = Measures::parse_csv_row(&row).unwrap();
        assert_eq!(back, m);
        assert_eq!(
            back.values().map(f64::to_bits),
            m.values().map(f64::to_bits)
        );
        assert_eq!(m.get("nu"), Some(f64::INFINITY));
        assert_eq!(m.get("Ktilde"), Some(146.0));
        assert_eq!(m.get("x"), None);
        assert!(Measures::parse_csv_row("1,2,3").is_err());
        assert!(Measures::parse_csv_row(&row.replacen("88", "8.5", 1)).is_err());
        assert!(Measures::parse_csv_row(&row.replacen("146", "abc", 1)).is_err());
    }
}
