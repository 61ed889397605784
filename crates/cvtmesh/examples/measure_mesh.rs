//! Score a mesh with the paper's 12 quality measures.
//!
//! ```text
//! cargo run --release -p cvtmesh --example measure_mesh -- MESH [REGION]
//! ```
//!
//! reads MESH (Triangle `.node` with its `.ele`, Gmsh `.msh` or `.obj`) and REGION (a region
//! file, or a built-in name such as `lake`; see `cvtmesh regions`; without it, the region the
//! mesh's triangles cover). Without arguments it meshes the built-in `square_hole` with 500
//! vertices and scores that.
use cvtmesh::{Measures, Mesh, Region};
use std::path::Path;

/// The mesh and region named on the command line, or a fresh mesh of `square_hole`.
pub fn inputs(args: &[String]) -> Result<(Mesh, Region), Box<dyn std::error::Error>> {
    match args {
        [mesh, region_spec] => Ok((
            cvtmesh::io::read_mesh(Path::new(mesh))?,
            cvtmesh::load_region(region_spec)?,
        )),
        [mesh] => {
            let path = Path::new(mesh);
            let (mesh, walls) = cvtmesh::io::read_mesh_with_walls(path)?;
            let region = cvtmesh::region_of_mesh(&mesh, &walls, path)?;
            Ok((mesh, region))
        }
        [] => {
            let region = Region::builtin("square_hole")?;
            let mesh = cvtmesh::mesh(&region, 500)?.mesh;
            Ok((mesh, region))
        }
        _ => Err("usage: measure_mesh [MESH [REGION]]".into()),
    }
}

/// The 12 measures as (name, value) in the paper's table order: point distribution (λ, γ),
/// Voronoi cells (h, μ, χ, ν, τ, d), triangles (α, β, q, p). All are 0 for the ideal
/// (equilateral, equal-area) mesh and grow as it gets worse; see `cvtmesh::Measures` for
/// each one's definition.
pub fn table(m: &Measures) -> Vec<(&'static str, f64)> {
    // NAMES and values() start with K and K̃, which are counts, not measures.
    Measures::NAMES
        .into_iter()
        .zip(m.values())
        .skip(2)
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mesh, region) = inputs(&args)?;
    // The measures assume the mesh covers the region; say so when it does not.
    if let Err(e) = cvtmesh::check_conforming(&mesh, &region) {
        eprintln!("warning: the mesh does not conform to the region: {e}");
    }
    let m = cvtmesh::measures(&mesh, &region)?;
    println!("region {}: K = {}, K~ = {}", region.name(), m.k, m.k_tilde);
    for (name, value) in table(&m) {
        println!("{name:>8}  {value:.6e}");
    }
    Ok(())
}
