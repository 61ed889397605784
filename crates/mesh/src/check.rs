//! The conformity check every method's mesh must pass (and every test asserts).
use crate::types::{maybe_below, rows_by_vertex, smallest_angle_cosines};
use crate::{Mesh, MeshError, VertexMarker};
use geometry::predicates::orient;
use geometry::{DVec2, Region};
use rayon::prelude::*;
use thiserror::Error;

/// The first way in which a mesh fails to conform to its region.
#[derive(Debug, Error, PartialEq)]
pub enum ConformityError {
    /// A coordinate is NaN or infinite.
    #[error("vertex {0} is not finite")]
    NotFinite(usize),
    /// A vertex lies outside the region.
    #[error("vertex {0} at ({1}, {2}) lies outside the region (distance {3:e})")]
    VertexOutside(usize, f64, f64, f64),
    /// A vertex marked as boundary is not on the boundary.
    #[error("vertex {0} is marked as a boundary vertex but lies {1:e} from the boundary")]
    MarkerOffBoundary(usize, f64),
    /// A triangle index is out of range, repeated, or the triangle is not CCW with positive area.
    #[error("triangle {0} is inverted or degenerate (area {1:e})")]
    Degenerate(usize, f64),
    /// Part of a triangle lies outside the region or inside a hole.
    #[error("triangle {0} reaches outside the region or into a hole near ({1}, {2})")]
    TriangleOutside(usize, f64, f64),
    /// An edge is shared by more than two triangles or twice in the same direction.
    #[error("edge ({0}, {1}) is not manifold")]
    NonManifold(u32, u32),
    /// A mesh-boundary edge has an interior vertex: the mesh does not reach the region boundary.
    #[error("boundary edge ({0}, {1}) of the mesh has an interior vertex")]
    OpenBoundary(u32, u32),
    /// A vertex belongs to no triangle.
    #[error("vertex {0} belongs to no triangle")]
    Orphan(usize),
    /// The mesh is not one piece with the region's number of holes (Euler characteristic).
    #[error("Euler characteristic {0}, expected {1} (overlapping or missing triangles)")]
    Topology(i64, i64),
    /// The marker list does not have one entry per vertex.
    #[error("{0} markers for {1} vertices")]
    MarkerCount(usize, usize),
    /// A mesh-boundary edge joins vertices on two different boundary loops (it spans a gap).
    #[error("boundary edge ({0}, {1}) joins two different boundary loops")]
    CrossLoopEdge(u32, u32),
    /// A boundary loop of the region carries fewer than 3 mesh vertices (e.g. a covered hole).
    #[error("boundary loop {0} carries {1} mesh vertices; a meshed loop needs at least 3")]
    LoopUncovered(usize, usize),
}

/// Vertices per run of the conformity check's parallel passes over edge rows.
const ROWS: usize = 4096;

