//! Step 0 of Algorithms 1 and 2: the initial generators.
use crate::sublevel::Sublevel;
use geometry::{DVec2, Region, Rng};
use rayon::prelude::*;

/// How the initial K generators are chosen (Algorithm 1, step 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Init {
    /// Uniform random in Ω (rejection sampling in the bounding box).
    Random,
    /// An equilateral lattice of the hexagonal spacing centred on Ω's centroid and rotated by a
    /// seeded random angle, clipped to Ω, with
    /// surplus points dropped (or missing ones drawn at random) to reach exactly K; every
    /// lattice point is moved by a seeded jitter of at most 1e-9 of the spacing (which makes
    /// its Delaunay triangulation unique and fast to compute).
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
            // Lattice points inside by more than 1e-3 h, row by row in parallel (the rows are
            // concatenated in order, so the result does not depend on the thread count).
            let inside = Sublevel::new(region, -1e-3 * h, 3.0 * h);
            let (blo, bhi) = (lo - DVec2::splat(h), hi + DVec2::splat(h));
            let rows: Vec<Vec<DVec2>> = (-reach..=reach)
                .into_par_iter()
                .map(|i| {
                    (-reach..=reach)
                        .map(|j| centre + u * i as f64 + v * j as f64)
                        .filter(|p| p.cmpge(blo).all() && p.cmple(bhi).all() && inside.contains(*p))
                        .collect()
                })
                .collect();
            let mut pts: Vec<DVec2> = rows.concat();
            while pts.len() > k {
                let i = rng.below(pts.len());
                pts.swap_remove(i);
            }
            // A seeded jitter of 1e-9 h breaks the lattice's exact cocircularities: the
            // Delaunay triangulation becomes unique and its predicates stay on their fast
            // floating-point path (the perfect lattice takes twice as long to triangulate).
            for p in pts.iter_mut() {
                *p += DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * (1e-9 * h);
            }
            while pts.len() < k {
                pts.push(random_inside(&mut rng));
            }
            pts
        }
    }
}
