//! Units do not matter: a region given in other units (scaled by a power of two, which
//! floating point does exactly) gives the same mesh in those units, bit for bit, from the
//! smallest to the largest extent regions may have; beyond those limits, or far from the
//! origin, a region is refused with what to do.
use cvtmesh::geometry::{Density, GeometryError, LoopRole, EXTENT_LIMIT, OFFSET_LIMIT};
use cvtmesh::{DVec2, MeshRequest, Method, Region};
use std::sync::Arc;

/// A square with a notch, scaled by `s` and moved by `at`.
fn notched(s: f64, at: DVec2) -> Result<Region, GeometryError> {
    let pts = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.5, 0.7), (0.0, 1.0)]
        .map(|(x, y)| at + s * DVec2::new(x, y))
        .to_vec();
    Ok(Region::from_loops("notched", vec![(LoopRole::Outer, pts)])?.with_default_corners())
}

#[test]
fn a_region_in_other_units_gives_the_same_mesh_in_those_units() {
    // 2^±46: the notched square's diameter is within a factor 1.1 of the limits.
    let unit = notched(1.0, DVec2::ZERO).unwrap();
    for k in [-46, 46] {
        let s = 2f64.powi(k);
        let scaled = notched(s, DVec2::ZERO).unwrap();
        assert!(
            scaled.diameter() * 1.1
                > if k < 0 {
                    1.0 / EXTENT_LIMIT
                } else {
                    EXTENT_LIMIT
                }
        );
        for method in Method::ALL {
            let request = MeshRequest::points(150).max_iter(300);
            let a = method.run(&unit, &request).unwrap().mesh;
            let b = method.run(&scaled, &request).unwrap().mesh;
            assert_eq!(a.triangles, b.triangles, "{method} at 2^{k}");
            let moved = a
                .points
                .iter()
                .zip(&b.points)
                .filter(|(p, q)| **p * s != **q);
            assert_eq!(moved.count(), 0, "{method} at 2^{k}");
        }
        // A density is a shape, not a length: ρ(x / s) gives the same graded mesh.
        let rho = |s: f64| Density::Function(Arc::new(move |p: DVec2| 1.0 + 8.0 * (p.x / s)));
        let a = Method::Ccvt
            .run(&unit, &MeshRequest::points(150).density(rho(1.0)))
            .unwrap()
            .mesh;
        let b = Method::Ccvt
            .run(&scaled, &MeshRequest::points(150).density(rho(s)))
            .unwrap()
            .mesh;
        assert_eq!(a.triangles, b.triangles, "graded at 2^{k}");
        assert!(a.points.iter().zip(&b.points).all(|(p, q)| *p * s == *q));
    }
}

#[test]
fn regions_beyond_the_extent_limits_or_far_from_the_origin_are_refused_with_what_to_do() {
    for s in [1e-15, 1e15, 1e-150, 1e150] {
        let e = notched(s, DVec2::ZERO).unwrap_err().to_string();
        assert!(
            e.contains("diameter") && e.contains("scale its coordinates"),
            "{s}: {e}"
        );
    }
    // 1e9 diameters from the origin: refused, naming the translation; 1e5 is meshed as at 0.
    let far = DVec2::new(1e9, -3e8);
    let e = notched(1.0, far).unwrap_err().to_string();
    assert!(
        e.contains("translate its coordinates") && e.contains("subtract"),
        "{e}"
    );
    assert!(far.length() > OFFSET_LIMIT * 1.2);
    let near = notched(1.0, DVec2::new(1e5, 0.0)).unwrap();
    let result = Method::Ccvt.run(&near, &MeshRequest::points(150)).unwrap();
    assert!(result.converged);
    assert!((result.mesh.area() - near.area()).abs() < 1e-9 * near.area());
}
