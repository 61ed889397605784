//! Delaunay triangulation of generators (spade) and their Voronoi cells clipped to a region,
//! with the moments CCVT and the quality measures need.
#![forbid(unsafe_code)]

mod cells;
mod conforming;
mod delaunay;

pub use cells::{clipped_cells, Cell, Cells};
pub use conforming::{conforming_mesh, mark_vertices};
pub use delaunay::Delaunay;
