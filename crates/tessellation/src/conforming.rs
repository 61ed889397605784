//! From generators to a conforming mesh (CCVT "From generators to a mesh").
use geometry::{DVec2, Region};
use mesh::{Mesh, MeshError, VertexMarker};

/// Marker of each point: corner if within `tol` of a corner, boundary if within `tol` of the
/// boundary (with its piece, loop and arc-length position), interior otherwise.
pub fn mark_vertices(points: &[DVec2], region: &Region, tol: f64) -> Vec<VertexMarker> {
    let _ = (points, region, tol);
    todo!()
}

/// Triangulate `points` so the mesh conforms to `region`: a constrained Delaunay triangulation
/// in which consecutive boundary vertices along each loop (ordered by `loop_param`) are joined
/// by constraint edges, triangles outside the region or inside holes are removed, and
/// degenerate triangles are not produced. Passes `mesh::check_conforming`.
pub fn conforming_mesh(
    points: &[DVec2],
    markers: &[VertexMarker],
    region: &Region,
) -> Result<Mesh, MeshError> {
    let _ = (points, markers, region);
    todo!()
}
