use thiserror::Error;

/// Why the measures could not be computed (structurally invalid input). Degenerate but
/// well-formed input (duplicate points, zero-area triangles, empty sampled cells) is not an
/// error: the affected measures are then `inf` (or `NaN` where a ratio is 0/0).
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum MetricsError {
    /// γ_k needs at least two points.
    #[error("the quality measures need at least 2 points, got {0}")]
    TooFewPoints(usize),
    /// α, β, q, p need at least one triangle.
    #[error("the quality measures need at least one triangle")]
    NoTriangles,
    /// A point coordinate is NaN or infinite.
    #[error("point {index} is not finite: ({x}, {y})")]
    NonFinitePoint {
        /// Point index.
        index: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
    },
    /// A triangle refers to a point that does not exist.
    #[error("triangle {triangle} refers to vertex {vertex}, but there are only {points} points")]
    BadTriangle {
        /// Triangle index.
        triangle: usize,
        /// The offending vertex index.
        vertex: u32,
        /// Number of points.
        points: usize,
    },
    /// There must be exactly one cell per point.
    #[error("{cells} Voronoi cells given for {points} points")]
    CellCount {
        /// Number of cells.
        cells: usize,
        /// Number of points.
        points: usize,
    },
    /// |Ω| must be positive and finite.
    #[error("region area must be positive and finite, got {0}")]
    BadArea(f64),
    /// The Monte-Carlo estimate was asked for zero samples.
    #[error("bad sampling parameters: samples must be positive")]
    NoSamples,
    /// The Monte-Carlo coordinate scale is not a positive finite number.
    #[error("bad sampling parameters: scale must be positive and finite, got {0}")]
    BadScale(f64),
    /// Rejection sampling found (almost) no points of the region in its bounding box.
    #[error("rejection sampling accepted only {accepted} of {tried} points; is the region empty?")]
    SamplingFailed {
        /// Points accepted.
        accepted: usize,
        /// Points tried.
        tried: usize,
    },
    /// A line of measures CSV could not be parsed.
    #[error("cannot parse measures CSV row: {0}")]
    Parse(String),
}
