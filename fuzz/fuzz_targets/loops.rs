//! Plain loop lists: any text is a region or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(r) = geometry::formats::loops_from_str(text, "fuzz.txt", "fuzz") {
            let _ = r.parts();
        }
    }
});
