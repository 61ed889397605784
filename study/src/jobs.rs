//! The deterministic job list and its sharding.
use crate::paper::{region_names, TableSpec, TABLES};
use crate::{MethodId, StudyError};

/// One mesh to make and measure: a method on a paper region at the paper's K with one seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Job {
    /// The paper table this job fills.
    pub table: &'static TableSpec,
    /// The method.
    pub method: MethodId,
    /// The seed of the method's random choices.
    pub seed: u64,
}

impl Job {
    /// Region name.
    pub fn region(&self) -> &'static str {
        self.table.region
    }
    /// Requested K.
    pub fn k(&self) -> usize {
        self.table.k
    }
    /// "circle K=88 ccvt2 seed 1".
    pub fn label(&self) -> String {
        format!(
            "{} K={} {} seed {}",
            self.region(),
            self.k(),
            self.method.name(),
            self.seed
        )
    }
    /// Rough relative cost, for starting the expensive jobs first.
    pub fn cost(&self) -> f64 {
        self.k() as f64 * self.method.cost_weight()
    }
}

/// Parse `--regions a,b` into region names (table order, repeats dropped); unknown names are
/// an error listing the valid ones.
pub fn parse_regions(list: &str) -> Result<Vec<&'static str>, StudyError> {
    let valid = region_names();
    let mut chosen = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let r = valid
            .iter()
            .find(|v| v.eq_ignore_ascii_case(name))
            .ok_or_else(|| StudyError::UnknownRegion {
                name: name.to_string(),
                valid: valid.join(", "),
            })?;
        chosen.push(*r);
    }
    if chosen.is_empty() {
        return Err(StudyError::BadOption(format!(
            "--regions is empty; valid regions: {}",
            valid.join(", ")
        )));
    }
    Ok(valid.into_iter().filter(|v| chosen.contains(v)).collect())
}

/// Every (table, method, seed) for the chosen regions and methods with seeds 1..=`seeds`,
/// ordered by table, then method (column order), then seed. The order is part of the
/// sharding contract: the same arguments always give the same list.
pub fn job_list(regions: &[&str], methods: &[MethodId], seeds: u64) -> Vec<Job> {
    let mut methods = methods.to_vec();
    methods.sort();
    methods.dedup();
    let mut jobs = Vec::new();
    for table in TABLES.iter().filter(|t| regions.contains(&t.region)) {
        for &method in &methods {
            for seed in 1..=seeds {
                jobs.push(Job {
                    table,
                    method,
                    seed,
                });
            }
        }
    }
    jobs
}

/// `--shard I/N`: the I-th of N interleaved parts of the job list (1-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// I, 1..=N.
    pub index: usize,
    /// N ≥ 1.
    pub count: usize,
}

impl Shard {
    /// Parse "I/N".
    pub fn parse(s: &str) -> Result<Shard, StudyError> {
        let bad = || StudyError::BadShard(s.to_string());
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// True if job number `j` (0-based position in the job list) belongs to this shard:
    /// j mod N = I − 1, so shards interleave and each gets a mix of cheap and costly jobs.
    pub fn owns(&self, j: usize) -> bool {
        j % self.count == self.index - 1
    }

    /// The jobs of this shard, in list order.
    pub fn select(&self, jobs: &[Job]) -> Vec<Job> {
        jobs.iter()
            .enumerate()
            .filter(|(j, _)| self.owns(*j))
            .map(|(_, job)| *job)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_job_list_is_tables_by_methods_by_seeds() {
        let all = region_names();
        let jobs = job_list(&all, &MethodId::ALL, 2);
        assert_eq!(jobs.len(), 12 * 7 * 2);
        assert_eq!(jobs[0].label(), "circle K=19 refine seed 1");
        assert_eq!(jobs[1].label(), "circle K=19 refine seed 2");
        assert_eq!(jobs[2].label(), "circle K=19 distmesh seed 1");
        assert_eq!(jobs.last().unwrap().label(), "lake K=1109 ccvt seed 2");
        // Same arguments, same list; method order on the command line does not matter.
        let rev: Vec<MethodId> = MethodId::ALL.iter().rev().copied().collect();
        assert_eq!(job_list(&all, &rev, 2), jobs);
    }

    #[test]
    fn region_filter_keeps_every_table_of_a_region() {
        let r = parse_regions("lake,Circle").unwrap();
        assert_eq!(r, vec!["circle", "lake"]);
        let jobs = job_list(&r, &[MethodId::Ccvt2], 1);
        let ks: Vec<usize> = jobs.iter().map(|j| j.k()).collect();
        assert_eq!(ks, vec![19, 88, 362, 1109]);
        let e = parse_regions("circle,moon").unwrap_err().to_string();
        assert!(e.contains("'moon'") && e.contains("square_two_hex"), "{e}");
        assert!(parse_regions("").is_err());
    }

    #[test]
    fn shards_are_disjoint_and_cover_the_list() {
        let jobs = job_list(&region_names(), &MethodId::ALL, 3);
        for n in [1, 2, 3, 7, 8, 13, jobs.len(), jobs.len() + 5] {
            let mut seen = vec![0usize; jobs.len()];
            let mut total = 0;
            for i in 1..=n {
                let shard = Shard { index: i, count: n };
                let part = shard.select(&jobs);
                total += part.len();
                for (j, job) in jobs.iter().enumerate() {
                    if shard.owns(j) {
                        seen[j] += 1;
                        assert!(part.contains(job));
                    }
                }
                // Balanced: sizes differ by at most one.
                assert!(part.len() == jobs.len() / n || part.len() == jobs.len() / n + 1);
            }
            assert_eq!(total, jobs.len());
            assert!(seen.iter().all(|&c| c == 1), "n = {n}");
        }
    }

    #[test]
    fn shard_parsing() {
        assert_eq!(Shard::parse("3/8").unwrap(), Shard { index: 3, count: 8 });
        assert_eq!(
            Shard::parse(" 1 / 1 ").unwrap(),
            Shard { index: 1, count: 1 }
        );
        for bad in ["0/8", "9/8", "1/0", "3", "a/b", "3/8/1", ""] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }
}
