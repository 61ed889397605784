//! CCVT at scale: per-phase cost of one iteration against spade alone, scaling of converged
//! runs with K, Lloyd against Anderson, and a coarse-to-fine start, on the unit circle and the
//! lake.
//!
//! `cargo bench -p cvtmesh-ccvt --bench scale -- [SIZES...] [TABLES...] [regions=a,b] [seed=N]`
//! - SIZES: generator counts such as `1e3 1e4 1e5 1e6` (default `1e3 1e4 1e5`);
//! - TABLES (default `iter converge anderson`):
//!   - `iter`: one iteration split into its phases, against spade's `bulk_load` of the same
//!     points (best of 3);
//!   - `converge` / `fast` / `newton`: Algorithm 2 with Lloyd / Anderson / Newton to the default
//!     tolerance (largest move < 1e-4 of the mean spacing), iterations per phase, seconds, time
//!     split, peak RSS;
//!   - `anderson`: Lloyd against Anderson (Algorithms 1 and 2);
//!   - `c2f`: Algorithm 2 from a refined coarse solution (vertices and edge midpoints of the
//!     CCVT mesh of about K/4 generators) against the lattice start at the same K.
//!
//! With no argument the words are read from the environment variable `CCVT_BENCH`.
//! Peak RSS is VmHWM from /proc/self/status, reset before each run by writing 5 to
//! /proc/self/clear_refs (Linux ≥ 4.0); where the reset is refused it is the process peak.
use cvtmesh_ccvt::{Algorithm, Ccvt, Generators, Init, Solver};
use geometry::{DVec2, Density, Region};
use mesh::{MeshRequest, Mesher};
use spade::{DelaunayTriangulation, Point2, Triangulation};
use std::collections::HashMap;
use std::time::Instant;
use tessellation::{clipped_cells, Delaunay};

struct Args {
    sizes: Vec<usize>,
    tables: Vec<String>,
    regions: Vec<String>,
    seed: u64,
}

fn parse_args() -> Args {
    // `cargo bench` passes `--bench`; flags are ignored.
    let mut words: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    if words.is_empty() {
        if let Ok(v) = std::env::var("CCVT_BENCH") {
            words = v.split_whitespace().map(String::from).collect();
        }
    }
    let mut args = Args {
        sizes: Vec::new(),
        tables: Vec::new(),
        regions: vec!["circle".into(), "lake".into()],
        seed: 1,
    };
    for w in words {
        if let Some(r) = w.strip_prefix("regions=") {
            args.regions = r.split(',').map(String::from).collect();
        } else if let Some(s) = w.strip_prefix("seed=") {
            args.seed = s.parse().expect("seed=N");
        } else if let Ok(x) = w.parse::<f64>() {
            args.sizes.push(x.round() as usize);
        } else {
            args.tables.push(w);
        }
    }
    if args.sizes.is_empty() {
        args.sizes = vec![1_000, 10_000, 100_000];
    }
    if args.tables.is_empty() {
        args.tables = vec!["iter".into(), "converge".into(), "anderson".into()];
    }
    args
}

/// Peak resident set size in MiB since the last reset (NaN where /proc is missing).
fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

/// Reset the peak RSS counter (ignored where not permitted).
fn reset_peak_rss() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

fn spade_bulk_load(pts: &[DVec2]) -> usize {
    let v: Vec<Point2<f64>> = pts.iter().map(|p| Point2::new(p.x, p.y)).collect();
    DelaunayTriangulation::<Point2<f64>>::bulk_load(v)
        .map(|t| t.num_vertices())
        .unwrap_or(0)
}

/// One solve with a record of (phase index, energy, seconds since start) per iteration.
struct Run {
    g: Generators,
    secs: f64,
    trace: Vec<(usize, f64, f64)>,
    peak_mib: f64,
}

impl Run {
    /// Iterations of each phase joined by '+'.
    fn phases(&self) -> String {
        let mut counts: Vec<usize> = Vec::new();
        for &(p, _, _) in &self.trace {
            if counts.len() <= p {
                counts.resize(p + 1, 0);
            }
            counts[p] += 1;
        }
        counts
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join("+")
    }
}

