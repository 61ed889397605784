//! One Delaunay refinement at a fixed area bound (Triangle's `-q20 -a<A>`) on the circle and
//! the lake, uniform and with the graded comparison's size fields (toward the circle's centre,
//! toward the lake's shores: the CCVT's graded start is two such runs); then the whole method,
//! whose area search refines once per step, on the lake at 10⁵. Run: `cargo bench -p
//! cvtmesh-refine --bench refine [-- quick]` (`quick` stops at 10⁵). Prints a Markdown table
//! of best-of-3 wall-clock seconds and microseconds per vertex: the refinement is O(n log n)
//! (the queue of bad triangles), so the last column should grow slowly with n.
#[path = "../../geometry/benches/common/mod.rs"]
mod common;

use common::best_of;
use cvtmesh_refine::Refine;
use geometry::{DVec2, Density, Region, SizeField, Threshold, Toward};
use mesh::{MeshRequest, Mesher};

fn main() {
    let quick = std::env::args().any(|a| a == "quick");
    let sizes: &[usize] = if quick {
        &[10_000, 100_000]
    } else {
        &[10_000, 100_000, 1_000_000]
    };
    let method = Refine::default();
    println!("| region | density | vertices | s | µs per vertex |");
    println!("|---|---|---|---|---|");
    for name in ["circle", "lake"] {
        let region = Region::builtin(name).expect("built-in region");
        let (toward, t) = match name {
            "circle" => (Toward::Point(DVec2::ZERO), [0.0018, 0.02, 0.0, 1.0]),
            _ => (Toward::Loop(0), [1.0, 5.0, 0.0, 35.0]),
        };
        let [size_min, size_max, dist_min, dist_max] = t;
        let threshold = Threshold {
            size_min,
            size_max,
            dist_min,
            dist_max,
        };
        let graded = SizeField::threshold(&region, &[toward], threshold)
            .expect("a valid field")
            .density(size_min);
        for (label, density) in [("uniform", Density::Uniform), ("graded", graded)] {
            let run = |area: f64, n: usize| {
                method
                    .refine_with_area(&region, area, &density, 20 * n)
                    .expect("a valid bound")
            };
            for &n in sizes {
                // About two triangles per vertex, each about 0.55 of the bound where ρ = 1;
                // the vertex count goes as 1/A, which one trial run calibrates.
                let guess = 1.8 * region.area() / (2.0 * n as f64);
                let trial = run(guess, n).mesh.num_vertices();
                let area = guess * trial as f64 / n as f64;
                let (s, r) = best_of(3, || run(area, n));
                let v = r.mesh.num_vertices();
                println!(
                    "| {name} | {label} | {v} | {s:.3} | {:.2} |",
                    1e6 * s / v as f64
                );
            }
        }
    }
    let region = Region::builtin("lake").expect("built-in region");
    let (s, r) = best_of(1, || {
        method
            .mesh(&region, &MeshRequest::points(100_000), &mut |_| {})
            .expect("a mesh")
    });
    println!(
        "\nthe method on the lake at K = 10⁵ (area search): {s:.2} s, {} refinements, K = {}",
        r.iterations,
        r.mesh.num_vertices()
    );
}
