//! The measures computed exactly from a point set, its triangles and its clipped Voronoi cells.
use crate::{nearest::nearest_neighbor_distances, Measures, MetricsError};
use geometry::{DVec2, Density, Region};
use mesh::Mesh;
use std::f64::consts::PI;
use tessellation::{clipped_cells, Cells, Delaunay};

/// Relative chord tolerance used to polygonize the region for the exact Voronoi measures:
/// the boundary is approximated to within `POLYGON_TOL · (|Ω|/K)^{1/2}`, i.e. relative to the
/// mesh spacing, so that a boundary cell's area, moments and h_k carry a relative error of
/// order 1e-6 at any K (a tolerance relative to the region's diameter would not: its error
/// relative to the cells grows with K). Dividing it by 100 changes the measures by less than
/// 1e-4 relative (checked by the `converged_in_polygon_tolerance` test).
// At K = 10⁵ in the unit circle, a tolerance of 1e-6·diameter moves h and ν by ~1e-3.
pub const POLYGON_TOL: f64 = 1e-6;

/// The 12 measures of a mesh, computed exactly as Section 3 defines them.
///
/// - λ, γ (and the γ_k in χ) from `mesh.points`;
/// - h, μ, χ, ν, τ, d from the Voronoi cells of `mesh.points` clipped to `region`, polygonized
///   with chord error [`polygon_tolerance`]; *all* cells count, boundary cells
///   included, as the paper states for ν;
/// - α, β, q, p from the mesh's own triangles (K̃ = `mesh.triangles.len()`);
/// - |Ω| = `region.area()` (exact, not the polygon's area).
///
/// A mesh of equal equilateral triangles is ideal for the triangle measures: an equilateral
/// triangle cut into four by its edge midpoints has α = β = q = p = 0 and λ = γ = 0.
///
/// ```
/// use cvtmesh::geometry::{DVec2, LoopRole, Piece, Region};
/// use cvtmesh::{Mesh, VertexMarker};
///
/// let c = [(0.0, 0.0), (1.0, 0.0), (0.5, 0.75f64.sqrt())].map(|(x, y)| DVec2::new(x, y));
/// let sides = (0..3).map(|i| Piece::Line { a: c[i], b: c[(i + 1) % 3] }).collect();
/// let triangle = Region::new("triangle", vec![(LoopRole::Outer, sides)], None)?;
/// let mut points = c.to_vec();
/// points.extend((0..3).map(|i| (c[i] + c[(i + 1) % 3]) / 2.0));
/// let markers = points
///     .iter()
///     .map(|&p| match triangle.project(p).corner {
///         Some(i) => VertexMarker::at_corner(&triangle, i),
///         None => VertexMarker::on_piece(&triangle, p, triangle.project(p).piece),
///     })
///     .collect();
/// let triangles = vec![[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];
/// let mesh = Mesh { points, triangles, markers };
///
/// let m = cvtmesh::metrics::measures(&mesh, &triangle)?;
/// assert_eq!((m.k, m.k_tilde), (6, 4));
/// for value in [m.alpha, m.beta, m.q, m.p, m.lambda, m.gamma] {
///     assert!(value.abs() < 1e-12, "{m:?}");
/// }
/// // The Voronoi cells of corner and midpoint vertices differ in area.
/// assert!(m.nu > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn measures(mesh: &Mesh, region: &Region) -> Result<Measures, MetricsError> {
    check_points(&mesh.points)?;
    check_triangles(mesh.points.len(), &mesh.triangles)?;
    let polygon = region.polygonize(polygon_tolerance(region, mesh.points.len()));
    let delaunay = Delaunay::new(&mesh.points);
    let cells = clipped_cells(&mesh.points, &delaunay, &polygon, &Density::Uniform);
    measures_from_parts(&mesh.points, &mesh.triangles, &cells, region.area())
}

/// The chord tolerance [`measures`] polygonizes `region` with for `k` points:
/// [`POLYGON_TOL`]` · (|Ω|/k)^{1/2}`.
pub fn polygon_tolerance(region: &Region, k: usize) -> f64 {
    POLYGON_TOL * (region.area() / k.max(1) as f64).sqrt()
}

pub(crate) fn check_points(points: &[DVec2]) -> Result<(), MetricsError> {
    if points.len() < 2 {
        return Err(MetricsError::TooFewPoints(points.len()));
    }
    if let Some((index, p)) = points.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(MetricsError::NonFinitePoint {
            index,
            x: p.x,
            y: p.y,
        });
    }
    Ok(())
}

pub(crate) fn check_triangles(n: usize, triangles: &[[u32; 3]]) -> Result<(), MetricsError> {
    if triangles.is_empty() {
        return Err(MetricsError::NoTriangles);
    }
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&v) = tri.iter().find(|&&v| v as usize >= n) {
            return Err(MetricsError::BadTriangle {
                triangle: t,
                vertex: v,
                points: n,
            });
        }
    }
    Ok(())
}

