//! Six-node (quadratic) triangles, as finite-element codes with P2 elements read them: a node
//! on every edge of the linear mesh, placed on the region's exact boundary where the edge is a
//! boundary edge, so a circle's mesh is bounded by arcs of the circle, not by its chords.
use crate::io::UNKNOWN_PIECE;
use crate::types::{Mesh, VertexMarker};
use geometry::{DVec2, Region};

/// A mesh of six-node triangles: the linear mesh's vertices (same indices), then one node per
/// edge. Triangles list their corners counter-clockwise, then the nodes of their edges
/// (a, b), (b, c), (c, a): the order of Gmsh's element type 9 and VTK's quadratic triangle.
#[derive(Clone, Debug)]
pub struct Quadratic {
    /// Every node: the corners first, then one per edge.
    pub points: Vec<DVec2>,
    /// One marker per node; an edge's node is on the boundary where its edge is.
    pub markers: Vec<VertexMarker>,
    /// Corners a, b, c, then the nodes of edges ab, bc, ca.
    pub triangles: Vec<[u32; 6]>,
    /// The edges (low vertex, high vertex) in order: edge `e`'s node is the number of corners
    /// plus `e`.
    edges: Vec<(u32, u32)>,
    /// The linear mesh: its boundary edges and triangles' qualities go into the files too.
    linear: Mesh,
    /// The region whose boundary the boundary nodes were placed on, if one was given.
    region: Option<Region>,
}

