//! Voronoi cells clipped to a region (Section 2.1 eq. (1), restricted to Ω) and their moments.
//!
//! Interior cells (whose circumcentre polygon lies in boundary-free grid squares inside Ω) are
//! the plain Voronoi polygons. A cell that may reach the boundary is built as the intersection
//! of a box around Ω with the bisector half-planes of its Delaunay neighbours (robust also for
//! hull vertices and near-degenerate triangles) and then intersected with Ω using only the
//! boundary edges near it: each maximal run of nearby edges is clipped by the cell with
//! Sutherland–Hodgman (open-polyline passes), the cut-off far parts are replaced by their
//! projection onto the cell boundary (which changes no winding number inside the cell), and the
//! number of whole turns of that projection is fixed by the winding number of one reference
//! point. All integrals are fans of signed triangles from that point, so a cell cut into several
//! parts, or clipped by holes, is integrated exactly.
use crate::boundary::Boundary;
use crate::clip::{
    angle, clip_closed, clip_open, clip_segment, edge_fn, segment_meets_box, Fan, Mom,
};
use crate::delaunay::Delaunay;
use geometry::predicates::{circumcenter, segment_distance};
use geometry::{DVec2, Density, PieceId, Polygon};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// One generator's Voronoi cell V_k ∩ Ω (the union of its parts if Ω cuts it in several).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cell {
    /// |V_k|.
    pub area: f64,
    /// Geometric centroid (Section 3, first moment / area).
    pub centroid: DVec2,
    /// Second-moment tensor about the centroid, normalised by the area: [Mxx, Mxy, Myy].
    pub second_moment: [f64; 3],
    /// ∫_V ρ dx (equals `area` for ρ ≡ 1).
    pub mass: f64,
    /// ρ-weighted centroid of eq. (2) (equals `centroid` for ρ ≡ 1).
    pub mass_centroid: DVec2,
    /// ∫_V ρ |x − z_k|² dx: this cell's term of the CVT energy (4).
    pub energy: f64,
    /// h_k = max over y in the closed cell of |z_k − y| (Section 3.2).
    pub h: f64,
    /// Boundary pieces the cell's closure touches (sorted, unique); empty for interior cells.
    pub pieces: Vec<PieceId>,
}

impl Cell {
    /// True if the cell's closure meets the boundary.
    pub fn on_boundary(&self) -> bool {
        !self.pieces.is_empty()
    }
}

/// The clipped Voronoi cells of all generators, indexed like the generators.
#[derive(Clone, Debug)]
pub struct Cells {
    /// One cell per generator.
    pub cells: Vec<Cell>,
}

impl Cells {
    /// CVT energy (4): Σ_k ∫_{V_k} ρ |x − z_k|² dx.
    pub fn energy(&self) -> f64 {
        self.cells.iter().map(|c| c.energy).sum()
    }
    /// Σ |V_k| (equals the domain polygon's area).
    pub fn total_area(&self) -> f64 {
        self.cells.iter().map(|c| c.area).sum()
    }
}

/// Clip every generator's Voronoi cell to `domain` and compute its moments. Generators must lie
/// in the domain or on its boundary. `delaunay` must be the triangulation of `points`.
/// Parallel over cells; the result does not depend on the thread count.
///
/// Details:
/// - the result has one cell per point of `delaunay` (which must equal `points.len()`);
/// - a duplicate point (or one that was not triangulated) gets an empty cell (area 0,
///   centroid = the point); the first point at a position gets the whole cell;
/// - with a density, the cell integrals are sums of signed triangles fanned from a point of
///   the convex cell, so ρ may also be evaluated at points of the convex cell outside Ω (with
///   weights that cancel): ρ should be finite near Ω, not only on it;
/// - `pieces` lists the pieces with an edge that meets the closed convex Voronoi cell grown by
///   1e-10 of its size, so a cell touching the boundary in a single point (a Voronoi vertex on
///   the boundary, a generator at a corner) counts the pieces there;
/// - `h` is the largest distance from z_k to a vertex of V_k ∩ Ω̄ (Voronoi vertices in Ω̄,
///   boundary-edge/cell-edge crossings, ring vertices inside the cell);
/// - rings are used with outer rings counter-clockwise and holes clockwise whatever their
///   stored orientation; rings with fewer than 3 points are ignored;
/// - a domain without rings gives empty cells; a generator outside Ω̄ gets the part of its
///   cell inside Ω (possibly empty).
///
/// ```
/// use cvtmesh::tessellation::{clipped_cells, Delaunay};
/// use cvtmesh::geometry::{DVec2, Density, Region, Rng};
/// let region = Region::builtin("square_hole")?;
/// let domain = region.polygonize(1e-4);
/// // 200 random generators in the domain.
/// let mut rng = Rng::new(7);
/// let mut points = Vec::new();
/// while points.len() < 200 {
///     let p = DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
///     if domain.contains(p) {
///         points.push(p);
///     }
/// }
/// let delaunay = Delaunay::new(&points);
/// let cells = clipped_cells(&points, &delaunay, &domain, &Density::Uniform);
/// assert_eq!(cells.cells.len(), 200);
/// // The cells partition the domain: their areas sum to its area.
/// assert!((cells.total_area() - domain.area()).abs() < 1e-12 * domain.area());
/// assert!((domain.area() - region.area()).abs() < 1e-3);
/// for (cell, p) in cells.cells.iter().zip(&points) {
///     assert!(cell.area > 0.0);
///     // A cell's centroid lies in the domain and h bounds its distance from the generator.
///     assert!(domain.contains(cell.centroid));
///     assert!(cell.centroid.distance(*p) <= cell.h);
/// }
/// // Cells that reach the boundary name the boundary pieces they touch.
/// assert!(cells.cells.iter().any(|c| c.on_boundary()));
/// # Ok::<(), cvtmesh::geometry::GeometryError>(())
/// ```
pub fn clipped_cells(
    points: &[DVec2],
    delaunay: &Delaunay,
    domain: &Polygon,
    density: &Density,
) -> Cells {
    let mut cells = Cells { cells: Vec::new() };
    let mut buffer = CellsBuffer::default();
    clipped_cells_into(points, delaunay, domain, density, &mut cells, &mut buffer);
    cells
}

