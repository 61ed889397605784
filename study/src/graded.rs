//! The graded comparison: every method that honours a density, asked for a mesh whose edge
//! lengths follow a size field h(x), and measured against that field
//! ([`cvtmesh::metrics::size_conformity`]: the share of unit-length edges, the efficiency
//! index, angles).
//!
//! Three cases, each a Gmsh-style Threshold field h = h_min … ratio·h_min by the distance to
//! a target: a point source at the centre of the unit circle, the re-entrant corner of an
//! L-shape, and the hole of `square_hole`. h_min is scaled so that the field asks for
//! [`GradedCase::k`] vertices ((2/√3) ∫ h⁻² goes as h_min⁻²), and K is also passed to every
//! method explicitly, so all of them spend the same budget.
//!
//! Output: `DIR/csv/graded.csv` (a row per case, method and seed), `DIR/csv/graded_failures.csv`,
//! `DIR/graded.md` (a table per case) and `DIR/figures/graded_CASE.png` (a panel per method),
//! meshes under `DIR/meshes/graded/`.
use crate::record::{read_csv_with_header, to_csv, Failure};
use crate::{output, MethodId, Shard, StudyError};
use cvtmesh::geometry::{LoopRole, Region, SizeField, Threshold, Toward};
use cvtmesh::{DVec2, Mesh, MeshRequest};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The vertex budget of every case: large enough for a tenfold-or-more size range to be
/// resolved by several cells, small enough that the graded part stays well under the paper
/// part's run time.
pub const GRADED_K: usize = 1500;

/// The methods run by default. Every method honours the request's density, but MESHGEN and
/// VTM (10–40 s per case at this K, and a uniform start that the density only reshapes
/// through their relaxation targets) and CCVT(1)/CCVT(2) (30 s to minutes per case) would
/// take the graded part from about ten seconds to several minutes, so they run only when
/// named with `--methods`.
pub const GRADED_METHODS: [MethodId; 3] =
    [MethodId::Triangle, MethodId::Distmesh, MethodId::CcvtFast];

/// The method whose mesh is drawn first in each case's figure.
pub const DEFAULT_METHOD: MethodId = MethodId::CcvtFast;

/// Where the region of a case comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Domain {
    /// A built-in region by name.
    Builtin(&'static str),
    /// `[0,1]²` minus `[0.5,1]²`.
    LShape,
}

/// One graded case: a region and a Threshold size field toward one target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GradedCase {
    /// Name in the CSV and file names.
    pub name: &'static str,
    /// Heading in `graded.md`.
    pub title: &'static str,
    /// The region.
    pub domain: Domain,
    /// What h grows away from.
    pub toward: Toward,
    /// size_max / size_min.
    pub ratio: f64,
    /// Distance up to which h = h_min.
    pub dist_min: f64,
    /// Distance from which h = ratio · h_min.
    pub dist_max: f64,
    /// Vertices asked for.
    pub k: usize,
}

/// The three graded cases, in table order.
pub const CASES: [GradedCase; 3] = [
    GradedCase {
        name: "circle_point",
        title: "Unit circle, point source at the origin (h_min … 11 h_min over distance 0 … 1)",
        domain: Domain::Builtin("circle"),
        toward: Toward::Point(DVec2::ZERO),
        ratio: 11.0,
        dist_min: 0.0,
        dist_max: 1.0,
        k: GRADED_K,
    },
    GradedCase {
        name: "l_shape_corner",
        title: "L-shape [0,1]² \\ [0.5,1]², refined toward the re-entrant corner (0.5, 0.5) (ratio 30, distance 0 … 0.7)",
        domain: Domain::LShape,
        toward: Toward::Point(DVec2::new(0.5, 0.5)),
        ratio: 30.0,
        dist_min: 0.0,
        dist_max: 0.7,
        k: GRADED_K,
    },
    GradedCase {
        name: "square_hole_loop",
        title: "square_hole refined toward its hole (loop 1, ratio 10, distance 0.02 … 0.6)",
        domain: Domain::Builtin("square_hole"),
        toward: Toward::Loop(1),
        ratio: 10.0,
        dist_min: 0.02,
        dist_max: 0.6,
        k: GRADED_K,
    },
];