/// The measures from their ingredients (a pure function; [`measures`] and
/// [`crate::sampled_measures`] both end here).
///
/// `cells[k]` must be generator `k`'s Voronoi cell in Ω; its `area`, `second_moment` and `h`
/// are used (|V_k|, M_k, h_k). `area` is |Ω|. Conventions where the paper is silent:
/// - λ and p use the *population* standard deviation (divide by K, resp. K̃), as the
///   paper's formula for λ does explicitly;
/// - a triangle's smallest angle is taken over its three angles, each computed as
///   `atan2(|cross|, dot)` (accurate for tiny and near-π angles);
/// - degenerate input gives `inf`, e.g. a duplicated point (γ_k = 0: γ, χ = inf) or a
///   zero-area triangle (β, q, p = inf).
pub fn measures_from_parts(
    points: &[DVec2],
    triangles: &[[u32; 3]],
    cells: &Cells,
    area: f64,
) -> Result<Measures, MetricsError> {
    check_points(points)?;
    check_triangles(points.len(), triangles)?;
    if cells.cells.len() != points.len() {
        return Err(MetricsError::CellCount {
            cells: cells.cells.len(),
            points: points.len(),
        });
    }
    if !(area > 0.0 && area.is_finite()) {
        return Err(MetricsError::BadArea(area));
    }
    let k = points.len();
    let kf = k as f64;

    // 3.1: nearest-neighbour distances.
    let gk = nearest_neighbor_distances(points);
    let (lambda, gamma) = spread(&gk);

    // 3.2: Voronoi cells.
    let hk: Vec<f64> = cells.cells.iter().map(|c| c.h).collect();
    let h_max = max(&hk);
    let h_star = (12f64.sqrt() * area / (9.0 * kf)).sqrt();
    let h = h_max / h_star - 1.0;
    let mu = h_max / min(&hk) - 1.0;
    let chi = hk
        .iter()
        .zip(&gk)
        .map(|(h, g)| 3f64.sqrt() * h / g)
        .fold(f64::NEG_INFINITY, nan_max)
        - 1.0;
    let vk: Vec<f64> = cells.cells.iter().map(|c| c.area).collect();
    let nu = max(&vk) / min(&vk) - 1.0;
    let tk: Vec<f64> = cells
        .cells
        .iter()
        .map(|c| c.second_moment[0] + c.second_moment[2])
        .collect();
    let t_mean = tk.iter().sum::<f64>() / kf;
    let tau = tk.iter().map(|t| (t - t_mean).abs()).fold(0.0, nan_max);
    // det(M − (T/2) I) = −(((Mxx − Myy)/2)² + Mxy²): evaluated in this form it is exactly
    // 0 for an isotropic cell instead of a cancellation residue.
    let d = cells
        .cells
        .iter()
        .map(|c| {
            let [mxx, mxy, myy] = c.second_moment;
            let half = 0.5 * (mxx - myy);
            half * half + mxy * mxy
        })
        .fold(0.0, nan_max);

    // 3.3: triangles.
    let stats: Vec<TriangleStats> = triangles
        .iter()
        .map(|t| {
            TriangleStats::new(
                points[t[0] as usize],
                points[t[1] as usize],
                points[t[2] as usize],
            )
        })
        .collect();
    let kt = triangles.len() as f64;
    let alpha = kt / area * stats.iter().map(|s| s.area).fold(0.0, nan_max) - 1.0;
    let beta = (PI / 3.0)
        / stats
            .iter()
            .map(|s| s.min_angle)
            .fold(f64::INFINITY, nan_min)
        - 1.0;
    let q = stats.iter().map(|s| s.q).fold(f64::NEG_INFINITY, nan_max) - 1.0;
    let radii: Vec<f64> = stats.iter().map(|s| s.circumradius).collect();
    let p = if radii.iter().all(|r| r.is_finite()) {
        let mean = radii.iter().sum::<f64>() / kt;
        (radii.iter().map(|r| (r - mean) * (r - mean)).sum::<f64>() / kt).sqrt() / mean
    } else {
        f64::INFINITY
    };

    Ok(Measures {
        k,
        k_tilde: triangles.len(),
        lambda,
        gamma,
        h,
        mu,
        chi,
        nu,
        tau,
        d,
        alpha,
        beta,
        q,
        p,
    })
}

/// (λ, γ) of the nearest-neighbour distances: population coefficient of variation, and
/// max/min − 1.
fn spread(gk: &[f64]) -> (f64, f64) {
    let n = gk.len() as f64;
    let mean = gk.iter().sum::<f64>() / n;
    let var = gk.iter().map(|g| (g - mean) * (g - mean)).sum::<f64>() / n;
    (var.sqrt() / mean, max(gk) / min(gk) - 1.0)
}

/// max that propagates NaN (a NaN measure must not be hidden by `f64::max`).
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

fn nan_min(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.min(b)
    }
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, nan_max)
}

fn min(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, nan_min)
}

/// Per-triangle quantities of Section 3.3.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TriangleStats {
    /// |Δ| (unsigned).
    pub area: f64,
    /// Smallest interior angle (radians).
    pub min_angle: f64,
    /// q_j = abc / ((b+c−a)(c+a−b)(a+b−c)) = R/(2r); inf if degenerate.
    pub q: f64,
    /// Circumradius R = abc / (4|Δ|); inf if degenerate.
    pub circumradius: f64,
}

impl TriangleStats {
    pub(crate) fn new(p0: DVec2, p1: DVec2, p2: DVec2) -> Self {
        let (a, b, c) = ((p1 - p2).length(), (p2 - p0).length(), (p0 - p1).length());
        let area = 0.5 * (p1 - p0).perp_dot(p2 - p0).abs();
        let angle = |u: DVec2, v: DVec2| u.perp_dot(v).abs().atan2(u.dot(v));
        let min_angle = angle(p1 - p0, p2 - p0)
            .min(angle(p2 - p1, p0 - p1))
            .min(angle(p0 - p2, p1 - p2));
        let den = (b + c - a) * (c + a - b) * (a + b - c);
        let q = if den > 0.0 {
            a * b * c / den
        } else {
            f64::INFINITY
        };
        let circumradius = if area > 0.0 {
            a * b * c / (4.0 * area)
        } else {
            f64::INFINITY
        };
        TriangleStats {
            area,
            min_angle,
            q,
            circumradius,
        }
    }
}
