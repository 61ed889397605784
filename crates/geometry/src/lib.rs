//! Planar regions of the paper (Section 2.2): an outer boundary loop and hole loops, each a
//! chain of smooth *boundary pieces* joined at *corners*.
//!
//! Everything downstream (tessellation, methods, measures) sees a region only through
//! [`Region`] and the straight-edged [`Polygon`] it polygonizes to.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

mod background;
mod build;
mod crossings;
mod density;
mod error;
mod expand;
pub mod expr;
mod faces;
mod file;
pub mod formats;
mod index;
mod lines;
mod numeric;
mod piece;
mod polygon;
pub mod predicates;
mod region;
mod rng;
mod se;
mod simplify;
mod size;
mod spacing_corners;
mod state;
mod subdomains;
mod triangulated;
mod types;

pub use build::{DEFAULT_CORNER_ANGLE, EXTENT_LIMIT, OFFSET_LIMIT};
pub use density::Density;
pub use error::GeometryError;
pub use glam::DVec2;
pub use lines::EmbeddedLine;
pub use numeric::ln_gamma;
pub use piece::Piece;
pub use polygon::{Polygon, Ring};
pub use region::{Part, Region, INSIDE_GRID};
pub use rng::Rng;
pub use simplify::Simplified;
pub use size::{
    SampledDensity, SizeField, SizeFieldError, SizeRange, Threshold, Toward, Unresolved,
    MAX_GRID_SIDE,
};
pub use spacing_corners::{SpacingCorners, BEND_TOLERANCE, CHORDS, GAP_SPACINGS};
pub use types::{BoundaryPoint, Corner, Loop, LoopRole, PieceId};