/// The L-shape `[0,1]²` minus `[0.5,1]²`, six corners, the re-entrant one at (0.5, 0.5).
pub fn l_shape() -> Result<Region, StudyError> {
    let p = |x, y| DVec2::new(x, y);
    let outer = vec![
        p(0.0, 0.0),
        p(1.0, 0.0),
        p(1.0, 0.5),
        p(0.5, 0.5),
        p(0.5, 1.0),
        p(0.0, 1.0),
    ];
    Ok(Region::from_loops(
        "l_shape",
        vec![(LoopRole::Outer, outer)],
    )?)
}

/// A case with its region and field built.
#[derive(Clone, Debug)]
pub struct BuiltCase {
    /// The case.
    pub case: &'static GradedCase,
    /// Its region.
    pub region: Region,
    /// The size field, scaled to ask for `case.k` vertices.
    pub field: SizeField,
    /// The smallest size of the field.
    pub h_min: f64,
}

impl GradedCase {
    /// Find a case by name.
    pub fn by_name(name: &str) -> Option<&'static GradedCase> {
        CASES.iter().find(|c| c.name == name)
    }

    /// The region of the case.
    pub fn region(&self) -> Result<Region, StudyError> {
        match self.domain {
            Domain::Builtin(name) => Ok(Region::builtin(name)?),
            Domain::LShape => l_shape(),
        }
    }

    /// The Threshold field with smallest size `h_min`.
    pub fn field(&self, region: &Region, h_min: f64) -> Result<SizeField, StudyError> {
        let t = Threshold {
            size_min: h_min,
            size_max: self.ratio * h_min,
            dist_min: self.dist_min,
            dist_max: self.dist_max,
        };
        Ok(SizeField::threshold(region, &[self.toward], t)?)
    }

    /// Region and field, with h_min chosen so that the field asks for `k` vertices. The
    /// field is h_min times a shape fixed by the distances, so the count goes exactly as
    /// h_min⁻²; a second step corrects for the background grid, whose resolution follows
    /// h_min.
    pub fn build(&'static self) -> Result<BuiltCase, StudyError> {
        let region = self.region()?;
        let mut h_min = 0.02;
        for _ in 0..2 {
            let n = self.field(&region, h_min)?.predicted_points(&region);
            h_min *= (n / self.k as f64).sqrt();
        }
        let field = self.field(&region, h_min)?;
        Ok(BuiltCase {
            case: self,
            region,
            field,
            h_min,
        })
    }
}

/// One graded mesh to make and measure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GradedJob {
    /// The case.
    pub case: &'static GradedCase,
    /// The method.
    pub method: MethodId,
    /// The seed.
    pub seed: u64,
}

impl GradedJob {
    /// "graded l_shape_corner K=1500 ccvt seed 1".
    pub fn label(&self) -> String {
        format!(
            "graded {} K={} {} seed {}",
            self.case.name,
            self.case.k,
            self.method.name(),
            self.seed
        )
    }
}

/// Every (case, method, seed) for the graded methods among `methods` and seeds 1..=`seeds`,
/// ordered by case, method (column order), seed: the order is the sharding contract, as for
/// [`crate::job_list`].
pub fn graded_jobs(methods: &[MethodId], seeds: u64) -> Vec<GradedJob> {
    let mut methods = methods.to_vec();
    methods.sort();
    methods.dedup();
    let mut jobs = Vec::new();
    for case in &CASES {
        for &method in &methods {
            for seed in 1..=seeds {
                jobs.push(GradedJob { case, method, seed });
            }
        }
    }
    jobs
}

/// The graded jobs of one shard (the same interleaving rule as the paper's jobs).
pub fn shard_graded(shard: Option<Shard>, jobs: Vec<GradedJob>) -> Vec<GradedJob> {
    match shard {
        Some(s) => jobs
            .into_iter()
            .enumerate()
            .filter(|(j, _)| s.owns(*j))
            .map(|(_, job)| job)
            .collect(),
        None => jobs,
    }
}

