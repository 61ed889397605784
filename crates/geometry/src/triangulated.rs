//! A region given as a triangle mesh: the region its triangles cover, bounded by the edges of
//! exactly one triangle. This is how a user with only a mesh (a solver's last mesh, Gmsh's or
//! Triangle's output) names the region to mesh again, polish or measure against.
use crate::error::GeometryError;
use crate::formats::{key, marked_polygon_region, segment_key};
use crate::predicates::ring_signed_area;
use crate::region::Region;
use crate::types::LoopRole;
use glam::DVec2;

impl Region {
    /// The region covered by the triangles `triangles` (indices into `points`, in either
    /// orientation): each chain of edges that belong to exactly one triangle is a loop, an
    /// outer loop where the triangles lie to its left when it runs counter-clockwise, a hole
    /// otherwise, and several outer loops make several parts. Every boundary vertex where the
    /// boundary turns is a corner, as for the polygon formats ([`Region::with_corner_angle`]
    /// and [`Region::with_default_corners`] keep fewer). Where two loops touch at one vertex
    /// (two triangles meeting only at a corner), the boundary turns away from the triangles
    /// at each visit, so the loops are kept apart and then refused as touching by the region's
    /// own checks.
    ///
    /// Refused with an error naming the triangle or edge: a vertex index out of range, a point
    /// that is not finite, a triangle of zero area, an edge shared by more than two triangles,
    /// two triangles that lie on the same side of their common edge (they overlap), and
    /// whatever [`Region::from_loops`] refuses of the loops found.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// // A unit square of two triangles, with a square hole of side 1/3 in a 3 × 3 grid of
    /// // squares (eight squares, sixteen triangles).
    /// let points: Vec<DVec2> = (0..16).map(|i| DVec2::new((i % 4) as f64, (i / 4) as f64) / 3.0).collect();
    /// let mut triangles = Vec::new();
    /// for (i, j) in (0..3).flat_map(|j| (0..3).map(move |i| (i, j))).filter(|&c| c != (1, 1)) {
    ///     let v = 4 * j + i;
    ///     triangles.push([v, v + 1, v + 5]);
    ///     triangles.push([v, v + 5, v + 4]);
    /// }
    /// let r = Region::from_triangles("frame", &points, &triangles)?;
    /// assert_eq!(r.loops().len(), 2);
    /// assert!((r.area() - 8.0 / 9.0).abs() < 1e-12);
    /// assert!(!r.contains(DVec2::new(0.5, 0.5)));
    /// assert_eq!(r.with_default_corners().corners().len(), 8);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn from_triangles(
        name: &str,
        points: &[DVec2],
        triangles: &[[u32; 3]],
    ) -> Result<Region, GeometryError> {
        Self::from_triangles_marked(name, points, triangles, &[])
    }

    /// [`Region::from_triangles`] with the walls a mesh file numbers: each `(edge, marker)` of
    /// `walls` gives the boundary edge between those two vertices (either order) its marker,
    /// as a Gmsh file's physical curves or a Triangle `.poly`'s segment markers do, and the
    /// region's pieces take them ([`Region::piece_markers`]; 0 for a boundary edge `walls`
    /// does not name, none at all when `walls` is empty). A vertex where the marker changes is
    /// a corner, so a mesh of the region keeps the walls apart: remeshing keeps its boundary
    /// conditions. Pairs that are not boundary edges are ignored.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// // Two triangles of the unit square; its bottom edge is wall 7, the rest wall 9.
    /// let points = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from).to_vec();
    /// let triangles = [[0, 1, 2], [0, 2, 3]];
    /// let walls = [([0, 1], 7), ([1, 2], 9), ([2, 3], 9), ([3, 0], 9), ([0, 2], 5)];
    /// let r = Region::from_triangles_marked("square", &points, &triangles, &walls)?;
    /// let mut m = r.with_default_corners().piece_markers().unwrap().to_vec();
    /// m.sort();
    /// assert_eq!(m, [7, 9, 9, 9]);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn from_triangles_marked(
        name: &str,
        points: &[DVec2],
        triangles: &[[u32; 3]],
        walls: &[([u32; 2], i64)],
    ) -> Result<Region, GeometryError> {
        Self::from_triangles_pinned(name, points, triangles, walls, &[])
    }

    /// [`Region::from_triangles_marked`] with the vertices a mesh file marks on their own:
    /// each `(vertex, marker)` of `pinned` whose marker differs from the walls' on both sides
    /// of that boundary vertex (1 where `walls` is empty, Triangle's unmarked boundary) is a
    /// corner with that marker ([`Region::vertex_markers`]), as a Gmsh physical point or a
    /// `.node`'s boundary marker names a point where a solver pins a value; a vertex of a
    /// triangle inside with a nonzero marker is an embedded point
    /// ([`Region::embedded_points`]). Other pairs are ignored.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// // A 2 × 1 rectangle of four triangles, all walls 1; vertex 1, the middle of the
    /// // bottom, is marked 5.
    /// let points = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (0.0, 1.0)]
    ///     .map(DVec2::from)
    ///     .to_vec();
    /// let triangles = [[0, 1, 4], [0, 4, 5], [1, 2, 3], [1, 3, 4]];
    /// let walls = [([0, 1], 1), ([1, 2], 1), ([2, 3], 1), ([3, 4], 1), ([4, 5], 1), ([5, 0], 1)];
    /// let r = Region::from_triangles_pinned("r", &points, &triangles, &walls, &[(1, 5), (4, 1)])?;
    /// assert_eq!(r.vertex_markers(), &[(DVec2::new(1.0, 0.0), 5)]);
    /// assert_eq!(r.with_default_corners().corners().len(), 5);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn from_triangles_pinned(
        name: &str,
        points: &[DVec2],
        triangles: &[[u32; 3]],
        walls: &[([u32; 2], i64)],
        pinned: &[(u32, i64)],
    ) -> Result<Region, GeometryError> {
        let invalid = |message: String| GeometryError::Invalid {
            region: name.to_string(),
            message,
        };
        if triangles.is_empty() {
            return Err(invalid("the mesh has no triangles".into()));
        }
        // Every edge of every triangle, directed with the triangle counter-clockwise:
        // (low vertex, high vertex, from, triangle).
        let mut edges: Vec<(u32, u32, u32, u32)> = Vec::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            let mut p = [DVec2::ZERO; 3];
            for (k, &v) in tri.iter().enumerate() {
                p[k] = *points.get(v as usize).ok_or_else(|| {
                    invalid(format!(
                        "triangle {t} names vertex {v}, but the mesh has {} vertices",
                        points.len()
                    ))
                })?;
                if !p[k].is_finite() {
                    return Err(invalid(format!(
                        "vertex {v} (of triangle {t}) is at {}, not a finite point",
                        p[k]
                    )));
                }
            }
            let area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
            if area == 0.0 || !area.is_finite() {
                return Err(invalid(format!(
                    "triangle {t} ({}, {}, {}) has zero area",
                    tri[0], tri[1], tri[2]
                )));
            }
            let ccw = if area > 0.0 {
                *tri
            } else {
                [tri[0], tri[2], tri[1]]
            };
            for k in 0..3 {
                let (a, b) = (ccw[k], ccw[(k + 1) % 3]);
                edges.push((a.min(b), a.max(b), a, t as u32));
            }
        }
        edges.sort_unstable();
        // Boundary edges (from, to): the edges of one triangle.
        let mut boundary: Vec<(u32, u32)> = Vec::new();
        let mut i = 0;
        while i < edges.len() {
            let (lo, hi, from, t) = edges[i];
            let mut j = i + 1;
            while j < edges.len() && (edges[j].0, edges[j].1) == (lo, hi) {
                j += 1;
            }
            match j - i {
                1 => boundary.push((from, if from == lo { hi } else { lo })),
                2 if edges[i + 1].2 != from => {}
                2 => {
                    return Err(invalid(format!(
                        "triangles {t} and {} lie on the same side of their common edge \
                         {lo}–{hi}: they overlap",
                        edges[i + 1].3
                    )))
                }
                n => {
                    return Err(invalid(format!(
                        "edge {lo}–{hi} belongs to {n} triangles (at most two may share an edge)"
                    )))
                }
            }
            i = j;
        }
        let on_boundary: std::collections::HashSet<u32> =
            boundary.iter().flat_map(|&(a, b)| [a, b]).collect();
        let used: std::collections::HashSet<u32> = triangles.iter().flatten().copied().collect();
        let loops = boundary_loops(points, boundary)
            .into_iter()
            .map(|ring| {
                let role = if ring_signed_area(&ring) > 0.0 {
                    LoopRole::Outer
                } else {
                    LoopRole::Hole
                };
                (Some(role), ring)
            })
            .collect();
        let markers = (!walls.is_empty()).then(|| {
            walls
                .iter()
                .filter_map(|&([a, b], m)| {
                    let (a, b) = (points.get(a as usize)?, points.get(b as usize)?);
                    Some((segment_key(*a, *b), m))
                })
                .collect()
        });
        let on_loops = pinned
            .iter()
            .filter(|(v, _)| on_boundary.contains(v))
            .filter_map(|&(v, m)| Some((key(*points.get(v as usize)?), m)))
            .collect();
        // A marked vertex of a triangle inside (a physical point there) is a point the next
        // mesh keeps; one in no triangle (a file's stray node) is not.
        let inside: Vec<(DVec2, i64)> = pinned
            .iter()
            .filter(|&&(v, m)| m != 0 && used.contains(&v) && !on_boundary.contains(&v))
            .filter_map(|&(v, m)| Some((*points.get(v as usize)?, m)))
            .collect();
        let region = marked_polygon_region(name, name, loops, markers, &on_loops)?;
        let off = 1e-9 * region.diameter();
        let inside: Vec<(DVec2, i64)> = inside
            .into_iter()
            .filter(|&(p, _)| region.signed_distance(p) < -off)
            .collect();
        region.with_embedded_points(inside)
    }
}

