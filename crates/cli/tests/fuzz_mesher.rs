//! Random small regions through every method: no panic, no hang, and every mesh a method
//! returns conforms to its region (a method may refuse a region it cannot mesh, with an error).
use cvtmesh::geometry::{DVec2, LoopRole, Piece, Region};
use cvtmesh::{check_conforming, MeshRequest, Mesher};
use proptest::prelude::*;

fn methods() -> Vec<Box<dyn Mesher>> {
    vec![
        Box::new(cvtmesh::ccvt::Ccvt::fast()),
        Box::new(cvtmesh::ccvt::Ccvt::algorithm1()),
        Box::new(cvtmesh::distmesh::DistMesh::default()),
        Box::new(cvtmesh::meshgen::Meshgen),
        Box::new(cvtmesh::vtm::Vtm::default()),
        Box::new(cvtmesh::refine::Refine::default()),
    ]
}

/// A star-shaped polygon around the origin, optionally with a small square hole.
fn region(radii: &[f64], hole: bool) -> Option<Region> {
    let n = radii.len();
    let pts: Vec<DVec2> = (0..n)
        .map(|i| DVec2::from_angle(std::f64::consts::TAU * i as f64 / n as f64) * radii[i])
        .collect();
    let lines = |p: &[DVec2]| {
        (0..p.len())
            .map(|i| Piece::Line {
                a: p[i],
                b: p[(i + 1) % p.len()],
            })
            .collect::<Vec<_>>()
    };
    let mut loops = vec![(LoopRole::Outer, lines(&pts))];
    if hole {
        let s = 0.08;
        let sq = [
            DVec2::new(-s, -s),
            DVec2::new(-s, s),
            DVec2::new(s, s),
            DVec2::new(s, -s),
        ];
        loops.push((LoopRole::Hole, lines(&sq)));
    }
    Region::new("random", loops, None).ok()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]
    #[test]
    fn random_regions_mesh_or_fail_cleanly(
        radii in prop::collection::vec(0.35f64..1.0, 3..9),
        hole in any::<bool>(),
        extra in 10usize..60,
        seed in 0u64..1000,
    ) {
        let Some(region) = region(&radii, hole) else { return Ok(()) };
        let k = cvtmesh::boundary_points_needed(&region) + extra;
        let mut meshed = 0;
        for m in methods() {
            let req = MeshRequest::points(k).seed(seed).max_iter(400);
            if let Ok(r) = m.mesh(&region, &req, &mut |_| {}) {
                if let Err(e) = check_conforming(&r.mesh, &region) {
                    panic!("{} returned a non-conforming mesh for radii {radii:?} hole {hole} K {k} seed {seed}: {e}", m.name());
                }
                meshed += 1;
            }
        }
        // A refusal is allowed, not a region that no method meshes.
        prop_assert!(meshed > 0, "no method meshed radii {:?} hole {} K {}", radii, hole, k);
    }
}
