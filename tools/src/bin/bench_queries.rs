//! Cost per query of `signed_distance` and `project` on the paper regions (and a large
//! synthetic coastline), in CPU time per call. Run with
//! `cargo run --release -p cvtmesh-tools --bin bench_queries`.
use geometry::{DVec2, LoopRole, Piece, Region, Rng};
use std::time::Instant;

/// CPU time of this thread in seconds (Linux; falls back to wall time elsewhere), so that the
/// numbers mean something on a loaded machine.
fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| {
            s.split_whitespace()
                .next()
                .and_then(|x| x.parse::<f64>().ok())
        })
        .map_or_else(|| START.with(|t| t.elapsed().as_secs_f64()), |ns| ns * 1e-9)
}

thread_local!(static START: Instant = Instant::now());

struct Clock(f64);
impl Clock {
    fn start() -> Clock {
        Clock(cpu_seconds())
    }
    fn secs(&self) -> f64 {
        cpu_seconds() - self.0
    }
}

fn bench(r: &Region, n: usize) {
    let (lo, hi) = r.bbox();
    let d = r.diameter();
    let mut rng = Rng::new(7);
    // Points in and around the region (a CCVT/DistMesh-like mix: most near or inside).
    let pts: Vec<DVec2> = (0..n)
        .map(|_| {
            DVec2::new(
                rng.range(lo.x - 0.05 * d, hi.x + 0.05 * d),
                rng.range(lo.y - 0.05 * d, hi.y + 0.05 * d),
            )
        })
        .collect();
    let t = Clock::start();
    let mut s = 0.0;
    for p in &pts {
        s += r.signed_distance(*p);
    }
    let sd = t.secs() / n as f64;
    let t = Clock::start();
    for p in &pts {
        s += r.project(*p).loop_param;
    }
    let pr = t.secs() / n as f64;
    let t = Clock::start();
    let mut inside = 0usize;
    for p in &pts {
        inside += usize::from(r.contains(*p));
    }
    let ct = t.secs() / n as f64;
    println!(
        "{:<16} pieces {:>6}  signed_distance {:>7.3} µs  project {:>7.3} µs  contains {:>7.3} µs  (checksum {:.3e}, {inside} inside)",
        r.name(),
        r.pieces().len(),
        sd * 1e6,
        pr * 1e6,
        ct * 1e6,
        s
    );
}

fn main() {
    // Calibration: a loop of one square root and one atan2 per point.
    let mut rng = Rng::new(1);
    let pts: Vec<DVec2> = (0..200_000)
        .map(|_| DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)))
        .collect();
    let t = Clock::start();
    let s: f64 = pts.iter().map(|p| p.length() + p.y.atan2(p.x)).sum();
    println!(
        "calibration: sqrt + atan2 {:.3} µs (checksum {s:.3})",
        t.secs() / 2e5 * 1e6
    );
    for &name in Region::builtin_names() {
        bench(&Region::builtin(name).unwrap(), 200_000);
    }
    // A wiggly 10⁴-edge coastline.
    let n = 10_000;
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let t = i as f64 / n as f64 * std::f64::consts::TAU;
            let r = 100.0 * (1.0 + 0.2 * (7.0 * t).sin() + 0.05 * (53.0 * t).cos());
            DVec2::new(r * t.cos(), r * t.sin())
        })
        .collect();
    let pieces = (0..n)
        .map(|i| Piece::Line {
            a: pts[i],
            b: pts[(i + 1) % n],
        })
        .collect();
    let t = Clock::start();
    let coast = Region::new("coast10k", vec![(LoopRole::Outer, pieces)], None).unwrap();
    println!("coast10k: Region::new {:.1} ms", t.secs() * 1e3);
    bench(&coast, 200_000);
    let t = Clock::start();
    let merged = coast.with_corner_angle(10.0);
    println!(
        "coast10k: with_corner_angle(10°) {:.1} ms -> {} pieces",
        t.secs() * 1e3,
        merged.pieces().len()
    );
    bench(&merged, 200_000);
    // Expansions are short: wall time over repeated runs.
    bench_expand(&coast, 2.0, 0.05);
    bench_expand(&Region::builtin("lake").unwrap(), 5.0, 0.05);
}

/// Mean wall time of `region.expand(eps, tol)` over 20 runs.
fn bench_expand(region: &Region, eps: f64, tol: f64) {
    let reps = 20;
    let t = Instant::now();
    let mut e = region.expand(eps, tol);
    for _ in 1..reps {
        e = region.expand(eps, tol);
    }
    println!(
        "{}: expand({eps}, {tol}) {:.2} ms wall -> {} vertices",
        region.name(),
        t.elapsed().as_secs_f64() * 1e3 / reps as f64,
        e.rings.iter().map(|r| r.points.len()).sum::<usize>()
    );
}
