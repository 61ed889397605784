//! The Voronoi dual of a triangle mesh: the control volumes and faces of vertex-centred finite
//! volumes (two-point flux), read off the triangles by the cotangent formulas.
use crate::{Mesh, MeshError};
use geometry::DVec2;
use rayon::prelude::*;

/// The Voronoi dual of a [`Mesh`], restricted to the mesh: each vertex's control volume (the
/// part of its Voronoi cell inside the mesh), and for each edge the dual face between its ends'
/// cells, as a two-point flux scheme needs them (flux across the face ≈ `faces[e]` /
/// `lengths[e]` × the difference of the two values).
///
/// Read off each triangle (a, b, c) with angles α, β, γ: the face of edge ab gains
/// |ab|/2 · cot γ (the signed distance from its midpoint to the circumcentre), and a's volume
/// (|ab|² cot γ + |ac|² cot β) / 8. On a Delaunay mesh every interior face is non-negative;
/// a negative one marks an edge whose opposite angles sum to more than π. A triangle obtuse
/// at a boundary edge puts its circumcentre outside the mesh and gives that boundary edge a
/// negative face. The volumes are signed parts of the triangles, so they always sum to the
/// mesh's area.
#[derive(Clone, Debug, PartialEq)]
pub struct Dual {
    /// Each vertex's control volume.
    pub volumes: Vec<f64>,
    /// The mesh's edges, each once, lower vertex first, sorted.
    pub edges: Vec<[u32; 2]>,
    /// Each edge's length.
    pub lengths: Vec<f64>,
    /// Each edge's dual face: the length of the common side of its ends' cells (for a
    /// boundary edge, from its midpoint to its triangle's circumcentre). Signed, as above.
    pub faces: Vec<f64>,
    /// Whether each edge lies on the boundary (has one triangle).
    pub on_boundary: Vec<bool>,
    /// Each triangle's circumcentre: the Voronoi vertices.
    pub circumcentres: Vec<DVec2>,
}

