//! Six-node (P2) triangles on curved boundaries, for quadratic finite elements.
//!
//! ```text
//! cargo run --release -p cvtmesh --example quadratic_mesh -- [REGION [K [OUT]]]
//! ```
//!
//! meshes REGION (default the built-in `circle`) with K vertices (default 400), puts a node on
//! every edge, on the exact boundary where the edge is a boundary edge, and writes OUT (default
//! `circle_p2.msh`: Gmsh element types 9 and 8; `.vtu` and `.node` work too). It prints how
//! much of the region the three-node triangles miss (their chords cut across the circle) and
//! how much the six-node ones do.
use cvtmesh::{Quadratic, Region};
use std::path::Path;

/// The region meshed, its six-node mesh (written to `out`), and the areas the three- and
/// six-node triangles cover.
pub fn run(
    region: &Region,
    k: usize,
    out: &Path,
) -> Result<(Quadratic, f64, f64), Box<dyn std::error::Error>> {
    let mesh = cvtmesh::mesh(region, k)?.mesh;
    let quadratic = Quadratic::new(&mesh, Some(region));
    cvtmesh::io::write_quadratic(&quadratic, out)?;
    let areas = (mesh.area(), quadratic.area());
    Ok((quadratic, areas.0, areas.1))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let region = cvtmesh::load_region(args.first().map_or("circle", String::as_str))?;
    let k = args.get(1).map_or(Ok(400), |s| s.parse())?;
    let default_out = format!("{}_p2.msh", region.name());
    let out = Path::new(args.get(2).unwrap_or(&default_out));
    let (q, linear, quadratic) = run(&region, k, out)?;
    let exact = region.area();
    println!(
        "{}: {} vertices, {} nodes, {} six-node triangles -> {}",
        region.name(),
        q.num_corners(),
        q.points.len(),
        q.triangles.len(),
        out.display()
    );
    println!(
        "area missed: three-node {:.3e}, six-node {:.3e} (of {exact:.6})",
        exact - linear,
        exact - quadratic
    );
    Ok(())
}
