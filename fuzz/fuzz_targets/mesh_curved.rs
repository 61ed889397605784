//! Regions with curved boundaries built from fuzzed pieces (arcs up to nearly a full turn
//! between grid points, lines, whole circles and super-ellipses, corners merged into chains by
//! a fuzzed corner angle) and meshed at small K by every method: a conforming mesh or an
//! error, never a panic. `mesh_loops` covers straight loops; this target covers what
//! projection onto arcs, tangent joins, chains and closed curves do to every method.
//!
//! Bytes: the method and K (8–39) as in `mesh_loops`; the iteration cap (1–8) and, with its
//! high bit, a corner angle of 0–180° (bits 3–6, in steps of 12°) instead of the default;
//! then up to three loops, each a head byte (bits 0–1: pieces between grid points, a circle or
//! a super-ellipse; bits 2–4: the point count; the high bit makes any loop but the first a
//! hole) and its bytes (see `curves::loops_from`).
#![no_main]
use cvtmesh::MeshRequest;
use geometry::Region;
use libfuzzer_sys::fuzz_target;

#[path = "common/curves.rs"]
mod curves;

#[path = "common/meshing.rs"]
mod meshing;

fuzz_target!(
    init: meshing::one_core(),
    |data: &[u8]| {
        let [head, cap, rest @ ..] = data else {
            return;
        };
        let loops = curves::loops_from(rest);
        if loops.is_empty() {
            return;
        }
        let Ok(region) = Region::new("fuzz", loops, None) else {
            return;
        };
        let region = if cap & 0x80 != 0 {
            region.with_corner_angle(((cap >> 3) & 0x0f) as f64 * 12.0)
        } else {
            region.with_default_corners()
        };
        let run = meshing::Run::new(*head, *cap);
        let request = run.capped(MeshRequest::points(run.k));
        if let Ok(result) = run.method.run(&region, &request) {
            meshing::check_mesh(&result.mesh, &region, &run.to_string());
        }
    }
);