impl Dual {
    /// The dual of `mesh`. O(K log K) for the sort of its edges. A triangle that is not
    /// counter-clockwise with a positive area (a degenerate one read from a file) has no
    /// circumcentre: refused, naming it.
    ///
    /// ```
    /// use cvtmesh::{Dual, Mesh, VertexMarker};
    /// use cvtmesh::geometry::DVec2;
    /// // The unit square cut along a diagonal: two right triangles, circumcentres at the centre.
    /// let points = vec![DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
    /// let mesh = Mesh { markers: vec![VertexMarker::Interior; 4], points, triangles: vec![[0, 1, 2], [0, 2, 3]] };
    /// let dual = Dual::new(&mesh)?;
    /// // Each vertex owns the quarter of the square nearest to it.
    /// assert!(dual.volumes.iter().all(|&v| (v - 0.25).abs() < 1e-15));
    /// // The diagonal's two right angles put both circumcentres on it: no face between 0 and 2.
    /// let diagonal = dual.edges.iter().position(|&e| e == [0, 2]).unwrap();
    /// assert!(dual.faces[diagonal].abs() < 1e-15);
    /// // A side's face runs from its midpoint to the centre: half a side.
    /// let side = dual.edges.iter().position(|&e| e == [0, 1]).unwrap();
    /// assert!((dual.faces[side] - 0.5).abs() < 1e-15 && dual.on_boundary[side]);
    /// // Three vertices on a line: no circumcentre, refused by name.
    /// let flat = Mesh { triangles: vec![[0, 1, 2], [0, 2, 3]], points: vec![DVec2::ZERO, DVec2::X, 2.0 * DVec2::X, DVec2::Y], ..mesh };
    /// assert!(Dual::new(&flat).unwrap_err().to_string().contains("triangle 0"));
    /// # Ok::<(), cvtmesh::MeshError>(())
    /// ```
    pub fn new(mesh: &Mesh) -> Result<Dual, MeshError> {
        let p = &mesh.points;
        let area2 = |t: &[u32; 3]| {
            let v = t.map(|i| p.get(i as usize).copied().unwrap_or(DVec2::NAN));
            (v[1] - v[0]).perp_dot(v[2] - v[0])
        };
        if let Some(t) = mesh.triangles.par_iter().position_first(|t| {
            let a = area2(t);
            a.is_nan() || a <= 0.0
        }) {
            return Err(MeshError::BadRequest(format!(
                "triangle {t} ({:?}) has no positive area (degenerate, clockwise or out of \
                 range): the dual needs counter-clockwise triangles",
                mesh.triangles[t]
            )));
        }
        // Per triangle: its circumcentre, the cotangents of its angles at each corner, and the
        // squared lengths of its sides (side k opposite corner k).
        let parts: Vec<(DVec2, [f64; 3], [f64; 3])> = mesh
            .triangles
            .par_iter()
            .map(|t| {
                let v = t.map(|i| p[i as usize]);
                let twice_area = (v[1] - v[0]).perp_dot(v[2] - v[0]);
                let cot = std::array::from_fn(|k| {
                    let (u, w) = (v[(k + 1) % 3] - v[k], v[(k + 2) % 3] - v[k]);
                    u.dot(w) / u.perp_dot(w)
                });
                let side2 =
                    std::array::from_fn(|k| v[(k + 1) % 3].distance_squared(v[(k + 2) % 3]));
                let (b, c) = (v[1] - v[0], v[2] - v[0]);
                let centre = v[0]
                    + (b.perp() * c.length_squared() - c.perp() * b.length_squared())
                        / (2.0 * twice_area);
                (centre, cot, side2)
            })
            .collect();
        let mut volumes = vec![0.0; p.len()];
        let mut halves: Vec<([u32; 2], f64)> = Vec::with_capacity(3 * mesh.triangles.len());
        for (t, (_, cot, side2)) in mesh.triangles.iter().zip(&parts) {
            for k in 0..3 {
                let (a, b) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                // Side k (a–b) lies opposite corner k: its half-face is |ab|/2 · cot at k, and
                // each of its ends gets |ab|² cot / 8 of the triangle.
                let share = side2[k] * cot[k] / 8.0;
                volumes[a as usize] += share;
                volumes[b as usize] += share;
                halves.push(([a.min(b), a.max(b)], 0.5 * side2[k].sqrt() * cot[k]));
            }
        }
        halves.par_sort_unstable_by_key(|h| h.0);
        let (mut edges, mut faces, mut on_boundary) = (Vec::new(), Vec::new(), Vec::new());
        for run in halves.chunk_by(|x, y| x.0 == y.0) {
            edges.push(run[0].0);
            faces.push(run.iter().map(|h| h.1).sum());
            on_boundary.push(run.len() == 1);
        }
        let lengths = edges
            .iter()
            .map(|e| p[e[0] as usize].distance(p[e[1] as usize]))
            .collect();
        Ok(Dual {
            volumes,
            edges,
            lengths,
            faces,
            on_boundary,
            circumcentres: parts.into_iter().map(|x| x.0).collect(),
        })
    }

