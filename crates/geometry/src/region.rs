//! The region Ω: loops of pieces, corners, and the queries every method needs.
use crate::{piece::Piece, polygon::Polygon, GeometryError};
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

/// A planar region: one outer loop and any number of holes, validated and oriented
/// (outer CCW, holes CW).
#[derive(Clone, Debug)]
pub struct Region {
    pub(crate) name: String,
    pub(crate) pieces: Vec<Piece>,
    pub(crate) piece_loop: Vec<usize>,
    pub(crate) loops: Vec<Loop>,
    pub(crate) corners: Vec<Corner>,
    pub(crate) area: f64,
    /// Corner-angle threshold applied (degrees), if any (`with_corner_angle`).
    pub(crate) corner_threshold: Option<f64>,
}

impl Region {
    /// Build from loops of pieces (outer first). Validates (closed, no self-intersection, no
    /// loops crossing, holes inside the outer loop, finite numbers), normalises orientation,
    /// and takes `corners` as given (`None`: every junction whose turning angle exceeds 1e-6 rad).
    pub fn new(
        name: &str,
        loops: Vec<(LoopRole, Vec<Piece>)>,
        corners: Option<Vec<DVec2>>,
    ) -> Result<Region, GeometryError> {
        let _ = (name, loops, corners);
        todo!()
    }

    /// Name (file stem or built-in name).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// All pieces, indexed by `PieceId`.
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces
    }
    /// Loop of each piece.
    pub fn piece_loop(&self, piece: PieceId) -> usize {
        self.piece_loop[piece]
    }
    /// The loops, outer first.
    pub fn loops(&self) -> &[Loop] {
        &self.loops
    }
    /// The corners.
    pub fn corners(&self) -> &[Corner] {
        &self.corners
    }
    /// The corner-angle threshold (degrees) applied when the region was loaded, if any.
    pub fn corner_threshold(&self) -> Option<f64> {
        self.corner_threshold
    }
    /// Exact area |Ω| (analytic for circles, arcs, super-ellipses).
    pub fn area(&self) -> f64 {
        self.area
    }
    /// Bounding box (min, max).
    pub fn bbox(&self) -> (DVec2, DVec2) {
        todo!()
    }
    /// Length of the bounding box diagonal.
    pub fn diameter(&self) -> f64 {
        let (lo, hi) = self.bbox();
        (hi - lo).length()
    }
    /// Total boundary length.
    pub fn perimeter(&self) -> f64 {
        self.loops.iter().map(|l| l.length).sum()
    }
    /// True if `p` is in the closed region.
    pub fn contains(&self, p: DVec2) -> bool {
        self.signed_distance(p) <= 0.0
    }
    /// Signed distance to the boundary: negative inside, positive outside.
    pub fn signed_distance(&self, p: DVec2) -> f64 {
        let _ = p;
        todo!()
    }
    /// Nearest boundary point over all pieces.
    pub fn project(&self, p: DVec2) -> BoundaryPoint {
        let _ = p;
        todo!()
    }
    /// Nearest point on one given piece (the "own piece" projection of CCVT step 5).
    pub fn project_onto_piece(&self, p: DVec2, piece: PieceId) -> BoundaryPoint {
        let _ = (p, piece);
        todo!()
    }
    /// Straight-edged approximation with chord error ≤ `tol`; corners are kept as vertices.
    pub fn polygonize(&self, tol: f64) -> Polygon {
        let _ = tol;
        todo!()
    }
    /// Ω_ε = {x : dist(x, Ω) ≤ ε} of Section 2.4, polygonized to `tol`; each edge's piece is
    /// the piece of Ω it is nearest to. Holes shrink and vanish when ε exceeds their inradius.
    pub fn expand(&self, eps: f64, tol: f64) -> Polygon {
        crate::expand::expand(self, eps, tol)
    }
    /// The same region with only the corners whose turning angle exceeds `degrees`; pieces
    /// joined at the dropped corners merge into `Piece::Chain`s.
    pub fn with_corner_angle(&self, degrees: f64) -> Region {
        let _ = degrees;
        todo!()
    }
    /// Read a region file (the project's JSON schema, see `domains/`).
    pub fn from_file(path: &std::path::Path) -> Result<Region, GeometryError> {
        crate::file::from_file(path)
    }
    /// Parse region JSON; `label` names the source in errors.
    pub fn from_json_str(text: &str, label: &str) -> Result<Region, GeometryError> {
        crate::file::from_json_str(text, label)
    }
    /// One of the paper's ten regions by name (`circle`, `lake`, ...).
    pub fn builtin(name: &str) -> Result<Region, GeometryError> {
        crate::file::builtin(name)
    }
    /// Names of the built-in regions, in the paper's table order.
    pub fn builtin_names() -> &'static [&'static str] {
        crate::file::BUILTIN_NAMES
    }
}
