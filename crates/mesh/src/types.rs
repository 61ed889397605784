use geometry::{DVec2, PieceId};
use rayon::prelude::*;

/// What a vertex is with respect to the region's boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VertexMarker {
    /// Strictly inside.
    Interior,
    /// On a boundary piece (not at a corner).
    Boundary {
        /// Loop index (0 = outer).
        loop_index: usize,
        /// Piece id.
        piece: PieceId,
        /// Arc-length position along the loop.
        loop_param: f64,
    },
    /// At a corner of the region.
    Corner {
        /// Loop index.
        loop_index: usize,
        /// Corner index in `Region::corners()`.
        corner: usize,
        /// Arc-length position along the loop.
        loop_param: f64,
    },
}

impl VertexMarker {
    /// The marker of a vertex sitting on corner `corner` of `region`.
    pub fn at_corner(region: &geometry::Region, corner: usize) -> VertexMarker {
        let c = &region.corners()[corner];
        VertexMarker::Corner {
            loop_index: c.loop_index,
            corner,
            loop_param: c.loop_param,
        }
    }

    /// The marker of a vertex at `p` on boundary piece `piece` (its loop and arc-length position
    /// come from the projection onto that piece).
    pub fn on_piece(region: &geometry::Region, p: DVec2, piece: PieceId) -> VertexMarker {
        let bp = region.project_onto_piece(p, piece);
        VertexMarker::Boundary {
            loop_index: bp.loop_index,
            piece,
            loop_param: bp.loop_param,
        }
    }

    /// True for boundary and corner vertices.
    pub fn on_boundary(&self) -> bool {
        !matches!(self, VertexMarker::Interior)
    }
    /// Loop index of a boundary or corner vertex.
    pub fn loop_index(&self) -> Option<usize> {
        match *self {
            VertexMarker::Interior => None,
            VertexMarker::Boundary { loop_index, .. } | VertexMarker::Corner { loop_index, .. } => {
                Some(loop_index)
            }
        }
    }
    /// Arc-length position of a boundary or corner vertex.
    pub fn loop_param(&self) -> Option<f64> {
        match *self {
            VertexMarker::Interior => None,
            VertexMarker::Boundary { loop_param, .. } | VertexMarker::Corner { loop_param, .. } => {
                Some(loop_param)
            }
        }
    }
}

/// An edge of exactly one triangle: an edge of the mesh's boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoundaryEdge {
    /// First vertex, as the edge runs in its triangle (so the mesh lies to its left when the
    /// triangles are counter-clockwise).
    pub a: u32,
    /// Second vertex.
    pub b: u32,
    /// The boundary loop it lies on (0 = outer), from its vertices' markers (0 when neither
    /// end has one).
    pub loop_index: usize,
}

/// A triangle mesh: vertices, CCW triangles, and a boundary marker per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex coordinates (the generators, for CVT methods).
    pub points: Vec<DVec2>,
    /// Triangles as CCW vertex index triples.
    pub triangles: Vec<[u32; 3]>,
    /// One marker per vertex.
    pub markers: Vec<VertexMarker>,
}

