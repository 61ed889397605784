use crate::ConformityError;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why a method could not produce a mesh, or a mesh file could not be read or written.
///
/// The failures a caller can foresee and act on have their own variants (too few points, an
/// invalid request, a mesh that does not conform, a file problem); [`MeshError::BadRequest`] and
/// [`MeshError::Failed`] carry the rest as text. Every message names what to change.
///
/// ```
/// use cvtmesh::{MeshError, MeshRequest};
/// # use cvtmesh::geometry::Region;
/// let region = Region::builtin("hex_hole")?; // 12 corners on 2 loops
/// match MeshRequest::points(8).validate(&region) {
///     Err(MeshError::TooFewPoints { needed, corners, .. }) => {
///         assert_eq!((needed, corners), (12, 12));
///     }
///     other => panic!("expected TooFewPoints, got {other:?}"),
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum MeshError {
    /// K is below what the region's boundary needs: a vertex on every corner and at least three
    /// on every boundary loop ([`crate::boundary_points_needed`]), and one on every embedded
    /// point.
    #[error("{}", too_few_points(.region, *.requested, *.needed, (*.corners, *.embedded), *.loops, *.edge_length))]
    TooFewPoints {
        /// The region's name.
        region: String,
        /// The K asked for (derived from the edge length if one was given).
        requested: usize,
        /// The smallest K accepted: each loop's corners, and at least three on every loop.
        needed: usize,
        /// Number of corners of the region.
        corners: usize,
        /// Number of points embedded in the region ([`geometry::Region::embedded_points`]).
        embedded: usize,
        /// Number of boundary loops (1 + holes).
        loops: usize,
        /// The edge length K was derived from, if the size was given as one.
        edge_length: Option<f64>,
    },
    /// The convergence tolerance is not a positive finite number.
    #[error("the tolerance (tol, --tol) must be a positive finite number, got {0}")]
    InvalidTolerance(f64),
    /// The time limit is NaN or negative.
    #[error(
        "the time limit (time_limit, --time-limit) must be a number of seconds, 0 or more, got {0}"
    )]
    InvalidTimeLimit(f64),
    /// The polish threshold is not an angle from 0 to 60 degrees.
    #[error("the polish threshold (polish, --polish) must be an angle from 0 to 60 degrees (0: no polish), got {0}")]
    InvalidPolish(f64),
    /// The iteration cap is zero.
    #[error("the iteration cap (max_iter, --max-iter) must be at least 1")]
    ZeroMaxIter,
    /// The target edge length is not a positive finite number.
    #[error("the edge length (size, --size) must be a positive finite number, got {0}")]
    InvalidEdgeLength(f64),
    /// The density is negative or not finite somewhere in the region.
    #[error(
        "the density is {value} at ({x}, {y}): it must be finite and non-negative on the region"
    )]
    InvalidDensity {
        /// x of the offending point.
        x: f64,
        /// y of the offending point.
        y: f64,
        /// The density there.
        value: f64,
    },
    /// The density is zero at every sampled point of the region.
    #[error("the density is zero everywhere on the region")]
    ZeroDensity,
    /// A method's own setting is out of its range.
    #[error("{method}: {setting} must be {expected}, got {value}")]
    InvalidSetting {
        /// Method name.
        method: String,
        /// The setting (field) name.
        setting: &'static str,
        /// Its value.
        value: f64,
        /// The range it must be in.
        expected: &'static str,
    },
    /// A method's mesh does not conform to the region.
    #[error("{method}: the mesh does not conform to the region ({cause}); {hint}")]
    NotConforming {
        /// Method name.
        method: String,
        /// The first conformity failure found (its text is part of this error's message, so it
        /// is not also returned by `Error::source`).
        cause: ConformityError,
        /// What to change (e.g. "try a larger K").
        hint: String,
    },
    /// A size field that cannot be used on the region.
    #[error(transparent)]
    SizeField(#[from] geometry::SizeFieldError),
    /// A size field that asks for more than [`MAX_POINTS`](crate::MAX_POINTS) vertices
    /// (N ≈ (2/√3) ∫ h⁻² dx, with no K given).
    #[error("the size field asks for about {predicted:.3e} vertices (its smallest size {smallest:.3e}), more than cvtmesh meshes ({max} would need about 45 GiB); use larger sizes or give the number of points")]
    FieldTooFine {
        /// The vertex count the field asks for (may be infinite).
        predicted: f64,
        /// The field's smallest value on the region.
        smallest: f64,
        /// The limit.
        max: usize,
    },
    /// K is more than [`MAX_POINTS`](crate::MAX_POINTS).
    #[error("K = {requested} is more than cvtmesh meshes ({max} vertices would need about 45 GiB); use a larger size or fewer points")]
    TooManyPoints {
        /// K asked for.
        requested: usize,
        /// The limit.
        max: usize,
    },
    /// The request would need more memory than the machine has.
    #[error("K = {requested} would need about {} of memory ({bytes_per_vertex} bytes per vertex) but this machine has {}; ask for fewer points or a larger size", gib(*.bytes), gib(*.available))]
    TooMuchMemory {
        /// K asked for.
        requested: usize,
        /// The estimated peak, in bytes.
        bytes: u64,
        /// The estimate's bytes per vertex.
        bytes_per_vertex: u64,
        /// The machine's total memory, in bytes.
        available: u64,
    },
    /// A method was handed a region of several parts; [`Mesher::mesh_parts`](crate::Mesher::mesh_parts)
    /// meshes each part and merges the meshes.
    #[error("region '{region}' has {parts} disjoint parts and a method meshes one part at a time: mesh it through Mesher::mesh_parts (cvtmesh::mesh, Method::run, the command line and the Python package do)")]
    SeveralParts {
        /// The region's name.
        region: String,
        /// Its number of parts.
        parts: usize,
    },
    /// The request's cancel flag was set ([`MeshRequest::cancel_flag`](crate::MeshRequest::cancel_flag)).
    #[error("{method}: cancelled after {iterations} iterations")]
    Cancelled {
        /// Method name.
        method: String,
        /// Iterations run before the flag was seen.
        iterations: usize,
    },
    /// Another request a method cannot meet (message says which and why).
    #[error("{0}")]
    BadRequest(String),
    /// The method failed (message says where and why).
    #[error("{method}: {message}")]
    Failed {
        /// Method name.
        method: String,
        /// What went wrong.
        message: String,
    },
    /// A region problem.
    #[error(transparent)]
    Geometry(#[from] geometry::GeometryError),
    /// A mesh file's content or name is not acceptable (unknown extension, a malformed line, a
    /// mesh that cannot be written).
    #[error("{}: {message}", .path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The operating system refused to read or write a mesh file.
    #[error("{}: cannot {action}: {cause}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done ("read", "write", ...).
        action: String,
        /// The operating system's error (its text is part of this error's message, so it is not
        /// also returned by `Error::source`).
        cause: std::io::Error,
    },
}

