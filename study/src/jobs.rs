//! The deterministic job list and its sharding.
use crate::paper::{region_names, TableSpec, TABLES};
use crate::{output, record, MethodId, StudyError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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

/// What a sharded run writes to `DIR/csv/shard.csv`: the shard it ran and the arguments
/// that define the job list it is a part of. Shard directories look alike otherwise, so
/// without it a merge cannot tell every shard of a run from a set with one left out, or
/// with shards of a run split another way or asked for other jobs.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardRecord {
    /// I, 1..=N.
    pub index: usize,
    /// N.
    pub count: usize,
    /// The last seed of both job lists.
    pub seeds: u64,
    /// Their first seed.
    pub first_seed: u64,
    /// The regions of the paper's jobs, comma-separated in table order; empty if the run
    /// has none of them.
    pub regions: String,
    /// The methods of the paper's jobs, comma-separated in column order; empty as `regions`.
    pub methods: String,
    /// The methods of the graded jobs, as `methods`; empty if the run has none of them.
    pub graded_methods: String,
}

/// The header line of `shard.csv`.
pub const SHARD_HEADER: &str = "index,count,seeds,first_seed,regions,methods,graded_methods";

impl ShardRecord {
    /// The record of `shard` of the paper's jobs over `regions` × `methods` (`None`: the run
    /// has none) and the graded jobs of `graded_methods` (`None`: none), seeds
    /// `first_seed..=seeds`. Lists are written in the job list's order, so that arguments
    /// giving the same job list give the same record.
    pub fn new(
        shard: Shard,
        paper: Option<(&[&str], &[MethodId])>,
        graded_methods: Option<&[MethodId]>,
        seeds: u64,
        first_seed: u64,
    ) -> ShardRecord {
        let names = |methods: &[MethodId]| {
            let mut m = methods.to_vec();
            m.sort();
            m.dedup();
            m.iter().map(|m| m.name()).collect::<Vec<_>>().join(",")
        };
        let (regions, methods) = match paper {
            Some((r, m)) if !r.is_empty() && !m.is_empty() => (
                region_names()
                    .into_iter()
                    .filter(|n| r.contains(n))
                    .collect::<Vec<_>>()
                    .join(","),
                names(m),
            ),
            _ => (String::new(), String::new()),
        };
        ShardRecord {
            index: shard.index,
            count: shard.count,
            seeds,
            first_seed,
            regions,
            methods,
            graded_methods: graded_methods.map_or(String::new(), names),
        }
    }

    /// "shard 2/4".
    pub fn shard_text(&self) -> String {
        format!("shard {}/{}", self.index, self.count)
    }

    /// The job list, for messages: "seeds 1..=3; tables of circle with refine,vtm; no
    /// graded jobs".
    pub fn jobs_text(&self) -> String {
        let paper = match self.regions.is_empty() {
            true => "none of the paper's tables".to_string(),
            false => format!("tables of {} with {}", self.regions, self.methods),
        };
        let graded = match self.graded_methods.is_empty() {
            true => "no graded jobs".to_string(),
            false => format!("graded jobs with {}", self.graded_methods),
        };
        format!(
            "seeds {}..={}; {paper}; {graded}",
            self.first_seed, self.seeds
        )
    }

    /// True if both are parts of the same job list (whichever parts they are).
    pub fn same_jobs(&self, other: &ShardRecord) -> bool {
        (
            self.seeds,
            self.first_seed,
            &self.regions,
            &self.methods,
            &self.graded_methods,
        ) == (
            other.seeds,
            other.first_seed,
            &other.regions,
            &other.methods,
            &other.graded_methods,
        )
    }

    /// Write `DIR/csv/shard.csv`.
    pub fn write(&self, dir: &Path) -> Result<PathBuf, StudyError> {
        let p = output::shard_csv(dir);
        output::write_atomic(&p, &record::to_csv(std::slice::from_ref(self))?)?;
        Ok(p)
    }

    /// Read `DIR/csv/shard.csv`; `None` if there is none.
    pub fn read(dir: &Path) -> Result<Option<ShardRecord>, StudyError> {
        let p = output::shard_csv(dir);
        if !p.exists() {
            return Ok(None);
        }
        let records: Vec<ShardRecord> = record::read_csv_with_header(&p, SHARD_HEADER)?;
        match records.as_slice() {
            [r] if r.index >= 1 && r.index <= r.count => Ok(Some(r.clone())),
            _ => Err(StudyError::Csv {
                path: p.display().to_string(),
                message: "expected one record of a shard I/N with 1 <= I <= N".into(),
            }),
        }
    }
}

