//! A structured mesh of the unit square, for the conformity check's tests and bench.
use cvtmesh_mesh::{Mesh, VertexMarker};
use geometry::{DVec2, LoopRole, Piece, Region};

/// The unit square as a region, and its m × m structured mesh (each grid square cut along a
/// diagonal), with corner and side markers.
pub fn unit_square_mesh(m: usize) -> (Region, Mesh) {
    let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| DVec2::new(x, y));
    let sides = (0..4)
        .map(|i| Piece::Line {
            a: c[i],
            b: c[(i + 1) % 4],
        })
        .collect();
    let square =
        Region::new("square", vec![(LoopRole::Outer, sides)], None).expect("the unit square");
    let at = |i: usize, j: usize| DVec2::new(i as f64, j as f64) / (m - 1) as f64;
    let (mut points, mut markers) = (Vec::new(), Vec::new());
    for j in 0..m {
        for i in 0..m {
            let (ei, ej) = (i == 0 || i == m - 1, j == 0 || j == m - 1);
            markers.push(match (ei, ej) {
                (true, true) => VertexMarker::at_corner(
                    &square,
                    match (i == m - 1, j == m - 1) {
                        (false, false) => 0,
                        (true, false) => 1,
                        (true, true) => 2,
                        (false, true) => 3,
                    },
                ),
                (false, true) => {
                    VertexMarker::on_piece(&square, at(i, j), if j == 0 { 0 } else { 2 })
                }
                (true, false) => {
                    VertexMarker::on_piece(&square, at(i, j), if i == 0 { 3 } else { 1 })
                }
                (false, false) => VertexMarker::Interior,
            });
            points.push(at(i, j));
        }
    }
    let v = |i: usize, j: usize| (j * m + i) as u32;
    let mut triangles = Vec::new();
    for j in 0..m - 1 {
        for i in 0..m - 1 {
            triangles.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            triangles.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    let mesh = Mesh {
        points,
        triangles,
        markers,
    };
    (square, mesh)
}
