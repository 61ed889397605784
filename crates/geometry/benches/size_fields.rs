//! Building a graded size field, as `cvtmesh mesh --size-toward … --size-threshold …` does
//! before any meshing: the Distance + Threshold field sampled on its background grid (one
//! nearest-boundary query per node where a loop is a target, in parallel), its gradient limited
//! to 0.3 (`SizeField::bounded`), and the density the methods read. The four fields are those of
//! `scripts/compare_graded.sh` at about 10⁴ vertices, each on a 1024 × 1024 grid: O(nodes) work,
//! independent of K once the grid is at its cap, so at small K it is a large part of a run.
//! Then the density read at the seven points of a quadrature rule, as every clipped cell of a
//! graded run does for each of its fan triangles (`Density::at7`, nanoseconds per call), and a
//! field given at the vertices of meshes of 10⁴ to 10⁶ vertices (`SizeField::from_mesh`).
//! Run: `cargo bench -p cvtmesh-geometry --bench size_fields`. Prints Markdown tables of
//! best-of-3 wall-clock seconds.
use cvtmesh_geometry::{formats, DVec2, Density, Region, SizeField, Threshold, Toward};
mod common;
use common::best_of;

fn main() {
    let l_shape = formats::loops_from_str(
        "0 0\n1 0\n1 0.5\n0.5 0.5\n0.5 1\n0 1\n",
        "l_shape",
        "l_shape",
    )
    .unwrap()
    .with_default_corners();
    let t = |size_min: f64, size_max: f64, dist_min: f64, dist_max: f64| Threshold {
        size_min,
        size_max,
        dist_min,
        dist_max,
    };
    let cases: Vec<(&str, Region, Vec<Toward>, Threshold)> = vec![
        (
            "circle, toward its centre",
            Region::builtin("circle").unwrap(),
            vec![Toward::Point(DVec2::ZERO)],
            t(0.00574, 0.0631, 0.0, 1.0),
        ),
        (
            "L-shape, toward its corner",
            l_shape,
            vec![Toward::Point(DVec2::new(0.5, 0.5))],
            t(0.0017, 0.051, 0.0, 0.7),
        ),
        (
            "square_hole, toward its hole",
            Region::builtin("square_hole").unwrap(),
            vec![Toward::Loop(1)],
            t(0.00623, 0.0623, 0.02, 0.6),
        ),
        (
            "lake, toward its shores",
            Region::builtin("lake").unwrap(),
            vec![Toward::Loop(0), Toward::Loop(1)],
            t(3.0, 15.0, 0.0, 35.0),
        ),
    ];
    println!("| field | threshold (s) | gradation 0.3 (s) | density (s) | total (s) |");
    println!("| :--- | ---: | ---: | ---: | ---: |");
    for (name, region, toward, threshold) in cases {
        let (sample, field) = best_of(3, || {
            SizeField::threshold(&region, &toward, threshold).unwrap()
        });
        let (limit, bounded) =
            best_of(3, || field.bounded(&region, None, None, Some(0.3)).unwrap());
        let h_min = bounded.check(&region).unwrap().min;
        let (density, _) = best_of(3, || bounded.density(h_min));
        println!(
            "| {name} | {sample:.4} | {limit:.4} | {density:.4} | {:.4} |",
            sample + limit + density
        );
    }
    // The density at the seven points of small triangles swept row by row over the circle's
    // field (600 000 triangles of about a fifth of the finest spacing): one fan triangle each.
    let circle = Region::builtin("circle").unwrap();
    let field = SizeField::threshold(
        &circle,
        &[Toward::Point(DVec2::ZERO)],
        t(0.00574, 0.0631, 0.0, 1.0),
    )
    .unwrap();
    let rho = field.density(0.00574);
    let triangles: Vec<[DVec2; 7]> = (0..600_000)
        .map(|k| {
            let base = DVec2::new(
                -0.7 + 1.4 * (k % 1000) as f64 / 1000.0,
                -0.7 + 1.4 * (k / 1000) as f64 / 600.0,
            );
            std::array::from_fn(|i| base + DVec2::new(5e-4 * i as f64, 3e-4 * (i % 3) as f64))
        })
        .collect();
    let (t7, sum) = best_of(5, || {
        triangles
            .iter()
            .map(|p| rho.at7(std::hint::black_box(p)).iter().sum::<f64>())
            .sum::<f64>()
    });
    assert!(sum > 0.0 && matches!(rho, Density::Sampled(_)));
    println!("\n| density at seven points, circle toward its centre | calls | ns per call |");
    println!("| :--- | ---: | ---: |");
    println!(
        "| `Density::at7` | {} | {:.1} |",
        triangles.len(),
        t7 * 1e9 / triangles.len() as f64
    );
    // Sizes at the vertices of a mesh (an adaptive solver's): a structured mesh of n × n
    // vertices over the circle's box, h = 0.005 + 0.05·|x|, located on a grid of up to 1024²
    // nodes.
    println!("\n| sizes on a mesh of the circle's box | vertices | triangles | from_mesh (s) |");
    println!("| :--- | ---: | ---: | ---: |");
    for n in [101usize, 317, 1001] {
        let step = 2.2 / (n - 1) as f64;
        let points: Vec<DVec2> = (0..n * n)
            .map(|k| DVec2::new(-1.1 + step * (k % n) as f64, -1.1 + step * (k / n) as f64))
            .collect();
        let mut triangles = Vec::with_capacity(2 * (n - 1) * (n - 1));
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let a = (j * n + i) as u32;
                let (b, c, d) = (a + 1, a + 1 + n as u32, a + n as u32);
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        let sizes: Vec<f64> = points.iter().map(|p| 0.005 + 0.05 * p.length()).collect();
        let (t, _) = best_of(3, || {
            SizeField::from_mesh(&circle, &points, &triangles, &sizes).unwrap()
        });
        println!(
            "| structured | {} | {} | {t:.4} |",
            points.len(),
            triangles.len()
        );
    }
}
