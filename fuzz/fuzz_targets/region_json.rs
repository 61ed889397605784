//! The project's region JSON: any text is a region or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(r) = geometry::Region::from_json_str(text, "fuzz.json") {
            let _ = r.parts();
            let _ = r.with_default_corners();
        }
    }
});
