//! What the probes in `src/bin` share.
use geometry::Region;
use mesh::{check_conforming, MeshResult};

/// Print a probe's one-line account of a run: the K reached, K̃, the smallest angle, the
/// iterations, convergence, the wall time and whether the mesh conforms to `region`.
pub fn print_run(name: &str, k: usize, region: &Region, r: &MeshResult, secs: f64) {
    println!(
        "{name} K={k}: reached {} K~={} min angle {:.2} iterations {} converged {} {:.3} s conforming {:?}",
        r.mesh.num_vertices(),
        r.mesh.num_triangles(),
        r.mesh.min_angle_deg(),
        r.iterations,
        r.converged,
        secs,
        check_conforming(&r.mesh, region)
    );
}