fn solve_with(m: &Ccvt, region: &Region, k: usize, seed: u64, start: Option<Vec<DVec2>>) -> Run {
    let req = MeshRequest::points(k).seed(seed).max_iter(20_000);
    reset_peak_rss();
    let mut trace = Vec::new();
    let mut phase = 0;
    let mut last_it = 0;
    let t = Instant::now();
    let mut progress = |p: mesh::Progress| {
        // The iteration count restarts at 1 in every phase.
        if p.iteration <= last_it {
            phase += 1;
        }
        last_it = p.iteration;
        trace.push((phase, p.energy, t.elapsed().as_secs_f64()));
    };
    let g = match start {
        None => m.generators(region, &req, &mut progress),
        Some(z) => m.generators_from(region, &req, z, &mut progress),
    }
    .expect("solve");
    let secs = t.elapsed().as_secs_f64();
    Run {
        g,
        secs,
        trace,
        peak_mib: peak_rss_mib(),
    }
}

fn solve(m: &Ccvt, region: &Region, k: usize, seed: u64) -> Run {
    solve_with(m, region, k, seed, None)
}

/// CVT energy (4) of `z` over Ω itself (comparable between runs whatever their Ω_ε).
fn energy_on_region(region: &Region, z: &[DVec2]) -> f64 {
    let spacing = MeshRequest::points(z.len()).spacing(region);
    let omega = region.polygonize(1e-4 * spacing);
    let del = Delaunay::new(z);
    clipped_cells(z, &del, &omega, &Density::Uniform).energy()
}

fn solver_name(s: Solver) -> &'static str {
    match s {
        Solver::Lloyd => "Lloyd",
        Solver::Anderson { .. } => "Anderson",
        Solver::Newton => "Newton",
    }
}

fn table_iter(args: &Args) {
    println!(
        "\n## One iteration (Algorithm 1, Lloyd, from the lattice), seconds, best of 3: the first \
         (triangulation built afresh) and the mean of the next four (the previous triangulation \
         repaired by flips where it can be)"
    );
    println!("threads: {}", rayon::current_num_threads());
    println!("| region | K | spade bulk_load | fresh: triangulation | cells+moments | projection | convergence | iteration | iteration / spade | next 4: by flips | triangulation | cells+moments | iteration | iteration / spade | peak MiB |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in &args.regions {
        let region = Region::builtin(name).expect("region");
        for &k in &args.sizes {
            let pts = cvtmesh_ccvt::initial_points(&region, k, Init::Lattice, args.seed);
            let mut ts = f64::INFINITY;
            for _ in 0..3 {
                let t = Instant::now();
                std::hint::black_box(spade_bulk_load(&pts));
                ts = ts.min(t.elapsed().as_secs_f64());
            }
            drop(pts);
            let m = Ccvt::algorithm1();
            let mut peak = 0.0f64;
            let mut best = |iters: usize| {
                let req = MeshRequest::points(k).seed(args.seed).max_iter(iters);
                let mut best: Option<cvtmesh_ccvt::Profile> = None;
                for _ in 0..3 {
                    reset_peak_rss();
                    let g = m.generators(&region, &req, &mut |_| {}).expect("solve");
                    peak = peak.max(peak_rss_mib());
                    if best.as_ref().is_none_or(|b| g.profile.total() < b.total()) {
                        best = Some(g.profile);
                    }
                }
                best.expect("three runs")
            };
            let (one, five) = (best(1), best(5));
            let n = (five.evaluations - one.evaluations).max(1) as f64;
            let next = |f: fn(&cvtmesh_ccvt::Profile) -> f64| (f(&five) - f(&one)).max(0.0) / n;
            let it = next(cvtmesh_ccvt::Profile::total);
            println!(
                "| {name} | {k} | {ts:.3} | {:.3} | {:.3} | {:.3} | {:.4} | {:.3} | {:.2} | {} of {n} | {:.3} | {:.3} | {it:.3} | {:.2} | {peak:.0} |",
                one.triangulation,
                one.cells,
                one.projection,
                one.convergence,
                one.total(),
                one.total() / ts,
                five.flipped - one.flipped,
                next(|p| p.triangulation),
                next(|p| p.cells),
                it / ts,
            );
        }
    }
}