/// Check that `mesh` conforms to `region`: one marker per vertex, finite vertices inside Ω̄,
/// boundary markers on the boundary, every boundary loop carrying at least 3 vertices, CCW
/// non-degenerate triangles whose interiors stay in Ω (sampled at the centroid and along edges
/// with the allowance a straight chord of a curved piece needs, [`CHORD_ALLOWANCE`] of the edge's length, of
/// the longest edge at the centroid, none at the centroid of a triangle whose corners lie on
/// two different loops), a manifold with no orphan vertices whose boundary
/// edges join boundary vertices of one loop, and the region's topology (V − E + F = 1 − holes).
///
/// ```
/// use cvtmesh::{check_conforming, ConformityError, Mesh, VertexMarker};
/// use cvtmesh::geometry::{DVec2, LoopRole, Piece, Region};
///
/// // The unit square, cut into four triangles at its centre.
/// let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| DVec2::new(x, y));
/// let sides = (0..4).map(|i| Piece::Line { a: c[i], b: c[(i + 1) % 4] }).collect();
/// let square = Region::new("square", vec![(LoopRole::Outer, sides)], None)?;
/// let mut points = c.to_vec();
/// points.push(DVec2::new(0.5, 0.5));
/// let mut markers: Vec<VertexMarker> =
///     (0..4).map(|i| VertexMarker::at_corner(&square, i)).collect();
/// markers.push(VertexMarker::Interior);
/// let triangles = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
/// let mut mesh = Mesh { points, triangles, markers };
/// check_conforming(&mesh, &square)?;
///
/// // A clockwise triangle is refused, and so is a hole in the mesh.
/// mesh.triangles[1] = [2, 1, 4];
/// assert!(matches!(check_conforming(&mesh, &square), Err(ConformityError::Degenerate(1, _))));
/// mesh.triangles.remove(1);
/// assert!(matches!(check_conforming(&mesh, &square), Err(ConformityError::OpenBoundary(..))));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn check_conforming(mesh: &Mesh, region: &Region) -> Result<(), ConformityError> {
    // Relative to the region's size, and to its coordinates' rounding: a region 0.03 across at
    // (10⁶, 10⁶) has vertices one rounding step (1.2e-10) off its boundary.
    let (lo, hi) = region.bbox();
    let magnitude = lo.abs().max(hi.abs()).max_element();
    let eps = 1e-9 * region.diameter() + 16.0 * f64::EPSILON * magnitude;
    if mesh.markers.len() != mesh.points.len() {
        return Err(ConformityError::MarkerCount(
            mesh.markers.len(),
            mesh.points.len(),
        ));
    }
    // Signed distances (or, deep inside, bounds on them) in parallel; the checks in index
    // order, so the first problem reported does not depend on the thread count.
    let sd = vertex_depths(mesh, region);
    let mut on_loop = vec![0usize; region.loops().len()];
    for (i, (p, &sd)) in mesh.points.iter().zip(&sd).enumerate() {
        if !p.is_finite() {
            return Err(ConformityError::NotFinite(i));
        }
        if sd > eps {
            return Err(ConformityError::VertexOutside(i, p.x, p.y, sd));
        }
        if mesh.markers[i].on_boundary() && sd.abs() > eps {
            let exact = region.signed_distance(*p).abs();
            return Err(ConformityError::MarkerOffBoundary(i, exact));
        }
        if sd.abs() <= eps {
            on_loop[region.project(*p).loop_index] += 1;
        }
    }
    if let Some((l, &n)) = on_loop.iter().enumerate().find(|(_, &n)| n < 3) {
        return Err(ConformityError::LoopUncovered(l, n));
    }
    let n = mesh.points.len() as u32;
    let order = LoopOrder::new(&mesh.markers, region.loops().len());
    // Each triangle on its own (in parallel, the first problem in triangle order reported).
    let bad = (0..mesh.triangles.len())
        .into_par_iter()
        .find_map_first(|t| {
            let tri = mesh.triangles[t];
            if tri.iter().any(|&v| v >= n)
                || tri[0] == tri[1]
                || tri[1] == tri[2]
                || tri[0] == tri[2]
            {
                return Some(ConformityError::Degenerate(t, 0.0));
            }
            let [a, b, c] = mesh.triangle(t);
            let area = 0.5 * (b - a).perp_dot(c - a);
            let longest = [a.distance(b), b.distance(c), c.distance(a)]
                .into_iter()
                .fold(0.0, f64::max);
            // Flat as rounding leaves three points on a line (its height 10⁻¹² of its longest
            // side), whatever its size: a well-shaped triangle 10⁻⁷ across, where fractures
            // nearly meet, is a triangle of the mesh as Triangle's is.
            if area <= 0.5e-12 * longest * longest {
                return Some(ConformityError::Degenerate(t, area));
            }
            // Signed distance is 1-Lipschitz and every point of the triangle lies within its
            // longest edge of each corner: a triangle that deep inside needs no query of its
            // own (all but the boundary layer).
            let deepest = tri
                .iter()
                .map(|&v| sd[v as usize])
                .fold(f64::INFINITY, f64::min);
            if deepest + longest < 0.0 {
                return None;
            }
            let centroid = (a + b + c) / 3.0;
            let sd_c = region.signed_distance(centroid);
            // The allowance of the triangle's longest edge: an ear of three boundary vertices
            // along a wiggling boundary is a sliver whose centroid lies as close to its chord
            // as the chord to the boundary.
            // Only an ear along one loop earns that allowance: a triangle reaching across
            // from one loop to another whose centroid is outside spans a gap narrower than the
            // chords' sag (a ring far thinner than the spacing).
            let loops = tri.map(|v| mesh.markers[v as usize].loop_index());
            let across = loops[0].is_some()
                && loops.iter().all(|l| l.is_some())
                && loops.iter().any(|&l| l != loops[0]);
            let allowance = if across {
                0.0
            } else {
                EDGE_ALLOWANCE * longest
            };
            if sd_c > eps + allowance {
                return Some(ConformityError::TriangleOutside(t, centroid.x, centroid.y));
            }
            // Signed distance is 1-Lipschitz: a triangle within its centroid's depth is inside.
            let reach = [a, b, c]
                .iter()
                .map(|v| v.distance(centroid))
                .fold(0.0, f64::max);
            if sd_c + reach < 0.0 {
                return None;
            }
            for k in 0..3 {
                let (u, w) = (tri[k], tri[(k + 1) % 3]);
                let (p, q) = (mesh.points[u as usize], mesh.points[w as usize]);
                let sag = |share: f64| {
                    let allowance = eps + share * (q - p).length();
                    (1..8)
                        .map(|s| p.lerp(q, s as f64 / 8.0))
                        .find(|&x| region.signed_distance(x) > allowance)
                };
                // A boundary edge, the mesh on its left, runs along its loop from u to w:
                // across a curved stretch with no corner it may sag as far as a chord does.
                let far = sag(EDGE_ALLOWANCE).and_then(|x| match order.follows(u, w) {
                    true => sag(chord_allowance(
                        region,
                        &mesh.markers[u as usize],
                        &mesh.markers[w as usize],
                    )),
                    false => Some(x),
                });
                if let Some(x) = far {
                    return Some(ConformityError::TriangleOutside(t, x.x, x.y));
                }
            }
            None
        });
    if let Some(e) = bad {
        return Err(e);
    }
    // Each vertex's outgoing edges in compressed rows, sorted by head: (head, position
    // 3·triangle + side). Sorting keeps a vertex of huge degree from costing its degree squared.
    let nv = mesh.points.len();
    let (start, mut out) = rows_by_vertex(&mesh.triangles, nv, |t, k| {
        (mesh.triangles[t][(k + 1) % 3], (3 * t + k) as u32)
    });
    // Rows sorted in parallel, over runs of whole rows.
    {
        let mut runs = Vec::with_capacity(nv / ROWS + 1);
        let mut rest = out.as_mut_slice();
        for first in (0..nv).step_by(ROWS) {
            let last = (first + ROWS).min(nv);
            let (run, tail) = rest.split_at_mut(start[last] - start[first]);
            runs.push((first..last, run));
            rest = tail;
        }
        runs.into_par_iter().for_each(|(rows, run)| {
            let base = start[rows.start];
            for a in rows {
                run[start[a] - base..start[a + 1] - base].sort_unstable();
            }
        });
    }
    let row = |a: usize| &out[start[a]..start[a + 1]];
    // An edge met twice in one direction, reported where its second copy comes in triangle
    // order (as a single pass over the triangles would find it).
    let repeated = (0..nv)
        .into_par_iter()
        .filter_map(|a| {
            row(a)
                .windows(2)
                .filter(|w| w[0].0 == w[1].0)
                .map(|w| (w[1].1, a as u32, w[1].0))
                .min()
        })
        .min();
    if let Some((_, a, b)) = repeated {
        return Err(ConformityError::NonManifold(a, b));
    }
    if let Some(i) = (0..nv).find(|&i| start[i] == start[i + 1]) {
        return Err(ConformityError::Orphan(i));
    }
    // The undirected edges counted, and the first problem in (tail, head) order found, over
    // runs of tails in parallel, so that the problem reported is always the same.
    let runs: Vec<Result<i64, ConformityError>> = (0..nv.div_ceil(ROWS))
        .into_par_iter()
        .map(|r| {
            let mut undirected = 0i64;
            for a in (r * ROWS..((r + 1) * ROWS).min(nv)).map(|a| a as u32) {
                for &(b, _) in row(a as usize) {
                    if row(b as usize).binary_search_by_key(&a, |e| e.0).is_err() {
                        undirected += 1;
                        let (ma, mb) = (mesh.markers[a as usize], mesh.markers[b as usize]);
                        if !ma.on_boundary() || !mb.on_boundary() {
                            return Err(ConformityError::OpenBoundary(a, b));
                        }
                        let loop_of = |p: u32| region.project(mesh.points[p as usize]).loop_index;
                        if loop_of(a) != loop_of(b) {
                            return Err(ConformityError::CrossLoopEdge(a, b));
                        }
                    } else if a < b {
                        undirected += 1;
                    }
                }
            }
            Ok(undirected)
        })
        .collect();
    let mut undirected = 0i64;
    for run in runs {
        undirected += run?;
    }
    let chi = mesh.points.len() as i64 - undirected + mesh.triangles.len() as i64;
    // Each part is a disc with holes, χ = 1 − holes; over the parts, 2·parts − loops.
    let expected = 2 * region.num_parts() as i64 - region.loops().len() as i64;
    if chi != expected {
        return Err(ConformityError::Topology(chi, expected));
    }
    Ok(())
}

