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

/// Where each generator moves before Algorithm 1's labels and projections (steps 2–3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Update {
    /// To the mass centroid of its Voronoi cell: CCVT.
    #[default]
    Centroid,
    /// VTM's optimal-Delaunay target for a generator whose Voronoi cell does not meet ∂Ω: the
    /// area-weighted mean of the circumcentres of its Delaunay triangles inside Ω (barycentres
    /// for triangles on the boundary of that set, `tessellation::odt_targets`). A generator
    /// whose cell meets ∂Ω follows Algorithm 1 as under `Centroid` (its centroid projected onto
    /// ∂Ω, or the corner its cell holds): its patch of triangles is cut by ∂Ω. This is VTM with
    /// CCVT's boundary rule. Plain Lloyd-type iteration only (there is no energy whose gradient
    /// Newton or Anderson could follow), and Algorithm 1 only.
    Odt,
}
