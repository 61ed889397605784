//! The conformity check on structured meshes of the unit square, 10⁴–10⁶ vertices. Run:
//! `cargo bench -p cvtmesh-mesh --bench check [-- quick]` (`quick` stops at 10⁵). Prints a
//! Markdown table of best-of-3 wall-clock seconds; the check is O(K log K) (a distance query
//! per vertex, and per triangle only near the boundary), so the time per vertex should stay
//! about flat.
use cvtmesh_mesh::check_conforming;
use std::time::Instant;

#[path = "../tests/support/square.rs"]
mod structured;

fn main() {
    let quick = std::env::args().any(|a| a == "quick");
    let sides: &[usize] = if quick {
        &[100, 317]
    } else {
        &[100, 317, 1000]
    };
    println!("threads: {}", rayon::current_num_threads());
    println!("| vertices | triangles | check s | ns per vertex |");
    println!("|---|---|---|---|");
    for &m in sides {
        let (square, mesh) = structured::unit_square_mesh(m);
        let mut best = f64::INFINITY;
        for _ in 0..3 {
            let t = Instant::now();
            check_conforming(&mesh, &square).expect("a structured mesh conforms");
            best = best.min(t.elapsed().as_secs_f64());
        }
        println!(
            "| {} | {} | {best:.4} | {:.0} |",
            mesh.points.len(),
            mesh.triangles.len(),
            1e9 * best / mesh.points.len() as f64
        );
    }
}
