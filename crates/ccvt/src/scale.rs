//! The local spacing a density asks for, the yardstick of every per-generator length in a
//! phase: the convergence test, Newton's step cap, the active set's thresholds.
use geometry::{DVec2, Density, Region};
use rayon::prelude::*;

/// h(x) = s̄ · √(mean of ρ^½ over Ω) · ρ(x)^(−¼): spacing ∝ ρ^(−¼) (the CVT's density–spacing
/// law in 2D), normalised so that K hexagons of side h(x) tile Ω. For ρ ≡ 1 it is the mean
/// spacing s̄ itself, so uniform runs measure every move against the same number as before.
///
/// With a graded density a single yardstick fails both ends: a move of a tenth of the mean
/// spacing is several cells where the mesh is fine (the quadratic model is meaningless there)
/// and a hundredth of a cell where it is coarse (the elastic mode crawls).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LocalScale<'a> {
    spacing: f64,
    graded: Option<(f64, &'a Density)>,
    mean_sqrt: f64,
}

impl<'a> LocalScale<'a> {
    /// For K generators of mean spacing `spacing` on `region` with `density`.
    pub(crate) fn new(region: &Region, density: &'a Density, spacing: f64) -> Self {
        if density.is_uniform() {
            return LocalScale {
                spacing,
                graded: None,
                mean_sqrt: 1.0,
            };
        }
        // The mean of ρ^½ over Ω on the region's inside grid: a normalisation only, so a
        // percent of error scales every yardstick by half a percent.
        let inside = region.inside_grid().0;
        let roots: Vec<f64> = inside
            .par_iter()
            .map(|&p| density.at(p).max(0.0).sqrt())
            .collect();
        // Summed in row order.
        let (sum, count) = (roots.iter().sum::<f64>(), roots.len());
        let mean = if count > 0 && sum > 0.0 {
            sum / count as f64
        } else {
            1.0
        };
        LocalScale {
            spacing,
            graded: Some((spacing * mean.sqrt(), density)),
            mean_sqrt: mean,
        }
    }

    /// The mean of ρ^½ over Ω (1 for ρ ≡ 1).
    pub(crate) fn mean_sqrt_density(&self) -> f64 {
        self.mean_sqrt
    }

    /// The mean spacing s̄.
    pub(crate) fn mean(&self) -> f64 {
        self.spacing
    }

    /// True for a uniform density (the yardstick is the mean spacing everywhere).
    pub(crate) fn is_uniform(&self) -> bool {
        self.graded.is_none()
    }

    /// h at `p`; the mean spacing where ρ is zero or not finite there.
    #[inline]
    pub(crate) fn at(&self, p: DVec2) -> f64 {
        match self.graded {
            None => self.spacing,
            Some((c, density)) => {
                let h = c * density.at(p).powf(-0.25);
                if h.is_finite() && h > 0.0 {
                    h
                } else {
                    self.spacing
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn uniform_density_measures_by_the_mean_spacing() {
        let region = Region::builtin("circle").unwrap();
        let s = LocalScale::new(&region, &Density::Uniform, 0.1);
        assert!(s.is_uniform());
        assert_eq!(s.at(DVec2::new(0.3, 0.2)), 0.1);
    }

    #[test]
    fn graded_density_gives_spacing_proportional_to_rho_to_the_minus_quarter() {
        let region = Region::builtin("square_hole").unwrap();
        // ρ = 16 on the left half, 1 on the right: spacing 1/2 as large on the left.
        let rho = Density::Function(Arc::new(|p: DVec2| if p.x < 0.0 { 16.0 } else { 1.0 }));
        let s = LocalScale::new(&region, &rho, 0.1);
        let (left, right) = (s.at(DVec2::new(-0.5, 0.1)), s.at(DVec2::new(0.5, 0.1)));
        assert!((right / left - 2.0).abs() < 1e-12);
        // K hexagons of side h(x) tile Ω: ∫ h⁻² dx = ∫ s̄⁻² dx (the mean spacing's count),
        // within the grid's error; the hole makes the left and right halves equal in area.
        let ratio = 0.5 * (left.powi(-2) + right.powi(-2)) / 0.1f64.powi(-2);
        assert!((ratio - 1.0).abs() < 0.02, "{ratio}");
    }
}
