//! Run CCVT on a region (a built-in name or a region file, with the default corners) and print
//! iterations per phase, energy and where the time went:
//! `cargo run --release -p cvtmesh-tools --bin solve -- REGION K [ccvt1|ccvt2|fast|fast1|anderson] [seed]`.
use ccvt::Ccvt;
use mesh::MeshRequest;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let region = cvtmesh::load_region(args.get(1).map(String::as_str).unwrap_or("circle"))
        .expect("region")
        .with_default_corners();
    let k: usize = args
        .get(2)
        .and_then(|s| s.parse::<f64>().ok())
        .map_or(88, |x| x.round() as usize);
    let m = match args.get(3).map(String::as_str).unwrap_or("ccvt2") {
        "ccvt1" => Ccvt::algorithm1(),
        "fast" => Ccvt::fast(),
        "anderson" => Ccvt::anderson(),
        "fast1" => Ccvt {
            algorithm: ccvt::Algorithm::One,
            ..Ccvt::fast()
        },
        _ => Ccvt::algorithm2(),
    };
    // For experiments: CCVT_EPS_PHASE_TOL overrides the ε-phase tolerance, CCVT_ACTIVE_FROM the
    // size from which Newton takes active-set steps, CCVT_MULTILEVEL_FROM the size from which a
    // coarser level gives the start, CCVT_ROW_FROM the size from which the row start is taken.
    let m = Ccvt {
        eps_phase_tol: env("CCVT_EPS_PHASE_TOL").unwrap_or(m.eps_phase_tol),
        active_from: env("CCVT_ACTIVE_FROM").unwrap_or(m.active_from),
        eps_start: env("CCVT_EPS_START").unwrap_or(m.eps_start),
        row_from: env("CCVT_ROW_FROM").unwrap_or(m.row_from),
        multilevel_from: env("CCVT_MULTILEVEL_FROM").unwrap_or(m.multilevel_from),
        ..m
    };
    let seed = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1);
    // CCVT_MAX_ITER caps every phase (default 20 000).
    let cap = env("CCVT_MAX_ITER").unwrap_or(20_000);
    let req = MeshRequest::points(k).seed(seed).max_iter(cap);
    // Iterations of each phase (the progress count restarts at 1 in every phase).
    let mut phases: Vec<usize> = Vec::new();
    // Wall-clock time at the end of each phase's last reported iteration.
    let mut ends: Vec<f64> = Vec::new();
    let t = std::time::Instant::now();
    // CCVT_TRACE=1 prints every evaluation: phase, iteration, seconds, largest move, energy.
    let trace = std::env::var_os("CCVT_TRACE").is_some();
    let g = m
        .generators(&region, &req, &mut |p| {
            if trace {
                eprintln!(
                    "trace {} {} {:.4} {:.3e} {:.10e}",
                    phases.len() - usize::from(p.iteration != 1) + 1,
                    p.iteration,
                    t.elapsed().as_secs_f64(),
                    p.max_move,
                    p.energy
                );
            }
            if p.iteration == 1 {
                phases.push(0);
                ends.push(0.0);
            }
            if let Some(e) = ends.last_mut() {
                *e = t.elapsed().as_secs_f64();
            }
            if let Some(n) = phases.last_mut() {
                *n = p.iteration;
            }
        })
        .expect("solve");
    let omega = region.polygonize(1e-4 * req.spacing(&region));
    let e_omega = tessellation::clipped_cells(
        &g.points,
        &tessellation::Delaunay::new(&g.points),
        &omega,
        &geometry::Density::Uniform,
    )
    .energy();
    println!("energy on region {e_omega:.10e}");
    let boundary = g.markers.iter().filter(|m| m.on_boundary()).count();
    println!(
        "{} K={k} iterations={} {:?} converged={} energy={:.8e} boundary={boundary} {:.3}s notes={:?}",
        region.name(),
        g.iterations,
        phases,
        g.converged,
        g.energy_history.last().unwrap(),
        t.elapsed().as_secs_f64(),
        g.notes
    );
    println!("{:?}", g.profile);
    let mesh = tessellation::conforming_mesh(&g.points, &g.markers, &region).expect("mesh");
    let c = cvtmesh::metrics::size_conformity(
        &mesh,
        &geometry::SizeField::constant(req.spacing(&region)),
        &region,
    )
    .expect("measures");
    println!(
        "min angle {:.1} (1st percentile {:.1}), unit share {:.4}, efficiency {:.4}",
        c.min_angle_deg, c.min_angle_p1_deg, c.unit_share, c.efficiency
    );
    let mut prev = 0.0;
    let secs: Vec<String> = ends
        .iter()
        .map(|&e| {
            let d = e - prev;
            prev = e;
            format!("{d:.2}")
        })
        .collect();
    println!(
        "seconds per phase (to its last iteration): {}",
        secs.join(" ")
    );
    // CCVT_HISTORY=1 prints the largest move (per spacing) at log-spaced iterations of each phase
    // (exact for Lloyd; Anderson's phase counts include rejected steps, which have no move).
    if std::env::var("CCVT_HISTORY").is_ok() {
        let mut start = 0;
        for (i, n) in phases.iter().enumerate() {
            let end = (start + n).min(g.move_history.len());
            let h = &g.move_history[start.min(end)..end];
            let n = &h.len();
            if *n == 0 {
                break;
            }
            let mut marks: Vec<usize> = (0..40)
                .map(|e| (1.25f64.powi(e) as usize).min(*n) - 1)
                .collect();
            marks.dedup();
            let line: Vec<String> = marks
                .iter()
                .map(|&m| format!("{}:{:.1e}", m + 1, h[m]))
                .collect();
            println!("phase {i}: {}", line.join(" "));
            start += n;
        }
    }
}

/// The environment variable `name` parsed, if set and valid.
fn env<T: std::str::FromStr>(name: &str) -> Option<T> {
    std::env::var(name).ok().and_then(|v| v.parse().ok())
}
