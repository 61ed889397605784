//! Time MESHGEN on a built-in region (use --release):
//! `cargo run --release -p cvtmesh-tools --bin meshgen_run -- circle 88 [max_iter]`
use geometry::Region;
use mesh::{MeshRequest, Mesher};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map(String::as_str).unwrap_or("circle");
    let k: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(88);
    let max_iter: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1000);
    let region = Region::builtin(name)?;
    let start = Instant::now();
    let r = meshgen::Meshgen.mesh(
        &region,
        &MeshRequest::points(k).max_iter(max_iter),
        &mut |_| {},
    )?;
    let secs = start.elapsed().as_secs_f64();
    mesh::check_conforming(&r.mesh, &region)?;
    println!(
        "meshgen {name}: K {} K~ {} min angle {:.2} iterations {} converged {} last move {:.2e} seconds {secs:.3}",
        r.mesh.num_vertices(),
        r.mesh.num_triangles(),
        r.mesh.min_angle_deg(),
        r.iterations,
        r.converged,
        r.move_history.last().copied().unwrap_or(f64::NAN)
    );
    for n in &r.notes {
        println!("  {n}");
    }
    Ok(())
}
