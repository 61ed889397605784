//! Mesh your own region: a polygon with a hole, given as lists of coordinates.
//!
//! ```text
//! cargo run --release -p cvtmesh --example mesh_polygon_with_hole -- house.msh
//! ```
//!
//! writes the mesh to `house.msh` (Gmsh; `.node`, `.vtu` and `.obj` work too) or, without an
//! argument, to `polygon_with_hole.msh` in the system's temporary directory. Open it in Gmsh or
//! ParaView, draw it with `cvtmesh show house.msh -o house.png`, or score it with the
//! `measure_mesh` example.
use cvtmesh::geometry::{GeometryError, LoopRole, Piece};
use cvtmesh::{DVec2, MeshRequest, MeshResult, Method, Region};
use std::path::{Path, PathBuf};

/// The outline of a house, counter-clockwise (clockwise works too: loops are reoriented).
pub const OUTER: [(f64, f64); 5] = [(0.0, 0.0), (4.0, 0.0), (4.0, 3.0), (2.0, 4.5), (0.0, 3.0)];
/// A square window: a hole in the region.
pub const HOLE: [(f64, f64); 4] = [(1.0, 1.0), (2.0, 1.0), (2.0, 2.0), (1.0, 2.0)];
/// Number of mesh vertices K.
pub const POINTS: usize = 400;

/// A region from its outer polygon and its holes, each a list of (x, y) vertices.
///
/// A region's boundary is made of pieces (lines, arcs, ...); a polygon is one line per edge,
/// from each vertex to the next, the last edge closing the loop. `Region::new` checks the
/// loops (closed, not crossing, holes inside) and, given `None` for the corners, makes every
/// vertex where the boundary turns a corner: a mesh vertex is placed there exactly.
pub fn polygon_region(
    name: &str,
    outer: &[(f64, f64)],
    holes: &[&[(f64, f64)]],
) -> Result<Region, GeometryError> {
    let edges = |loop_: &[(f64, f64)]| -> Vec<Piece> {
        let p: Vec<DVec2> = loop_.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
        (0..p.len())
            .map(|i| Piece::Line {
                a: p[i],
                b: p[(i + 1) % p.len()],
            })
            .collect()
    };
    let mut loops = vec![(LoopRole::Outer, edges(outer))];
    loops.extend(holes.iter().map(|h| (LoopRole::Hole, edges(h))));
    Region::new(name, loops, None)
}

/// Mesh the house with [`POINTS`] vertices and write the mesh to `out`.
pub fn run(out: &Path) -> Result<(Region, MeshResult), Box<dyn std::error::Error>> {
    let region = polygon_region("house", &OUTER, &[&HOLE])?;

    // The one-line way: the default method (CCVT, Algorithm 2 with Newton's method) and the
    // default request (seed 1, tolerance 1e-4).
    //     let result = cvtmesh::mesh(&region, POINTS)?;
    // The same, with every choice spelled out so it can be changed:
    let request = MeshRequest::points(POINTS).seed(1).tol(1e-4);
    let result = Method::Ccvt.run(&region, &request)?;

    // The format follows the extension; the file is written whole or not at all.
    cvtmesh::io::write_mesh(&result.mesh, out)?;
    Ok((region, result))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("polygon_with_hole.msh"));
    let (region, result) = run(&out)?;
    let mesh = &result.mesh;
    println!("region     {} (area {})", region.name(), region.area());
    println!("K          {} vertices", mesh.num_vertices());
    println!("K~         {} triangles", mesh.num_triangles());
    println!(
        "converged  {} after {} iterations",
        result.converged, result.iterations
    );
    println!("min angle  {:.2}°", mesh.min_angle_deg());
    println!("written to {}", out.display());
    Ok(())
}
