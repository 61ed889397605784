//! `study --real-peers`: the real Triangle and the real Gmsh (Frontal-Delaunay) beside the
//! stand-ins, at the paper's K, scored by the same exact measures as every method.
//!
//! The tools are Python packages, so they run in a child process: `scripts/real_peers.py`
//! (which meshes with `scripts/compare_tools.py`'s code) under the interpreter of
//! `--python`, `$CVTMESH_PYTHON` or this repository's `scripts/.venv` (made by
//! `scripts/compare_tools.sh`). The study writes the region file it needs from its own copy
//! of the region data, the driver writes `DIR/meshes/REGION_K<K>_<peer>.node|.ele` and prints
//! one line, and the study reads and scores the mesh. Without the interpreter or its packages
//! the part is skipped with one line saying what is missing.
//!
//! Outputs: `DIR/csv/real_peers.csv` (one row per table and tool, with the K obtained and
//! the tool's parameters, or the error), `DIR/csv/real_peers_fidelity.csv` (every real value
//! against every method's values over seeds) and `DIR/real_peers.md`, redrawn by every report.
use crate::fidelity::{median, Basis, Fidelity, NEAR};
use crate::methods::TRIANGLE_MIN_ANGLE_DEG;
use crate::paper::{sample_scale, untrustworthy, PaperTables, TableSpec, TABLES};
use crate::record::{Kind, Row};
use crate::stats::mean_std;
use crate::tables::{failed_runs, format_cell, seed_list};
use crate::{output, record, scaled_label, Measure, MethodId, StudyError};
use cvtmesh::geometry::Region;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A real tool run beside the stand-ins.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Peer {
    /// Shewchuk's Triangle (`-pq<angle>a<area>`), the original of our TRIANGLE column.
    Triangle,
    /// Gmsh's Frontal-Delaunay (algorithm 6) at a uniform size: a reference no column imitates.
    GmshFrontal,
}

impl Peer {
    /// Both, in column order.
    pub const ALL: [Peer; 2] = [Peer::Triangle, Peer::GmshFrontal];

    /// Name in the CSV and in mesh file names.
    pub fn name(self) -> &'static str {
        match self {
            Peer::Triangle => "triangle-real",
            Peer::GmshFrontal => "gmsh-frontal-real",
        }
    }

    /// Column header.
    pub fn column(self) -> &'static str {
        match self {
            Peer::Triangle => "Triangle (real)",
            Peer::GmshFrontal => "Gmsh-FD (real)",
        }
    }

    /// The driver's `--tool` value.
    pub fn tool(self) -> &'static str {
        match self {
            Peer::Triangle => "triangle",
            Peer::GmshFrontal => "gmsh-frontal",
        }
    }

    /// The peer with this CSV name.
    pub fn parse(name: &str) -> Option<Peer> {
        Peer::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The stand-in of this tool among our methods, if there is one.
    pub fn stand_in(self) -> Option<MethodId> {
        match self {
            Peer::Triangle => Some(MethodId::Triangle),
            Peer::GmshFrontal => None,
        }
    }
}

/// The region files the driver reads, copied from the repository's region data at build time.
const REGION_FILES: [(&str, &str); 10] = [
    (
        "circle",
        include_str!("../../crates/geometry/regions/circle.json"),
    ),
    (
        "annulus",
        include_str!("../../crates/geometry/regions/annulus.json"),
    ),
    (
        "square_hole",
        include_str!("../../crates/geometry/regions/square_hole.json"),
    ),
    (
        "hex_hole",
        include_str!("../../crates/geometry/regions/hex_hole.json"),
    ),
    (
        "horn",
        include_str!("../../crates/geometry/regions/horn.json"),
    ),
    (
        "superellipse",
        include_str!("../../crates/geometry/regions/superellipse.json"),
    ),
    (
        "bike_seat",
        include_str!("../../crates/geometry/regions/bike_seat.json"),
    ),
    (
        "pie_hole",
        include_str!("../../crates/geometry/regions/pie_hole.json"),
    ),
    (
        "square_two_hex",
        include_str!("../../crates/geometry/regions/square_two_hex.json"),
    ),
    (
        "lake",
        include_str!("../../crates/geometry/regions/lake.json"),
    ),
];

/// The region file of a paper region, as the driver reads it.
pub fn region_json(name: &str) -> Option<&'static str> {
    REGION_FILES.iter().find(|(n, _)| *n == name).map(|f| f.1)
}

/// This repository's top directory (where `scripts/` is).
fn repo_dir() -> PathBuf {
    let study = Path::new(env!("CARGO_MANIFEST_DIR"));
    study.parent().unwrap_or(study).to_path_buf()
}

/// `scripts/real_peers.py` of this repository.
pub fn driver_path() -> PathBuf {
    repo_dir().join("scripts").join("real_peers.py")
}

/// The interpreter used without `--python`: `$CVTMESH_PYTHON` if set, else this
/// repository's `scripts/.venv/bin/python`.
pub fn default_python() -> PathBuf {
    match std::env::var_os("CVTMESH_PYTHON") {
        Some(p) if !p.is_empty() => PathBuf::from(p),
        _ => repo_dir()
            .join("scripts")
            .join(".venv")
            .join("bin")
            .join("python"),
    }
}

/// What to say, besides the reason, when the tools cannot run.
const HOW_TO_GET_THEM: &str = "scripts/compare_tools.sh makes scripts/.venv with numpy, \
    triangle and gmsh (or pass --python PATH, or set CVTMESH_PYTHON)";

/// Longest a single driver run may take.
const RUN_LIMIT: Duration = Duration::from_secs(600);

/// The interpreter and the driver.
#[derive(Clone, Debug)]
pub struct PythonTools {
    /// The Python interpreter.
    pub python: PathBuf,
    /// `scripts/real_peers.py`.
    pub driver: PathBuf,
    /// The packages' versions, as the driver reported them ("gmsh=4.15.2 numpy=… triangle=…").
    pub versions: String,
}

