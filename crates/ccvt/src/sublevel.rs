//! Fast exact test "signed distance to ∂Ω below a threshold" for many points: a grid of
//! squares known to lie deep in the sublevel set answers most points without a distance query.
use geometry::{DVec2, Region};
use rayon::prelude::*;

/// The set {p : signed_distance(p) < threshold} with a grid of squares wholly inside it.
pub struct Sublevel<'a> {
    region: &'a Region,
    threshold: f64,
    lo: DVec2,
    inv_s: f64,
    nx: usize,
    ny: usize,
    /// Square (i, j) at `j * nx + i` lies in the set: its centre's signed distance is below
    /// the threshold by more than the half-diagonal (signed distance is 1-Lipschitz).
    deep: Vec<bool>,
    /// For a square that is not deep but may hold points of the set (∂ of the set passes
    /// near it): the first of its `FINE`² sub-squares in `fine_deep`, else `NO_BLOCK`.
    block: Vec<u32>,
    /// Whether each sub-square lies in the set, as `deep` for the squares.
    fine_deep: Vec<bool>,
}

/// Sub-squares per side of a square along the set's boundary: a graded mesh packs several rows
/// of generators into a square there, and every one of them needed a distance query.
const FINE: usize = 8;
const NO_BLOCK: u32 = u32::MAX;

impl<'a> Sublevel<'a> {
    /// Index the set with squares of side about `cell` (a few generator spacings).
    pub fn new(region: &'a Region, threshold: f64, cell: f64) -> Sublevel<'a> {
        let (lo, hi) = region.bbox();
        let margin = threshold.max(0.0) + cell;
        let (lo, hi) = (lo - DVec2::splat(margin), hi + DVec2::splat(margin));
        let size = hi - lo;
        // At most 2^22 squares: beyond that the grid would cost more than it saves.
        let s = cell
            .max((size.x * size.y / f64::from(1u32 << 22)).sqrt())
            .max(size.max_element() * 1e-9);
        let nx = ((size.x / s).ceil() as usize).max(1);
        let ny = ((size.y / s).ceil() as usize).max(1);
        let half_diag = 0.5 * s * std::f64::consts::SQRT_2 * (1.0 + 1e-9);
        let centre = |q: usize| lo + DVec2::new((q % nx) as f64 + 0.5, (q / nx) as f64 + 0.5) * s;
        let distance: Vec<f64> = (0..nx * ny)
            .into_par_iter()
            .map(|q| region.signed_distance(centre(q)))
            .collect();
        let deep: Vec<bool> = distance
            .iter()
            .map(|&d| d < threshold - half_diag)
            .collect();
        let mut block = vec![NO_BLOCK; nx * ny];
        let mut along = Vec::new();
        for (q, &d) in distance.iter().enumerate() {
            if !deep[q]
                && d < threshold + half_diag
                && along.len() < (NO_BLOCK as usize) / (FINE * FINE)
            {
                block[q] = (along.len() * FINE * FINE) as u32;
                along.push(q);
            }
        }
        let fs = s / FINE as f64;
        let fine_half_diag = half_diag / FINE as f64;
        let fine_deep = along
            .par_iter()
            .flat_map_iter(|&q| {
                let corner = centre(q) - DVec2::splat(0.5 * s);
                (0..FINE * FINE).map(move |f| {
                    let c =
                        corner + DVec2::new((f % FINE) as f64 + 0.5, (f / FINE) as f64 + 0.5) * fs;
                    region.signed_distance(c) < threshold - fine_half_diag
                })
            })
            .collect();
        Sublevel {
            region,
            threshold,
            lo,
            inv_s: 1.0 / s,
            nx,
            ny,
            deep,
            block,
            fine_deep,
        }
    }

    /// signed_distance(p) < threshold (false for a non-finite p).
    pub fn contains(&self, p: DVec2) -> bool {
        if !p.is_finite() {
            return false;
        }
        let q = (p - self.lo) * self.inv_s;
        if q.x >= 0.0 && q.y >= 0.0 {
            let (i, j) = (q.x as usize, q.y as usize);
            if i < self.nx && j < self.ny {
                let sq = j * self.nx + i;
                if self.deep[sq] {
                    return true;
                }
                let b = self.block[sq];
                if b != NO_BLOCK {
                    let f = FINE as f64;
                    let (fi, fj) = (
                        (((q.x - i as f64) * f) as usize).min(FINE - 1),
                        (((q.y - j as f64) * f) as usize).min(FINE - 1),
                    );
                    if self.fine_deep[b as usize + fj * FINE + fi] {
                        return true;
                    }
                }
            }
        }
        self.region.signed_distance(p) < self.threshold
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::Rng;

    #[test]
    fn agrees_with_signed_distance() {
        for name in ["lake", "pie_hole", "annulus"] {
            let region = Region::builtin(name).unwrap();
            let d = region.diameter();
            for t in [0.0, 0.01 * d, -0.02 * d] {
                let set = Sublevel::new(&region, t, 0.013 * d);
                assert!(set.deep.iter().any(|&b| b), "{name}: no deep square");
                // Along the boundary the sub-squares answer too: some lie in the set, some not.
                assert!(
                    set.fine_deep.iter().any(|&b| b),
                    "{name}: no deep sub-square"
                );
                assert!(
                    set.fine_deep.iter().any(|&b| !b),
                    "{name}: every sub-square deep"
                );
                let (lo, hi) = region.bbox();
                let mut rng = Rng::new(4);
                for _ in 0..20_000 {
                    let p = DVec2::new(
                        rng.range(lo.x - 0.1 * d, hi.x + 0.1 * d),
                        rng.range(lo.y - 0.1 * d, hi.y + 0.1 * d),
                    );
                    assert_eq!(set.contains(p), region.signed_distance(p) < t, "{name} {p}");
                }
                assert!(!set.contains(DVec2::NAN));
            }
        }
    }
}
