//! Wavefront .obj: a mesh (and the region its triangles cover) or an error,
//! never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(m) = mesh::io::obj_from_str(text) {
            let _ = m.boundary_edges();
            // The region its triangles cover (what `cvtmesh mesh FILE` meshes again).
            if let Ok(r) = geometry::Region::from_triangles("fuzz", &m.points, &m.triangles) {
                assert!(!r.loops().is_empty());
            }
        }
    }
});