/// From this many vertices [`vertex_depths`] bounds the deep ones from a grid.
const DEPTH_GRID_FROM: usize = 20_000;
/// The grid's cell side, in mean vertex spacings.
const DEPTH_CELL: f64 = 4.0;

/// Each vertex's signed distance to ∂`region` (NaN where not finite), or, where a grid cell
/// shows it lies deeper than the cell's diagonal, an upper bound on it: signed distance is
/// 1-Lipschitz, so no point of a cell lies deeper than its centre's distance plus half its
/// diagonal. Every test of the check reads the same from a bound below −diagonal as from the
/// distance (inside, off the boundary, deep enough for its triangles to need no query), and
/// the distance queries, deep ones the dearest, are left to the boundary layer and one per cell
/// (about 10⁶ → 10⁵ on a circle of 10⁶ vertices).
fn vertex_depths(mesh: &Mesh, region: &Region) -> Vec<f64> {
    let exact = |p: &DVec2| {
        if p.is_finite() {
            region.signed_distance(*p)
        } else {
            f64::NAN
        }
    };
    let n = mesh.points.len();
    if n < DEPTH_GRID_FROM {
        return mesh.points.par_iter().map(exact).collect();
    }
    let (lo, hi) = region.bbox();
    let side = DEPTH_CELL * (region.area() / n as f64).sqrt();
    let cells = ((hi - lo) / side).ceil().max(DVec2::ONE);
    let (nx, ny) = (cells.x as usize, cells.y as usize);
    let step = (hi - lo) / DVec2::new(nx as f64, ny as f64);
    let half_diagonal = 0.5 * step.length();
    let centre_depth: Vec<f64> = (0..nx * ny)
        .into_par_iter()
        .map(|k| {
            let c = lo + step * DVec2::new((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5);
            region.signed_distance(c)
        })
        .collect();
    mesh.points
        .par_iter()
        .map(|p| {
            let t = (*p - lo) / step;
            let inside_box = t.x >= 0.0 && t.y >= 0.0 && t.x < nx as f64 && t.y < ny as f64;
            if inside_box {
                let bound = centre_depth[t.y as usize * nx + t.x as usize] + half_diagonal;
                if bound < -2.0 * half_diagonal {
                    return bound;
                }
            }
            exact(p)
        })
        .collect()
}

/// Below this angle (degrees) [`slivers`] reports a triangle. A finite-element matrix on such
/// a triangle is ill-conditioned by about 1/sin of it; no method here leaves one on a region
/// that is wide enough for its spacing (refinement guarantees 20°, CCVT and DistMesh give
/// 25–40° there).
pub const SLIVER_ANGLE_DEG: f64 = 1.0;

/// Triangles with an angle under [`SLIVER_ANGLE_DEG`] that the boundary does not force: what
/// a method leaves where the region is about as narrow as the spacing (DistMesh on a strip
/// half a spacing wide puts every point on one side and fans across), or between holes that
/// nearly touch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slivers {
    /// How many triangles have such an angle.
    pub count: usize,
    /// The mesh's triangle count.
    pub triangles: usize,
    /// The smallest such angle, in degrees.
    pub smallest_deg: f64,
    /// The midpoint of the shortest side of the triangle with that angle (a needle's far apex
    /// says less about where it is than its short side).
    pub at: geometry::DVec2,
    /// The mesh's vertex count.
    pub points: usize,
}

