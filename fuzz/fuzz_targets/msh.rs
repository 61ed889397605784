//! Gmsh .msh (2.2 and 4.1, ASCII and binary in either byte order): a mesh (and the region its
//! triangles cover, with the walls its physical curves number and the points its physical
//! points mark) or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "common/region_of_mesh.rs"]
mod region_of_mesh;

fuzz_target!(|data: &[u8]| {
    // Binary files are not text: the reader takes bytes.
    if let Ok(m) = mesh::io::gmsh_from_bytes(data) {
        let _ = m.boundary_edges();
        // The region its triangles cover (what `cvtmesh mesh FILE` meshes again).
        let walls = mesh::io::gmsh_walls_from_bytes(data).expect("the mesh was read");
        if let Some(r) = region_of_mesh::checked(&m, &walls) {
            if let Some(markers) = r.with_default_corners().piece_markers() {
                assert!(!walls.edges.is_empty() && !markers.is_empty());
            }
        }
    }
    // The same file read as a size field on a mesh (its first $NodeData view).
    if let Ok((m, sizes)) = mesh::io::gmsh_sizes_from_bytes(data) {
        assert_eq!(sizes.len(), m.points.len());
    }
});
