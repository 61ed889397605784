//! Inputs the fuzz targets in `fuzz/` found, each named after what it caught.
use cvtmesh::geometry::LoopRole;
use cvtmesh::{check_conforming, DVec2, MeshRequest, Method, Region};

/// `mesh_loops`: two needles joined at the top, 1e-4 wide at their tips, with a 19° bend that
/// the default corners drop; CCVT at K = 20 returned a triangle outside the region. Since the
/// needles' sides, which face each other across a gap, get corners one spacing apart, it is
/// meshed; the thin feature is still reported.
#[test]
fn a_needle_far_thinner_than_the_spacing_is_never_meshed_outside() {
    let pts = [(11, 15), (14, 15), (11, 0), (12, 6), (11, 12), (6, 1)]
        .map(|(x, y)| DVec2::new(x as f64, y as f64))
        .to_vec();
    let raw = Region::from_loops("needles", vec![(LoopRole::Outer, pts)]).unwrap();
    let region = raw.with_default_corners();
    assert_eq!(region.corners().len(), 5);
    let request = MeshRequest::points(20).tol(1e-2).max_iter(200);
    // The needles' tips are sharp corners, which no K resolves; the place reported is the
    // narrowest one a larger K does resolve, 0.2 wide between them.
    let thin = cvtmesh::thin_feature(&region, &request).expect("a thin feature");
    assert!(thin.spacing / thin.width > 5.0, "{thin}");
    assert_eq!(thin.corner, None, "{thin}");
    let r = Method::Ccvt.run(&region, &request).unwrap();
    check_conforming(&r.mesh, &raw).unwrap();
    // Every method gives a conforming mesh or an error, never a mesh outside the region.
    for m in Method::ALL {
        if let Ok(r) = m.run(&region, &request) {
            check_conforming(&r.mesh, &raw).unwrap_or_else(|e| panic!("{m}: {e}"));
        }
    }
}
