//! Every boundary edge is told the piece (wall) it lies on, by every method.
use cvtmesh::geometry::{LoopRole, Region};
use cvtmesh::{DVec2, MeshRequest, Method};

#[test]
fn each_boundary_edge_lies_on_the_piece_it_is_given() {
    // A 4 × 1 channel with a round obstacle: inlet, wall, outlet, wall, and the circle.
    let outer = vec![
        DVec2::ZERO,
        DVec2::new(4.0, 0.0),
        DVec2::new(4.0, 1.0),
        DVec2::new(0.0, 1.0),
    ];
    let circle: Vec<DVec2> = (0..48)
        .map(|k| {
            DVec2::new(1.0, 0.5) + 0.2 * DVec2::from_angle(k as f64 * std::f64::consts::TAU / 48.0)
        })
        .collect();
    let channel = Region::from_loops(
        "channel",
        vec![(LoopRole::Outer, outer), (LoopRole::Hole, circle)],
    )
    .unwrap()
    .with_default_corners();
    // Four sides and the obstacle's one chain of segments.
    assert_eq!(channel.pieces().len(), 5);
    for method in ["ccvt", "refine", "distmesh"] {
        let m: Method = method.parse().unwrap();
        let mesh = m.run(&channel, &MeshRequest::points(600)).unwrap().mesh;
        let edges = mesh.boundary_edges();
        let pieces = mesh.boundary_pieces(&channel);
        assert_eq!(pieces.len(), edges.len());
        let mut count = [0usize; 5];
        // How far the farther end of an edge lies from piece j.
        let off = |e: &cvtmesh::BoundaryEdge, j: usize| {
            [e.a, e.b]
                .map(|v| {
                    let x = mesh.points[v as usize];
                    channel.pieces()[j].closest_point(x).0.distance(x)
                })
                .into_iter()
                .fold(0.0, f64::max)
        };
        for (e, &p) in edges.iter().zip(&pieces) {
            // On the straight sides exactly; on the obstacle's chain of 48 segments, which the
            // methods may follow as a curve through its vertices, within a hundredth of it.
            assert!(
                off(e, p) < 1e-2 * 0.2,
                "{method}: edge {e:?} is {} from piece {p}",
                off(e, p)
            );
            for j in (0..5).filter(|&j| j != p) {
                assert!(
                    off(e, p) < off(e, j),
                    "{method}: edge {e:?} nearer piece {j} than {p}"
                );
            }
            count[p] += 1;
        }
        // Edges of about the same length everywhere: the walls (length 4) hold about four
        // times the edges of the inlet and the outlet (length 1).
        let sides: Vec<usize> = (0..4).map(|j| count[j]).collect();
        let (short, long) = {
            let mut s = sides.clone();
            s.sort_unstable();
            (s[0] + s[1], s[2] + s[3])
        };
        let ratio = long as f64 / short as f64;
        assert!((3.0..5.0).contains(&ratio), "{method}: {sides:?}");
        assert!(count[4] > 0, "{method}: no edge on the obstacle");
    }
}
