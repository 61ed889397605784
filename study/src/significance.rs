//! Which method is best in one (table, measure) cell, and whether that is more than noise:
//! a Friedman test across the methods with seeds as blocks, then a two-sided Wilcoxon
//! signed-rank test for every pair of methods (paired by seed), Holm-corrected over the
//! cell's pairs.
//!
//! A method *wins* a cell only if it has the lowest mean, the Friedman test rejects "all
//! methods alike" at α, and after Holm's correction it is significantly lower than every
//! other method. Anything else is a tie. Every pair is in the Holm family (not only the
//! best one's), because which method is "best" is itself read off the same data.
use crate::inference::{friedman, holm, wilcoxon, Friedman, SignedRank};
use crate::record::{Kind, Row};
use crate::{Measure, MethodId};
use std::collections::{BTreeMap, BTreeSet};

/// Family-wise significance level of the study's tests.
pub const ALPHA: f64 = 0.05;

/// One method's values of one measure in one cell, by seed.
pub type Samples = BTreeMap<u64, f64>;

/// The values of `m` for every method of `methods` in (region, K, kind), keyed by seed.
/// Methods without rows are left out.
pub fn cell_samples(
    rows: &[Row],
    region: &str,
    k: usize,
    kind: Kind,
    m: Measure,
    methods: &[MethodId],
) -> Vec<(MethodId, Samples)> {
    let mut by: BTreeMap<MethodId, Samples> = BTreeMap::new();
    for r in rows
        .iter()
        .filter(|r| r.region == region && r.K_requested == k && r.kind == kind)
    {
        if let Some(id) = r.method_id().filter(|id| methods.contains(id)) {
            by.entry(id).or_default().insert(r.seed, r.value(m));
        }
    }
    by.into_iter().collect()
}

/// The pairwise test of two methods.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairTest {
    /// First method (its values are x).
    pub a: MethodId,
    /// Second method (its values are y).
    pub b: MethodId,
    /// Wilcoxon signed-rank test of a − b.
    pub test: SignedRank,
    /// Holm-adjusted p-value within the cell's family of pairs.
    pub p_holm: f64,
}

/// The outcome of one cell.
#[derive(Clone, Debug, PartialEq)]
pub struct CellTest {
    /// Methods compared, in column order.
    pub methods: Vec<MethodId>,
    /// Their means over the paired seeds (same order).
    pub means: Vec<f64>,
    /// Seeds every method has a finite-or-infinite (not NaN) value for: the blocks.
    pub seeds: usize,
    /// Friedman test across the methods (`None` with fewer than two methods or seeds).
    pub friedman: Option<Friedman>,
    /// Every pair, Holm-corrected.
    pub pairs: Vec<PairTest>,
    /// The method with the lowest mean (the first on an exact tie).
    pub best: Option<MethodId>,
    /// `best`, if it wins significantly.
    pub winner: Option<MethodId>,
    /// The methods not significantly worse than `best` (`best` included), in column order.
    pub level_with_best: Vec<MethodId>,
}

impl CellTest {
    /// The pair test of `a` and `b` in either order, with `a`'s view (x = a).
    pub fn pair(&self, a: MethodId, b: MethodId) -> Option<(SignedRank, f64)> {
        self.pairs.iter().find_map(|p| {
            if p.a == a && p.b == b {
                Some((p.test, p.p_holm))
            } else if p.a == b && p.b == a {
                let n = p.test.n;
                let mirrored = SignedRank {
                    w_plus: (n * (n + 1)) as f64 / 2.0 - p.test.w_plus,
                    ..p.test
                };
                Some((mirrored, p.p_holm))
            } else {
                None
            }
        })
    }

    /// True if the cell has something to compare (two methods or more).
    pub fn scored(&self) -> bool {
        self.methods.len() >= 2 && self.best.is_some()
    }
}

