//! The user examples' own functions, run as tests: `cargo test` builds the examples but never
//! runs them, so a change that breaks what they show would otherwise go unnoticed.
#[allow(dead_code)] // its `main`
#[path = "../examples/mesh_polygon_with_hole.rs"]
mod mesh_polygon_with_hole;

#[allow(dead_code)] // its `main`
#[path = "../examples/measure_mesh.rs"]
mod measure_mesh;

#[allow(dead_code)] // its `main`
#[path = "../examples/graded_mesh.rs"]
mod graded_mesh;

#[allow(dead_code)] // its `main`
#[path = "../examples/adaptive_remesh.rs"]
mod adaptive_remesh;

#[allow(dead_code)] // its `main`
#[path = "../examples/quadratic_mesh.rs"]
mod quadratic_mesh;

use cvtmesh::DVec2;
use mesh_polygon_with_hole::{HOLE, OUTER, POINTS};
use std::path::PathBuf;

/// A fresh scratch directory per test, removed when the test ends.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Scratch {
        let d =
            std::env::temp_dir().join(format!("cvtmesh-examples-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Scratch(d)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn polygon_with_hole_is_meshed_and_written() {
    let d = Scratch::new("polygon");
    let out = d.0.join("house.msh");
    let (region, result) = mesh_polygon_with_hole::run(&out).unwrap();
    // A 4×3 rectangle under a roof of height 1.5, minus a unit window.
    assert!((region.area() - 14.0).abs() < 1e-12, "{}", region.area());
    assert_eq!(region.loops().len(), 2);
    assert_eq!(region.corners().len(), OUTER.len() + HOLE.len());
    let mesh = &result.mesh;
    assert_eq!(mesh.num_vertices(), POINTS);
    assert!(result.converged);
    cvtmesh::check_conforming(mesh, &region).unwrap();
    // Straight edges only, so the triangles cover the region exactly.
    assert!((mesh.area() - 14.0).abs() < 1e-9, "{}", mesh.area());
    assert!(mesh.min_angle_deg() > 25.0, "{}", mesh.min_angle_deg());
    // Every polygon vertex is a mesh vertex.
    for (x, y) in OUTER.into_iter().chain(HOLE) {
        let v = DVec2::new(x, y);
        assert!(
            mesh.points.iter().any(|p| (*p - v).length() < 1e-12),
            "no vertex at {v}"
        );
    }
    let back = cvtmesh::io::read_mesh(&out).unwrap();
    assert_eq!(back.num_vertices(), mesh.num_vertices());
    assert_eq!(back.num_triangles(), mesh.num_triangles());
    assert!((back.area() - mesh.area()).abs() < 1e-9);
}

#[test]
fn a_hole_outside_the_polygon_is_refused() {
    let far = [(10.0, 10.0), (11.0, 10.0), (11.0, 11.0)];
    let e = mesh_polygon_with_hole::polygon_region("bad", &OUTER, &[&far]).unwrap_err();
    assert!(e.to_string().contains("outside"), "{e}");
}

#[test]
fn measures_of_a_written_mesh_match_the_mesh_in_memory() {
    let d = Scratch::new("measure");
    let out = d.0.join("house.msh");
    let (region, result) = mesh_polygon_with_hole::run(&out).unwrap();
    // The same region as a plain loop-list file, for the example's REGION argument.
    let loops = |l: &[(f64, f64)]| {
        l.iter()
            .map(|(x, y)| format!("{x} {y}\n"))
            .collect::<String>()
    };
    let region_file = d.0.join("house.txt");
    std::fs::write(&region_file, format!("{}\n{}", loops(&OUTER), loops(&HOLE))).unwrap();

    let args = [out, region_file].map(|p| p.to_str().unwrap().to_string());
    let (mesh, read_region) = measure_mesh::inputs(&args).unwrap();
    assert!((read_region.area() - region.area()).abs() < 1e-12);
    // Without the region file, the region the mesh covers: the same polygon, the same measures.
    let (_, own) = measure_mesh::inputs(&args[..1]).unwrap();
    assert!((own.area() - region.area()).abs() < 1e-12);
    let own_measures = cvtmesh::measures(&mesh, &own).unwrap();
    let from_file = cvtmesh::measures(&mesh, &read_region).unwrap();
    let in_memory = cvtmesh::measures(&result.mesh, &region).unwrap();
    assert_eq!(
        (from_file.k, from_file.k_tilde),
        (POINTS, result.mesh.num_triangles())
    );
    let table = measure_mesh::table(&from_file);
    let names: Vec<&str> = table.iter().map(|t| t.0).collect();
    assert_eq!(
        names,
        ["lambda", "gamma", "h", "mu", "chi", "nu", "tau", "d", "alpha", "beta", "q", "p"]
    );
    for ((name, a), (_, b)) in table.iter().zip(measure_mesh::table(&in_memory)) {
        assert!(a.is_finite() && *a >= 0.0, "{name} = {a}");
        assert!(
            (a - b).abs() <= 1e-9 * b.abs().max(1e-12),
            "{name}: {a} vs {b}"
        );
    }
    for ((name, a), (_, b)) in measure_mesh::table(&own_measures)
        .iter()
        .zip(measure_mesh::table(&from_file))
    {
        assert!(
            (a - b).abs() <= 1e-9 * b.abs().max(1e-12),
            "{name}: {a} vs {b}"
        );
    }
    // β is the smallest angle's shortfall from 60°.
    let beta = 60.0 / mesh.min_angle_deg() - 1.0;
    assert!(
        (from_file.beta - beta).abs() < 1e-9,
        "{} vs {beta}",
        from_file.beta
    );
}

#[test]
fn measure_mesh_without_arguments_scores_a_fresh_mesh() {
    let (mesh, region) = measure_mesh::inputs(&[]).unwrap();
    assert_eq!(region.name(), "square_hole");
    assert_eq!(mesh.num_vertices(), 500);
    let m = cvtmesh::measures(&mesh, &region).unwrap();
    assert_eq!(measure_mesh::table(&m).len(), 12);
    let e = measure_mesh::inputs(&["missing.msh".to_string()]).unwrap_err();
    assert!(e.to_string().contains("missing.msh"), "{e}");
    let three = ["a", "b", "c"].map(String::from);
    let e = measure_mesh::inputs(&three).unwrap_err();
    assert!(e.to_string().contains("usage"), "{e}");
    // A mesh that reads, with a region that does not: the region is named.
    let d = Scratch::new("measure_inputs");
    let file = d.0.join("m.msh");
    cvtmesh::io::write_mesh(&mesh, &file).unwrap();
    let path = file.to_string_lossy().to_string();
    let e = measure_mesh::inputs(&[path.clone(), "nonesuch".to_string()]).unwrap_err();
    assert!(e.to_string().contains("nonesuch"), "{e}");
    let (read, _) = measure_mesh::inputs(&[path, "square_hole".to_string()]).unwrap();
    assert_eq!(read.num_vertices(), 500);
}

#[test]
fn graded_mesh_follows_its_size_field() {
    let d = Scratch::new("graded");
    let out = d.0.join("graded.vtu");
    let (result, c) = graded_mesh::run(&out).unwrap();
    assert!(result.converged);
    assert!(out.metadata().unwrap().len() > 0);
    assert_eq!(result.mesh.num_vertices(), c.vertices);
    assert!(
        (c.vertices as f64 - c.predicted_vertices).abs() <= 0.5,
        "{c:?}"
    );
    assert!(
        c.unit_share >= 0.95 && c.efficiency >= 0.9 && c.min_angle_deg >= 30.0,
        "{c:?}"
    );
    // Graded: edges near the centre are shorter than edges near the rim.
    let m = &result.mesh;
    let mut inner = (0.0, 0usize);
    let mut outer = (0.0, 0usize);
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (m.points[t[k] as usize], m.points[t[(k + 1) % 3] as usize]);
            let r = (0.5 * (a + b)).length();
            let slot = if r < 0.2 {
                &mut inner
            } else if r > 0.8 {
                &mut outer
            } else {
                continue;
            };
            slot.0 += (b - a).length();
            slot.1 += 1;
        }
    }
    assert!(outer.0 / outer.1 as f64 > 2.5 * inner.0 / inner.1 as f64);
}

