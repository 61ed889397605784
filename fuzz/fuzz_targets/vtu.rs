//! VTK .vtu (ASCII, base64, appended raw or base64 data; zlib; one piece or several): a mesh
//! (and the region its triangles cover) or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Raw appended data is not text: the reader takes bytes.
    if let Ok(m) = mesh::io::vtu_from_bytes(data) {
        assert_eq!(m.markers.len(), m.points.len());
        let n = m.points.len() as u32;
        assert!(m.triangles.iter().flatten().all(|&v| v < n));
        assert!(m.points.iter().all(|p| p.is_finite()));
        let _ = m.boundary_edges();
        // The region its triangles cover (what `cvtmesh mesh FILE` meshes again).
        if let Ok(r) = geometry::Region::from_triangles("fuzz", &m.points, &m.triangles) {
            assert!(!r.loops().is_empty());
        }
    }
});
