//! What the meshing targets share: one core per fuzzing process, the run their first two
//! bytes ask for, and what is asked of every mesh a method hands back.

use cvtmesh::{check_conforming, Mesh, MeshRequest, Method};
use geometry::Region;
use std::fmt;

/// Rayon on one thread: one fuzzing process is one core (rayon would otherwise start a worker
/// per core).
pub fn one_core() {
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global();
}

/// The run a target's first two bytes ask for: the method and K (8–39) from the first, the
/// iteration cap (1–8) from the low three bits of the second.
pub struct Run {
    pub method: Method,
    pub k: usize,
    pub max_iter: usize,
}

impl Run {
    pub fn new(head: u8, cap: u8) -> Run {
        Run {
            method: Method::ALL[head as usize % Method::ALL.len()],
            k: 8 + (head as usize / 8) % 32,
            max_iter: 1 + cap as usize % 8,
        }
    }

    /// `request` at a loose tolerance and the run's cap: robustness, not convergence, is
    /// under test.
    pub fn capped(&self, request: MeshRequest) -> MeshRequest {
        request.tol(1e-2).max_iter(self.max_iter)
    }
}

impl fmt::Display for Run {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} K={} max_iter={}", self.method, self.k, self.max_iter)
    }
}

/// A mesh a method returned conforms to the region (else a crash naming the run), and what the
/// command line reports on every mesh it writes (slivers, short coverage) neither panics nor
/// miscounts.
pub fn check_mesh(mesh: &Mesh, region: &Region, run: &str) {
    if let Err(e) = check_conforming(mesh, region) {
        panic!("{run}: a mesh that does not conform: {e}");
    }
    if let Some(s) = cvtmesh::slivers(mesh) {
        assert!(s.count > 0 && s.count <= s.triangles, "{s:?}");
        let _ = s.to_string();
    }
    let _ = cvtmesh::short_coverage(mesh, region).map(|s| s.to_string());
}