impl Mesh {
    /// K, the number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.points.len()
    }
    /// K̃, the number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.triangles.len()
    }
    /// The three corner points of triangle `t`.
    pub fn triangle(&self, t: usize) -> [DVec2; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.points[a as usize],
            self.points[b as usize],
            self.points[c as usize],
        ]
    }
    /// Sum of triangle areas.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.triangle(t);
                0.5 * (b - a).perp_dot(c - a)
            })
            .sum()
    }
    /// Smallest interior angle over all triangles, in degrees. O(M), in parallel.
    ///
    /// ```
    /// use cvtmesh::{Mesh, VertexMarker};
    /// use cvtmesh::geometry::DVec2;
    /// // A right isosceles triangle and a 30°–60°–90° one.
    /// let mesh = Mesh {
    ///     points: vec![DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::new(3f64.sqrt(), 1.0)],
    ///     triangles: vec![[0, 1, 2], [0, 3, 2]],
    ///     markers: vec![VertexMarker::Interior; 4],
    /// };
    /// assert!((mesh.min_angle_deg() - 30.0).abs() < 1e-9);
    /// ```
    pub fn min_angle_deg(&self) -> f64 {
        self.min_angle_deg_in(&smallest_angle_cosines(self))
    }

    /// [`Mesh::min_angle_deg`] from the triangles' cosines ([`smallest_angle_cosines`]).
    pub(crate) fn min_angle_deg_in(&self, cos: &[f64]) -> f64 {
        // The flattest triangles by the cosine of their smallest angle first (no
        // trigonometry), then the angles of those alone: the same value as the angles of every
        // triangle, with the inverse trigonometry of a few instead of 2·10⁶ at 10⁶ vertices.
        maybe_below(cos, |worst| worst)
            .into_par_iter()
            .map(|t| triangle_min_angle_deg(self.triangle(t)))
            .reduce(|| f64::INFINITY, f64::min)
    }

    /// The edges of exactly one triangle, grouped by boundary loop and, within a loop, in
    /// order along it, each edge starting where the last ended: from the edge whose first
    /// vertex has the least arc-length position (for a mesh read from a file, which records
    /// none, the least vertex index). A loop that touches itself at a vertex goes on with a
    /// new chain from its next edge not yet taken. Triangles may have either orientation.
    /// O(M) to find them, O(B log B) to order the B found.
    ///
    /// ```
    /// use cvtmesh::{Mesh, VertexMarker};
    /// use cvtmesh::geometry::DVec2;
    /// // Two triangles making the unit square: four boundary edges, the diagonal is inner.
    /// let mesh = Mesh {
    ///     points: vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)],
    ///     triangles: vec![[0, 1, 2], [0, 2, 3]],
    ///     markers: vec![VertexMarker::Interior; 4],
    /// };
    /// let edges: Vec<(u32, u32)> = mesh.boundary_edges().iter().map(|e| (e.a, e.b)).collect();
    /// assert_eq!(edges, vec![(0, 1), (1, 2), (2, 3), (3, 0)]);
    /// ```
    pub fn boundary_edges(&self) -> Vec<BoundaryEdge> {
        let loop_of = |v: u32| self.markers.get(v as usize).and_then(|m| m.loop_index());
        let param = |v: u32| {
            self.markers
                .get(v as usize)
                .and_then(|m| m.loop_param())
                .unwrap_or(f64::NAN)
        };
        let mut edges: Vec<BoundaryEdge> = single_edges(&self.triangles)
            .into_iter()
            .map(|(a, b)| BoundaryEdge {
                a,
                b,
                // In a conforming mesh both ends lie on the edge's loop; otherwise any loop
                // an end knows, so that no boundary edge is dropped.
                loop_index: loop_of(a).or(loop_of(b)).unwrap_or(0),
            })
            .collect();
        edges.sort_by(|x, y| {
            x.loop_index
                .cmp(&y.loop_index)
                .then(param(x.a).total_cmp(&param(y.a)))
                .then((x.a, x.b).cmp(&(y.a, y.b)))
        });
        // Sorted by position they already follow one another; sorted by index they do not.
        chained(&edges).into_iter().map(|i| edges[i]).collect()
    }
}

/// The order that chains `edges` (grouped by loop) along each loop: from the group's first
/// edge, each next edge starts where the last ended. A loop that does not close into one chain
/// (it touches itself at a vertex) goes on with a new chain from its first edge not yet taken.
fn chained(edges: &[BoundaryEdge]) -> Vec<usize> {
    let mut order = Vec::with_capacity(edges.len());
    let mut start = 0;
    while start < edges.len() {
        let loop_index = edges[start].loop_index;
        let end = start
            + edges[start..]
                .iter()
                .take_while(|e| e.loop_index == loop_index)
                .count();
        let mut leaving: std::collections::HashMap<u32, Vec<usize>> =
            std::collections::HashMap::new();
        for i in (start..end).rev() {
            leaving.entry(edges[i].a).or_default().push(i);
        }
        let mut taken = vec![false; end - start];
        for first in start..end {
            if taken[first - start] {
                continue;
            }
            let mut i = first;
            loop {
                taken[i - start] = true;
                order.push(i);
                let next = leaving.get_mut(&edges[i].b).and_then(|out| {
                    while let Some(&j) = out.last() {
                        if !taken[j - start] {
                            return Some(j);
                        }
                        out.pop();
                    }
                    None
                });
                match next {
                    Some(j) => i = j,
                    None => break,
                }
            }
        }
        start = end;
    }
    order
}

