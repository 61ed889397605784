//! Measure the refinement on one region: `cargo run --release -p cvtmesh-tools --bin refine_probe -- NAME K [ANGLE]`.
use cvtmesh_tools::print_run;
use geometry::Region;
use mesh::{MeshRequest, Mesher};
use refine::Refine;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("circle", |s| s.as_str());
    let k: usize = args.get(2).map_or(88, |s| s.parse().unwrap());
    let angle: f64 = args.get(3).map_or(20.0, |s| s.parse().unwrap());
    let region = Region::builtin(name).unwrap();
    let m = Refine {
        min_angle_deg: angle,
        ..Refine::default()
    };
    let t = Instant::now();
    let mut last = Instant::now();
    let r = m
        .mesh(&region, &MeshRequest::points(k), &mut |p| {
            eprintln!(
                "step {} |dK|/K {:.4} ({:.3} s)",
                p.iteration,
                p.max_move,
                last.elapsed().as_secs_f64()
            );
            last = Instant::now();
        })
        .unwrap();
    let secs = t.elapsed().as_secs_f64();
    print_run(name, k, &region, &r, secs);
    let (mut bsum, mut bn, mut isum, mut inn) = (0.0, 0, 0.0, 0);
    let mut edges = std::collections::HashMap::new();
    for t in &r.mesh.triangles {
        for i in 0..3 {
            let (a, b) = (t[i].min(t[(i + 1) % 3]), t[i].max(t[(i + 1) % 3]));
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    for ((a, b), c) in edges {
        let l = (r.mesh.points[a as usize] - r.mesh.points[b as usize]).length();
        if c == 1 {
            bsum += l;
            bn += 1;
        } else {
            isum += l;
            inn += 1;
        }
    }
    println!(
        "  mean boundary edge {:.4}, mean interior edge {:.4}, ratio {:.3}",
        bsum / bn as f64,
        isum / inn as f64,
        (bsum / bn as f64) / (isum / inn as f64)
    );
    for n in &r.notes {
        println!("  {n}");
    }
}
