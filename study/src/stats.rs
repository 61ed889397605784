//! Mean ± standard deviation over seeds, and the per-table aggregate of the rows.
use crate::record::{Kind, Row};
use crate::{Measure, MethodId};
use std::collections::BTreeMap;

/// Mean and sample standard deviation (n − 1 in the denominator; 0 for a single value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stat {
    /// Arithmetic mean.
    pub mean: f64,
    /// Sample standard deviation; 0 when `n == 1`.
    pub std: f64,
    /// Number of values.
    pub n: usize,
}

/// Mean and sample standard deviation of `values`; `None` if empty. Non-finite values
/// propagate (an infinite measure gives an infinite mean).
pub fn mean_std(values: &[f64]) -> Option<Stat> {
    let n = values.len();
    if n == 0 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let std = if n > 1 {
        (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt()
    } else {
        0.0
    };
    Some(Stat { mean, std, n })
}

/// Statistics of every measure per (region, K, method, kind), over the seeds present.
#[derive(Clone, Debug, Default)]
pub struct Aggregate {
    cells: BTreeMap<(String, usize, MethodId, Kind), [Stat; 14]>,
    seeds: BTreeMap<(String, usize, MethodId), Vec<u64>>,
}

impl Aggregate {
    /// Group rows and reduce each group over its seeds. Rows with unknown methods are skipped.
    pub fn from_rows(rows: &[Row]) -> Aggregate {
        let mut groups: BTreeMap<(String, usize, MethodId, Kind), Vec<&Row>> = BTreeMap::new();
        for r in rows {
            if let Some(m) = r.method_id() {
                groups
                    .entry((r.region.clone(), r.K_requested, m, r.kind))
                    .or_default()
                    .push(r);
            }
        }
        let mut agg = Aggregate::default();
        for (key, group) in groups {
            let stats = Measure::ALL.map(|m| {
                let v: Vec<f64> = group.iter().map(|r| r.value(m)).collect();
                mean_std(&v).unwrap_or(Stat {
                    mean: f64::NAN,
                    std: f64::NAN,
                    n: 0,
                })
            });
            if key.3 == Kind::Exact {
                let mut s: Vec<u64> = group.iter().map(|r| r.seed).collect();
                s.sort_unstable();
                agg.seeds.insert((key.0.clone(), key.1, key.2), s);
            }
            agg.cells.insert(key, stats);
        }
        agg
    }

    /// The statistic of one measure, if that (region, K, method, kind) has rows.
    pub fn get(
        &self,
        region: &str,
        k: usize,
        method: MethodId,
        kind: Kind,
        m: Measure,
    ) -> Option<Stat> {
        self.cells
            .get(&(region.to_string(), k, method, kind))
            .map(|s| s[m.index()])
    }

    /// Methods with rows for (region, K), in column order.
    pub fn methods(&self, region: &str, k: usize) -> Vec<MethodId> {
        let mut v: Vec<MethodId> = self
            .cells
            .keys()
            .filter(|c| c.0 == region && c.1 == k)
            .map(|c| c.2)
            .collect();
        v.dedup();
        v
    }

    /// All seeds present (exact rows), sorted and distinct.
    pub fn all_seeds(&self) -> Vec<u64> {
        let mut s: Vec<u64> = self.seeds.values().flatten().copied().collect();
        s.sort_unstable();
        s.dedup();
        s
    }

    /// True if nothing was aggregated.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::fake_row;

    #[test]
    fn mean_and_sample_std() {
        let s = mean_std(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]).unwrap();
        assert_eq!(s.n, 8);
        assert!((s.mean - 5.0).abs() < 1e-15);
        // Sum of squared deviations 32, n − 1 = 7.
        assert!((s.std - (32.0f64 / 7.0).sqrt()).abs() < 1e-15);
        assert_eq!(
            mean_std(&[3.5]).unwrap(),
            Stat {
                mean: 3.5,
                std: 0.0,
                n: 1
            }
        );
        assert!(mean_std(&[]).is_none());
        assert!(mean_std(&[1.0, f64::INFINITY]).unwrap().mean.is_infinite());
    }

    #[test]
    fn aggregate_reduces_over_seeds_per_group() {
        let rows: Vec<Row> = (1..=3)
            .flat_map(|s| {
                [
                    fake_row("circle", 88, MethodId::Ccvt2, s, Kind::Exact, s as f64),
                    fake_row(
                        "circle",
                        88,
                        MethodId::Ccvt2,
                        s,
                        Kind::Sampled,
                        10.0 * s as f64,
                    ),
                    fake_row("circle", 88, MethodId::Distmesh, s, Kind::Exact, 0.0),
                ]
            })
            .collect();
        let a = Aggregate::from_rows(&rows);
        let lam = a
            .get("circle", 88, MethodId::Ccvt2, Kind::Exact, Measure::Lambda)
            .unwrap();
        // fake_row: lambda = x/2 + 1/3 with x = 1, 2, 3.
        assert!((lam.mean - (1.0 + 1.0 / 3.0)).abs() < 1e-12);
        assert!((lam.std - 0.5).abs() < 1e-12);
        assert_eq!(lam.n, 3);
        let lam_s = a
            .get(
                "circle",
                88,
                MethodId::Ccvt2,
                Kind::Sampled,
                Measure::Lambda,
            )
            .unwrap();
        assert!((lam_s.mean - (10.0 + 1.0 / 3.0)).abs() < 1e-12);
        let d = a
            .get("circle", 88, MethodId::Distmesh, Kind::Exact, Measure::K)
            .unwrap();
        assert_eq!((d.mean, d.std), (88.0, 0.0));
        assert!(a
            .get("circle", 88, MethodId::Vtm, Kind::Exact, Measure::K)
            .is_none());
        assert_eq!(
            a.methods("circle", 88),
            vec![MethodId::Distmesh, MethodId::Ccvt2]
        );
        assert_eq!(a.all_seeds(), vec![1, 2, 3]);
    }
}