impl Mesh {
    /// The piece of `region` each edge of [`Mesh::boundary_edges`] lies on, in the same order:
    /// the piece nearest the edge's midpoint when both ends lie on it, else, of the pieces
    /// nearest the midpoint and each end, the one whose distance to the farther end is least (a
    /// curve the mesher followed through a chain's vertices, say): three nearest-piece queries
    /// per edge at most. Pieces run from corner to corner and `cvtmesh
    /// regions` numbers them, so a finite-element code can set a boundary condition per wall.
    /// (The vertices' markers are not asked: a mesher may have split pieces at corners of its
    /// own, and a mesh read from a foreign file has none.)
    ///
    /// ```
    /// use cvtmesh::{io::markers_from_topology, Mesh};
    /// use cvtmesh::geometry::{DVec2, LoopRole, Region};
    /// // A 2 × 1 channel whose four sides are its four pieces (every vertex a corner).
    /// let corners = vec![DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(2.0, 1.0), DVec2::Y];
    /// let channel = Region::from_loops("channel", vec![(LoopRole::Outer, corners.clone())])?;
    /// let triangles = vec![[0, 1, 2], [0, 2, 3]];
    /// let mesh = Mesh { markers: markers_from_topology(&corners, &triangles), points: corners, triangles };
    /// let pieces = mesh.boundary_pieces(&channel);
    /// // Each side its own piece: the edge from corner i to corner i + 1 lies on piece i.
    /// for (e, piece) in mesh.boundary_edges().iter().zip(&pieces) {
    ///     let (a, b) = (e.a.min(e.b), e.a.max(e.b));
    ///     assert_eq!(*piece, if (a, b) == (0, 3) { 3 } else { a as usize });
    /// }
    /// let mut distinct = pieces.clone();
    /// distinct.sort();
    /// assert_eq!(distinct, [0, 1, 2, 3]);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn boundary_pieces(&self, region: &geometry::Region) -> Vec<PieceId> {
        self.pieces_of(&self.boundary_edges(), region)
    }

    /// [`Mesh::boundary_pieces`] of the boundary edges `edges` (as [`Mesh::boundary_edges`]
    /// lists them).
    pub(crate) fn pieces_of(
        &self,
        edges: &[BoundaryEdge],
        region: &geometry::Region,
    ) -> Vec<PieceId> {
        let (lo, hi) = region.bbox();
        let tol = 1e-9 * (hi - lo).length();
        let pieces = region.pieces();
        // How far the farther end of a-b lies from piece p.
        let off = |p: PieceId, a: DVec2, b: DVec2| {
            let d = |x: DVec2| pieces[p].closest_point(x).0.distance(x);
            d(a).max(d(b))
        };
        edges
            .iter()
            .map(|e| {
                let (a, b) = (self.points[e.a as usize], self.points[e.b as usize]);
                let guess = region.project(0.5 * (a + b)).piece;
                if off(guess, a, b) <= tol {
                    return guess;
                }
                // Each end lies on (or, on a curve the mesher followed through a chain's
                // vertices, next to) the edge's piece, so it is the piece nearest one of them.
                [guess, region.project(a).piece, region.project(b).piece]
                    .into_iter()
                    .min_by(|&p, &q| off(p, a, b).total_cmp(&off(q, a, b)))
                    .unwrap_or(guess)
            })
            .collect()
    }
}