/// Working memory of [`clipped_cells_into`], kept between calls.
#[derive(Clone, Debug, Default)]
pub struct CellsBuffer {
    per_vertex: Vec<Cell>,
}

/// [`clipped_cells`] written into `out`, reusing its memory and `buffer`'s: an iteration that
/// recomputes the cells of the same generators (Lloyd, Newton) reuses the previous iteration's
/// vectors instead of allocating them afresh.
pub fn clipped_cells_into(
    points: &[DVec2],
    delaunay: &Delaunay,
    domain: &Polygon,
    density: &Density,
    out: &mut Cells,
    buffer: &mut CellsBuffer,
) {
    let grid = DomainGrid::new(domain, delaunay.num_vertices());
    clipped_cells_on(points, delaunay, &grid, density, out, buffer);
}

/// [`clipped_cells_into`] on the domain's `grid` ([`DomainGrid::new`] of the domain with
/// `delaunay.num_vertices()`), kept by a caller that clips to the same domain again and again:
/// the grid is then built once instead of at every call, with the same cells bit for bit.
///
/// ```
/// use cvtmesh::geometry::{DVec2, Density, Region};
/// use cvtmesh::tessellation::{
///     clipped_cells, clipped_cells_on, Cells, CellsBuffer, Delaunay, DomainGrid,
/// };
/// let region = Region::builtin("circle")?;
/// let domain = region.polygonize(1e-3);
/// let points: Vec<DVec2> = (0..50)
///     .map(|i| DVec2::from_angle(i as f64 * 2.4) * (i as f64 / 50.0).sqrt() * 0.9)
///     .collect();
/// let delaunay = Delaunay::new(&points);
/// let grid = DomainGrid::new(&domain, delaunay.num_vertices());
/// let (mut cells, mut buffer) = (Cells { cells: Vec::new() }, CellsBuffer::default());
/// clipped_cells_on(&points, &delaunay, &grid, &Density::Uniform, &mut cells, &mut buffer);
/// let fresh = clipped_cells(&points, &delaunay, &domain, &Density::Uniform);
/// assert!(cells.cells.iter().zip(&fresh.cells).all(|(a, b)| a.mass == b.mass));
/// # Ok::<(), cvtmesh::geometry::GeometryError>(())
/// ```
pub fn clipped_cells_on(
    points: &[DVec2],
    delaunay: &Delaunay,
    grid: &DomainGrid,
    density: &Density,
    out: &mut Cells,
    buffer: &mut CellsBuffer,
) {
    cells_with(
        points,
        delaunay,
        grid,
        density,
        false,
        &mut out.cells,
        &mut buffer.per_vertex,
    );
}

/// A domain's boundary edges indexed on a grid, built once for many partial updates
/// ([`update_cells`], [`crate::energy_hessian_rows`]) where building it per call would cost
/// more than the few cells updated.
pub struct DomainGrid {
    pub(crate) bnd: Option<Boundary>,
}

impl DomainGrid {
    /// The grid of `domain` as [`clipped_cells`] builds it for a triangulation of `vertices`
    /// distinct points (the same grid gives bit-identical cells).
    pub fn new(domain: &Polygon, vertices: usize) -> DomainGrid {
        DomainGrid {
            bnd: Boundary::new(domain, vertices),
        }
    }
}

/// Recompute, in `out`, the cells of the Delaunay vertices `vertices` (e.g. those
/// [`Delaunay::move_points`] reports), leaving every other cell as it is. `grid` must be
/// [`DomainGrid::new`] of the domain the cells were clipped to, with `delaunay.num_vertices()`;
/// the cells are then bit-identical to those of a full [`clipped_cells`].
pub fn update_cells(
    delaunay: &Delaunay,
    grid: &DomainGrid,
    density: &Density,
    vertices: &[u32],
    out: &mut Cells,
) {
    let Some(bnd) = grid.bnd.as_ref() else {
        return;
    };
    let ctx = Ctx {
        del: delaunay,
        bnd,
        density: (!density.is_uniform()).then_some(density),
        whole_rings: false,
    };
    let new: Vec<Cell> = vertices
        .par_iter()
        .map_init(
            || Scratch::new(bnd.num_edges()),
            |s, &v| ctx.cell(s, v as usize),
        )
        .collect();
    for (&v, c) in vertices.iter().zip(new) {
        out.cells[delaunay.point_of_vertex(v as usize)] = c;
    }
}

