//! The one triangle mesh type every method produces, the [`Mesher`] interface they share,
//! the conformity check every mesh must pass, and mesh file formats.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

mod check;
mod dual;
mod error;
pub mod io;
mod lines;
mod mesher;
mod parts;
mod polish;
mod quadratic;
mod subdomains;
mod thin;
mod types;

pub use check::{
    check_conforming, chord_allowance, measurable, min_angle_and_slivers, short_coverage, slivers,
    slivers_in_region, ConformityError, ShortCoverage, Slivers, CHORD_ALLOWANCE, EDGE_ALLOWANCE,
    MIN_COVERAGE, SLIVER_ANGLE_DEG,
};
pub use dual::Dual;
pub use error::MeshError;
pub use lines::{line_edges, sliver_advice, split_at_spacing};
pub use mesher::{
    boundary_points_needed, memory_estimate, refuse_embedded, total_memory, MeshRequest,
    MeshResult, Mesher, Progress, Size, BYTES_PER_VERTEX, GRADATION_NOTE, MAX_POINTS,
    SIMPLIFY_SPACINGS,
};
pub use parts::CONFORMITY_CHECK_LIMIT;
pub use polish::{
    looks_graded, polish, polish_restored, polish_restored_holding, polish_within, PolishReport,
    Polished, GRADED_SPREAD, POLISH_BELOW_DEG,
};
pub use quadratic::Quadratic;
pub use subdomains::{has_subdomains, subdomain_points_of, subdomains};
pub use thin::{thin_feature, ThinFeature};
pub use types::{triangle_min_angle_deg, BoundaryEdge, Mesh, VertexMarker};
