//! The study's error type.
use std::path::PathBuf;
use thiserror::Error;

/// Why the study could not run, read or write something. Messages say what to do.
#[derive(Debug, Error)]
pub enum StudyError {
    /// An unknown region name in `--regions`.
    #[error("unknown region '{name}'; valid regions: {valid}")]
    UnknownRegion {
        /// The name given.
        name: String,
        /// Comma-separated valid names.
        valid: String,
    },
    /// An unknown method name in `--methods`.
    #[error("unknown method '{name}'; valid methods: {valid}")]
    UnknownMethod {
        /// The name given.
        name: String,
        /// Comma-separated valid names.
        valid: String,
    },
    /// A malformed `--shard I/N`.
    #[error("bad shard '{0}': expected I/N with 1 <= I <= N, e.g. 3/8")]
    BadShard(String),
    /// Any other bad option value.
    #[error("{0}")]
    BadOption(String),
    /// Reading or writing a file failed. The OS error is part of the message and not also a
    /// source, so that printing the error with its chain says it once.
    #[error("{path}: {cause}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        cause: std::io::Error,
    },
    /// A CSV file is malformed.
    #[error("{path}: {message}")]
    Csv {
        /// The file (or a description of the embedded data).
        path: String,
        /// What is wrong.
        message: String,
    },
    /// Two merged CSVs contain the same (region, K, method, seed, kind) row.
    #[error("duplicate result for {0} in the merged inputs (do two shard directories overlap?)")]
    Duplicate(String),
    /// The shard directories given to a merge are not every shard of one run, once each.
    #[error("{0}")]
    ShardSet(String),
    /// A mesh file could not be read or written.
    #[error(transparent)]
    Mesh(#[from] cvtmesh::MeshError),
    /// A region could not be loaded.
    #[error(transparent)]
    Geometry(#[from] cvtmesh::geometry::GeometryError),
    /// A size field could not be built.
    #[error(transparent)]
    SizeField(#[from] cvtmesh::SizeFieldError),
    /// A picture could not be drawn or written.
    #[error(transparent)]
    Render(#[from] render::RenderError),
    /// The thread pool could not be built.
    #[error("cannot start the thread pool: {0}")]
    Pool(String),
}

impl StudyError {
    /// An I/O error at `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> StudyError {
        StudyError::Io {
            path: path.into(),
            cause: source,
        }
    }
}