/// A scratch directory of this process, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> Result<Scratch, String> {
        let base = std::env::temp_dir();
        for i in 0..100u32 {
            let p = base.join(format!("cvtmesh-real-peers-{}-{i}", std::process::id()));
            if std::fs::create_dir(&p).is_ok() {
                return Ok(Scratch(p));
            }
        }
        Err(format!(
            "cannot create a scratch directory in {}",
            base.display()
        ))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Run `cmd` with stdout and stderr in files of `scratch` (a pipe could fill and stall the
/// child); kill it after `limit`. Returns the exit code (None if killed by a signal), stdout
/// and stderr.
fn run_captured(
    cmd: &mut Command,
    scratch: &Path,
    tag: &str,
    limit: Duration,
) -> Result<(Option<i32>, String, String), std::io::Error> {
    let (out_path, err_path) = (
        scratch.join(format!("{tag}.out")),
        scratch.join(format!("{tag}.err")),
    );
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out_path)?)
        .stderr(std::fs::File::create(&err_path)?)
        .spawn()?;
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait()? {
            break Some(s);
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let read = |p: &Path| {
        std::fs::read(p)
            .map(|b| String::from_utf8_lossy(&b).into_owned())
            .unwrap_or_default()
    };
    let (out, err) = (read(&out_path), read(&err_path));
    match status {
        Some(s) => Ok((s.code(), out, err)),
        None => Err(std::io::Error::new(
            std::io::ErrorKind::TimedOut,
            format!("no result within {} s", limit.as_secs()),
        )),
    }
}

/// The first non-empty line of `text`, or "no output".
fn first_line(text: &str) -> &str {
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("no output")
}

/// The last line of `text` that starts with `real_peers:` (the driver's answer), without it.
fn driver_line(text: &str) -> Option<&str> {
    text.lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix("real_peers:"))
        .map(str::trim)
}

/// Ask the driver whether the interpreter has the packages. `Err` is one line saying what is
/// missing and how to get it.
pub fn check_python(python: &Path) -> Result<PythonTools, String> {
    let skip = |why: String| format!("real peers skipped: {why}; {HOW_TO_GET_THEM}");
    let driver = driver_path();
    if !driver.is_file() {
        return Err(skip(format!("the driver {} is missing", driver.display())));
    }
    let scratch = Scratch::new().map_err(skip)?;
    let ran = run_captured(
        Command::new(python).arg(&driver).arg("--check"),
        &scratch.0,
        "check",
        Duration::from_secs(120),
    );
    match ran {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(skip(format!(
            "no Python interpreter at {}",
            python.display()
        ))),
        Err(e) => Err(skip(format!("cannot run {}: {e}", python.display()))),
        Ok((Some(0), out, _)) => match driver_line(&out).and_then(|l| l.strip_prefix("ok")) {
            Some(v) => Ok(PythonTools {
                python: python.to_path_buf(),
                driver,
                versions: v.trim().to_string(),
            }),
            None => Err(skip(format!(
                "{} {} --check answered '{}'",
                python.display(),
                driver.display(),
                first_line(&out)
            ))),
        },
        Ok((code, out, err)) => {
            let why = match driver_line(&out) {
                Some(line) => line.to_string(),
                None => format!(
                    "{} {} --check failed ({}): {}",
                    python.display(),
                    driver.display(),
                    code.map_or("killed".to_string(), |c| format!("exit {c}")),
                    first_line(if err.trim().is_empty() { &out } else { &err })
                ),
            };
            Err(skip(why))
        }
    }
}

/// What the driver printed about a mesh it wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct DriverOutput {
    /// `triangle` or `gmsh-frontal`.
    pub tool: String,
    /// Vertices of the mesh written.
    pub k: usize,
    /// Triangles of the mesh written.
    pub triangles: usize,
    /// Seconds of the mesher call (the last search step).
    pub seconds: f64,
    /// The tool's parameters (Triangle's switches, Gmsh's options and size).
    pub params: String,
}

/// Parse the driver's stdout: its last `real_peers:` line, either
/// `tool=T K=N triangles=N seconds=S params=P` (`params` last, it may hold anything but a
/// newline) or `error MESSAGE`.
pub fn parse_driver_output(stdout: &str) -> Result<DriverOutput, String> {
    let line = driver_line(stdout)
        .ok_or_else(|| format!("the driver printed no answer ({})", first_line(stdout)))?;
    if let Some(e) = line.strip_prefix("error") {
        return Err(format!("the tool failed: {}", e.trim()));
    }
    let (head, params) = match line.split_once(" params=") {
        Some((h, p)) => (h, p.trim().to_string()),
        None => (line, String::new()),
    };
    let mut fields: BTreeMap<&str, &str> = BTreeMap::new();
    for word in head.split_whitespace() {
        let (k, v) = word
            .split_once('=')
            .ok_or_else(|| format!("unexpected '{word}' in the driver's answer '{line}'"))?;
        fields.insert(k, v);
    }
    let get = |k: &str| {
        fields
            .get(k)
            .copied()
            .ok_or_else(|| format!("no {k}= in the driver's answer '{line}'"))
    };
    let bad = |k: &str, v: &str| format!("bad {k}={v} in the driver's answer '{line}'");
    let k = get("K")?;
    let t = get("triangles")?;
    let s = get("seconds")?;
    Ok(DriverOutput {
        tool: get("tool")?.to_string(),
        k: k.parse().map_err(|_| bad("K", k))?,
        triangles: t.parse().map_err(|_| bad("triangles", t))?,
        seconds: s.parse().map_err(|_| bad("seconds", s))?,
        params,
    })
}

/// One line of `csv/real_peers.csv`: a real tool's mesh of one table, scored by the exact
/// measures; or, with `error` set, why there is none (measures NaN).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct PeerRow {
    /// The paper's table.
    pub table: u8,
    /// Region name.
    pub region: String,
    /// The K asked for (the paper's K).
    pub K_requested: usize,
    /// [`Peer::name`].
    pub peer: String,
    /// Vertices obtained.
    pub K: usize,
    /// Triangles obtained.
    pub Ktilde: usize,
    /// λ.
    pub lambda: f64,
    /// γ.
    pub gamma: f64,
    /// h.
    pub h: f64,
    /// μ.
    pub mu: f64,
    /// χ.
    pub chi: f64,
    /// ν.
    pub nu: f64,
    /// τ.
    pub tau: f64,
    /// d.
    pub d: f64,
    /// α.
    pub alpha: f64,
    /// β.
    pub beta: f64,
    /// q.
    pub q: f64,
    /// p.
    pub p: f64,
    /// Seconds of the tool's mesher call, as the driver timed it.
    pub seconds: f64,
    /// The tool's parameters.
    pub params: String,
    /// Empty, or why the run failed.
    pub error: String,
}

