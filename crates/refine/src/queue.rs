//! The queue of bad triangles: the worst (smallest sine of its smallest angle) first, and among
//! equals the one queued first.
//!
//! A refinement of 10⁵ vertices pops about 2.7 triangles per vertex, most of them already gone
//! from the triangulation, from a queue of 10⁵ or more: the pops' cache misses were a fifth of
//! the run with `std`'s binary heap. This heap has four children per node (half the levels)
//! and keeps the keys apart from the triangles, so a node's children are two cache lines of
//! keys. Every key is distinct (it ends in the queueing order), so any heap pops the same
//! sequence: the refinement does not depend on how the queue is built.

/// A key whose unsigned order is (sine, queueing order): the sine's bits mapped as
/// `f64::total_cmp` orders them, then the sequence number.
fn key(sin_min: f64, seq: u64) -> u128 {
    let bits = sin_min.to_bits();
    let ordered = if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    };
    (u128::from(ordered) << 64) | u128::from(seq)
}

/// A min-heap of bad triangles (any `T` that names one), four children per node.
pub(crate) struct BadQueue<T> {
    keys: Vec<u128>,
    faces: Vec<T>,
    seq: u64,
}

impl<T> Default for BadQueue<T> {
    fn default() -> Self {
        BadQueue {
            keys: Vec::new(),
            faces: Vec::new(),
            seq: 0,
        }
    }
}

impl<T: Copy> BadQueue<T> {
    /// Queue `face` with priority `sin_min` (smaller first; equal ones in queueing order).
    pub(crate) fn push(&mut self, sin_min: f64, face: T) {
        self.seq += 1;
        let k = key(sin_min, self.seq);
        let mut i = self.keys.len();
        self.keys.push(k);
        self.faces.push(face);
        while i > 0 {
            let parent = (i - 1) / 4;
            if self.keys[parent] <= k {
                break;
            }
            self.keys[i] = self.keys[parent];
            self.faces[i] = self.faces[parent];
            i = parent;
        }
        self.keys[i] = k;
        self.faces[i] = face;
    }

    /// The worst queued face with its priority, removed from the queue.
    pub(crate) fn pop(&mut self) -> Option<(f64, T)> {
        let top_key = *self.keys.first()?;
        let top = self.faces[0];
        let last_key = self.keys.pop()?;
        let last = self.faces.pop()?;
        let n = self.keys.len();
        if n > 0 {
            let mut i = 0;
            loop {
                let first = 4 * i + 1;
                if first >= n {
                    break;
                }
                let end = (first + 4).min(n);
                let mut c = first;
                for j in first + 1..end {
                    if self.keys[j] < self.keys[c] {
                        c = j;
                    }
                }
                if self.keys[c] >= last_key {
                    break;
                }
                self.keys[i] = self.keys[c];
                self.faces[i] = self.faces[c];
                i = c;
            }
            self.keys[i] = last_key;
            self.faces[i] = last;
        }
        Some((sine_of(top_key), top))
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }
}

/// The sine a key was made from (the inverse of [`key`]'s mapping).
fn sine_of(k: u128) -> f64 {
    let ordered = (k >> 64) as u64;
    let bits = if ordered >> 63 == 1 {
        ordered & !(1 << 63)
    } else {
        !ordered
    };
    f64::from_bits(bits)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BinaryHeap;

    #[test]
    fn pops_worst_first_then_in_queueing_order() {
        let mut q = BadQueue::default();
        for (i, s) in [0.5, 0.1, 0.5, 0.3].into_iter().enumerate() {
            q.push(s, i as u32);
        }
        let order: Vec<u32> = std::iter::from_fn(|| q.pop().map(|(_, f)| f)).collect();
        assert_eq!(order, [1, 3, 0, 2]);
    }

    #[test]
    fn keys_order_as_total_cmp_and_give_the_sine_back() {
        let sines = [-1.0, -0.0, 0.0, 1e-300, 0.2, 0.5, 0.8660254037844386, 1.0];
        for w in sines.windows(2) {
            assert!(key(w[0], 7) < key(w[1], 1), "{} {}", w[0], w[1]);
        }
        for s in sines {
            assert_eq!(sine_of(key(s, 3)).to_bits(), f64::to_bits(s));
        }
    }

    /// Interleaved pushes and pops against `std`'s binary heap on (sine, order) reversed.
    #[test]
    fn matches_a_binary_heap_on_random_interleavings() {
        let mut rng = geometry::Rng::new(11);
        let mut q = BadQueue::default();
        let mut h = BinaryHeap::new();
        let mut seq = 0u64;
        for step in 0..20_000u32 {
            if rng.uniform() < 0.55 {
                // Few distinct sines, so ties are common.
                let s = (rng.uniform() * 40.0).floor() / 40.0;
                seq += 1;
                q.push(s, step);
                h.push(std::cmp::Reverse((key(s, seq), step)));
            } else {
                let a = q.pop().map(|(s, f)| (s.to_bits(), f));
                let b = h
                    .pop()
                    .map(|std::cmp::Reverse((k, f))| (sine_of(k).to_bits(), f));
                assert_eq!(a, b, "step {step}");
            }
        }
        while let Some(std::cmp::Reverse((_, f))) = h.pop() {
            assert_eq!(q.pop().map(|(_, g)| g), Some(f));
        }
        assert!(q.is_empty());
    }
}