/// The edges of exactly one triangle, each oriented as in its triangle, in triangle order.
/// An edge is matched by its unordered vertex pair, so the triangles' orientation does not
/// matter. Per-vertex lists of outgoing edges (a few entries each) make this linear, where
/// hashing or sorting every edge would dominate on million-vertex meshes.
pub(crate) fn single_edges(triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let n = triangles
        .par_iter()
        .flatten()
        .map(|&v| v as usize + 1)
        .max()
        .unwrap_or(0);
    let (start, targets) = rows_by_vertex(triangles, n, |t, k| triangles[t][(k + 1) % 3]);
    let count = |a: u32, b: u32| {
        targets[start[a as usize]..start[a as usize + 1]]
            .iter()
            .filter(|&&t| t == b)
            .count()
    };
    // In parallel, collected in triangle order.
    triangles
        .par_iter()
        .flat_map_iter(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .filter(|&(a, b)| count(a, b) + count(b, a) == 1)
        .collect()
}

/// Vertices per run of [`rows_by_vertex`]: below it, one run (one thread).
const ROWS_PER_RUN: usize = 50_000;

/// `item(t, k)` for every corner `k` of every triangle `t`, filed in the row of the corner's
/// vertex: row `v` is `entries[start[v]..start[v + 1]]`, in triangle order. Corners at vertices
/// from `n` on are left out. The vertices are split into runs, one per thread, and each run reads
/// every triangle and fills only its own rows: no row depends on the number of threads.
pub(crate) fn rows_by_vertex<T: Copy + Default + Send>(
    triangles: &[[u32; 3]],
    n: usize,
    item: impl Fn(usize, usize) -> T + Sync,
) -> (Vec<usize>, Vec<T>) {
    let runs = rayon::current_num_threads()
        .min(n.div_ceil(ROWS_PER_RUN))
        .max(1);
    let bounds: Vec<usize> = (0..=runs).map(|r| r * n / runs).collect();
    let counts: Vec<Vec<u32>> = (0..runs)
        .into_par_iter()
        .map(|r| {
            let mut count = vec![0u32; bounds[r + 1] - bounds[r]];
            corners_of_run(triangles, bounds[r]..bounds[r + 1], |_, _, v| count[v] += 1);
            count
        })
        .collect();
    let mut start = Vec::with_capacity(n + 1);
    start.push(0);
    let mut total = 0;
    for &c in counts.iter().flatten() {
        total += c as usize;
        start.push(total);
    }
    let mut entries = vec![T::default(); total];
    let mut parts = Vec::with_capacity(runs);
    let mut rest = entries.as_mut_slice();
    for r in 0..runs {
        let (part, tail) = rest.split_at_mut(start[bounds[r + 1]] - start[bounds[r]]);
        parts.push((r, part));
        rest = tail;
    }
    parts.into_par_iter().for_each(|(r, part)| {
        let base = start[bounds[r]];
        let mut fill: Vec<usize> = start[bounds[r]..bounds[r + 1]]
            .iter()
            .map(|s| s - base)
            .collect();
        corners_of_run(triangles, bounds[r]..bounds[r + 1], |t, k, v| {
            part[fill[v]] = item(t, k);
            fill[v] += 1;
        });
    });
    (start, entries)
}

/// `each(t, k, v − run.start)` for every corner `k` of every triangle `t` whose vertex `v` lies
/// in `run`, in triangle order.
#[inline]
fn corners_of_run(
    triangles: &[[u32; 3]],
    run: std::ops::Range<usize>,
    mut each: impl FnMut(usize, usize, usize),
) {
    let len = run.end - run.start;
    for (t, tri) in triangles.iter().enumerate() {
        for (k, &v) in tri.iter().enumerate() {
            let v = (v as usize).wrapping_sub(run.start);
            if v < len {
                each(t, k, v);
            }
        }
    }
}

/// The cosine of the smallest angle of triangle `q` (opposite its shortest side), by the law
/// of cosines: 0.5 for an equilateral triangle, 1 for a flat one (and for a side of length 0,
/// or a corner that is not a number). Larger is worse; no inverse trigonometric function.
pub(crate) fn smallest_angle_cos(q: [DVec2; 3]) -> f64 {
    let (cos, _) = smallest_corner(q);
    if cos.is_finite() {
        cos.min(1.0)
    } else {
        1.0
    }
}

/// The law of cosines at the corner opposite the shortest side of `q`, unclamped, and the
/// squared sides.
fn smallest_corner(q: [DVec2; 3]) -> (f64, [f64; 3]) {
    let l = [0, 1, 2].map(|i| (q[(i + 2) % 3] - q[(i + 1) % 3]).length_squared());
    let k = (0..3).min_by(|&a, &b| l[a].total_cmp(&l[b])).unwrap_or(0);
    let (b, c) = (l[(k + 1) % 3], l[(k + 2) % 3]);
    ((b + c - l[k]) / (2.0 * (b * c).sqrt()), l)
}

/// [`smallest_corner`]'s cosine, and NaN where it may not order the triangle among others as
/// its angles do: a corner not a number, a side of length 0, or squared sides outside the
/// normal numbers (coordinates beyond ~10¹⁵⁰, or sides below ~10⁻¹⁴⁶).
fn law_of_cosines(q: [DVec2; 3]) -> f64 {
    let (cos, l) = smallest_corner(q);
    let normal = |x: f64| x.is_normal() && x > 1e-292 && x < 1e300;
    if l.iter().all(|&x| normal(x)) {
        cos
    } else {
        f64::NAN
    }
}

/// [`law_of_cosines`] of every triangle, in order: what [`maybe_below`] reads, computed once
/// where several bounds are asked of the same mesh.
pub(crate) fn smallest_angle_cosines(mesh: &Mesh) -> Vec<f64> {
    (0..mesh.triangles.len())
        .into_par_iter()
        .map(|t| law_of_cosines(mesh.triangle(t)))
        .collect()
}

/// The triangles (in order) whose smallest angle may lie within rounding of the cosine
/// `least`, or below it, from the triangles' cosines `cos` ([`smallest_angle_cosines`]):
/// [`law_of_cosines`] at least `least` − [`COS_MARGIN`], or not a number.
/// The law of cosines and `angle_to` round differently, but by ~10⁻¹⁴ of the cosine even for a
/// triangle 10⁶ times longer than wide, so a pass that computes the angles of these alone finds
/// what the angles of every triangle would.
pub(crate) fn maybe_below(cos: &[f64], least: impl Fn(f64) -> f64 + Sync) -> Vec<usize> {
    let worst = cos
        .par_iter()
        .copied()
        .filter(|c| !c.is_nan())
        .reduce(|| f64::NEG_INFINITY, f64::max);
    let bound = least(worst) - COS_MARGIN;
    (0..cos.len())
        .into_par_iter()
        .filter(|&t| cos[t].is_nan() || cos[t] >= bound)
        .collect()
}

/// How far below a bound a triangle's cosine may lie and the triangle still be given its
/// exact angles ([`maybe_below`]).
const COS_MARGIN: f64 = 1e-6;

/// Smallest interior angle of the triangle with corners `p`, in degrees (infinite only if no
/// angle is a number).
pub fn triangle_min_angle_deg(p: [DVec2; 3]) -> f64 {
    (0..3)
        .map(|i| corner_angle_deg(p, i))
        .fold(f64::INFINITY, f64::min)
}

/// The interior angle at corner `i` of the triangle with corners `p`, in degrees (NaN where a
/// side from it has zero length).
pub(crate) fn corner_angle_deg(p: [DVec2; 3], i: usize) -> f64 {
    (p[(i + 1) % 3] - p[i])
        .angle_to(p[(i + 2) % 3] - p[i])
        .abs()
        .to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh read from a file knows no positions along its loops: its boundary edges still
    /// follow one another, loop by loop, whatever the vertices' numbering.
    #[test]
    fn boundary_edges_of_a_mesh_without_positions_follow_one_another() {
        // The square [0, 3]² minus [1, 2]², its eight corners numbered out of order.
        let at = [
            (2.0, 1.0),
            (0.0, 3.0),
            (3.0, 0.0),
            (1.0, 2.0),
            (0.0, 0.0),
            (2.0, 2.0),
            (3.0, 3.0),
            (1.0, 1.0),
        ];
        let points: Vec<DVec2> = at.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
        // Outer 4 → 2 → 6 → 1 → 4, inner 7 → 3 → 5 → 0 → 7 (clockwise); the ring between.
        let triangles = vec![
            [4, 2, 0],
            [4, 0, 7],
            [2, 6, 5],
            [2, 5, 0],
            [6, 1, 3],
            [6, 3, 5],
            [1, 4, 7],
            [1, 7, 3],
        ];
        for markers in [
            vec![VertexMarker::Interior; 8],
            crate::io::markers_from_topology(&points, &triangles),
        ] {
            let mesh = Mesh {
                points: points.clone(),
                triangles: triangles.clone(),
                markers,
            };
            let edges = mesh.boundary_edges();
            assert_eq!(edges.len(), 8);
            let chains = edges.windows(2).filter(|w| w[0].b != w[1].a).count();
            // One break: from the end of the first loop to the start of the second.
            assert_eq!(chains, 1, "{edges:?}");
            let outer: Vec<u32> = edges
                .iter()
                .filter(|e| e.loop_index == edges[0].loop_index)
                .map(|e| e.a)
                .collect();
            assert!(outer.len() == 8 || outer.len() == 4, "{edges:?}");
        }
    }

    /// The rows are those of filing the corners one by one, on any number of threads and
    /// whatever the runs, with the corners at vertices from `n` on left out.
    #[test]
    fn rows_by_vertex_are_the_corners_filed_one_by_one() {
        let mut rng = geometry::Rng::new(4);
        for (triangles, n) in [(10usize, 40usize), (30_000, 120_000), (60_000, 110_000)] {
            // Vertices up to 5 % beyond n, so that some corners are left out.
            let tris: Vec<[u32; 3]> = (0..triangles)
                .map(|_| [0; 3].map(|_| rng.below(n + n / 20 + 1) as u32))
                .collect();
            let mut rows: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n];
            for (t, tri) in tris.iter().enumerate() {
                for (k, &v) in tri.iter().enumerate() {
                    if (v as usize) < n {
                        rows[v as usize].push((t as u32, k as u32));
                    }
                }
            }
            for threads in [1, 2, 3, 8] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let (start, entries) =
                    pool.install(|| rows_by_vertex(&tris, n, |t, k| (t as u32, k as u32)));
                assert_eq!(start.len(), n + 1);
                for (v, row) in rows.iter().enumerate() {
                    assert_eq!(
                        &entries[start[v]..start[v + 1]],
                        &row[..],
                        "{threads} threads"
                    );
                }
            }
        }
    }
}