/// `clipped_cells`, optionally clipping whole rings instead of nearby edges (the fallback,
/// forced in tests to cross-check the local method).
fn cells_with(
    points: &[DVec2],
    delaunay: &Delaunay,
    grid: &DomainGrid,
    density: &Density,
    whole_rings: bool,
    out: &mut Vec<Cell>,
    per_vertex: &mut Vec<Cell>,
) {
    debug_assert_eq!(
        points.len(),
        delaunay.num_points(),
        "points and triangulation differ"
    );
    let nv = delaunay.num_vertices();
    let empty = |i: usize| Cell::empty(points.get(i).copied().unwrap_or(DVec2::ZERO));
    let Some(bnd) = grid.bnd.as_ref() else {
        (0..delaunay.num_points())
            .into_par_iter()
            .map(empty)
            .collect_into_vec(out);
        return;
    };
    let ctx = Ctx {
        del: delaunay,
        bnd,
        density: (!density.is_uniform()).then_some(density),
        whole_rings,
    };
    // In vertex order (Hilbert order: cache-friendly whatever the input order), then back to
    // input order in parallel (cloning an empty `pieces` does not allocate).
    (0..nv)
        .into_par_iter()
        .map_init(|| Scratch::new(bnd.num_edges()), |s, v| ctx.cell(s, v))
        .collect_into_vec(per_vertex);
    (0..delaunay.num_points())
        .into_par_iter()
        .map(|i| match delaunay.vertex_of(i) {
            Some(first) if first == i => per_vertex[delaunay.vertex_of_point[i] as usize].clone(),
            _ => empty(i),
        })
        .collect_into_vec(out);
}

impl Cell {
    /// The empty cell of a generator at `z`.
    fn empty(z: DVec2) -> Cell {
        Cell {
            centroid: z,
            mass_centroid: z,
            ..Cell::default()
        }
    }
}

/// Per-thread buffers, reused from cell to cell.
struct Scratch {
    nb: Vec<(u32, DVec2)>,
    k: Vec<DVec2>,
    tmp: Vec<DVec2>,
    chain: Vec<DVec2>,
    /// Per-edge marks for de-duplication (allocated on first use: most threads' chunks may
    /// never reach the boundary).
    stamp: Vec<u32>,
    num_edges: usize,
    epoch: u32,
    near: Vec<u32>,
    runs: Vec<(usize, usize)>,
    /// How many times each edge of the convex cell enters the clipped cell's moments, as a
    /// difference array (entry i adds to edges i.., a run's end takes it off again).
    uses: Vec<i32>,
    phi: Vec<f64>,
    pieces: Vec<PieceId>,
}

impl Scratch {
    fn new(num_edges: usize) -> Scratch {
        Scratch {
            nb: Vec::with_capacity(16),
            k: Vec::with_capacity(16),
            tmp: Vec::with_capacity(16),
            chain: Vec::new(),
            stamp: Vec::new(),
            num_edges,
            epoch: 0,
            near: Vec::new(),
            runs: Vec::new(),
            uses: Vec::new(),
            phi: Vec::new(),
            pieces: Vec::new(),
        }
    }

    /// A fresh stamp value for de-duplicating edges.
    fn next_epoch(&mut self) -> u32 {
        if self.stamp.len() < self.num_edges {
            self.stamp = vec![0; self.num_edges];
            self.epoch = 0;
        }
        if self.epoch == u32::MAX {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.epoch = 0;
        }
        self.epoch += 1;
        self.epoch
    }
}

/// Shared read-only inputs of the per-cell computation.
struct Ctx<'a> {
    del: &'a Delaunay,
    bnd: &'a Boundary,
    density: Option<&'a Density>,
    /// Always use the whole-ring fallback (tests).
    whole_rings: bool,
}

