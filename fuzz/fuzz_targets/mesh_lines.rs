//! Regions built from fuzzed loops with lines embedded in them (interfaces, cracks, inclusions:
//! polylines every mesh must follow with its edges), meshed at small K by every method: a
//! conforming mesh whose edges run along every line, or an error, never a panic.
//!
//! Bytes: the method and K (8–39) as in `mesh_loops`; the iteration cap (1–8); a byte whose
//! low bit gives one or two lines and whose next two bits each line's extra points (2–4
//! points a line, the last equal to the first closing it when the bit above is set); two
//! bytes per point, each a coordinate on a quarter of the loops' grid step (0 to 15.75), so
//! points fall on walls, at corners and beside them; then the loops, as `mesh_loops` reads
//! them.
#![no_main]
use cvtmesh::MeshRequest;
use geometry::{DVec2, EmbeddedLine, Region};
use libfuzzer_sys::fuzz_target;

#[path = "common/loops.rs"]
mod loops;
#[path = "common/meshing.rs"]
mod meshing;

fuzz_target!(
    init: meshing::one_core(),
    |data: &[u8]| {
        let [head, cap, shape, rest @ ..] = data else {
            return;
        };
        let count = 1 + (*shape & 1) as usize;
        let sizes: Vec<usize> = (0..count)
            .map(|i| 2 + ((*shape >> (1 + 2 * i)) & 3).min(2) as usize)
            .collect();
        let closed = *shape & 0x80 != 0;
        let needed: usize = 2 * sizes.iter().sum::<usize>();
        if rest.len() < needed {
            return;
        }
        let (coords, rest) = rest.split_at(needed);
        let quarter = |b: u8| (b % 64) as f64 * 0.25;
        let mut points = coords
            .chunks(2)
            .map(|c| DVec2::new(quarter(c[0]), quarter(c[1])));
        let lines: Vec<EmbeddedLine> = sizes
            .iter()
            .enumerate()
            .map(|(i, &n)| {
                let mut pts: Vec<DVec2> = points.by_ref().take(n).collect();
                if closed && n > 2 {
                    pts.push(pts[0]);
                }
                EmbeddedLine {
                    points: pts,
                    marker: i as i64 + 1,
                }
            })
            .collect();
        let Ok(region) = Region::from_loops("fuzz", loops::loops_from(rest)) else {
            return;
        };
        let Ok(region) = region.with_default_corners().with_embedded_lines(lines) else {
            return;
        };
        let run = meshing::Run::new(*head, *cap);
        let request = run.capped(MeshRequest::points(run.k));
        if let Ok(result) = run.method.run(&region, &request) {
            meshing::check_mesh(&result.mesh, &region, &run.to_string());
            if let Err(e) = cvtmesh::line_edges(&result.mesh, &region) {
                panic!("{run}: a mesh returned without following its lines: {e}");
            }
        }
    }
);