/// The boundary edges `(from, to)` (each with the triangles on its left) chained into loops of
/// points. At a vertex where the boundary passes more than once, each visit leaves by the edge
/// reached first turning clockwise from the edge it came in by, which keeps each loop on the
/// side of its own triangles.
fn boundary_loops(points: &[DVec2], mut boundary: Vec<(u32, u32)>) -> Vec<Vec<DVec2>> {
    boundary.sort_unstable();
    let mut used = vec![false; boundary.len()];
    // The boundary edges leaving vertex v: boundary[first(v)..] while from == v.
    let first = |v: u32, b: &[(u32, u32)]| b.partition_point(|e| e.0 < v);
    let mut loops = Vec::new();
    for start in 0..boundary.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let mut ring = vec![points[boundary[start].0 as usize]];
        let (mut from, mut at) = boundary[start];
        loop {
            let back = points[from as usize] - points[at as usize];
            // The leaving edges still to walk, and the start edge, which closes the loop.
            let next = (first(at, &boundary)..boundary.len())
                .take_while(|&e| boundary[e].0 == at)
                .filter(|&e| !used[e] || e == start)
                .min_by(|&a, &b| {
                    let turn = |e: usize| {
                        let d = points[boundary[e].1 as usize] - points[at as usize];
                        clockwise_angle(back, d)
                    };
                    turn(a).total_cmp(&turn(b)).then(a.cmp(&b))
                });
            match next {
                Some(e) if e != start => {
                    used[e] = true;
                    ring.push(points[at as usize]);
                    (from, at) = boundary[e];
                }
                // Back at the start, or (for boundary edges that do not close, which a
                // consistent set of triangles cannot give) nowhere to go: the loop ends here.
                _ => break,
            }
        }
        loops.push(ring);
    }
    loops
}

