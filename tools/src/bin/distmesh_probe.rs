//! Measure DistMesh on one region: `cargo run --release -p cvtmesh-tools --bin distmesh_probe -- NAME K [MAX_ITER]`.
use cvtmesh_tools::print_run;
use distmesh::DistMesh;
use geometry::Region;
use mesh::{triangle_min_angle_deg, MeshRequest, Mesher};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("circle", |s| s.as_str());
    let k: usize = args.get(2).map_or(88, |s| s.parse().unwrap());
    let max_iter: usize = args.get(3).map_or(1000, |s| s.parse().unwrap());
    let region = Region::builtin(name).unwrap();
    let t = Instant::now();
    let r = DistMesh::default()
        .mesh(
            &region,
            &MeshRequest::points(k).max_iter(max_iter),
            &mut |_| {},
        )
        .unwrap();
    let secs = t.elapsed().as_secs_f64();
    print_run(name, k, &region, &r, secs);
    for t in 0..r.mesh.num_triangles() {
        let p = r.mesh.triangle(t);
        let m = triangle_min_angle_deg(p);
        if m < 15.0 {
            let tri = r.mesh.triangles[t];
            println!(
                "  tri {tri:?} min {m:.3} {:?} {:?}",
                p,
                tri.map(|v| r.mesh.markers[v as usize])
            );
        }
    }
    for n in &r.notes {
        println!("  {n}");
    }
}
