//! A size field given at the vertices of a mesh: the sizes an adaptive solver's error
//! estimate puts on its last mesh, Gmsh's background mesh, mmg's per-vertex sizes. The field
//! is linear on each triangle and is sampled once onto the background grid every sampled
//! field uses ([`SizeField::from_samples`]), so a method never searches the mesh.
use crate::index::Bvh;
use crate::predicates::closest_on_segment;
use crate::{DVec2, Region, SizeField, SizeFieldError};
use rayon::prelude::*;

/// How far (× the region's diameter) a point of the region may lie from a mesh of sizes
/// before the mesh is taken not to be the region's: the sag of a polygon inscribed in a
/// curved boundary is far below it (0.24 % of the diameter for a 32-gon in a circle).
pub(crate) const COVER_GAP: f64 = 0.05;

impl SizeField {
    /// h given at the vertices `points` of a triangle mesh (`triangles`: indices into
    /// `points`, either orientation) and linear on each triangle, sampled once onto a
    /// background grid over `region` (4 nodes per smallest size, 64 to 1024 per side) and
    /// interpolated by cubic B-splines there. Where the mesh does not reach (a polygon
    /// inscribed in a curved boundary, a coarser region), a point takes the value at the
    /// nearest point of the mesh.
    ///
    /// Refused, naming the problem: a size count that is not the vertex count, a size that
    /// is not positive and finite, a coordinate that is not finite, a triangle naming a vertex
    /// the mesh does not have, no triangle at all, or a mesh that leaves a point of the region
    /// more than 5 % of its diameter away (another region's mesh, or other units).
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region, SizeField};
    /// let square = Region::builtin("square_hole")?; // [-1, 1]² minus a disc
    /// // Two triangles over [-1, 1]², h = 0.02 + 0.01 (x + 1): linear, so kept exactly.
    /// let points = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| DVec2::new(x, y));
    /// let sizes: Vec<f64> = points.iter().map(|p| 0.02 + 0.01 * (p.x + 1.0)).collect();
    /// let h = SizeField::from_mesh(&square, &points, &[[0, 1, 2], [0, 2, 3]], &sizes)?;
    /// assert!((h.at(DVec2::new(0.7, -0.6)) - 0.037).abs() < 1e-12);
    /// assert!(SizeField::from_mesh(&square, &points, &[[0, 1, 4]], &sizes).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_mesh(
        region: &Region,
        points: &[DVec2],
        triangles: &[[u32; 3]],
        sizes: &[f64],
    ) -> Result<SizeField, SizeFieldError> {
        if sizes.len() != points.len() {
            return Err(SizeFieldError::MeshSizes {
                sizes: sizes.len(),
                vertices: points.len(),
            });
        }
        if let Some(vertex) = points.iter().position(|p| !p.is_finite()) {
            return Err(SizeFieldError::MeshPoint { vertex });
        }
        if let Some((vertex, &value)) = sizes
            .iter()
            .enumerate()
            .find(|(_, &h)| !(h > 0.0 && h < f64::INFINITY))
        {
            return Err(SizeFieldError::MeshSize { vertex, value });
        }
        for (triangle, t) in triangles.iter().enumerate() {
            if let Some(&vertex) = t.iter().find(|&&v| v as usize >= points.len()) {
                return Err(SizeFieldError::MeshTriangle {
                    triangle,
                    vertex,
                    vertices: points.len(),
                });
            }
        }
        if triangles.is_empty() {
            return Err(SizeFieldError::EmptyMesh);
        }
        let corners = |t: &[u32; 3]| t.map(|v| points[v as usize]);
        let boxes: Vec<(DVec2, DVec2)> = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = corners(t);
                (a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        let bvh = Bvh::build(&boxes, (0..triangles.len() as u32).collect());
        let value = |t: u32, w: [f64; 3]| {
            let tri = &triangles[t as usize];
            w[0] * sizes[tri[0] as usize]
                + w[1] * sizes[tri[1] as usize]
                + w[2] * sizes[tri[2] as usize]
        };
        // The value at `p` and the triangle it came from. Consecutive grid nodes mostly lie in
        // the same triangle: the last one is tried first, and the hierarchy searched only when
        // it does not hold the node.
        let at = |p: DVec2, last: Option<u32>| {
            if let Some(t) = last {
                let (w, d2) = nearest_in(corners(&triangles[t as usize]), p);
                if d2 == 0.0 {
                    return (value(t, w), t);
                }
            }
            // Nothing is found only when every distance overflows (coordinates near 1e154 or
            // beyond): NaN, which the check below reports.
            let Some((t, _)) =
                bvh.nearest(p, |t, _| nearest_in(corners(&triangles[t as usize]), p).1)
            else {
                return (f64::NAN, last.unwrap_or(0));
            };
            (
                value(t, nearest_in(corners(&triangles[t as usize]), p).0),
                t,
            )
        };
        // The region's point farthest from the mesh, over the region's inside grid.
        let (centres, _) = region.inside_grid();
        let gap = |p: DVec2| {
            bvh.nearest(p, |t, _| nearest_in(corners(&triangles[t as usize]), p).1)
                .map_or(f64::INFINITY, |(_, d2)| d2.sqrt())
        };
        let far = centres
            .par_iter()
            .map(|&p| (gap(p), p))
            .reduce(|| (0.0, DVec2::ZERO), |a, b| if b.0 > a.0 { b } else { a });
        let diameter = region.diameter();
        if far.0 > COVER_GAP * diameter {
            return Err(SizeFieldError::MeshMissesRegion {
                x: far.1.x,
                y: far.1.y,
                gap: far.0,
                diameter,
            });
        }
        let smallest = sizes.iter().copied().fold(f64::INFINITY, f64::min);
        let n = crate::size::grid_side(region, smallest, 1024);
        let field = SizeField::from_samples(region, n, |nodes| {
            let values = nodes
                .par_chunks(1024)
                .flat_map_iter(|chunk| {
                    let mut last = None;
                    chunk.iter().map(move |&p| {
                        let (v, t) = at(p, last);
                        last = Some(t);
                        v
                    })
                })
                .collect();
            Ok::<_, std::convert::Infallible>(values)
        })?;
        let field = field.unwrap_or_else(|never| match never {});
        // Sizes are positive, and a linear interpolant of them too, unless the arithmetic
        // overflowed on a mesh far out of scale: say so rather than hand on NaN.
        field.check(region)?;
        Ok(field)
    }
}

