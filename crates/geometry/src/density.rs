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

    /// ρ where it is one known constant over the whole box `lo`–`hi`: 1 for ρ ≡ 1, a sampled
    /// density's value where every sample its interpolation reads there is the same
    /// ([`SampledDensity::constant_over`]), else None (a function is never known to be
    /// constant).
    ///
    /// ```
    /// use cvtmesh::geometry::{Density, DVec2};
    /// let (lo, hi) = (DVec2::ZERO, DVec2::ONE);
    /// assert_eq!(Density::Uniform.constant_over(lo, hi), Some(1.0));
    /// let f = Density::Function(std::sync::Arc::new(|_| 2.0));
    /// assert_eq!(f.constant_over(lo, hi), None);
    /// ```
    #[inline]
    pub fn constant_over(&self, lo: DVec2, hi: DVec2) -> Option<f64> {
        match self {
            Density::Uniform => Some(1.0),
            Density::Function(_) => None,
            Density::Sampled(s) => s.constant_over(lo, hi),
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
