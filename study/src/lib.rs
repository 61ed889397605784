//! The study: every method on every paper region at the paper's K, measured exactly and
//! paper-style, written as the paper's Tables 1–12 (Markdown), one CSV of every number,
//! Figures 3–7 and a summary with the paper's "keeping score" count; a graded comparison
//! beyond the paper ([`graded`]): meshes that follow a size field, measured against it; and,
//! on request, the real Triangle and Gmsh beside the stand-ins ([`peers`]).
//!
//! The pipeline is split so that sharded runs and their merge share one path:
//! [`run_study`] runs jobs and writes `DIR/csv/*.csv` and `DIR/meshes/*`; [`merge`] combines
//! several such directories; [`write_report`] turns a directory's CSV and meshes into tables,
//! figures and `summary.md`.
#![forbid(unsafe_code)]

mod error;
pub mod fidelity;
pub mod figures;
pub mod graded;
pub mod inference;
pub mod jobs;
mod measure;
pub mod methods;
pub mod output;
pub mod paper;
pub mod peers;
pub mod record;
pub mod run;
pub mod significance;
pub mod stats;
pub mod summary;
pub mod tables;

pub use error::StudyError;
pub use jobs::{job_list, parse_regions, Job, Shard, ShardRecord};
pub use measure::{scaled_label, superscript, Measure};
pub use methods::MethodId;
pub use record::{Failure, Kind, Row};
pub use run::{run_job, run_jobs, Event, JobResult};

use figures::MeshSet;
use paper::{PaperTables, TABLES};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// What [`run_study`] should run and where it writes.
#[derive(Clone, Debug)]
pub struct StudyOptions {
    /// Region names (all ten by default).
    pub regions: Vec<&'static str>,
    /// Methods (all seven by default).
    pub methods: Vec<MethodId>,
    /// The last seed: seeds `first_seed..=seeds` are run.
    pub seeds: u64,
    /// The first seed (1 by default). Above 1, rows of lower seeds already in the output
    /// CSV are kept, so a run can be extended to more seeds without redoing the ones it has.
    pub first_seed: u64,
    /// Output directory.
    pub out: PathBuf,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Run only this shard and write only the CSV (and meshes).
    pub shard: Option<Shard>,
    /// Discard rows already in `DIR/csv/metrics.csv` (and `graded.csv`) instead of
    /// updating them.
    pub fresh: bool,
    /// Run the paper's tables (true by default).
    pub paper: bool,
    /// Run the graded comparison ([`graded`], true by default); `regions` does not apply to it.
    pub graded: bool,
    /// Methods of the graded comparison ([`graded::GRADED_METHODS`] by default).
    pub graded_methods: Vec<MethodId>,
    /// Also mesh the tables of `regions` with the real Triangle and Gmsh ([`peers`]; false by
    /// default). Not with a shard.
    pub real_peers: bool,
    /// The Python interpreter for [`peers`] (`None`: [`peers::default_python`]).
    pub python: Option<PathBuf>,
}

impl Default for StudyOptions {
    fn default() -> Self {
        StudyOptions {
            regions: paper::region_names(),
            methods: MethodId::ALL.to_vec(),
            seeds: 1,
            first_seed: 1,
            out: PathBuf::from("results"),
            threads: None,
            shard: None,
            fresh: false,
            paper: true,
            graded: true,
            graded_methods: graded::GRADED_METHODS.to_vec(),
            real_peers: false,
            python: None,
        }
    }
}

impl StudyOptions {
    /// The jobs these options select, in the deterministic list order.
    pub fn jobs(&self) -> Vec<Job> {
        if !self.paper {
            return Vec::new();
        }
        let mut all = job_list(&self.regions, &self.methods, self.seeds);
        all.retain(|j| j.seed >= self.first_seed);
        match self.shard {
            Some(s) => s.select(&all),
            None => all,
        }
    }

