//! Delaunay triangulation of generators, built by inserting in Hilbert-curve order
//! (see notes: plain `insert` on unsorted points is ~100× slower at 10⁶).
use geometry::DVec2;
use rayon::prelude::*;
use spade::handles::FixedVertexHandle;
use spade::{DelaunayTriangulation, Point2, Triangulation};

/// Marks an input point that is not a vertex (non-finite or rejected coordinates).
const NONE: u32 = u32::MAX;

/// Delaunay triangulation of a point set. Vertex `i` is `points[i]` (duplicates are merged
/// onto the first occurrence; `vertex_of` maps each input point to its vertex).
///
/// Points with non-finite coordinates (or coordinates spade rejects) are not inserted: they have
/// no vertex, no neighbours and an empty Voronoi cell.
pub struct Delaunay {
    /// The spade triangulation; its vertex `v` was inserted `v`-th (Hilbert order).
    pub(crate) dt: DelaunayTriangulation<Point2<f64>>,
    /// Spade vertex index → input index of the first point at that position.
    pub(crate) point_of_vertex: Vec<u32>,
    /// Input index → spade vertex index (`NONE` if not inserted).
    pub(crate) vertex_of_point: Vec<u32>,
    /// Position of each spade vertex (a compact copy for cache-friendly passes).
    pub(crate) pos: Vec<DVec2>,
    /// Start vertices for nearest-point walks.
    hints: HintGrid,
    /// Hilbert keys of the last rebuild (kept for their memory).
    keys: Vec<u64>,
}

impl Delaunay {
    /// Triangulate `points`.
    pub fn new(points: &[DVec2]) -> Delaunay {
        let mut d = Delaunay {
            dt: DelaunayTriangulation::new(),
            point_of_vertex: Vec::new(),
            vertex_of_point: Vec::new(),
            pos: Vec::new(),
            hints: HintGrid::new(&DelaunayTriangulation::new()),
            keys: Vec::new(),
        };
        d.rebuild(points);
        d
    }

    /// Triangulate `points` afresh in this triangulation's memory: the same result as
    /// [`Delaunay::new`], without the large allocations (at 10⁶ points a fresh triangulation
    /// faults in ~150 MB of new pages per Lloyd iteration).
    pub fn rebuild(&mut self, points: &[DVec2]) {
        assert!(
            points.len() < NONE as usize,
            "at most 2^32 - 1 points are supported"
        );
        hilbert_keys(points, &mut self.keys);
        self.dt.clear();
        self.point_of_vertex.clear();
        self.vertex_of_point.clear();
        self.vertex_of_point.resize(points.len(), NONE);
        for &key in &self.keys {
            let i = key as u32;
            let p = points[i as usize];
            let before = self.dt.num_vertices();
            // Errors are NaN/infinite/out-of-range coordinates: such points stay un-inserted.
            if let Ok(h) = self.dt.insert(Point2::new(p.x, p.y)) {
                if self.dt.num_vertices() > before {
                    self.point_of_vertex.push(i);
                }
                self.vertex_of_point[i as usize] = h.index() as u32;
            }
        }
        self.hints = HintGrid::new(&self.dt);
        self.pos.clear();
        self.pos
            .extend(self.point_of_vertex.iter().map(|&i| points[i as usize]));
    }

    /// Number of input points (including duplicates and rejected points).
    pub fn num_points(&self) -> usize {
        self.vertex_of_point.len()
    }

    /// Number of distinct vertices.
    pub fn num_vertices(&self) -> usize {
        self.point_of_vertex.len()
    }

    /// The input index of the vertex that point `i` was merged onto: `Some(i)` for the first
    /// point at a position, the first occurrence for a duplicate, `None` for a point that was not
    /// inserted (non-finite coordinates) or an out-of-range `i`.
    pub fn vertex_of(&self, i: usize) -> Option<usize> {
        let v = *self.vertex_of_point.get(i)?;
        (v != NONE).then(|| self.point_of_vertex[v as usize] as usize)
    }

    /// The input index of vertex `v` (vertices are numbered `0..num_vertices()` along a Hilbert
    /// curve, so passes in vertex order are cache-friendly).
    pub fn point_of_vertex(&self, v: usize) -> usize {
        self.point_of_vertex[v] as usize
    }