fn bbox(pts: &[DVec2]) -> (DVec2, DVec2) {
    pts.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

fn max_norm(pts: &[DVec2]) -> f64 {
    pts.iter().map(|p| p.length()).fold(0.0, f64::max)
}

/// Circumcentre of the triangle of vertices `a`, `b`, `c` (index, position), computed with the
/// vertices in index order so that the three cells sharing the triangle get bit-identical
/// Voronoi vertices.
pub(crate) fn canonical_circumcenter(a: (u32, DVec2), b: (u32, DVec2), c: (u32, DVec2)) -> DVec2 {
    let (a, b) = if a.0 < b.0 { (a, b) } else { (b, a) };
    let (b, c) = if b.0 < c.0 { (b, c) } else { (c, b) };
    let (a, b) = if a.0 < b.0 { (a, b) } else { (b, a) };
    circumcenter(a.1, b.1, c.1)
}

/// Drop vertices closer than `eps` to their predecessor (short edges have unreliable
/// directions, and they would be used as clipping lines).
fn dedupe(k: &mut Vec<DVec2>, eps: f64) {
    let mut n = 0;
    for i in 0..k.len() {
        if n == 0 || k[i].distance(k[n - 1]) > eps {
            k[n] = k[i];
            n += 1;
        }
    }
    k.truncate(n);
    while k.len() > 1 && k[0].distance(k[k.len() - 1]) <= eps {
        k.pop();
    }
}

/// Signed number of times the boundary edges `near` (relative coordinates) cross the segment
/// c → v: the winding number at v minus the one at c (for v not on an edge).
fn crossings(c: DVec2, v: DVec2, edges: impl Iterator<Item = (DVec2, DVec2)>) -> i32 {
    let d = v - c;
    let mut w = 0;
    for (a, b) in edges {
        let (sa, sb) = (d.perp_dot(a - c) > 0.0, d.perp_dot(b - c) > 0.0);
        if sa != sb {
            let e = b - a;
            let (oc, ov) = (e.perp_dot(c - a), e.perp_dot(v - a));
            if (oc > 0.0 && ov < 0.0) || (oc < 0.0 && ov > 0.0) {
                // Crossing from the right of c→v to its left means leaving the region.
                w += if sb { -1 } else { 1 };
            }
        }
    }
    w
}

impl Ctx<'_> {
    fn fan(&self, origin: DVec2) -> Fan<'_> {
        Fan {
            origin,
            density: self.density,
            fine: false,
            constant: None,
        }
    }

    fn cell(&self, s: &mut Scratch, v: usize) -> Cell {
        let z = self.del.pos[v];
        // Delaunay neighbours in CCW order; the face between consecutive ones is (v, n_i, n_i+1)
        // unless it is the outer face (a hull vertex, whose cell is unbounded).
        s.nb.clear();
        let (ring, outer) = self.del.rings.of(v);
        let mut bounded = !outer.contains(&true);
        s.nb.extend(ring.iter().map(|&u| (u, self.del.pos[u as usize])));
        s.k.clear();
        if bounded {
            let n = s.nb.len();
            for i in 0..n {
                let cc = canonical_circumcenter((v as u32, z), s.nb[i], s.nb[(i + 1) % n]) - z;
                if !cc.is_finite() {
                    bounded = false;
                    break;
                }
                s.k.push(cc);
            }
        }
        if bounded && s.k.len() >= 3 {
            let (lo, hi) = bbox(&s.k);
            if self.bnd.box_inside(z + lo, z + hi) {
                // Where ρ is one constant over the cell (a size field's plateau), its moments
                // are that multiple of the exact ones: no quadrature.
                let fan = Fan {
                    constant: self.density.and_then(|d| d.constant_over(z + lo, z + hi)),
                    ..self.fan(z)
                };
                return self.finish(
                    fan.polygon(&s.k),
                    DVec2::ZERO,
                    z,
                    max_norm(&s.k),
                    Vec::new(),
                );
            }
        }
        self.clipped(s, z)
    }

    /// Turn moments about the origin z + c into a cell.
    fn finish(&self, mom: Mom, c: DVec2, z: DVec2, h: f64, pieces: Vec<PieceId>) -> Cell {
        let a = mom.a;
        if a.is_nan() || a <= 0.0 || a.is_infinite() {
            return Cell {
                h,
                pieces,
                ..Cell::empty(z)
            };
        }
        let g = DVec2::new(mom.sx, mom.sy) / a;
        let mxx = (mom.sxx / a - g.x * g.x).max(0.0);
        let mxy = mom.sxy / a - g.x * g.y;
        let myy = (mom.syy / a - g.y * g.y).max(0.0);
        let gz = c + g;
        let centroid = z + gz;
        let (mass, mass_centroid, energy) = match self.density {
            None => (a, centroid, a * (mxx + myy + gz.length_squared())),
            Some(_) => {
                let mx = DVec2::new(mom.mx, mom.my);
                let mc = if mom.m > 0.0 {
                    z + c + mx / mom.m
                } else {
                    centroid
                };
                (
                    mom.m,
                    mc,
                    mom.mr2 + 2.0 * c.dot(mx) + c.length_squared() * mom.m,
                )
            }
        };
        Cell {
            area: a,
            centroid,
            second_moment: [mxx, mxy, myy],
            mass,
            mass_centroid,
            energy,
            h,
            pieces,
        }
    }

    /// A cell that may reach the boundary.
    fn clipped(&self, s: &mut Scratch, z: DVec2) -> Cell {
        let bnd = self.bnd;
        // The convex Voronoi cell within the box around Ω, relative to z.
        let (blo, bhi) = (bnd.lo - z, bnd.hi - z);
        s.k.clear();
        s.k.extend([blo, DVec2::new(bhi.x, blo.y), bhi, DVec2::new(blo.x, bhi.y)]);
        for &(_, p) in &s.nb {
            let r = p - z;
            let half = 0.5 * r.length_squared();
            clip_closed(&s.k, &mut s.tmp, |x| half - r.dot(x));
            std::mem::swap(&mut s.k, &mut s.tmp);
        }
        let (klo, khi) = bbox(&s.k);
        let diam = (khi - klo).length();
        dedupe(&mut s.k, 1e-12 * diam);
        if s.k.len() < 3 {
            return Cell::empty(z);
        }
        // The density's moments are wanted only if the cell meets no boundary (below).
        let kmom = Fan {
            density: None,
            ..self.fan(z)
        }
        .polygon(&s.k);
        if kmom.a.is_nan() || kmom.a <= 1e-14 * diam * diam {
            return Cell {
                h: max_norm(&s.k),
                ..Cell::empty(z)
            };
        }

        // Boundary edges near the cell (all edges that meet the slightly grown bounding box).
        let delta = 1e-6 * diam + 1e-12 * (bnd.hi - bnd.lo).max_element();
        let (glo, ghi) = (z + klo - DVec2::splat(delta), z + khi + DVec2::splat(delta));
        let epoch = s.next_epoch();
        s.near.clear();
        bnd.edges_near(glo, ghi, |e| {
            let ei = e as usize;
            if s.stamp[ei] != epoch {
                s.stamp[ei] = epoch;
                if segment_meets_box(bnd.a[ei], bnd.b[ei], glo, ghi) {
                    s.near.push(e);
                }
            }
        });
        s.near.sort_unstable();

        // Pieces touched (with a hair of tolerance) and the farthest genuine boundary points.
        let tol = 1e-10 * diam;
        let mut h = 0.0f64;
        let mut meets = false;
        s.pieces.clear();
        for &e in &s.near {
            let (a, b) = (bnd.a[e as usize] - z, bnd.b[e as usize] - z);
            if clip_segment(a, b, &s.k, tol).is_some() {
                s.pieces.push(bnd.piece[e as usize]);
            }
            if let Some((t0, t1)) = clip_segment(a, b, &s.k, 0.0) {
                meets = true;
                h = h.max(a.lerp(b, t0).length()).max(a.lerp(b, t1).length());
            }
        }
        s.pieces.sort_unstable();
        s.pieces.dedup();
        let pieces = s.pieces.clone();
        if !meets {
            // The cell lies on one side of the boundary: z (not on it) tells which.
            return if bnd.inside(z) {
                let mom = match self.density {
                    Some(_) => self.fan(z).polygon(&s.k),
                    None => kmom,
                };
                self.finish(mom, DVec2::ZERO, z, max_norm(&s.k), pieces)
            } else {
                Cell {
                    pieces,
                    ..Cell::empty(z)
                }
            };
        }

        let diam = if self.density.is_some() {
            self.drop_far_outside(s, z, h + delta, diam)
        } else {
            diam
        };
        let c = self.reference_point(s, z, diam);
        let wc = bnd.winding(z + c);
        // A size field toward a loop is smallest on it, so ρ changes most across the cells
        // that reach the boundary (by half or more across one cell where the field grows by
        // 0.2 of the distance), and one 7-point rule per fan triangle leaves errors there
        // larger than the energy changes near convergence. Four sub-triangles per fan
        // triangle cost about a fifth more per graded evaluation (docs/design-notes.md,
        // "Refinement toward a wall").
        let fan = Fan {
            fine: true,
            ..self.fan(z + c)
        };
        // The fan moments of the convex cell's edges are summed at the end, each as many
        // times as the clipped cell's boundary runs along it: an edge outside Ω (about half of
        // them) costs no quadrature at all.
        let m = s.k.len();
        s.phi.clear();
        s.phi.push(0.0);
        for i in 0..m {
            let (p, q) = (s.k[i] - c, s.k[(i + 1) % m] - c);
            let a = s.phi[i] + angle(p, q);
            s.phi.push(a);
        }
        s.uses.clear();
        s.uses.resize(m, 0);

        // Runs of consecutive nearby edges of one ring.
        s.runs.clear();
        let mut i = 0;
        while i < s.near.len() {
            let mut j = i + 1;
            while j < s.near.len()
                && s.near[j] == s.near[j - 1] + 1
                && bnd.ring[s.near[j] as usize] == bnd.ring[s.near[i] as usize]
            {
                j += 1;
            }
            s.runs.push((i, j));
            i = j;
        }
        let mut mom = Mom::default();
        let mut sweep = 0.0;
        let mut r = 0;
        while r < s.runs.len() {
            let ring = bnd.ring[s.near[s.runs[r].0] as usize] as usize;
            let mut r_end = r;
            while r_end + 1 < s.runs.len()
                && bnd.ring[s.near[s.runs[r_end + 1].0] as usize] as usize == ring
            {
                r_end += 1;
            }
            let (rs, re) = bnd.ring_range[ring];
            let (first, last) = (s.runs[r], s.runs[r_end]);
            let starts_ring = s.near[first.0] == rs;
            let ends_ring = s.near[last.1 - 1] == re - 1;
            if r == r_end && first.1 - first.0 == (re - rs) as usize {
                // The whole ring is near: an ordinary closed clip.
                s.chain.clear();
                s.chain.extend(
                    s.near[first.0..first.1]
                        .iter()
                        .map(|&e| bnd.a[e as usize] - z),
                );
                self.clip_chain(s, true);
                let n = s.chain.len();
                for t in 0..n {
                    let (p, q) = (s.chain[t] - c, s.chain[(t + 1) % n] - c);
                    mom += fan.tri(p, q);
                    sweep += angle(p, q);
                }
            } else {
                // Open chains; the run that ends the ring continues into the one that starts it.
                let merge = starts_ring && ends_ring && r != r_end;
                let mut k = r;
                while k <= r_end {
                    if merge && k == r {
                        k += 1;
                        continue;
                    }
                    s.chain.clear();
                    let (a0, a1) = s.runs[k];
                    s.chain.push(bnd.a[s.near[a0] as usize] - z);
                    s.chain
                        .extend(s.near[a0..a1].iter().map(|&e| bnd.b[e as usize] - z));
                    if merge && k == r_end {
                        s.chain.extend(
                            s.near[first.0..first.1]
                                .iter()
                                .map(|&e| bnd.b[e as usize] - z),
                        );
                    }
                    self.clip_chain(s, false);
                    if let (Some(&start), Some(&end)) = (s.chain.first(), s.chain.last()) {
                        for t in 1..s.chain.len() {
                            let (p, q) = (s.chain[t - 1] - c, s.chain[t] - c);
                            mom += fan.tri(p, q);
                            sweep += angle(p, q);
                        }
                        let (is, fs, ps) = self.on_cell_boundary(s, fan, c, start);
                        let (ie, fe, pe) = self.on_cell_boundary(s, fan, c, end);
                        // The whole edges before `is`, less those before `ie`: once each
                        // from `ie` up to `is`, or taken off from `is` up to `ie`.
                        s.uses[is] -= 1;
                        s.uses[ie] += 1;
                        mom += fs - fe;
                        sweep += ps - pe;
                    }
                    k += 1;
                }
            }
            r = r_end + 1;
        }
        let turns = (TAU * wc as f64 - sweep) / TAU;
        let whole = turns.round();
        if !self.whole_rings && (turns - whole).abs() < 0.1 {
            let mut uses = whole as i32;
            for i in 0..m {
                uses += s.uses[i];
                if uses != 0 {
                    let (p, q) = (s.k[i] - c, s.k[(i + 1) % m] - c);
                    mom += fan.tri(p, q) * uses as f64;
                }
            }
        } else {
            // Inconsistent angles (a degenerate configuration): clip whole rings instead.
            mom = self.clip_whole_rings(s, z, c, fan);
        }

        // Vertices of the convex cell that lie in Ω are farthest-point candidates too.
        for &kv in &s.k {
            let w = wc
                + crossings(
                    c,
                    kv,
                    s.near
                        .iter()
                        .map(|&e| (bnd.a[e as usize] - z, bnd.b[e as usize] - z)),
                );
            if w > 0 {
                h = h.max(kv.length());
            }
        }
        self.finish(mom, c, z, h, pieces)
    }

    /// Cut the convex cell `s.k` down to the smallest box |x − z|∞ ≤ r that holds every
    /// boundary point in it (all within `reach` of z) and every vertex of it inside Ω, and
    /// return the cell's new diameter (`diam` if it is kept whole).
    ///
    /// A generator on the hull, or on a shore facing land, has a convex cell that runs far
    /// beyond its part in Ω: to the box around Ω, or across the land. The fan triangles would
    /// span the whole convex cell, and the density's quadrature does not cancel over
    /// triangles hundreds of spacings long (a corner cell of the lake gets a negative mass and
    /// an energy 10³ times its own).
    /// Each part of the cell beyond the box meets no boundary, so it lies wholly inside or
    /// wholly outside Ω; it holds a vertex of the cell (a part without one would lie along a
    /// single edge whose two ends are in the box), which is outside Ω. Exact moments do not
    /// change; only where the triangles lie.
    fn drop_far_outside(&self, s: &mut Scratch, z: DVec2, reach: f64, diam: f64) -> f64 {
        if max_norm(&s.k) <= 2.0 * reach {
            return diam;
        }
        let r =
            s.k.iter()
                .filter(|&&v| self.bnd.inside(z + v))
                .fold(reach, |r, v| r.max(v.x.abs()).max(v.y.abs()));
        let r = 1.01 * r;
        if max_norm(&s.k) <= 2.0 * r {
            return diam;
        }
        for (axis, sign) in [
            (DVec2::X, 1.0),
            (DVec2::X, -1.0),
            (DVec2::Y, 1.0),
            (DVec2::Y, -1.0),
        ] {
            clip_closed(&s.k, &mut s.tmp, |x| r - sign * axis.dot(x));
            std::mem::swap(&mut s.k, &mut s.tmp);
        }
        let (klo, khi) = bbox(&s.k);
        let diam = (khi - klo).length();
        dedupe(&mut s.k, 1e-12 * diam);
        diam
    }

    /// Clip `s.chain` (closed ring or open polyline) by every edge of the convex cell `s.k`.
    fn clip_chain(&self, s: &mut Scratch, closed: bool) {
        let m = s.k.len();
        for i in 0..m {
            if s.chain.is_empty() {
                return;
            }
            let f = edge_fn(s.k[i], s.k[(i + 1) % m]);
            if closed {
                clip_closed(&s.chain, &mut s.tmp, f);
            } else {
                clip_open(&s.chain, &mut s.tmp, f);
            }
            std::mem::swap(&mut s.chain, &mut s.tmp);
        }
    }

    /// For a point p on the cell boundary: the edge of the convex cell it lies on, the fan
    /// moments from that edge's first vertex to p, and the angle swept (about c) along the
    /// boundary from the cell's first vertex to p, counter-clockwise. The fan moments of the
    /// whole edges before it are the caller's to add.
    fn on_cell_boundary(&self, s: &Scratch, fan: Fan<'_>, c: DVec2, p: DVec2) -> (usize, Mom, f64) {
        let m = s.k.len();
        let mut best = (f64::INFINITY, 0);
        for i in 0..m {
            let d = segment_distance(p, s.k[i], s.k[(i + 1) % m]);
            if d < best.0 {
                best = (d, i);
            }
        }
        let i = best.1;
        let (u, q) = (s.k[i] - c, p - c);
        (i, fan.tri(u, q), s.phi[i] + angle(u, q))
    }

    /// A point inside the convex cell well away from every nearby boundary edge.
    fn reference_point(&self, s: &Scratch, z: DVec2, diam: f64) -> DVec2 {
        let bnd = self.bnd;
        let g = s.k.iter().copied().sum::<DVec2>() / s.k.len() as f64;
        let clearance = |p: DVec2| {
            s.near
                .iter()
                .map(|&e| segment_distance(p, bnd.a[e as usize] - z, bnd.b[e as usize] - z))
                .fold(f64::INFINITY, f64::min)
        };
        let mut best = (clearance(g), g);
        if best.0 >= 1e-6 * diam {
            return g;
        }
        for &kv in &s.k {
            for t in [0.5, 0.25, 0.75] {
                let p = g.lerp(kv, t);
                let d = clearance(p);
                if d >= 1e-6 * diam {
                    return p;
                }
                if d > best.0 {
                    best = (d, p);
                }
            }
        }
        best.1
    }

    /// Fallback: clip every ring of the domain as a closed polygon (cost linear in the
    /// number of boundary edges).
    fn clip_whole_rings(&self, s: &mut Scratch, z: DVec2, c: DVec2, fan: Fan<'_>) -> Mom {
        let bnd = self.bnd;
        let mut mom = Mom::default();
        for &(rs, re) in &bnd.ring_range {
            s.chain.clear();
            s.chain.extend((rs..re).map(|e| bnd.a[e as usize] - z));
            self.clip_chain(s, true);
            let n = s.chain.len();
            for t in 0..n {
                mom += fan.tri(s.chain[t] - c, s.chain[(t + 1) % n] - c);
            }
        }
        mom
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::{Ring, Rng};
    use std::sync::Arc;

    /// The local method (nearby edges, projected far parts, winding-number turns) against
    /// clipping whole rings, on a comb-shaped domain whose teeth cut cells into several parts.
    #[test]
    fn local_clipping_matches_whole_ring_clipping() {
        let mut outer = vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0)];
        for k in (0..5).rev() {
            let x = 0.2 * k as f64;
            outer.extend([
                DVec2::new(x + 0.2, 1.0),
                DVec2::new(x + 0.1, 1.0),
                DVec2::new(x + 0.1, 0.3),
                DVec2::new(x + 0.0, 0.3),
            ]);
        }
        let n = outer.len();
        let hole = vec![
            DVec2::new(0.45, 0.1),
            DVec2::new(0.45, 0.2),
            DVec2::new(0.55, 0.2),
            DVec2::new(0.55, 0.1),
        ];
        let domain = Polygon {
            rings: vec![
                Ring {
                    points: outer,
                    pieces: (0..n).collect(),
                    loop_index: 0,
                    hole: false,
                },
                Ring {
                    points: hole,
                    pieces: vec![n; 4],
                    loop_index: 1,
                    hole: true,
                },
            ],
        };
        // Base 1 × 0.3, five teeth 0.1 × 0.7, minus the hole.
        assert!((domain.area() - 0.64).abs() < 1e-14);
        let rho = Density::Function(Arc::new(|p: DVec2| 1.0 + p.x * p.y));
        let mut rng = Rng::new(17);
        for k in [3, 10, 40, 200] {
            let mut pts = Vec::new();
            while pts.len() < k {
                let p = DVec2::new(rng.uniform(), rng.uniform());
                if domain.contains(p) {
                    pts.push(p);
                }
            }
            pts.push(DVec2::new(0.45, 0.15));
            pts.push(DVec2::new(0.1, 0.3));
            let del = Delaunay::new(&pts);
            for density in [Density::Uniform, rho.clone()] {
                let run = |whole_rings| {
                    let mut cells = Cells { cells: Vec::new() };
                    let mut buffer = Vec::new();
                    cells_with(
                        &pts,
                        &del,
                        &DomainGrid::new(&domain, del.num_vertices()),
                        &density,
                        whole_rings,
                        &mut cells.cells,
                        &mut buffer,
                    );
                    cells
                };
                let (local, whole) = (run(false), run(true));
                assert!((local.total_area() - domain.area()).abs() < 1e-12);
                for (a, b) in local.cells.iter().zip(&whole.cells) {
                    assert!((a.area - b.area).abs() < 1e-13, "{} vs {}", a.area, b.area);
                    assert!((a.mass - b.mass).abs() < 1e-13);
                    assert!((a.centroid - b.centroid).length() < 1e-11);
                    assert!((a.energy - b.energy).abs() < 1e-13);
                    assert_eq!(a.pieces, b.pieces);
                }
            }
        }
    }

    /// Generators on the inner shores of a U have convex cells reaching across the gap; with a
    /// density that is not a polynomial the fan's quadrature must not be spread over the gap.
    #[test]
    fn cells_across_a_gap_integrate_the_density_where_they_lie() {
        let corners = [
            (0.0, 0.0),
            (20.0, 0.0),
            (20.0, 20.0),
            (15.0, 20.0),
            (15.0, 5.0),
            (5.0, 5.0),
            (5.0, 20.0),
            (0.0, 20.0),
        ];
        let domain = Polygon {
            rings: vec![Ring {
                points: corners.iter().map(|&(x, y)| DVec2::new(x, y)).collect(),
                pieces: (0..8).collect(),
                loop_index: 0,
                hole: false,
            }],
        };
        let rho = Density::Function(Arc::new(|p: DVec2| 1.0 + 0.9 * p.x.sin() * p.y.sin()));
        // ∫ρ over [a, b] × [c, d], exactly.
        let box_mass = |a: f64, b: f64, c: f64, d: f64| {
            (b - a) * (d - c) + 0.9 * (a.cos() - b.cos()) * (c.cos() - d.cos())
        };
        let exact = box_mass(0.0, 20.0, 0.0, 20.0) - box_mass(5.0, 15.0, 5.0, 20.0);
        let mut rng = Rng::new(3);
        let mut pts = Vec::new();
        for j in 0..80 {
            for i in 0..80 {
                let p = DVec2::new(0.25 * i as f64 + 0.125, 0.25 * j as f64 + 0.125)
                    + 0.05 * DVec2::new(rng.uniform() - 0.5, rng.uniform() - 0.5);
                if domain.contains(p) {
                    pts.push(p);
                }
            }
        }
        let cells = clipped_cells(&pts, &Delaunay::new(&pts), &domain, &rho);
        let total: f64 = cells.cells.iter().map(|c| c.mass).sum();
        assert!((total - exact).abs() < 1e-9 * exact, "{total} vs {exact}");
        for c in &cells.cells {
            // ρ lies in [0.1, 1.9], and the cell within h of its generator.
            assert!(c.mass >= 0.1 * c.area && c.mass <= 1.9 * c.area, "{c:?}");
            assert!(c.energy > 0.0 && c.energy <= c.mass * c.h * c.h, "{c:?}");
        }
    }

    /// The square [0, 1]², one piece per side.
    fn unit_square() -> Polygon {
        Polygon {
            rings: vec![Ring {
                points: vec![
                    DVec2::new(0.0, 0.0),
                    DVec2::new(1.0, 0.0),
                    DVec2::new(1.0, 1.0),
                    DVec2::new(0.0, 1.0),
                ],
                pieces: vec![0, 1, 2, 3],
                loop_index: 0,
                hole: false,
            }],
        }
    }

    /// ρ that falls by e⁻² across a cell from one side of the square, most of its mass in the
    /// cells on that side: they integrate it on four sub-triangles per fan triangle.
    #[test]
    fn cells_on_the_boundary_integrate_a_steep_density_finely() {
        let domain = unit_square();
        let rho = Density::Function(Arc::new(|p: DVec2| (-30.0 * p.x).exp()));
        let exact = (1.0 - (-30.0f64).exp()) / 30.0;
        let mut rng = Rng::new(9);
        let n = 16;
        let mut pts = Vec::new();
        for j in 0..n {
            for i in 0..n {
                pts.push(
                    DVec2::new(i as f64 + 0.5, j as f64 + 0.5) / n as f64
                        + 0.01 * DVec2::new(rng.uniform() - 0.5, rng.uniform() - 0.5),
                );
            }
        }
        let cells = clipped_cells(&pts, &Delaunay::new(&pts), &domain, &rho);
        let total: f64 = cells.cells.iter().map(|c| c.mass).sum();
        // 2.9e-7 so, 4.6e-6 with one 7-point rule per fan triangle.
        assert!((total - exact).abs() < 1e-6 * exact, "{total} vs {exact}");
    }

    /// Where a sampled density is one constant over an interior cell (a size field's far
    /// field), the cell's moments are that multiple of its exact polygon moments; the same
    /// cells integrated by quadrature (the density read through a function, which is never
    /// known constant) agree to rounding, near the point and far from it.
    #[test]
    fn cells_in_a_constant_far_field_equal_their_quadrature() {
        let region = geometry::Region::builtin("circle").unwrap();
        let domain = region.polygonize(1e-4);
        let t = geometry::Threshold {
            size_min: 0.05,
            size_max: 0.2,
            dist_min: 0.1,
            dist_max: 0.4,
        };
        let field =
            geometry::SizeField::threshold(&region, &[geometry::Toward::Point(DVec2::ZERO)], t)
                .unwrap();
        let sampled = field.density(0.05);
        let Density::Sampled(grid) = sampled.clone() else {
            panic!("a threshold field is sampled")
        };
        let read = Density::Function(Arc::new(move |p| grid.at(p)));
        let mut rng = Rng::new(11);
        let mut pts = Vec::new();
        while pts.len() < 3000 {
            let p = DVec2::new(2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0);
            if region.signed_distance(p) < -0.01 {
                pts.push(p);
            }
        }
        let far = pts
            .iter()
            .filter(|p| sampled.constant_over(**p - 0.05, **p + 0.05).is_some())
            .count();
        assert!(far > 1000, "{far} generators in the far field");
        let del = Delaunay::new(&pts);
        let (a, b) = (
            clipped_cells(&pts, &del, &domain, &sampled),
            clipped_cells(&pts, &del, &domain, &read),
        );
        for (x, y) in a.cells.iter().zip(&b.cells) {
            assert!((x.mass - y.mass).abs() <= 1e-12 * y.mass, "{x:?} vs {y:?}");
            assert!(
                (x.energy - y.energy).abs() <= 1e-12 * y.energy,
                "{x:?} vs {y:?}"
            );
            assert!(
                (x.mass_centroid - y.mass_centroid).length() <= 1e-12,
                "{x:?} vs {y:?}"
            );
        }
    }

    #[test]
    fn cells_into_reused_memory_equal_fresh_cells() {
        let domain = unit_square();
        let mut rng = Rng::new(5);
        let mut random = |n: usize| -> Vec<DVec2> {
            (0..n)
                .map(|_| DVec2::new(rng.uniform(), rng.uniform()))
                .collect()
        };
        let (a, b) = (random(400), random(150));
        let mut out = clipped_cells(&a, &Delaunay::new(&a), &domain, &Density::Uniform);
        let mut buffer = CellsBuffer::default();
        clipped_cells_into(
            &a,
            &Delaunay::new(&a),
            &domain,
            &Density::Uniform,
            &mut out,
            &mut buffer,
        );
        let del = Delaunay::new(&b);
        clipped_cells_into(&b, &del, &domain, &Density::Uniform, &mut out, &mut buffer);
        let fresh = clipped_cells(&b, &del, &domain, &Density::Uniform);
        assert_eq!(out.cells.len(), 150);
        for (x, y) in out.cells.iter().zip(&fresh.cells) {
            assert_eq!(x.area, y.area);
            assert_eq!(x.mass_centroid, y.mass_centroid);
            assert_eq!(x.energy, y.energy);
            assert_eq!(x.pieces, y.pieces);
        }
        assert!((out.total_area() - 1.0).abs() < 1e-12);
    }
}
