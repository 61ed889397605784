//! Every generator's move under the map (its target minus itself, relative to the local
//! spacing), kept with the largest of each block of generators: an active-set step changes the
//! moves of a few hundred generators, and the convergence test and the next active set then read
//! the blocks, and only the blocks that can hold a move above their bound, instead of all K.
//! Generators listed along a Hilbert curve (`start::along_hilbert`) put the changed ones in a
//! few blocks.
use crate::map::Step;
use crate::scale::LocalScale;
use geometry::DVec2;
use rayon::prelude::*;

/// Generators per block.
const BLOCK: usize = 256;

/// The squared relative moves and their block maxima.
pub(crate) struct Moves {
    /// Per generator, as `map::max_move` measures it: |t_k − z_k|² (ρ ≡ 1) or that over h_k²,
    /// infinite where |t_k − z_k|² is not a number.
    rel: Vec<f64>,
    /// The largest `rel` of each block (NaN ignored, as `f64::max` does).
    block: Vec<f64>,
}

impl Moves {
    /// None yet: the first [`Moves::sync`] finds them all.
    pub(crate) fn empty() -> Moves {
        Moves {
            rel: Vec::new(),
            block: Vec::new(),
        }
    }

    /// The moves of the iterate `z` under its map `s`, in this memory. O(K), in parallel.
    fn rebuild(&mut self, z: &[DVec2], s: &Step, scale: &LocalScale) {
        self.rel.resize(z.len(), 0.0);
        self.rel
            .par_iter_mut()
            .enumerate()
            .for_each(|(k, r)| *r = relative(z, s, scale, k));
        self.block.clear();
        self.block
            .par_extend(self.rel.par_chunks(BLOCK).map(block_max));
    }

    /// Brought up to `s`: every move again after a whole evaluation (`s.touched` is None),
    /// else those of the generators it lists, and their blocks. Leaves `s.touched` empty.
    pub(crate) fn sync(&mut self, z: &[DVec2], s: &mut Step, scale: &LocalScale) {
        let Some(mut touched) = s.touched.take() else {
            self.rebuild(z, s, scale);
            s.touched = Some(Vec::new());
            return;
        };
        for &k in &touched {
            self.rel[k] = relative(z, s, scale, k);
        }
        touched.iter_mut().for_each(|k| *k /= BLOCK);
        touched.sort_unstable();
        touched.dedup();
        for &b in &touched {
            let end = ((b + 1) * BLOCK).min(self.rel.len());
            self.block[b] = block_max(&self.rel[b * BLOCK..end]);
        }
        touched.clear();
        s.touched = Some(touched);
    }

    /// The largest move relative to the local spacing: `map::max_move`'s value, bit for bit.
    pub(crate) fn largest(&self, scale: &LocalScale) -> f64 {
        let m = self.block.iter().copied().fold(0.0, f64::max);
        if scale.is_uniform() {
            m.sqrt() / scale.mean()
        } else {
            m.sqrt()
        }
    }

    /// The generators, in order, of the blocks that may hold one whose squared move relative
    /// to its local spacing (`|t_k − z_k|² / h_k²`, h_k the mean spacing where ρ ≡ 1) exceeds
    /// `bound`; every other generator's is at most `bound` or not a number.
    pub(crate) fn candidates(
        &self,
        scale: &LocalScale,
        bound: f64,
    ) -> impl Iterator<Item = usize> + '_ {
        // Where ρ ≡ 1 a move is stored unscaled: dividing is monotone, so a block whose largest
        // scaled move is at most the bound holds no larger one.
        let h2 = if scale.is_uniform() {
            scale.mean().powi(2)
        } else {
            1.0
        };
        let n = self.rel.len();
        self.block
            .iter()
            .enumerate()
            .filter(move |&(_, &m)| m / h2 > bound)
            .flat_map(move |(b, _)| b * BLOCK..((b + 1) * BLOCK).min(n))
    }
}

/// Generator `k`'s entry of `Moves::rel`.
#[inline]
fn relative(z: &[DVec2], s: &Step, scale: &LocalScale, k: usize) -> f64 {
    let d = (s.targets[k] - z[k]).length_squared();
    if d.is_nan() {
        f64::INFINITY
    } else if scale.is_uniform() {
        d
    } else {
        d / s.h[k].powi(2)
    }
}

