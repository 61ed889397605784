//! Graded CCVT: time, evaluations and size conformity from different starts and algorithms,
//! for one region and size field.
//! `cargo run --release -p cvtmesh-tools --bin graded -- REGION FIELD [K] [VARIANTS]`
//!
//! FIELD is an expression `H(x,y)` or a distance field `toward:loop:0+point:X,Y@HMIN,HMAX,DMIN,DMAX`.
//! VARIANTS (comma-separated): `1r`, `1l`, `2r`, `2l` (Algorithm 1 or 2 from the refinement
//! start or the lattice), `d` (the default method), `f` (Algorithm 1 from the vertices of the
//! Triangle `.node` file GRADED_FROM, e.g. another tool's mesh), `m` (coarser levels from
//! GRADED_LEVELS_FROM generators on, default 2000), `s` (single level), `w` (with
//! GRADED_WHERE=N: the generators, by their move over h(x), and the cells that change most
//! between evaluations N and N + 1).
//! GRADED_TRACE prints the largest move through the run (GRADED_TRACE_ALL every evaluation),
//! GRADED_JUMPS the evaluations where it jumps tenfold, GRADED_TIMES the seconds at every
//! evaluation, GRADED_SEED the seed, GRADED_GRADATION the gradient limit, GRADED_EXACT
//! evaluates an expression itself instead of its background grid.
use cvtmesh::ccvt::{Algorithm, Generators};
use cvtmesh::geometry::{Threshold, Toward};
use cvtmesh::metrics::size_conformity;
use cvtmesh::{Ccvt, Mesh, MeshRequest, Method, SizeField};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let region = cvtmesh::load_region(args.get(1).map_or("circle", String::as_str))?;
    let text = args
        .get(2)
        .map_or("0.03 + 0.12*sqrt(x^2+y^2)", String::as_str);
    let k: Option<usize> = args
        .get(3)
        .filter(|s| *s != "-")
        .map(|s| s.parse())
        .transpose()?;
    // With K given, the field is scaled to ask for K itself, so that it is what the mesh should
    // follow.
    // `toward:loop:0+point:1,2@HMIN,HMAX,DMIN,DMAX` is a distance field, anything else an
    // expression.
    let make = |scale: f64| -> Result<SizeField, Box<dyn std::error::Error>> {
        Ok(match text.strip_prefix("toward:") {
            Some(rest) => {
                let (targets, t) = rest.split_once('@').ok_or("toward:TARGETS@H,H,D,D")?;
                let targets: Vec<Toward> = targets
                    .split('+')
                    .map(str::parse)
                    .collect::<Result<_, _>>()?;
                let v: Vec<f64> = t.split(',').map(str::parse).collect::<Result<_, _>>()?;
                let t = Threshold {
                    size_min: v[0] * scale,
                    size_max: v[1] * scale,
                    dist_min: v[2],
                    dist_max: v[3],
                };
                SizeField::threshold(&region, &targets, t)?
            }
            None => SizeField::from_expr(&format!("({text}) * {scale:e}"))?,
        })
    };
    // GRADED_GRADATION=G limits the field's gradient as `cvtmesh mesh --gradation G` does.
    let gradation: Option<f64> = std::env::var("GRADED_GRADATION")
        .ok()
        .map(|g| g.parse())
        .transpose()?;
    let make = |scale: f64| -> Result<SizeField, Box<dyn std::error::Error>> {
        let field = make(scale)?;
        Ok(match gradation {
            Some(g) => field.bounded(&region, None, None, Some(g))?,
            None => field,
        })
    };
    let field = make(1.0)?;
    // A distance field is handed over unscaled, as `cvtmesh mesh --points K` does (its
    // background grid follows its smallest size); an expression is scaled to ask for K.
    let field = match k {
        Some(k) if !text.starts_with("toward:") => {
            make((field.predicted_points(&region) / k as f64).sqrt())?
        }
        _ => field,
    };
    let mut request = MeshRequest::size_field(&field, &region, k)?;
    if let Some(seed) = std::env::var("GRADED_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        request.seed = seed;
    }
    if std::env::var_os("GRADED_EXACT").is_some() {
        // The expression itself, not its samples on the background grid.
        request.density = field.density(field.check(&region)?.min);
    }
    let k = request.size.points(&region);
    // The field the mesh should follow: scaled when K is given.
    let scale = (field.predicted_points(&region) / k as f64).sqrt();
    let (scaled, scale) = if text.starts_with("toward:") {
        (make(scale)?, 1.0)
    } else {
        (field.on_grid(&region, field.check(&region)?.min), scale)
    };
    let report = |label: &str, secs: f64, mesh: &Mesh, iterations: usize, converged: bool| {
        let c = size_conformity(mesh, &scaled, &region).expect("a mesh");
        println!(
            "{label:<28} {secs:>7.2} s  K {:>7}  evaluations {iterations:>6} {}  unit share {:.3}  efficiency {:.3}  l {:.3}  min angle {:.1}° (1st percentile {:.1}°)",
            mesh.num_vertices(),
            if converged { "converged" } else { "CAPPED   " },
            c.unit_share,
            c.efficiency,
            c.mean_length / scale,
            c.min_angle_deg,
            c.min_angle_p1_deg
        );
    };
    // The refinement method's vertices as a start (timed and measured on their own).
    let refine_start = || -> Result<Vec<cvtmesh::DVec2>, Box<dyn std::error::Error>> {
        let t = Instant::now();
        let start = Method::Refine.run(&region, &request)?;
        report(
            "refine (start)",
            t.elapsed().as_secs_f64(),
            &start.mesh,
            start.iterations,
            start.converged,
        );
        let mut z = start.mesh.points.clone();
        let mut rng = cvtmesh::geometry::Rng::new(request.seed);
        while z.len() > k {
            z.swap_remove(rng.below(z.len()));
        }
        Ok(z)
    };
    let one = Ccvt {
        algorithm: Algorithm::One,
        ..Ccvt::fast()
    };
    let run = |label: &str,
               ccvt: &Ccvt,
               from: Option<Vec<cvtmesh::DVec2>>|
     -> Result<(), Box<dyn std::error::Error>> {
        let t = Instant::now();
        let g: Generators = match from {
            Some(z) => ccvt.generators_from(&region, &request, z, &mut |_| {})?,
            None => {
                // GRADED_JUMPS: the evaluations whose largest move is 10× the one before.
                let jumps = std::env::var_os("GRADED_JUMPS").is_some();
                // GRADED_TIMES: seconds, evaluation and largest move of every evaluation.
                let times = std::env::var_os("GRADED_TIMES").is_some();
                let mut last = f64::INFINITY;
                ccvt.generators(&region, &request, &mut |p| {
                    if times {
                        println!(
                            "  time {:.3} evaluation {} move {:.2e}",
                            t.elapsed().as_secs_f64(),
                            p.iteration,
                            p.max_move
                        );
                    }
                    if jumps && p.max_move > 10.0 * last {
                        println!(
                            "  jump at evaluation {}: {last:.1e} -> {:.1e}",
                            p.iteration, p.max_move
                        );
                    }
                    last = p.max_move;
                })?
            }
        };
        eprintln!(
            "{label}: {} evaluations, converged {}",
            g.iterations, g.converged
        );
        if std::env::var_os("GRADED_TRACE").is_some() {
            let m = &g.move_history;
            let picks: Vec<String> = (0..m.len())
                .step_by(if std::env::var_os("GRADED_TRACE_ALL").is_some() {
                    1
                } else {
                    (m.len() / 40).max(1)
                })
                .map(|i| format!("{i}:{:.1e}", m[i]))
                .collect();
            println!("  moves {}", picks.join(" "));
        }
        let mesh = cvtmesh::tessellation::conforming_mesh(&g.points, &g.markers, &region)?;
        report(
            label,
            t.elapsed().as_secs_f64(),
            &mesh,
            g.iterations,
            g.converged,
        );
        let p = &g.profile;
        println!(
            "{:<28} triangulation {:.2}  cells {:.2}  projection {:.2}  hessian {:.2}  solve {:.2}  convergence {:.2}  rejected {}  local {}  cg {}",
            "", p.triangulation, p.cells, p.projection, p.hessian, p.linear_solve, p.convergence, p.rejected, p.local_evaluations, p.linear_iterations
        );
        Ok(())
    };
    let which = args.get(4).map_or("1r,1l,2r,2l", String::as_str);
    for w in which.split(',') {
        match w {
            "1r" => run("algorithm 1, refine start", &one, Some(refine_start()?))?,
            "1l" => run("algorithm 1, lattice start", &one, None)?,
            "2r" => run(
                "algorithm 2, refine start",
                &Ccvt::fast(),
                Some(refine_start()?),
            )?,
            "2l" => run("algorithm 2, lattice start", &Ccvt::fast(), None)?,
            "d" => run("default", &Ccvt::default(), None)?,
            // Algorithm 1 from the vertices of a Triangle .node file (GRADED_FROM).
            "f" => {
                let text = std::fs::read_to_string(std::env::var("GRADED_FROM")?)?;
                let z: Vec<cvtmesh::DVec2> = text
                    .lines()
                    .skip(1)
                    .filter_map(|l| {
                        let v: Vec<f64> = l
                            .split_whitespace()
                            .skip(1)
                            .take(2)
                            .filter_map(|t| t.parse().ok())
                            .collect();
                        (v.len() == 2).then(|| cvtmesh::DVec2::new(v[0], v[1]))
                    })
                    .collect();
                run("algorithm 1, file start", &one, Some(z))?
            }
            "m" => run(
                "levels",
                &Ccvt {
                    graded_multilevel_from: std::env::var("GRADED_LEVELS_FROM")
                        .ok()
                        .and_then(|v| v.parse().ok())
                        .unwrap_or(2000),
                    ..Ccvt::default()
                },
                None,
            )?,
            "s" => run(
                "single level",
                &Ccvt {
                    graded_multilevel_from: usize::MAX,
                    ..Ccvt::default()
                },
                None,
            )?,
            // Which generators move most between evaluation N and N + 1 (N from GRADED_WHERE).
            "w" => {
                let n: usize = std::env::var("GRADED_WHERE")?.parse()?;
                let at = |cap: usize| {
                    let mut r = request.clone();
                    r.max_iter = cap;
                    Ccvt::default().generators(&region, &r, &mut |_| {})
                };
                let (a, b) = (at(n)?, at(n + 1)?);
                let mut moves: Vec<(f64, usize)> = a
                    .points
                    .iter()
                    .zip(&b.points)
                    .enumerate()
                    .map(|(i, (p, q))| ((*p - *q).length() / scaled.at(*p), i))
                    .collect();
                moves.sort_by(|x, y| y.0.total_cmp(&x.0));
                let omega = region.polygonize(1e-4 * request.spacing(&region));
                let cells = |z: &[cvtmesh::DVec2]| {
                    let d = cvtmesh::tessellation::Delaunay::new(z);
                    cvtmesh::tessellation::clipped_cells(z, &d, &omega, &request.density)
                };
                let (ca, cb) = (cells(&a.points), cells(&b.points));
                let mut jumps: Vec<(f64, usize)> = ca
                    .cells
                    .iter()
                    .zip(&cb.cells)
                    .enumerate()
                    .map(|(i, (x, y))| ((x.energy - y.energy).abs(), i))
                    .collect();
                jumps.sort_by(|x, y| y.0.total_cmp(&x.0));
                println!("  total energy {:.6e} -> {:.6e}", ca.energy(), cb.energy());
                for &(d, i) in jumps.iter().take(6) {
                    let (x, y) = (&ca.cells[i], &cb.cells[i]);
                    println!(
                        "  cell {i} at ({:.3}, {:.3}) {:?}: energy {:.4e} -> {:.4e} (jump {d:.3e}), mass {:.4e} -> {:.4e}, area {:.4e} -> {:.4e}, h {:.3} -> {:.3}",
                        a.points[i].x, a.points[i].y, a.markers[i], x.energy, y.energy, x.mass, y.mass, x.area, y.area, x.h, y.h
                    );
                }
                for &(d, i) in moves.iter().take(8) {
                    println!(
                        "  {i:>6} at ({:.3}, {:.3}) moved {d:.3e} of h ({:?} -> {:?}), energy {:.9e} -> {:.9e}",
                        a.points[i].x, a.points[i].y, a.markers[i], b.markers[i],
                        a.energy_history.last().unwrap_or(&0.0), b.energy_history.last().unwrap_or(&0.0)
                    );
                }
            }
            _ => return Err(format!("unknown variant {w}").into()),
        }
    }
    Ok(())
}
