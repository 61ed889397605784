//! Triangle's .node and .ele, split at the first NUL byte: a mesh (and the region its triangles cover) or an error,
//! never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let cut = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    let (node, ele) = (&data[..cut], data.get(cut + 1..).unwrap_or(&[]));
    if let (Ok(node), Ok(ele)) = (std::str::from_utf8(node), std::str::from_utf8(ele)) {
        if let Ok(m) = mesh::io::triangle_from_str(node, ele) {
            let _ = m.boundary_edges();
            // The region its triangles cover (what `cvtmesh mesh FILE` meshes again).
            if let Ok(r) = geometry::Region::from_triangles("fuzz", &m.points, &m.triangles) {
                assert!(!r.loops().is_empty());
            }
        }
        // The same files read as a size field on a mesh (first attribute = size).
        if let Ok((m, sizes)) = mesh::io::triangle_sizes_from_str(node, ele) {
            size_field_on(&m, &sizes);
        }
    }
});

/// The size field of a mesh read with sizes, on the unit circle. Sizes below a tenth of the
/// circle's extent would make the background grid large and the target slow, so they are
/// left to the unit tests.
fn size_field_on(m: &mesh::Mesh, sizes: &[f64]) {
    if sizes.iter().all(|&h| h >= 0.2) && m.points.len() <= 64 {
        let circle = geometry::Region::builtin("circle").expect("a built-in region");
        if let Ok(h) = geometry::SizeField::from_mesh(&circle, &m.points, &m.triangles, sizes) {
            let v = h.at(geometry::DVec2::new(0.1, 0.2));
            assert!(v.is_finite() && v > 0.0, "size {v}");
        }
    }
}