    /// The interior edges whose face is negative (opposite angles summing to more than π: the
    /// mesh is not Delaunay there) and the boundary edges whose face is negative (the triangle
    /// is obtuse at the edge, its circumcentre outside the mesh): where a two-point flux loses
    /// monotonicity. Counts (interior, boundary) below `-tol` times the edge's length.
    ///
    /// ```
    /// use cvtmesh::{Dual, Region};
    /// let mesh = cvtmesh::mesh(&Region::builtin("square_hole")?, 2000)?.mesh;
    /// assert_eq!(Dual::new(&mesh)?.negative_faces(1e-12), (0, 0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn negative_faces(&self, tol: f64) -> (usize, usize) {
        let bad = |e: usize| self.faces[e] < -tol * self.lengths[e];
        let inner = (0..self.edges.len())
            .filter(|&e| !self.on_boundary[e] && bad(e))
            .count();
        let outer = (0..self.edges.len())
            .filter(|&e| self.on_boundary[e] && bad(e))
            .count();
        (inner, outer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::VertexMarker;

    fn mesh(points: Vec<DVec2>, triangles: Vec<[u32; 3]>) -> Mesh {
        Mesh {
            markers: vec![VertexMarker::Interior; points.len()],
            points,
            triangles,
        }
    }

    /// A patch of the equilateral lattice: every inner vertex owns a regular hexagon of area
    /// (√3/2)·s², every inner face is s/√3, and the volumes sum to the mesh's area.
    #[test]
    fn an_equilateral_lattice_gives_hexagons() {
        let (n, s) = (8usize, 0.7);
        let h = s * 3f64.sqrt() / 2.0;
        let points: Vec<DVec2> = (0..n * n)
            .map(|k| {
                let (i, j) = ((k % n) as f64, (k / n) as f64);
                DVec2::new(s * (i + 0.5 * (j as usize % 2) as f64), h * j)
            })
            .collect();
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = |i: usize, j: usize| (j * n + i) as u32;
                if j % 2 == 0 {
                    triangles.push([v(i, j), v(i + 1, j), v(i, j + 1)]);
                    triangles.push([v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]);
                } else {
                    triangles.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
                    triangles.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                }
            }
        }
        let m = mesh(points, triangles);
        let dual = Dual::new(&m).unwrap();
        let total: f64 = dual.volumes.iter().sum();
        assert!((total - m.area()).abs() < 1e-12 * m.area());
        let inner = |v: usize| (2..n - 2).contains(&(v % n)) && (2..n - 2).contains(&(v / n));
        for v in (0..n * n).filter(|&v| inner(v)) {
            assert!(
                (dual.volumes[v] - h * s).abs() < 1e-12,
                "{v}: {}",
                dual.volumes[v]
            );
        }
        for (e, &[a, b]) in dual.edges.iter().enumerate() {
            if inner(a as usize) && inner(b as usize) {
                assert!((dual.faces[e] - s / 3f64.sqrt()).abs() < 1e-12);
                assert!((dual.lengths[e] - s).abs() < 1e-12);
            }
        }
        assert_eq!(dual.negative_faces(1e-12), (0, 0));
    }

    /// Rotating and translating the mesh changes neither volumes nor faces; the circumcentres
    /// move with it and lie at equal distances from their triangles' corners.
    #[test]
    fn the_dual_is_invariant_under_rigid_motions() {
        let region = geometry::Region::builtin("circle").unwrap();
        let points: Vec<DVec2> = region.polygonize(0.05).rings[0].points.clone();
        let m0 = {
            let mut pts = points.clone();
            pts.push(DVec2::new(0.1, -0.05));
            let c = (pts.len() - 1) as u32;
            let n = points.len() as u32;
            mesh(pts, (0..n).map(|i| [i, (i + 1) % n, c]).collect())
        };
        let (rot, shift) = (DVec2::from_angle(0.7), DVec2::new(3.0, -2.0));
        let m1 = mesh(
            m0.points.iter().map(|&p| rot.rotate(p) + shift).collect(),
            m0.triangles.clone(),
        );
        let (d0, d1) = (Dual::new(&m0).unwrap(), Dual::new(&m1).unwrap());
        assert_eq!(d0.edges, d1.edges);
        for (a, b) in d0
            .volumes
            .iter()
            .zip(&d1.volumes)
            .chain(d0.faces.iter().zip(&d1.faces))
        {
            assert!((a - b).abs() < 1e-12, "{a} {b}");
        }
        for (t, c) in m1.triangles.iter().zip(&d1.circumcentres) {
            let r = t.map(|v| m1.points[v as usize].distance(*c));
            assert!((r[0] - r[1]).abs() < 1e-10 * r[0] && (r[0] - r[2]).abs() < 1e-10 * r[0]);
        }
        let total: f64 = d1.volumes.iter().sum();
        assert!((total - m1.area()).abs() < 1e-12);
    }

    /// A non-Delaunay pair (a rhombus cut along its long diagonal) gives that diagonal a
    /// negative face; an obtuse triangle gives its long side a negative face.
    #[test]
    fn non_delaunay_and_obtuse_edges_have_negative_faces() {
        let pts = vec![
            DVec2::new(-1.0, 0.0),
            DVec2::new(0.0, -0.3),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 0.3),
        ];
        let d = Dual::new(&mesh(pts.clone(), vec![[0, 1, 2], [0, 2, 3]])).unwrap();
        let diagonal = d.edges.iter().position(|&e| e == [0, 2]).unwrap();
        assert!(d.faces[diagonal] < 0.0);
        assert_eq!(d.negative_faces(1e-12), (1, 0));
        let d = Dual::new(&mesh(pts, vec![[0, 1, 2]])).unwrap();
        assert_eq!(d.negative_faces(1e-12), (0, 1));
    }
}
