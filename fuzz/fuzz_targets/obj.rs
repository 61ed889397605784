//! Wavefront .obj: a mesh or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(m) = mesh::io::obj_from_str(text) {
            let _ = m.boundary_edges();
        }
    }
});
