use thiserror::Error;

/// Why a method could not produce a mesh, or a mesh file could not be read or written.
#[derive(Debug, Error)]
pub enum MeshError {
    /// The request cannot be met (e.g. K smaller than the number of corners).
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
    /// File input/output.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
}
