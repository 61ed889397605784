//! An adaptive loop: sizes computed at the vertices of one mesh make the next one.
//!
//! ```text
//! cargo run --release -p cvtmesh --example adaptive_remesh -- [OUT.vtu]
//! ```
//!
//! The function is the wave front of Mitchell's collection of adaptive test problems
//! (NISTIR 7668): u = atan(α (r − r₀)) on the unit circle, a ring of steep change at r₀ = 0.5.
//! Each step takes the size that equidistributes the interpolation error, h ∝ |∇²u|^(−½), at
//! the vertices of the current mesh (what an error estimator gives a solver) and meshes again
//! from those sizes with the same number of vertices. The example prints the largest
//! interpolation error of the uniform mesh and of each adapted one, and writes the last mesh
//! (default `adaptive.vtu`).
use cvtmesh::{DVec2, Mesh, MeshRequest, Method, Region, SizeField};
use std::path::Path;

/// Steepness of the front.
pub const ALPHA: f64 = 40.0;
/// Radius of the front.
pub const R0: f64 = 0.5;
/// Vertices of every mesh of the loop.
pub const VERTICES: usize = 3000;

/// The wave front u(x).
pub fn u(p: DVec2) -> f64 {
    (ALPHA * (p.length() - R0)).atan()
}

/// The larger of |∇²u|'s eigenvalues at `p`: |u_rr| across the front, |u_r / r| along it.
fn curvature(p: DVec2) -> f64 {
    let r = p.length().max(1e-9);
    let s = ALPHA * (r - R0);
    let u_r = ALPHA / (1.0 + s * s);
    let u_rr = -2.0 * ALPHA * ALPHA * s / (1.0 + s * s).powi(2);
    u_rr.abs().max(u_r / r)
}

/// The size at each vertex that equidistributes the interpolation error, h ∝ |∇²u|^(−½),
/// kept between 1/50 and 1 of the largest (the front's curvature would otherwise ask for
/// sizes far below any mesh of a few thousand vertices). The scale does not matter: the
/// next mesh has [`VERTICES`] vertices whatever it is.
pub fn sizes(mesh: &Mesh) -> Vec<f64> {
    let h: Vec<f64> = mesh
        .points
        .iter()
        .map(|&p| 1.0 / curvature(p).max(1e-12).sqrt())
        .collect();
    let largest = h.iter().copied().fold(0.0, f64::max);
    h.iter()
        .map(|&v| v.clamp(largest / 50.0, largest))
        .collect()
}

/// The largest interpolation error of the linear interpolant of u over the mesh, sampled at
/// every triangle's centroid and edge midpoints.
pub fn interpolation_error(mesh: &Mesh) -> f64 {
    let mut worst = 0.0f64;
    for t in &mesh.triangles {
        let p = t.map(|v| mesh.points[v as usize]);
        let f = p.map(u);
        let mut check = |w: [f64; 3]| {
            let x = p[0] * w[0] + p[1] * w[1] + p[2] * w[2];
            let interpolated = f[0] * w[0] + f[1] * w[1] + f[2] * w[2];
            worst = worst.max((u(x) - interpolated).abs());
        };
        check([1.0 / 3.0; 3]);
        check([0.5, 0.5, 0.0]);
        check([0.0, 0.5, 0.5]);
        check([0.5, 0.0, 0.5]);
    }
    worst
}

/// The uniform mesh and `steps` adapted ones, each from the sizes at the vertices of the one
/// before; the last is written to `out`.
pub fn run(steps: usize, out: &Path) -> Result<Vec<Mesh>, Box<dyn std::error::Error>> {
    let region = Region::builtin("circle")?;
    let mut meshes = vec![
        Method::Ccvt
            .run(&region, &MeshRequest::points(VERTICES))?
            .mesh,
    ];
    for _ in 0..steps {
        let last = meshes.last().expect("the uniform mesh");
        let field = SizeField::from_mesh(&region, &last.points, &last.triangles, &sizes(last))?
            .bounded(&region, None, None, Some(0.3))?;
        let request = MeshRequest::size_field(&field, &region, Some(VERTICES))?;
        meshes.push(Method::Ccvt.run(&region, &request)?.mesh);
    }
    cvtmesh::io::write_mesh(meshes.last().expect("a mesh"), out)?;
    Ok(meshes)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "adaptive.vtu".into());
    let meshes = run(2, Path::new(&out))?;
    for (i, m) in meshes.iter().enumerate() {
        println!(
            "{}: {} vertices, largest interpolation error {:.4}",
            if i == 0 {
                "uniform".to_string()
            } else {
                format!("adapted {i}")
            },
            m.num_vertices(),
            interpolation_error(m)
        );
    }
    println!("written to {out}");
    Ok(())
}