    /// The vertex of point `i` if `i` is the first point at its position (`None` for a
    /// duplicate, a point that was not inserted, or an out-of-range `i`).
    pub fn vertex_index(&self, i: usize) -> Option<usize> {
        let v = *self.vertex_of_point.get(i)?;
        (v != NONE && self.point_of_vertex[v as usize] as usize == i).then_some(v as usize)
    }

    /// All finite triangles as CCW index triples into the input points.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.dt
            .inner_faces()
            .map(|f| f.vertices().map(|v| self.point_of_vertex[v.fix().index()]))
            .collect()
    }

    /// Delaunay neighbours of input point `i`, in CCW order (empty for a point without vertex).
    pub fn neighbors(&self, i: usize) -> Vec<usize> {
        match self.vertex_of_point.get(i) {
            Some(&v) if v != NONE => self
                .dt
                .vertex(FixedVertexHandle::from_index(v as usize))
                .out_edges()
                .map(|e| self.point_of_vertex[e.to().fix().index()] as usize)
                .collect(),
            _ => Vec::new(),
        }
    }

    /// Index of the input point nearest to `p` (`usize::MAX` if there is no vertex or `p` is
    /// not finite; see [`Delaunay::try_nearest`]).
    pub fn nearest(&self, p: DVec2) -> usize {
        self.try_nearest(p).unwrap_or(usize::MAX)
    }

    /// Index of the input point nearest to `p`, or `None` for an empty triangulation or a
    /// non-finite `p`. Deterministic: a greedy walk over Delaunay edges (which always ends at a
    /// nearest vertex) from a start vertex looked up in a fixed grid.
    pub fn try_nearest(&self, p: DVec2) -> Option<usize> {
        if !p.is_finite() || self.num_vertices() == 0 {
            return None;
        }
        let mut v = FixedVertexHandle::from_index(self.hints.start(p) as usize);
        let dist = |h: FixedVertexHandle| {
            let q = self.dt.vertex(h).position();
            (q.x - p.x).powi(2) + (q.y - p.y).powi(2)
        };
        let mut d = dist(v);
        loop {
            let mut best = (v, d);
            for e in self.dt.vertex(v).out_edges() {
                let u = e.to().fix();
                let du = dist(u);
                if du < best.1 {
                    best = (u, du);
                }
            }
            if best.0 == v {
                return Some(self.point_of_vertex[v.index()] as usize);
            }
            (v, d) = best;
        }
    }
}

/// A coarse grid of start vertices for nearest-point walks.
struct HintGrid {
    lo: DVec2,
    inv: DVec2,
    nx: usize,
    ny: usize,
    cells: Vec<u32>,
}

impl HintGrid {
    fn new(dt: &DelaunayTriangulation<Point2<f64>>) -> HintGrid {
        let n = dt.num_vertices();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for v in dt.vertices() {
            let p = DVec2::new(v.position().x, v.position().y);
            lo = lo.min(p);
            hi = hi.max(p);
        }
        if n == 0 {
            return HintGrid {
                lo: DVec2::ZERO,
                inv: DVec2::ZERO,
                nx: 1,
                ny: 1,
                cells: vec![0],
            };
        }
        // About four vertices per grid cell.
        let ext = (hi - lo).max(DVec2::splat(1e-300));
        let target = (n / 4).clamp(1, 1 << 20) as f64;
        let s = (ext.x * ext.y / target)
            .sqrt()
            .max(ext.x.max(ext.y) / 1024.0);
        let nx = ((ext.x / s).ceil() as usize).clamp(1, 1024);
        let ny = ((ext.y / s).ceil() as usize).clamp(1, 1024);
        let inv = DVec2::new(nx as f64 / ext.x, ny as f64 / ext.y);
        let mut grid = HintGrid {
            lo,
            inv,
            nx,
            ny,
            cells: vec![NONE; nx * ny],
        };
        for v in dt.vertices() {
            let c = grid.cell(DVec2::new(v.position().x, v.position().y));
            if grid.cells[c] == NONE {
                grid.cells[c] = v.fix().index() as u32;
            }
        }
        // Empty cells borrow the previous filled cell's vertex (any start is correct).
        let first = grid.cells.iter().copied().find(|&c| c != NONE).unwrap_or(0);
        let mut last = first;
        for c in grid.cells.iter_mut() {
            if *c == NONE {
                *c = last;
            } else {
                last = *c;
            }
        }
        grid
    }

