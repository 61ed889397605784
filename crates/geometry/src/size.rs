//! Size fields: a target edge length h(x) over a region, and the CVT density that realises it.
//!
//! Finite-element users think in edge lengths, CVT in densities. A converged CVT is locally a
//! lattice of regular hexagons whose spacing scales as ρ^(−1/4) in the plane, so the density
//! that gives spacing ∝ h is **ρ(x) = (h_min / h(x))⁴** ([`SizeField::density`]). A regular
//! hexagonal cell of spacing h has area (√3/2)h², so a field asks for about
//! **N ≈ (2/√3) ∫_Ω h(x)⁻² dx** vertices ([`SizeField::predicted_points`]).
//!
//! A field is a constant, an expression in `x` and `y` (parsed once, evaluated per point), or
//! values sampled once on a background grid over the region's bounding box and interpolated
//! by cubic B-splines ([`SizeField::from_samples`]): a user function is then called a single time on
//! every grid node at once, never point by point, which is what callers in array languages
//! need.
use crate::expr::{Expr, ExprError};
use crate::{DVec2, Density, Region};
use rayon::prelude::*;
use std::sync::Arc;
use thiserror::Error;

/// Why a size field cannot be used on a region.
#[derive(Debug, Error)]
pub enum SizeFieldError {
    /// The expression does not parse.
    #[error("size field '{text}': {source}")]
    Expr {
        /// The expression as given.
        text: String,
        /// Where and why it does not parse.
        source: ExprError,
    },
    /// The field is zero, negative, infinite or NaN somewhere on the region.
    #[error(
        "size field is {value} at ({x}, {y}){}: it must be positive and finite on the region",
        if *.on_boundary {
            " on the region's boundary, where an expression is evaluated too (rounding can put \
             a boundary point a hair outside a curve: sqrt(max(0, ...)) keeps a root real there)"
        } else {
            ""
        }
    )]
    NotPositive {
        /// The offending value.
        value: f64,
        /// Where (x).
        x: f64,
        /// Where (y).
        y: f64,
        /// The point is a vertex of the boundary's polygon.
        on_boundary: bool,
    },
    /// Sampled values do not match the grid.
    #[error("size field: {got} samples returned for {expected} grid nodes")]
    SampleCount {
        /// Values returned.
        got: usize,
        /// Grid nodes asked for.
        expected: usize,
    },
    /// Size bounds that are not edge lengths in order: the smallest finite and at least 0 (0
    /// bounds nothing), the largest positive (∞ bounds nothing), the smallest no larger.
    #[error("{}", bounds_message(*.min, *.max))]
    Bounds {
        /// The lower bound given, if any.
        min: Option<f64>,
        /// The upper bound given, if any.
        max: Option<f64>,
    },
    /// A gradation limit that is not a positive number.
    #[error("the gradation limit must be positive (or infinite to turn it off), got {0}")]
    Gradation(f64),
    /// A distance field names a boundary loop the region does not have.
    #[error("size field: the region has {loops} boundary loops (0 = outer, then the holes), so there is no loop {index}")]
    UnknownLoop {
        /// The loop asked for.
        index: usize,
        /// How many the region has.
        loops: usize,
    },
    /// A threshold whose sizes or distances are not positive, finite and ordered.
    #[error("size threshold: need 0 < h_min <= h_max and 0 <= d_min <= d_max (HMIN,HMAX,DMIN,DMAX), all finite; got sizes {size_min}, {size_max} and distances {dist_min}, {dist_max}")]
    Threshold {
        /// Size within `dist_min`.
        size_min: f64,
        /// Size beyond `dist_max`.
        size_max: f64,
        /// Distance up to which the size is `size_min`.
        dist_min: f64,
        /// Distance from which the size is `size_max`.
        dist_max: f64,
    },
    /// A distance target that is none of `loop:I`, `piece:J`, `marker:M`, `point:X,Y`.
    #[error("'{0}': expected loop:I (0 = outer, then the holes), piece:J, marker:M, line:L or point:X,Y")]
    Toward(String),
    /// A distance field names a wall marker no piece of the region has.
    #[error("size field: no boundary piece or line is marked {marker} ({})", match markers.is_empty() {
        true => "the region numbers no walls: a .poly's segment markers, a JSON segment's \
                 \"marker\" or markers given with the loops number them".to_string(),
        false => format!("the region's markers are {}", markers.iter().map(i64::to_string).collect::<Vec<_>>().join(", ")),
    })]
    UnknownMarker {
        /// The marker asked for.
        marker: i64,
        /// The region's markers, sorted, each once.
        markers: Vec<i64>,
    },
    /// A distance field names a boundary piece the region does not have.
    #[error("size field: the region has {pieces} boundary pieces (0 to {last}; `cvtmesh regions REGION` lists them), so there is no piece {index}", last = pieces.saturating_sub(1))]
    UnknownPiece {
        /// The piece asked for.
        index: usize,
        /// How many the region has.
        pieces: usize,
    },
    /// A distance field names an embedded line the region does not have.
    #[error("size field: the region has {lines} embedded line{} (`cvtmesh regions REGION` lists them), so there is no line {index}", if *lines == 1 { "" } else { "s" })]
    UnknownLine {
        /// The line asked for.
        index: usize,
        /// How many the region has.
        lines: usize,
    },
    /// A distance field with nothing to measure the distance to.
    #[error("size field: a distance field needs at least one loop or point to refine toward")]
    NothingToward,
    /// A background grid needs at least 2 nodes per side.
    #[error("size field: a background grid needs at least 2 nodes per side, got {0}")]
    GridTooSmall(usize),
    /// A background grid of more nodes per side than [`MAX_GRID_SIDE`].
    #[error(
        "size field: a background grid of {0} nodes per side is more than the {MAX_GRID_SIDE} \
         allowed (its n² values would not fit in memory)"
    )]
    GridTooLarge(usize),
    /// Sizes given on a mesh do not match its vertices.
    #[error("size field: {sizes} sizes for a mesh of {vertices} vertices (one size per vertex)")]
    MeshSizes {
        /// Sizes given.
        sizes: usize,
        /// Vertices of the mesh.
        vertices: usize,
    },
    /// A size given on a mesh that is not positive and finite.
    #[error(
        "size field: the size at vertex {vertex} is {value}; sizes must be positive and finite"
    )]
    MeshSize {
        /// The vertex (0-based).
        vertex: usize,
        /// Its size.
        value: f64,
    },
    /// A mesh vertex with a coordinate that is not finite.
    #[error("size field: vertex {vertex} of the mesh has a coordinate that is not finite")]
    MeshPoint {
        /// The vertex (0-based).
        vertex: usize,
    },
    /// A mesh triangle naming a vertex the mesh does not have.
    #[error("size field: triangle {triangle} refers to vertex {vertex}, but the mesh has {vertices} vertices")]
    MeshTriangle {
        /// The triangle (0-based).
        triangle: usize,
        /// The vertex it names (0-based).
        vertex: u32,
        /// Vertices of the mesh.
        vertices: usize,
    },
    /// Sizes given on a mesh without triangles.
    #[error("size field: the mesh has no triangles to interpolate the sizes on")]
    EmptyMesh,
    /// Sizes given on a mesh that leaves part of the region far from any of its triangles.
    #[error(
        "size field: the mesh of sizes does not cover the region: ({x}, {y}) in the region lies \
         {gap:.3e} from its nearest triangle, {:.0} % of the region's diameter (sizes are carried \
         to the region from the mesh's nearest point only up to {:.0} %, where a mesh of a \
         polygon inscribed in a curved boundary leaves slivers); is it the mesh of this \
         region, in the same units?",
        100.0 * gap / diameter,
        100.0 * crate::background::COVER_GAP
    )]
    MeshMissesRegion {
        /// The region's point farthest from the mesh (a centre of its inside grid).
        x: f64,
        /// Its ordinate.
        y: f64,
        /// Its distance to the mesh.
        gap: f64,
        /// The region's diameter.
        diameter: f64,
    },
}

/// What [`SizeFieldError::Bounds`] says: the first bound at fault, by the names Python and the
/// command line give it.
fn bounds_message(min: Option<f64>, max: Option<f64>) -> String {
    let (lo, hi) = (min.unwrap_or(0.0), max.unwrap_or(f64::INFINITY));
    if !(lo.is_finite() && lo >= 0.0) {
        format!("the smallest edge length (size_min, --size-min) must be finite and at least 0 (0 bounds nothing), got {lo}")
    } else if hi.is_nan() || hi <= 0.0 {
        format!("the largest edge length (size_max, --size-max) must be positive (inf bounds nothing), got {hi}")
    } else {
        format!("the smallest edge length (size_min, --size-min) {lo} is larger than the largest (size_max, --size-max) {hi}")
    }
}

/// Most nodes per side of a background grid ([`SizeField::from_samples`]): 8192² values take
/// half a GiB.
pub const MAX_GRID_SIDE: usize = 8192;

/// Nodes per side of a background grid over `region` fine enough for sizes down to `h_min`:
/// 4 per `h_min` across the longer side of its bounding box, from 64 up to `max`.
pub(crate) fn grid_side(region: &Region, h_min: f64, max: usize) -> usize {
    let (lo, hi) = region.bbox();
    ((4.0 * (hi - lo).max_element() / h_min).ceil() as usize).clamp(64, max)
}

/// Six times the uniform cubic B-spline weights of the four nodes around a point at `u` ∈
/// [0, 1] of its interval (nodes at −1, 0, 1, 2). The factor 1/6 of each axis is applied
/// once per interpolation, as a multiplication: the compiler keeps a division by 6 a
/// division, and the interpolation runs dozens of times per cell and evaluation.
#[inline]
fn bspline_weights_6(u: f64) -> [f64; 4] {
    let (u2, u3) = (u * u, u * u * u);
    let v = 1.0 - u;
    [
        v * v * v,
        3.0 * u3 - 6.0 * u2 + 4.0,
        -3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0,
        u3,
    ]
}

/// [`bspline_weights_6`] of eight values at once, by weight: entry `[a][k]` is weight a of
/// `u[k]` (laid out so that each weight is one operation on eight lanes).
#[inline(always)]
fn bspline_weights_6_lanes(u: &[f64; 8]) -> [[f64; 8]; 4] {
    let mut w = [[0.0f64; 8]; 4];
    for (k, &u) in u.iter().enumerate() {
        for (a, wa) in bspline_weights_6(u).into_iter().enumerate() {
            w[a][k] = wa;
        }
    }
    w
}

/// Whether an interpolated density is positive and finite (NaN fails both comparisons, which
/// compile to fewer instructions than `is_finite`).
#[inline]
fn usable(v: f64) -> bool {
    v > 0.0 && v < f64::INFINITY
}

/// A density sampled on a background grid and interpolated by cubic B-splines, as
/// [`SizeField::density`] makes it from a sampled field: [`Density::Sampled`].
#[derive(Clone, Debug)]
pub struct SampledDensity {
    grid: Grid,
}

impl SampledDensity {
    /// ρ at `p` (the nearest grid value's extension outside the grid's box).
    ///
    /// ```
    /// use cvtmesh::geometry::{Density, DVec2, Region, SizeField, Threshold, Toward};
    /// let region = Region::builtin("circle")?;
    /// let t = Threshold { size_min: 0.05, size_max: 0.2, dist_min: 0.3, dist_max: 0.7 };
    /// let h = SizeField::threshold(&region, &[Toward::Point(DVec2::ZERO)], t)?;
    /// let Density::Sampled(rho) = h.density(0.05) else { panic!("a sampled field") };
    /// // ρ = (h_min / h)⁴: 1 near the point, (0.05 / 0.2)⁴ near the unit circle.
    /// assert!((rho.at(DVec2::new(0.1, 0.0)) - 1.0).abs() < 1e-12);
    /// assert!((rho.at(DVec2::new(0.0, 0.95)) - 1.0 / 256.0).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn at(&self, p: DVec2) -> f64 {
        self.grid.at(p)
    }

    /// ρ at seven points: the same values as [`SampledDensity::at`] at each, computed side by
    /// side (a quadrature rule's points).
    #[inline]
    pub fn at7(&self, ps: &[DVec2; 7]) -> [f64; 7] {
        self.grid.at7(ps)
    }

    /// ρ where it is one constant over the whole box `lo`–`hi` (the far field of a size field
    /// that reaches its largest size), else None.
    ///
    /// ```
    /// use cvtmesh::geometry::{Density, DVec2, Region, SizeField, Threshold, Toward};
    /// let region = Region::builtin("circle")?;
    /// let t = Threshold { size_min: 0.05, size_max: 0.2, dist_min: 0.1, dist_max: 0.3 };
    /// let h = SizeField::threshold(&region, &[Toward::Point(DVec2::ZERO)], t)?;
    /// let Density::Sampled(rho) = h.density(0.05) else { panic!("a sampled field") };
    /// // Far from the point h is 0.2 everywhere: ρ = (0.05 / 0.2)⁴.
    /// let far = rho.constant_over(DVec2::new(0.6, 0.0), DVec2::new(0.7, 0.1));
    /// assert_eq!(far, Some(1.0 / 256.0));
    /// assert_eq!(rho.constant_over(DVec2::new(-0.1, -0.1), DVec2::new(0.1, 0.1)), None);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn constant_over(&self, lo: DVec2, hi: DVec2) -> Option<f64> {
        self.grid.constant_over(lo, hi)
    }
}