impl PeerRow {
    fn new(t: &TableSpec, peer: Peer) -> PeerRow {
        PeerRow {
            table: t.number,
            region: t.region.to_string(),
            K_requested: t.k,
            peer: peer.name().to_string(),
            K: 0,
            Ktilde: 0,
            lambda: f64::NAN,
            gamma: f64::NAN,
            h: f64::NAN,
            mu: f64::NAN,
            chi: f64::NAN,
            nu: f64::NAN,
            tau: f64::NAN,
            d: f64::NAN,
            alpha: f64::NAN,
            beta: f64::NAN,
            q: f64::NAN,
            p: f64::NAN,
            seconds: f64::NAN,
            params: String::new(),
            error: String::new(),
        }
    }

    /// A row recording a failed run.
    pub fn failed(t: &TableSpec, peer: Peer, error: &str) -> PeerRow {
        PeerRow {
            error: error.replace('\n', " "),
            ..PeerRow::new(t, peer)
        }
    }

    /// The peer, if the name is known.
    pub fn peer_id(&self) -> Option<Peer> {
        Peer::parse(&self.peer)
    }

    /// The value of one table row (NaN for a failed run).
    pub fn value(&self, m: Measure) -> f64 {
        match m {
            Measure::K if self.error.is_empty() => self.K as f64,
            Measure::Ktilde if self.error.is_empty() => self.Ktilde as f64,
            Measure::K | Measure::Ktilde => f64::NAN,
            Measure::Lambda => self.lambda,
            Measure::Gamma => self.gamma,
            Measure::H => self.h,
            Measure::Mu => self.mu,
            Measure::Chi => self.chi,
            Measure::Nu => self.nu,
            Measure::Tau => self.tau,
            Measure::D => self.d,
            Measure::Alpha => self.alpha,
            Measure::Beta => self.beta,
            Measure::Q => self.q,
            Measure::P => self.p,
        }
    }
}

/// Read the mesh the driver wrote at `node` (with its `.ele`), check it against what the
/// driver printed, and score it with the exact measures on `table`'s region.
pub fn score_mesh(
    table: &TableSpec,
    peer: Peer,
    printed: &DriverOutput,
    node: &Path,
    region: &Region,
) -> Result<PeerRow, String> {
    if printed.tool != peer.tool() {
        return Err(format!(
            "the driver ran '{}', not '{}'",
            printed.tool,
            peer.tool()
        ));
    }
    let mesh = cvtmesh::io::read_triangle(node).map_err(|e| e.to_string())?;
    if mesh.num_vertices() != printed.k || mesh.num_triangles() != printed.triangles {
        return Err(format!(
            "{} has {} vertices and {} triangles; the driver said {} and {}",
            node.display(),
            mesh.num_vertices(),
            mesh.num_triangles(),
            printed.k,
            printed.triangles
        ));
    }
    let m = crate::run::catch(|| {
        cvtmesh::metrics::measures(&mesh, region).map_err(|e| format!("exact measures: {e}"))
    })?;
    let v = m.values();
    Ok(PeerRow {
        K: mesh.num_vertices(),
        Ktilde: mesh.num_triangles(),
        lambda: v[2],
        gamma: v[3],
        h: v[4],
        mu: v[5],
        chi: v[6],
        nu: v[7],
        tau: v[8],
        d: v[9],
        alpha: v[10],
        beta: v[11],
        q: v[12],
        p: v[13],
        seconds: printed.seconds,
        params: printed.params.clone(),
        ..PeerRow::new(table, peer)
    })
}

/// `DIR/meshes/REGION_K<K>_<peer>` (the driver adds `.node` and `.ele`).
pub fn mesh_base(dir: &Path, region: &str, k: usize, peer: Peer) -> PathBuf {
    dir.join("meshes")
        .join(format!("{region}_K{k}_{}", peer.name()))
}

/// `DIR/csv/real_peers.csv`.
pub fn peers_csv(dir: &Path) -> PathBuf {
    dir.join("csv").join("real_peers.csv")
}

/// `DIR/csv/real_peers_fidelity.csv`.
pub fn peers_fidelity_csv(dir: &Path) -> PathBuf {
    dir.join("csv").join("real_peers_fidelity.csv")
}

/// `DIR/real_peers.md`.
pub fn peers_md(dir: &Path) -> PathBuf {
    dir.join("real_peers.md")
}

/// The (table, peer) runs for `regions`, in table order.
pub fn peer_runs(regions: &[&str]) -> Vec<(&'static TableSpec, Peer)> {
    TABLES
        .iter()
        .filter(|t| regions.contains(&t.region))
        .flat_map(|t| Peer::ALL.map(|p| (t, p)))
        .collect()
}

/// How the real Triangle is run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleSettings {
    /// `-q` bound in degrees.
    pub min_angle_deg: f64,
    /// Let Triangle split boundary segments (its default; without it `-Y` keeps the boundary
    /// as sampled: curves at the hexagonal spacing of K, straight edges whole).
    pub split_boundary: bool,
    /// Give Triangle straight edges split at the hexagonal spacing of K, as curves are
    /// (otherwise whole, as our `refine` gets them).
    pub sample_straight: bool,
}

impl Default for TriangleSettings {
    /// As our TRIANGLE: [`TRIANGLE_MIN_ANGLE_DEG`], and straight boundary edges split when
    /// encroached (our `refine` splits them so).
    fn default() -> Self {
        TriangleSettings {
            min_angle_deg: TRIANGLE_MIN_ANGLE_DEG,
            split_boundary: true,
            sample_straight: false,
        }
    }
}

/// Mesh one table with one tool through the driver, writing the mesh under `dir/meshes`,
/// and score it. `triangle` applies to [`Peer::Triangle`] only.
pub fn run_peer(
    tools: &PythonTools,
    dir: &Path,
    table: &TableSpec,
    peer: Peer,
    triangle: &TriangleSettings,
) -> Result<PeerRow, String> {
    let scratch = Scratch::new()?;
    run_one(tools, &scratch.0, dir, table, peer, triangle)
}

