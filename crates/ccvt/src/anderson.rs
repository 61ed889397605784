//! Anderson acceleration (type II) of a fixed-point map z ↦ G(z) on point sets (read as one
//! flat vector of coordinates).
//!
//! Keeps the differences of the last `m + 1` residuals f = G(z) − z and map values; the next
//! iterate is the combination of past G values that minimises the combined residual in least
//! squares. The Gram matrix of the residual differences is updated incrementally (one new
//! column per step), buffers are recycled, and every pass over the 2K coordinates runs in
//! parallel with a fixed chunking, so the result does not depend on the thread count.
use geometry::DVec2;
use rayon::prelude::*;
use std::collections::VecDeque;

/// Points per chunk of the parallel passes (fixed, so sums are reproducible).
const CHUNK: usize = 4096;

/// History of the last `m` differences.
pub struct Anderson {
    m: usize,
    /// ΔF_j = f_{j+1} − f_j, oldest first.
    df: VecDeque<Vec<DVec2>>,
    /// ΔG_j = G_{j+1} − G_j, aligned with `df`.
    dg: VecDeque<Vec<DVec2>>,
    /// gram[i][j] = ΔF_i · ΔF_j, aligned with `df`.
    gram: VecDeque<VecDeque<f64>>,
    /// The last residual and map value (empty before the first step).
    prev_f: Vec<DVec2>,
    prev_g: Vec<DVec2>,
    /// Buffers of dropped columns, reused for new ones.
    spare: Vec<Vec<DVec2>>,
}

impl Anderson {
    /// Empty history of depth `m`.
    pub fn new(m: usize) -> Self {
        Anderson {
            m,
            df: VecDeque::new(),
            dg: VecDeque::new(),
            gram: VecDeque::new(),
            prev_f: Vec::new(),
            prev_g: Vec::new(),
            spare: Vec::new(),
        }
    }

    /// Forget the history (after a rejected step or a change of constraints).
    pub fn reset(&mut self) {
        self.spare.extend(self.df.drain(..));
        self.spare.extend(self.dg.drain(..));
        self.gram.clear();
        self.prev_f.clear();
        self.prev_g.clear();
    }

    fn buffer(&mut self, n: usize) -> Vec<DVec2> {
        let mut b = self.spare.pop().unwrap_or_default();
        b.resize(n, DVec2::ZERO);
        b
    }

