//! Triangle's .node and .ele, split at the first NUL byte: a mesh or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let cut = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    let (node, ele) = (&data[..cut], data.get(cut + 1..).unwrap_or(&[]));
    if let (Ok(node), Ok(ele)) = (std::str::from_utf8(node), std::str::from_utf8(ele)) {
        if let Ok(m) = mesh::io::triangle_from_str(node, ele) {
            let _ = m.boundary_edges();
        }
    }
});
