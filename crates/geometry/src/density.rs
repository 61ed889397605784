//! The density ρ of eq. (2): constant by default, or a user function for graded meshes.
use crate::size::SampledDensity;
use glam::DVec2;
use std::sync::Arc;

/// A non-negative density ρ(x) on the region (eq. 2). `Uniform` is ρ ≡ 1.
#[derive(Clone, Default)]
pub enum Density {
    /// ρ ≡ 1: a uniform mesh, as in all of the paper's experiments.
    #[default]
    Uniform,
    /// A user function; it must be finite and non-negative on the region.
    Function(Arc<dyn Fn(DVec2) -> f64 + Send + Sync>),
    /// Samples on a background grid, interpolated by cubic B-splines: what a size field gives
    /// ([`crate::SizeField::density`]). A variant of its own rather than a function, so that
    /// the quadrature inlines the interpolation instead of calling through a pointer: the
    /// cells read ρ about 45 times per cell and evaluation.
    Sampled(Arc<SampledDensity>),
}

impl Density {
    /// ρ at `p`.
    #[inline]
    pub fn at(&self, p: DVec2) -> f64 {
        match self {
            Density::Uniform => 1.0,
            Density::Function(f) => f(p),
            Density::Sampled(s) => s.at(p),
        }
    }

    /// ρ at seven points (a quadrature rule's), the same values as [`Density::at`] at each.
    ///
    /// ```
    /// use cvtmesh::geometry::{Density, DVec2};
    /// let rho = Density::Function(std::sync::Arc::new(|p: DVec2| 1.0 + p.x * p.x));
    /// let ps = [DVec2::new(2.0, 0.0); 7];
    /// assert_eq!(rho.at7(&ps), [5.0; 7]);
    /// ```
    #[inline]
    pub fn at7(&self, ps: &[DVec2; 7]) -> [f64; 7] {
        match self {
            Density::Uniform => [1.0; 7],
            Density::Function(f) => ps.map(|p| f(p)),
            Density::Sampled(s) => s.at7(ps),
        }
    }

    /// True for ρ ≡ 1, where exact polygon moments replace quadrature.
    pub fn is_uniform(&self) -> bool {
        matches!(self, Density::Uniform)
    }
}

impl std::fmt::Debug for Density {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Density::Uniform => write!(f, "Uniform"),
            Density::Function(_) => write!(f, "Function(..)"),
            Density::Sampled(_) => write!(f, "Sampled(..)"),
        }
    }
}
