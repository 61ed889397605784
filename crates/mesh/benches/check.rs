//! The conformity check on structured meshes of the unit square, 10⁴–10⁶ vertices. Run:
//! `cargo bench -p cvtmesh-mesh --bench check [-- quick]` (`quick` stops at 10⁵). Prints a
//! Markdown table of best-of-3 wall-clock seconds; the check is O(K log K) (a distance query
//! per vertex, and per triangle only near the boundary), so the time per vertex should stay
//! about flat.
use cvtmesh_mesh::{check_conforming, Mesh, VertexMarker};
use geometry::{DVec2, LoopRole, Piece, Region};
use std::time::Instant;

/// The unit square split into m × m vertices, each grid square cut along its diagonal.
fn square_mesh(square: &Region, m: usize) -> Mesh {
    let at = |i: usize, j: usize| DVec2::new(i as f64, j as f64) / (m - 1) as f64;
    let mut points = Vec::with_capacity(m * m);
    let mut markers = Vec::with_capacity(m * m);
    for j in 0..m {
        for i in 0..m {
            let p = at(i, j);
            let (low, high) = (|k: usize| k == 0, |k: usize| k == m - 1);
            let marker = match (low(i) || high(i), low(j) || high(j)) {
                (true, true) => {
                    let corner = match (high(i), high(j)) {
                        (false, false) => 0,
                        (true, false) => 1,
                        (true, true) => 2,
                        (false, true) => 3,
                    };
                    VertexMarker::at_corner(square, corner)
                }
                (false, true) => VertexMarker::on_piece(square, p, if low(j) { 0 } else { 2 }),
                (true, false) => VertexMarker::on_piece(square, p, if high(i) { 1 } else { 3 }),
                (false, false) => VertexMarker::Interior,
            };
            points.push(p);
            markers.push(marker);
        }
    }
    let v = |i: usize, j: usize| (j * m + i) as u32;
    let mut triangles = Vec::with_capacity(2 * (m - 1) * (m - 1));
    for j in 0..m - 1 {
        for i in 0..m - 1 {
            triangles.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            triangles.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    Mesh {
        points,
        triangles,
        markers,
    }
}

fn main() {
    let quick = std::env::args().any(|a| a == "quick");
    let sides: &[usize] = if quick {
        &[100, 317]
    } else {
        &[100, 317, 1000]
    };
    let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| DVec2::new(x, y));
    let sides_of_square = (0..4)
        .map(|i| Piece::Line {
            a: c[i],
            b: c[(i + 1) % 4],
        })
        .collect();
    let square = Region::new("square", vec![(LoopRole::Outer, sides_of_square)], None)
        .expect("the unit square");
    println!("threads: {}", rayon::current_num_threads());
    println!("| vertices | triangles | check s | ns per vertex |");
    println!("|---|---|---|---|");
    for &m in sides {
        let mesh = square_mesh(&square, m);
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