/// One line of `csv/graded.csv`. Floats round-trip exactly, as in `metrics.csv`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct GradedRow {
    /// Case name.
    pub case: String,
    /// Vertices asked for.
    pub K_requested: usize,
    /// Method name.
    pub method: String,
    /// Seed.
    pub seed: u64,
    /// The smallest size of the field.
    pub h_min: f64,
    /// Vertices produced.
    pub K: usize,
    /// Triangles produced.
    pub triangles: usize,
    /// The vertex count the field asks for, (2/√3) ∫ h⁻² dx.
    pub predicted_K: f64,
    /// Edges.
    pub edges: usize,
    /// Share of edges with |e| / h(midpoint) in [1/√2, √2].
    pub unit_share: f64,
    /// Efficiency index exp(mean δ).
    pub efficiency: f64,
    /// Mean of |e| / h(midpoint).
    pub mean_length: f64,
    /// Smallest angle, degrees.
    pub min_angle_deg: f64,
    /// 1st percentile of the triangles' smallest angles, degrees.
    pub min_angle_p1_deg: f64,
    /// Iterations the method ran.
    pub iterations: usize,
    /// Whether it met its convergence criterion.
    pub converged: bool,
    /// Wall time of the method (meshing only), seconds.
    pub seconds: f64,
}

/// Header of `graded.csv`, written also when there are no rows.
pub const GRADED_HEADER: &str = "case,K_requested,method,seed,h_min,K,triangles,predicted_K,edges,unit_share,efficiency,mean_length,min_angle_deg,min_angle_p1_deg,iterations,converged,seconds";

impl GradedRow {
    /// "l_shape_corner K=1500 ccvt seed 1": the identity of the row.
    pub fn key(&self) -> String {
        format!(
            "{} K={} {} seed {}",
            self.case, self.K_requested, self.method, self.seed
        )
    }

    /// The method, if the name is known.
    pub fn method_id(&self) -> Option<MethodId> {
        MethodId::parse(&self.method)
    }

    fn order(&self) -> (usize, String, usize, u64) {
        let c = CASES
            .iter()
            .position(|c| c.name == self.case)
            .unwrap_or(usize::MAX);
        let m = self.method_id().map_or(usize::MAX, |m| m as usize);
        (c, self.case.clone(), m, self.seed)
    }
}

/// Sort rows by case (table order), method (column order), seed.
pub fn sort_graded(rows: &mut [GradedRow]) {
    rows.sort_by(|a, b| {
        a.order()
            .cmp(&b.order())
            .then_with(|| a.method.cmp(&b.method))
    });
}

/// CSV text of rows (just the header if there are none).
pub fn graded_csv(rows: &[GradedRow]) -> Result<Vec<u8>, StudyError> {
    if rows.is_empty() {
        return Ok(format!("{GRADED_HEADER}\n").into_bytes());
    }
    to_csv(rows)
}

/// Read `DIR/csv/graded.csv` and `DIR/csv/graded_failures.csv` (absent: empty).
pub fn read_graded(dir: &Path) -> Result<(Vec<GradedRow>, Vec<Failure>), StudyError> {
    let p = graded_csv_path(dir);
    let rows = match p.exists() {
        true => read_csv_with_header(&p, GRADED_HEADER)?,
        false => Vec::new(),
    };
    let p = graded_failures_path(dir);
    let failures = match p.exists() {
        true => read_csv_with_header(&p, crate::record::FAILURES_HEADER)?,
        false => Vec::new(),
    };
    Ok((rows, failures))
}

/// Write both graded CSVs, sorted.
pub fn write_graded(
    dir: &Path,
    rows: &mut [GradedRow],
    failures: &mut [Failure],
) -> Result<Vec<PathBuf>, StudyError> {
    sort_graded(rows);
    failures.sort_by(|a, b| {
        let pos = |f: &Failure| CASES.iter().position(|c| c.name == f.region);
        let m = |f: &Failure| MethodId::parse(&f.method);
        (pos(a), m(a), a.seed).cmp(&(pos(b), m(b), b.seed))
    });
    let p = graded_csv_path(dir);
    output::write_atomic(&p, &graded_csv(rows)?)?;
    let f = graded_failures_path(dir);
    output::write_atomic(&f, &crate::record::failures_csv(failures)?)?;
    Ok(vec![p, f])
}

