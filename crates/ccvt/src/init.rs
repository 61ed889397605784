//! Step 0 of Algorithms 1 and 2: the initial generators.
use geometry::{DVec2, Region, Rng};

/// How the initial K generators are chosen (Algorithm 1, step 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Init {
    /// Uniform random in Ω (rejection sampling in the bounding box).
    Random,
    /// An equilateral lattice of the hexagonal spacing centred on Ω's centroid and rotated by a
    /// seeded random angle, clipped to Ω, with
    /// surplus points dropped (or missing ones drawn at random) to reach exactly K.
    Lattice,
    /// Uniform random, then an ordinary (unconstrained) CVT of Ω (Algorithm 1, step 0, third
    /// option). Under the labels of Section 2.2.3 a generator once on Γ never leaves it, so a
    /// random start over-populates the boundary; an ordinary CVT keeps the first boundary layer
    /// one cell deep.
    Cvt,
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
        Init::Random | Init::Cvt => (0..k).map(|_| random_inside(&mut rng)).collect(),
        Init::Lattice => {
            // Centred on the region's centroid, rotated by a seeded angle: a disc then gets
            // the hexagonal numbers 1, 7, 19, ... in rings, as in Table 1.
            let h = (2.0 * region.area() / (3f64.sqrt() * k as f64)).sqrt();
            let centre = region.polygonize(1e-3 * h).centroid();
            let angle = rng.range(0.0, std::f64::consts::FRAC_PI_3);
            let (u, v) = (
                DVec2::from_angle(angle) * h,
                DVec2::from_angle(angle + std::f64::consts::FRAC_PI_3) * h,
            );
            let reach = ((hi - lo).length() / h).ceil() as i64 + 1;
            let mut pts = Vec::new();
            for i in -reach..=reach {
                for j in -reach..=reach {
                    let p = centre + u * i as f64 + v * j as f64;
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