/// Values on a regular grid over a box, interpolated by cubic B-splines (clamped outside the
/// box).
#[derive(Clone, Debug)]
struct Grid {
    lo: DVec2,
    step: DVec2,
    /// 1 / `step`, set by [`Grid::sealed`].
    inv_step: DVec2,
    nx: usize,
    ny: usize,
    /// Row-major: node (i, j) at `values[j * nx + i]`, position `lo + (i, j) * step`.
    values: Vec<f64>,
    /// `values` with a border of one node on every side repeating its nearest node, (nx + 2)
    /// × (ny + 2) row-major, made by [`Grid::sealed`]: every 4 × 4 stencil of the B-spline
    /// then lies inside it, so an evaluation reads four runs of four values with no clamping
    /// per node. The interpolation is most of a graded run's time.
    padded: Vec<f64>,
    /// Per tile of `FLAT_TILE` × `FLAT_TILE` grid intervals (row-major, `flat_nx` per row): the
    /// value every node its B-spline reads holds, where they all hold the same, else NaN. Made
    /// by [`Grid::tiled`] (empty otherwise); see [`Grid::constant_over`].
    flat: Vec<f64>,
    flat_nx: usize,
}

/// Grid intervals per side of a tile of [`Grid::constant_over`]'s map.
const FLAT_TILE: usize = 8;

impl Grid {
    /// The grid with `padded` made from `values`; call it once the values are final.
    fn sealed(mut self) -> Grid {
        let (nx, ny) = (self.nx, self.ny);
        let mut padded = Vec::with_capacity((nx + 2) * (ny + 2));
        for j in 0..ny + 2 {
            let row = &self.values[j.saturating_sub(1).min(ny - 1) * nx..][..nx];
            padded.push(row[0]);
            padded.extend_from_slice(row);
            padded.push(row[nx - 1]);
        }
        self.padded = padded;
        self.inv_step = 1.0 / self.step;
        self
    }

    /// The grid with its map of constant tiles ([`Grid::constant_over`]) made: a density's
    /// grid, which the cells read, not a size field's.
    fn tiled(mut self) -> Grid {
        let (nx, ny) = (self.nx, self.ny);
        // Interval i of an axis reads nodes i − 1 … i + 2, padded nodes i … i + 3; a tile of
        // intervals t·T … t·T + T − 1 reads padded nodes t·T … t·T + T + 2.
        let w = nx + 2;
        let (tx, ty) = ((nx - 1).div_ceil(FLAT_TILE), (ny - 1).div_ceil(FLAT_TILE));
        let tile = |t: usize| {
            let (ti, tj) = (t % tx, t / tx);
            let (i0, j0) = (ti * FLAT_TILE, tj * FLAT_TILE);
            let (i1, j1) = (
                (i0 + FLAT_TILE + 2).min(nx + 1),
                (j0 + FLAT_TILE + 2).min(ny + 1),
            );
            let first = self.padded[j0 * w + i0];
            let same = (j0..=j1).all(|j| {
                self.padded[j * w + i0..=j * w + i1]
                    .iter()
                    .all(|v| v.to_bits() == first.to_bits())
            });
            if same && usable(first) {
                first
            } else {
                f64::NAN
            }
        };
        self.flat = (0..tx * ty).into_par_iter().map(tile).collect();
        self.flat_nx = tx;
        self
    }

    /// The B-spline's value where it is the same constant over the whole box `lo`–`hi` (every
    /// node it reads there holds that value), else None: a cell inside such a box has ρ's
    /// moments as exact multiples of its area's, with no quadrature.
    #[inline]
    fn constant_over(&self, lo: DVec2, hi: DVec2) -> Option<f64> {
        let cell = |p: DVec2| {
            let t = (p - self.lo) * self.inv_step;
            let i = (t.x.clamp(0.0, (self.nx - 1) as f64) as usize).min(self.nx - 2);
            let j = (t.y.clamp(0.0, (self.ny - 1) as f64) as usize).min(self.ny - 2);
            (i / FLAT_TILE, j / FLAT_TILE)
        };
        if self.flat.is_empty() {
            return None;
        }
        let ((i0, j0), (i1, j1)) = (cell(lo), cell(hi));
        let first = self.flat[j0 * self.flat_nx + i0];
        if first.is_nan() {
            return None;
        }
        for j in j0..=j1 {
            for i in i0..=i1 {
                if self.flat[j * self.flat_nx + i].to_bits() != first.to_bits() {
                    return None;
                }
            }
        }
        Some(first)
    }

    /// The same grid holding other values (one per node), sealed.
    fn with_values(&self, values: Vec<f64>) -> Grid {
        Grid {
            lo: self.lo,
            step: self.step,
            inv_step: self.inv_step,
            nx: self.nx,
            ny: self.ny,
            values,
            padded: Vec::new(),
            flat: Vec::new(),
            flat_nx: 0,
        }
        .sealed()
    }

    /// The node inside `region` whose value a neighbour inside exceeds by the largest factor,
    /// with that neighbour's value; `None` without two such nodes with positive values. Each
    /// pair of neighbours is looked at once, from its first node in row order.
    fn steepest_rise(&self, region: &Region) -> Option<Unresolved> {
        let (nx, ny) = (self.nx, self.ny);
        let inside = self.inside(region);
        let value = |k: usize| {
            let v = self.values[k];
            if inside[k] && v.is_finite() && v > 0.0 {
                v
            } else {
                f64::NAN
            }
        };
        // (factor, node, neighbour's value), the larger factor first, then the earlier node.
        let better = |a: (f64, usize, f64), b: (f64, usize, f64)| {
            if b.0 > a.0 || (b.0 == a.0 && b.1 < a.1) {
                b
            } else {
                a
            }
        };
        let none = (0.0, usize::MAX, 0.0);
        let best = (0..ny)
            .into_par_iter()
            .map(|j| {
                let mut best = none;
                for i in 0..nx {
                    let k = j * nx + i;
                    let v = value(k);
                    if v.is_nan() {
                        continue;
                    }
                    // The neighbours after (i, j) in row order: east, then the row above.
                    let east = (i + 1 < nx).then_some(k + 1);
                    let above = (j + 1 < ny).then_some(k + nx);
                    let north_west = (i > 0 && j + 1 < ny).then(|| k + nx - 1);
                    let north_east = (i + 1 < nx && j + 1 < ny).then(|| k + nx + 1);
                    for m in [east, north_west, above, north_east].into_iter().flatten() {
                        let w = value(m);
                        if w.is_nan() {
                            continue;
                        }
                        best = if w >= v {
                            better(best, (w / v, k, w))
                        } else {
                            better(best, (v / w, m, v))
                        };
                    }
                }
                best
            })
            .reduce(|| none, better);
        (best.1 != usize::MAX).then(|| {
            let k = best.1;
            Unresolved {
                at: self.lo + self.step * DVec2::new((k % nx) as f64, (k / nx) as f64),
                size: self.values[k],
                neighbour: best.2,
                step: self.step.max_element(),
                side: nx.max(ny),
            }
        })
    }

