//! Gmsh .msh (2.2 and 4.1 ASCII): a mesh (and the region its triangles cover, with the walls
//! its physical curves number and the points its physical points mark) or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(m) = mesh::io::gmsh_from_str(text) {
            let _ = m.boundary_edges();
            // The region its triangles cover (what `cvtmesh mesh FILE` meshes again).
            let walls = mesh::io::gmsh_walls_from_str(text).expect("the mesh was read");
            if let Ok(r) = geometry::Region::from_triangles_pinned(
                "fuzz",
                &m.points,
                &m.triangles,
                &walls.edges,
                &walls.points,
            ) {
                assert!(!r.loops().is_empty());
                // A point marked on its own is a vertex of the mesh, and a corner.
                let c = r.with_default_corners();
                for (p, _) in r.vertex_markers() {
                    assert!(m.points.contains(p) && c.corners().iter().any(|k| k.pos == *p));
                }
                if let Some(markers) = r.with_default_corners().piece_markers() {
                    assert!(!walls.edges.is_empty() && !markers.is_empty());
                }
            }
        }
        // The same file read as a size field on a mesh (its first $NodeData view).
        if let Ok((m, sizes)) = mesh::io::gmsh_sizes_from_str(text) {
            assert_eq!(sizes.len(), m.points.len());
        }
    }
});
