use crate::{Mesh, MeshError};
use geometry::{Density, Region};

/// How fine the mesh should be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Size {
    /// K, the number of vertices (generators).
    Points(usize),
    /// A target edge length h; K is derived as the hexagonal-lattice count for |Ω|.
    EdgeLength(f64),
}

impl Size {
    /// The vertex count requested for `region`: for an edge length h, K = 2|Ω| / (√3 h²).
    pub fn points(&self, region: &Region) -> usize {
        match *self {
            Size::Points(k) => k,
            Size::EdgeLength(h) => (2.0 * region.area() / (3f64.sqrt() * h * h)).round() as usize,
        }
    }
}

/// What every method is asked for. Defaults: seed 1, tolerance 1e-4, at most 10 000
/// iterations (Lloyd-type methods converge linearly; CCVT applies the cap per phase), ρ ≡ 1.
#[derive(Clone, Debug)]
pub struct MeshRequest {
    /// Target size.
    pub size: Size,
    /// Seed of every random choice.
    pub seed: u64,
    /// Convergence tolerance, relative to the mean generator spacing.
    pub tol: f64,
    /// Iteration cap; hitting it is reported as not converged.
    pub max_iter: usize,
    /// Density ρ.
    pub density: Density,
}

impl MeshRequest {
    /// A request for K points with the documented defaults.
    pub fn points(k: usize) -> Self {
        MeshRequest {
            size: Size::Points(k),
            seed: 1,
            tol: 1e-4,
            max_iter: 10_000,
            density: Density::Uniform,
        }
    }
    /// Builder: seed.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }
    /// Builder: tolerance.
    pub fn tol(mut self, tol: f64) -> Self {
        self.tol = tol;
        self
    }
    /// Builder: iteration cap.
    pub fn max_iter(mut self, n: usize) -> Self {
        self.max_iter = n;
        self
    }
    /// Builder: density.
    pub fn density(mut self, d: Density) -> Self {
        self.density = d;
        self
    }
    /// Mean spacing of K generators on |Ω|: the hexagonal-lattice edge √(2|Ω| / (√3 K)).
    pub fn spacing(&self, region: &Region) -> f64 {
        let k = self.size.points(region).max(1) as f64;
        (2.0 * region.area() / (3f64.sqrt() * k)).sqrt()
    }
}

/// One progress report: iteration number, a method-specific objective (CVT energy for CVT
/// methods) and the largest vertex move relative to the mean spacing.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Iteration (1-based).
    pub iteration: usize,
    /// The iteration cap.
    pub max_iter: usize,
    /// Objective value (NaN if the method has none).
    pub energy: f64,
    /// Largest move divided by the mean spacing.
    pub max_move: f64,
}

/// What a method produced and how it got there.
#[derive(Clone, Debug)]
pub struct MeshResult {
    /// The conforming mesh.
    pub mesh: Mesh,
    /// Iterations run (outer iterations for nested schemes).
    pub iterations: usize,
    /// True only if the convergence criterion was met before the cap.
    pub converged: bool,
    /// Objective per iteration (CVT energy of eq. (4) for CVT methods; empty if none).
    pub energy_history: Vec<f64>,
    /// Largest relative move per iteration.
    pub move_history: Vec<f64>,
    /// Free-form notes for the user (e.g. "area bound 1.2e-3 after 14 bisection steps").
    pub notes: Vec<String>,
}

/// A mesh generator: a region and a request in, a conforming mesh out.
pub trait Mesher: Sync {
    /// Short name used on the command line and in tables (`ccvt2`, `distmesh`, ...).
    fn name(&self) -> &'static str;
    /// Mesh `region`. `progress` is called once per iteration.
    fn mesh(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<MeshResult, MeshError>;
}
