//! The polish raises the smallest angle of a CCVT mesh without making its worst triangles or
//! cells worse by any of the measures it bounds.
use cvtmesh::geometry::{Threshold, Toward};
use cvtmesh::{
    looks_graded, measures, polish_restored, polish_within, MeshRequest, Method, Region, SizeField,
};

#[test]
fn the_polish_raises_the_smallest_angle_and_keeps_the_worst_triangles_and_cells() {
    // Runs in which an unbounded polish enlarged the largest triangle by half (α 0.173 → 0.265
    // on the horn, 0.220 → 0.323 on the lake).
    for (name, seed) in [("horn", 1), ("lake", 1)] {
        let region = Region::builtin(name).unwrap();
        let request = MeshRequest::points(10_000).seed(seed).polish(0.0);
        let mut mesh = Method::Ccvt.run(&region, &request).unwrap().mesh;
        let before = measures(&mesh, &region).unwrap();
        let report = polish_within(&mut mesh, &region, 40.0);
        assert!(report.kept && report.polished.moved > 0, "{name}: {report}");
        let after = measures(&mesh, &region).unwrap();
        // β = (π/3) / smallest angle − 1: the smallest angle rises by more than a degree.
        assert!(
            after.beta < before.beta - 0.03,
            "{name}: β {} -> {}",
            before.beta,
            after.beta
        );
        none_rose(
            name,
            &[
                ("α (largest triangle)", after.alpha, before.alpha),
                ("q (worst radius ratio)", after.q, before.q),
                ("h (largest cell)", after.h, before.h),
                ("μ (largest / smallest cell)", after.mu, before.mu),
                ("ν (largest / smallest cell area)", after.nu, before.nu),
                ("γ (nearest-neighbour distances)", after.gamma, before.gamma),
                ("χ (cell per nearest neighbour)", after.chi, before.chi),
            ],
        );
    }
}

/// Each (measure, after, before): after at most before, up to rounding.
fn none_rose(case: &str, measures: &[(&str, f64, f64)]) {
    for &(what, after, before) in measures {
        assert!(
            after <= before * (1.0 + 1e-9),
            "{case}: {what} {before} -> {after}"
        );
    }
}

#[test]
fn a_graded_mesh_is_polished_with_its_sizes_free_and_its_shapes_held() {
    // Toward the hole of square_hole, h from 0.02 to 0.1: the largest triangles sit at the
    // outer corners and the smallest cells at the hole, where the size field puts them; held,
    // those sizes would keep the worst angles where they are. The worst shapes (radius ratio,
    // cell reach per nearest neighbour) do not depend on the size and stay held.
    let region = Region::builtin("square_hole").unwrap();
    let t = Threshold {
        size_min: 0.02,
        size_max: 0.1,
        dist_min: 0.02,
        dist_max: 0.6,
    };
    let h = SizeField::threshold(&region, &[Toward::Loop(1)], t).unwrap();
    let request = MeshRequest::size_field(&h, &region, None).unwrap();
    let meshed = Method::Ccvt.run(&region, &request).unwrap().mesh;
    let unpolished = Method::Ccvt
        .run(&region, &request.clone().polish(0.0))
        .unwrap()
        .mesh;
    let (before, after) = (
        measures(&unpolished, &region).unwrap(),
        measures(&meshed, &region).unwrap(),
    );
    let mut held = unpolished.clone();
    polish_within(&mut held, &region, 40.0);
    let (free, bounded) = (meshed.min_angle_deg(), held.min_angle_deg());
    assert!(
        free >= 40.0 && free > bounded + 1.0,
        "{}° -> {free}° (sizes free), {bounded}° (held)",
        unpolished.min_angle_deg()
    );
    // From a file, which carries no size field, the mesh looks graded and is polished so.
    assert!(looks_graded(&unpolished));
    let mut from_file = unpolished.clone();
    polish_restored(&mut from_file, &region, 40.0).unwrap();
    let restored = measures(&from_file, &region).unwrap();
    assert!(
        from_file.min_angle_deg() >= 40.0,
        "{}",
        from_file.min_angle_deg()
    );
    none_rose(
        "graded square_hole",
        &[
            ("q (worst radius ratio)", after.q, before.q),
            ("χ (cell per nearest neighbour)", after.chi, before.chi),
            ("q from the file", restored.q, before.q),
            ("χ from the file", restored.chi, before.chi),
        ],
    );
}

#[test]
fn uniform_meshes_of_every_method_do_not_look_graded() {
    let region = Region::builtin("horn").unwrap();
    for method in [Method::Ccvt, Method::Refine, Method::Distmesh] {
        let request = MeshRequest::points(3000).polish(0.0).tol(1e-3);
        let mesh = method.run(&region, &request).unwrap().mesh;
        assert!(!looks_graded(&mesh), "{method}");
    }
}
