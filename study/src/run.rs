//! Running jobs: mesh, measure (exact and sampled), time; in parallel on a rayon pool.
use crate::graded::GradedJob;
use crate::paper::sample_scale;
use crate::record::{Failure, Kind, Row};
use crate::tables::{SAMPLES, SAMPLE_SEED};
use crate::{Job, StudyError};
use cvtmesh::geometry::Region;
use cvtmesh::metrics::SampleParams;
use cvtmesh::{Mesh, MeshRequest};
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// What one successful job produced.
#[derive(Clone, Debug)]
pub struct JobOutput {
    /// The exact row, then the sampled row.
    pub rows: [Row; 2],
    /// The mesh.
    pub mesh: Mesh,
    /// The method's notes.
    pub notes: Vec<String>,
}

/// A job and its outcome (an error message on failure).
#[derive(Clone, Debug)]
pub struct JobResult {
    /// The job.
    pub job: Job,
    /// Its output, or why it failed.
    pub outcome: Result<JobOutput, String>,
}

impl JobResult {
    /// The failure record, if it failed.
    pub fn failure(&self) -> Option<Failure> {
        self.outcome.as_ref().err().map(|e| Failure {
            region: self.job.region().to_string(),
            K_requested: self.job.k(),
            method: self.job.method.name().to_string(),
            seed: self.job.seed,
            error: e.clone(),
        })
    }
}

/// Progress of [`run_jobs`], reported from worker threads.
#[derive(Clone, Copy, Debug)]
pub enum Event<'a> {
    /// A job started.
    Started(&'a Job),
    /// A job finished: whether it succeeded, and its wall time in seconds (meshing and
    /// measuring).
    Finished(&'a Job, bool, f64),
    /// A graded job started.
    GradedStarted(&'a GradedJob),
    /// A graded job finished, as [`Event::Finished`].
    GradedFinished(&'a GradedJob, bool, f64),
    /// A real tool's run (`--real-peers`) finished: its label, whether it worked, its wall
    /// time in seconds (the driver's whole run).
    PeerFinished(&'a str, bool, f64),
}

impl Event<'_> {
    /// The label of the job.
    pub fn label(&self) -> String {
        match self {
            Event::Started(j) | Event::Finished(j, ..) => j.label(),
            Event::GradedStarted(j) | Event::GradedFinished(j, ..) => j.label(),
            Event::PeerFinished(label, ..) => label.to_string(),
        }
    }
}

/// Load the built-in regions named.
pub fn load_regions(names: &[&'static str]) -> Result<BTreeMap<&'static str, Region>, StudyError> {
    names
        .iter()
        .map(|&n| Ok((n, Region::builtin(n)?)))
        .collect()
}

/// The sampled-estimate parameters used for `region` (10⁴ samples, seed 1, the paper's scale).
pub fn sample_params(region: &str) -> SampleParams {
    SampleParams {
        samples: SAMPLES,
        seed: SAMPLE_SEED,
        scale: sample_scale(region),
    }
}

/// Mesh one job with the method's defaults (`MeshRequest::points(K).seed(seed)`), time the
/// meshing, and compute both kinds of measures. Errors (and panics) become messages.
pub fn run_job(job: &Job, region: &Region) -> Result<JobOutput, String> {
    let work = || -> Result<JobOutput, String> {
        let mesher = job.method.mesher();
        let request = MeshRequest::points(job.k()).seed(job.seed);
        let start = Instant::now();
        let result = mesher
            .mesh(region, &request, &mut |_| {})
            .map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        let exact = cvtmesh::metrics::measures(&result.mesh, region)
            .map_err(|e| format!("exact measures: {e}"))?;
        let sampled =
            cvtmesh::metrics::sampled_measures(&result.mesh, region, &sample_params(job.region()))
                .map_err(|e| format!("sampled measures: {e}"))?;
        let row = |kind, values| {
            Row::new(
                job.region(),
                job.k(),
                job.method,
                job.seed,
                kind,
                values,
                result.iterations,
                result.converged,
                seconds,
            )
        };
        Ok(JobOutput {
            rows: [
                row(Kind::Exact, exact.values()),
                row(Kind::Sampled, sampled.values()),
            ],
            mesh: result.mesh,
            notes: result.notes,
        })
    };
    catch(work)
}

/// Run `work`, turning a panic into an error message.
pub(crate) fn catch<T>(work: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    match catch_unwind(AssertUnwindSafe(work)) {
        Ok(r) => r,
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(format!("panicked: {msg}"))
        }
    }
}

/// Run `jobs` on a pool of `threads` workers (`None`: all cores), the costliest first (for
/// load balance); results come back in the order of `jobs`. `regions` must hold every job's
/// region. `on_event` is called from the workers.
pub fn run_jobs(
    jobs: &[Job],
    regions: &BTreeMap<&'static str, Region>,
    threads: Option<usize>,
    on_event: &(dyn Fn(Event<'_>) + Sync),
) -> Result<Vec<JobResult>, StudyError> {
    for j in jobs {
        if !regions.contains_key(j.region()) {
            return Err(StudyError::BadOption(format!(
                "region '{}' was not loaded",
                j.region()
            )));
        }
    }
    let results = pool_map(jobs, threads, Job::cost, |job| {
        on_event(Event::Started(job));
        let start = Instant::now();
        let outcome = run_job(job, &regions[job.region()]);
        on_event(Event::Finished(
            job,
            outcome.is_ok(),
            start.elapsed().as_secs_f64(),
        ));
        JobResult { job: *job, outcome }
    })?;
    Ok(results
        .into_iter()
        .zip(jobs)
        .map(|(r, job)| {
            r.unwrap_or_else(|| JobResult {
                job: *job,
                outcome: Err("not run".into()),
            })
        })
        .collect())
}

/// Map `work` over `jobs` on a pool of `threads` workers (`None`: all cores), the costliest
/// first (for load balance); results come back in the order of `jobs`, `None` for a job
/// whose worker died.
pub(crate) fn pool_map<J: Sync, R: Send + Clone>(
    jobs: &[J],
    threads: Option<usize>,
    cost: impl Fn(&J) -> f64,
    work: impl Fn(&J) -> R + Sync,
) -> Result<Vec<Option<R>>, StudyError> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        if n == 0 {
            return Err(StudyError::BadOption("--jobs must be at least 1".into()));
        }
        builder = builder.num_threads(n);
    }
    let pool = builder
        .build()
        .map_err(|e| StudyError::Pool(e.to_string()))?;
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| cost(&jobs[b]).total_cmp(&cost(&jobs[a])).then(a.cmp(&b)));
    let next = AtomicUsize::new(0);
    let slots: Mutex<Vec<Option<R>>> = Mutex::new(vec![None; jobs.len()]);
    let workers = pool.current_num_threads().min(jobs.len());
    pool.scope(|s| {
        for _ in 0..workers {
            s.spawn(|_| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(&j) = order.get(i) else { break };
                let r = work(&jobs[j]);
                if let Ok(mut slots) = slots.lock() {
                    slots[j] = Some(r);
                }
            });
        }
    });
    slots
        .into_inner()
        .map_err(|_| StudyError::Pool("a worker panicked".into()))
}