impl std::fmt::Display for Slivers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // Three digits, unless they would round up to the bound (a 1° wedge's 0.9999999°).
        let mut smallest = format!("{:.2e}", self.smallest_deg);
        if smallest.parse::<f64>().is_ok_and(|a| a >= SLIVER_ANGLE_DEG) {
            smallest = self.smallest_deg.to_string();
        }
        write!(
            f,
            "{} of {} triangles have an angle under {SLIVER_ANGLE_DEG}° (the smallest {smallest}° near ({:.6}, {:.6})): \
             the region is about as narrow as the spacing there at K = {}, or points the mesh \
             must keep (corners, embedded points, the vertices of a line inside) lie that \
             close; ask for more points, simplify a digitized boundary or line to the mesh's \
             scale (simplify \"auto\", --simplify auto), or use another method",
            self.count, self.triangles, self.at.x, self.at.y, self.points
        )
    }
}

/// The triangles of `mesh` with an angle under [`SLIVER_ANGLE_DEG`], if there are any, except
/// those whose smallest angle lies between two boundary edges: the boundary itself is that
/// sharp there (a wedge's tip), and every mesh of it has that angle. O(M).
///
/// ```
/// use cvtmesh::{slivers, Mesh, VertexMarker};
/// use cvtmesh::geometry::DVec2;
/// // A flat triangle with an interior vertex on its long side's apex: its 0.11° angles lie
/// // between a boundary edge and an inner one.
/// let p = |x: f64, y: f64| DVec2::new(x, y);
/// let mesh = Mesh {
///     points: vec![p(0.0, 0.0), p(1.0, 0.0), p(0.5, 0.001), p(0.5, 1.0)],
///     triangles: vec![[0, 1, 2], [0, 2, 3], [2, 1, 3]],
///     markers: vec![VertexMarker::Interior; 4],
/// };
/// let s = slivers(&mesh).expect("a 0.11° triangle");
/// assert_eq!((s.count, s.triangles), (1, 3));
/// assert!((s.smallest_deg - 0.001f64.atan2(0.5).to_degrees()).abs() < 1e-9);
/// // Alone, the same triangle's angles lie between its boundary edges: forced, not reported.
/// let alone = Mesh { triangles: vec![[0, 1, 2]], ..mesh };
/// assert_eq!(slivers(&alone), None);
/// ```
pub fn slivers(mesh: &Mesh) -> Option<Slivers> {
    slivers_in(mesh, &smallest_angle_cosines(mesh), &|_, _| false)
}

