//! The expression language of --size-field and --density: parse, evaluate, never panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(e) = geometry::expr::Expr::parse(text) {
            for p in [(0.0, 0.0), (0.5, -1.5), (1e300, -1e-300)] {
                let _ = e.eval(geometry::DVec2::new(p.0, p.1));
            }
        }
        let _ = geometry::SizeField::from_expr(text);
    }
});
