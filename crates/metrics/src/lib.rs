//! The 12 mesh quality measures of Section 3 of Nguyen, Burkardt, Gunzburger, Ju & Saka
//! (2009), for a mesh of K points and K̃ triangles in a region Ω.
//!
//! | measure | definition (k over points, j over triangles) | from |
//! |---|---|---|
//! | λ | std(γ_k)/mean(γ_k), γ_k = distance to the nearest other point | points |
//! | γ | max γ_k / min γ_k − 1 | points |
//! | h | max h_k / h* − 1, h_k = max_{y∈V_k} \|z_k − y\|, h* = (√12\|Ω\|/(9K))^{1/2} | cells |
//! | μ | max h_k / min h_k − 1 | cells |
//! | χ | max √3 h_k/γ_k − 1 | cells, points |
//! | ν | max \|V_k\| / min \|V_k\| − 1 | cells |
//! | τ | max \|τ_k − τ̄\|, τ_k = trace M_k | cells |
//! | d | max \|det(M_k − (τ_k/2) I)\| | cells |
//! | α | (K̃/\|Ω\|) max \|Δ_j\| − 1 | triangles |
//! | β | (π/3) / min (smallest angle of Δ_j) − 1 | triangles |
//! | q | max abc/((b+c−a)(c+a−b)(a+b−c)) − 1 | triangles |
//! | p | std(R_j)/mean(R_j), R_j circumradius (population std) | triangles |
//!
//! V_k is generator k's Voronoi cell intersected with Ω, M_k its second-moment tensor about
//! its centroid divided by |V_k|. [`measures`] computes these exactly (clipped cells, all
//! cells including boundary ones); [`sampled_measures`] estimates the cell-based ones by
//! Monte-Carlo sampling, which is how the paper's tables appear to have been computed.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

mod conformity;
mod error;
mod exact;
mod measures;
mod nearest;
mod sample;

pub use conformity::{size_conformity, SizeConformity};
pub use error::MetricsError;
pub use exact::{measures, measures_from_parts, polygon_tolerance, POLYGON_TOL};
pub use measures::Measures;
pub use sample::{sampled_measures, SampleParams};
