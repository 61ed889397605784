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
//!
//! ```
//! use cvtmesh::ccvt::Ccvt;
//! use cvtmesh::geometry::Region;
//! use cvtmesh::{MeshRequest, Mesher};
//!
//! // The paper's Algorithm 2 with Lloyd iteration, watched through the progress reports.
//! let region = Region::builtin("circle")?;
//! let request = MeshRequest::points(88).tol(1e-4);
//! let mut reports = Vec::new();
//! let result = Ccvt::algorithm2().mesh(&region, &request, &mut |p| reports.push(p))?;
//! assert!(result.converged);
//! // Lloyd reports every iteration; the count restarts with each phase of Algorithm 2.
//! assert_eq!(reports.len(), result.iterations);
//! assert!(reports.iter().filter(|p| p.iteration == 1).count() >= 2);
//! // The last report is the final phase meeting the tolerance; the histories hold every report.
//! assert!(reports.last().unwrap().max_move < request.tol);
//! let energies: Vec<f64> = reports.iter().map(|p| p.energy).collect();
//! assert_eq!(energies, result.energy_history);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

mod active;
mod anderson;
mod init;
mod iterate;
mod map;
mod method;
mod moves;
mod newton;
mod params;
mod scale;
mod start;
mod sublevel;

pub use init::{initial_points, Init};
pub use map::Profile;
pub use method::{Ccvt, Generators};
pub use newton::piece_tangent;
pub use params::{Algorithm, Solver, Update};