    /// The graded jobs these options select, in their deterministic list order.
    pub fn graded_jobs(&self) -> Vec<graded::GradedJob> {
        if !self.graded {
            return Vec::new();
        }
        let mut all = graded::graded_jobs(&self.graded_methods, self.seeds);
        all.retain(|j| j.seed >= self.first_seed);
        graded::shard_graded(self.shard, all)
    }

    /// What a run with these options writes to `DIR/csv/shard.csv`: `None` without a shard.
    pub fn shard_record(&self) -> Option<ShardRecord> {
        let shard = self.shard?;
        Some(ShardRecord::new(
            shard,
            self.paper
                .then_some((self.regions.as_slice(), self.methods.as_slice())),
            self.graded.then_some(self.graded_methods.as_slice()),
            self.seeds,
            self.first_seed,
        ))
    }
}

/// What a run or merge did.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// Jobs run (0 for a merge).
    pub jobs: usize,
    /// Failed jobs of this run (or in the merged inputs).
    pub failures: Vec<Failure>,
    /// Files written.
    pub written: Vec<PathBuf>,
    /// Messages for the user (skipped figures, missing meshes).
    pub notes: Vec<String>,
}

/// `path` (a file or directory every study output has) is missing: no study wrote there.
fn not_a_study(path: &Path, missing: &str) -> StudyError {
    StudyError::io(
        path,
        std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("no {missing} here; is this a study output directory?"),
        ),
    )
}

/// Refuse a directory without `csv/metrics.csv`: no study wrote there (a mistyped path).
fn require_metrics(dir: &Path) -> Result<(), StudyError> {
    let m = output::metrics_csv(dir);
    match m.exists() {
        true => Ok(()),
        false => Err(not_a_study(&m, "metrics.csv")),
    }
}

/// Refuse to merge `dirs` unless their shards are every shard of one run, once each
/// ([`jobs::check_shard_set`]). A directory without a shard record holds a whole run if a
/// report was drawn in it (every unsharded run and every merge draws one, a shard never
/// does); otherwise it is a shard of a version that did not record its place, or of a run
/// that stopped, and whether the set is complete cannot be told.
fn check_shards(dirs: &[PathBuf]) -> Result<(), StudyError> {
    let mut shards = Vec::new();
    for d in dirs {
        match ShardRecord::read(d)? {
            Some(r) => shards.push((d.as_path(), r)),
            None if output::summary_md(d).exists() || graded::graded_md_path(d).exists() => {}
            None => {
                return Err(StudyError::ShardSet(format!(
                    "{}: no {} and no report, so it is a shard of an older version of the \
                     study (or of a run that stopped) and which shard it is cannot be \
                     checked; rerun it",
                    d.display(),
                    output::shard_csv(d).display()
                )))
            }
        }
    }
    jobs::check_shard_set(&shards)
}

/// Read `DIR/csv/metrics.csv` and `DIR/csv/failures.csv` (either may be absent: empty).
pub fn read_dir_csv(dir: &Path) -> Result<(Vec<Row>, Vec<Failure>), StudyError> {
    let m = output::metrics_csv(dir);
    let rows = if m.exists() {
        record::read_csv_with_header(&m, record::METRICS_HEADER)?
    } else {
        Vec::new()
    };
    let f = output::failures_csv(dir);
    let failures = if f.exists() {
        record::read_csv_with_header(&f, record::FAILURES_HEADER)?
    } else {
        Vec::new()
    };
    Ok((rows, failures))
}

fn write_csvs(
    dir: &Path,
    rows: &mut [Row],
    failures: &mut [Failure],
    written: &mut Vec<PathBuf>,
) -> Result<(), StudyError> {
    record::sort_rows(rows);
    record::sort_failures(failures);
    let m = output::metrics_csv(dir);
    output::write_atomic(&m, &record::rows_csv(rows)?)?;
    let f = output::failures_csv(dir);
    output::write_atomic(&f, &record::failures_csv(failures)?)?;
    written.extend([m, f]);
    Ok(())
}

