//! Step 0 of Algorithms 1 and 2: the initial generators.
use geometry::{DVec2, Region, Rng};

/// How the initial K generators are chosen (Algorithm 1, step 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Init {
    /// Uniform random in Ω (rejection sampling in the bounding box).
    Random,
    /// An equilateral lattice of the hexagonal spacing, randomly shifted, clipped to Ω, with
    /// surplus points dropped (or missing ones drawn at random) to reach exactly K.
    Lattice,
}

/// K initial generators strictly inside `region`, reproducible from `seed`.
pub fn initial_points(region: &Region, k: usize, init: Init, seed: u64) -> Vec<DVec2> {
    let mut rng = Rng::new(seed);
    let (lo, hi) = region.bbox();
    let random_inside = |rng: &mut Rng| loop {
        let p = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        if region.signed_distance(p) < 0.0 {
            return p;
        }
    };
    match init {
        Init::Random => (0..k).map(|_| random_inside(&mut rng)).collect(),
        Init::Lattice => {
            let h = (2.0 * region.area() / (3f64.sqrt() * k as f64)).sqrt();
            let shift = DVec2::new(rng.range(0.0, h), rng.range(0.0, h));
            let dy = h * 3f64.sqrt() / 2.0;
            let mut pts = Vec::new();
            let rows = ((hi.y - lo.y) / dy).ceil() as i64 + 1;
            let cols = ((hi.x - lo.x) / h).ceil() as i64 + 2;
            for r in 0..rows {
                for c in -1..cols {
                    let x = lo.x + shift.x + c as f64 * h + if r % 2 == 1 { h / 2.0 } else { 0.0 };
                    let p = DVec2::new(x, lo.y + shift.y * 0.5 + r as f64 * dy);
                    if region.signed_distance(p) < -1e-3 * h {
                        pts.push(p);
                    }
                }
            }
            while pts.len() > k {
                let i = rng.below(pts.len());
                pts.swap_remove(i);
            }
            while pts.len() < k {
                pts.push(random_inside(&mut rng));
            }
            pts
        }
    }
}