impl Quadratic {
    /// The six-node mesh of `mesh`. With `region`, the node of each boundary edge is the point
    /// of the region's boundary nearest the edge's midpoint, on the piece its ends lie on (the
    /// arc's midpoint on a circle), unless that would take it more than a quarter of the edge
    /// away or fold its triangle (the Jacobian of a six-node triangle must stay positive);
    /// there, and everywhere without a region, the node is the edge's midpoint. O(M log M) for
    /// M triangles.
    ///
    /// ```
    /// use cvtmesh::{io::markers_from_topology, Mesh, Quadratic};
    /// use cvtmesh::geometry::{DVec2, Region};
    /// let mesh = |points: Vec<DVec2>, triangles: Vec<[u32; 3]>| Mesh {
    ///     markers: markers_from_topology(&points, &triangles),
    ///     points,
    ///     triangles,
    /// };
    /// // A square of two triangles: five edges, so 4 + 5 nodes, all on straight edges.
    /// let square = mesh(
    ///     vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)],
    ///     vec![[0, 1, 2], [0, 2, 3]],
    /// );
    /// let q = Quadratic::new(&square, None);
    /// assert_eq!((q.points.len(), q.triangles.len()), (9, 2));
    /// assert_eq!(q.points[q.triangles[0][3] as usize], DVec2::new(0.5, 0.0));
    /// assert!((q.area() - 1.0).abs() < 1e-15);
    /// // On the unit circle the boundary nodes lie on the circle itself.
    /// let circle = Region::builtin("circle")?;
    /// let ring: Vec<DVec2> = (0..6).map(|k| DVec2::from_angle(k as f64 * std::f64::consts::TAU / 6.0)).collect();
    /// let hexagon = mesh([vec![DVec2::ZERO], ring].concat(), (1..=6).map(|k| [0, k, k % 6 + 1]).collect());
    /// let q = Quadratic::new(&hexagon, Some(&circle));
    /// assert!(q.edge_node(1, 2).is_some_and(|m| (q.points[m as usize].length() - 1.0).abs() < 1e-12));
    /// assert!((q.area() - std::f64::consts::PI).abs() < (hexagon.area() - std::f64::consts::PI).abs() / 10.0);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn new(mesh: &Mesh, region: Option<&Region>) -> Quadratic {
        let corners = mesh.points.len();
        // Every edge once per triangle holding it, then the distinct ones with their count.
        let mut all: Vec<(u32, u32)> = mesh
            .triangles
            .iter()
            .flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)])
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        all.sort_unstable();
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(all.len() / 2 + 1);
        let mut on_boundary: Vec<bool> = Vec::with_capacity(all.len() / 2 + 1);
        for (k, &e) in all.iter().enumerate() {
            if edges.last() == Some(&e) {
                *on_boundary.last_mut().expect("pushed with the edge") = false;
            } else {
                edges.push(e);
                on_boundary.push(k + 1 == all.len() || all[k + 1] != e);
            }
        }
        let mut points = mesh.points.clone();
        let mut markers = mesh.markers.clone();
        for (&(a, b), &boundary) in edges.iter().zip(&on_boundary) {
            let (pa, pb) = (mesh.points[a as usize], mesh.points[b as usize]);
            points.push(0.5 * (pa + pb));
            markers.push(if boundary {
                edge_marker(mesh.markers[a as usize], mesh.markers[b as usize])
            } else {
                VertexMarker::Interior
            });
        }
        let node = |a: u32, b: u32| -> u32 {
            let e = edges
                .binary_search(&(a.min(b), a.max(b)))
                .expect("every edge of a triangle was listed");
            (corners + e) as u32
        };
        let triangles: Vec<[u32; 6]> = mesh
            .triangles
            .iter()
            .map(|&[a, b, c]| [a, b, c, node(a, b), node(b, c), node(c, a)])
            .collect();
        let mut q = Quadratic {
            points,
            markers,
            triangles,
            edges,
            linear: mesh.clone(),
            region: region.cloned(),
        };
        if let Some(region) = region {
            q.onto_boundary(mesh, region, &on_boundary);
        }
        q
    }

    /// Moves the node of every boundary edge onto `region`'s boundary where that keeps its
    /// triangle unfolded.
    fn onto_boundary(&mut self, mesh: &Mesh, region: &Region, on_boundary: &[bool]) {
        // The one triangle of each boundary edge, and the edge's place in it.
        let mut owner: Vec<Option<(usize, usize)>> = vec![None; self.edges.len()];
        for (t, tri) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let e = tri[3 + k] as usize - self.num_corners();
                if on_boundary[e] {
                    owner[e] = Some((t, 3 + k));
                }
            }
        }
        for (e, &(a, b)) in self.edges.iter().enumerate() {
            let Some((t, slot)) = owner[e] else {
                continue;
            };
            let node = self.num_corners() + e;
            let mid = self.points[node];
            let piece = [a, b].iter().find_map(|&v| match mesh.markers[v as usize] {
                VertexMarker::Boundary { piece, .. } if piece != UNKNOWN_PIECE => Some(piece),
                _ => None,
            });
            let hit = match piece {
                Some(piece) => region.project_onto_piece(mid, piece),
                None => region.project(mid),
            };
            let length = (mesh.points[a as usize] - mesh.points[b as usize]).length();
            if !(hit.point.is_finite() && hit.distance <= 0.25 * length) {
                continue;
            }
            let mut nodes = self.triangles[t].map(|v| self.points[v as usize]);
            nodes[slot] = hit.point;
            if unfolded(&nodes) {
                self.points[node] = hit.point;
                // The loop as the mesh numbers it (a mesh read from a file numbers its loops
                // by its own topology), the piece and place on it as the region has them.
                self.markers[node] = VertexMarker::Boundary {
                    loop_index: self.markers[node].loop_index().unwrap_or(hit.loop_index),
                    piece: hit.piece,
                    loop_param: hit.loop_param,
                };
            }
        }
    }

    /// The same mesh with the edge nodes `nodes` (each by its edge's ends) where they were
    /// given: what a six-node file had ([`crate::io::MeshFile::edge_nodes`]) for the edges a
    /// change left alone, so that writing it back keeps the file's curved edges. Edges the
    /// mesh does not have are passed over.
    ///
    /// ```
    /// use cvtmesh::{io::markers_from_topology, Mesh, Quadratic};
    /// use cvtmesh::geometry::DVec2;
    /// let points = vec![DVec2::ZERO, DVec2::X, DVec2::Y];
    /// let mesh = Mesh { markers: markers_from_topology(&points, &[[0, 1, 2]]), points, triangles: vec![[0, 1, 2]] };
    /// let bowed = DVec2::new(0.6, 0.6);
    /// let q = Quadratic::new(&mesh, None).keeping(&[([1, 2], bowed), ([0, 5], DVec2::ONE)]);
    /// assert_eq!(q.points[q.edge_node(2, 1).unwrap() as usize], bowed);
    /// assert_eq!(q.points[q.edge_node(0, 1).unwrap() as usize], DVec2::new(0.5, 0.0));
    /// ```
    pub fn keeping(mut self, nodes: &[([u32; 2], DVec2)]) -> Quadratic {
        for &([a, b], p) in nodes {
            if let Some(n) = self.edge_node(a, b) {
                self.points[n as usize] = p;
            }
        }
        self
    }

    /// The node on the edge between vertices `a` and `b`, if they share an edge.
    pub fn edge_node(&self, a: u32, b: u32) -> Option<u32> {
        self.edges
            .binary_search(&(a.min(b), a.max(b)))
            .ok()
            .map(|e| (self.num_corners() + e) as u32)
    }

    /// The three-node mesh this one was made from: its vertices are the corner nodes.
    pub fn linear(&self) -> &Mesh {
        &self.linear
    }

    /// The region the boundary nodes were placed on, if one was given.
    pub fn region(&self) -> Option<&Region> {
        self.region.as_ref()
    }

    /// The number of corner nodes, which are the linear mesh's vertices and come first.
    pub fn num_corners(&self) -> usize {
        self.linear.points.len()
    }

    /// The exact area the curved triangles cover (each triangle's Jacobian is quadratic, and
    /// its three-point edge-midpoint rule exact).
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let x = t.map(|v| self.points[v as usize]);
                (jacobian(&x, 0.5, 0.0) + jacobian(&x, 0.5, 0.5) + jacobian(&x, 0.0, 0.5)) / 6.0
            })
            .sum()
    }
}