/// The barycentric weights of the point of triangle `[a, b, c]` nearest to `p`, and the
/// squared distance to it (0 inside). A flat triangle is its three edges.
fn nearest_in([a, b, c]: [DVec2; 3], p: DVec2) -> ([f64; 3], f64) {
    let area = (b - a).perp_dot(c - a);
    if area != 0.0 {
        let wa = (b - p).perp_dot(c - p) / area;
        let wb = (c - p).perp_dot(a - p) / area;
        let wc = 1.0 - wa - wb;
        if wa >= 0.0 && wb >= 0.0 && wc >= 0.0 {
            return ([wa, wb, wc], 0.0);
        }
    }
    let edges = [(0, 1, a, b), (1, 2, b, c), (2, 0, c, a)];
    let (i, j, _, t, d2) = edges
        .iter()
        .map(|&(i, j, u, v)| {
            let (q, t, d2) = closest_on_segment(u, v, p);
            (i, j, q, t, d2)
        })
        .min_by(|x, y| x.4.total_cmp(&y.4))
        .expect("three edges");
    let mut w = [0.0; 3];
    w[i] += 1.0 - t;
    w[j] += t;
    (w, d2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> (Vec<DVec2>, Vec<[u32; 3]>) {
        let points = [
            (-1.0, -1.0),
            (1.0, -1.0),
            (1.0, 1.0),
            (-1.0, 1.0),
            (0.0, 0.0),
        ]
        .map(|(x, y)| DVec2::new(x, y))
        .to_vec();
        // Four triangles around the centre, two of them clockwise.
        (points, vec![[0, 1, 4], [2, 1, 4], [2, 3, 4], [0, 4, 3]])
    }

    #[test]
    fn a_linear_field_is_kept_away_from_the_boundary() {
        let region = Region::builtin("square_hole").unwrap();
        let (points, triangles) = square();
        let h = |p: DVec2| 0.03 + 0.01 * p.x - 0.005 * p.y;
        let sizes: Vec<f64> = points.iter().map(|&p| h(p)).collect();
        let field = SizeField::from_mesh(&region, &points, &triangles, &sizes).unwrap();
        for p in [(0.7, 0.1), (-0.6, -0.8), (0.2, 0.75), (-0.75, 0.5)] {
            let p = DVec2::new(p.0, p.1);
            assert!(
                (field.at(p) - h(p)).abs() < 1e-12,
                "{p}: {} against {}",
                field.at(p),
                h(p)
            );
        }
    }

    #[test]
    fn a_point_off_the_mesh_takes_the_value_at_the_nearest_point_of_it() {
        // A mesh of [-0.9, 1] × [-1, 1], square_hole's square but a strip 0.1 wide (3.5 % of
        // the region's diameter) on its left.
        let region = Region::builtin("square_hole").unwrap();
        let points = [(-0.9, -1.0), (1.0, -1.0), (1.0, 1.0), (-0.9, 1.0)]
            .map(|(x, y)| DVec2::new(x, y))
            .to_vec();
        let h = |p: DVec2| 0.03 + 0.02 * p.x + 0.01 * p.y;
        let sizes: Vec<f64> = points.iter().map(|&p| h(p)).collect();
        let field =
            SizeField::from_mesh(&region, &points, &[[0, 1, 2], [0, 2, 3]], &sizes).unwrap();
        // Left of the mesh: the value on its edge x = -0.9 at the same height.
        for p in [(-0.97, 0.5), (-0.95, -0.7)] {
            let p = DVec2::new(p.0, p.1);
            let edge = h(DVec2::new(-0.9, p.y));
            assert!(
                (field.at(p) - edge).abs() < 1e-12,
                "{p}: {} against {edge}",
                field.at(p)
            );
        }
        assert_eq!(
            nearest_in([points[0], points[1], points[2]], DVec2::new(2.0, 0.0)).0,
            [0.0, 0.5, 0.5]
        );
    }

    #[test]
    fn a_mesh_that_leaves_the_region_far_from_it_is_not_the_regions() {
        let region = Region::builtin("square_hole").unwrap();
        let mesh_of = |x0: f64, shift: DVec2| {
            let points: Vec<DVec2> = [(x0, -1.0), (1.0, -1.0), (1.0, 1.0), (x0, 1.0)]
                .map(|(x, y)| shift + DVec2::new(x, y))
                .to_vec();
            let sizes = vec![0.05; 4];
            SizeField::from_mesh(&region, &points, &[[0, 1, 2], [0, 2, 3]], &sizes)
        };
        // Half the square: its left edge is 1 from the mesh, 35 % of the diameter.
        match mesh_of(0.0, DVec2::ZERO) {
            Err(SizeFieldError::MeshMissesRegion { x, gap, .. }) => {
                assert!(x < -0.99 && (gap - (0.0 - x)).abs() < 1e-12, "{x} {gap}")
            }
            other => panic!("{other:?}"),
        }
        // The whole square in other units (or another place): refused, saying so.
        let e = mesh_of(-1.0, DVec2::new(5.0, 5.0)).unwrap_err().to_string();
        assert!(
            e.contains("does not cover the region") && e.contains("same units"),
            "{e}"
        );
        // A strip of 0.13 (4.6 %) left out is carried; 0.15 (5.3 %) is not.
        assert!(mesh_of(-0.87, DVec2::ZERO).is_ok());
        assert!(mesh_of(-0.85, DVec2::ZERO).is_err());
    }

    #[test]
    fn bad_meshes_are_refused_naming_the_problem() {
        let region = Region::builtin("square_hole").unwrap();
        let (points, triangles) = square();
        let ok = [0.1; 5];
        let refuse = |t: &[[u32; 3]], s: &[f64], want: &str| {
            let e = SizeField::from_mesh(&region, &points, t, s)
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{e}");
        };
        refuse(&triangles, &[0.1; 4], "4 sizes for a mesh of 5 vertices");
        refuse(&triangles, &[0.1, 0.1, 0.0, 0.1, 0.1], "vertex 2 is 0");
        refuse(
            &triangles,
            &[0.1, f64::NAN, 0.1, 0.1, 0.1],
            "vertex 1 is NaN",
        );
        refuse(&[[0, 1, 7]], &ok, "triangle 0 refers to vertex 7");
        refuse(&[], &ok, "no triangles");
        let mut bad = points;
        bad[3].x = f64::INFINITY;
        let e = SizeField::from_mesh(&region, &bad, &triangles, &ok).unwrap_err();
        assert!(e.to_string().contains("vertex 3"), "{e}");
        // Finite but so far away that every squared distance overflows: an error, no panic.
        let far: Vec<DVec2> = [(1e200, 0.0), (2e200, 0.0), (1e200, 1e200)]
            .map(|(x, y)| DVec2::new(x, y))
            .to_vec();
        let e = SizeField::from_mesh(&region, &far, &[[0, 1, 2]], &[0.1; 3]).unwrap_err();
        assert!(e.to_string().contains("does not cover the region"), "{e}");
    }
}