#[test]
fn adaptive_remeshing_from_sizes_on_the_last_mesh_lowers_the_interpolation_error() {
    let d = Scratch::new("adaptive");
    let out = d.0.join("adaptive.vtu");
    let meshes = adaptive_remesh::run(2, &out).unwrap();
    assert!(out.metadata().unwrap().len() > 0);
    let errors: Vec<f64> = meshes
        .iter()
        .map(adaptive_remesh::interpolation_error)
        .collect();
    // The same vertex count every time, and the error falling with each step (0.139, 0.072,
    // 0.045 when written).
    for m in &meshes {
        assert_eq!(m.num_vertices(), adaptive_remesh::VERTICES);
    }
    assert!(
        errors[1] < 0.75 * errors[0] && errors[2] < 0.5 * errors[0],
        "{errors:?}"
    );
    // The adapted vertices crowd at the front: the median distance to it is a fraction of
    // the uniform mesh's.
    let median_gap = |m: &cvtmesh::Mesh| {
        let mut g: Vec<f64> = m
            .points
            .iter()
            .map(|p| (p.length() - adaptive_remesh::R0).abs())
            .collect();
        g.sort_by(f64::total_cmp);
        g[g.len() / 2]
    };
    assert!(median_gap(&meshes[2]) < 0.5 * median_gap(&meshes[0]));
}

#[test]
fn quadratic_triangles_cover_the_circle_far_better_than_chords() {
    let d = Scratch::new("quadratic");
    let out = d.0.join("circle_p2.msh");
    let region = cvtmesh::Region::builtin("circle").unwrap();
    let (q, linear, quadratic) = quadratic_mesh::run(&region, 400, &out).unwrap();
    let exact = region.area();
    // The chords cut across the circle: the three-node mesh misses area of order h² times the
    // boundary's length (5.6e-3 here); the six-node mesh's parabolas a hundredth of that or
    // less (7e-7: the error falls from O(h²) to O(h⁴)).
    assert!(exact - linear > 1e-3, "{}", exact - linear);
    assert!(
        (exact - quadratic).abs() < (exact - linear) * 1e-2,
        "{} against {}",
        exact - quadratic,
        exact - linear
    );
    // Read back by its corners, the file is the three-node mesh.
    let back = cvtmesh::io::read_mesh(&out).unwrap();
    assert_eq!(back.num_vertices(), q.num_corners());
    assert_eq!(back.num_triangles(), q.triangles.len());
}
