//! `study`: regenerate the paper's Tables 1–12 and Figures 3–7 with every method.
//! Run `study --help` for the options; README describes sharding.
#![forbid(unsafe_code)]

use anyhow::Context;
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use study::{paper, Event, MethodId, Shard, StudyOptions};

/// Every method on every paper region at the paper's K: Tables 1–12 (Markdown), one CSV of
/// every measure, Figures 3–7 and a summary, under --out.
#[derive(Parser, Debug)]
#[command(name = "study", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Comma-separated regions (default: all ten).
    #[arg(long, value_name = "A,B")]
    regions: Option<String>,
    /// Comma-separated methods: refine (= triangle), distmesh, meshgen, vtm, ccvt1, ccvt2, ccvt (= ccvt-fast) (default: all).
    #[arg(long, value_name = "X,Y")]
    methods: Option<String>,
    /// Run seeds 1..=N; tables then show means with 95 % confidence intervals, and summary.md tests which method is best (Friedman, Holm-corrected Wilcoxon).
    #[arg(long, value_name = "N", default_value_t = 1)]
    seeds: u64,
    /// Start at seed S instead of 1 (seeds S..=N), keeping the rows of lower seeds already in DIR: extends a run to more seeds.
    #[arg(long, value_name = "S", default_value_t = 1)]
    first_seed: u64,
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "results")]
    out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Run only jobs j with j mod N = I−1 of the job list, and write only the CSV (with csv/shard.csv, the shard and its job list, which merge checks) and meshes.
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    /// Replace DIR/csv/metrics.csv (and graded.csv) instead of updating only the cells run.
    #[arg(long)]
    fresh: bool,
    /// Skip the graded comparison (graded.md, csv/graded.csv), run by default.
    #[arg(long, conflicts_with = "graded_only")]
    no_graded: bool,
    /// Run only the graded comparison: three size-field cases at K = 1500, default methods refine, distmesh, ccvt (--methods chooses others). --regions does not apply to it.
    #[arg(long)]
    graded_only: bool,
    /// Also mesh every selected table with the real Triangle and the real Gmsh (Frontal-Delaunay) through scripts/real_peers.py, scored like every method: real_peers.md and csv/real_peers*.csv. Without the Python packages: a note, and the study runs as without the flag.
    #[arg(long, conflicts_with = "shard")]
    real_peers: bool,
    /// Run only the real tools (as --real-peers) and redraw DIR's report: adds them to a finished run.
    #[arg(long, conflicts_with_all = ["shard", "graded_only"])]
    real_peers_only: bool,
    /// Python interpreter with numpy, triangle and gmsh for --real-peers (default: $CVTMESH_PYTHON, else this repository's scripts/.venv/bin/python, made by scripts/compare_tools.sh).
    #[arg(long, value_name = "PATH")]
    python: Option<PathBuf>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Combine shard directories into one CSV, tables, figures and summary.
    ///
    /// The shards must be every shard of one run (the same job list and N), each once; directories of unsharded runs or merges may be given beside them.
    Merge {
        /// Shard output directories (each with csv/metrics.csv and meshes/).
        #[arg(required = true, value_name = "DIR")]
        dirs: Vec<PathBuf>,
        /// Output directory.
        #[arg(long, value_name = "DIR", default_value = "results")]
        out: PathBuf,
    },
    /// Redraw tables, figures and summary from DIR's CSV and meshes without running anything.
    Report {
        /// Output directory to redraw.
        #[arg(long, value_name = "DIR", default_value = "results")]
        out: PathBuf,
    },
}

fn options(cli: &Cli) -> anyhow::Result<StudyOptions> {
    let mut o = StudyOptions {
        seeds: cli.seeds,
        first_seed: cli.first_seed,
        out: cli.out.clone(),
        threads: cli.jobs,
        fresh: cli.fresh,
        paper: !cli.graded_only && !cli.real_peers_only,
        graded: !cli.no_graded && !cli.real_peers_only,
        real_peers: cli.real_peers || cli.real_peers_only,
        python: cli.python.clone(),
        ..StudyOptions::default()
    };
    if let Some(r) = &cli.regions {
        o.regions = study::parse_regions(r)?;
    }
    if let Some(m) = &cli.methods {
        o.methods = MethodId::parse_list(m)?;
        o.graded_methods = o.methods.clone();
    }
    if let Some(s) = &cli.shard {
        o.shard = Some(Shard::parse(s)?);
    }
    if o.seeds == 0 {
        anyhow::bail!("--seeds must be at least 1");
    }
    if o.first_seed == 0 || o.first_seed > o.seeds {
        anyhow::bail!("--first-seed must be between 1 and --seeds ({})", o.seeds);
    }
    if o.threads == Some(0) {
        anyhow::bail!("--jobs must be at least 1");
    }
    Ok(o)
}