fn table_converge(args: &Args, solver: Solver) {
    println!(
        "\n## Algorithm 2 ({}) to tol 1e-4 of the spacing ({})",
        solver_name(solver),
        if solver == Solver::Newton {
            "the default method: the row start from 3000 generators, else the lattice"
        } else {
            "lattice start"
        }
    );
    println!(
        "Counts are energy evaluations, including rejected accelerated steps; 'acceleration' is \
         Anderson's mixing or Newton's Hessian, restriction and candidate; CG = Newton's \
         conjugate-gradient solves (iterations, seconds)."
    );
    println!("| region | K | iterations (per phase) | rejected | converged | total s | s / iteration | ns / (K log2 K) per iteration | triangulation s (by flips) | cells s | projection s | convergence s | acceleration s | CG its | CG s | setup s | active-set evaluations (moved per step) | energy on Ω | peak MiB | notes |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in &args.regions {
        let region = Region::builtin(name).expect("region");
        for &k in &args.sizes {
            // Newton as the default method runs it (the row start from `row_from` on); Lloyd
            // and Anderson as the paper's Algorithm 2, from the lattice.
            let m = match solver {
                Solver::Newton => Ccvt::fast(),
                _ => Ccvt {
                    solver,
                    ..Ccvt::algorithm2()
                },
            };
            let r = solve(&m, &region, k, args.seed);
            let p = r.g.profile;
            let per = p.total() / p.evaluations.max(1) as f64;
            let e = energy_on_region(&region, &r.g.points);
            println!(
                "| {name} | {k} | {} ({}) | {} | {} | {:.2} | {per:.4} | {:.1} | {:.2} ({}) | {:.2} | {:.2} | {:.2} | {:.2} | {} | {:.2} | {:.2} | {} ({:.0}) | {e:.10e} | {:.0} | {} |",
                r.g.iterations,
                r.phases(),
                p.rejected,
                r.g.converged,
                r.secs,
                per / (k as f64 * (k as f64).log2()) * 1e9,
                p.triangulation,
                p.flipped,
                p.cells,
                p.projection,
                p.convergence,
                p.acceleration + p.hessian,
                p.linear_iterations,
                p.linear_solve,
                r.secs - p.total(),
                p.local_evaluations,
                p.local_moved as f64 / p.local_evaluations.max(1) as f64,
                r.peak_mib,
                r.g.notes.join("; ")
            );
        }
    }
}

fn table_anderson(args: &Args) {
    println!("\n## Lloyd vs Anderson (depth 5), lattice start, tol 1e-4");
    println!(
        "'reach': Anderson's iterations and seconds until its final-phase energy is at or below"
    );
    println!(
        "Lloyd's final energy (same domain Ω only for Algorithm 1; for Algorithm 2 each run has"
    );
    println!("its own ε, so the final generators are compared by their CVT energy on Ω instead).");
    println!("| region | K | algorithm | Lloyd its | Lloyd s | Anderson its | Anderson s | Anderson reach (accepted its) | reach s | E_Ω Lloyd | E_Ω Anderson | Anderson ≤ Lloyd |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in &args.regions {
        let region = Region::builtin(name).expect("region");
        for &k in &args.sizes {
            for algorithm in [Algorithm::One, Algorithm::Two] {
                let base = Ccvt {
                    algorithm,
                    ..Ccvt::algorithm2()
                };
                let lloyd = solve(&base, &region, k, args.seed);
                let fast = solve(
                    &Ccvt {
                        solver: Solver::Anderson { depth: 5 },
                        ..base.clone()
                    },
                    &region,
                    k,
                    args.seed,
                );
                let reach = if algorithm == Algorithm::One {
                    reach(&fast, lloyd.trace.last().map_or(f64::NAN, |t| t.1))
                } else {
                    "– | –".to_string()
                };
                let el = energy_on_region(&region, &lloyd.g.points);
                let ef = energy_on_region(&region, &fast.g.points);
                let conv = |r: &Run| {
                    if r.g.converged {
                        ""
                    } else {
                        " (not converged)"
                    }
                };
                println!(
                    "| {name} | {k} | {} | {}{} | {:.2} | {}{} | {:.2} | {reach} | {el:.10e} | {ef:.10e} | {} |",
                    if algorithm == Algorithm::One { "1" } else { "2" },
                    lloyd.g.iterations,
                    conv(&lloyd),
                    lloyd.secs,
                    fast.g.iterations,
                    conv(&fast),
                    fast.secs,
                    if ef <= el { "yes" } else { "no" }
                );
            }
        }
    }
}