    fn cell(&self, p: DVec2) -> usize {
        let q = (p - self.lo) * self.inv;
        let i = (q.x.max(0.0) as usize).min(self.nx - 1);
        let j = (q.y.max(0.0) as usize).min(self.ny - 1);
        j * self.nx + i
    }

    fn start(&self, p: DVec2) -> u32 {
        self.cells[self.cell(p)]
    }
}

/// Input indices sorted along a Hilbert curve on a 2^16 × 2^16 grid over the bounding box of
/// the finite points (non-finite points go last). Ties keep index order, so the order is a pure
/// function of the input.
pub(crate) fn hilbert_order(points: &[DVec2]) -> Vec<u32> {
    let mut keys = Vec::new();
    hilbert_keys(points, &mut keys);
    keys.into_iter().map(|k| k as u32).collect()
}

/// `hilbert_order` as sorted (key << 32 | index) words, written into `keys`.
fn hilbert_keys(points: &[DVec2], keys: &mut Vec<u64>) {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in points.iter().filter(|p| p.is_finite()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let scale = 65535.0 / (hi - lo).max_element().max(f64::MIN_POSITIVE);
    points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            let key = if p.is_finite() {
                let q = (*p - lo) * scale;
                hilbert_key(q.x as u32, q.y as u32)
            } else {
                u32::MAX
            };
            (u64::from(key) << 32) | i as u64
        })
        .collect_into_vec(keys);
    keys.par_sort_unstable();
}