/// The marker of a boundary edge's node before it is placed: on the loop of its ends.
fn edge_marker(a: VertexMarker, b: VertexMarker) -> VertexMarker {
    let loop_index = a.loop_index().or(b.loop_index()).unwrap_or(0);
    let piece = [a, b]
        .iter()
        .find_map(|m| match *m {
            VertexMarker::Boundary { piece, .. } => Some(piece),
            _ => None,
        })
        .unwrap_or(UNKNOWN_PIECE);
    VertexMarker::Boundary {
        loop_index,
        piece,
        loop_param: f64::NAN,
    }
}

/// The Jacobian determinant of the six-node triangle `x` (corners, then the nodes of edges
/// 01, 12, 20) at (ξ, η) of the reference triangle.
fn jacobian(x: &[DVec2; 6], xi: f64, eta: f64) -> f64 {
    let l = 1.0 - xi - eta;
    let d_xi = [
        1.0 - 4.0 * l,
        4.0 * xi - 1.0,
        0.0,
        4.0 * (l - xi),
        4.0 * eta,
        -4.0 * eta,
    ];
    let d_eta = [
        1.0 - 4.0 * l,
        0.0,
        4.0 * eta - 1.0,
        -4.0 * xi,
        4.0 * xi,
        4.0 * (l - eta),
    ];
    let (mut jx, mut je) = (DVec2::ZERO, DVec2::ZERO);
    for k in 0..6 {
        jx += x[k] * d_xi[k];
        je += x[k] * d_eta[k];
    }
    jx.perp_dot(je)
}

