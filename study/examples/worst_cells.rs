//! Where the worst-case measures come from: for each method on some paper tables (seed 1),
//! whether the generator with the largest |D_k| (d), the smallest h_k (μ), the smallest cell
//! (ν) and the vertices of the triangle with the largest q_j and the smallest angle (β) lie on
//! the boundary, and each method's d next to the others'.
//!
//! `cargo run --release -p study --example worst_cells [-- circle:88,square_hole:194]`
use cvtmesh::geometry::Density;
use cvtmesh::tessellation::{clipped_cells, Delaunay};
use cvtmesh::VertexMarker;
use cvtmesh::{MeshRequest, Region};
use study::MethodId;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cases = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "circle:88,square_hole:194,superellipse:505,lake:1109".into());
    println!("B = on the boundary (or a corner), I = interior; d is max |D_k|.");
    for case in cases.split(',') {
        let (name, k) = case.split_once(':').ok_or("cases are region:K")?;
        let region = Region::builtin(name)?;
        let k: usize = k.parse()?;
        println!("{name} K={k}");
        for method in MethodId::ALL {
            let res = method
                .method()
                .run(&region, &MeshRequest::points(k).seed(1))?;
            let mesh = &res.mesh;
            let poly = region.polygonize(cvtmesh::metrics::polygon_tolerance(
                &region,
                mesh.points.len(),
            ));
            let cells = clipped_cells(
                &mesh.points,
                &Delaunay::new(&mesh.points),
                &poly,
                &Density::Uniform,
            );
            let on_boundary = |i: usize| !matches!(mesh.markers[i], VertexMarker::Interior);
            let tag = |i: usize| if on_boundary(i) { "B" } else { "I" };
            let arg = |f: &dyn Fn(usize) -> f64, max: bool| {
                (0..mesh.points.len())
                    .max_by(|&a, &b| {
                        let (x, y) = (f(a), f(b));
                        if max {
                            x.total_cmp(&y)
                        } else {
                            y.total_cmp(&x)
                        }
                    })
                    .unwrap_or(0)
            };
            let dk = |i: usize| {
                let [a, b, c] = cells.cells[i].second_moment;
                (0.5 * (a - c)).powi(2) + b * b
            };
            let i_d = arg(&dk, true);
            let d_int = (0..mesh.points.len())
                .filter(|&i| !on_boundary(i))
                .map(dk)
                .fold(0.0, f64::max);
            let i_mu = arg(&|i| cells.cells[i].h, false);
            let i_nu = arg(&|i| cells.cells[i].area, false);
            let tri = |t: &[u32; 3]| t.iter().map(|&v| tag(v as usize)).collect::<String>();
            let q_of = |t: &[u32; 3]| {
                let p = |j: usize| mesh.points[t[j] as usize];
                let (a, b, c) = (
                    (p(1) - p(2)).length(),
                    (p(2) - p(0)).length(),
                    (p(0) - p(1)).length(),
                );
                a * b * c / ((b + c - a) * (c + a - b) * (a + b - c))
            };
            let worst_q = mesh
                .triangles
                .iter()
                .max_by(|x, y| q_of(x).total_cmp(&q_of(y)))
                .ok_or("no triangles")?;
            let boundary = (0..mesh.points.len()).filter(|&i| on_boundary(i)).count();
            println!(
                "  {:9} d {:.2e} at {} (interior max {:.2e}) | min h_k at {} | min |V_k| at {} | worst q triangle {} | boundary vertices {}/{}",
                method.column(),
                dk(i_d),
                tag(i_d),
                d_int,
                tag(i_mu),
                tag(i_nu),
                tri(worst_q),
                boundary,
                mesh.points.len()
            );
        }
    }
    Ok(())
}