    /// Which nodes lie inside `region`, row by row: the crossings of each row's line with the
    /// boundary polygon, sorted, bound the inside stretches (even–odd rule). O(nodes + edges ×
    /// rows they span).
    fn inside(&self, region: &Region) -> Vec<bool> {
        let (nx, ny) = (self.nx, self.ny);
        let poly = region.polygonize(0.05 * self.step.min_element());
        let mut crossings: Vec<Vec<f64>> = vec![Vec::new(); ny];
        for ring in &poly.rings {
            let m = ring.points.len();
            for i in 0..m {
                let (a, b) = (ring.points[i], ring.points[(i + 1) % m]);
                let (ya, yb) = (
                    (a.y - self.lo.y) / self.step.y,
                    (b.y - self.lo.y) / self.step.y,
                );
                // Rows j with min(ya, yb) <= j < max(ya, yb): each crossing counted once.
                let (lo, hi) = (ya.min(yb), ya.max(yb));
                let first = lo.ceil().max(0.0) as usize;
                let last = (hi.ceil() as isize - 1).min(ny as isize - 1);
                for j in first as isize..=last {
                    let t = (j as f64 - ya) / (yb - ya);
                    crossings[j as usize].push(a.x + t * (b.x - a.x));
                }
            }
        }
        let mut inside = vec![false; nx * ny];
        for (j, xs) in crossings.iter_mut().enumerate() {
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                let from = ((pair[0] - self.lo.x) / self.step.x).ceil().max(0.0) as usize;
                let to = ((pair[1] - self.lo.x) / self.step.x).floor();
                if to < 0.0 {
                    continue;
                }
                for i in from..=(to as usize).min(nx - 1) {
                    inside[j * nx + i] = true;
                }
            }
        }
        inside
    }

    /// Give every node outside `region` the mean of its already-set neighbours, layer by
    /// layer outward from the nodes inside (a constant extension across ∂Ω). Cells of a
    /// boundary generator reach outside Ω and their moments are sums of signed triangles that
    /// cover the outside part too; their quadrature errors cancel only where ρ is as smooth
    /// out there as inside, and a distance field has a kink on the loop it measures to.
    fn extend_outside(&mut self, inside: Vec<bool>) {
        let (nx, ny) = (self.nx, self.ny);
        let outside: Vec<bool> = inside.iter().map(|&i| !i).collect();
        let mut set = inside;
        if !set.iter().any(|&s| s) {
            return;
        }
        let usable = |v: f64| v.is_finite() && v > 0.0;
        // Inside nodes whose sample is unusable are left as they are, and are no source.
        for (s, v) in set.iter_mut().zip(&self.values) {
            *s &= usable(*v);
        }
        let neighbours = |k: usize| {
            let (i, j) = ((k % nx) as isize, (k / nx) as isize);
            [(-1, 0), (1, 0), (0, -1), (0, 1)]
                .into_iter()
                .map(move |(di, dj)| (i + di, j + dj))
                .filter(move |&(a, b)| a >= 0 && b >= 0 && a < nx as isize && b < ny as isize)
                .map(move |(a, b)| b as usize * nx + a as usize)
        };
        // Only the nodes outside take values: an inside node's sample stays as it is, for
        // the field's check to refuse.
        let mut front: Vec<usize> = (0..nx * ny)
            .filter(|&k| outside[k] && neighbours(k).any(|u| set[u]))
            .collect();
        // A layer's values come from the layers before it only, so the order within a layer
        // does not matter: the next one is collected unsorted, each node once (`queued`).
        let mut queued = vec![false; nx * ny];
        let mut values = Vec::new();
        while !front.is_empty() {
            values.clear();
            values.extend(front.iter().map(|&k| {
                let (sum, n) = neighbours(k)
                    .filter(|&u| set[u])
                    .fold((0.0, 0usize), |(s, n), u| (s + self.values[u], n + 1));
                sum / n as f64
            }));
            for (&k, &v) in front.iter().zip(&values) {
                self.values[k] = v;
                set[k] = true;
            }
            let mut next = Vec::with_capacity(front.len() + 8);
            for &k in &front {
                for u in neighbours(k) {
                    if outside[u] && !set[u] && !queued[u] {
                        queued[u] = true;
                        next.push(u);
                    }
                }
            }
            front = next;
        }
    }

    /// h_i ← min(h_i, h_j + g |x_i − x_j|) over the eight neighbours until nothing changes:
    /// the two passes of a distance transform, then Gauss–Seidel rounds over all eight in
    /// alternating directions until one changes nothing.
    fn limit_gradation(&mut self, g: f64) {
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        let (dx, dy) = (self.step.x, self.step.y);
        let diag = (dx * dx + dy * dy).sqrt();
        let mut offsets = Vec::new();
        for (di, dj) in NEIGHBOURS {
            let d = match (di, dj) {
                (0, _) => dy,
                (_, 0) => dx,
                _ => diag,
            };
            offsets.push((di, dj, g * d));
        }
        // One pass forward with the four neighbours before each node in row order, one back
        // with the other four: every shortest path of axis and diagonal steps can be ordered
        // into the first pass's steps followed by the second's, so these two passes alone
        // reach the limit up to rounding (the two-pass distance transform of Rosenfeld and
        // Pfaltz). The rounds after them settle the last bits, and stop when one changes
        // nothing; the limit is the least path sum at every node, whatever the order of the
        // updates that reach it.
        let (forward, backward) = offsets.split_at(4);
        sweep(&mut self.values, nx, ny, forward, false, false);
        sweep(&mut self.values, nx, ny, backward, true, true);
        for round in 0.. {
            if !sweep(
                &mut self.values,
                nx,
                ny,
                &offsets,
                round % 2 == 1,
                (round / 2) % 2 == 1,
            ) {
                break;
            }
        }
    }

    /// The cubic B-spline of the samples: twice continuously differentiable, so that the CVT
    /// energy's quadrature varies smoothly as cells move over the grid (Newton's method stalls
    /// on the kinks of a bilinear interpolant), and a convex combination of sixteen samples,
    /// so positive wherever they are. It reproduces fields linear in x and y. Where a sample it
    /// reads is not positive and finite (outside the region), the bilinear value instead.
    #[inline]
    fn at(&self, p: DVec2) -> f64 {
        let t = (p - self.lo) * self.inv_step;
        let (fx, fy) = (
            t.x.clamp(0.0, (self.nx - 1) as f64),
            t.y.clamp(0.0, (self.ny - 1) as f64),
        );
        // The interval's indices as floating-point numbers (exact), as `at7` takes them.
        let (i, j) = (
            fx.floor().min((self.nx - 2) as f64),
            fy.floor().min((self.ny - 2) as f64),
        );
        let (wx, wy) = (bspline_weights_6(fx - i), bspline_weights_6(fy - j));
        let v = self.stencil_sum((j * (self.nx + 2) as f64 + i) as usize, &wx, &wy);
        if usable(v) {
            v
        } else {
            self.bilinear(p)
        }
    }

    /// The B-spline's sum over the 4 × 4 stencil of interval (i, j) with the weights (times 6)
    /// of each axis; `start` = j·(nx + 2) + i, the stencil's first node in `padded` (node
    /// (i + a − 1, j + b − 1), clamped to the grid, is padded node (i + a, j + b)).
    #[inline(always)]
    fn stencil_sum(&self, start: usize, wx: &[f64; 4], wy: &[f64; 4]) -> f64 {
        let w = self.nx + 2;
        let mut v = 0.0;
        for (b, wy) in wy.iter().enumerate() {
            let row: &[f64; 4] = self.padded[start + b * w..][..4]
                .try_into()
                .expect("a run of four");
            let mut r = 0.0;
            for (wx, value) in wx.iter().zip(row) {
                r += wx * value;
            }
            v += wy * r;
        }
        v * (1.0 / 36.0)
    }

    /// [`Grid::at`] at seven points at once, the same arithmetic per point (so the same
    /// values bit for bit) laid out lane by lane, so that the index and weight arithmetic runs
    /// in vector registers and the sixteen reads of every point overlap. That arithmetic is
    /// written out here rather than shared with `at` through a per-point helper: called once
    /// per point, the helper made the graded cells a fifth slower.
    #[inline]
    fn at7(&self, ps: &[DVec2; 7]) -> [f64; 7] {
        const L: usize = 8;
        let (mx, my) = ((self.nx - 1) as f64, (self.ny - 1) as f64);
        let (ix, iy) = ((self.nx - 2) as f64, (self.ny - 2) as f64);
        let w = (self.nx + 2) as f64;
        // Lane by lane (the eighth lane repeats the last point), and the interval's indices as
        // floating-point numbers (exact): every step is one operation on eight lanes, and only
        // the start of each point's stencil is converted to an integer.
        let (mut fx, mut fy) = ([0.0f64; L], [0.0f64; L]);
        for k in 0..L {
            let t = (ps[k.min(6)] - self.lo) * self.inv_step;
            fx[k] = t.x.clamp(0.0, mx);
            fy[k] = t.y.clamp(0.0, my);
        }
        let (mut u, mut v, mut start) = ([0.0f64; L], [0.0f64; L], [0.0f64; L]);
        for k in 0..L {
            let (i, j) = (fx[k].floor().min(ix), fy[k].floor().min(iy));
            u[k] = fx[k] - i;
            v[k] = fy[k] - j;
            start[k] = j * w + i;
        }
        // The weights of node a (b) of every point, across the lanes.
        let (wxl, wyl) = (bspline_weights_6_lanes(&u), bspline_weights_6_lanes(&v));
        let mut out = [0.0f64; 7];
        for k in 0..7 {
            let wx = [wxl[0][k], wxl[1][k], wxl[2][k], wxl[3][k]];
            let wy = [wyl[0][k], wyl[1][k], wyl[2][k], wyl[3][k]];
            out[k] = self.stencil_sum(start[k] as usize, &wx, &wy);
        }
        if !out.iter().all(|&v| usable(v)) {
            for (v, p) in out.iter_mut().zip(ps) {
                if !usable(*v) {
                    *v = self.bilinear(*p);
                }
            }
        }
        out
    }

    #[cold]
    fn bilinear(&self, p: DVec2) -> f64 {
        let t = (p - self.lo) / self.step;
        let fx = t.x.clamp(0.0, (self.nx - 1) as f64);
        let fy = t.y.clamp(0.0, (self.ny - 1) as f64);
        let i = (fx.floor() as usize).min(self.nx - 2);
        let j = (fy.floor() as usize).min(self.ny - 2);
        let (u, v) = (fx - i as f64, fy - j as f64);
        let at = |i: usize, j: usize| self.values[j * self.nx + i];
        (1.0 - v) * ((1.0 - u) * at(i, j) + u * at(i + 1, j))
            + v * ((1.0 - u) * at(i, j + 1) + u * at(i + 1, j + 1))
    }
}

#[derive(Clone, Debug)]
enum Kind {
    Constant(f64),
    Expr(Arc<Expr>),
    Grid(Arc<Grid>),
}

/// What a distance field measures the distance to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Toward {
    /// A boundary loop: 0 the outer one, then the holes in order.
    Loop(usize),
    /// One boundary piece (a side, an arc: a wall where a boundary layer forms), numbered as
    /// [`Region::pieces`] lists them (`cvtmesh regions REGION` prints them).
    Piece(usize),
    /// A point (a source, a re-entrant corner).
    Point(DVec2),
    /// Every piece with this marker, where the region file numbers its walls
    /// ([`Region::piece_markers`], a Triangle `.poly`'s segment markers), and every embedded
    /// line with it.
    Marker(i64),
    /// An embedded line (a material interface, a crack), numbered as
    /// [`Region::embedded_lines`] lists them (`cvtmesh regions REGION` prints them).
    Line(usize),
}

impl std::str::FromStr for Toward {
    type Err = SizeFieldError;

    /// `loop:I` (0 the outer loop, then the holes), `piece:J`, `marker:M`, `line:L` or
    /// `point:X,Y`, as the command line and the Python package take them.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Toward};
    /// assert_eq!("loop:1".parse::<Toward>()?, Toward::Loop(1));
    /// assert_eq!("piece:3".parse::<Toward>()?, Toward::Piece(3));
    /// assert_eq!("marker:-2".parse::<Toward>()?, Toward::Marker(-2));
    /// assert_eq!("line:0".parse::<Toward>()?, Toward::Line(0));
    /// assert_eq!("point: 0.5, 0.25".parse::<Toward>()?, Toward::Point(DVec2::new(0.5, 0.25)));
    /// assert!("corner:1".parse::<Toward>().is_err());
    /// # Ok::<(), cvtmesh::geometry::SizeFieldError>(())
    /// ```
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let bad = || SizeFieldError::Toward(text.to_string());
        let (kind, rest) = text.split_once(':').ok_or_else(bad)?;
        match kind.trim() {
            "loop" => Ok(Toward::Loop(rest.trim().parse().map_err(|_| bad())?)),
            "piece" => Ok(Toward::Piece(rest.trim().parse().map_err(|_| bad())?)),
            "marker" => Ok(Toward::Marker(rest.trim().parse().map_err(|_| bad())?)),
            "line" => Ok(Toward::Line(rest.trim().parse().map_err(|_| bad())?)),
            "point" => {
                let (x, y) = rest.split_once(',').ok_or_else(bad)?;
                let p = DVec2::new(
                    x.trim().parse().map_err(|_| bad())?,
                    y.trim().parse().map_err(|_| bad())?,
                );
                if p.is_finite() {
                    Ok(Toward::Point(p))
                } else {
                    Err(bad())
                }
            }
            _ => Err(bad()),
        }
    }
}

/// Gmsh's Threshold: h = `size_min` within `dist_min` of the targets, `size_max` beyond
/// `dist_max`, linear in the distance between; with `dist_min` = `dist_max` a step there.
///
/// ```
/// use cvtmesh::geometry::Threshold;
/// let ramp = Threshold { size_min: 0.01, size_max: 0.1, dist_min: 0.2, dist_max: 0.4 };
/// assert_eq!((ramp.at(0.1), ramp.at(1.0)), (0.01, 0.1));
/// assert!((ramp.at(0.3) - 0.055).abs() < 1e-12);
/// let step = Threshold { dist_min: 0.3, dist_max: 0.3, ..ramp };
/// assert_eq!((step.at(0.3), step.at(0.300001)), (0.01, 0.1));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Threshold {
    /// Size within `dist_min`.
    pub size_min: f64,
    /// Size beyond `dist_max`.
    pub size_max: f64,
    /// Distance up to which the size is `size_min`.
    pub dist_min: f64,
    /// Distance from which the size is `size_max`.
    pub dist_max: f64,
}

impl Threshold {
    fn check(&self) -> Result<(), SizeFieldError> {
        let t = *self;
        let finite = [t.size_min, t.size_max, t.dist_min, t.dist_max]
            .iter()
            .all(|v| v.is_finite());
        if finite
            && t.size_min > 0.0
            && t.size_min <= t.size_max
            && t.dist_min >= 0.0
            && t.dist_min <= t.dist_max
        {
            Ok(())
        } else {
            Err(SizeFieldError::Threshold {
                size_min: t.size_min,
                size_max: t.size_max,
                dist_min: t.dist_min,
                dist_max: t.dist_max,
            })
        }
    }

    /// h at distance `d`.
    pub fn at(&self, d: f64) -> f64 {
        if d <= self.dist_min {
            return self.size_min;
        }
        if d >= self.dist_max {
            return self.size_max;
        }
        let t = ((d - self.dist_min) / (self.dist_max - self.dist_min)).clamp(0.0, 1.0);
        self.size_min + t * (self.size_max - self.size_min)
    }
}

/// A target edge length h(x) on a region.
///
/// ```
/// use cvtmesh::geometry::{DVec2, Region, SizeField};
///
/// let square = Region::builtin("square_hole")?;
/// // Finer (h = 0.02) at the origin, coarser (h = 0.1) far from it.
/// let h = SizeField::from_expr("0.02 + 0.08 * min(1, sqrt(x^2 + y^2))")?;
/// let range = h.check(&square)?;
/// assert!(range.min >= 0.02 && range.max <= 0.1);
/// // The density that gives these edge lengths, and the vertex count they ask for.
/// let rho = h.density(0.02);
/// assert!((rho.at(DVec2::ZERO) - 1.0).abs() < 1e-12); // h(0, 0) = 0.02
/// assert!((rho.at(DVec2::new(3.0, 4.0)) - 1.0 / 625.0).abs() < 1e-12); // h = 0.1
/// let n = h.predicted_points(&square);
/// assert!(n > 2.0 * square.area() / (3f64.sqrt() * 0.1 * 0.1));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct SizeField {
    kind: Kind,
}

/// The smallest and largest size of a field on a region (on the sample grid and the
/// boundary's polygon vertices).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeRange {
    /// Smallest h found.
    pub min: f64,
    /// Largest h found.
    pub max: f64,
}

/// Where a size field changes faster than its background grid can follow
/// ([`SizeField::unresolved`]): the grid node inside the region from which the field grows
/// most, relative to itself, to a neighbouring node. The B-spline that interpolates the grid
/// smooths such a rise over a few steps, so the mesh's edges there come out longer than the
/// field asks: a grid of at most 2048 nodes a side cannot follow a point source asking for
/// 10⁻⁵ on a region 2 wide.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unresolved {
    /// The grid node.
    pub at: DVec2,
    /// The field's size there.
    pub size: f64,
    /// The largest size at a neighbouring node inside the region.
    pub neighbour: f64,
    /// The grid's step (the larger of its two).
    pub step: f64,
    /// The grid's nodes per side (the larger of its two counts).
    pub side: usize,
}