/// Run the selected jobs in parallel and write `out/csv/metrics.csv`, `out/csv/failures.csv`
/// and `out/meshes/*.node|.ele|.poly`. Without a shard, rows of (table, method, seed) that
/// were not run are kept from an existing CSV (unless `fresh`), so rerunning one method or
/// one seed updates only those rows; then tables, figures and the summary are written from the whole
/// CSV. With a shard, the CSV holds exactly this shard's rows and nothing else is drawn.
pub fn run_study(
    opts: &StudyOptions,
    on_event: &(dyn Fn(Event<'_>) + Sync),
) -> Result<Outcome, StudyError> {
    if opts.seeds == 0 {
        return Err(StudyError::BadOption("--seeds must be at least 1".into()));
    }
    if opts.first_seed == 0 || opts.first_seed > opts.seeds {
        return Err(StudyError::BadOption(format!(
            "--first-seed must be between 1 and --seeds ({})",
            opts.seeds
        )));
    }
    if opts.real_peers && opts.shard.is_some() {
        return Err(StudyError::BadOption(
            "--real-peers runs without --shard (its runs are few and cheap)".into(),
        ));
    }
    // An output directory that cannot be made fails now, not after every job has run.
    output::create_dir(&opts.out)?;
    // A record of an earlier sharded run here would pass this directory off as that shard.
    output::remove_if_present(&output::shard_csv(&opts.out))?;
    let jobs = opts.jobs();
    let names: Vec<&'static str> = {
        let set: BTreeSet<&'static str> = jobs.iter().map(|j| j.region()).collect();
        set.into_iter().collect()
    };
    let regions = run::load_regions(&names)?;
    let results = run_jobs(&jobs, &regions, opts.threads, on_event)?;
    let mut out = Outcome {
        jobs: jobs.len(),
        ..Outcome::default()
    };
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for r in &results {
        match &r.outcome {
            Ok(o) => {
                rows.extend(o.rows.iter().cloned());
                let base = output::mesh_base(
                    &opts.out,
                    r.job.region(),
                    r.job.k(),
                    r.job.method,
                    r.job.seed,
                );
                output::create_dir(base.parent().unwrap_or(&opts.out))?;
                cvtmesh::io::write_triangle(&o.mesh, &base)?;
            }
            Err(_) => failures.extend(r.failure()),
        }
    }
    out.failures = failures.clone();
    if opts.shard.is_none() && !opts.fresh {
        let ran: BTreeSet<(String, usize, String)> = jobs
            .iter()
            .map(|j| (j.region().to_string(), j.k(), j.method.name().to_string()))
            .collect();
        let (old_rows, old_failures) = read_dir_csv(&opts.out)?;
        // Keep the cells this run did not touch, and in the cells it did, the seeds it did
        // not run: rerunning seed 1 of one method in a run of three seeds updates that seed.
        let keep = |region: &str, k: usize, method: &str, seed: u64| {
            !(opts.first_seed..=opts.seeds).contains(&seed)
                || !ran.contains(&(region.to_string(), k, method.to_string()))
        };
        rows.extend(
            old_rows
                .into_iter()
                .filter(|r| keep(&r.region, r.K_requested, &r.method, r.seed)),
        );
        failures.extend(
            old_failures
                .into_iter()
                .filter(|f| keep(&f.region, f.K_requested, &f.method, f.seed)),
        );
    }
    // Without the paper part an unsharded run leaves metrics.csv alone (`--fresh` would
    // otherwise empty it); a shard still writes one, which merge expects in every directory.
    if opts.paper || opts.shard.is_some() {
        write_csvs(&opts.out, &mut rows, &mut failures, &mut out.written)?;
    }
    run_graded_part(opts, on_event, &mut out)?;
    // Written last, so that a shard which stopped before its CSVs has none.
    if let Some(r) = opts.shard_record() {
        out.written.push(r.write(&opts.out)?);
    }
    if opts.real_peers {
        run_peers_part(opts, on_event, &mut out)?;
    }
    if opts.shard.is_none() {
        let report = write_report(&opts.out)?;
        out.written.extend(report.written);
        out.notes.extend(report.notes);
    }
    Ok(out)
}

/// The graded part of [`run_study`]: run its jobs, write their meshes and `graded.csv`
/// (keeping, as for the paper's rows, the cells and seeds not run).
fn run_graded_part(
    opts: &StudyOptions,
    on_event: &(dyn Fn(Event<'_>) + Sync),
    out: &mut Outcome,
) -> Result<(), StudyError> {
    let jobs = opts.graded_jobs();
    if jobs.is_empty() {
        return Ok(());
    }
    let results = graded::run_graded(&jobs, opts.threads, on_event)?;
    graded::write_graded_meshes(&opts.out, &results)?;
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for r in &results {
        match &r.outcome {
            Ok((row, _)) => rows.push(row.clone()),
            Err(_) => failures.extend(r.failure()),
        }
    }
    out.jobs += jobs.len();
    out.failures.extend(failures.iter().cloned());
    if opts.shard.is_none() && !opts.fresh {
        let ran: BTreeSet<(&str, &str)> = jobs
            .iter()
            .map(|j| (j.case.name, j.method.name()))
            .collect();
        let keep = |case: &str, method: &str, seed: u64| {
            !(opts.first_seed..=opts.seeds).contains(&seed) || !ran.contains(&(case, method))
        };
        let (old_rows, old_failures) = graded::read_graded(&opts.out)?;
        rows.extend(
            old_rows
                .into_iter()
                .filter(|r| keep(&r.case, &r.method, r.seed)),
        );
        failures.extend(
            old_failures
                .into_iter()
                .filter(|f| keep(&f.region, &f.method, f.seed)),
        );
    }
    out.written
        .extend(graded::write_graded(&opts.out, &mut rows, &mut failures)?);
    Ok(())
}

/// The real tools' part of [`run_study`]: check the interpreter (without it, a note and
/// nothing else), run both tools on the selected tables and write `csv/real_peers.csv`,
/// keeping the rows of tables not run (unless `fresh`).
fn run_peers_part(
    opts: &StudyOptions,
    on_event: &(dyn Fn(Event<'_>) + Sync),
    out: &mut Outcome,
) -> Result<(), StudyError> {
    let python = opts.python.clone().unwrap_or_else(peers::default_python);
    let tools = match peers::check_python(&python) {
        Ok(t) => t,
        Err(why) => {
            out.notes.push(why);
            return Ok(());
        }
    };
    out.notes.push(format!(
        "real peers: {} with {}",
        tools.python.display(),
        tools.versions
    ));
    let ran = peers::run_peers(&tools, &opts.out, &opts.regions, &|label, ok, secs| {
        on_event(Event::PeerFinished(label, ok, secs))
    });
    // The stand-ins' results are written already; a scratch directory that cannot be made
    // must not turn the run into a failure.
    let mut rows = match ran {
        Ok(rows) => rows,
        Err(e) => {
            out.notes.push(format!("real peers skipped: {e}"));
            return Ok(());
        }
    };
    let failed = rows.iter().filter(|r| !r.error.is_empty()).count();
    if failed > 0 {
        out.notes.push(format!(
            "real peers: {failed} of {} runs failed (listed in real_peers.md)",
            rows.len()
        ));
    }
    if !opts.fresh {
        let ran: BTreeSet<u8> = rows.iter().map(|r| r.table).collect();
        rows.extend(
            peers::read_peers(&opts.out)?
                .into_iter()
                .filter(|r| !ran.contains(&r.table)),
        );
    }
    out.written.push(peers::write_peers(&opts.out, &mut rows)?);
    Ok(())
}

/// Combine the CSVs and meshes of shard directories `dirs` into `out` (rows sorted as an
/// unsharded run writes them; a row present twice is an error), then write the report.
/// The shards must be every shard of one run, each once (`csv/shard.csv`); directories of
/// unsharded runs or merges may be given beside them.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Outcome, StudyError> {
    if dirs.is_empty() {
        return Err(StudyError::BadOption(
            "merge needs at least one directory".into(),
        ));
    }
    let mut result = Outcome::default();
    // Every directory read, its shards found to be every shard of one run, and the merge
    // checked (a row in two of them is refused) before anything is written to `out`.
    for d in dirs {
        require_metrics(d)?;
    }
    check_shards(dirs)?;
    let mut read = Vec::with_capacity(dirs.len());
    for d in dirs {
        read.push((d, read_dir_csv(d)?));
    }
    let mut graded_read = Vec::new();
    for d in dirs.iter().filter(|d| graded::graded_csv_path(d).exists()) {
        graded_read.push((d, graded::read_graded(d)?));
    }
    let mut rows = record::merge_rows(read.iter().map(|(_, (r, _))| r.clone()).collect())?;
    let graded_rows = match graded_read.is_empty() {
        true => None,
        false => Some(graded::merge_graded(
            graded_read.iter().map(|(_, (g, _))| g.clone()).collect(),
        )?),
    };
    let mut failures = Vec::new();
    for (d, (shard_rows, f)) in &read {
        // Copy this shard's meshes (those of its rows) unless merging in place.
        if d.as_path() != out {
            for r in shard_rows.iter().filter(|r| r.kind == Kind::Exact) {
                let Some(method) = r.method_id() else {
                    continue;
                };
                let src = output::mesh_node(d, &r.region, r.K_requested, method, r.seed);
                if !src.exists() {
                    result.notes.push(format!(
                        "{}: missing; its figure panel will be empty",
                        src.display()
                    ));
                    continue;
                }
                let mesh = cvtmesh::io::read_triangle(&src)?;
                let base = output::mesh_base(out, &r.region, r.K_requested, method, r.seed);
                output::create_dir(base.parent().unwrap_or(out))?;
                cvtmesh::io::write_triangle(&mesh, &base)?;
            }
        }
        failures.extend(f.iter().cloned());
    }
    result.failures = failures.clone();
    write_csvs(out, &mut rows, &mut failures, &mut result.written)?;
    if let Some(mut g) = graded_rows {
        let mut graded_failures = Vec::new();
        for (d, (shard_rows, f)) in &graded_read {
            if d.as_path() != out {
                graded::copy_graded_meshes(d, out, shard_rows, &mut result.notes)?;
            }
            graded_failures.extend(f.iter().cloned());
        }
        result.failures.extend(graded_failures.iter().cloned());
        result
            .written
            .extend(graded::write_graded(out, &mut g, &mut graded_failures)?);
    }
    // Merged into one of its shards, or over an old shard, `out` now holds the whole run.
    output::remove_if_present(&output::shard_csv(out))?;
    let report = write_report(out)?;
    result.written.extend(report.written);
    result.notes.extend(report.notes);
    Ok(result)
}

/// Load the meshes to draw: for each (region, K, method) with exact rows, the lowest seed's
/// mesh from `dir/meshes`. Missing files become notes.
pub fn load_meshes(
    dir: &Path,
    rows: &[Row],
    notes: &mut Vec<String>,
) -> Result<MeshSet, StudyError> {
    let mut lowest: BTreeMap<(String, usize, MethodId), u64> = BTreeMap::new();
    for r in rows.iter().filter(|r| r.kind == Kind::Exact) {
        if let Some(m) = r.method_id() {
            let e = lowest
                .entry((r.region.clone(), r.K_requested, m))
                .or_insert(r.seed);
            *e = (*e).min(r.seed);
        }
    }
    let mut set = MeshSet::new();
    for ((region, k, method), seed) in lowest {
        let node = output::mesh_node(dir, &region, k, method, seed);
        if !node.exists() {
            notes.push(format!(
                "{}: missing, so its figure panel is left empty",
                node.display()
            ));
            continue;
        }
        set.insert((region, k, method), cvtmesh::io::read_triangle(&node)?);
    }
    Ok(set)
}

/// Write `dir/tables/table_NN.md`, `dir/summary.md`, `dir/fidelity.md`, `dir/graded.md` and
/// `dir/figures/*` from `dir/csv/*.csv` and `dir/meshes/*`; `summary.md` and `fidelity.md`
/// only if the directory has a row or failure of the paper's tables.
pub fn write_report(dir: &Path) -> Result<Outcome, StudyError> {
    // Every study writes `csv/` (a graded-only one no metrics.csv): without it, no study
    // wrote here (a mistyped path), and an empty report would hide that.
    let csv = dir.join("csv");
    if !csv.is_dir() {
        return Err(not_a_study(&csv, "csv/"));
    }
    let (rows, failures) = read_dir_csv(dir)?;
    let paper = PaperTables::embedded()?;
    let agg = stats::Aggregate::from_rows(&rows);
    let mut out = Outcome {
        failures: failures.clone(),
        ..Outcome::default()
    };
    let mut methods: Vec<MethodId> = rows
        .iter()
        .filter_map(Row::method_id)
        .chain(failures.iter().filter_map(|f| MethodId::parse(&f.method)))
        .collect();
    methods.sort();
    methods.dedup();
    let present = |t: &paper::TableSpec| {
        rows.iter()
            .any(|r| r.region == t.region && r.K_requested == t.k)
            || failures
                .iter()
                .any(|f| f.region == t.region && f.K_requested == t.k)
    };
    let tables: Vec<&paper::TableSpec> = TABLES.iter().filter(|t| present(t)).collect();
    for t in &tables {
        let md = tables::render_table(t, &agg, &paper, &methods, &failures);
        let p = output::table_md(dir, t.number);
        output::write_atomic(&p, md.as_bytes())?;
        out.written.push(p);
    }
    // Without a row or failure of the paper's tables (a graded-only run) both files would
    // be headings over empty tables, read as a run whose methods produced nothing.
    if rows.is_empty() && failures.is_empty() {
        out.notes.push(format!(
            "{}: no results of the paper's tables in csv/metrics.csv, so no summary.md or \
             fidelity.md",
            dir.display()
        ));
    } else {
        let p = output::summary_md(dir);
        output::write_atomic(
            &p,
            summary::render_summary(&rows, &paper, &tables, &methods, &failures).as_bytes(),
        )?;
        out.written.push(p);
        let fid = |b| fidelity::compare(&rows, &paper, &tables, b);
        let (main, sampled, exact) = (
            fid(fidelity::Basis::ExactPaperScale),
            fid(fidelity::Basis::Sampled),
            fid(fidelity::Basis::Exact),
        );
        let p = output::fidelity_md(dir);
        let md = fidelity::render_fidelity(
            &main,
            &sampled,
            &exact,
            &tables,
            &paper,
            &tables::seed_list(&agg.all_seeds()),
        );
        output::write_atomic(&p, md.as_bytes())?;
        out.written.push(p);
        let p = output::fidelity_csv(dir);
        let all: Vec<fidelity::Fidelity> = main.into_iter().chain(sampled).chain(exact).collect();
        output::write_atomic(&p, &fidelity::fidelity_csv(&all))?;
        out.written.push(p);
        if agg.all_seeds().len() >= 2 {
            let p = output::significance_csv(dir);
            output::write_atomic(&p, &summary::significance_csv(&rows, &tables, &methods))?;
            out.written.push(p);
        }
    }
    let meshes = load_meshes(dir, &rows, &mut out.notes)?;
    let names: BTreeSet<&'static str> = tables.iter().map(|t| t.region).collect();
    let regions = run::load_regions(&names.into_iter().collect::<Vec<_>>())?;
    out.written
        .extend(figures::draw_figures(dir, &regions, &meshes, &methods)?);
    out.written
        .extend(graded::write_graded_report(dir, &mut out.notes)?);
    out.written
        .extend(peers::write_peers_report(dir, &rows, &paper)?);
    Ok(out)
}

#[cfg(test)]
pub(crate) mod testutil {
    use crate::{Kind, MethodId, Row};

    /// A synthetic row: K = k, K̃ = 2k, measure i = x/i + 1/3, converged for odd seeds.
    pub fn fake_row(
        region: &str,
        k: usize,
        method: MethodId,
        seed: u64,
        kind: Kind,
        x: f64,
    ) -> Row {
        let mut v = [0.0; 14];
        v[0] = k as f64;
        v[1] = (2 * k) as f64;
        for (i, slot) in v.iter_mut().enumerate().skip(2) {
            *slot = x / (i as f64) + 1.0 / 3.0;
        }
        Row::new(region, k, method, seed, kind, v, 17, seed % 2 == 1, 0.1 + x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use testutil::fake_row;

    /// Synthetic rows for every job of `jobs` (both kinds), as a run would produce them.
    fn rows_for(jobs: &[Job]) -> Vec<Row> {
        jobs.iter()
            .flat_map(|j| {
                Kind::ALL.map(|kind| {
                    fake_row(
                        j.region(),
                        j.k(),
                        j.method,
                        j.seed,
                        kind,
                        j.seed as f64 + j.method as usize as f64,
                    )
                })
            })
            .collect()
    }

    #[test]
    fn a_metrics_csv_under_another_header_is_refused_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let m = output::metrics_csv(dir.path());
        output::write_atomic(&m, format!("{}\n", graded::GRADED_HEADER).as_bytes()).unwrap();
        let e = read_dir_csv(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains(&m.display().to_string()) && e.contains(record::METRICS_HEADER),
            "{e}"
        );
        assert!(write_report(dir.path()).is_err());
        assert!(merge(&[dir.path().to_path_buf()], &dir.path().join("merged")).is_err());
        // Just the header is what a run whose every job failed writes: no rows, no error.
        output::write_atomic(&m, &record::rows_csv(&[]).unwrap()).unwrap();
        assert_eq!(read_dir_csv(dir.path()).unwrap(), (vec![], vec![]));
    }

    /// Options of a two-seed run of every method on `regions`, as shard `i` of `n`.
    fn options(regions: &[&'static str], i: usize, n: usize) -> StudyOptions {
        StudyOptions {
            regions: regions.to_vec(),
            seeds: 2,
            graded: false,
            shard: Some(Shard { index: i, count: n }),
            ..StudyOptions::default()
        }
    }

    /// Write into `dir` what the shard of `opts` writes: its rows of `all` (the whole job
    /// list) and its record.
    fn write_shard(dir: &Path, opts: &StudyOptions, all: &[Job]) {
        let part = opts.shard.unwrap().select(all);
        output::write_atomic(
            &output::metrics_csv(dir),
            &record::rows_csv(&rows_for(&part)).unwrap(),
        )
        .unwrap();
        opts.shard_record().unwrap().write(dir).unwrap();
    }

    #[test]
    fn merge_refuses_shards_that_are_not_every_shard_of_one_run() {
        let regions = ["circle"];
        let all = job_list(&regions, &MethodId::ALL, 2);
        let tmp = tempfile::tempdir().unwrap();
        let shard = |name: &str, opts: &StudyOptions| {
            let d = tmp.path().join(name);
            let all = job_list(&opts.regions, &opts.methods, opts.seeds);
            write_shard(&d, opts, &all);
            d
        };
        let s: Vec<PathBuf> = (1..=3)
            .map(|i| shard(&format!("s{i}"), &options(&regions, i, 3)))
            .collect();
        let out = tmp.path().join("merged");
        let refused = |dirs: &[PathBuf]| {
            let e = merge(dirs, &out).unwrap_err();
            assert!(matches!(e, StudyError::ShardSet(_)), "{e:?}");
            // Refused before anything is written.
            assert!(!out.exists());
            e.to_string()
        };
        let e = refused(&s[..2]);
        assert!(e.contains("shard 3/3 missing"), "{e}");
        let e = refused(&[s[0].clone(), s[1].clone(), s[1].clone(), s[2].clone()]);
        assert!(e.contains("shard 2/3 given twice"), "{e}");
        let other_n = shard("t2", &options(&regions, 2, 2));
        let e = refused(&[s[0].clone(), other_n, s[2].clone()]);
        assert!(
            e.contains("is shard 1/3 but") && e.contains("is shard 2/2"),
            "{e}"
        );
        let other_jobs = shard(
            "u2",
            &StudyOptions {
                seeds: 3,
                ..options(&regions, 2, 3)
            },
        );
        let e = refused(&[s[0].clone(), other_jobs, s[2].clone()]);
        assert!(e.contains("different job lists"), "{e}");
        // A shard of a version that did not record which it is: its place cannot be checked.
        let old = tmp.path().join("old");
        output::write_atomic(
            &output::metrics_csv(&old),
            &record::rows_csv(&rows_for(&Shard { index: 2, count: 3 }.select(&all))).unwrap(),
        )
        .unwrap();
        let e = refused(&[s[0].clone(), old, s[2].clone()]);
        assert!(
            e.contains("no ") && e.contains("shard.csv") && e.contains("rerun"),
            "{e}"
        );

        // Every shard, with an unsharded run of another region beside them, as before.
        let whole = tmp.path().join("whole");
        let lake = StudyOptions {
            shard: None,
            ..options(&["lake"], 1, 1)
        };
        output::write_atomic(
            &output::metrics_csv(&whole),
            &record::rows_csv(&rows_for(&lake.jobs())).unwrap(),
        )
        .unwrap();
        write_report(&whole).unwrap();
        let mut dirs = s.clone();
        dirs.push(whole);
        merge(&dirs, &out).unwrap();
        let rows: Vec<Row> = record::read_csv(&output::metrics_csv(&out)).unwrap();
        assert_eq!(rows.len(), 2 * (all.len() + lake.jobs().len()));
        assert!(!output::shard_csv(&out).exists());
        // Merged into one of its shards, the directory is no longer that shard.
        merge(&s, &s[0]).unwrap();
        assert!(!output::shard_csv(&s[0]).exists());
    }

    #[test]
    fn merging_two_shards_equals_the_unsharded_csv() {
        let all = job_list(&["circle", "square_two_hex"], &MethodId::ALL, 2);
        let dir = tempfile::tempdir().unwrap();
        let mut shard_dirs = Vec::new();
        for i in 1..=2 {
            let d = dir.path().join(format!("shard_{i}"));
            write_shard(&d, &options(&["circle", "square_two_hex"], i, 2), &all);
            shard_dirs.push(d);
        }
        // Shard 2 also had a failure.
        let fail = Failure {
            region: "circle".into(),
            K_requested: 19,
            method: "vtm".into(),
            seed: 2,
            error: "boom".into(),
        };
        output::write_atomic(
            &output::failures_csv(&shard_dirs[1]),
            &record::failures_csv(std::slice::from_ref(&fail)).unwrap(),
        )
        .unwrap();

        let merged_dir = dir.path().join("merged");
        let outcome = merge(&shard_dirs, &merged_dir).unwrap();
        let mut whole = rows_for(&all);
        record::sort_rows(&mut whole);
        let expected = record::rows_csv(&whole).unwrap();
        assert_eq!(
            std::fs::read(output::metrics_csv(&merged_dir)).unwrap(),
            expected
        );
        assert_eq!(outcome.failures, vec![fail]);
        // The report was drawn from the merged CSV: the four tables of the two regions.
        for n in [1u8, 2, 3, 11] {
            assert!(output::table_md(&merged_dir, n).exists(), "table {n}");
        }
        assert!(!output::table_md(&merged_dir, 4).exists());
        assert!(std::fs::read_to_string(output::summary_md(&merged_dir))
            .unwrap()
            .contains("circle K=19 vtm seed 2: boom"));

        // Merging a shard twice is refused.
        let twice = merge(
            &[shard_dirs[0].clone(), shard_dirs[0].clone()],
            &dir.path().join("bad"),
        );
        assert!(matches!(twice, Err(StudyError::ShardSet(_))), "{twice:?}");
        // A directory without metrics.csv is refused with a message naming it.
        let e = merge(&[dir.path().join("nowhere")], &dir.path().join("bad2")).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("nowhere") && text.contains("is this a study output directory"),
            "{text}"
        );
    }
}
