//! Voronoi cells clipped to a region (Section 2.1 eq. (1), restricted to Ω) and their moments.
use geometry::{DVec2, Density, PieceId, Polygon};

/// One generator's Voronoi cell V_k ∩ Ω (the union of its parts if Ω cuts it in several).
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// |V_k|.
    pub area: f64,
    /// Geometric centroid (Section 3, first moment / area).
    pub centroid: DVec2,
    /// Second-moment tensor about the centroid, normalised by the area: [Mxx, Mxy, Myy].
    pub second_moment: [f64; 3],
    /// ∫_V ρ dx (equals `area` for ρ ≡ 1).
    pub mass: f64,
    /// ρ-weighted centroid of eq. (2) (equals `centroid` for ρ ≡ 1).
    pub mass_centroid: DVec2,
    /// ∫_V ρ |x − z_k|² dx: this cell's term of the CVT energy (4).
    pub energy: f64,
    /// h_k = max over y in the closed cell of |z_k − y| (Section 3.2).
    pub h: f64,
    /// Boundary pieces the cell's closure touches (sorted, unique); empty for interior cells.
    pub pieces: Vec<PieceId>,
}

impl Cell {
    /// True if the cell's closure meets the boundary.
    pub fn on_boundary(&self) -> bool {
        !self.pieces.is_empty()
    }
}

/// The clipped Voronoi cells of all generators, indexed like the generators.
#[derive(Clone, Debug)]
pub struct Cells {
    /// One cell per generator.
    pub cells: Vec<Cell>,
}

impl Cells {
    /// CVT energy (4): Σ_k ∫_{V_k} ρ |x − z_k|² dx.
    pub fn energy(&self) -> f64 {
        self.cells.iter().map(|c| c.energy).sum()
    }
    /// Σ |V_k| (equals the domain polygon's area).
    pub fn total_area(&self) -> f64 {
        self.cells.iter().map(|c| c.area).sum()
    }
}

/// Clip every generator's Voronoi cell to `domain` and compute its moments. Generators must lie
/// in the domain or on its boundary. `delaunay` must be the triangulation of `points`.
/// Parallel over cells; the result does not depend on the thread count.
pub fn clipped_cells(
    points: &[DVec2],
    delaunay: &crate::Delaunay,
    domain: &Polygon,
    density: &Density,
) -> Cells {
    let _ = (points, delaunay, domain, density);
    todo!()
}