fn run_one(
    tools: &PythonTools,
    scratch: &Path,
    dir: &Path,
    table: &TableSpec,
    peer: Peer,
    triangle: &TriangleSettings,
) -> Result<PeerRow, String> {
    let json = region_json(table.region)
        .ok_or_else(|| format!("no region file for '{}'", table.region))?;
    let region_file = scratch.join(format!("{}.json", table.region));
    std::fs::write(&region_file, json)
        .map_err(|e| format!("cannot write {}: {e}", region_file.display()))?;
    let region = Region::builtin(table.region).map_err(|e| e.to_string())?;
    let base = mesh_base(dir, table.region, table.k, peer);
    if let Some(parent) = base.parent() {
        std::fs::create_dir_all(parent)
            .map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
    }
    let mut cmd = Command::new(&tools.python);
    cmd.arg(&tools.driver)
        .args(["--tool", peer.tool(), "--k", &table.k.to_string()])
        .arg("--region")
        .arg(&region_file)
        .arg("--out")
        .arg(&base)
        .args(["--min-angle", &triangle.min_angle_deg.to_string()]);
    if triangle.split_boundary {
        cmd.arg("--split-boundary");
    }
    if triangle.sample_straight {
        cmd.arg("--sample-straight");
    }
    let tag = format!("{}_{}", table.number, peer.tool());
    let (code, out, err) =
        run_captured(&mut cmd, scratch, &tag, RUN_LIMIT).map_err(|e| e.to_string())?;
    let printed = parse_driver_output(&out).map_err(|e| match code {
        Some(0) => e,
        _ => format!(
            "{e} (exit {}; {})",
            code.map_or("by a signal".into(), |c| c.to_string()),
            first_line(&err)
        ),
    })?;
    let mut node = base.into_os_string();
    node.push(".node");
    score_mesh(table, peer, &printed, Path::new(&node), &region)
}

/// Run both tools on every table of `regions`, one after the other (each run takes well
/// under a second of the tool's time, most of it Python's start). `on_run` hears each run's
/// label, whether it worked and its wall time. A failed run is a row with its error.
pub fn run_peers(
    tools: &PythonTools,
    dir: &Path,
    regions: &[&str],
    on_run: &dyn Fn(&str, bool, f64),
) -> Result<Vec<PeerRow>, StudyError> {
    let scratch = Scratch::new().map_err(StudyError::BadOption)?;
    let mut rows = Vec::new();
    for (t, peer) in peer_runs(regions) {
        let start = Instant::now();
        let row = run_one(
            tools,
            &scratch.0,
            dir,
            t,
            peer,
            &TriangleSettings::default(),
        )
        .unwrap_or_else(|e| PeerRow::failed(t, peer, &e));
        on_run(
            &format!("{} K={} {}", t.region, t.k, peer.name()),
            row.error.is_empty(),
            start.elapsed().as_secs_f64(),
        );
        rows.push(row);
    }
    Ok(rows)
}

/// Sort rows by table, then peer.
pub fn sort_peer_rows(rows: &mut [PeerRow]) {
    rows.sort_by(|a, b| (a.table, a.peer_id(), &a.peer).cmp(&(b.table, b.peer_id(), &b.peer)));
}

/// Read `DIR/csv/real_peers.csv` (empty if absent).
pub fn read_peers(dir: &Path) -> Result<Vec<PeerRow>, StudyError> {
    let p = peers_csv(dir);
    if p.exists() {
        record::read_csv(&p)
    } else {
        Ok(Vec::new())
    }
}

/// Write `DIR/csv/real_peers.csv` (sorted).
pub fn write_peers(dir: &Path, rows: &mut [PeerRow]) -> Result<PathBuf, StudyError> {
    sort_peer_rows(rows);
    let p = peers_csv(dir);
    output::write_atomic(&p, &record::to_csv(rows)?)?;
    Ok(p)
}

/// One real value against one of our methods' values over seeds (exact measures, our scale).
#[derive(Clone, Debug, PartialEq)]
pub struct PeerCell {
    /// The paper's table.
    pub table: u8,
    /// The row.
    pub measure: Measure,
    /// The real tool.
    pub peer: Peer,
    /// Our method placed against it.
    pub method: MethodId,
    /// The real tool's value.
    pub real: f64,
    /// Our method's values over seeds, sorted (NaN dropped).
    pub ours: Vec<f64>,
}

impl PeerCell {
    /// Our median over seeds.
    pub fn median(&self) -> f64 {
        median(&self.ours)
    }

    /// Ours ÷ real (our median).
    pub fn ratio(&self) -> f64 {
        self.median() / self.real
    }

    /// True if the real value lies within our range over seeds.
    pub fn in_range(&self) -> bool {
        match (self.ours.first(), self.ours.last()) {
            (Some(lo), Some(hi)) => *lo <= self.real && self.real <= *hi,
            _ => false,
        }
    }

    /// True if the real value is within ±[`NEAR`] of our median (as `fidelity.md` judges
    /// the paper's numbers).
    pub fn near(&self) -> bool {
        let m = self.median();
        m.is_finite() && (self.real - m).abs() <= NEAR * m.abs()
    }
}

/// Every successful real value of `peers` on `tables` against each of our methods with exact
/// rows there: TRIANGLE against the real Triangle (its original), every method against Gmsh.
pub fn compare_peers(rows: &[Row], peers: &[PeerRow], tables: &[&TableSpec]) -> Vec<PeerCell> {
    let mut ours: BTreeMap<(u8, MethodId), Vec<&Row>> = BTreeMap::new();
    for t in tables {
        for r in rows
            .iter()
            .filter(|r| r.region == t.region && r.K_requested == t.k && r.kind == Kind::Exact)
        {
            if let Some(m) = r.method_id() {
                ours.entry((t.number, m)).or_default().push(r);
            }
        }
    }
    let mut out = Vec::new();
    for t in tables {
        for p in peers.iter().filter(|p| {
            p.table == t.number
                && p.region == t.region
                && p.K_requested == t.k
                && p.error.is_empty()
        }) {
            let Some(peer) = p.peer_id() else { continue };
            let methods: Vec<MethodId> = match peer.stand_in() {
                Some(m) => vec![m],
                None => MethodId::ALL.to_vec(),
            };
            for method in methods {
                let Some(rs) = ours.get(&(t.number, method)) else {
                    continue;
                };
                for m in Measure::ALL {
                    let mut v: Vec<f64> = rs
                        .iter()
                        .map(|r| r.value(m))
                        .filter(|v| !v.is_nan())
                        .collect();
                    v.sort_by(f64::total_cmp);
                    out.push(PeerCell {
                        table: t.number,
                        measure: m,
                        peer,
                        method,
                        real: p.value(m),
                        ours: v,
                    });
                }
            }
        }
    }
    out
}