/// [`slivers`] of `mesh` as a mesh of `region`, where the input forces small angles as well:
/// a triangle is left out when its shortest side runs between two segments of the input (the
/// embedded lines' segments and the straight walls) that share an end, and its smallest angle
/// is no smaller than theirs there. Two fractures crossing at half a degree, or a crack
/// meeting a wall at a grazing angle, give every mesh that keeps them such triangles, as
/// Triangle's refinement leaves them (its exemption for small input angles). O(M) plus, for
/// each triangle under the bound, a pass over the input's segments.
///
/// ```
/// use cvtmesh::geometry::{DVec2, EmbeddedLine, LoopRole, Region};
/// use cvtmesh::{slivers, slivers_in_region, MeshRequest, Method};
/// // Two cracks crossing at half a degree in the unit square.
/// let crack = |d: DVec2, marker| EmbeddedLine {
///     points: vec![DVec2::splat(0.5) - 0.4 * d, DVec2::splat(0.5) + 0.4 * d],
///     marker,
/// };
/// let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from).to_vec();
/// let across = DVec2::from_angle(0.5f64.to_radians());
/// let region = Region::from_loops("cracks", vec![(LoopRole::Outer, square)])?
///     .with_embedded_lines([crack(DVec2::X, 1), crack(across, 2)])?;
/// let mesh = Method::Refine.run(&region, &MeshRequest::points(1000))?.mesh;
/// // Delaunay refinement leaves the crossing's angle and no smaller one.
/// assert!((mesh.min_angle_deg() - 0.5).abs() < 1e-6);
/// assert!(slivers(&mesh).is_some());
/// assert_eq!(slivers_in_region(&mesh, &region), None);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn slivers_in_region(mesh: &Mesh, region: &Region) -> Option<Slivers> {
    slivers_of_input(mesh, &smallest_angle_cosines(mesh), region)
}

/// [`slivers_in_region`] from the triangles' cosines.
fn slivers_of_input(mesh: &Mesh, cos: &[f64], region: &Region) -> Option<Slivers> {
    // Only a mesh with slivers pays for the input's segments.
    let plain = slivers_in(mesh, cos, &|_, _| false)?;
    let segments: Vec<(DVec2, DVec2)> = region
        .embedded_lines()
        .iter()
        .flat_map(|l| l.segments())
        .chain(region.pieces().iter().filter_map(|p| match p {
            geometry::Piece::Line { a, b } => Some((*a, *b)),
            _ => None,
        }))
        .collect();
    if segments.is_empty() {
        return Some(plain);
    }
    let off = 1e-9 * region.diameter();
    let on = |p: DVec2| {
        segments.iter().filter(move |&&(a, b)| {
            geometry::predicates::closest_on_segment(a, b, p)
                .0
                .distance(p)
                <= off
        })
    };
    // The angle at a shared end of two segments, in degrees.
    let between = |(a, b): (DVec2, DVec2), (c, d): (DVec2, DVec2)| -> Option<f64> {
        let (apex, u, v) = if a == c {
            (a, b, d)
        } else if a == d {
            (a, b, c)
        } else if b == c {
            (b, a, d)
        } else if b == d {
            (b, a, c)
        } else {
            return None;
        };
        let (u, v) = (u - apex, v - apex);
        Some(u.perp_dot(v).abs().atan2(u.dot(v)).to_degrees())
    };
    slivers_in(mesh, cos, &|t, angle| {
        let p = mesh.triangle(t);
        let k = (0..3)
            .min_by(|&i, &j| {
                let side = |i: usize| p[i].distance_squared(p[(i + 1) % 3]);
                side(i).total_cmp(&side(j))
            })
            .expect("three sides");
        let (u, v) = (p[k], p[(k + 1) % 3]);
        on(u).any(|&s| {
            on(v).any(|&r| {
                s != r && between(s, r).is_some_and(|input| angle >= input * (1.0 - 1e-9))
            })
        })
    })
}