impl Unresolved {
    /// The report with what it means for a mesh made from the field.
    pub fn for_mesh(&self) -> String {
        format!("{self}: the mesh's edges near that point come out longer than the field asks")
    }
}

impl std::fmt::Display for Unresolved {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "size field: near ({:.6}, {:.6}) it grows from {:.3e} to {:.3e} over one step \
             ({:.3e}) of its background grid ({} nodes a side), which smooths it there",
            self.at.x, self.at.y, self.size, self.neighbour, self.step, self.side
        )
    }
}

/// [`SizeField::unresolved`] reports a field that grows by more than this factor from one grid
/// node to a neighbour. A field limited to a gradient g grows by at most 1 + 1.08·g·step/h,
/// so under the default g = 0.3 this is where h < 0.32 steps. The circle, a point source at
/// (0.3, 0.2), sizes from `h_min` to 0.1 over distance 0–1 on a grid of step 1.96·10⁻³: for
/// `h_min` = 10⁻³ / 3·10⁻⁴ / 10⁻⁴ / 10⁻⁵ the factor is below 1.5 / 1.68 / 2.36 / 3.43, the unit
/// share 1.000 / 1.000 / 0.998 / 0.844, and the ring of vertices nearest the source lies 1.1·10⁻³
/// / 4·10⁻⁴ / 2·10⁻⁴ / 10⁻⁴ from it (at 3·10⁻⁴ its edges are about 1.2 times the size asked).
const UNRESOLVED_GROWTH: f64 = 2.0;

impl SizeField {
    /// h ≡ `h` everywhere. Its density is uniform.
    pub fn constant(h: f64) -> SizeField {
        SizeField {
            kind: Kind::Constant(h),
        }
    }

    /// A distance field, as Gmsh's Distance + Threshold: h grows with the distance d to the
    /// nearest of `toward` (boundary loops, pieces, embedded lines, points) as `threshold`
    /// says. Sampled once on a
    /// background grid over the region (at least 4 nodes per `size_min`, at most 1024 per
    /// side); distances to a loop are exact distances to its curved pieces.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region, SizeField, Threshold, Toward};
    /// // Refine toward the hole of square_hole (loop 1, radius 0.4 about the origin).
    /// let region = Region::builtin("square_hole")?;
    /// let t = Threshold { size_min: 0.02, size_max: 0.2, dist_min: 0.05, dist_max: 0.5 };
    /// let h = SizeField::threshold(&region, &[Toward::Loop(1)], t)?;
    /// assert!((h.at(DVec2::new(0.42, 0.0)) - 0.02).abs() < 1e-3); // 0.02 from the hole
    /// assert!((h.at(DVec2::new(0.95, 0.95)) - 0.2).abs() < 1e-3); // far from it
    /// assert!(SizeField::threshold(&region, &[Toward::Loop(2)], t).is_err()); // no loop 2
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn threshold(
        region: &Region,
        toward: &[Toward],
        threshold: Threshold,
    ) -> Result<SizeField, SizeFieldError> {
        threshold.check()?;
        if toward.is_empty() {
            return Err(SizeFieldError::NothingToward);
        }
        let loops = region.loops();
        let pieces = region.pieces().len();
        for t in toward {
            match *t {
                Toward::Loop(index) if index >= loops.len() => {
                    return Err(SizeFieldError::UnknownLoop {
                        index,
                        loops: loops.len(),
                    });
                }
                Toward::Piece(index) if index >= pieces => {
                    return Err(SizeFieldError::UnknownPiece { index, pieces });
                }
                Toward::Line(index) if index >= region.embedded_lines().len() => {
                    return Err(SizeFieldError::UnknownLine {
                        index,
                        lines: region.embedded_lines().len(),
                    });
                }
                Toward::Marker(marker)
                    if !region.piece_markers().is_some_and(|m| m.contains(&marker))
                        && !region.embedded_lines().iter().any(|l| l.marker == marker) =>
                {
                    let mut markers = region.piece_markers().unwrap_or_default().to_vec();
                    markers.extend(region.embedded_lines().iter().map(|l| l.marker));
                    markers.sort_unstable();
                    markers.dedup();
                    return Err(SizeFieldError::UnknownMarker { marker, markers });
                }
                _ => {}
            }
        }
        let n = grid_side(region, threshold.size_min, 1024);
        let mut target_piece = vec![false; pieces];
        for t in toward {
            match *t {
                Toward::Loop(i) => {
                    for &piece in &loops[i].pieces {
                        target_piece[piece] = true;
                    }
                }
                Toward::Piece(j) => target_piece[j] = true,
                Toward::Marker(m) => {
                    for (j, &pm) in region
                        .piece_markers()
                        .unwrap_or_default()
                        .iter()
                        .enumerate()
                    {
                        target_piece[j] |= pm == m;
                    }
                }
                Toward::Point(_) | Toward::Line(_) => {}
            }
        }
        let to_loops = target_piece.iter().any(|&t| t);
        // The target lines' segments, indexed for the nearest one: a digitized interface may
        // have thousands, and the grid a million nodes.
        let lines = region.embedded_lines();
        let segments: Vec<(DVec2, DVec2)> = (0..lines.len())
            .filter(|&l| {
                toward.iter().any(|t| match *t {
                    Toward::Line(i) => i == l,
                    // A marker names the lines it marks as well as the walls.
                    Toward::Marker(m) => lines[l].marker == m,
                    _ => false,
                })
            })
            .flat_map(|l| lines[l].segments())
            .collect();
        let boxes: Vec<(DVec2, DVec2)> = segments
            .iter()
            .map(|&(a, b)| (a.min(b), a.max(b)))
            .collect();
        let to_lines = crate::index::Bvh::build(&boxes, (0..segments.len() as u32).collect());
        let distance = |p: DVec2| {
            let to_points = toward
                .iter()
                .filter_map(|t| match *t {
                    Toward::Point(q) => Some((p - q).length()),
                    Toward::Loop(_) | Toward::Piece(_) | Toward::Marker(_) | Toward::Line(_) => {
                        None
                    }
                })
                .fold(f64::INFINITY, f64::min);
            let to_lines = to_lines
                .nearest(p, |s, _| {
                    let (a, b) = segments[s as usize];
                    crate::predicates::closest_on_segment(a, b, p).2
                })
                .map_or(f64::INFINITY, |(_, d2)| d2.sqrt());
            let near = to_points.min(to_lines);
            if to_loops {
                near.min(region.distance_where(p, |piece| target_piece[piece]))
            } else {
                near
            }
        };
        // Up to a million nodes, each a nearest-piece query: in parallel, inside Ω only.
        let field = SizeField::from_inside_samples(region, n, |nodes| {
            Ok::<_, std::convert::Infallible>(
                nodes
                    .par_iter()
                    .map(|&p| threshold.at(distance(p)))
                    .collect(),
            )
        })?;
        Ok(field.unwrap_or_else(|never| match never {}))
    }

    /// The smaller of two fields at every point (Gmsh's Min field), sampled on the finer of
    /// their background grids over `region`.
    pub fn min(&self, other: &SizeField, region: &Region) -> Result<SizeField, SizeFieldError> {
        let smallest = self.check(region)?.min.min(other.check(region)?.min);
        let n = grid_side(region, smallest, 2048);
        let field = SizeField::from_inside_samples(region, n, |nodes| {
            Ok::<_, std::convert::Infallible>(
                nodes
                    .par_iter()
                    .map(|&p| self.at(p).min(other.at(p)))
                    .collect(),
            )
        })?;
        Ok(field.unwrap_or_else(|never| match never {}))
    }

    /// h given by an expression in `x` and `y` (the syntax of [`crate::expr`]).
    pub fn from_expr(text: &str) -> Result<SizeField, SizeFieldError> {
        let expr = Expr::parse(text).map_err(|source| SizeFieldError::Expr {
            text: text.to_string(),
            source,
        })?;
        Ok(SizeField {
            kind: Kind::Expr(Arc::new(expr)),
        })
    }