/// CSV of every [`PeerCell`].
pub fn peer_cells_csv(cells: &[PeerCell]) -> Vec<u8> {
    let mut s = String::from(
        "table,measure,peer,method,real,seeds,min,median,max,ours_over_real,real_in_range,real_near_median\n",
    );
    let num = |x: Option<&f64>| x.map_or(String::new(), |v| format!("{v}"));
    for c in cells {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            c.table,
            c.measure.csv_name(),
            c.peer.name(),
            c.method.name(),
            c.real,
            c.ours.len(),
            num(c.ours.first()),
            c.median(),
            num(c.ours.last()),
            c.ratio(),
            c.in_range(),
            c.near()
        );
    }
    s.into_bytes()
}

/// The quality cells that enter the summaries (Table 6's misprinted γ and h are kept: the
/// comparison here does not involve the paper).
fn quality(cells: &[PeerCell], peer: Peer, method: MethodId, m: Measure) -> Vec<&PeerCell> {
    cells
        .iter()
        .filter(|c| c.peer == peer && c.method == method && c.measure == m && !c.ours.is_empty())
        .collect()
}

fn count(cells: &[&PeerCell], pred: impl Fn(&PeerCell) -> bool) -> String {
    format!(
        "{}/{}",
        cells.iter().filter(|c| pred(c)).count(),
        cells.len()
    )
}

fn sorted_finite(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = v.filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    v
}

fn two(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2}")
    } else {
        "—".into()
    }
}

/// τ and d at the paper's length scale (the paper's circle and annulus coordinates are
/// halved; the other measures are scale-free), so a value can be set beside the paper's.
pub fn at_paper_scale(region: &str, m: Measure, v: f64) -> f64 {
    let s = sample_scale(region);
    match m {
        Measure::Tau => v * s * s,
        Measure::D => v * s.powi(4),
        _ => v,
    }
}

fn render_runs(out: &mut String, peers: &[PeerRow]) {
    out.push_str("## Runs\n\n");
    out.push_str(
        "| table | region | tool | K asked | K | K̃ | mesher time (s) | parameters |\n\
         | ---: | :--- | :--- | ---: | ---: | ---: | ---: | :--- |\n",
    );
    for p in peers {
        let tool = p
            .peer_id()
            .map_or(p.peer.clone(), |id| id.column().to_string());
        if p.error.is_empty() {
            let _ = writeln!(
                out,
                "| {} | {} | {tool} | {} | {} | {} | {:.4} | `{}` |",
                p.table, p.region, p.K_requested, p.K, p.Ktilde, p.seconds, p.params
            );
        } else {
            let _ = writeln!(
                out,
                "| {} | {} | {tool} | {} | — | — | — | failed (below) |",
                p.table, p.region, p.K_requested
            );
        }
    }
    out.push('\n');
}

fn render_stand_in(out: &mut String, cells: &[PeerCell]) {
    out.push_str("## Our TRIANGLE against the real Triangle\n\n");
    let _ = writeln!(
        out,
        "Per measure over the tables: ours ÷ real (ours: our median over seeds), its median and \
         range; in how many tables the real value lies inside our range over seeds; and in how \
         many it is within ±{:.0} % of our median. Our TRIANGLE does not use the seed, so its \
         range is one value and \"in range\" means equal: judge it by the ratio and \"within\".\n",
        NEAR * 100.0
    );
    out.push_str(
        "| measure | ours ÷ real, median | ours ÷ real, min–max | real in our range | real within ±30 % |\n\
         | :--- | ---: | ---: | ---: | ---: |\n",
    );
    let mut all = Vec::new();
    for m in Measure::QUALITY {
        let c = quality(cells, Peer::Triangle, MethodId::Triangle, m);
        let r = sorted_finite(c.iter().map(|c| c.ratio()));
        let _ = writeln!(
            out,
            "| {} | {} | {}–{} | {} | {} |",
            m.symbol(),
            two(median(&r)),
            two(r.first().copied().unwrap_or(f64::NAN)),
            two(r.last().copied().unwrap_or(f64::NAN)),
            count(&c, PeerCell::in_range),
            count(&c, PeerCell::near)
        );
        all.extend(c);
    }
    let r = sorted_finite(all.iter().map(|c| c.ratio()));
    let _ = writeln!(
        out,
        "| all | {} | {}–{} | {} | {} |\n",
        two(median(&r)),
        two(r.first().copied().unwrap_or(f64::NAN)),
        two(r.last().copied().unwrap_or(f64::NAN)),
        count(&all, PeerCell::in_range),
        count(&all, PeerCell::near)
    );
}