/// The mesh's smallest angle in degrees ([`Mesh::min_angle_deg`]) and its slivers as a mesh
/// of `region` ([`slivers_in_region`]), from one pass over the triangles' cosines instead of
/// one each (a command reports both).
///
/// ```
/// use cvtmesh::{min_angle_and_slivers, slivers, Mesh, Region, VertexMarker};
/// use cvtmesh::geometry::{DVec2, LoopRole};
/// let p = |x: f64, y: f64| DVec2::new(x, y);
/// let mesh = Mesh {
///     points: vec![p(0.0, 0.0), p(1.0, 0.0), p(0.5, 0.001), p(0.5, 1.0)],
///     triangles: vec![[0, 1, 2], [0, 2, 3], [2, 1, 3]],
///     markers: vec![VertexMarker::Interior; 4],
/// };
/// let outline = vec![p(0.0, 0.0), p(1.0, 0.0), p(0.5, 1.0)];
/// let region = Region::from_loops("triangle", vec![(LoopRole::Outer, outline)])?;
/// let (angle, flat) = min_angle_and_slivers(&mesh, &region);
/// assert_eq!(angle, mesh.min_angle_deg());
/// assert_eq!(flat, slivers(&mesh));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn min_angle_and_slivers(mesh: &Mesh, region: &Region) -> (f64, Option<Slivers>) {
    let cos = smallest_angle_cosines(mesh);
    (
        mesh.min_angle_deg_in(&cos),
        slivers_of_input(mesh, &cos, region),
    )
}

/// [`slivers`] from the triangles' cosines ([`smallest_angle_cosines`]), a triangle also left
/// out where `forced(triangle, its smallest angle in degrees)` says the input has that angle.
fn slivers_in(
    mesh: &Mesh,
    cos: &[f64],
    forced: &(dyn Fn(usize, f64) -> bool + Sync),
) -> Option<Slivers> {
    // (angle, triangle, corner at the angle) of every triangle with an angle under the bound;
    // a triangle with a zero-length side has no angle (NaN) and counts as 0°.
    // The angles themselves only of triangles whose smallest angle's cosine says they may be
    // under it (a few, against 2·10⁶ at a 10⁶-vertex mesh's end).
    let flat_cos = SLIVER_ANGLE_DEG.to_radians().cos();
    let flat: Vec<(f64, usize, usize)> = maybe_below(cos, |_| flat_cos)
        .into_par_iter()
        .filter_map(|t| {
            let p = mesh.triangle(t);
            let (i, a) = (0..3)
                .map(|i| {
                    let a = crate::types::corner_angle_deg(p, i);
                    (i, if a.is_nan() { 0.0 } else { a })
                })
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .expect("three corners");
            (a < SLIVER_ANGLE_DEG).then_some((a, t, i))
        })
        .collect();
    if flat.is_empty() {
        return None;
    }
    let boundary: std::collections::HashSet<(u32, u32)> = mesh
        .boundary_edges()
        .iter()
        .map(|e| (e.a.min(e.b), e.a.max(e.b)))
        .collect();
    let on_boundary = |a: u32, b: u32| boundary.contains(&(a.min(b), a.max(b)));
    let unforced: Vec<&(f64, usize, usize)> = flat
        .iter()
        .filter(|&&(angle, t, i)| {
            let v = mesh.triangles[t];
            let wedge = on_boundary(v[i], v[(i + 1) % 3]) && on_boundary(v[i], v[(i + 2) % 3]);
            !(wedge || forced(t, angle))
        })
        .collect();
    let &&(smallest_deg, worst, _) = unforced.iter().min_by(|x, y| x.0.total_cmp(&y.0))?;
    let p = mesh.triangle(worst);
    let (i, _) = (0..3)
        .map(|i| (i, p[i].distance_squared(p[(i + 1) % 3])))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .expect("three sides");
    Some(Slivers {
        count: unforced.len(),
        triangles: mesh.triangles.len(),
        smallest_deg,
        at: 0.5 * (p[i] + p[(i + 1) % 3]),
        points: mesh.num_vertices(),
    })
}

