//! Regions built from fuzzed loops (small integer coordinates make collinear, touching and
//! crossing loops common) and meshed at small K by every method: a conforming mesh or an
//! error, never a panic, and the reports on the mesh (slivers, coverage) never panic either.
//!
//! The first byte picks the method and K (8–39), the second the iteration cap (1–8) and,
//! with its high bit, a simplification of the loops (`Region::simplified`), the rest are the
//! loops. A small cap is the point: robustness, not convergence, is under test, and a
//! method stopped after one or two iterations must still hand back a conforming mesh. CCVT
//! applies the cap per phase: a Newton step needs a cap of 3 or more, an active-set step 4,
//! and the range covers them as well as the single Lloyd step of a cap of 1.
#![no_main]
use cvtmesh::MeshRequest;
use geometry::Region;
use libfuzzer_sys::fuzz_target;

#[path = "common/loops.rs"]
mod loops;
#[path = "common/meshing.rs"]
mod meshing;

fuzz_target!(
    init: meshing::one_core(),
    |data: &[u8]| {
        let [head, cap, rest @ ..] = data else {
            return;
        };
        let loops = loops::loops_from(rest);
        let Ok(region) = Region::from_loops("fuzz", loops) else {
            return;
        };
        let run = meshing::Run::new(*head, *cap);
        let request = run.capped(MeshRequest::points(run.k));
        // The high bit simplifies the loops first, at 0 to 7.5 grid steps.
        let region = if cap & 0x80 != 0 {
            let tol = ((cap >> 3) & 0x0f) as f64 * 0.5;
            let Ok(simple) = region.simplified(tol) else {
                return;
            };
            assert!(simple.deviation <= tol, "deviation {} > {tol}", simple.deviation);
            simple.region
        } else {
            region
        };
        if let Ok(result) = run.method.run(&region.with_default_corners(), &request) {
            meshing::check_mesh(&result.mesh, &region, &run.to_string());
        }
    }
);
