//! One smooth boundary piece Γ_j of Section 2.2.2.
use glam::DVec2;

/// A boundary piece: smooth between its end points (corners sit only at piece junctions).
/// Every piece is traversed in its loop's direction (outer CCW, holes CW).
#[derive(Clone, Debug, PartialEq)]
pub enum Piece {
    /// Straight segment from `a` to `b`.
    Line {
        /// Start.
        a: DVec2,
        /// End.
        b: DVec2,
    },
    /// Circular arc from angle `from` to angle `to` (radians); CCW when `to > from`.
    Arc {
        /// Centre.
        center: DVec2,
        /// Radius.
        radius: f64,
        /// Start angle (radians).
        from: f64,
        /// End angle (radians).
        to: f64,
    },
    /// A full circle, a whole loop on its own; `ccw` gives its direction.
    Circle {
        /// Centre.
        center: DVec2,
        /// Radius.
        radius: f64,
        /// Direction of traversal.
        ccw: bool,
    },
    /// A full super-ellipse |x/a|^n + |y/b|^n = 1 about `center`, a whole loop on its own.
    SuperEllipse {
        /// Centre.
        center: DVec2,
        /// Semi-axis along x.
        a: f64,
        /// Semi-axis along y.
        b: f64,
        /// Exponent n ≥ 2 (smooth).
        n: f64,
        /// Direction of traversal.
        ccw: bool,
    },
    /// A densely sampled curve (a parametric curve, or nearly straight polyline vertices merged
    /// by the corner-angle threshold), treated as one smooth piece.
    Chain(Vec<DVec2>),
}

impl Piece {
    /// First point.
    pub fn start(&self) -> DVec2 {
        todo!()
    }
    /// Last point (equals `start()` for closed pieces).
    pub fn end(&self) -> DVec2 {
        todo!()
    }
    /// True for pieces that form a whole loop (circle, super-ellipse).
    pub fn is_closed(&self) -> bool {
        matches!(self, Piece::Circle { .. } | Piece::SuperEllipse { .. })
    }
    /// Arc length.
    pub fn length(&self) -> f64 {
        todo!()
    }
    /// Nearest point of the piece to `p` and its arc-length parameter from `start()`.
    pub fn closest_point(&self, p: DVec2) -> (DVec2, f64) {
        todo!()
    }
    /// Points along the piece from `start()` to `end()` inclusive, such that the chord error
    /// (largest distance from the curve to the polyline) is at most `tol`.
    pub fn polygonize(&self, tol: f64) -> Vec<DVec2> {
        todo!()
    }
    /// Exact ∮ x dy over the piece (Green's theorem); summed over a loop it is the signed area.
    pub fn area_integral(&self) -> f64 {
        todo!()
    }
    /// Unit tangent at the start and at the end, in traversal direction (for corner angles).
    pub fn end_tangents(&self) -> (DVec2, DVec2) {
        todo!()
    }
}