    /// Record (z, G(z)) and write the accelerated next iterate into `out`.
    pub fn step(&mut self, z: &[DVec2], gz: &[DVec2], out: &mut Vec<DVec2>) {
        let n = z.len();
        out.clear();
        out.extend_from_slice(gz);
        if self.m == 0 {
            return;
        }
        if self.prev_f.len() != n {
            // First step (or a reset): remember f and G, return the plain map value.
            self.reset();
            self.prev_f = z.iter().zip(gz).map(|(z, g)| *g - *z).collect();
            self.prev_g = gz.to_vec();
            return;
        }
        if self.df.len() == self.m {
            self.spare.extend(self.df.pop_front());
            self.spare.extend(self.dg.pop_front());
            self.gram.pop_front();
            for row in &mut self.gram {
                row.pop_front();
            }
        }
        // New columns ΔF, ΔG; prev_f, prev_g become f, G of this step.
        let (mut dfn, mut dgn) = (self.buffer(n), self.buffer(n));
        dfn.par_chunks_mut(CHUNK)
            .zip(dgn.par_chunks_mut(CHUNK))
            .zip(self.prev_f.par_chunks_mut(CHUNK))
            .zip(self.prev_g.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(c, (((df, dg), pf), pg))| {
                let base = c * CHUNK;
                for i in 0..df.len() {
                    let f = gz[base + i] - z[base + i];
                    df[i] = f - pf[i];
                    dg[i] = gz[base + i] - pg[i];
                    pf[i] = f;
                    pg[i] = gz[base + i];
                }
            });
        self.df.push_back(dfn);
        self.dg.push_back(dgn);
        // One pass for the new Gram column (ΔF_j · ΔF_new) and b_j = ΔF_j · f.
        let p = self.df.len();
        let last = &self.df[p - 1];
        let f = &self.prev_f;
        let cols: Vec<&[DVec2]> = self.df.iter().map(Vec::as_slice).collect();
        let partial: Vec<Vec<f64>> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let r = c * CHUNK..((c + 1) * CHUNK).min(n);
                let mut acc = vec![0.0; 2 * p];
                for (j, col) in cols.iter().enumerate() {
                    let (mut g, mut b) = (0.0, 0.0);
                    for i in r.clone() {
                        g += col[i].dot(last[i]);
                        b += col[i].dot(f[i]);
                    }
                    acc[j] = g;
                    acc[p + j] = b;
                }
                acc
            })
            .collect();
        let mut sums = vec![0.0; 2 * p];
        for acc in &partial {
            for (s, a) in sums.iter_mut().zip(acc) {
                *s += a;
            }
        }
        for (j, row) in self.gram.iter_mut().enumerate() {
            row.push_back(sums[j]);
        }
        self.gram.push_back(sums[..p].iter().copied().collect());
        let mut a: Vec<Vec<f64>> = self
            .gram
            .iter()
            .map(|r| r.iter().copied().collect())
            .collect();
        let b = sums[p..].to_vec();
        let trace: f64 = (0..p).map(|i| a[i][i]).sum();
        for (i, row) in a.iter_mut().enumerate() {
            row[i] += 1e-10 * trace.max(f64::MIN_POSITIVE);
        }
        let Some(gamma) = solve(a, b) else {
            self.reset();
            return;
        };
        let dg: Vec<&[DVec2]> = self.dg.iter().map(Vec::as_slice).collect();
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, o)| {
            let base = c * CHUNK;
            for (i, o) in o.iter_mut().enumerate() {
                for (gj, col) in gamma.iter().zip(&dg) {
                    *o -= *gj * col[base + i];
                }
            }
        });
    }
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

    /// G(z) = A z + c per point with slow contraction: plain iteration needs hundreds of steps.
    fn g(z: &[DVec2]) -> Vec<DVec2> {
        z.iter()
            .enumerate()
            .map(|(k, p)| {
                let s = 1.0 + 0.01 * k as f64;
                DVec2::new(0.99 * p.x + 0.01 * p.y + s, 0.005 * p.x + 0.98 * p.y - 1.0)
            })
            .collect()
    }

    fn fixed(k: usize) -> DVec2 {
        // Solve (I − A) z = c directly.
        let s = 1.0 + 0.01 * k as f64;
        let (a, b, c, d) = (1.0 - 0.99, -0.01, -0.005, 1.0 - 0.98);
        let det = a * d - b * c;
        DVec2::new((d * s + b) / det, (-c * s - a) / det)
    }

    #[test]
    fn accelerates_a_linear_contraction() {
        // Enough points for several parallel chunks.
        let n = 3 * CHUNK + 17;
        let mut aa = Anderson::new(3);
        let mut z = vec![DVec2::ZERO; n];
        let mut out = Vec::new();
        let err = |z: &[DVec2]| {
            z.iter()
                .enumerate()
                .map(|(k, p)| (*p - fixed(k)).length())
                .fold(0.0, f64::max)
        };
        let mut steps = 0;
        while err(&z) > 1e-8 && steps < 100 {
            let gz = g(&z);
            aa.step(&z, &gz, &mut out);
            std::mem::swap(&mut z, &mut out);
            steps += 1;
        }
        // Every point has the same linear part (two eigenvalues), so a short history suffices.
        assert!(steps < 10, "Anderson took {steps} steps, error {}", err(&z));
    }

    #[test]
    fn reset_returns_the_plain_map_value() {
        let mut aa = Anderson::new(2);
        let z = vec![DVec2::new(1.0, 2.0); 5];
        let gz = g(&z);
        let mut out = Vec::new();
        aa.step(&z, &gz, &mut out);
        assert_eq!(out, gz);
        let z2 = out.clone();
        let gz2 = g(&z2);
        aa.step(&z2, &gz2, &mut out);
        assert_ne!(out, gz2);
        aa.reset();
        aa.step(&z2, &gz2, &mut out);
        assert_eq!(out, gz2);
    }
}
