//! The plain data types a region is described with: piece ids, loop roles, loops, corners
//! and boundary points. A leaf module: everything else in the crate may use it.
use glam::DVec2;

/// Index of a boundary piece in `Region::pieces()` (global over all loops).
pub type PieceId = usize;

/// Outer boundary or hole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoopRole {
    /// The outer boundary (CCW).
    Outer,
    /// A hole (CW).
    Hole,
}

/// One closed boundary loop: pieces in traversal order, each starting where the last ended.
#[derive(Clone, Debug)]
pub struct Loop {
    /// Outer or hole.
    pub role: LoopRole,
    /// Global ids of this loop's pieces in order.
    pub pieces: Vec<PieceId>,
    /// Arc length at the start of each piece, measured from the loop's start.
    pub offsets: Vec<f64>,
    /// Total length.
    pub length: f64,
}

/// A corner Γ_c of Section 2.2.3: a junction of two pieces where the tangent jumps.
#[derive(Clone, Debug, PartialEq)]
pub struct Corner {
    /// Position.
    pub pos: DVec2,
    /// Loop it lies on.
    pub loop_index: usize,
    /// Piece ending here.
    pub piece_in: PieceId,
    /// Piece starting here.
    pub piece_out: PieceId,
    /// Arc-length position along its loop.
    pub loop_param: f64,
}

/// Result of projecting a point onto the boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryPoint {
    /// The nearest boundary point.
    pub point: DVec2,
    /// Its distance from the query point.
    pub distance: f64,
    /// Piece it lies on.
    pub piece: PieceId,
    /// Loop it lies on.
    pub loop_index: usize,
    /// Arc-length position along the loop (for ordering boundary vertices).
    pub loop_param: f64,
    /// The corner it coincides with (within 1e-12·diameter), if any.
    pub corner: Option<usize>,
}