/// How `mesh` stands against `region` for measuring it: `Ok(None)` where it conforms,
/// `Ok(Some(e))` where it only nearly does (a file's rounded coordinates, a polygon inscribed
/// in a curve), and [`MeshError::BadRequest`] where it is no mesh of the region: more than
/// half the region's area left uncovered, or more than half the mesh's area outside the
/// region (by each triangle's centroid; its α would be below 0, its ν inf).
///
/// ```
/// use cvtmesh::{measurable, Region};
/// let disc = Region::builtin("circle")?;
/// let mesh = cvtmesh::mesh(&disc, 200)?.mesh;
/// assert!(measurable(&mesh, &disc)?.is_none());
/// let e = measurable(&mesh, &Region::builtin("lake")?).unwrap_err();
/// assert!(e.to_string().contains("not a mesh of that region"), "{e}");
/// // A mesh of the same area as the disc, shifted off most of it.
/// let mut off = mesh.clone();
/// off.points.iter_mut().for_each(|p| p.x += 1.5);
/// let e = measurable(&off, &disc).unwrap_err();
/// assert!(e.to_string().contains("not a mesh of that region"), "{e}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn measurable(mesh: &Mesh, region: &Region) -> Result<Option<ConformityError>, MeshError> {
    let Err(e) = check_conforming(mesh, region) else {
        return Ok(None);
    };
    let (covered, whole) = (mesh.area(), region.area());
    let inside: f64 = (0..mesh.triangles.len())
        .map(|t| mesh.triangle(t))
        .filter(|q| region.contains((q[0] + q[1] + q[2]) / 3.0))
        .map(|q| 0.5 * orient(q[0], q[1], q[2]).abs())
        .sum();
    if whole - inside > 0.5 * whole || covered - inside > 0.5 * covered {
        return Err(MeshError::BadRequest(format!(
            "the mesh covers an area of {covered:.6e}, {inside:.6e} of it inside region '{}' \
             of area {whole:.6e}: not a mesh of that region ({e})",
            region.name()
        )));
    }
    Ok(Some(e))
}

/// How far, as a share of its length, an edge of a conforming mesh may stray outside the
/// region: the sagitta of a chord across a stretch of curved boundary, about 60° of a circle
/// (a chord across an arc of θ strays (1 − cos(θ/2)) / (2 sin(θ/2)) of its length).
pub const EDGE_ALLOWANCE: f64 = 0.13;

/// How far, as a share of its length, a boundary edge between two boundary vertices that
/// follow each other along their loop may stray outside the region where no corner lies
/// between them ([`chord_allowance`]): 0.3 lets a hole's boundary vertices lie as far apart
/// as the corners of a triangle inscribed in it (θ = 120°, 0.289), a coarse mesh of a round
/// hole as every mesher gives one, where [`EDGE_ALLOWANCE`] would refuse a hexagon in
/// square_hole's hole (K = 40) and the superellipse's hole at some K (120–140) but not at
/// others (100, 150). Every other
/// edge keeps [`EDGE_ALLOWANCE`]: an edge over a hole or across a gap between two parts of one
/// loop is not a chord of the boundary.
pub const CHORD_ALLOWANCE: f64 = 0.3;

/// The allowance, as a share of its length, of the boundary edge from the boundary vertex
/// marked `a` to the one marked `b` that follows it along their loop: [`CHORD_ALLOWANCE`]
/// where no corner of the region lies between them, else [`EDGE_ALLOWANCE`] (a chord that
/// skips a corner cuts across it, as a skipped reflex corner of the lake does).
///
/// ```
/// use cvtmesh::{chord_allowance, VertexMarker, CHORD_ALLOWANCE, EDGE_ALLOWANCE};
/// use cvtmesh::geometry::{DVec2, Region};
/// let disc = Region::builtin("circle")?;
/// let at = |t: f64| VertexMarker::on_piece(&disc, DVec2::from_angle(t), 0);
/// assert_eq!(chord_allowance(&disc, &at(0.0), &at(2.0)), CHORD_ALLOWANCE);
/// let l = Region::from_loops("L", vec![(cvtmesh::geometry::LoopRole::Outer,
///     [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)].map(|(x, y)| DVec2::new(x, y)).to_vec())])?;
/// // From (2, 0.5) to (0.5, 2) the chord skips the corners (2, 1), (1, 1) and (1, 2).
/// let on = |x: f64, y: f64| VertexMarker::on_piece(&l, DVec2::new(x, y), l.project(DVec2::new(x, y)).piece);
/// assert_eq!(chord_allowance(&l, &on(2.0, 0.5), &on(0.5, 2.0)), EDGE_ALLOWANCE);
/// assert_eq!(chord_allowance(&l, &on(0.5, 0.0), &on(1.5, 0.0)), CHORD_ALLOWANCE);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn chord_allowance(region: &Region, a: &VertexMarker, b: &VertexMarker) -> f64 {
    let (Some(l), Some(pa), Some(pb)) = (a.loop_index(), a.loop_param(), b.loop_param()) else {
        return EDGE_ALLOWANCE;
    };
    let length = region.loops().get(l).map_or(f64::NAN, |lp| lp.length);
    if b.loop_index() != Some(l) || !(pa.is_finite() && pb.is_finite() && length > 0.0) {
        return EDGE_ALLOWANCE;
    }
    let tol = 1e-12 * length;
    let span = (pb - pa).rem_euclid(length);
    let skips = region.corners().iter().any(|c| {
        let at = (c.loop_param - pa).rem_euclid(length);
        c.loop_index == l && at > tol && at < span - tol
    });
    if skips {
        EDGE_ALLOWANCE
    } else {
        CHORD_ALLOWANCE
    }
}