/// Check that `shards` (each a directory and its record) are every shard of one job list
/// split N ways, each once: a merge of anything less would pass for the whole run.
pub fn check_shard_set(shards: &[(&Path, ShardRecord)]) -> Result<(), StudyError> {
    let Some((first_dir, first)) = shards.first() else {
        return Ok(());
    };
    let bad = |m: String| Err(StudyError::ShardSet(m));
    for (dir, r) in &shards[1..] {
        if r.count != first.count {
            return bad(format!(
                "{} is {} but {} is {}: shards of a run split into another number of parts; \
                 merge the shards of one run",
                first_dir.display(),
                first.shard_text(),
                dir.display(),
                r.shard_text()
            ));
        }
        if !r.same_jobs(first) {
            return bad(format!(
                "{} ({}) and {} ({}) are shards of different job lists, \"{}\" and \"{}\"; \
                 every shard of a run needs the same --regions, --methods, --seeds, \
                 --first-seed and graded options",
                first_dir.display(),
                first.shard_text(),
                dir.display(),
                r.shard_text(),
                first.jobs_text(),
                r.jobs_text()
            ));
        }
    }
    let mut given: BTreeMap<usize, &Path> = BTreeMap::new();
    for (dir, r) in shards {
        if let Some(before) = given.insert(r.index, dir) {
            return bad(format!(
                "{} given twice: {} and {}",
                r.shard_text(),
                before.display(),
                dir.display()
            ));
        }
    }
    let missing: Vec<String> = (1..=first.count)
        .filter(|i| !given.contains_key(i))
        .map(|i| format!("{i}/{}", first.count))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    // A run split a hundred ways and merged from one shard need not list 99 others.
    const LISTED: usize = 10;
    let mut list = missing[..missing.len().min(LISTED)].join(", ");
    if missing.len() > LISTED {
        list.push_str(&format!(" and {} more", missing.len() - LISTED));
    }
    bad(format!(
        "incomplete set of shards: {} {list} missing, {} of {} given (job list \"{}\"); \
         merge every shard of the run",
        if missing.len() == 1 {
            "shard"
        } else {
            "shards"
        },
        given.len(),
        first.count,
        first.jobs_text()
    ))
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

    fn record(index: usize, count: usize, seeds: u64) -> ShardRecord {
        let regions: &[&str] = &["lake", "circle"];
        let methods: &[MethodId] = &[MethodId::Vtm, MethodId::Triangle];
        ShardRecord::new(
            Shard { index, count },
            Some((regions, methods)),
            None,
            seeds,
            1,
        )
    }

    #[test]
    fn a_shard_record_names_the_job_list_in_its_own_order() {
        let r = record(2, 4, 3);
        assert_eq!(
            (r.regions.as_str(), r.methods.as_str()),
            ("circle,lake", "refine,vtm")
        );
        assert_eq!(r.graded_methods, "");
        assert_eq!(
            r.jobs_text(),
            "seeds 1..=3; tables of circle,lake with refine,vtm; no graded jobs"
        );
        // Without the paper's jobs their regions do not matter.
        let graded = |regions: &[&str]| {
            ShardRecord::new(
                Shard { index: 1, count: 2 },
                None,
                Some(&[MethodId::CcvtFast, MethodId::Triangle]),
                1,
                1,
            )
            .same_jobs(&ShardRecord::new(
                Shard { index: 2, count: 2 },
                Some((regions, &[][..])),
                Some(&[MethodId::Triangle, MethodId::CcvtFast]),
                1,
                1,
            ))
        };
        assert!(graded(&["circle"]));
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(ShardRecord::read(dir.path()).unwrap(), None);
        r.write(dir.path()).unwrap();
        assert_eq!(ShardRecord::read(dir.path()).unwrap(), Some(r));
        std::fs::write(output::shard_csv(dir.path()), format!("{SHARD_HEADER}\n")).unwrap();
        assert!(ShardRecord::read(dir.path()).is_err());
    }

    #[test]
    fn a_shard_set_must_be_every_shard_of_one_job_list_once() {
        let dirs: Vec<PathBuf> = (0..6).map(|i| PathBuf::from(format!("s{i}"))).collect();
        let set = |records: &[ShardRecord]| -> Result<(), String> {
            let given: Vec<(&Path, ShardRecord)> = dirs
                .iter()
                .map(PathBuf::as_path)
                .zip(records.iter().cloned())
                .collect();
            check_shard_set(&given).map_err(|e| e.to_string())
        };
        assert_eq!(set(&[]), Ok(()));
        assert_eq!(
            set(&[record(3, 3, 2), record(1, 3, 2), record(2, 3, 2)]),
            Ok(())
        );
        let e = set(&[record(1, 4, 2), record(2, 4, 2)]).unwrap_err();
        assert!(
            e.contains("shards 3/4, 4/4 missing, 2 of 4 given") && e.contains("seeds 1..=2"),
            "{e}"
        );
        let e = set(&[record(1, 2, 2)]).unwrap_err();
        assert!(e.contains("shard 2/2 missing"), "{e}");
        let e = set(&[record(1, 2, 2), record(2, 2, 2), record(2, 2, 2)]).unwrap_err();
        assert!(e.contains("shard 2/2 given twice: s1 and s2"), "{e}");
        let e = set(&[record(1, 2, 2), record(2, 3, 2), record(3, 3, 2)]).unwrap_err();
        assert!(e.contains("s0 is shard 1/2 but s1 is shard 2/3"), "{e}");
        let e = set(&[record(1, 2, 2), record(2, 2, 3)]).unwrap_err();
        assert!(
            e.contains("different job lists")
                && e.contains("seeds 1..=2")
                && e.contains("seeds 1..=3"),
            "{e}"
        );
        let e = set(&[record(1, 100, 2)]).unwrap_err();
        assert!(
            e.contains("2/100, 3/100") && e.contains("and 89 more"),
            "{e}"
        );
    }
}