/// `DIR/csv/graded.csv`.
pub fn graded_csv_path(dir: &Path) -> PathBuf {
    dir.join("csv").join("graded.csv")
}

/// `DIR/csv/graded_failures.csv`.
pub fn graded_failures_path(dir: &Path) -> PathBuf {
    dir.join("csv").join("graded_failures.csv")
}

/// `DIR/graded.md`.
pub fn graded_md_path(dir: &Path) -> PathBuf {
    dir.join("graded.md")
}

/// `DIR/figures/graded_CASE.png`.
pub fn graded_png(dir: &Path, case: &str) -> PathBuf {
    dir.join("figures").join(format!("graded_{case}.png"))
}

/// `DIR/meshes/graded/CASE_METHOD_seedS` (Triangle files beside it).
pub fn graded_mesh_base(dir: &Path, case: &str, method: MethodId, seed: u64) -> PathBuf {
    dir.join("meshes")
        .join("graded")
        .join(format!("{case}_{}_seed{seed}", method.name()))
}

fn node_of(base: &Path) -> PathBuf {
    let mut p = base.as_os_str().to_owned();
    p.push(".node");
    PathBuf::from(p)
}

/// Mesh one graded job through [`MeshRequest::size_field`] with K given, time the meshing
/// and measure the mesh against the field. Errors and panics become messages.
pub fn run_graded_job(job: &GradedJob, built: &BuiltCase) -> Result<(GradedRow, Mesh), String> {
    crate::run::catch(|| {
        let request = MeshRequest::size_field(&built.field, &built.region, Some(job.case.k))
            .map_err(|e| e.to_string())?
            .seed(job.seed);
        let mesher = job.method.mesher();
        let start = Instant::now();
        let result = mesher
            .mesh(&built.region, &request, &mut |_| {})
            .map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        let c = cvtmesh::metrics::size_conformity(&result.mesh, &built.field, &built.region)
            .map_err(|e| format!("size conformity: {e}"))?;
        let row = GradedRow {
            case: job.case.name.to_string(),
            K_requested: job.case.k,
            method: job.method.name().to_string(),
            seed: job.seed,
            h_min: built.h_min,
            K: c.vertices,
            triangles: result.mesh.num_triangles(),
            predicted_K: c.predicted_vertices,
            edges: c.edges,
            unit_share: c.unit_share,
            efficiency: c.efficiency,
            mean_length: c.mean_length,
            min_angle_deg: c.min_angle_deg,
            min_angle_p1_deg: c.min_angle_p1_deg,
            iterations: result.iterations,
            converged: result.converged,
            seconds,
        };
        Ok((row, result.mesh))
    })
}

/// The result of one graded job.
#[derive(Clone, Debug)]
pub struct GradedResult {
    /// The job.
    pub job: GradedJob,
    /// Its row and mesh, or why it failed.
    pub outcome: Result<(GradedRow, Mesh), String>,
}

impl GradedResult {
    /// The failure record, if it failed (the case name in the region column).
    pub fn failure(&self) -> Option<Failure> {
        self.outcome.as_ref().err().map(|e| Failure {
            region: self.job.case.name.to_string(),
            K_requested: self.job.case.k,
            method: self.job.method.name().to_string(),
            seed: self.job.seed,
            error: e.clone(),
        })
    }
}

