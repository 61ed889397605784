//! Sparse symmetric matrices of 2×2 blocks, one block row per generator (the CVT energy's
//! Hessian and the operators built from it).
use geometry::DVec2;
use glam::{DMat2, Mat2};
use rayon::prelude::*;

/// Block-CSR matrix: row `i` holds the blocks `block[row_start[i]..row_start[i + 1]]` in the
/// columns `col[..]` of the same range. Every row starts with its diagonal block. Blocks are
/// stored in single precision (products are formed in double): the matrix only steers inexact
/// Newton steps, and at 10⁶ rows half the bytes (112 MB instead of 224) make every product
/// about twice as fast, memory bandwidth being its limit.
#[derive(Clone, Debug, Default)]
pub struct BlockMatrix {
    /// Start of each row in `col` / `block` (length rows + 1).
    pub row_start: Vec<usize>,
    /// Column (generator index) of each block.
    pub col: Vec<u32>,
    /// The blocks.
    pub block: Vec<Mat2>,
}

impl BlockMatrix {
    /// Number of block rows.
    pub fn rows(&self) -> usize {
        self.row_start.len().saturating_sub(1)
    }

    /// The diagonal block of row `i`.
    pub fn diagonal(&self, i: usize) -> DMat2 {
        self.block[self.row_start[i]].as_dmat2()
    }

    /// Calls `f(scratch, row, columns, blocks)` for every row, in parallel over chunks of rows
    /// (each chunk gets its own `init()` scratch). The row layout (`row_start`) must be set.
    pub fn par_rows_mut<S>(
        &mut self,
        init: impl Fn() -> S + Sync + Send,
        f: impl Fn(&mut S, usize, &mut [u32], &mut [Mat2]) + Sync + Send,
    ) {
        const ROWS: usize = 2048;
        let n = self.rows();
        let starts = &self.row_start;
        let mut chunks = Vec::with_capacity(n.div_ceil(ROWS));
        let (mut cols, mut blocks) = (&mut self.col[..], &mut self.block[..]);
        for first in (0..n).step_by(ROWS) {
            let last = (first + ROWS).min(n);
            let len = starts[last] - starts[first];
            let (c, cr) = std::mem::take(&mut cols).split_at_mut(len);
            let (b, br) = std::mem::take(&mut blocks).split_at_mut(len);
            chunks.push((first, last, c, b));
            cols = cr;
            blocks = br;
        }
        chunks.into_par_iter().for_each(|(first, last, c, b)| {
            let mut scratch = init();
            let base = starts[first];
            for row in first..last {
                let r = starts[row] - base..starts[row + 1] - base;
                f(&mut scratch, row, &mut c[r.clone()], &mut b[r]);
            }
        });
    }

    /// Row `i` of `A x` (its blocks summed in a fixed order).
    pub fn row_times(&self, i: usize, x: &[DVec2]) -> DVec2 {
        let r = self.row_start[i]..self.row_start[i + 1];
        self.col[r.clone()]
            .iter()
            .zip(&self.block[r])
            .fold(DVec2::ZERO, |s, (&j, b)| s + b.as_dmat2() * x[j as usize])
    }

    /// `out = A x` (parallel over rows).
    pub fn mul_vec(&self, x: &[DVec2], out: &mut [DVec2]) {
        out.par_iter_mut()
            .enumerate()
            .for_each(|(i, o)| *o = self.row_times(i, x));
    }
}

/// Length of the fixed chunks of [`dot`] (and of passes that fuse a dot product into other work:
/// summing per chunk, then the chunks in order, gives the same bits on any number of threads).
pub const DOT_CHUNK: usize = 4096;

/// Parallel dot product with a fixed chunking (the same bits on any number of threads).
pub fn dot(a: &[DVec2], b: &[DVec2]) -> f64 {
    const CHUNK: usize = DOT_CHUNK;
    let partial: Vec<f64> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| a.iter().zip(b).map(|(p, q)| p.dot(*q)).sum())
        .collect();
    partial.iter().sum()
}
