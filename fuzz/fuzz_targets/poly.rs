//! Triangle's .poly: any text is a region or an error, never a panic; a region's corners
//! chosen, and its boundary simplified, keep a marker for every piece and every vertex marked
//! on its own as a corner; its vertices on no segment that it keeps lie inside.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(r) = geometry::formats::poly_from_str(text, "fuzz.poly", "fuzz") {
            let marked = r.piece_markers().is_some();
            let c = r.with_default_corners();
            assert_eq!(c.piece_markers().is_some(), marked);
            let corners_hold = |r: &geometry::Region| {
                r.vertex_markers()
                    .iter()
                    .all(|(p, _)| r.corners().iter().any(|c| c.pos == *p))
            };
            assert!(corners_hold(&c));
            // Points kept inside lie inside.
            for &(p, _) in r.embedded_points() {
                assert!(r.signed_distance(p) < 0.0, "{p}");
            }
            assert!(r.vertex_markers().is_empty() || marked);
            if let Ok(s) = r.simplified(0.05 * r.diameter()) {
                if let Some(m) = s.region.piece_markers() {
                    assert_eq!(m.len(), s.region.pieces().len());
                }
                assert_eq!(s.region.vertex_markers(), r.vertex_markers());
                assert!(corners_hold(&s.region.with_default_corners()));
            }
        }
    }
});