    /// h sampled once on an `n`×`n` grid of nodes over `region`'s bounding box (enlarged by
    /// one grid step so that every point of the region lies between nodes) and interpolated
    /// by cubic B-splines. `sample` receives every node at once and returns h at each, in order; its
    /// own error type passes through.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region, SizeField};
    ///
    /// let circle = Region::builtin("circle")?;
    /// let mut calls = 0;
    /// let h = SizeField::from_samples(&circle, 64, |nodes| {
    ///     calls += 1;
    ///     Ok::<_, std::convert::Infallible>(nodes.iter().map(|p| 0.05 + 0.1 * p.x.abs()).collect())
    /// })?
    /// .unwrap();
    /// assert_eq!(calls, 1);
    /// // A field linear along each grid line is reproduced exactly between nodes of one sign.
    /// assert!((h.at(DVec2::new(0.5, 0.3)) - 0.1).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_samples<E>(
        region: &Region,
        n: usize,
        sample: impl FnOnce(&[DVec2]) -> Result<Vec<f64>, E>,
    ) -> Result<Result<SizeField, E>, SizeFieldError> {
        SizeField::sampled(region, n, false, sample)
    }

    /// h given by a function of the position, sampled once onto a background grid over
    /// `region` as [`SizeField::on_grid`] samples an expression: fine enough for the smallest
    /// size `f` gives on a first 256 × 256 grid (4 nodes per that size, up to 2048 per side).
    /// `f` is called in parallel, once per node of both grids. Whether h is positive and
    /// finite on the region is checked with the request, as for every field.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region, SizeField};
    /// let circle = Region::builtin("circle")?;
    /// // Fine toward the origin, as a point source asks.
    /// let h = SizeField::from_fn(&circle, |p: DVec2| 0.01 + 0.1 * p.length());
    /// assert!((h.at(DVec2::new(0.5, 0.0)) - 0.06).abs() < 1e-3);
    /// h.check(&circle)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_fn(region: &Region, f: impl Fn(DVec2) -> f64 + Sync) -> SizeField {
        SizeField::from_sampler(region, |nodes| {
            Ok::<_, std::convert::Infallible>(nodes.par_iter().map(|&p| f(p)).collect())
        })
        .expect("the grids are between 2 and the largest side, one value per node")
        .unwrap_or_else(|never| match never {})
    }

    /// [`SizeField::from_samples`] on a grid fine enough for the field: `sample` (all of a
    /// grid's nodes inside `region` at once, as [`SizeField::from_samples`] takes it) is called
    /// on a first 256 × 256 grid, and again on one of 4 nodes per the smallest size it gave
    /// (up to 2048 per side) if that is finer. What [`SizeField::from_fn`] and Python's
    /// callables run.
    pub fn from_sampler<E>(
        region: &Region,
        mut sample: impl FnMut(&[DVec2]) -> Result<Vec<f64>, E>,
    ) -> Result<Result<SizeField, E>, SizeFieldError> {
        // A value that is no size at a node inside the region is refused there, named with
        // its node: between the check's points the B-spline could mix it with its neighbours
        // out of sight.
        enum Stop<E> {
            Sample(E),
            Bad(SizeFieldError),
        }
        let mut checked = |nodes: &[DVec2]| {
            let values = sample(nodes).map_err(Stop::Sample)?;
            // (All the nodes are sampled when none lies inside: those outside are free.)
            let refused = |&(p, &v): &(&DVec2, &f64)| !usable(v) && region.contains(*p);
            match nodes.iter().zip(&values).find(refused) {
                Some((p, &value)) => Err(Stop::Bad(SizeFieldError::NotPositive {
                    value,
                    x: p.x,
                    y: p.y,
                    on_boundary: false,
                })),
                None => Ok(values),
            }
        };
        let mut grid = |n: usize| match SizeField::from_inside_samples(region, n, &mut checked)? {
            Ok(field) => Ok(Ok(field)),
            Err(Stop::Sample(e)) => Ok(Err(e)),
            Err(Stop::Bad(e)) => Err(e),
        };
        let coarse = match grid(256)? {
            Ok(field) => field,
            Err(e) => return Ok(Err(e)),
        };
        let smallest = match &coarse.kind {
            Kind::Grid(g) => g.values.iter().copied().fold(f64::INFINITY, f64::min),
            _ => f64::NAN,
        };
        match grid_side(region, smallest, 2048) {
            n if n <= 256 => Ok(Ok(coarse)),
            n => grid(n),
        }
    }

    /// [`SizeField::from_samples`] with `sample` called on the nodes inside `region` only (in
    /// row order; on every node if none is inside): the others take the values of the nearest
    /// nodes inside whatever they were sampled as, so the grid is the same, and a distance
    /// field's nodes in the bounding box's empty corners and a lake's land cost nothing.
    pub(crate) fn from_inside_samples<E>(
        region: &Region,
        n: usize,
        sample: impl FnOnce(&[DVec2]) -> Result<Vec<f64>, E>,
    ) -> Result<Result<SizeField, E>, SizeFieldError> {
        SizeField::sampled(region, n, true, sample)
    }

    fn sampled<E>(
        region: &Region,
        n: usize,
        inside_only: bool,
        sample: impl FnOnce(&[DVec2]) -> Result<Vec<f64>, E>,
    ) -> Result<Result<SizeField, E>, SizeFieldError> {
        if n < 2 {
            return Err(SizeFieldError::GridTooSmall(n));
        }
        if n > MAX_GRID_SIDE {
            return Err(SizeFieldError::GridTooLarge(n));
        }
        let (lo, hi) = region.bbox();
        let pad = (hi - lo) / (n - 1) as f64;
        let (lo, hi) = (lo - pad, hi + pad);
        let step = (hi - lo) / DVec2::new((n - 1) as f64, (n - 1) as f64);
        let mut grid = Grid {
            lo,
            step,
            inv_step: 1.0 / step,
            nx: n,
            ny: n,
            values: Vec::new(),
            padded: Vec::new(),
            flat: Vec::new(),
            flat_nx: 0,
        };
        let inside = grid.inside(region);
        let node = |k: usize| lo + step * DVec2::new((k % n) as f64, (k / n) as f64);
        let masked = inside_only && inside.contains(&true);
        let chosen = || (0..n * n).filter(|&k| !masked || inside[k]);
        let nodes: Vec<DVec2> = chosen().map(node).collect();
        let values = match sample(&nodes) {
            Ok(v) => v,
            Err(e) => return Ok(Err(e)),
        };
        if values.len() != nodes.len() {
            return Err(SizeFieldError::SampleCount {
                got: values.len(),
                expected: nodes.len(),
            });
        }
        drop(nodes);
        grid.values = if masked {
            let mut all = vec![f64::NAN; n * n];
            for (k, v) in chosen().zip(values) {
                all[k] = v;
            }
            all
        } else {
            values
        };
        // Nodes outside the region may hold anything (a distance field may be undefined
        // there, or have a kink on ∂Ω): they take the values of the nearest nodes inside.
        grid.extend_outside(inside);
        let grid = grid.sealed();
        Ok(Ok(SizeField {
            kind: Kind::Grid(Arc::new(grid)),
        }))
    }

    /// The field sampled once onto a background grid over `region` fine enough for its
    /// smallest size `h_min` (at least 4 nodes per `h_min`, at most 2048 per side), for fields
    /// that are costly to evaluate: an expression is a tree walked at every point, and a
    /// method evaluates the density dozens of times per cell and iteration. Constant and
    /// sampled fields are returned as they are.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region, SizeField};
    /// let circle = Region::builtin("circle")?;
    /// let h = SizeField::from_expr("0.02 + 0.1 * (x + 1)")?;
    /// let g = h.on_grid(&circle, 0.02);
    /// // The B-spline reproduces a linear field.
    /// let p = DVec2::new(0.3, -0.2);
    /// assert!((g.at(p) - h.at(p)).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn on_grid(&self, region: &Region, h_min: f64) -> SizeField {
        match &self.kind {
            Kind::Constant(_) | Kind::Grid(_) => self.clone(),
            Kind::Expr(e) => {
                let n = grid_side(region, h_min, 2048);
                SizeField::from_inside_samples(region, n, |nodes| {
                    Ok::<_, std::convert::Infallible>(
                        nodes.par_iter().map(|&p| e.eval(p)).collect(),
                    )
                })
                .expect("n is at least 2 and one value is made per node")
                .unwrap_or_else(|never| match never {})
            }
        }
    }

    /// The field clamped to [`min`, `max`] (either bound optional) and then limited to
    /// |∇h| ≤ `gradation`: h(x) = min_y h(y) + g |x − y| (Persson, "Mesh size functions for
    /// implicit geometries and PDE-based gradient limiting", 2006), so that sizes change
    /// smoothly away from where the field is small. Computed on the background grid of
    /// [`SizeField::on_grid`] by sweeps over each node's eight neighbours until nothing
    /// changes; distances along the grid's axes and diagonals make the cones octagons, at
    /// most 8 % wider than the exact ones. Nodes where the field is not positive and finite
    /// (outside the region, say) are never sources. An infinite `gradation` (or `None`)
    /// leaves the gradient alone.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region, SizeField};
    /// let square = Region::builtin("square_hole")?;
    /// // A jump from 0.01 to 0.2 across x = 0.5 ...
    /// let h = SizeField::from_expr("0.01 + 0.19 * max(0, min(1, (x - 0.5) * 1e6))")?;
    /// // ... becomes a ramp of slope at most 0.25 (8 % more along the grid's diagonals).
    /// let g = h.bounded(&square, None, Some(0.15), Some(0.25))?;
    /// let (a, b) = (DVec2::new(0.5, 0.1), DVec2::new(0.7, 0.1));
    /// assert!((g.at(b) - g.at(a)).abs() <= 0.25 * 1.08 * 0.2 + 1e-3);
    /// assert!(g.at(DVec2::new(0.95, 0.1)) <= 0.15 + 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn bounded(
        &self,
        region: &Region,
        min: Option<f64>,
        max: Option<f64>,
        gradation: Option<f64>,
    ) -> Result<SizeField, SizeFieldError> {
        Ok(self.bounding(region, min, max, gradation, false)?.0)
    }

    /// [`SizeField::bounded`], and the vertex count ([`SizeField::predicted_points`]) the
    /// field asked for once clamped, before its gradient was limited: what the limit changed,
    /// which a user is told when it adds many vertices. `None` without a limit or for a
    /// constant field.
    ///
    /// ```
    /// use cvtmesh::geometry::{Region, SizeField};
    /// let square = Region::builtin("square_hole")?;
    /// let steep = SizeField::from_expr("0.005 + 0.5*abs(x)")?;
    /// let (limited, before) = steep.bounded_counted(&square, None, None, Some(0.3))?;
    /// let before = before.unwrap();
    /// assert!((before / steep.predicted_points(&square) - 1.0).abs() < 0.01);
    /// // Sizes growing at most 0.3 per unit of distance ask for many more vertices.
    /// assert!(limited.predicted_points(&square) > 1.5 * before);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn bounded_counted(
        &self,
        region: &Region,
        min: Option<f64>,
        max: Option<f64>,
        gradation: Option<f64>,
    ) -> Result<(SizeField, Option<f64>), SizeFieldError> {
        self.bounding(region, min, max, gradation, true)
    }

    fn bounding(
        &self,
        region: &Region,
        min: Option<f64>,
        max: Option<f64>,
        gradation: Option<f64>,
        count: bool,
    ) -> Result<(SizeField, Option<f64>), SizeFieldError> {
        let (lo, hi) = (min.unwrap_or(0.0), max.unwrap_or(f64::INFINITY));
        // As Gmsh's Mesh.MeshSizeMin = 0 and MeshSizeMax = 1e22, 0 and ∞ bound nothing.
        if !(lo.is_finite() && lo >= 0.0 && hi > 0.0 && lo <= hi) {
            return Err(SizeFieldError::Bounds { min, max });
        }
        let g = gradation.unwrap_or(f64::INFINITY);
        if g.is_nan() || g <= 0.0 {
            return Err(SizeFieldError::Gradation(g));
        }
        if let Kind::Constant(h) = self.kind {
            return Ok((SizeField::constant(h.clamp(lo, hi)), None));
        }
        let smallest = self.check(region)?.min.max(lo);
        let Kind::Grid(grid) = self.on_grid(region, smallest).kind else {
            unreachable!("on_grid makes a grid of every non-constant field")
        };
        // The values only: `sealed` below makes the padded copy afresh.
        let mut grid = Grid {
            values: grid.values.clone(),
            padded: Vec::new(),
            flat: Vec::new(),
            ..*grid
        };
        for v in grid.values.iter_mut() {
            if v.is_finite() && *v > 0.0 {
                *v = v.clamp(lo, hi);
            }
        }
        let mut before = None;
        if g.is_finite() {
            if count {
                // The clamped grid sealed for its count, then taken back to be limited: no copy
                // of its values.
                let clamped = SizeField {
                    kind: Kind::Grid(Arc::new(grid.sealed())),
                };
                before = Some(clamped.predicted_points(region));
                let Kind::Grid(sealed) = clamped.kind else {
                    unreachable!("made as a grid just above")
                };
                grid = Arc::try_unwrap(sealed).expect("the only handle on the grid");
                grid.padded = Vec::new();
            }
            grid.limit_gradation(g);
        }
        Ok((
            SizeField {
                kind: Kind::Grid(Arc::new(grid.sealed())),
            },
            before,
        ))
    }

    /// h at `p`.
    pub fn at(&self, p: DVec2) -> f64 {
        match &self.kind {
            Kind::Constant(h) => *h,
            Kind::Expr(e) => e.eval(p),
            Kind::Grid(g) => g.at(p),
        }
    }

    /// True for a constant field (its density is uniform, which the methods treat exactly).
    pub fn is_constant(&self) -> bool {
        matches!(self.kind, Kind::Constant(_))
    }

    /// True for a field read from values on a background grid (a distance field, sizes on a
    /// mesh or from a callable, a gradation-limited or combined field); false for a constant or
    /// an expression, which [`SizeField::at`] evaluates where asked.
    pub fn is_sampled(&self) -> bool {
        matches!(self.kind, Kind::Grid(_))
    }

    /// Where the field grows faster than the background grid it is meshed from can follow
    /// ([`Unresolved`]): the node inside `region` whose size a neighbour exceeds by the largest
    /// factor, if that factor is over 2. An expression is looked at on the grid
    /// [`SizeField::on_grid`] samples it onto for its smallest size on `region`; a constant
    /// field, or one that fails [`SizeField::check`], has nothing to report. O(n²) for a grid
    /// of n nodes a side.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region, SizeField, Threshold, Toward};
    /// let circle = Region::builtin("circle")?;
    /// let toward = [Toward::Point(DVec2::new(0.3, 0.2))];
    /// let t = |size_min| Threshold { size_min, size_max: 0.1, dist_min: 0.0, dist_max: 1.0 };
    /// // Sizes from 10⁻² are followed; from 10⁻⁵ (200 times below the grid's step) they are not.
    /// assert!(SizeField::threshold(&circle, &toward, t(1e-2))?.unresolved(&circle).is_none());
    /// let u = SizeField::threshold(&circle, &toward, t(1e-5))?.unresolved(&circle).unwrap();
    /// assert!((u.at - DVec2::new(0.3, 0.2)).length() < 2.0 * u.step);
    /// assert!(u.neighbour > 2.0 * u.size);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn unresolved(&self, region: &Region) -> Option<Unresolved> {
        let grid = match &self.kind {
            Kind::Constant(_) => return None,
            Kind::Grid(g) => g.clone(),
            Kind::Expr(_) => match self.on_grid(region, self.check(region).ok()?.min).kind {
                Kind::Grid(g) => g,
                Kind::Constant(_) | Kind::Expr(_) => return None,
            },
        };
        grid.steepest_rise(region)
            .filter(|u| u.neighbour > UNRESOLVED_GROWTH * u.size)
    }

    /// Check that h is positive and finite on `region` (at the centres of a 256×256 grid over
    /// its bounding box that lie inside, and at the vertices of its boundary polygon) and
    /// return the range found. The first offending point is named in the error.
    pub fn check(&self, region: &Region) -> Result<SizeRange, SizeFieldError> {
        let mut range = SizeRange {
            min: f64::INFINITY,
            max: 0.0,
        };
        let polygon = region.polygonize(1e-3 * region.diameter());
        let boundary = polygon
            .rings
            .iter()
            .flat_map(|r| r.points.iter().map(|&p| (p, true)));
        let inside = region.inside_grid().0.iter().map(|&p| (p, false));
        for (p, on_boundary) in boundary.chain(inside) {
            let h = self.at(p);
            if !(h.is_finite() && h > 0.0) {
                return Err(SizeFieldError::NotPositive {
                    value: h,
                    x: p.x,
                    y: p.y,
                    on_boundary,
                });
            }
            range.min = range.min.min(h);
            range.max = range.max.max(h);
        }
        Ok(range)
    }

    /// The vertex count the field asks for, N ≈ (2/√3) ∫_Ω h⁻² dx (a converged CVT is a
    /// lattice of regular hexagons, each of area (√3/2)h²), by the midpoint rule on a 256×256
    /// grid whose cell areas are scaled to the region's exact area. Assumes a checked field.
    pub fn predicted_points(&self, region: &Region) -> f64 {
        let inside = region.inside_grid().0;
        if inside.is_empty() {
            return 0.0;
        }
        let mean = inside.iter().map(|&p| self.at(p).powi(-2)).sum::<f64>() / inside.len() as f64;
        2.0 / 3f64.sqrt() * mean * region.area()
    }

    /// The CVT density whose generators are spaced ∝ h: ρ = (h_min / h)⁴ (uniform for a
    /// constant field). `h_min` only scales ρ (to 1 where h is smallest); the spacing's shape
    /// does not depend on it.
    pub fn density(&self, h_min: f64) -> Density {
        match &self.kind {
            Kind::Constant(_) => Density::Uniform,
            // ρ itself on the grid: the cells read it ~45 times per cell and evaluation.
            Kind::Grid(g) => Density::Sampled(Arc::new(SampledDensity {
                grid: g
                    .with_values(g.values.iter().map(|&h| (h_min / h).powi(4)).collect())
                    .tiled(),
            })),
            Kind::Expr(_) => {
                let field = self.clone();
                Density::Function(Arc::new(move |p| (h_min / field.at(p)).powi(4)))
            }
        }
    }
}