/// Test one cell. Seeds where a method has no value or a NaN are left out for every method,
/// so that the tests stay paired.
pub fn test_cell(samples: &[(MethodId, Samples)], alpha: f64) -> CellTest {
    let present: Vec<&(MethodId, Samples)> =
        samples.iter().filter(|(_, s)| !s.is_empty()).collect();
    let methods: Vec<MethodId> = present.iter().map(|(m, _)| *m).collect();
    let mut seeds: BTreeSet<u64> = present
        .first()
        .map(|(_, s)| s.keys().copied().collect())
        .unwrap_or_default();
    for (_, s) in &present {
        seeds.retain(|seed| s.get(seed).is_some_and(|v| !v.is_nan()));
    }
    let columns: Vec<Vec<f64>> = present
        .iter()
        .map(|(_, s)| seeds.iter().map(|seed| s[seed]).collect())
        .collect();
    let means: Vec<f64> = columns
        .iter()
        .map(|c| {
            if c.is_empty() {
                f64::NAN
            } else {
                c.iter().sum::<f64>() / c.len() as f64
            }
        })
        .collect();
    let mut best: Option<usize> = None;
    for (i, &m) in means.iter().enumerate() {
        if !m.is_nan() && best.is_none_or(|b| m < means[b]) {
            best = Some(i);
        }
    }

    let blocks: Vec<Vec<f64>> = (0..seeds.len())
        .map(|i| columns.iter().map(|c| c[i]).collect())
        .collect();
    let friedman = if blocks.len() >= 2 {
        friedman(&blocks)
    } else {
        None
    };

    let mut raw = Vec::new();
    for i in 0..methods.len() {
        for j in i + 1..methods.len() {
            if let Some(t) = wilcoxon(&columns[i], &columns[j]) {
                raw.push((i, j, t));
            }
        }
    }
    let adjusted = holm(&raw.iter().map(|r| r.2.p_value).collect::<Vec<_>>());
    let pairs: Vec<PairTest> = raw
        .iter()
        .zip(&adjusted)
        .map(|(&(i, j, test), &p_holm)| PairTest {
            a: methods[i],
            b: methods[j],
            test,
            p_holm,
        })
        .collect();

    let mut out = CellTest {
        methods: methods.clone(),
        means,
        seeds: seeds.len(),
        friedman,
        pairs,
        best: best.map(|b| methods[b]),
        winner: None,
        level_with_best: Vec::new(),
    };
    if let Some(b) = out.best {
        let significantly_below = |o: MethodId| {
            out.pair(b, o)
                .is_some_and(|(t, p)| p < alpha && t.x_lower())
        };
        out.level_with_best = methods
            .iter()
            .copied()
            .filter(|&o| o == b || !significantly_below(o))
            .collect();
        let global = out.friedman.is_some_and(|f| f.p_value < alpha);
        if global && methods.len() >= 2 && out.level_with_best == [b] {
            out.winner = Some(b);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use MethodId::*;

    fn samples(values: &[(MethodId, Vec<f64>)]) -> Vec<(MethodId, Samples)> {
        values
            .iter()
            .map(|(m, v)| {
                (
                    *m,
                    v.iter()
                        .enumerate()
                        .map(|(i, x)| (i as u64 + 1, *x))
                        .collect(),
                )
            })
            .collect()
    }

    /// Deterministic noise in [-0.5, 0.5).
    fn noise(i: usize, salt: u64) -> f64 {
        let mut s = (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt;
        s ^= s >> 29;
        s = s.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        s ^= s >> 32;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    #[test]
    fn a_clearly_better_method_wins_over_eight_seeds() {
        let v = |shift: f64, salt: u64| -> Vec<f64> {
            (0..8).map(|i| 1.0 + shift + 0.1 * noise(i, salt)).collect()
        };
        let t = test_cell(
            &samples(&[(Distmesh, v(0.5, 1)), (Ccvt2, v(0.0, 2)), (Vtm, v(0.6, 3))]),
            ALPHA,
        );
        assert_eq!(t.seeds, 8);
        assert_eq!(t.best, Some(Ccvt2));
        assert_eq!(t.winner, Some(Ccvt2), "{t:?}");
        assert!(t.friedman.unwrap().p_value < ALPHA);
        // Three pairs; CCVT(2) is below both others in all 8 seeds: raw p = 2/2⁸.
        assert_eq!(t.pairs.len(), 3);
        let (w, p) = t.pair(Ccvt2, Distmesh).unwrap();
        assert!(w.x_lower() && (w.p_value - 2.0 / 256.0).abs() < 1e-15 && p < ALPHA);
        assert_eq!(t.level_with_best, vec![Ccvt2]);
    }

    #[test]
    fn identical_methods_tie() {
        let v: Vec<f64> = (0..8).map(|i| 1.0 + noise(i, 7)).collect();
        let t = test_cell(
            &samples(&[(Distmesh, v.clone()), (Ccvt2, v.clone())]),
            ALPHA,
        );
        assert_eq!(t.winner, None);
        assert_eq!(t.friedman.unwrap().p_value, 1.0);
        assert_eq!(t.level_with_best, vec![Distmesh, Ccvt2]);
        // Two methods apart from a third: both level with each other, so no winner either.
        let far: Vec<f64> = v.iter().map(|x| x + 10.0).collect();
        let t = test_cell(
            &samples(&[(Distmesh, v.clone()), (Ccvt2, v), (Vtm, far)]),
            ALPHA,
        );
        assert_eq!(t.winner, None);
        assert_eq!(t.level_with_best, vec![Distmesh, Ccvt2]);
    }

    #[test]
    fn too_few_seeds_cannot_win() {
        // Five seeds, always lower: the smallest two-sided p is 2/2⁵ = 0.0625 > α.
        let t = test_cell(
            &samples(&[
                (Distmesh, vec![1.0, 1.1, 1.2, 1.3, 1.4]),
                (Ccvt2, vec![2.0, 2.1, 2.2, 2.3, 2.4]),
            ]),
            ALPHA,
        );
        assert_eq!(t.best, Some(Distmesh));
        assert_eq!(t.winner, None);
        // One seed: no test at all.
        let t = test_cell(
            &samples(&[(Distmesh, vec![1.0]), (Ccvt2, vec![2.0])]),
            ALPHA,
        );
        assert!(t.friedman.is_none());
        assert_eq!((t.best, t.winner), (Some(Distmesh), None));
    }

    #[test]
    fn pairing_drops_seeds_a_method_lacks() {
        let mut s = samples(&[
            (Distmesh, (0..12).map(|i| f64::from(i as u8)).collect()),
            (Ccvt2, (0..12).map(|i| 100.0 + f64::from(i as u8)).collect()),
        ]);
        s[1].1.remove(&3);
        s[0].1.insert(5, f64::NAN);
        let t = test_cell(&s, ALPHA);
        assert_eq!(t.seeds, 10);
        assert_eq!(t.winner, Some(Distmesh));
        // The winner does not depend on the order the methods are given in.
        let mut r = s.clone();
        r.reverse();
        assert_eq!(test_cell(&r, ALPHA).winner, Some(Distmesh));
    }

    #[test]
    fn rows_are_grouped_by_cell() {
        use crate::testutil::fake_row;
        let rows: Vec<Row> = (1..=3)
            .flat_map(|s| {
                [
                    fake_row("circle", 19, Ccvt2, s, Kind::Exact, s as f64),
                    fake_row("circle", 19, Ccvt2, s, Kind::Sampled, 9.0),
                    fake_row("circle", 88, Ccvt2, s, Kind::Exact, 9.0),
                    fake_row("circle", 19, Vtm, s, Kind::Exact, 0.0),
                ]
            })
            .collect();
        let c = cell_samples(&rows, "circle", 19, Kind::Exact, Measure::Lambda, &[Ccvt2]);
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].0, Ccvt2);
        let lam: Vec<f64> = c[0].1.values().copied().collect();
        assert_eq!(lam, vec![0.5 + 1.0 / 3.0, 1.0 + 1.0 / 3.0, 1.5 + 1.0 / 3.0]);
    }
}
