//! Triangle's .node, .ele and .poly, split at NUL bytes: a mesh (and the region its triangles
//! cover, with the walls the .poly's segment markers number) or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "common/region_of_mesh.rs"]
mod region_of_mesh;

fuzz_target!(|data: &[u8]| {
    let mut parts = data.splitn(3, |&b| b == 0);
    let (node, ele, poly) = (
        parts.next().unwrap_or(&[]),
        parts.next().unwrap_or(&[]),
        parts.next().unwrap_or(&[]),
    );
    let text = std::str::from_utf8;
    if let (Ok(node), Ok(ele), Ok(poly)) = (text(node), text(ele), text(poly)) {
        if let Ok(m) = mesh::io::triangle_from_str(node, ele) {
            let _ = m.boundary_edges();
            // The region its triangles cover (what `cvtmesh mesh FILE` meshes again), with
            // the walls of the .poly beside it.
            let walls = mesh::io::triangle_walls_from_str(node, ele, poly).unwrap_or_default();
            region_of_mesh::checked(&m, &walls);
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