/// Accepted iterations and seconds after which the energy of the final phase of `r` stays at
/// or below `target` ("not reached" if it ends above). Rejected Anderson evaluations are not in
/// the trace; the seconds include them.
fn reach(r: &Run, target: f64) -> String {
    let last = r.trace.last().map_or(0, |t| t.0);
    let from = r
        .trace
        .iter()
        .rposition(|t| t.0 != last || t.1 > target)
        .map_or(0, |i| i + 1);
    match r.trace.get(from) {
        Some(t) => format!("{} | {:.2}", from + 1, t.2),
        None => "not reached | –".to_string(),
    }
}

/// The generators of `m` plus the midpoints of its edges; midpoints of boundary edges (or
/// outside Ω) are projected onto ∂Ω. A hexagonal lattice refines to the lattice of half the
/// spacing.
fn refine(region: &Region, m: &mesh::Mesh) -> Vec<DVec2> {
    let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &m.triangles {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut edges: Vec<((u32, u32), u32)> = uses.into_iter().collect();
    edges.sort_unstable();
    let mut pts = m.points.clone();
    for ((a, b), n) in edges {
        let mid = (m.points[a as usize] + m.points[b as usize]) * 0.5;
        pts.push(if n == 1 || region.signed_distance(mid) >= 0.0 {
            region.project(mid).point
        } else {
            mid
        });
    }
    pts
}

fn table_c2f(args: &Args) {
    println!("\n## Coarse-to-fine start vs lattice start (Algorithm 2, Anderson and Lloyd)");
    println!("| region | K coarse | coarse its | coarse s | K fine | solver | refined start: its (per phase) | s | lattice start: its (per phase) | s | E_Ω refined | E_Ω lattice |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in &args.regions {
        let region = Region::builtin(name).expect("region");
        for &k in &args.sizes {
            for solver in [Solver::Anderson { depth: 5 }, Solver::Lloyd] {
                let m = Ccvt {
                    solver,
                    ..Ccvt::algorithm2()
                };
                let kc = k / 4;
                let t = Instant::now();
                let coarse = m
                    .mesh(
                        &region,
                        &MeshRequest::points(kc).seed(args.seed).max_iter(20_000),
                        &mut |_| {},
                    )
                    .expect("coarse");
                let tc = t.elapsed().as_secs_f64();
                let z = refine(&region, &coarse.mesh);
                let kf = z.len();
                let from = solve_with(&m, &region, kf, args.seed, Some(z));
                let lattice = solve(&m, &region, kf, args.seed);
                println!(
                    "| {name} | {kc} | {} | {tc:.2} | {kf} | {} | {} ({}) | {:.2} | {} ({}) | {:.2} | {:.10e} | {:.10e} |",
                    coarse.iterations,
                    solver_name(solver),
                    from.g.iterations,
                    from.phases(),
                    from.secs,
                    lattice.g.iterations,
                    lattice.phases(),
                    lattice.secs,
                    energy_on_region(&region, &from.g.points),
                    energy_on_region(&region, &lattice.g.points),
                );
            }
        }
    }
}

fn main() {
    let args = parse_args();
    println!(
        "sizes {:?}, regions {:?}, tables {:?}, seed {}",
        args.sizes, args.regions, args.tables, args.seed
    );
    for t in &args.tables {
        match t.as_str() {
            "iter" => table_iter(&args),
            "converge" => table_converge(&args, Solver::Lloyd),
            "fast" => table_converge(&args, Solver::Anderson { depth: 5 }),
            "newton" => table_converge(&args, Solver::Newton),
            "anderson" => table_anderson(&args),
            "c2f" => table_c2f(&args),
            other => {
                eprintln!("unknown table '{other}' (iter, converge, fast, newton, anderson, c2f)")
            }
        }
    }
}