/// A grid node's eight neighbours (di, dj), the four before it in row order first.
const NEIGHBOURS: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// One Gauss–Seidel sweep of h_i ← min(h_i, h_j + step) over the neighbours j = i + (di, dj)
/// of `mask` on the `nx` × `ny` row-major grid `values`, rows and columns in the given
/// directions; values that are not positive and finite are never sources. Returns whether a
/// value changed. Where every value is usable, nodes off the grid's border skip the tests.
fn sweep(
    values: &mut [f64],
    nx: isize,
    ny: isize,
    mask: &[(isize, isize, f64)],
    rev_i: bool,
    rev_j: bool,
) -> bool {
    let usable = |v: f64| v.is_finite() && v > 0.0;
    let linear: Vec<(isize, f64)> = mask.iter().map(|&(di, dj, s)| (dj * nx + di, s)).collect();
    // Where every value is usable (a checked field extended outside the region), the update
    // is a plain minimum, without branches.
    let all_usable = values.iter().all(|&v| usable(v));
    let mut changed = false;
    for jj in 0..ny {
        let j = if rev_j { ny - 1 - jj } else { jj };
        let inner_row = j > 0 && j < ny - 1;
        for ii in 0..nx {
            let i = if rev_i { nx - 1 - ii } else { ii };
            let at = j * nx + i;
            let mut h = values[at as usize];
            if all_usable && inner_row && i > 0 && i < nx - 1 {
                for &(off, step) in &linear {
                    h = h.min(values[(at + off) as usize] + step);
                }
            } else {
                for &(di, dj, step) in mask {
                    let (a, b) = (i + di, j + dj);
                    if a < 0 || b < 0 || a >= nx || b >= ny {
                        continue;
                    }
                    let v = values[(b * nx + a) as usize];
                    if usable(v) && (!usable(h) || v + step < h) {
                        h = v + step;
                    }
                }
            }
            if h != values[at as usize] && usable(h) {
                values[at as usize] = h;
                changed = true;
            }
        }
    }
    changed
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closure's field is sampled as finely as its smallest size asks: a point source of
    /// h = 0.002 + 0.1 r, whose curvature across the rays (0.1 / r) the B-spline smooths over
    /// a few grid steps, is within 0.1 % of h at r = 0.02 on a grid of 4 nodes per 0.002 and
    /// about 1 % off on the first 256 × 256 one.
    #[test]
    fn a_closure_is_sampled_as_finely_as_its_smallest_size_asks() {
        let circle = Region::builtin("circle").unwrap();
        let f = |p: DVec2| 0.002 + 0.1 * p.length();
        let fine = SizeField::from_fn(&circle, f);
        let coarse = SizeField::from_samples(&circle, 256, |nodes| {
            Ok::<_, std::convert::Infallible>(nodes.iter().map(|&p| f(p)).collect())
        })
        .unwrap()
        .unwrap();
        let p = DVec2::new(0.02, 0.0);
        assert!((fine.at(p) - f(p)).abs() < 1e-3 * f(p), "{}", fine.at(p));
        assert!(
            (coarse.at(p) - f(p)).abs() > 4e-3 * f(p),
            "{}",
            coarse.at(p)
        );
        // A grid too large for memory is refused before any node is sampled.
        let refused =
            SizeField::from_samples(&circle, MAX_GRID_SIDE + 1, |_| -> Result<Vec<f64>, ()> {
                unreachable!("refused first")
            });
        assert!(matches!(refused, Err(SizeFieldError::GridTooLarge(_))));
    }

    #[test]
    fn constant_field_predicts_the_lattice_count_and_a_uniform_density() {
        let r = Region::builtin("square_hole").unwrap();
        let h = SizeField::constant(0.05);
        let n = h.predicted_points(&r);
        let lattice = 2.0 * r.area() / (3f64.sqrt() * 0.05 * 0.05);
        assert!((n - lattice).abs() < 1e-9 * lattice, "{n} vs {lattice}");
        assert!(h.density(0.05).is_uniform());
        assert_eq!(
            h.check(&r).unwrap(),
            SizeRange {
                min: 0.05,
                max: 0.05
            }
        );
    }

    /// square_hole refined toward its hole: h from 0.01 on the hole to 0.1 at distance 0.6.
    fn toward_the_hole() -> (Region, Threshold, SizeField) {
        let r = Region::builtin("square_hole").unwrap();
        let t = Threshold {
            size_min: 0.01,
            size_max: 0.1,
            dist_min: 0.0,
            dist_max: 0.6,
        };
        let h = SizeField::threshold(&r, &[Toward::Loop(1)], t).unwrap();
        (r, t, h)
    }

    #[test]
    fn grid_holds_the_boundary_sizes_outside_the_region() {
        // The distance to the hole grows again inside it, a kink on the loop; outside the
        // region the grid holds the loop's size instead, so ρ is as smooth across ∂Ω as inside.
        let (_, t, h) = toward_the_hole();
        for q in [0.3, 0.2, 0.0] {
            let v = h.at(DVec2::new(q, 0.1));
            assert!((v - 0.01).abs() < 1e-3, "inside the hole at x = {q}: {v}");
        }
        // Inside the region the field is the threshold of the distance.
        let v = h.at(DVec2::new(0.7, 0.0));
        assert!((v - t.at(0.3)).abs() < 1e-3, "{v}");
    }

    /// A field positive everywhere that varies from node to node in both directions.
    fn wavy(p: DVec2) -> f64 {
        2.0 + (3.1 * p.x).sin() * (1.7 * p.y).cos() + 1e-3 * p.x
    }

    fn grid_of(field: &SizeField) -> &Grid {
        match &field.kind {
            Kind::Grid(g) => g,
            _ => panic!("a sampled field"),
        }
    }

    #[test]
    fn sampling_only_the_nodes_inside_gives_the_same_grid() {
        // The nodes outside Ω take their values from the nodes inside, so sampling them is
        // wasted work: the grid is the same bit for bit. The lake's bounding box is half land.
        for name in ["square_hole", "lake", "annulus"] {
            let r = Region::builtin(name).unwrap();
            let n = 97;
            let every = SizeField::from_samples(&r, n, |nodes| {
                Ok::<_, ()>(nodes.iter().map(|&p| wavy(p)).collect())
            })
            .unwrap()
            .unwrap();
            let mut sampled = 0;
            let inside = SizeField::from_inside_samples(&r, n, |nodes| {
                sampled = nodes.len();
                assert!(nodes
                    .iter()
                    .all(|&p| r.signed_distance(p) < 0.05 * r.diameter()));
                Ok::<_, ()>(nodes.iter().map(|&p| wavy(p)).collect())
            })
            .unwrap()
            .unwrap();
            assert!(sampled > n * n / 10 && sampled < n * n, "{name}: {sampled}");
            let (a, b) = (grid_of(&every), grid_of(&inside));
            assert_eq!(a.values.len(), b.values.len());
            for (k, (x, y)) in a.values.iter().zip(&b.values).enumerate() {
                assert_eq!(
                    x.to_bits(),
                    y.to_bits(),
                    "{name}: node {k}: {x} against {y}"
                );
            }
            assert!(a
                .padded
                .iter()
                .zip(&b.padded)
                .all(|(x, y)| x.to_bits() == y.to_bits()));
        }
    }

    #[test]
    fn the_outside_takes_the_layer_by_layer_mean_of_the_nodes_inside() {
        // Each node outside Ω, one layer after another outward from the nodes inside, takes
        // the mean of its four-neighbours already set: against that rule written out plainly,
        // bit for bit.
        let r = Region::builtin("square_hole").unwrap();
        let n = 41;
        let field = SizeField::from_inside_samples(&r, n, |nodes| {
            Ok::<_, ()>(nodes.iter().map(|&p| wavy(p)).collect())
        })
        .unwrap()
        .unwrap();
        let g = grid_of(&field);
        let inside = g.inside(&r);
        let mut values: Vec<f64> = (0..n * n)
            .map(|k| {
                let p = g.lo + g.step * DVec2::new((k % n) as f64, (k / n) as f64);
                if inside[k] {
                    wavy(p)
                } else {
                    f64::NAN
                }
            })
            .collect();
        let mut set = inside.clone();
        let neighbours = |k: usize| {
            let (i, j) = (k % n, k / n);
            let mut v = Vec::new();
            if i > 0 {
                v.push(k - 1);
            }
            if i + 1 < n {
                v.push(k + 1);
            }
            if j > 0 {
                v.push(k - n);
            }
            if j + 1 < n {
                v.push(k + n);
            }
            v
        };
        let mut layers = 0;
        loop {
            let front: Vec<usize> = (0..n * n)
                .filter(|&k| !set[k] && neighbours(k).iter().any(|&u| set[u]))
                .collect();
            if front.is_empty() {
                break;
            }
            layers += 1;
            let means: Vec<f64> = front
                .iter()
                .map(|&k| {
                    let from: Vec<f64> = neighbours(k)
                        .into_iter()
                        .filter(|&u| set[u])
                        .map(|u| values[u])
                        .collect();
                    from.iter().fold(0.0, |s, v| s + v) / from.len() as f64
                })
                .collect();
            for (&k, m) in front.iter().zip(means) {
                values[k] = m;
                set[k] = true;
            }
        }
        assert!(layers > 2, "{layers} layers");
        for (k, (x, y)) in g.values.iter().zip(&values).enumerate() {
            assert_eq!(x.to_bits(), y.to_bits(), "node {k}: {x} against {y}");
        }
    }

    #[test]
    fn grid_interpolation_is_smooth_across_nodes() {
        // The cubic B-spline is C²: second differences across a node match those beside it.
        let r = Region::builtin("circle").unwrap();
        let h = SizeField::from_samples(&r, 16, |nodes| {
            Ok::<_, ()>(nodes.iter().map(|p| 0.05 + 0.1 * p.x.abs()).collect())
        })
        .unwrap()
        .unwrap();
        let d = 1e-3;
        let second = |x: f64| {
            let f = |x: f64| h.at(DVec2::new(x, 0.05));
            (f(x + d) - 2.0 * f(x) + f(x - d)) / (d * d)
        };
        // At the nodes beside the kink of |x|: a bilinear interpolant has a slope jump of up to
        // 0.2 there (a second difference of 0.2 / d = 200); the spline's f'' stays bounded.
        let (lo, step) = (-1.0 - 2.0 / 15.0, (2.0 + 4.0 / 15.0) / 15.0);
        for i in [6, 7, 8, 9] {
            let node = lo + i as f64 * step;
            assert!(second(node).abs() < 10.0, "node {i}: {}", second(node));
        }
    }

    #[test]
    fn the_density_at_seven_points_is_its_value_at_each_bit_for_bit() {
        // Points inside the region, in the hole (where the grid holds the loop's size), outside
        // the grid's box (clamped, from infinitely far too), at NaN, and on its nodes; and a
        // grid with a non-positive sample, where both take the bilinear value.
        let (r, _, toward_hole) = toward_the_hole();
        let with_zero = SizeField::from_samples(&r, 16, |nodes| {
            Ok::<_, ()>(nodes.iter().map(|p| p.x.max(0.0) * 0.1).collect())
        })
        .unwrap()
        .unwrap();
        let mut rng = crate::Rng::new(3);
        for field in [&toward_hole, &with_zero] {
            let Density::Sampled(rho) = field.density(0.01) else {
                panic!("a sampled field")
            };
            for round in 0..200 {
                let spread = if round % 2 == 0 { 1.0 } else { 1.5 };
                let far = [
                    f64::INFINITY,
                    -f64::INFINITY,
                    1e300,
                    -1e300,
                    f64::NAN,
                    2.5,
                    -7.0,
                ];
                let ps: [DVec2; 7] = std::array::from_fn(|k| {
                    if round == 0 {
                        DVec2::new(-1.0 + k as f64 / 3.0, 1.0)
                    } else if round == 1 {
                        DVec2::new(far[k], far[(k + 3) % 7])
                    } else {
                        DVec2::new(rng.range(-spread, spread), rng.range(-spread, spread))
                    }
                });
                let many = rho.at7(&ps);
                for (p, v) in ps.iter().zip(many) {
                    assert_eq!(v.to_bits(), rho.at(*p).to_bits(), "at {p}");
                }
            }
        }
    }

    /// Wherever the density claims a constant over a box, the B-spline there gives it at every
    /// point; boxes of every size across the ramp of a threshold field, near and far.
    #[test]
    fn a_constant_over_a_box_is_the_value_inside_it() {
        let r = Region::builtin("circle").unwrap();
        let t = Threshold {
            size_min: 0.02,
            size_max: 0.1,
            dist_min: 0.2,
            dist_max: 0.5,
        };
        let Density::Sampled(rho) = SizeField::threshold(&r, &[Toward::Point(DVec2::ZERO)], t)
            .unwrap()
            .density(0.02)
        else {
            panic!("a sampled field")
        };
        let mut rng = crate::Rng::new(4);
        let (mut some, mut none) = (0, 0);
        for _ in 0..4000 {
            let c = DVec2::new(2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0) * 0.7;
            let half = DVec2::new(rng.uniform(), rng.uniform()) * 0.05;
            match rho.constant_over(c - half, c + half) {
                Some(v) => {
                    some += 1;
                    // ρ = 1 on the plateau by the point, (h_min / h_max)⁴ in the far field.
                    assert!(v == 1.0 || (v - 0.0016).abs() < 1e-15, "{v}");
                    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
                    let random: Vec<(f64, f64)> = (0..20)
                        .map(|_| (2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0))
                        .collect();
                    for (x, y) in corners.into_iter().chain(random) {
                        let p = c + half * DVec2::new(x, y);
                        assert!(
                            (rho.at(p) - v).abs() <= 1e-15 * v,
                            "{p}: {} vs {v}",
                            rho.at(p)
                        );
                    }
                }
                None => none += 1,
            }
        }
        assert!(
            some > 500 && none > 500,
            "{some} constant boxes, {none} not"
        );
    }

    #[test]
    fn density_gives_spacing_proportional_to_h() {
        // Spacing ∝ ρ^(-1/4): two points whose h differ by 2 have densities 16 apart.
        let h = SizeField::from_expr("0.01 * (1 + x)").unwrap();
        let rho = h.density(0.01);
        let (a, b) = (DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0));
        assert!((rho.at(a) / rho.at(b) - 16.0).abs() < 1e-12);
        assert!((rho.at(a) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_fields_are_refused_with_the_place() {
        let r = Region::builtin("circle").unwrap();
        for text in ["x", "0 * x", "1 / 0", "log(-1)", "-1"] {
            let e = SizeField::from_expr(text).unwrap().check(&r).unwrap_err();
            assert!(
                matches!(e, SizeFieldError::NotPositive { .. }),
                "{text}: {e}"
            );
            assert!(e.to_string().contains("positive and finite"), "{e}");
        }
        assert!(matches!(
            SizeField::from_expr("0.1 +").unwrap_err(),
            SizeFieldError::Expr { .. }
        ));
        assert!(matches!(
            SizeField::from_samples(&r, 8, |_| Ok::<_, ()>(vec![1.0; 3])).unwrap_err(),
            SizeFieldError::SampleCount {
                got: 3,
                expected: 64
            }
        ));
        assert!(matches!(
            SizeField::from_samples(&r, 1, |_| Ok::<_, ()>(vec![1.0])).unwrap_err(),
            SizeFieldError::GridTooSmall(1)
        ));
        // The sampler's own error passes through untouched.
        assert_eq!(
            SizeField::from_samples(&r, 4, |_| Err::<Vec<f64>, _>("no"))
                .unwrap()
                .unwrap_err(),
            "no"
        );
    }

    #[test]
    fn a_sampled_size_that_is_no_size_somewhere_inside_is_refused_there() {
        let r = Region::builtin("square_hole").unwrap();
        // Zero on the right half, negative everywhere, NaN at one spot, a hair below zero on
        // a sliver: each named with a node where it is so.
        type Field = fn(DVec2) -> f64;
        let cases: [(&str, Field); 4] = [
            ("zero right", |p| if p.x > 0.5 { 0.0 } else { 0.1 }),
            ("negative", |_| -1.0),
            ("one NaN", |p| {
                if (p - DVec2::new(0.7, 0.7)).length() < 0.01 {
                    f64::NAN
                } else {
                    0.1
                }
            }),
            ("sliver", |p| if p.y > 0.99 { -1e-12 } else { 0.05 }),
        ];
        for (what, h) in cases {
            let e = SizeField::from_sampler(&r, |nodes| {
                Ok::<_, ()>(nodes.iter().map(|&p| h(p)).collect())
            })
            .unwrap_err();
            let SizeFieldError::NotPositive { value, x, y, .. } = e else {
                panic!("{what}: {e}");
            };
            let p = DVec2::new(x, y);
            assert!(r.contains(p), "{what}: {p} is outside");
            assert_eq!(value.to_bits(), h(p).to_bits(), "{what} at {p}");
        }
        // A density may be zero: its zeros inside stay zeros, not its neighbours' values.
        let rho = SizeField::from_samples(&r, 128, |nodes| {
            Ok::<_, ()>(
                nodes
                    .iter()
                    .map(|p| if p.x > 0.5 { 0.0 } else { 1.0 })
                    .collect(),
            )
        })
        .unwrap()
        .unwrap();
        assert_eq!(rho.at(DVec2::new(0.8, 0.0)), 0.0);
        assert_eq!(rho.at(DVec2::new(-0.8, 0.0)), 1.0);
    }

    #[test]
    fn sampled_field_matches_the_expression_it_samples() {
        let r = Region::builtin("lake").unwrap();
        let text = "0.02 + 0.01 * (x + 2 * y)";
        let e = SizeField::from_expr(text).unwrap();
        let g = SizeField::from_samples(&r, 33, |nodes| {
            Ok::<_, ()>(nodes.iter().map(|&p| e.at(p)).collect())
        })
        .unwrap()
        .unwrap();
        // The B-spline reproduces a linear field where it reads only nodes inside the region
        // (two grid steps in); nearer ∂Ω it reads the boundary sizes held outside.
        let (lo, hi) = r.bbox();
        let step = (hi - lo).max_element() / 31.0;
        let mut tested = 0;
        for k in 0..2000 {
            let t = DVec2::new((k as f64 * 0.37).fract(), (k as f64 * 0.61).fract());
            let p = lo + (hi - lo) * t;
            if r.signed_distance(p) < -3.0 * step {
                tested += 1;
                assert!((g.at(p) - e.at(p)).abs() < 1e-12 * (1.0 + e.at(p)), "{p}");
            }
        }
        assert!(tested > 40, "{tested}");
        let (a, b) = (e.predicted_points(&r), g.predicted_points(&r));
        assert!((a - b).abs() < 1e-2 * a, "{a} {b}");
    }

    /// The limit the sweeps reach, bit for bit, is the least path sum at every node: Dijkstra's
    /// over the eight-neighbour grid, each path summed step by step from a usable value.
    /// Unusable values (zero, negative, NaN, infinite) are never sources, but take a value
    /// reached from one; a grid with none usable is left as it is.
    #[test]
    fn gradation_limiting_reaches_the_least_path_sum_at_every_node() {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        #[derive(PartialEq)]
        struct Key(f64);
        impl Eq for Key {}
        impl PartialOrd for Key {
            fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
                Some(self.cmp(o))
            }
        }
        impl Ord for Key {
            fn cmp(&self, o: &Self) -> std::cmp::Ordering {
                self.0.total_cmp(&o.0)
            }
        }
        let usable = |v: f64| v.is_finite() && v > 0.0;
        for (seed, (nx, ny), unusable_share) in [
            (1, (37, 23), 0.05),
            (2, (5, 61), 0.3),
            (3, (64, 64), 0.0),
            (4, (9, 9), 1.0),
        ] {
            let mut rng = crate::rng::Rng::new(seed);
            let bad = [0.0, -1.0, f64::NAN, f64::INFINITY];
            let values: Vec<f64> = (0..nx * ny)
                .map(|_| {
                    if rng.uniform() < unusable_share {
                        bad[rng.below(4)]
                    } else {
                        rng.range(0.01, 1.0)
                    }
                })
                .collect();
            let step = DVec2::new(0.1, 0.07);
            let mut grid = Grid {
                lo: DVec2::ZERO,
                step,
                inv_step: 1.0 / step,
                nx,
                ny,
                values: values.clone(),
                padded: Vec::new(),
                flat: Vec::new(),
                flat_nx: 0,
            };
            let g = 0.3;
            grid.limit_gradation(g);
            // Dijkstra from every usable node at once.
            let diag = step.length();
            let mut best: Vec<f64> = values
                .iter()
                .map(|&v| if usable(v) { v } else { f64::INFINITY })
                .collect();
            let mut heap: BinaryHeap<Reverse<(Key, usize)>> = (0..nx * ny)
                .filter(|&k| best[k].is_finite())
                .map(|k| Reverse((Key(best[k]), k)))
                .collect();
            while let Some(Reverse((Key(d), k))) = heap.pop() {
                if d > best[k] {
                    continue;
                }
                let (i, j) = ((k % nx) as isize, (k / nx) as isize);
                for (di, dj) in NEIGHBOURS {
                    let (a, b) = (i + di, j + dj);
                    if a < 0 || b < 0 || a >= nx as isize || b >= ny as isize {
                        continue;
                    }
                    let len = match (di, dj) {
                        (0, _) => step.y,
                        (_, 0) => step.x,
                        _ => diag,
                    };
                    let u = b as usize * nx + a as usize;
                    let through = d + g * len;
                    if through < best[u] {
                        best[u] = through;
                        heap.push(Reverse((Key(through), u)));
                    }
                }
            }
            for (k, (&now, &least)) in grid.values.iter().zip(&best).enumerate() {
                let want = if least.is_finite() { least } else { values[k] };
                assert!(
                    now.to_bits() == want.to_bits(),
                    "seed {seed}, node {k}: {now} against {want}"
                );
            }
        }
    }

    #[test]
    fn gradation_limiting_turns_a_jump_into_a_ramp_and_leaves_gentle_fields_alone() {
        let r = Region::builtin("circle").unwrap();
        // A tiny size in a small disc around the origin, large elsewhere.
        let jump = SizeField::from_expr("0.01 + 0.3 * min(1, max(0, (sqrt(x^2+y^2) - 0.1) * 1e6))")
            .unwrap();
        let g = jump.bounded(&r, None, None, Some(0.2)).unwrap();
        for k in 0..50 {
            let d = 0.1 + 0.8 * k as f64 / 49.0;
            let p = DVec2::new(d * 0.6, d * 0.8);
            // Never above the cone from the small disc, never below the field's small value.
            assert!(
                g.at(p) <= 0.01 + 0.2 * 1.09 * (d - 0.1) + 2e-3,
                "{d}: {}",
                g.at(p)
            );
            assert!(g.at(p) >= 0.01 - 1e-12);
        }
        assert!(g.at(DVec2::new(0.0, 0.0)) < 0.0105);
        // A field whose slope is already below the limit keeps its values (to interpolation).
        let gentle = SizeField::from_expr("0.05 + 0.1 * (x + 1)").unwrap();
        let same = gentle.bounded(&r, None, None, Some(0.3)).unwrap();
        for p in [
            DVec2::new(0.3, 0.2),
            DVec2::new(-0.7, 0.1),
            DVec2::new(0.0, -0.9),
        ] {
            assert!((same.at(p) - gentle.at(p)).abs() < 1e-12, "{p}");
        }
        // Bounds clamp; a constant stays constant.
        let c = gentle.bounded(&r, Some(0.08), Some(0.2), None).unwrap();
        assert!((c.at(DVec2::new(-1.0, 0.0)) - 0.08).abs() < 1e-12);
        assert!((c.at(DVec2::new(1.0, 0.0)) - 0.2).abs() < 1e-12);
        let k = SizeField::constant(0.5)
            .bounded(&r, None, Some(0.1), Some(0.3))
            .unwrap();
        assert!(k.is_constant() && k.at(DVec2::ZERO) == 0.1);
    }

    #[test]
    fn a_distance_field_toward_a_marker_refines_the_walls_so_marked() {
        // A 4 × 1 channel: walls 1, inlet 2, outlet 3, a strip 4 on the bottom from 1.5 to 2.5.
        let r = crate::formats::poly_from_str(
            "6 2 0 0\n1 0 0\n2 1.5 0\n3 2.5 0\n4 4 0\n5 4 1\n6 0 1\n\
             6 1\n1 1 2 1\n2 2 3 4\n3 3 4 1\n4 4 5 3\n5 5 6 1\n6 6 1 2\n0\n",
            "channel.poly",
            "channel",
        )
        .unwrap()
        .with_default_corners();
        let t = Threshold {
            size_min: 0.01,
            size_max: 0.1,
            dist_min: 0.0,
            dist_max: 0.5,
        };
        let strip = SizeField::threshold(&r, &[Toward::Marker(4)], t).unwrap();
        let ends = SizeField::threshold(&r, &[Toward::Marker(2), Toward::Marker(3)], t).unwrap();
        for (p, d_strip, d_ends) in [
            ((2.0, 0.1), 0.1, 1.9),
            ((0.5, 0.1), 1.0_f64.hypot(0.1), 0.5),
            ((3.9, 0.5), 1.4_f64.hypot(0.5), 0.1),
        ] {
            let p = DVec2::new(p.0, p.1);
            assert!((strip.at(p) - t.at(d_strip)).abs() < 2e-3, "{p}");
            assert!((ends.at(p) - t.at(d_ends)).abs() < 2e-3, "{p}");
        }
        let e = SizeField::threshold(&r, &[Toward::Marker(7)], t).unwrap_err();
        assert!(e.to_string().contains("markers are 1, 2, 3, 4"), "{e}");
        let circle = Region::builtin("circle").unwrap();
        let e = SizeField::threshold(&circle, &[Toward::Marker(1)], t).unwrap_err();
        assert!(e.to_string().contains("numbers no walls"), "{e}");
    }

    #[test]
    fn a_distance_field_toward_an_embedded_line_measures_the_distance_to_its_segments() {
        // A bent interface (0.4, 0) → (0.6, 0.5) → (0.4, 1) across the unit square.
        let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from);
        let line = crate::EmbeddedLine {
            points: [(0.4, 0.0), (0.6, 0.5), (0.4, 1.0)]
                .map(DVec2::from)
                .to_vec(),
            marker: 0,
        };
        let r = Region::from_loops("square", vec![(crate::LoopRole::Outer, square.to_vec())])
            .unwrap()
            .with_embedded_lines([line])
            .unwrap();
        let t = Threshold {
            size_min: 0.01,
            size_max: 0.1,
            dist_min: 0.0,
            dist_max: 0.5,
        };
        let h = SizeField::threshold(&r, &[Toward::Line(0)], t).unwrap();
        let bend_to = |p: DVec2| {
            [((0.4, 0.0), (0.6, 0.5)), ((0.6, 0.5), (0.4, 1.0))]
                .map(|(a, b)| crate::predicates::closest_on_segment(a.into(), b.into(), p).2)
                .into_iter()
                .fold(f64::INFINITY, f64::min)
                .sqrt()
        };
        for p in [
            (0.6, 0.5),
            (0.9, 0.5),
            (0.1, 0.9),
            (0.5, 0.25),
            (0.95, 0.05),
        ] {
            let p = DVec2::from(p);
            assert!(
                (h.at(p) - t.at(bend_to(p))).abs() < 2e-3,
                "{p}: {}",
                h.at(p)
            );
        }
        // A marker names the lines it marks too.
        let marked = r
            .clone()
            .with_embedded_lines([crate::EmbeddedLine {
                points: vec![DVec2::new(0.1, 0.2), DVec2::new(0.2, 0.2)],
                marker: 5,
            }])
            .unwrap();
        let by_marker = SizeField::threshold(&marked, &[Toward::Marker(5)], t).unwrap();
        let p = DVec2::new(0.15, 0.5);
        assert!(
            (by_marker.at(p) - t.at(0.3)).abs() < 2e-3,
            "{}",
            by_marker.at(p)
        );
        let e = SizeField::threshold(&r, &[Toward::Line(1)], t).unwrap_err();
        assert!(matches!(
            e,
            SizeFieldError::UnknownLine { index: 1, lines: 1 }
        ));
        assert!(e.to_string().contains("1 embedded line (") && e.to_string().contains("no line 1"));
    }

    #[test]
    fn a_distance_field_toward_one_piece_refines_that_wall_only() {
        // square_hole's outer loop is four straight pieces; find the bottom side y = -1.
        let r = Region::builtin("square_hole").unwrap();
        let bottom = r
            .pieces()
            .iter()
            .position(|p| p.start().y == -1.0 && p.end().y == -1.0)
            .expect("a bottom side");
        let t = Threshold {
            size_min: 0.01,
            size_max: 0.1,
            dist_min: 0.0,
            dist_max: 0.5,
        };
        let wall = SizeField::threshold(&r, &[Toward::Piece(bottom)], t).unwrap();
        for (p, d) in [
            ((0.5, -0.9), 0.1),
            ((-0.7, -0.8), 0.2),
            ((0.0, 0.9), 1.9),
            ((0.9, 0.0), 1.0),
        ] {
            let want = t.at(d);
            let got = wall.at(DVec2::new(p.0, p.1));
            assert!((got - want).abs() < 2e-3, "{p:?}: {got} vs {want}");
        }
        let pieces = r.pieces().len();
        let e = SizeField::threshold(&r, &[Toward::Piece(pieces)], t).unwrap_err();
        assert!(matches!(e, SizeFieldError::UnknownPiece { index, .. } if index == pieces));
        assert!(e.to_string().contains(&format!("no piece {pieces}")), "{e}");
    }

    #[test]
    fn distance_fields_follow_the_threshold_and_combine_by_min() {
        let r = Region::builtin("annulus").unwrap();
        let t = Threshold {
            size_min: 0.01,
            size_max: 0.1,
            dist_min: 0.0,
            dist_max: 0.3,
        };
        // Toward the outer loop (a circle of radius 1 about the origin): h = 0.01 + 0.3 d.
        let outer = SizeField::threshold(&r, &[Toward::Loop(0)], t).unwrap();
        for radius in [0.95, 0.85, 0.75] {
            let p = DVec2::new(radius, 0.0);
            let want = t.at(1.0 - radius);
            assert!(
                (outer.at(p) - want).abs() < 2e-3,
                "{radius}: {} vs {want}",
                outer.at(p)
            );
        }
        let point = SizeField::threshold(&r, &[Toward::Point(DVec2::new(0.0, 0.8))], t).unwrap();
        let both = outer.min(&point, &r).unwrap();
        for p in [
            DVec2::new(0.7, 0.0),
            DVec2::new(0.0, 0.75),
            DVec2::new(-0.6, -0.3),
        ] {
            assert!(
                (both.at(p) - outer.at(p).min(point.at(p))).abs() < 2e-3,
                "{p}"
            );
        }
        for bad in [
            Threshold { size_min: 0.0, ..t },
            Threshold {
                size_max: 0.001,
                ..t
            },
            Threshold {
                dist_min: 0.3,
                dist_max: 0.2,
                ..t
            },
            Threshold {
                dist_min: f64::NAN,
                ..t
            },
        ] {
            assert!(matches!(
                SizeField::threshold(&r, &[Toward::Loop(0)], bad),
                Err(SizeFieldError::Threshold { .. })
            ));
        }
        assert!(matches!(
            SizeField::threshold(&r, &[], t),
            Err(SizeFieldError::NothingToward)
        ));
    }

    #[test]
    fn bad_bounds_and_gradations_are_refused() {
        let r = Region::builtin("circle").unwrap();
        let h = SizeField::constant(0.1);
        for (min, max, says) in [
            (
                Some(0.2),
                Some(0.1),
                "0.2 is larger than the largest (size_max, --size-max) 0.1",
            ),
            (
                Some(-1.0),
                None,
                "(size_min, --size-min) must be finite and at least 0",
            ),
            (None, Some(-1.0), "(size_max, --size-max) must be positive"),
            (Some(f64::NAN), None, "got NaN"),
            (Some(f64::INFINITY), None, "got inf"),
            (None, Some(0.0), "got 0"),
        ] {
            let e = h.bounded(&r, min, max, None).unwrap_err();
            assert!(
                matches!(e, SizeFieldError::Bounds { .. }),
                "{min:?} {max:?}"
            );
            assert!(e.to_string().contains(says), "{e}");
        }
        // 0 and ∞ bound nothing, as Gmsh's defaults do.
        let open = h.bounded(&r, Some(0.0), Some(f64::INFINITY), None).unwrap();
        assert_eq!(open.at(DVec2::ZERO), 0.1);
        for g in [0.0, -1.0, f64::NAN] {
            assert!(
                matches!(
                    h.bounded(&r, None, None, Some(g)),
                    Err(SizeFieldError::Gradation(_))
                ),
                "{g}"
            );
        }
    }

    #[test]
    fn predicted_points_integrates_a_graded_field() {
        // On the unit circle, h = 0.05 (1 + r): ∫ h⁻² = 2π/0.0025 ∫₀¹ r/(1+r)² dr
        // = 2π/0.0025 (ln 2 − 1/2).
        let r = Region::builtin("circle").unwrap();
        let h = SizeField::from_expr("0.05 * (1 + sqrt(x^2 + y^2))").unwrap();
        let exact = 2.0 / 3f64.sqrt() * 2.0 * std::f64::consts::PI / 0.0025 * (2f64.ln() - 0.5);
        let n = h.predicted_points(&r);
        assert!((n - exact).abs() < 5e-3 * exact, "{n} vs {exact}");
    }

    /// A point source's rise is reported at the source, under gradation limiting and from an
    /// expression as well; fields the grid follows (the graded comparison's, a steep but
    /// gradation-limited one) are not, nor is a constant one.
    #[test]
    fn a_rise_too_steep_for_the_grid_is_reported_where_it_is() {
        let circle = Region::builtin("circle").unwrap();
        let source = DVec2::new(0.3, 0.2);
        let toward = [Toward::Point(source)];
        let t = |size_min| Threshold {
            size_min,
            size_max: 0.1,
            dist_min: 0.0,
            dist_max: 1.0,
        };
        let fine = SizeField::threshold(&circle, &toward, t(1e-5)).unwrap();
        let graded = fine.bounded(&circle, None, None, Some(0.3)).unwrap();
        let expr = SizeField::from_expr("1e-5 + 0.1 * sqrt((x - 0.3)^2 + (y - 0.2)^2)").unwrap();
        for (name, h) in [
            ("threshold", &fine),
            ("bounded", &graded),
            ("expression", &expr),
        ] {
            let u = h
                .unresolved(&circle)
                .unwrap_or_else(|| panic!("{name}: nothing reported"));
            assert!((u.at - source).length() < 2.0 * u.step, "{name}: {u}");
            assert!(u.neighbour > 2.0 * u.size && u.size < 1e-3, "{name}: {u}");
            assert!(u.to_string().contains("over one step"), "{name}: {u}");
            assert!(u.for_mesh().starts_with(&u.to_string()), "{name}: {u}");
        }
        // Where the sizes are read off a grid at all (`cvtmesh measure` reads an expression
        // where the edges are).
        assert!(fine.is_sampled() && graded.is_sampled());
        assert!(!expr.is_sampled() && !SizeField::constant(0.1).is_sampled());
        let (square_hole, _, toward_hole) = toward_the_hole();
        let followed = [
            SizeField::threshold(&circle, &toward, t(1e-2)).unwrap(),
            toward_hole,
            SizeField::from_expr("0.002 + 10 * x^2")
                .unwrap()
                .bounded(&circle, None, None, Some(0.3))
                .unwrap(),
            SizeField::constant(1e-9),
        ];
        assert!(followed[0].unresolved(&circle).is_none());
        assert!(followed[1].unresolved(&square_hole).is_none());
        assert!(followed[2].unresolved(&circle).is_none());
        assert!(followed[3].unresolved(&circle).is_none());
    }
}