fn report_outcome(o: &study::Outcome, started: Instant, what: &str) -> ExitCode {
    for n in &o.notes {
        eprintln!("note: {n}");
    }
    for f in &o.failures {
        eprintln!(
            "FAILED {} K={} {} seed {}: {}",
            f.region, f.K_requested, f.method, f.seed, f.error
        );
    }
    let tables = o
        .written
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .count();
    let pngs = o
        .written
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .count();
    println!(
        "{what}: {} jobs, {} failed; wrote {} files ({tables} Markdown, {pngs} PNG); wall time {:.1} s",
        o.jobs,
        o.failures.len(),
        o.written.len(),
        started.elapsed().as_secs_f64()
    );
    if o.failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    }
}

fn main() -> ExitCode {
    match real_main() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn real_main() -> anyhow::Result<ExitCode> {
    let cli = Cli::parse();
    let started = Instant::now();
    match &cli.command {
        Some(Command::Merge { dirs, out }) => {
            let o = study::merge(dirs, out)
                .with_context(|| format!("merging into {}", out.display()))?;
            Ok(report_outcome(&o, started, "merge"))
        }
        Some(Command::Report { out }) => {
            let o =
                study::write_report(out).with_context(|| format!("reporting {}", out.display()))?;
            Ok(report_outcome(&o, started, "report"))
        }
        None => {
            let opts = options(&cli)?;
            let jobs = opts.jobs();
            let graded_jobs = opts.graded_jobs();
            let peer_runs = if opts.real_peers {
                study::peers::peer_runs(&opts.regions).len()
            } else {
                0
            };
            let total = jobs.len() + graded_jobs.len() + peer_runs;
            let bar = ProgressBar::new(total as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{elapsed_precise} [{bar:30}] {pos}/{len} jobs  {msg}",
                )
                .map(|s| s.progress_chars("=> "))
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            let n_tables = paper::TABLES
                .iter()
                .filter(|t| opts.regions.contains(&t.region))
                .count();
            bar.println(format!(
                "study: {} jobs ({} tables × {} methods × {} seeds, {} graded{}{}) on {} threads → {}",
                total,
                if opts.paper { n_tables } else { 0 },
                opts.methods.len(),
                opts.seeds + 1 - opts.first_seed,
                graded_jobs.len(),
                if peer_runs > 0 {
                    format!(", {peer_runs} real-tool runs")
                } else {
                    String::new()
                },
                opts.shard.map_or(String::new(), |s| format!(
                    ", shard {}/{}",
                    s.index, s.count
                )),
                opts.threads
                    .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
                opts.out.display()
            ));
            // One line per panic inside a job (the job becomes a failure), instead of the
            // default multi-line report and backtrace tearing through the progress bar.
            let hook_bar = bar.clone();
            std::panic::set_hook(Box::new(move |info| {
                hook_bar.println(format!("panic: {}", info.to_string().replace('\n', " ")))
            }));
            // Without a terminal (batch logs) the bar is hidden: log one line per job instead.
            let log_lines = !std::io::stderr().is_terminal();
            // The jobs in flight, shown after the counter.
            let running = std::sync::Mutex::new(Vec::<String>::new());
            let show = |f: &dyn Fn(&mut Vec<String>)| {
                if let Ok(mut r) = running.lock() {
                    f(&mut r);
                    bar.set_message(format!("running: {}", r.join(" | ")));
                }
            };
            let on_event = |e: Event<'_>| match e {
                Event::Started(_) | Event::GradedStarted(_) => show(&|r| r.push(e.label())),
                Event::Finished(_, ok, secs)
                | Event::GradedFinished(_, ok, secs)
                | Event::PeerFinished(_, ok, secs) => {
                    let label = e.label();
                    show(&|r| r.retain(|l| *l != label));
                    bar.inc(1);
                    let status = if ok { "done" } else { "FAILED" };
                    if log_lines {
                        eprintln!(
                            "[{}/{total}] {status} {} ({secs:.1} s)",
                            bar.position(),
                            label
                        );
                    } else if !ok {
                        bar.println(format!("failed: {label}"));
                    }
                }
            };
            let o = study::run_study(&opts, &on_event)?;
            bar.finish_and_clear();
            Ok(report_outcome(&o, started, "study"))
        }
    }
}