/// Whether the six-node triangle `x` keeps a positive Jacobian everywhere: the Jacobian is a
/// quadratic polynomial, and its Bézier coefficients (its values at the corners, and twice its
/// value at each edge's midpoint less the mean of that edge's corner values) bound it from
/// below.
fn unfolded(x: &[DVec2; 6]) -> bool {
    let v = [
        jacobian(x, 0.0, 0.0),
        jacobian(x, 1.0, 0.0),
        jacobian(x, 0.0, 1.0),
    ];
    let m = [
        jacobian(x, 0.5, 0.0),
        jacobian(x, 0.5, 0.5),
        jacobian(x, 0.0, 0.5),
    ];
    v.iter().all(|&j| j > 0.0) && (0..3).all(|k| 2.0 * m[k] - 0.5 * (v[k] + v[(k + 1) % 3]) > 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_triangles(points: Vec<DVec2>, triangles: Vec<[u32; 3]>) -> Mesh {
        Mesh {
            markers: crate::io::markers_from_topology(&points, &triangles),
            points,
            triangles,
        }
    }

    fn circle_mesh(k: usize) -> (Mesh, Region) {
        let region = Region::builtin("circle").unwrap();
        let ring: Vec<DVec2> = (0..k)
            .map(|i| DVec2::from_angle(i as f64 * std::f64::consts::TAU / k as f64))
            .collect();
        let tris = (1..=k as u32).map(|i| [0, i, i % k as u32 + 1]).collect();
        let mut mesh = from_triangles([vec![DVec2::ZERO], ring].concat(), tris);
        // The markers a mesher gives: every ring vertex on the circle's one piece.
        for (i, m) in mesh.markers.iter_mut().enumerate().skip(1) {
            *m = VertexMarker::Boundary {
                loop_index: 0,
                piece: 0,
                loop_param: (i - 1) as f64,
            };
        }
        (mesh, region)
    }

    #[test]
    fn every_edge_has_one_node_shared_by_its_triangles() {
        let (mesh, region) = circle_mesh(12);
        let q = Quadratic::new(&mesh, Some(&region));
        // 12 spokes and 12 rim edges.
        assert_eq!(q.points.len(), 13 + 24);
        assert_eq!(q.markers.len(), q.points.len());
        for (t, tri) in q.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                assert_eq!(Some(tri[3 + k]), q.edge_node(a, b), "triangle {t}");
            }
        }
        // Spoke nodes are midpoints, interior; rim nodes on the circle, on its piece.
        for i in 1..=12u32 {
            let s = q.edge_node(0, i).unwrap() as usize;
            assert_eq!(q.points[s], 0.5 * mesh.points[i as usize]);
            assert_eq!(q.markers[s], VertexMarker::Interior);
            let r = q.edge_node(i, i % 12 + 1).unwrap() as usize;
            assert!((q.points[r].length() - 1.0).abs() < 1e-12);
            assert!(matches!(
                q.markers[r],
                VertexMarker::Boundary { piece: 0, .. }
            ));
        }
    }

    #[test]
    fn curved_boundaries_cover_the_circle_far_better_than_chords() {
        for k in [6, 24, 96] {
            let (mesh, region) = circle_mesh(k);
            let pi = std::f64::consts::PI;
            let straight = Quadratic::new(&mesh, None);
            let curved = Quadratic::new(&mesh, Some(&region));
            assert!((straight.area() - mesh.area()).abs() < 1e-12);
            // The chord's error falls like k⁻², the parabola's like k⁻⁴.
            let (e1, e2) = ((mesh.area() - pi).abs(), (curved.area() - pi).abs());
            assert!(e2 < e1 * 4.0 / (k as f64), "k = {k}: {e1:e} against {e2:e}");
        }
    }

    #[test]
    fn a_node_that_would_fold_its_triangle_stays_on_the_chord() {
        // A flat triangle outside a chord of the circle, as along a hole: its edge's node,
        // moved out to the circle, would pass the opposite corner.
        let a = DVec2::from_angle(0.0);
        let b = DVec2::from_angle(1.2);
        let mid = 0.5 * (a + b);
        let mut mesh = from_triangles(vec![a, b, mid + 0.01 * mid.normalize()], vec![[0, 2, 1]]);
        for v in [0, 1] {
            mesh.markers[v] = VertexMarker::Boundary {
                loop_index: 0,
                piece: 0,
                loop_param: 0.0,
            };
        }
        let region = Region::builtin("circle").unwrap();
        let q = Quadratic::new(&mesh, Some(&region));
        let node = q.edge_node(0, 1).unwrap() as usize;
        assert_eq!(q.points[node], mid);
        assert!(q.area() > 0.0);
        // The same edge on a fatter triangle does move.
        let mut fat = mesh.clone();
        fat.points[2] = 3.0 * mid;
        let q = Quadratic::new(&fat, Some(&region));
        assert!((q.points[node].length() - 1.0).abs() < 1e-12);
        assert!(q.area() > 0.0);
    }

    #[test]
    fn every_format_reads_back_as_the_corners_mesh() {
        let (mesh, region) = circle_mesh(12);
        let q = Quadratic::new(&mesh, Some(&region));
        let dir = std::env::temp_dir().join(format!("cvtmesh-p2-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for name in ["q.msh", "q.node"] {
            let path = dir.join(name);
            crate::io::write_quadratic(&q, &path).unwrap();
            let back = crate::io::read_mesh(&path).unwrap();
            assert_eq!(back.points, mesh.points, "{name}");
            assert_eq!(back.triangles, mesh.triangles, "{name}");
        }
        // Triangle's .ele lists the node opposite each corner after the corners.
        let ele = std::fs::read_to_string(dir.join("q.ele")).unwrap();
        let first: Vec<u32> = ele
            .lines()
            .find(|l| l.starts_with("1 "))
            .unwrap()
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        let [a, b, c] = mesh.triangles[0];
        let node = |u, v| q.edge_node(u, v).unwrap() + 1;
        assert_eq!(
            first[1..],
            [a + 1, b + 1, c + 1, node(b, c), node(c, a), node(a, b)]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_jacobian_test_tells_folded_from_unfolded() {
        // The reference triangle, straight.
        let mut x = [
            DVec2::ZERO,
            DVec2::X,
            DVec2::Y,
            DVec2::new(0.5, 0.0),
            DVec2::new(0.5, 0.5),
            DVec2::new(0.0, 0.5),
        ];
        assert!(unfolded(&x));
        // A mild bulge outward keeps it unfolded.
        x[3] = DVec2::new(0.5, -0.1);
        assert!(unfolded(&x));
        // Pulled far inward, the Jacobian turns negative somewhere, which the test sees.
        x[3] = DVec2::new(0.5, 0.6);
        assert!(!unfolded(&x));
        let negative = (0..=20)
            .flat_map(|i| (0..=20 - i).map(move |j| (i as f64 / 20.0, j as f64 / 20.0)))
            .any(|(xi, eta)| jacobian(&x, xi, eta) < 0.0);
        assert!(negative);
    }
}
