//! Delaunay alone vs Delaunay + all clipped cells with moments, 10⁴–10⁶ generators in the unit
//! circle and in the lake; and the cells again with the density of a size field (the graded
//! comparison's: toward the circle's centre, toward the lake's shores), whose quadrature is
//! most of a graded run's cost; and the repair by flips after 5 % of the generators, those
//! nearest one point (an active set's cluster), moved by up to a tenth of the mean spacing and
//! back (`Delaunay::move_points`, two calls); and a fresh framed build, the one a run starts
//! with (from 5·10⁴ points the two halves on two threads, joined). Run: `cargo bench -p cvtmesh-tessellation --bench cells [--
//! quick]` (`quick` stops at 10⁵). Prints a Markdown table of best-of-3 wall-clock seconds
//! (best of 7 for the graded cells and the moves).
#[path = "../../geometry/benches/common/mod.rs"]
mod common;

use common::best_of;
use cvtmesh_tessellation::{clipped_cells, Delaunay};
use geometry::{DVec2, Density, Polygon, Region, Rng, SizeField, Threshold, Toward};
use spade::{DelaunayTriangulation, Point2, Triangulation};

/// `n` generators: random points inside plus about 2√n points spread along the boundary rings
/// (CCVT puts generators on the boundary).
fn generators(poly: &Polygon, n: usize, seed: u64) -> Vec<DVec2> {
    let mut rng = Rng::new(seed);
    let perimeter: f64 = poly.edges().map(|(a, b, _)| a.distance(b)).sum();
    let nb = (2.0 * (n as f64).sqrt()) as usize;
    let mut pts = Vec::with_capacity(n);
    for (a, b, _) in poly.edges() {
        let k = (nb as f64 * a.distance(b) / perimeter).round() as usize;
        pts.extend((0..k).map(|i| a.lerp(b, (i as f64 + rng.uniform()) / k.max(1) as f64)));
    }
    let (lo, hi) = poly.bbox();
    while pts.len() < n {
        let p = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        if poly.contains(p) {
            pts.push(p);
        }
    }
    pts
}

/// Best of 7: 5 % of `pts` (those nearest a point inside `poly`) moved by up to a tenth of the
/// mean spacing and back, each by `Delaunay::move_points` on a framed triangulation.
fn moved_and_back(poly: &Polygon, pts: &[DVec2]) -> f64 {
    let (lo, hi) = poly.bbox();
    let mut del = Delaunay::framed(lo, hi);
    del.rebuild(pts);
    let centre = pts[pts.len() / 2];
    let mut order: Vec<u32> = (0..pts.len() as u32).collect();
    order.sort_by(|&a, &b| {
        let d = |i: u32| pts[i as usize].distance_squared(centre);
        d(a).total_cmp(&d(b))
    });
    let mut moved = order[..pts.len() / 20].to_vec();
    moved.sort_unstable();
    let step = 0.1 * (poly.area() / pts.len() as f64).sqrt();
    let mut rng = Rng::new(5);
    let mut to = pts.to_vec();
    for &i in &moved {
        to[i as usize] += DVec2::new(rng.range(-step, step), rng.range(-step, step));
    }
    best_of(7, || {
        let there = del.move_points(&to, &moved).is_some();
        let back = del.move_points(pts, &moved).is_some();
        assert!(there && back, "repaired by flips");
    })
    .0
}

fn main() {
    let quick = std::env::args().any(|a| a == "quick");
    let sizes: &[usize] = if quick {
        &[10_000, 100_000]
    } else {
        &[10_000, 100_000, 1_000_000]
    };
    println!("threads: {}", rayon::current_num_threads());
    println!(
        "| domain | edges | n | spade bulk_load s | Delaunay::new s | framed fresh s | cells s | total s | total / spade | boundary cells | area rel. err | cells, graded ρ s | 5 % moved and back s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in ["circle", "lake"] {
        let region = Region::builtin(name).expect("built-in region");
        let poly = region.polygonize(1e-4 * region.diameter());
        let edges = poly.edges().count();
        // The graded comparison's fields at 10⁵ (scripts/compare_graded.sh).
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
        for &n in sizes {
            let pts = generators(&poly, n, 1);
            let (ts, _) = best_of(3, || {
                let v: Vec<Point2<f64>> = pts.iter().map(|p| Point2::new(p.x, p.y)).collect();
                DelaunayTriangulation::<Point2<f64>>::bulk_load(v).map(|t| t.num_vertices())
            });
            let (td, del) = best_of(3, || Delaunay::new(&pts));
            let (lo, hi) = region.bbox();
            let (tf, _) = best_of(3, || {
                let mut d = Delaunay::framed(lo, hi);
                d.rebuild(&pts);
                d.num_vertices()
            });
            let (tc, cells) = best_of(3, || clipped_cells(&pts, &del, &poly, &Density::Uniform));
            let boundary = cells.cells.iter().filter(|c| c.on_boundary()).count();
            let err = (cells.total_area() - poly.area()).abs() / poly.area();
            let (tg, _) = best_of(7, || clipped_cells(&pts, &del, &poly, &graded));
            let tm = moved_and_back(&poly, &pts);
            println!(
                "| {name} | {edges} | {n} | {ts:.3} | {td:.3} | {tf:.3} | {tc:.3} | {:.3} | {:.2} | {boundary} | {err:.1e} | {tg:.3} | {tm:.4} |",
                td + tc,
                (td + tc) / ts
            );
        }
    }
}