/// Build the cases the jobs need (fields are sampled once per case) and run the jobs on
/// `threads` workers, the costliest first. Results come back in job order.
pub fn run_graded(
    jobs: &[GradedJob],
    threads: Option<usize>,
    on_event: &(dyn Fn(crate::Event<'_>) + Sync),
) -> Result<Vec<GradedResult>, StudyError> {
    let names: BTreeSet<&'static str> = jobs.iter().map(|j| j.case.name).collect();
    let mut built: BTreeMap<&'static str, BuiltCase> = BTreeMap::new();
    for case in CASES.iter().filter(|c| names.contains(c.name)) {
        built.insert(case.name, case.build()?);
    }
    let cost = |j: &GradedJob| j.case.k as f64 * j.method.cost_weight();
    let results = crate::run::pool_map(jobs, threads, cost, |job| {
        on_event(crate::Event::GradedStarted(job));
        let start = Instant::now();
        let outcome = run_graded_job(job, &built[job.case.name]);
        on_event(crate::Event::GradedFinished(
            job,
            outcome.is_ok(),
            start.elapsed().as_secs_f64(),
        ));
        GradedResult { job: *job, outcome }
    })?;
    Ok(results
        .into_iter()
        .zip(jobs)
        .map(|(r, job)| {
            r.unwrap_or_else(|| GradedResult {
                job: *job,
                outcome: Err("not run".into()),
            })
        })
        .collect())
}

/// Write the meshes of successful results under `dir/meshes/graded/`.
pub fn write_graded_meshes(dir: &Path, results: &[GradedResult]) -> Result<(), StudyError> {
    for r in results {
        if let Ok((_, mesh)) = &r.outcome {
            let base = graded_mesh_base(dir, r.job.case.name, r.job.method, r.job.seed);
            output::create_dir(base.parent().unwrap_or(dir))?;
            cvtmesh::io::write_triangle(mesh, &base)?;
        }
    }
    Ok(())
}

/// Copy the meshes of `rows` from `from` to `to` (a merge); missing files become notes.
pub fn copy_graded_meshes(
    from: &Path,
    to: &Path,
    rows: &[GradedRow],
    notes: &mut Vec<String>,
) -> Result<(), StudyError> {
    for r in rows {
        let Some(m) = r.method_id() else { continue };
        let src = node_of(&graded_mesh_base(from, &r.case, m, r.seed));
        if !src.exists() {
            notes.push(format!(
                "{}: missing; its panel will be empty",
                src.display()
            ));
            continue;
        }
        let mesh = cvtmesh::io::read_triangle(&src)?;
        let base = graded_mesh_base(to, &r.case, m, r.seed);
        output::create_dir(base.parent().unwrap_or(to))?;
        cvtmesh::io::write_triangle(&mesh, &base)?;
    }
    Ok(())
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    s / n as f64
}

/// `graded.md`: a table per case with a row per method (means over the seeds present).
pub fn render_graded_md(rows: &[GradedRow], failures: &[Failure]) -> String {
    let mut md = String::from(
        "# Graded meshes\n\n\
         Every method that honours a density is asked for K vertices whose spacing follows a \
         size field h(x) (`MeshRequest::size_field`, density ρ = (h_min/h)⁴, K given \
         explicitly), and measured against h: l = |e| / h(midpoint) per edge; *unit* is the \
         share of edges with l in [1/√2, √2]; *eff.* the efficiency index exp(mean δ), \
         δ = l − 1 for l < 1 and 1/l − 1 otherwise (1 is ideal); *mean l* should be near 1; \
         angles are the smallest of any triangle and the 1st percentile of the triangles' \
         smallest angles. Time is the method's wall time (meshing only). \
         h_min is scaled so that the field itself asks for K vertices, \
         (2/√3) ∫ h⁻² dx = K.\n",
    );
    for case in &CASES {
        let here: Vec<&GradedRow> = rows.iter().filter(|r| r.case == case.name).collect();
        let failed: Vec<&Failure> = failures.iter().filter(|f| f.region == case.name).collect();
        if here.is_empty() && failed.is_empty() {
            continue;
        }
        let seeds: BTreeSet<u64> = here.iter().map(|r| r.seed).collect();
        let h_min = here.first().map_or(f64::NAN, |r| r.h_min);
        let _ = write!(
            md,
            "\n## {}\n\n`{}`: K = {}, h_min = {:.5}, h_max = {:.5}; {}.\n\n",
            case.title,
            case.name,
            case.k,
            h_min,
            case.ratio * h_min,
            if seeds.len() == 1 {
                format!("seed {}", seeds.iter().next().copied().unwrap_or(1))
            } else {
                format!("means over {} seeds", seeds.len())
            }
        );
        md.push_str(
            "| method | vertices | unit | eff. | min angle (°) | 1 % min angle (°) | mean l | time (s) | converged |\n\
             |---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        );
        let mut methods: Vec<MethodId> = here.iter().filter_map(|r| r.method_id()).collect();
        methods.sort();
        methods.dedup();
        for m in methods {
            let rs: Vec<&&GradedRow> = here.iter().filter(|r| r.method_id() == Some(m)).collect();
            let avg = |f: &dyn Fn(&GradedRow) -> f64| mean(rs.iter().map(|r| f(r)));
            let conv = rs.iter().filter(|r| r.converged).count();
            let converged = if rs.len() == 1 {
                if conv == 1 { "yes" } else { "no" }.to_string()
            } else {
                format!("{conv}/{}", rs.len())
            };
            let _ = writeln!(
                md,
                "| {} | {:.0} | {:.3} | {:.3} | {:.1} | {:.1} | {:.3} | {:.2} | {} |",
                m.column(),
                avg(&|r| r.K as f64),
                avg(&|r| r.unit_share),
                avg(&|r| r.efficiency),
                avg(&|r| r.min_angle_deg),
                avg(&|r| r.min_angle_p1_deg),
                avg(&|r| r.mean_length),
                avg(&|r| r.seconds),
                converged
            );
        }
        for f in failed {
            let _ = writeln!(
                md,
                "\nFailed: {} seed {}: {}",
                f.method,
                f.seed,
                f.error.replace('\n', " ")
            );
        }
        let _ = writeln!(md, "\n![{}](figures/graded_{}.png)", case.name, case.name);
    }
    md
}

/// Draw `dir/figures/graded_CASE.png` for every case with a mesh: one panel per method
/// (lowest seed), the default method first. Missing meshes become notes.
pub fn draw_graded_figures(
    dir: &Path,
    rows: &[GradedRow],
    notes: &mut Vec<String>,
) -> Result<Vec<PathBuf>, StudyError> {
    let mut written = Vec::new();
    for case in &CASES {
        let mut lowest: BTreeMap<MethodId, u64> = BTreeMap::new();
        for r in rows.iter().filter(|r| r.case == case.name) {
            if let Some(m) = r.method_id() {
                let e = lowest.entry(m).or_insert(r.seed);
                *e = (*e).min(r.seed);
            }
        }
        if lowest.is_empty() {
            continue;
        }
        let mut meshes: Vec<(MethodId, Mesh)> = Vec::new();
        for (&m, &seed) in &lowest {
            let node = node_of(&graded_mesh_base(dir, case.name, m, seed));
            if !node.exists() {
                notes.push(format!(
                    "{}: missing, so its panel is left out",
                    node.display()
                ));
                continue;
            }
            meshes.push((m, cvtmesh::io::read_triangle(&node)?));
        }
        if meshes.is_empty() {
            continue;
        }
        meshes.sort_by_key(|(m, _)| (*m != DEFAULT_METHOD, *m));
        let region = case.region()?;
        let panels: Vec<render::Panel> = meshes
            .iter()
            .map(|(m, mesh)| {
                render::Panel::new(
                    format!(
                        "{} ({} pts, {} tri)",
                        m.column(),
                        mesh.num_vertices(),
                        mesh.num_triangles()
                    ),
                    &region,
                )
                .with_mesh(mesh)
            })
            .collect();
        let layout = render::Layout::new(panels.len().min(3))
            .panel_px(420)
            .title(format!("Graded: {}", case.title));
        let path = graded_png(dir, case.name);
        output::create_dir(path.parent().unwrap_or(dir))?;
        render::render_png(&panels, &layout, &path)?;
        written.push(path);
    }
    Ok(written)
}

/// Write `graded.md` and the figures from `dir`'s graded CSVs and meshes; nothing if there
/// is no `graded.csv`.
pub fn write_graded_report(
    dir: &Path,
    notes: &mut Vec<String>,
) -> Result<Vec<PathBuf>, StudyError> {
    if !graded_csv_path(dir).exists() {
        return Ok(Vec::new());
    }
    let (rows, failures) = read_graded(dir)?;
    let p = graded_md_path(dir);
    output::write_atomic(&p, render_graded_md(&rows, &failures).as_bytes())?;
    let mut written = vec![p];
    written.extend(draw_graded_figures(dir, &rows, notes)?);
    Ok(written)
}

/// Combine graded rows of several directories: a row present twice is an error.
pub fn merge_graded(parts: Vec<Vec<GradedRow>>) -> Result<Vec<GradedRow>, StudyError> {
    let mut seen = BTreeSet::new();
    let mut all = Vec::new();
    for row in parts.into_iter().flatten() {
        if !seen.insert(row.key()) {
            return Err(StudyError::Duplicate(row.key()));
        }
        all.push(row);
    }
    sort_graded(&mut all);
    Ok(all)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn l_shape_case_builds_its_region_and_field_and_asks_for_k() {
        let case = GradedCase::by_name("l_shape_corner").unwrap();
        let b = case.build().unwrap();
        assert!((b.region.area() - 0.75).abs() < 1e-12);
        assert_eq!(b.region.corners().len(), 6);
        assert!(!b.region.contains(DVec2::new(0.75, 0.75)));
        assert!(b.region.contains(DVec2::new(0.25, 0.75)));
        // h_min at the re-entrant corner (to within the background grid's smoothing of the
        // cone's tip), linear in the distance, 30 h_min from 0.7 away on.
        let corner = b.field.at(DVec2::new(0.5, 0.5));
        assert!(
            (corner / b.h_min - 1.0).abs() < 0.05,
            "{corner} {}",
            b.h_min
        );
        let mid = b.field.at(DVec2::new(0.5, 0.15));
        assert!((mid / b.h_min - 15.5).abs() < 1e-2, "{mid}");
        let far = b.field.at(DVec2::new(0.003, 0.003));
        assert!((far / b.h_min - 30.0).abs() < 1e-2, "{far}");
        // The field asks for K vertices (to the quadrature's accuracy), and the request
        // carries K itself.
        let n = b.field.predicted_points(&b.region);
        assert!((n / case.k as f64 - 1.0).abs() < 0.01, "{n}");
        let request = MeshRequest::size_field(&b.field, &b.region, Some(case.k)).unwrap();
        assert_eq!(request.validate(&b.region).unwrap(), GRADED_K);
        assert!(!request.density.is_uniform());
    }

    #[test]
    fn every_case_is_scaled_to_its_k() {
        for case in &CASES {
            let b = case.build().unwrap();
            let n = b.field.predicted_points(&b.region);
            assert!((n / case.k as f64 - 1.0).abs() < 0.01, "{}: {n}", case.name);
        }
    }

    #[test]
    fn graded_jobs_order_and_shards() {
        let jobs = graded_jobs(&[MethodId::CcvtFast, MethodId::Triangle], 2);
        assert_eq!(jobs.len(), 3 * 2 * 2);
        assert_eq!(jobs[0].label(), "graded circle_point K=1500 refine seed 1");
        assert_eq!(jobs[3].label(), "graded circle_point K=1500 ccvt seed 2");
        let a = shard_graded(Some(Shard { index: 1, count: 2 }), jobs.clone());
        let b = shard_graded(Some(Shard { index: 2, count: 2 }), jobs.clone());
        assert_eq!(a.len() + b.len(), jobs.len());
        assert!(a.iter().all(|j| !b.contains(j)));
    }

    #[test]
    fn csv_round_trip_and_table() {
        let row = GradedRow {
            case: "l_shape_corner".into(),
            K_requested: 1500,
            method: "ccvt".into(),
            seed: 1,
            h_min: 0.1 + 0.2,
            K: 1500,
            triangles: 2900,
            predicted_K: 1499.5,
            edges: 4400,
            unit_share: 0.9,
            efficiency: 0.88,
            mean_length: 1.01,
            min_angle_deg: 30.5,
            min_angle_p1_deg: 40.0,
            iterations: 17,
            converged: true,
            seconds: 0.5,
        };
        let text = graded_csv(std::slice::from_ref(&row)).unwrap();
        assert_eq!(
            String::from_utf8(text.clone()).unwrap().lines().next(),
            Some(GRADED_HEADER)
        );
        let back: Vec<GradedRow> = crate::record::from_csv(&text, "t").unwrap();
        assert_eq!(back, vec![row.clone()]);
        let md = render_graded_md(std::slice::from_ref(&row), &[]);
        assert!(
            md.contains("| CCVT-fast | 1500 | 0.900 | 0.880 | 30.5 | 40.0 | 1.010 | 0.50 | yes |")
        );
        assert!(merge_graded(vec![vec![row.clone()], vec![row]]).is_err());
    }
}
