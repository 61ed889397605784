//! Constrained centroidal Voronoi tessellation (CCVT) meshes: Algorithms 1 and 2 of Section 2.4
//! of Nguyen, Burkardt, Gunzburger, Ju & Saka (2009).
//!
//! [`Ccvt`] is a [`Mesher`](mesh::Mesher). Its [`Algorithm`]:
//!
//! * [`Algorithm::One`] — Lloyd's method in which boundary cells' generators go to the
//!   projection of their centroid onto their own boundary piece and corner cells' generators
//!   to their corner (the CCVT of Section 2.2.3, eq. (8)).
//! * [`Algorithm::Two`] — first an ordinary CVT of the ε-expanded region Ω_ε with ε chosen
//!   adaptively, then Algorithm 1 on Ω_ε with boundary centroids projected onto ∂Ω.
//!
//! and the [`Solver`] that runs each phase:
//!
//! * [`Solver::Lloyd`] — every generator to its (constrained) centroid, as in the paper.
//! * [`Solver::Anderson`] — Anderson mixing of the fixed-point map, safeguarded by the CVT
//!   energy (a step that raises it is replaced by the plain Lloyd step).
//! * [`Solver::Newton`] (the default) — Newton steps on the energy with its exact Hessian
//!   (`tessellation::energy_hessian`) restricted to the moves Algorithm 1 allows, a
//!   Levenberg–Marquardt shift and the same energy safeguard.
//!
//! Every per-generator pass (triangulation and clipped cells in `tessellation`, labels and
//! projections, the convergence test, Anderson's mixing, Newton's linear algebra) runs in
//! parallel, and the result does not depend on the thread count. [`Generators::profile`] says
//! where the time went.
#![forbid(unsafe_code)]

mod active;
mod anderson;
mod init;
mod iterate;
mod map;
mod method;
mod newton;
mod params;
mod sublevel;

pub use init::{initial_points, Init};
pub use map::Profile;
pub use method::{Ccvt, Generators};
pub use params::{Algorithm, Solver};
