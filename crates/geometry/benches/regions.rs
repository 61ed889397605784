//! Reading a digitized outline and fitting its corners to a spacing, 10³–10⁵ vertices: a star
//! with fractal radius noise written as a loop list, read with every vertex listed as a corner
//! (validation, crossings, corner matching), thinned to the default corners, then
//! `Region::with_spacing_corners` at the spacings of K = 300 and K = 10⁴. Reading grows
//! linearly; the fit examines every stretch of about a spacing, which holds more vertices the
//! coarser the spacing, so at K = 300 it grows faster (about n · spacing / vertex spacing).
//! Run: `cargo bench -p cvtmesh-geometry --bench regions`. Prints a Markdown
//! table of best-of-3 wall-clock seconds.
use cvtmesh_geometry::{formats, Region, Rng};
use std::f64::consts::TAU;
mod common;
use common::best_of;

/// `n` vertices around a disc of radius 10, 300 harmonics of fractal noise (amplitude k^-1.5).
fn outline(n: usize) -> String {
    let mut rng = Rng::new(3);
    let phases: Vec<f64> = (0..300).map(|_| rng.range(0.0, TAU)).collect();
    let mut text = String::with_capacity(48 * n);
    for i in 0..n {
        let t = TAU * i as f64 / n as f64;
        let v: f64 = phases
            .iter()
            .enumerate()
            .map(|(k, p)| ((k + 1) as f64).powf(-1.5) * ((k + 1) as f64 * t + p).sin())
            .sum();
        let r = 10.0 * (1.0 + 0.15 * v);
        text += &format!("{} {}\n", r * t.cos(), r * t.sin());
    }
    text
}

fn main() {
    println!("| vertices | read (s) | default corners (s) | fit, K = 300 (s) | fit, K = 10⁴ (s) | corners added |");
    println!("| ---: | ---: | ---: | ---: | ---: | ---: |");
    for n in [1_000, 10_000, 100_000] {
        let text = outline(n);
        let (read, raw) = best_of(3, || {
            formats::loops_from_str(&text, "coast", "coast").unwrap()
        });
        let (thin, region): (f64, Region) = best_of(3, || raw.with_default_corners());
        let spacing = |k: f64| (2.0 * region.area() / (3f64.sqrt() * k)).sqrt();
        let (h300, h1e4) = (spacing(300.0), spacing(1e4));
        let (coarse, a) = best_of(3, || region.with_spacing_corners(&|_| h300));
        let (fine, b) = best_of(3, || region.with_spacing_corners(&|_| h1e4));
        println!(
            "| {n} | {read:.4} | {thin:.4} | {coarse:.4} | {fine:.4} | {}, {} |",
            a.added(),
            b.added()
        );
    }
}
