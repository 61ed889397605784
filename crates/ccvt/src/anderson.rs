//! Anderson acceleration (type II) of a fixed-point map z ↦ G(z), on flat coordinate vectors.
//!
//! Keeps the last `m` residuals f = G(z) − z and map values; the next iterate is the
//! combination of past G values that minimises the combined residual in least squares.

/// History of the last `m` iterates.
pub struct Anderson {
    m: usize,
    g: Vec<Vec<f64>>,
    f: Vec<Vec<f64>>,
}

impl Anderson {
    /// Empty history of depth `m`.
    pub fn new(m: usize) -> Self {
        Anderson {
            m,
            g: Vec::new(),
            f: Vec::new(),
        }
    }

    /// Forget the history (after a rejected step or a change of constraints).
    pub fn reset(&mut self) {
        self.g.clear();
        self.f.clear();
    }

    /// Record (z, G(z)) and return the accelerated next iterate.
    pub fn step(&mut self, z: &[f64], gz: &[f64]) -> Vec<f64> {
        let f: Vec<f64> = gz.iter().zip(z).map(|(g, z)| g - z).collect();
        self.g.push(gz.to_vec());
        self.f.push(f);
        if self.g.len() > self.m + 1 {
            self.g.remove(0);
            self.f.remove(0);
        }
        let n = self.f.len();
        if n < 2 {
            return gz.to_vec();
        }
        // Differences ΔF_j = f_{j+1} − f_j, solve min |f_n − ΔF γ| via normal equations.
        let last = &self.f[n - 1];
        let df: Vec<Vec<f64>> = (0..n - 1)
            .map(|j| {
                self.f[j + 1]
                    .iter()
                    .zip(&self.f[j])
                    .map(|(a, b)| a - b)
                    .collect()
            })
            .collect();
        let p = df.len();
        let mut a = vec![vec![0.0; p]; p];
        let mut b = vec![0.0; p];
        for i in 0..p {
            for j in i..p {
                let v = dot(&df[i], &df[j]);
                a[i][j] = v;
                a[j][i] = v;
            }
            b[i] = dot(&df[i], last);
        }
        let trace: f64 = (0..p).map(|i| a[i][i]).sum();
        for (i, row) in a.iter_mut().enumerate() {
            row[i] += 1e-10 * trace.max(f64::MIN_POSITIVE);
        }
        let Some(gamma) = solve(a, b) else {
            self.reset();
            return gz.to_vec();
        };
        let mut out = self.g[n - 1].clone();
        for (j, gj) in gamma.iter().enumerate() {
            for (k, o) in out.iter_mut().enumerate() {
                *o -= gj * (self.g[j + 1][k] - self.g[j][k]);
            }
        }
        out
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Gaussian elimination with partial pivoting; `None` if singular.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for c in 0..n {
        let piv = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[piv][c].abs() < 1e-300 {
            return None;
        }
        a.swap(c, piv);
        b.swap(c, piv);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            let (top, rest) = a.split_at_mut(r);
            for (x, y) in rest[0][c..].iter_mut().zip(&top[c][c..]) {
                *x -= f * y;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accelerates_a_linear_contraction() {
        // G(z) = A z + c with slow contraction: plain iteration needs hundreds of steps.
        let g = |z: &[f64]| {
            vec![
                0.99 * z[0] + 0.01 * z[1] + 1.0,
                0.005 * z[0] + 0.98 * z[1] - 1.0,
            ]
        };
        let fixed = {
            // Solve (I − A) z = c directly.
            let (a, b, c, d) = (1.0 - 0.99, -0.01, -0.005, 1.0 - 0.98);
            let det = a * d - b * c;
            [(d + b) / det, (-a - c) / det] as [f64; 2]
        };
        let mut aa = Anderson::new(3);
        let mut z: Vec<f64> = vec![0.0, 0.0];
        let mut steps = 0;
        while ((z[0] - fixed[0]).powi(2) + (z[1] - fixed[1]).powi(2)).sqrt() > 1e-9 && steps < 100 {
            let gz = g(&z);
            z = aa.step(&z, &gz);
            steps += 1;
        }
        assert!(steps < 10, "Anderson took {steps} steps");
    }
}