/// Position of (x, y) along the Hilbert curve filling [0, 2^16)².
fn hilbert_key(mut x: u32, mut y: u32) -> u32 {
    const N: u32 = 1 << 16;
    let mut d = 0u32;
    let mut s = N / 2;
    while s > 0 {
        let rx = u32::from(x & s > 0);
        let ry = u32::from(y & s > 0);
        d += s * s * ((3 * rx) ^ ry);
        if ry == 0 {
            if rx == 1 {
                x = N - 1 - x;
                y = N - 1 - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s /= 2;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::Rng;

    fn lattice(n: usize) -> Vec<DVec2> {
        let mut pts = Vec::new();
        for j in 0..n {
            for i in 0..n {
                pts.push(DVec2::new(i as f64, j as f64));
            }
        }
        pts
    }

    #[test]
    fn hilbert_key_is_a_bijection_on_a_small_grid() {
        // On the 2^16 grid the low corner block [0,4)² maps onto keys 0..16.
        let mut keys: Vec<u32> = (0..4)
            .flat_map(|x| (0..4).map(move |y| hilbert_key(x, y)))
            .collect();
        keys.sort_unstable();
        assert_eq!(keys, (0..16).collect::<Vec<_>>());
        // Consecutive keys are grid neighbours (the curve is continuous).
        let mut inv = [(0u32, 0u32); 16];
        for x in 0..4 {
            for y in 0..4 {
                inv[hilbert_key(x, y) as usize] = (x, y);
            }
        }
        for w in inv.windows(2) {
            let d = w[0].0.abs_diff(w[1].0) + w[0].1.abs_diff(w[1].1);
            assert_eq!(d, 1, "{:?}", w);
        }
    }

    #[test]
    fn lattice_triangle_count_and_orientation() {
        // A square lattice (exact coordinates, four cocircular points per square): every
        // boundary point is on the hull, h = 4(k - 1), and Euler gives 2n - 2 - h triangles.
        let k = 12;
        let pts = lattice(k);
        let d = Delaunay::new(&pts);
        let hull = 4 * (k - 1);
        assert_eq!(d.dt.convex_hull_size(), hull);
        let tris = d.triangles();
        assert_eq!(tris.len(), 2 * pts.len() - 2 - hull);
        for t in &tris {
            let [a, b, c] = t.map(|i| pts[i as usize]);
            assert!((b - a).perp_dot(c - a) > 0.0, "triangle {t:?} not CCW");
        }
    }

    #[test]
    fn neighbors_are_ccw_and_symmetric() {
        let mut rng = Rng::new(3);
        let pts: Vec<DVec2> = (0..500)
            .map(|_| DVec2::new(rng.uniform(), rng.uniform()))
            .collect();
        let d = Delaunay::new(&pts);
        for i in 0..pts.len() {
            let nb = d.neighbors(i);
            for &j in &nb {
                assert!(d.neighbors(j).contains(&i));
            }
            // CCW: angles around i increase (with one wrap-around) for an interior vertex.
            let ang: Vec<f64> = nb.iter().map(|&j| (pts[j] - pts[i]).to_angle()).collect();
            let wraps = (0..ang.len())
                .filter(|&k| ang[(k + 1) % ang.len()] < ang[k])
                .count();
            assert!(wraps <= 1, "neighbours of {i} not in angular order");
        }
    }

    #[test]
    fn duplicates_and_non_finite_points() {
        let pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(f64::NAN, 0.0),
            DVec2::new(1.0, 1.0),
        ];
        let d = Delaunay::new(&pts);
        assert_eq!(d.num_points(), 6);
        assert_eq!(d.num_vertices(), 4);
        assert_eq!(d.vertex_of(3), Some(1));
        assert_eq!(d.vertex_of(1), Some(1));
        assert_eq!(d.vertex_of(4), None);
        assert!(d.neighbors(4).is_empty());
        assert_eq!(d.triangles().len(), 2);
        assert!(d.triangles().iter().flatten().all(|&i| i != 3 && i != 4));
        assert_eq!(d.nearest(DVec2::new(0.9, 0.2)), 1);
        assert_eq!(d.nearest(DVec2::NAN), usize::MAX);
        assert_eq!(Delaunay::new(&[]).try_nearest(DVec2::ZERO), None);
    }

    #[test]
    fn nearest_matches_brute_force() {
        let mut rng = Rng::new(11);
        let pts: Vec<DVec2> = (0..2000)
            .map(|_| DVec2::new(rng.uniform(), rng.range(0.0, 3.0)))
            .collect();
        let d = Delaunay::new(&pts);
        for _ in 0..2000 {
            let q = DVec2::new(rng.range(-0.5, 1.5), rng.range(-0.5, 3.5));
            let brute = (0..pts.len())
                .min_by(|&a, &b| {
                    pts[a]
                        .distance_squared(q)
                        .total_cmp(&pts[b].distance_squared(q))
                })
                .unwrap();
            let got = d.nearest(q);
            assert_eq!(pts[got].distance_squared(q), pts[brute].distance_squared(q));
        }
    }

    #[test]
    fn collinear_points_have_neighbours_and_no_triangles() {
        let pts: Vec<DVec2> = (0..10)
            .map(|i| DVec2::new(i as f64, 2.0 * i as f64))
            .collect();
        let d = Delaunay::new(&pts);
        assert!(d.triangles().is_empty());
        let mut nb = d.neighbors(4);
        nb.sort_unstable();
        assert_eq!(nb, vec![3, 5]);
        assert_eq!(d.nearest(DVec2::new(7.2, 13.0)), 7);
    }

    #[test]
    fn rebuild_equals_a_fresh_triangulation() {
        let mut rng = Rng::new(23);
        let mut random = |n: usize| -> Vec<DVec2> {
            (0..n)
                .map(|_| DVec2::new(rng.uniform(), rng.uniform()))
                .collect()
        };
        let (a, mut b) = (random(500), random(300));
        b[7] = b[3]; // a duplicate
        b[11] = DVec2::NAN; // a point without vertex
        let mut d = Delaunay::new(&a);
        d.rebuild(&b);
        let fresh = Delaunay::new(&b);
        assert_eq!(d.num_points(), 300);
        assert_eq!(d.num_vertices(), fresh.num_vertices());
        assert_eq!(d.triangles(), fresh.triangles());
        for i in 0..b.len() {
            assert_eq!(d.vertex_of(i), fresh.vertex_of(i));
            assert_eq!(d.neighbors(i), fresh.neighbors(i));
        }
        for q in random(50) {
            assert_eq!(d.nearest(q), fresh.nearest(q));
        }
        // Back to the larger set: nothing of the smaller one remains.
        d.rebuild(&a);
        assert_eq!(d.triangles(), Delaunay::new(&a).triangles());
    }
}