fn block_max(rel: &[f64]) -> f64 {
    rel.iter().copied().fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{max_move, Role};
    use geometry::{Density, Region, Rng};

    /// A map of `n` generators with random moves, some far larger than the rest, and the local
    /// spacing of `scale` at each.
    fn map(n: usize, scale: &LocalScale, seed: u64) -> (Vec<DVec2>, Step) {
        let mut rng = Rng::new(seed);
        let z: Vec<DVec2> = (0..n)
            .map(|_| DVec2::new(rng.range(-0.7, 0.7), rng.range(-0.7, 0.7)))
            .collect();
        let targets = z
            .iter()
            .enumerate()
            .map(|(k, &p)| {
                let r = if k % 97 == 5 { 1e-2 } else { 1e-5 };
                p + DVec2::new(rng.range(-r, r), rng.range(-r, r))
            })
            .collect();
        let h = if scale.is_uniform() {
            Vec::new()
        } else {
            z.iter().map(|&p| scale.at(p)).collect()
        };
        let s = Step {
            energy: 0.0,
            roles: vec![Role::Interior; n],
            targets,
            h,
            fixed: Vec::new(),
            touched: None,
        };
        (z, s)
    }

    #[test]
    fn moves_kept_by_blocks_are_the_moves_of_every_generator() {
        let region = Region::builtin("circle").unwrap();
        let graded = Density::Function(std::sync::Arc::new(|p: DVec2| 1.0 + 4.0 * p.x * p.x));
        for density in [Density::Uniform, graded] {
            let scale = LocalScale::new(&region, &density, 0.01);
            let (z, mut s) = map(3000, &scale, 7);
            let mut moves = Moves::empty();
            moves.sync(&z, &mut s, &scale);
            let every = max_move(&s.targets, &z, &s.h, &scale);
            assert_eq!(moves.largest(&scale).to_bits(), every.to_bits());
            // A few generators moved elsewhere (a local step): synced, the same as made afresh.
            let mut rng = Rng::new(3);
            let touched: Vec<usize> = (0..40).map(|_| rng.below(3000)).collect();
            for &k in &touched {
                s.targets[k] = z[k] + DVec2::new(rng.range(-1e-3, 1e-3), 0.0);
            }
            s.targets[1234] = z[1234] + DVec2::new(0.3, 0.0);
            s.touched = Some(touched.iter().copied().chain([1234]).collect());
            moves.sync(&z, &mut s, &scale);
            let mut fresh = Moves::empty();
            fresh.rebuild(&z, &s, &scale);
            assert_eq!(moves.rel.len(), fresh.rel.len());
            assert!(moves
                .rel
                .iter()
                .zip(&fresh.rel)
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            assert!(moves
                .block
                .iter()
                .zip(&fresh.block)
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            let every = max_move(&s.targets, &z, &s.h, &scale);
            assert_eq!(moves.largest(&scale).to_bits(), every.to_bits());
            // Every generator above a bound is a candidate, in order.
            let h2 = |k: usize| s.h(k, &scale).powi(2);
            for bound in [0.0, 1e-8, 1e-4, 1e-2, 1.0] {
                let candidates: Vec<usize> = moves.candidates(&scale, bound).collect();
                assert!(candidates.windows(2).all(|w| w[0] < w[1]));
                for (k, p) in z.iter().enumerate() {
                    if (s.targets[k] - *p).length_squared() / h2(k) > bound {
                        assert!(candidates.binary_search(&k).is_ok(), "{k} above {bound}");
                    }
                }
            }
            // A target that is not a number makes the largest move infinite, as it does for
            // every generator's test.
            s.targets[1000] = DVec2::splat(f64::NAN);
            s.touched = Some(vec![1000]);
            moves.sync(&z, &mut s, &scale);
            assert_eq!(moves.largest(&scale), f64::INFINITY);
            assert_eq!(max_move(&s.targets, &z, &s.h, &scale), f64::INFINITY);
        }
    }
}
