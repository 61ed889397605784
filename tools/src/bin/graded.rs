//! Graded CCVT: time, evaluations and size conformity from different starts and algorithms,
//! for one region and size field.
//! `cargo run --release -p cvtmesh-tools --bin graded -- REGION 'H(x,y)' [K]`
use cvtmesh::ccvt::{Algorithm, Generators};
use cvtmesh::metrics::size_conformity;
use cvtmesh::{Ccvt, Mesh, MeshRequest, Method, SizeField};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let region = cvtmesh::load_region(args.get(1).map_or("circle", String::as_str))?;
    let text = args
        .get(2)
        .map_or("0.03 + 0.12*sqrt(x^2+y^2)", String::as_str);
    let field = SizeField::from_expr(text)?;
    let k: Option<usize> = args.get(3).map(|s| s.parse()).transpose()?;
    let request = MeshRequest::size_field(&field, &region, k)?;
    let k = request.size.points(&region);
    // The field the mesh should follow: scaled when K is given.
    let scale = (field.predicted_points(&region) / k as f64).sqrt();
    let scaled = field.on_grid(&region, field.check(&region)?.min);
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
            None => ccvt.generators(&region, &request, &mut |_| {})?,
        };
        let mesh = cvtmesh::tessellation::conforming_mesh(&g.points, &g.markers, &region)?;
        report(
            label,
            t.elapsed().as_secs_f64(),
            &mesh,
            g.iterations,
            g.converged,
        );
        Ok(())
    };
    run("algorithm 1, refine start", &one, Some(z.clone()))?;
    run("algorithm 1, lattice start", &one, None)?;
    run("algorithm 2, refine start", &Ccvt::fast(), Some(z))?;
    run("algorithm 2, lattice start", &Ccvt::fast(), None)?;
    Ok(())
}
