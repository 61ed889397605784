//! Ω_ε (`Region::expand`) of the annulus (a round hole of radius 0.4 in the unit disc) at
//! tolerances that polygonize the hole with 63–2000 vertices, for ε at half the hole's
//! radius, just below its closing (a remnant smaller than the tolerance) and just past it,
//! against the polygonization itself. Each edge's offset is cut by its neighbours' and the
//! crossings are found on a grid of candidate pairs: about linear in the vertex count at half
//! the radius and past the closing (where a convex hole whose edges get swallowed is cut by
//! each edge's half-plane, not left to an arrangement of offsets that all cross: 0.47 s at
//! 199 vertices and 14.8 s at 629 before). Just below the closing the remnant's edges all
//! share one cell of the candidate grid, so that column grows about quadratically (0.076 s at
//! 1987 vertices).
//! Run: `cargo bench -p cvtmesh-geometry --bench expand`. Prints a Markdown table of
//! best-of-5 wall-clock seconds.
use cvtmesh_geometry::Region;
mod common;
use common::best_of;

fn main() {
    let region = Region::builtin("annulus").expect("a built-in region");
    println!("| tolerance | hole vertices | polygonize (s) | ε = 0.2 (s) | ε = 0.3999 (s) | ε = 0.4001 (s) |");
    println!("| ---: | ---: | ---: | ---: | ---: | ---: |");
    for tol in [1e-3, 1e-4, 1e-5, 1e-6] {
        let (poly, p) = best_of(5, || region.polygonize(0.5 * tol));
        let mut row = format!("| {tol:e} | {} | {poly:.5} |", p.rings[1].points.len());
        for eps in [0.2, 0.3999, 0.4001] {
            let (t, _) = best_of(5, || region.expand(eps, tol));
            row += &format!(" {t:.5} |");
        }
        println!("{row}");
    }
}
