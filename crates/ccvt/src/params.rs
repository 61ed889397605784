//! The choices that select a CCVT variant: which algorithm of Section 2.4, and which
//! fixed-point solver runs inside each of its phases.

/// Which algorithm of Section 2.4.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Algorithm {
    /// Algorithm 1: CCVT by constrained Lloyd iteration on Ω.
    One,
    /// Algorithm 2: adaptive ε-expansion, then Algorithm 1 on Ω_ε projecting onto ∂Ω.
    Two,
}

/// The fixed-point iteration used inside each phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Plain Lloyd: every generator to its (constrained) centroid.
    Lloyd,
    /// Anderson mixing of the last `depth` Lloyd maps, rejected when it raises the energy.
    Anderson {
        /// History depth (5 is a good default).
        depth: usize,
    },
    /// Newton's method on the energy with the Hessian restricted to the allowed moves, a
    /// Levenberg–Marquardt shift and an energy safeguard (falls back to the Lloyd step).
    Newton,
}