/// The paper's TRIANGLE numbers against the real Triangle and against our TRIANGLE.
fn render_paper(out: &mut String, cells: &[PeerCell], paper: &PaperTables, tables: &[&TableSpec]) {
    out.push_str("## The paper's TRIANGLE against the real Triangle and against ours\n\n");
    let _ = writeln!(
        out,
        "Which of the two the paper's TRIANGLE column is closer to: paper ÷ real and paper ÷ \
         ours (our median), medians over the tables, and in how many tables the paper's number \
         is within ±{:.0} % of each; τ and d at the paper's length scale, Table 6's misprinted \
         γ and h left out. \"Prints as real\": the real value lies within half a unit of the \
         paper's last digit, i.e. it would print as the paper's number; \"in our range\": \
         `fidelity.md`'s test, a value the paper's number rounds to lies within our range over \
         seeds. The real Triangle gives one mesh whatever the order of its input \
         (`scripts/triangle_order.py`), so where our TRIANGLE's range is one value (the regions \
         without a closed curve) a faithful stand-in is in range exactly where the original \
         prints as the paper.\n",
        NEAR * 100.0
    );
    out.push_str(
        "| measure | paper ÷ real | paper within ±30 % of real | paper prints as real | paper ÷ ours | paper within ±30 % of ours | paper in our range |\n\
         | :--- | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    let region = |n: u8| tables.iter().find(|t| t.number == n).map(|t| t.region);
    let near = |a: f64, b: f64| b.is_finite() && (a - b).abs() <= NEAR * b.abs();
    let [mut tot_real, mut tot_ours, mut tot_equal, mut tot_range, mut tot] = [0; 5];
    for m in Measure::QUALITY {
        let (mut vs_real, mut vs_ours) = (Vec::new(), Vec::new());
        let (mut equal, mut in_range) = (0, 0);
        for c in quality(cells, Peer::Triangle, MethodId::Triangle, m) {
            let (Some(r), Some(p)) = (region(c.table), paper.cell(c.table, m, MethodId::Triangle))
            else {
                continue;
            };
            if untrustworthy(c.table, m) {
                continue;
            }
            let real = at_paper_scale(r, m, c.real);
            vs_real.push((p.value, real));
            vs_ours.push((p.value, at_paper_scale(r, m, c.median())));
            // `fidelity.md`'s test, against the real value alone and against ours.
            let against = |ours: Vec<f64>| Fidelity {
                table: c.table,
                measure: m,
                method: MethodId::Triangle,
                basis: Basis::ExactPaperScale,
                paper: p.value,
                half_unit: p.half_unit(m),
                ours,
            };
            equal += usize::from(against(vec![real]).in_range());
            in_range += usize::from(
                against(c.ours.iter().map(|v| at_paper_scale(r, m, *v)).collect()).in_range(),
            );
        }
        let n_real = vs_real.iter().filter(|(p, x)| near(*p, *x)).count();
        let n_ours = vs_ours.iter().filter(|(p, x)| near(*p, *x)).count();
        tot_real += n_real;
        tot_ours += n_ours;
        tot_equal += equal;
        tot_range += in_range;
        tot += vs_real.len();
        let n = vs_real.len();
        let _ = writeln!(
            out,
            "| {} | {} | {n_real}/{n} | {equal}/{n} | {} | {n_ours}/{n} | {in_range}/{n} |",
            m.symbol(),
            two(median(&sorted_finite(vs_real.iter().map(|(p, x)| p / x)))),
            two(median(&sorted_finite(vs_ours.iter().map(|(p, x)| p / x)))),
        );
    }
    let _ = writeln!(
        out,
        "| all | | {tot_real}/{tot} | {tot_equal}/{tot} | | {tot_ours}/{tot} | {tot_range}/{tot} |\n"
    );
}

fn render_reference(out: &mut String, cells: &[PeerCell], peers: &[PeerRow]) {
    let methods: Vec<MethodId> = {
        let s: BTreeSet<MethodId> = cells
            .iter()
            .filter(|c| c.peer == Peer::GmshFrontal)
            .map(|c| c.method)
            .collect();
        s.into_iter().collect()
    };
    if methods.is_empty() {
        return;
    }
    out.push_str("## Gmsh-FD (real) as a reference\n\n");
    out.push_str(
        "No column of the paper imitates Gmsh; its Frontal-Delaunay mesher is a common yardstick. \
         Each cell: the median over the tables of ours ÷ Gmsh (ours: our median over seeds), and \
         in how many tables Gmsh's value lies inside our range over seeds. The real Triangle's \
         column is its own value ÷ Gmsh's.\n\n",
    );
    out.push_str("| measure |");
    for m in &methods {
        let _ = write!(out, " {} |", m.column());
    }
    out.push_str(" Triangle (real) |\n| :--- |");
    for _ in &methods {
        out.push_str(" ---: |");
    }
    out.push_str(" ---: |\n");
    for measure in Measure::QUALITY {
        let _ = write!(out, "| {} |", measure.symbol());
        for &m in &methods {
            let c = quality(cells, Peer::GmshFrontal, m, measure);
            let r = sorted_finite(c.iter().map(|c| c.ratio()));
            let _ = write!(
                out,
                " {} ({}) |",
                two(median(&r)),
                count(&c, PeerCell::in_range)
            );
        }
        let by_table = |peer: Peer| -> BTreeMap<u8, f64> {
            peers
                .iter()
                .filter(|p| p.peer_id() == Some(peer) && p.error.is_empty())
                .map(|p| (p.table, p.value(measure)))
                .collect()
        };
        let (tri, gm) = (by_table(Peer::Triangle), by_table(Peer::GmshFrontal));
        let r = sorted_finite(tri.iter().filter_map(|(t, v)| gm.get(t).map(|g| v / g)));
        let _ = writeln!(out, " {} |", two(median(&r)));
    }
    out.push('\n');
}

fn render_tables(
    out: &mut String,
    rows: &[Row],
    peers: &[PeerRow],
    paper: &PaperTables,
    tables: &[&TableSpec],
) {
    out.push_str("## Table by table\n\n");
    out.push_str(
        "Each table's rows with the paper's ×10ⁿ scaling and τ and d at the paper's length \
         scale (as in `fidelity.md`), so that every column can be read against the paper's. Our \
         TRIANGLE: the mean over seeds (± the half-width of its 95 % interval with several).\n\n",
    );
    for t in tables {
        let peer_row = |p: Peer| {
            peers
                .iter()
                .find(|r| r.table == t.number && r.peer_id() == Some(p) && r.error.is_empty())
        };
        if Peer::ALL.iter().all(|&p| peer_row(p).is_none()) {
            continue;
        }
        let _ = writeln!(out, "### {}\n", t.title());
        out.push_str("| | TRIANGLE (ours) |");
        for p in Peer::ALL {
            let _ = write!(out, " {} |", p.column());
        }
        out.push_str(" paper's TRIANGLE |\n| :--- | ---: |");
        for _ in Peer::ALL {
            out.push_str(" ---: |");
        }
        out.push_str(" ---: |\n");
        for m in Measure::ALL {
            let (_, exp) = paper.row_exps(t.number, m);
            let ours: Vec<f64> = rows
                .iter()
                .filter(|r| {
                    r.region == t.region
                        && r.K_requested == t.k
                        && r.kind == Kind::Exact
                        && r.method_id() == Some(MethodId::Triangle)
                })
                .map(|r| at_paper_scale(t.region, m, r.value(m)))
                .collect();
            let _ = write!(
                out,
                "| {} | {} |",
                scaled_label(m, exp),
                format_cell(mean_std(&ours), m, exp)
            );
            for p in Peer::ALL {
                let v = peer_row(p).map(|r| at_paper_scale(t.region, m, r.value(m)));
                let _ = write!(
                    out,
                    " {} |",
                    format_cell(v.and_then(|v| mean_std(&[v])), m, exp)
                );
            }
            let printed =
                paper
                    .cell(t.number, m, MethodId::Triangle)
                    .map_or("—".to_string(), |c| {
                        let v = format_cell(mean_std(&[c.value]), m, exp);
                        if untrustworthy(t.number, m) {
                            format!("{v} †")
                        } else {
                            v
                        }
                    });
            let _ = writeln!(out, " {printed} |");
        }
        out.push('\n');
    }
    if tables.iter().any(|t| t.number == 6) {
        out.push_str("† The paper's γ and h rows of Table 6 are a typesetting error.\n\n");
    }
}

/// The Markdown of `real_peers.md` from our rows (`metrics.csv`) and the real tools' rows.
pub fn render_peers_md(rows: &[Row], peers: &[PeerRow], paper: &PaperTables) -> String {
    let tables: Vec<&TableSpec> = TABLES
        .iter()
        .filter(|t| peers.iter().any(|p| p.table == t.number))
        .collect();
    let cells = compare_peers(rows, peers, &tables);
    let seeds: Vec<u64> = {
        let s: BTreeSet<u64> = rows
            .iter()
            .filter(|r| r.kind == Kind::Exact)
            .map(|r| r.seed)
            .collect();
        s.into_iter().collect()
    };
    let mut out = String::new();
    out.push_str("# The real Triangle and Gmsh beside the stand-ins\n\n");
    let _ = writeln!(
        out,
        "Shewchuk's Triangle (the Python package `triangle`) and Gmsh's Frontal-Delaunay \
         mesher (algorithm 6, one uniform size) meshed each region by `scripts/real_peers.py` \
         at the paper's K, reached by a search on Triangle's area bound and on Gmsh's size (the K \
         obtained is below), and each mesh was scored by the study's exact measures, the code \
         that scores every method. Triangle ran with the angle bound of our TRIANGLE \
         (`-q` in its switches below), its curved boundaries split at the hexagonal spacing of K \
         and straight edges given whole, which it splits when encroached: the input our \
         `refine` gets. Gmsh's sizes are not extended inward from short boundary edges \
         (`Mesh.MeshSizeExtendFromBoundary=0`; by default a hexagonal hole's split edges halve \
         the spacing around it). Ours: {}. Command: `study --real-peers` (or \
         `--real-peers-only` to add them to a finished run); docs/study-statistics.md discusses \
         the findings.\n",
        seed_list(&seeds)
    );
    render_runs(&mut out, peers);
    render_stand_in(&mut out, &cells);
    render_paper(&mut out, &cells, paper, &tables);
    render_reference(&mut out, &cells, peers);
    render_tables(&mut out, rows, peers, paper, &tables);
    let failed: Vec<crate::Failure> = peers
        .iter()
        .filter(|p| !p.error.is_empty())
        .map(|p| crate::Failure {
            region: p.region.clone(),
            K_requested: p.K_requested,
            method: p.peer.clone(),
            seed: 0,
            error: p.error.clone(),
        })
        .collect();
    failed_runs(&mut out, &failed, |f| {
        format!("{} K={} {}", f.region, f.K_requested, f.method)
    });
    out
}

/// Redraw `real_peers.md` and `csv/real_peers_fidelity.csv` from `DIR/csv/real_peers.csv`
/// and our rows, if the former exists; nothing otherwise.
pub fn write_peers_report(
    dir: &Path,
    rows: &[Row],
    paper: &PaperTables,
) -> Result<Vec<PathBuf>, StudyError> {
    if !peers_csv(dir).exists() {
        return Ok(Vec::new());
    }
    let peers = read_peers(dir)?;
    let tables: Vec<&TableSpec> = TABLES
        .iter()
        .filter(|t| peers.iter().any(|p| p.table == t.number))
        .collect();
    let md = peers_md(dir);
    output::write_atomic(&md, render_peers_md(rows, &peers, paper).as_bytes())?;
    let csv = peers_fidelity_csv(dir);
    output::write_atomic(&csv, &peer_cells_csv(&compare_peers(rows, &peers, &tables)))?;
    Ok(vec![md, csv])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::fake_row;

    #[test]
    fn every_paper_region_has_its_file_and_it_is_the_builtin_region() {
        for name in crate::paper::region_names() {
            let json = region_json(name).unwrap_or_else(|| panic!("{name}"));
            let copy = Region::from_json_str(json, name).unwrap();
            let builtin = Region::builtin(name).unwrap();
            assert_eq!(copy.name(), name);
            assert_eq!(copy.area(), builtin.area(), "{name}");
            assert_eq!(copy.corners(), builtin.corners(), "{name}");
            assert_eq!(copy.pieces(), builtin.pieces(), "{name}");
        }
        assert!(region_json("moon").is_none());
    }

    #[test]
    fn driver_answers_are_parsed_or_refused() {
        let out = "some warning\nreal_peers: tool=triangle K=20 triangles=24 seconds=5.8e-05 params=pq20a0.2054 Y\n";
        let d = parse_driver_output(out).unwrap();
        assert_eq!(
            d,
            DriverOutput {
                tool: "triangle".into(),
                k: 20,
                triangles: 24,
                seconds: 5.8e-5,
                params: "pq20a0.2054 Y".into()
            }
        );
        let e = parse_driver_output("real_peers: error ValueError: no luck\n").unwrap_err();
        assert!(e.contains("no luck"), "{e}");
        assert!(parse_driver_output("Traceback (most recent call last)\n").is_err());
        assert!(
            parse_driver_output("real_peers: tool=triangle K=x triangles=1 seconds=0\n")
                .unwrap_err()
                .contains("bad K=x")
        );
        assert!(
            parse_driver_output("real_peers: tool=triangle K=3 seconds=0\n")
                .unwrap_err()
                .contains("no triangles=")
        );
    }

    #[test]
    fn a_missing_interpreter_is_one_line_with_the_remedy() {
        let e = check_python(Path::new("/nonexistent/python")).unwrap_err();
        assert!(!e.contains('\n'), "{e}");
        assert!(
            e.starts_with("real peers skipped: no Python interpreter at /nonexistent/python;")
                && e.contains("scripts/compare_tools.sh"),
            "{e}"
        );
    }

    fn peer(t: &TableSpec, p: Peer, x: f64) -> PeerRow {
        let mut r = PeerRow::new(t, p);
        r.K = t.k;
        r.Ktilde = 2 * t.k;
        r.seconds = 0.25;
        r.params = "pq20a0.01".into();
        for (i, slot) in [
            &mut r.lambda,
            &mut r.gamma,
            &mut r.h,
            &mut r.mu,
            &mut r.chi,
            &mut r.nu,
            &mut r.tau,
            &mut r.d,
            &mut r.alpha,
            &mut r.beta,
            &mut r.q,
            &mut r.p,
        ]
        .into_iter()
        .enumerate()
        {
            *slot = x / (i + 2) as f64 + 1.0 / 3.0;
        }
        r
    }

    #[test]
    fn stand_in_against_its_original_and_every_method_against_gmsh() {
        let t = &TABLES[1];
        // fake_row gives measure i the value x/i + 1/3: seeds 1..=3 span x in [1, 3].
        let rows: Vec<Row> = (1..=3)
            .flat_map(|s| {
                [MethodId::Triangle, MethodId::Ccvt2]
                    .map(|m| fake_row(t.region, t.k, m, s, Kind::Exact, s as f64))
            })
            .collect();
        let peers = vec![
            peer(t, Peer::Triangle, 2.5),
            peer(t, Peer::GmshFrontal, 5.0),
            PeerRow::failed(&TABLES[0], Peer::Triangle, "boom\nline two"),
        ];
        let cells = compare_peers(&rows, &peers, &[t]);
        // Triangle: only TRIANGLE; Gmsh: both methods; 14 rows each.
        assert_eq!(cells.len(), 3 * 14);
        let tri: Vec<&PeerCell> = cells.iter().filter(|c| c.peer == Peer::Triangle).collect();
        assert!(tri.iter().all(|c| c.method == MethodId::Triangle));
        let beta = tri.iter().find(|c| c.measure == Measure::Beta).unwrap();
        // Ours: x/11 + 1/3 with x = 1, 2, 3; real: 2.5/11 + 1/3, inside the range.
        assert!(beta.in_range() && beta.near());
        assert!((beta.ratio() - (2.0 / 11.0 + 1.0 / 3.0) / (2.5 / 11.0 + 1.0 / 3.0)).abs() < 1e-12);
        let gm = cells
            .iter()
            .find(|c| c.peer == Peer::GmshFrontal && c.measure == Measure::Lambda)
            .unwrap();
        // Real λ 5/2 + 1/3 lies above ours (at most 3/2 + 1/3).
        assert!(!gm.in_range());
        let md = render_peers_md(&rows, &peers, &PaperTables::embedded().unwrap());
        assert!(
            md.contains("| 2 | circle | Triangle (real) | 88 | 88 | 176 |"),
            "{md}"
        );
        assert!(md.contains("| 1 | circle | Triangle (real) | 19 | — | — | — | failed (below) |"));
        assert!(
            md.contains("- circle K=19 triangle-real: boom line two"),
            "{md}"
        );
        assert!(md.contains("| β | 0.92 | 0.92–0.92 | 1/1 | 1/1 |"), "{md}");
        assert!(md.contains("### Table 2."));
        assert!(md.contains(
            "| | TRIANGLE (ours) | Triangle (real) | Gmsh-FD (real) | paper's TRIANGLE |"
        ));
        assert!(
            !md.contains("### Table 1."),
            "a table with only failed runs has no detail"
        );
        let csv = String::from_utf8(peer_cells_csv(&cells)).unwrap();
        assert_eq!(csv.lines().count(), 1 + 3 * 14);
    }

    #[test]
    fn the_paper_prints_as_the_real_value_within_half_its_last_digit() {
        let t = &TABLES[1];
        let paper = PaperTables::embedded().unwrap();
        let printed = paper.cell(2, Measure::Beta, MethodId::Triangle).unwrap();
        let (p, half) = (printed.value, printed.half_unit(Measure::Beta));
        let render = |real: f64, ours: Vec<f64>| {
            let cell = PeerCell {
                table: 2,
                measure: Measure::Beta,
                peer: Peer::Triangle,
                method: MethodId::Triangle,
                real,
                ours,
            };
            let mut out = String::new();
            render_paper(&mut out, &[cell], &paper, &[t]);
            out
        };
        // The real value rounds to the paper's; our single value just does not.
        let md = render(p + 0.9 * half, vec![p + 1.1 * half]);
        assert!(
            md.contains("| β | 1.00 | 1/1 | 1/1 | 0.99 | 1/1 | 0/1 |"),
            "{md}"
        );
        assert!(md.contains("| all | | 1/1 | 1/1 | | 1/1 | 0/1 |"), "{md}");
        // The other way round: the real value prints differently, our range covers the paper.
        let md = render(p - 1.1 * half, vec![p - 3.0 * half, p + 0.95 * half]);
        assert!(md.contains("| all | | 1/1 | 0/1 | | 1/1 | 1/1 |"), "{md}");
    }

    #[test]
    fn peer_rows_round_trip_through_the_csv() {
        let dir = tempfile::tempdir().unwrap();
        let mut rows = vec![
            peer(&TABLES[2], Peer::GmshFrontal, 1.0),
            PeerRow::failed(&TABLES[2], Peer::Triangle, "no, \"quoted\", commas"),
        ];
        write_peers(dir.path(), &mut rows).unwrap();
        let back = read_peers(dir.path()).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!(back[0].peer, "triangle-real");
        assert_eq!(back[0].error, "no, \"quoted\", commas");
        assert!(back[0].beta.is_nan());
        assert_eq!(back[1], rows[1]);
        assert!(read_peers(&dir.path().join("none")).unwrap().is_empty());
    }
}
