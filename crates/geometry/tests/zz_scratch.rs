use geometry::*;
#[test]
fn scratch() {
    for &name in Region::builtin_names() {
        let r = Region::builtin(name).unwrap();
        let d = r.diameter();
        let mut fails = 0;
        let mut worst: f64 = 0.0;
        let mut rng = Rng::new(1);
        let t = std::time::Instant::now();
        for _ in 0..300 {
            let eps = d * 10f64.powf(rng.range(-5.0, 0.0));
            let tol = eps * 10f64.powf(rng.range(-3.0, 0.0)).max(1e-9);
            let p = r.expand(eps, tol);
            let mut bad = p.area() <= r.area();
            for ring in &p.rings { for v in &ring.points { let e = (r.signed_distance(*v) - eps).abs() / tol; worst = worst.max(e); if e > 1.0 { bad = true; } } }
            if bad { fails += 1; if fails < 4 { println!("  {name} FAIL eps {eps:e} tol {tol:e} rings {}", p.rings.len()); } }
        }
        println!("{name}: fails {fails} worst/tol {worst:.3} {:?}", t.elapsed());
    }
}
