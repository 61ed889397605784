//! Graded meshes of fuzzed regions: a distance field (Gmsh's Distance + Threshold) toward a
//! loop, a piece or a point of a region built from fuzzed loops, optionally gradation-limited,
//! meshed at small K by every method. A conforming mesh or an error, never a panic; and the
//! size conformity of what comes back is measured without a panic, its shares in [0, 1].
//!
//! Bytes: the method and K (8–39) as in `mesh_loops`; the iteration cap (1–8), what the field
//! is toward (bits 3–4: a loop, a piece, a point, a loop and a point), a gradation limit of
//! 0.3 (bit 5) and curved loops (bit 6: read as `mesh_curved` reads them); the ratio of the
//! largest size to the smallest (1–40); the distances over which it grows (low and high
//! nibble, in grid steps); the loop, piece or point it is toward; then the loops. The field's
//! smallest size is one grid step, its scale set by K.
#![no_main]
use cvtmesh::MeshRequest;
use geometry::{DVec2, Region, SizeField, Threshold, Toward};
use libfuzzer_sys::fuzz_target;

#[path = "common/curves.rs"]
mod curves;
#[path = "common/loops.rs"]
mod loops;
#[path = "common/meshing.rs"]
mod meshing;

fuzz_target!(
    init: meshing::one_core(),
    |data: &[u8]| {
        let [head, flags, ratio, dists, target, rest @ ..] = data else {
            return;
        };
        let region = if flags & 0x40 != 0 {
            Region::new("fuzz", curves::loops_from(rest), None)
        } else {
            Region::from_loops("fuzz", loops::loops_from(rest))
        };
        let Ok(region) = region else {
            return;
        };
        let region = region.with_default_corners();
        let loop_at = Toward::Loop(*target as usize % region.loops().len().max(1));
        let point = Toward::Point(DVec2::new((target % 16) as f64, (target / 16) as f64));
        let toward = match (flags >> 3) & 3 {
            0 => vec![loop_at],
            1 => vec![Toward::Piece(*target as usize % region.pieces().len().max(1))],
            2 => vec![point],
            _ => vec![loop_at, point],
        };
        let dist_min = (dists & 0x0f) as f64 * 0.25;
        let threshold = Threshold {
            size_min: 1.0,
            size_max: 1.0 + (ratio % 40) as f64,
            dist_min,
            dist_max: dist_min + 0.25 + (dists >> 4) as f64 * 0.5,
        };
        let Ok(field) = SizeField::threshold(&region, &toward, threshold) else {
            return;
        };
        let field = if flags & 0x20 != 0 {
            match field.bounded(&region, None, None, Some(0.3)) {
                Ok(f) => f,
                Err(_) => return,
            }
        } else {
            field
        };
        // Where the field outgrows its grid, if anywhere: a node inside, a real rise.
        if let Some(u) = field.unresolved(&region) {
            assert!(u.neighbour > 2.0 * u.size && u.size > 0.0 && u.step > 0.0, "{u}");
        }
        let run = meshing::Run::new(*head, *flags);
        let Ok(request) = MeshRequest::size_field(&field, &region, Some(run.k)) else {
            return;
        };
        let request = run.capped(request);
        if let Ok(result) = run.method.run(&region, &request) {
            meshing::check_mesh(&result.mesh, &region, &run.to_string());
            if let Ok(c) = cvtmesh::metrics::size_conformity(&result.mesh, &field, &region) {
                assert!((0.0..=1.0).contains(&c.unit_share), "{c:?}");
                assert!(c.efficiency > 0.0 && c.efficiency <= 1.0, "{c:?}");
            }
        }
    }
);
