use thiserror::Error;

/// Everything that can be wrong with a region or its file. Messages name the file and the
/// problem so that a user can fix the input.
#[derive(Debug, Error)]
pub enum GeometryError {
    /// The file could not be read.
    #[error("cannot read region file {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file is not valid region JSON.
    #[error("region file {path}: {message}")]
    Parse {
        /// The file (or `<string>`).
        path: String,
        /// What is wrong, with line/column where known.
        message: String,
    },
    /// The geometry is invalid (open loop, self-intersection, hole outside, NaN, ...).
    #[error("region {region}: {message}")]
    Invalid {
        /// Region name or file.
        region: String,
        /// What is wrong, with coordinates where useful (e.g. the crossing point).
        message: String,
    },
    /// No built-in region has this name.
    #[error("unknown region '{0}'; built-in regions are: {1}")]
    UnknownBuiltin(String, String),
    /// The file's extension names no region format (and its text is no JSON object).
    #[error(
        "region file {path}: unknown region file extension {}; supported: .json (project schema \
         or GeoJSON), .geojson, .poly (Triangle), .txt/.xy/.dat (plain loops)",
        extension.as_deref().map_or("(none)".to_string(), |e| format!("'.{e}'"))
    )]
    UnknownFormat {
        /// The file.
        path: String,
        /// Its extension, lower case, if it has one.
        extension: Option<String>,
    },
}