/// The angle in (0, 2π] by which `d` lies clockwise of `from`.
fn clockwise_angle(from: DVec2, d: DVec2) -> f64 {
    let ccw = from.perp_dot(d).atan2(from.dot(d));
    let cw = -ccw;
    if cw <= 0.0 {
        cw + std::f64::consts::TAU
    } else {
        cw
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The n × m grid of unit squares with corners at integer points, two triangles each,
    /// the squares `skip` left out.
    fn grid(n: u32, m: u32, skip: &[(u32, u32)]) -> (Vec<DVec2>, Vec<[u32; 3]>) {
        let points = (0..=m)
            .flat_map(|j| (0..=n).map(move |i| DVec2::new(i as f64, j as f64)))
            .collect();
        let mut tris = Vec::new();
        for j in 0..m {
            for i in 0..n {
                if skip.contains(&(i, j)) {
                    continue;
                }
                let v = (n + 1) * j + i;
                tris.push([v, v + 1, v + n + 2]);
                tris.push([v, v + n + 2, v + n + 1]);
            }
        }
        (points, tris)
    }

    fn mesh_area(points: &[DVec2], tris: &[[u32; 3]]) -> f64 {
        tris.iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| points[v as usize]);
                0.5 * (b - a).perp_dot(c - a).abs()
            })
            .sum()
    }

    #[test]
    fn holes_islands_and_either_orientation() {
        // A 5 × 5 grid with a 3 × 3 hole, and in the hole an island of one square: two parts.
        let hole: Vec<(u32, u32)> = (1..4)
            .flat_map(|j| (1..4).map(move |i| (i, j)))
            .filter(|&c| c != (2, 2))
            .collect();
        let (points, mut tris) = grid(5, 5, &hole);
        // Half the triangles listed clockwise: orientation is the file's business.
        for t in tris.iter_mut().step_by(2) {
            t.swap(1, 2);
        }
        let r = Region::from_triangles("ring", &points, &tris).unwrap();
        assert_eq!(r.parts().len(), 2);
        assert_eq!(r.loops().len(), 3);
        assert_eq!(
            r.loops()
                .iter()
                .filter(|l| l.role == LoopRole::Hole)
                .count(),
            1
        );
        assert!((r.area() - mesh_area(&points, &tris)).abs() < 1e-12);
        assert!(r.contains(DVec2::new(2.5, 2.5)), "the island");
        assert!(!r.contains(DVec2::new(1.5, 2.5)), "the hole");
        // Corners only where the boundary turns: 4 + 4 + 4.
        assert_eq!(r.corners().len(), 12);
    }

    #[test]
    fn loops_that_touch_at_a_vertex_are_walked_apart() {
        // Two squares meeting at one corner, (1, 1): each loop keeps to its own square.
        let (points, tris) = grid(2, 2, &[(1, 0), (0, 1)]);
        let mut boundary = Vec::new();
        for t in &tris {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if !tris
                    .iter()
                    .any(|u| (0..3).any(|m| (u[m], u[(m + 1) % 3]) == (b, a)))
                {
                    boundary.push((a, b));
                }
            }
        }
        let loops = boundary_loops(&points, boundary);
        assert_eq!(loops.len(), 2, "{loops:?}");
        for ring in &loops {
            assert_eq!(ring.len(), 4, "{ring:?}");
            assert!((ring_signed_area(ring) - 1.0).abs() < 1e-12, "{ring:?}");
        }
        // As a region the two touch, which the region's checks refuse, naming the region.
        let e = Region::from_triangles("bow", &points, &tris).unwrap_err();
        assert!(e.to_string().contains("bow"), "{e}");
    }

    #[test]
    fn bad_meshes_are_named() {
        let (points, tris) = grid(2, 1, &[]);
        type Case = (Vec<DVec2>, Vec<[u32; 3]>, &'static str);
        let cases: Vec<Case> = vec![
            (points.clone(), vec![], "no triangles"),
            (points.clone(), vec![[0, 1, 99]], "vertex 99"),
            (
                {
                    let mut p = points.clone();
                    p[1].x = f64::NAN;
                    p
                },
                tris.clone(),
                "not a finite point",
            ),
            (points.clone(), vec![[0, 1, 2]], "zero area"),
            (
                points.clone(),
                {
                    let mut t = tris.clone();
                    t.push(t[0]);
                    t
                },
                "same side",
            ),
            (
                points.clone(),
                {
                    // A third triangle on edge 0–4 (the first square's diagonal).
                    let mut t = tris.clone();
                    t.push([0, 4, 2]);
                    t
                },
                "belongs to 3 triangles",
            ),
        ];
        for (p, t, want) in cases {
            let e = Region::from_triangles("m", &p, &t).unwrap_err();
            assert!(e.to_string().contains(want), "{want}: {e}");
        }
    }

    proptest! {
        /// Any grid with squares left out whose region is valid covers exactly the
        /// triangles' area, holds every triangle's centroid and no left-out square's centre.
        #[test]
        fn the_region_is_what_the_triangles_cover(
            n in 1u32..7,
            m in 1u32..7,
            skip in proptest::collection::vec((0u32..7, 0u32..7), 0..12),
            turn in 0.0f64..6.3,
        ) {
            let skip: Vec<(u32, u32)> = skip.into_iter().filter(|&(i, j)| i < n && j < m).collect();
            let (points, tris) = grid(n, m, &skip);
            prop_assume!(!tris.is_empty());
            // Rotated: nothing may depend on the axes.
            let rot = DVec2::from_angle(turn);
            let points: Vec<DVec2> = points.iter().map(|&p| rot.rotate(p)).collect();
            // Squares touching only at a corner make loops that touch, which a region refuses
            // (an error, never a panic); any other grid gives the region it covers.
            let present = |i: i64, j: i64| {
                (0..n as i64).contains(&i)
                    && (0..m as i64).contains(&j)
                    && !skip.contains(&(i as u32, j as u32))
            };
            let pinched = (0..=n as i64).any(|i| {
                (0..=m as i64).any(|j| {
                    let (a, b, c, d) =
                        (present(i - 1, j - 1), present(i, j - 1), present(i - 1, j), present(i, j));
                    (a && d && !b && !c) || (b && c && !a && !d)
                })
            });
            let result = Region::from_triangles("grid", &points, &tris);
            prop_assert!(pinched || result.is_ok(), "{:?}", result.err());
            if let Ok(r) = result {
                let area = mesh_area(&points, &tris);
                prop_assert!((r.area() - area).abs() < 1e-9 * area.max(1.0));
                for t in &tris {
                    let c = t.iter().map(|&v| points[v as usize]).sum::<DVec2>() / 3.0;
                    prop_assert!(r.contains(c));
                }
                for &(i, j) in &skip {
                    let c = rot.rotate(DVec2::new(i as f64 + 0.5, j as f64 + 0.5));
                    prop_assert!(!r.contains(c));
                }
            }
        }
    }
}