/// Each boundary vertex's rank along its loop (by loop parameter), to tell the boundary edges
/// that join neighbours along a loop.
struct LoopOrder {
    rank: Vec<u32>,
    loop_of: Vec<u32>,
    count: Vec<u32>,
}

impl LoopOrder {
    fn new(markers: &[VertexMarker], loops: usize) -> LoopOrder {
        let mut by_loop: Vec<Vec<(f64, u32)>> = vec![Vec::new(); loops];
        for (v, m) in markers.iter().enumerate() {
            if let (Some(l), Some(t)) = (m.loop_index(), m.loop_param()) {
                if l < loops && t.is_finite() {
                    by_loop[l].push((t, v as u32));
                }
            }
        }
        let mut rank = vec![u32::MAX; markers.len()];
        let mut loop_of = vec![u32::MAX; markers.len()];
        let mut count = vec![0; loops];
        for (l, vs) in by_loop.iter_mut().enumerate() {
            vs.sort_by(|x, y| x.0.total_cmp(&y.0));
            count[l] = vs.len() as u32;
            for (r, &(_, v)) in vs.iter().enumerate() {
                rank[v as usize] = r as u32;
                loop_of[v as usize] = l as u32;
            }
        }
        LoopOrder {
            rank,
            loop_of,
            count,
        }
    }

    /// Whether boundary vertex `w` comes right after `u` along their loop.
    fn follows(&self, u: u32, w: u32) -> bool {
        let (lu, lw) = (self.loop_of[u as usize], self.loop_of[w as usize]);
        lu != u32::MAX
            && lu == lw
            && (self.rank[u as usize] + 1) % self.count[lu as usize] == self.rank[w as usize]
    }
}

/// Below this share of the region's area covered, [`short_coverage`] reports a mesh. The
/// paper's coarsest mesh, a disc with 12 boundary vertices, covers 95.5 %.
pub const MIN_COVERAGE: f64 = 0.9;

/// A mesh that conforms (every triangle in the region) but leaves out a band along a curved
/// boundary whose vertices lie far apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShortCoverage {
    /// The share of the region's area the triangles cover.
    pub share: f64,
    /// The mesh's vertex count.
    pub points: usize,
}

impl std::fmt::Display for ShortCoverage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the mesh covers {:.1} % of the region's area: its boundary vertices are too far apart for the boundary's curvature at K = {} (ask for more points)",
            100.0 * self.share,
            self.points
        )
    }
}

/// How much of `region` `mesh` covers, when that is less than [`MIN_COVERAGE`].
///
/// ```
/// use cvtmesh::{short_coverage, Mesh, VertexMarker};
/// use cvtmesh::geometry::{DVec2, Region};
/// let disc = Region::builtin("circle")?;
/// // A square inscribed in the unit circle covers 2/π of it.
/// let points = vec![DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y];
/// let mesh = Mesh {
///     markers: vec![VertexMarker::Interior; 4],
///     points,
///     triangles: vec![[0, 1, 2], [0, 2, 3]],
/// };
/// let short = short_coverage(&mesh, &disc).expect("2/π < 0.9");
/// assert!((short.share - 2.0 / std::f64::consts::PI).abs() < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn short_coverage(mesh: &Mesh, region: &Region) -> Option<ShortCoverage> {
    let share = mesh.area() / region.area();
    (share < MIN_COVERAGE).then_some(ShortCoverage {
        share,
        points: mesh.num_vertices(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each depth is the signed distance, or an upper bound on it below the grid cell's
    /// diagonal, on a region with a hole and a wiggling shore.
    #[test]
    fn depths_bound_the_signed_distance_from_above() {
        let region = Region::builtin("lake").unwrap();
        let (lo, hi) = region.bbox();
        let mut rng = geometry::Rng::new(2);
        let points: Vec<DVec2> = (0..40_000)
            .map(|_| lo + (hi - lo) * DVec2::new(rng.uniform(), rng.uniform()))
            .chain([DVec2::NAN, hi + DVec2::ONE])
            .collect();
        let mesh = Mesh {
            markers: vec![crate::VertexMarker::Interior; points.len()],
            points,
            triangles: Vec::new(),
        };
        let depths = vertex_depths(&mesh, &region);
        let side = DEPTH_CELL * (region.area() / mesh.points.len() as f64).sqrt();
        let mut bounded = 0;
        for (p, &d) in mesh.points.iter().zip(&depths) {
            let exact = region.signed_distance(*p);
            if d.to_bits() != exact.to_bits() {
                bounded += 1;
                assert!(d >= exact, "{p}: {d} below {exact}");
                assert!(d < -side, "{p}: a bound {d} not deep");
            }
        }
        assert!(depths[depths.len() - 2].is_nan());
        assert!(bounded > 5_000, "{bounded} bounded");
    }
}
