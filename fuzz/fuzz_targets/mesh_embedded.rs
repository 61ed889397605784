//! Regions built from fuzzed loops with points embedded in them (sources, probes: vertices
//! every mesh must keep), meshed at small K by every method: a conforming mesh that has each
//! embedded point as a vertex at exactly its coordinates, or an error, never a panic.
//!
//! Bytes: the method and K (8–39) as in `mesh_loops`; the iteration cap (1–8); the count of
//! embedded points (1–4, from the low two bits); two bytes per point, each a coordinate on a
//! quarter of the loops' grid step (0 to 15.75), so points fall on edges, at vertices and
//! beside them; then the loops, as `mesh_loops` reads them.
#![no_main]
use cvtmesh::MeshRequest;
use geometry::{DVec2, Region};
use libfuzzer_sys::fuzz_target;

#[path = "common/loops.rs"]
mod loops;
#[path = "common/meshing.rs"]
mod meshing;

fuzz_target!(
    init: meshing::one_core(),
    |data: &[u8]| {
        let [head, cap, count, rest @ ..] = data else {
            return;
        };
        let n = 1 + (*count & 3) as usize;
        if rest.len() < 2 * n {
            return;
        }
        let (coords, rest) = rest.split_at(2 * n);
        let quarter = |b: u8| (b % 64) as f64 * 0.25;
        let points: Vec<(DVec2, i64)> = coords
            .chunks(2)
            .enumerate()
            .map(|(i, c)| (DVec2::new(quarter(c[0]), quarter(c[1])), i as i64 + 1))
            .collect();
        let Ok(region) = Region::from_loops("fuzz", loops::loops_from(rest)) else {
            return;
        };
        let Ok(region) = region.with_default_corners().with_embedded_points(points) else {
            return;
        };
        let run = meshing::Run::new(*head, *cap);
        let request = run.capped(MeshRequest::points(run.k));
        if let Ok(result) = run.method.run(&region, &request) {
            meshing::check_mesh(&result.mesh, &region, &run.to_string());
            for &(p, _) in region.embedded_points() {
                assert!(
                    result.mesh.points.contains(&p),
                    "{run}: the embedded point ({}, {}) is not a vertex",
                    p.x,
                    p.y
                );
            }
        }
    }
);
