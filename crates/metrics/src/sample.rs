//! The Monte-Carlo estimate of the Voronoi measures, as the paper's tables were computed.
use crate::{
    exact::{check_points, check_triangles, measures_from_parts},
    nearest::PointGrid,
    Measures, MetricsError,
};
use geometry::{DVec2, Region, Rng};
use mesh::Mesh;
use rayon::prelude::*;
use tessellation::{Cell, Cells};

/// Parameters of [`sampled_measures`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleParams {
    /// Number N of sample points in Ω (John Burkardt's QUALITY library uses 10⁴).
    pub samples: usize,
    /// Seed of the [`Rng`] drawing the samples.
    pub seed: u64,
    /// Every coordinate (points and samples) is multiplied by this first. Only τ (∝ s²) and
    /// d (∝ s⁴) depend on it. The paper's circle and annulus tables match s = 0.5, the other
    /// regions s = 1.
    pub scale: f64,
}

impl Default for SampleParams {
    /// 10⁴ samples, seed 1, scale 1.
    fn default() -> Self {
        SampleParams {
            samples: 10_000,
            seed: 1,
            scale: 1.0,
        }
    }
}

/// Give up rejection sampling after this many tries per requested sample.
const MAX_TRIES_PER_SAMPLE: usize = 1000;

/// The paper-style estimate of the 12 measures.
///
/// N points are drawn uniformly in Ω (uniform in `region.bbox()`, rejected unless
/// `region.contains`), each is assigned to its nearest generator (exact grid search, ties to
/// the lower index), and generator k's cell is represented by its n_k samples:
/// |V_k| ≈ |Ω| n_k / N, centroid and second moment = the samples' mean and (population)
/// covariance, h_k = largest sample distance from z_k. h, μ, χ, ν, τ, d follow from these
/// exactly as in [`crate::measures_from_parts`]; λ, γ, α, β, q, p do not involve the cells and
/// equal the exact values. A generator with no sample gets |V_k| = h_k = 0 and a zero moment
/// (then ν = μ = inf), as in the QUALITY library. Deterministic for a given `params`.
pub fn sampled_measures(
    mesh: &Mesh,
    region: &Region,
    params: &SampleParams,
) -> Result<Measures, MetricsError> {
    if params.samples == 0 {
        return Err(MetricsError::NoSamples);
    }
    if !(params.scale > 0.0 && params.scale.is_finite()) {
        return Err(MetricsError::BadScale(params.scale));
    }
    check_points(&mesh.points)?;
    check_triangles(mesh.points.len(), &mesh.triangles)?;
    let s = params.scale;
    let points: Vec<DVec2> = mesh.points.iter().map(|p| *p * s).collect();
    let samples = draw_samples(region, params)?
        .into_iter()
        .map(|x| x * s)
        .collect::<Vec<_>>();
    let area = region.area() * s * s;
    let cells = sample_cells(&points, &samples, area);
    measures_from_parts(&points, &mesh.triangles, &cells, area)
}

/// `params.samples` points uniform in Ω, in draw order.
fn draw_samples(region: &Region, params: &SampleParams) -> Result<Vec<DVec2>, MetricsError> {
    let (lo, hi) = region.bbox();
    let mut rng = Rng::new(params.seed);
    let max_tries = params.samples.saturating_mul(MAX_TRIES_PER_SAMPLE);
    let mut out = Vec::with_capacity(params.samples);
    let mut tries = 0;
    while out.len() < params.samples {
        if tries == max_tries {
            return Err(MetricsError::SamplingFailed {
                accepted: out.len(),
                tried: tries,
            });
        }
        tries += 1;
        let x = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        if region.contains(x) {
            out.push(x);
        }
    }
    Ok(out)
}

/// Sample-based cells: moments are accumulated relative to the generator, which avoids the
/// cancellation of E[xxᵀ] − E[x]E[x]ᵀ far from the origin.
fn sample_cells(points: &[DVec2], samples: &[DVec2], area: f64) -> Cells {
    let grid = PointGrid::new(points);
    let owner: Vec<(usize, f64)> = samples
        .par_iter()
        .map(|x| grid.nearest(*x, None).expect("at least one generator"))
        .collect();
    #[derive(Clone, Copy, Default)]
    struct Acc {
        n: usize,
        sum: DVec2,
        sxx: f64,
        sxy: f64,
        syy: f64,
        max_d2: f64,
    }
    let mut acc = vec![Acc::default(); points.len()];
    for (x, &(k, d2)) in samples.iter().zip(&owner) {
        let r = *x - points[k];
        let a = &mut acc[k];
        a.n += 1;
        a.sum += r;
        a.sxx += r.x * r.x;
        a.sxy += r.x * r.y;
        a.syy += r.y * r.y;
        a.max_d2 = a.max_d2.max(d2);
    }
    let n_total = samples.len() as f64;
    let cells = acc
        .iter()
        .zip(points)
        .map(|(a, z)| {
            let cell_area = area * a.n as f64 / n_total;
            if a.n == 0 {
                return Cell {
                    area: 0.0,
                    centroid: *z,
                    second_moment: [0.0; 3],
                    mass: 0.0,
                    mass_centroid: *z,
                    energy: 0.0,
                    h: 0.0,
                    pieces: Vec::new(),
                };
            }
            let n = a.n as f64;
            let c = a.sum / n;
            let m = [
                a.sxx / n - c.x * c.x,
                a.sxy / n - c.x * c.y,
                a.syy / n - c.y * c.y,
            ];
            Cell {
                area: cell_area,
                centroid: *z + c,
                second_moment: m,
                mass: cell_area,
                mass_centroid: *z + c,
                energy: cell_area * (a.sxx + a.syy) / n,
                h: a.max_d2.sqrt(),
                pieces: Vec::new(),
            }
        })
        .collect();
    Cells { cells }
}
