//! How well a graded mesh follows its size field h(x): the measures mesh adaptation tools
//! report (mmg's "unit mesh" share, Dobrzynski's efficiency index), and the angles.
//!
//! An edge's length in the metric of the field is l = |e| / h(midpoint). A mesh is a *unit
//! mesh* when every l lies in [1/√2, √2]; the efficiency index E = exp(mean δ), with
//! δ = l − 1 for l < 1 and δ = 1/l − 1 otherwise, is 1 for a mesh whose every edge has l = 1
//! and falls as edges stray either way.
use crate::exact::{check_points, check_triangles};
use crate::MetricsError;
use geometry::{Region, SizeField};
use mesh::Mesh;

/// Size conformity and angles of a mesh against a size field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeConformity {
    /// Number of edges.
    pub edges: usize,
    /// Share of edges with l = |e| / h(midpoint) in [1/√2, √2].
    pub unit_share: f64,
    /// E = exp(mean δ), δ = l − 1 for l < 1 and 1/l − 1 otherwise (1 is ideal).
    pub efficiency: f64,
    /// Mean of l.
    pub mean_length: f64,
    /// Smallest angle of any triangle, in degrees.
    pub min_angle_deg: f64,
    /// 1st percentile of the triangles' smallest angles, in degrees.
    pub min_angle_p1_deg: f64,
    /// Number of vertices.
    pub vertices: usize,
    /// The vertex count the field asks for on the region, (2/√3) ∫ h⁻² dx.
    pub predicted_vertices: f64,
}

impl SizeConformity {
    /// Names of the values, in [`SizeConformity::values`] order (also a CSV header).
    pub const NAMES: [&'static str; 8] = [
        "edges",
        "unit_share",
        "efficiency",
        "mean_length",
        "min_angle_deg",
        "min_angle_p1_deg",
        "vertices",
        "predicted_vertices",
    ];

    /// The values in [`SizeConformity::NAMES`] order (counts as floats).
    pub fn values(&self) -> [f64; 8] {
        [
            self.edges as f64,
            self.unit_share,
            self.efficiency,
            self.mean_length,
            self.min_angle_deg,
            self.min_angle_p1_deg,
            self.vertices as f64,
            self.predicted_vertices,
        ]
    }
}

/// Size conformity of `mesh` against `field` on `region` (see the module documentation).
///
/// ```
/// use cvtmesh::metrics::size_conformity;
/// use cvtmesh::geometry::{DVec2, Region, SizeField};
/// use cvtmesh::{Mesh, VertexMarker};
///
/// // Two equilateral triangles of side 0.1 (a rhombus): every edge has l = 1 for h ≡ 0.1.
/// let s = 3f64.sqrt() / 2.0;
/// let mesh = Mesh {
///     points: vec![DVec2::new(0.0, 0.0), DVec2::new(0.1, 0.0), DVec2::new(0.05, 0.1 * s), DVec2::new(0.15, 0.1 * s)],
///     triangles: vec![[0, 1, 2], [1, 3, 2]],
///     markers: vec![VertexMarker::Interior; 4],
/// };
/// let region = Region::builtin("circle")?;
/// let c = size_conformity(&mesh, &SizeField::constant(0.1), &region)?;
/// assert_eq!(c.edges, 5);
/// assert_eq!(c.unit_share, 1.0);
/// assert!((c.efficiency - 1.0).abs() < 1e-12 && (c.min_angle_deg - 60.0).abs() < 1e-9);
/// // Against h ≡ 0.05 every edge is twice too long: l = 2, δ = −1/2, none in [1/√2, √2].
/// let c = size_conformity(&mesh, &SizeField::constant(0.05), &region)?;
/// assert_eq!(c.unit_share, 0.0);
/// assert!((c.efficiency - (-0.5f64).exp()).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn size_conformity(
    mesh: &Mesh,
    field: &SizeField,
    region: &Region,
) -> Result<SizeConformity, MetricsError> {
    check_points(&mesh.points)?;
    check_triangles(mesh.points.len(), &mesh.triangles)?;
    let mut edges: Vec<(u32, u32)> = mesh
        .triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let (lo, hi) = (0.5f64.sqrt(), 2f64.sqrt());
    let (mut unit, mut delta, mut sum_l) = (0usize, 0.0, 0.0);
    for &(a, b) in &edges {
        let (p, q) = (mesh.points[a as usize], mesh.points[b as usize]);
        let l = (q - p).length() / field.at(0.5 * (p + q));
        unit += usize::from((lo..=hi).contains(&l));
        delta += if l < 1.0 { l - 1.0 } else { 1.0 / l - 1.0 };
        sum_l += l;
    }
    let n = edges.len() as f64;
    let mut angles: Vec<f64> = (0..mesh.num_triangles())
        .map(|t| {
            let p = mesh.triangle(t);
            (0..3)
                .map(|i| {
                    let (u, v) = (p[(i + 1) % 3] - p[i], p[(i + 2) % 3] - p[i]);
                    u.angle_to(v).abs().to_degrees()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    angles.sort_unstable_by(f64::total_cmp);
    let p1 = angles[(angles.len() - 1) / 100];
    Ok(SizeConformity {
        edges: edges.len(),
        unit_share: unit as f64 / n,
        efficiency: (delta / n).exp(),
        mean_length: sum_l / n,
        min_angle_deg: angles[0],
        min_angle_p1_deg: p1,
        vertices: mesh.num_vertices(),
        predicted_vertices: field.predicted_points(region),
    })
}
