//! Delaunay triangulation of generators (spade) and their Voronoi cells clipped to a region,
//! with the moments CCVT and the quality measures need.
//!
//! - [`Delaunay`]: triangulation built by inserting points along a Hilbert curve (spade), kept
//!   as flat arrays (triangles, neighbours, canonically rotated vertex rings) that a rebuild of
//!   moved points repairs by Lawson flips when it can; optionally framed by far fixed vertices
//!   ([`Delaunay::framed`]) so that the hull never turns over; neighbours, triangles, nearest
//!   generator.
//! - [`clipped_cells`]: every generator's Voronoi cell ∩ Ω (a [`geometry::Polygon`]) with area,
//!   centroid, second moments, ρ-mass and ρ-centroid, CVT energy term, h_k and the boundary pieces
//!   it touches; exact for cells cut by holes or split by concave boundaries; parallel and
//!   independent of the thread count.
//! - [`odt_targets`] and [`odt_energy`]: VTM's optimal-Delaunay update on a triangle list.
//! - [`mark_vertices`] and [`conforming_mesh`]: from generators to a mesh that passes
//!   `mesh::check_conforming`.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

mod boundary;
mod cells;
mod clip;
mod conforming;
mod delaunay;
mod halves;
mod hessian;
mod odt;
mod sparse;
mod topology;

pub use cells::{
    clipped_cells, clipped_cells_into, clipped_cells_on, update_cells, Cell, Cells, CellsBuffer,
    DomainGrid,
};
pub use clip::segment_meets_box;
pub use conforming::{conforming_mesh, conforming_mesh_from, mark_vertices};
pub use delaunay::{hilbert_order, Delaunay};
pub use hessian::{energy_hessian, energy_hessian_on, energy_hessian_rows};
pub use odt::{odt_boundary_triangles, odt_energy, odt_targets};
pub use sparse::{dot, BlockMatrix, DOT_CHUNK};

/// `n` points drawn uniformly in the unit square, x then y from `rng` for each (tests).
#[cfg(test)]
pub(crate) fn unit_square_points(rng: &mut geometry::Rng, n: usize) -> Vec<geometry::DVec2> {
    (0..n)
        .map(|_| geometry::DVec2::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0)))
        .collect()
}