impl MeshError {
    /// The file a [`MeshError::File`] or [`MeshError::Io`] error is about.
    pub fn path(&self) -> Option<&Path> {
        match self {
            MeshError::File { path, .. } | MeshError::Io { path, .. } => Some(path),
            _ => None,
        }
    }

    /// The error for a method setting `setting` of `method` whose `value` is not `expected`
    /// (e.g. "positive and finite").
    pub fn invalid_setting(
        method: &str,
        setting: &'static str,
        value: f64,
        expected: &'static str,
    ) -> MeshError {
        MeshError::InvalidSetting {
            method: method.to_string(),
            setting,
            value,
            expected,
        }
    }

    /// `Ok` if the setting's `value` is positive and finite, else
    /// [`MeshError::invalid_setting`].
    pub fn check_positive(
        method: &str,
        setting: &'static str,
        value: f64,
    ) -> Result<(), MeshError> {
        Self::check_setting(method, setting, value, value > 0.0, "positive and finite")
    }

    /// `Ok` if the setting's `value` is non-negative and finite, else
    /// [`MeshError::invalid_setting`].
    pub fn check_non_negative(
        method: &str,
        setting: &'static str,
        value: f64,
    ) -> Result<(), MeshError> {
        Self::check_setting(
            method,
            setting,
            value,
            value >= 0.0,
            "non-negative and finite",
        )
    }

    fn check_setting(
        method: &str,
        setting: &'static str,
        value: f64,
        in_range: bool,
        expected: &'static str,
    ) -> Result<(), MeshError> {
        if value.is_finite() && in_range {
            Ok(())
        } else {
            Err(Self::invalid_setting(method, setting, value, expected))
        }
    }

    /// True for errors that the request alone causes (checked by
    /// [`MeshRequest::validate`](crate::MeshRequest::validate) before any work is done).
    pub fn is_invalid_request(&self) -> bool {
        matches!(
            self,
            MeshError::TooFewPoints { .. }
                | MeshError::TooManyPoints { .. }
                | MeshError::FieldTooFine { .. }
                | MeshError::TooMuchMemory { .. }
                | MeshError::InvalidTolerance(_)
                | MeshError::InvalidTimeLimit(_)
                | MeshError::ZeroMaxIter
                | MeshError::InvalidPolish(_)
                | MeshError::InvalidEdgeLength(_)
                | MeshError::InvalidDensity { .. }
                | MeshError::ZeroDensity
        )
    }
}

/// Bytes as GiB (or MiB below one GiB), for messages.
fn gib(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= (1u64 << 30) as f64 {
        format!("{:.1} GiB", b / (1u64 << 30) as f64)
    } else {
        format!("{:.0} MiB", b / (1u64 << 20) as f64)
    }
}

fn too_few_points(
    region: &str,
    requested: usize,
    needed: usize,
    (corners, embedded): (usize, usize),
    loops: usize,
    edge_length: Option<f64>,
) -> String {
    let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    let mut s = format!(
        "K = {requested} is too small for region '{region}': it has {} and {}, so at least \
         {needed} vertices are needed (one on every corner, and at least three on every loop)",
        plural(corners, "corner"),
        plural(loops, "boundary loop"),
    );
    if embedded > 0 {
        s += &format!(
            ", and one on each of its {}",
            plural(embedded, "embedded point")
        );
    }
    match edge_length {
        Some(h) => {
            s += &format!("; the edge length {h} (size, --size) is too large for the region")
        }
        None => s += "; ask for more points",
    }
    if corners > 0 || embedded > 0 {
        s += ", keep only the sharper corners (corner_angle, --corner-angle), or simplify a \
              digitized boundary or line inside to the mesh's scale (simplify \"auto\", \
              --simplify auto)";
    }
    s
}
