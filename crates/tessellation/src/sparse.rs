//! Sparse symmetric matrices of 2×2 blocks, one block row per generator (the CVT energy's
//! Hessian and the operators built from it).
use geometry::DVec2;
use glam::{DMat2, Mat2};
use rayon::prelude::*;

/// Block-CSR matrix: row `i` is the diagonal block `diag[i]` and the blocks
/// `block[row_start[i]..row_start[i + 1]]` in the columns `col[..]` of the same range. The
/// diagonal apart, in an array of its own and in double precision: block Jacobi reads it in
/// order at every CG iteration, where a diagonal within the rows was a cache miss of its own.
/// The other blocks are single precision (products are summed in double): half the memory and
/// the memory traffic of the matrix-vector products that dominate a CG iteration; Newton's
/// directions need no more precision.
#[derive(Clone, Debug, Default)]
pub struct BlockMatrix {
    /// Start of each row in `col` / `block` (length rows + 1).
    pub row_start: Vec<usize>,
    /// Column (generator index) of each off-diagonal block.
    pub col: Vec<u32>,
    /// The off-diagonal blocks, in single precision: the CG's matrix-vector products read
    /// them at every iteration, and memory bandwidth is their cost.
    pub block: Vec<Mat2>,
    /// The diagonal blocks.
    pub diag: Vec<DMat2>,
}

impl BlockMatrix {
    /// Number of block rows.
    pub fn rows(&self) -> usize {
        self.diag.len()
    }

    /// The diagonal block of row `i`.
    pub fn diagonal(&self, i: usize) -> DMat2 {
        self.diag[i]
    }

    /// Block (i, j) (zero where there is none).
    pub fn get(&self, i: usize, j: usize) -> DMat2 {
        let r = self.row_start[i]..self.row_start[i + 1];
        let off = self.col[r.clone()]
            .iter()
            .zip(&self.block[r])
            .filter(|(&c, _)| c as usize == j)
            .fold(DMat2::ZERO, |s, (_, b)| s + b.as_dmat2());
        if i == j {
            off + self.diag[i]
        } else {
            off
        }
    }

    /// Calls `f(scratch, row, diagonal, columns, blocks)` for every row, in parallel over chunks
    /// of rows (each chunk gets its own `init()` scratch). The row layout (`row_start`) and the
    /// number of rows (`diag`) must be set.
    pub fn par_rows_mut<S>(
        &mut self,
        init: impl Fn() -> S + Sync + Send,
        f: impl Fn(&mut S, usize, &mut DMat2, &mut [u32], &mut [Mat2]) + Sync + Send,
    ) {
        par_rows(
            &self.row_start,
            &mut self.diag,
            &mut self.col,
            &mut self.block,
            2048,
            init,
            f,
        );
    }

    /// Row `i` of `A x` (the diagonal, then the other blocks, summed in a fixed order).
    #[inline]
    pub fn row_times(&self, i: usize, x: &[DVec2]) -> DVec2 {
        let r = self.row_start[i]..self.row_start[i + 1];
        self.col[r.clone()]
            .iter()
            .zip(&self.block[r])
            .fold(self.diag[i] * x[i], |s, (&j, b)| {
                s + b.as_dmat2() * x[j as usize]
            })
    }

    /// `out = A x` (parallel over rows).
    pub fn mul_vec(&self, x: &[DVec2], out: &mut [DVec2]) {
        out.par_iter_mut()
            .enumerate()
            .for_each(|(i, o)| *o = self.row_times(i, x));
    }
}

/// Calls `f(scratch, row, per_row[row], a_row, b_row)` for every row of two arrays laid out by
/// `starts` (row r is `starts[r]..starts[r + 1]` of both), in parallel over chunks of `rows`
/// rows, each chunk with its own `init()` scratch.
pub(crate) fn par_rows<R: Send, A: Send, B: Send, S>(
    starts: &[usize],
    per_row: &mut [R],
    a: &mut [A],
    b: &mut [B],
    rows: usize,
    init: impl Fn() -> S + Sync + Send,
    f: impl Fn(&mut S, usize, &mut R, &mut [A], &mut [B]) + Sync + Send,
) {
    let n = starts.len().saturating_sub(1);
    assert_eq!(per_row.len(), n, "one per-row value for every row");
    let mut chunks = Vec::with_capacity(n.div_ceil(rows));
    let (mut p, mut a, mut b) = (per_row, a, b);
    for first in (0..n).step_by(rows) {
        let last = (first + rows).min(n);
        let len = starts[last] - starts[first];
        let (pc, pr) = std::mem::take(&mut p).split_at_mut(last - first);
        let (ac, ar) = std::mem::take(&mut a).split_at_mut(len);
        let (bc, br) = std::mem::take(&mut b).split_at_mut(len);
        chunks.push((first, pc, ac, bc));
        p = pr;
        a = ar;
        b = br;
    }
    chunks.into_par_iter().for_each(|(first, p, a, b)| {
        let mut scratch = init();
        let base = starts[first];
        for (k, pk) in p.iter_mut().enumerate() {
            let row = first + k;
            let r = starts[row] - base..starts[row + 1] - base;
            f(&mut scratch, row, pk, &mut a[r.clone()], &mut b[r]);
        }
    });
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
