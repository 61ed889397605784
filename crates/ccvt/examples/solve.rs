//! Run CCVT on a built-in region and print iterations, energy and timings:
//! `cargo run --release -p ccvt --example solve -- REGION K [ccvt1|ccvt2|fast] [seed]`.
use ccvt::Ccvt;
use geometry::Region;
use mesh::MeshRequest;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let region =
        Region::builtin(args.get(1).map(String::as_str).unwrap_or("circle")).expect("region");
    let k: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(88);
    let m = match args.get(3).map(String::as_str).unwrap_or("ccvt2") {
        "ccvt1" => Ccvt::algorithm1(),
        "fast" => Ccvt::fast(),
        "fast1" => Ccvt {
            algorithm: ccvt::Algorithm::One,
            ..Ccvt::fast()
        },
        _ => Ccvt::algorithm2(),
    };
    let seed = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1);
    let req = MeshRequest::points(k).seed(seed).max_iter(5000);
    let t = std::time::Instant::now();
    let g = m.generators(&region, &req, &mut |_| {}).expect("solve");
    let boundary = g.markers.iter().filter(|m| m.on_boundary()).count();
    println!(
        "{} K={k} iterations={} converged={} energy={:.8e} boundary={boundary} {:.3}s notes={:?}",
        region.name(),
        g.iterations,
        g.converged,
        g.energy_history.last().unwrap(),
        t.elapsed().as_secs_f64(),
        g.notes
    );
}
