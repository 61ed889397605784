//! Geometric multigrid V-cycle preconditioner for the Newton systems `A x = b` of the CVT
//! energy (2×2 block SPD matrices, one block row per generator).
//!
//! Level 1 is a Cartesian grid of spacing `H₁ = COARSE_FACTOR · h` over the points, keeping
//! only nodes whose bilinear basis function is nonzero at some point; the prolongation
//! interpolates each displacement component bilinearly from the 4 nodes around a point.
//! Every further level doubles the grid spacing (nested grids, so the composite interpolation
//! is again bilinear) until at most [`COARSEST`] nodes remain, which are solved by a dense
//! Cholesky factorisation. Coarse matrices are Galerkin products `Pᵀ A P`, assembled per coarse
//! row (gather, no scattered float accumulation) into block CSR with only nonzero blocks.
//!
//! The smoother is Chebyshev iteration on the block-Jacobi-scaled matrix `D⁻¹A` (a polynomial
//! in it, hence symmetric), the same before and after the coarse correction, started from zero:
//! the V-cycle is a symmetric positive definite linear operator whenever the polynomial keeps
//! `|1 − λ p(λ)| < 1` on the spectrum, which the Lanczos estimate of `λ_max` with a safety
//! margin guarantees in practice. Everything is deterministic: per-row gathers and fixed
//! chunking, no result depends on the thread count.
#![allow(dead_code)] // wired in by the Newton solver

use geometry::DVec2;
use glam::DMat2;
use rayon::prelude::*;
use std::sync::Mutex;
use tessellation::BlockMatrix;

/// Marks "no coarse node" (a zero interpolation weight).
const NONE: u32 = u32::MAX;
/// The coarsest level is solved directly once it has at most this many nodes.
const COARSEST: usize = 300;
/// Level-1 grid spacing in units of the mean point spacing. Measured at 10⁶ points (CG
/// iterations to 1e-8 × cost of one V-cycle in fine `mul_vec`s, hierarchy memory): 2 h gives
/// 10–15 × 10 and 390 MB; 3 h 12–14 iterations but 170 MB; 4 h 15 × 9 and 115 MB.
const COARSE_FACTOR: f64 = 4.0;
/// Interpolation weights below this are dropped (they only make nearly empty coarse rows).
const MIN_WEIGHT: f64 = 1e-7;
/// Rows per parallel task in the assembly passes.
const CHUNK: usize = 512;
/// Minimum rows per rayon task in vector passes.
const MIN_LEN: usize = 1024;
/// Lanczos steps for the largest eigenvalue of `D⁻¹A` on the fine level (each costs a fine
/// `mul_vec`; 6 steps come within ~5% of the top at 10⁶ rows) and on the cheap coarse levels.
const LANCZOS_FINE: usize = 6;
const LANCZOS_COARSE: usize = 12;
/// Chebyshev smoothing degree on the finest level and on the coarse levels (each degree costs
/// two fused `mul_vec` passes per V-cycle; at 10⁶ points degree 1 needs 24 CG iterations,
/// 2 needs 15, 3 needs 12–15).
const DEGREE_FINE: usize = 2;
const DEGREE_COARSE: usize = 2;
/// The Chebyshev smoother targets `[λ_max / RATIO, λ_max]`.
const RATIO: f64 = 4.0;
/// `λ_max` is the Lanczos estimate times this margin (Lanczos estimates from below).
const MARGIN: f64 = 1.1;

/// A multigrid V-cycle for one SPD block matrix, usable as a CG preconditioner.
pub(crate) struct Multigrid<'a> {
    /// The finest matrix (level 0), borrowed: it is the Newton system itself.
    fine: &'a BlockMatrix,
    /// Smoothed levels, finest first; `levels[0]` is the fine matrix.
    levels: Vec<Level>,
    /// Direct solver of the coarsest level (the fine matrix itself when it is small).
    direct: Cholesky,
}

/// One smoothed level: its matrix (`None` on level 0), smoother and the interpolation from
/// the next coarser level.
struct Level {
    matrix: Option<BlockMatrix>,
    smoother: Chebyshev,
    down: Transfer,
    /// Work vectors kept between applications (fresh pages at 10⁶ rows cost ~1 `mul_vec`);
    /// a concurrent application finds it empty and allocates its own.
    scratch: Mutex<Option<Scratch>>,
}

/// Work vectors of one level: residual, two Chebyshev directions, coarse rhs and solution.
struct Scratch {
    r: Vec<DVec2>,
    d: Vec<DVec2>,
    dn: Vec<DVec2>,
    bc: Vec<DVec2>,
    xc: Vec<DVec2>,
}

/// Bilinear interpolation from the active nodes of a coarse grid to the rows of a finer level.
struct Transfer {
    /// Coarse node (compact index) of each of the 4 cell corners of each fine row, `NONE` where
    /// the weight is zero. Corner order: (0,0), (1,0), (0,1), (1,1).
    node: Vec<[u32; 4]>,
    /// Local coordinates (s, t) of each fine row in its cell; the weights of the corners are
    /// [`bilinear`] of them (f32 is plenty; restriction uses the same numbers, so `R = Pᵀ`
    /// exactly).
    st: Vec<[f32; 2]>,
    /// For each coarse node, the fine rows in its support as `row * 4 + corner`.
    support_start: Vec<usize>,
    support: Vec<u32>,
    /// Grid coordinates of the coarse nodes.
    coords: Vec<[i32; 2]>,
    /// The coarse grid (shared origin, spacing of that level).
    grid: Grid,
}

/// A Cartesian grid: node `(x, y)` at `origin + h (x, y)`, `0 ≤ x < nx`, `0 ≤ y < ny`.
#[derive(Clone, Copy, Debug)]
struct Grid {
    origin: DVec2,
    h: f64,
    nx: usize,
    ny: usize,
}

/// Where a fine row sits in the coarse grid: its cell and local coordinates in [0, 1).
#[derive(Clone, Copy)]
struct Located {
    cell: [i32; 2],
    s: f64,
    t: f64,
}

impl<'a> Multigrid<'a> {
    /// Build the hierarchy for the SPD block matrix `a`; row `i` belongs to the point
    /// `points[i]`; `spacing` is the mean distance between neighbouring points (estimated from
    /// the bounding box when it is not a positive number).
    pub(crate) fn new(a: &'a BlockMatrix, points: &[DVec2], spacing: f64) -> Multigrid<'a> {
        let n = a.rows();
        assert_eq!(points.len(), n, "one point per block row");
        let mut levels = Vec::new();
        if n <= COARSEST {
            return Multigrid {
                fine: a,
                levels,
                direct: Cholesky::new(a),
            };
        }
        let (lo, hi) = bbox(points);
        let h = if spacing.is_finite() && spacing > 0.0 {
            spacing
        } else {
            let ext = (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
            (ext.x * ext.y / n as f64).sqrt().max(f64::MIN_POSITIVE)
        };
        let h1 = COARSE_FACTOR * h;
        let grid = Grid {
            origin: lo,
            h: h1,
            nx: cells_along(hi.x - lo.x, h1) + 1,
            ny: cells_along(hi.y - lo.y, h1) + 1,
        };
        let down = Transfer::new(n, grid, |i| {
            let p = points[i];
            if !p.is_finite() {
                return None;
            }
            let u = (p - lo) / h1;
            let (cx, cy) = (u.x.floor(), u.y.floor());
            Some(Located {
                cell: [cx as i32, cy as i32],
                s: u.x - cx,
                t: u.y - cy,
            })
        });
        let smoother = Chebyshev::new(a, DEGREE_FINE, LANCZOS_FINE, 0x5EED);
        let mut coarse = galerkin(a, &down);
        levels.push(Level {
            matrix: None,
            smoother,
            down,
            scratch: Mutex::new(None),
        });
        while coarse.rows() > COARSEST && levels.len() < 40 {
            let prev = &levels.last().expect("level 0 exists").down;
            let coords = &prev.coords;
            let g = prev.grid;
            let grid = Grid {
                origin: g.origin,
                h: 2.0 * g.h,
                nx: (g.nx - 1) / 2 + 2,
                ny: (g.ny - 1) / 2 + 2,
            };
            // Nested grids: node x of the fine grid is in coarse cell x / 2 at s = (x % 2) / 2,
            // exact in binary, so only the exact 1, 1/2, 1/4 weights appear.
            let down = Transfer::new(coarse.rows(), grid, |i| {
                let [x, y] = coords[i];
                Some(Located {
                    cell: [x / 2, y / 2],
                    s: 0.5 * (x % 2) as f64,
                    t: 0.5 * (y % 2) as f64,
                })
            });
            let next = galerkin(&coarse, &down);
            let smoother = Chebyshev::new(
                &coarse,
                DEGREE_COARSE,
                LANCZOS_COARSE,
                0x5EED + levels.len() as u64,
            );
            levels.push(Level {
                matrix: Some(coarse),
                smoother,
                down,
                scratch: Mutex::new(None),
            });
            coarse = next;
        }
        Multigrid {
            fine: a,
            levels,
            direct: Cholesky::new(&coarse),
        }
    }

    /// One V-cycle applied to the residual `r`: `out ≈ A⁻¹ r`. A symmetric positive definite
    /// linear operator of `r` (the same smoother before and after, zero initial guess).
    pub(crate) fn apply(&self, r: &[DVec2], out: &mut [DVec2]) {
        assert_eq!(r.len(), self.fine.rows());
        assert_eq!(out.len(), r.len());
        self.vcycle(0, r, out);
    }

    /// Number of levels including the directly solved one.
    pub(crate) fn depth(&self) -> usize {
        self.levels.len() + 1
    }

    /// Bytes held by the hierarchy (not counting the borrowed fine matrix).
    pub(crate) fn memory(&self) -> usize {
        let mat = |m: &BlockMatrix| {
            m.row_start.capacity() * 8 + m.col.capacity() * 4 + m.block.capacity() * 32
        };
        let lv: usize = self
            .levels
            .iter()
            .map(|l| {
                l.matrix.as_ref().map_or(0, mat)
                    + l.down.node.capacity() * 16
                    + l.down.st.capacity() * 8
                    + l.down.support_start.capacity() * 8
                    + l.down.support.capacity() * 4
                    + l.down.coords.capacity() * 8
            })
            .sum();
        lv + self.direct.l.capacity() * 8
    }

    /// Rows of each level, finest first (the last is the directly solved one).
    pub(crate) fn level_sizes(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self.levels.iter().map(|l| l.smoother.rows).collect();
        v.push(self.direct.n / 2);
        v
    }

    /// `x = B_l b` on level `l` (x is overwritten).
    fn vcycle(&self, l: usize, b: &[DVec2], x: &mut [DVec2]) {
        let Some(level) = self.levels.get(l) else {
            self.direct.solve(b, x);
            return;
        };
        let a = level.matrix.as_ref().unwrap_or(self.fine);
        let n = b.len();
        let nc = level.down.coords.len();
        let taken = level.scratch.lock().ok().and_then(|mut g| g.take());
        let Scratch {
            mut r,
            mut d,
            mut dn,
            mut bc,
            mut xc,
        } = taken.unwrap_or_else(|| Scratch {
            r: vec![DVec2::ZERO; n],
            d: vec![DVec2::ZERO; n],
            dn: vec![DVec2::ZERO; n],
            bc: vec![DVec2::ZERO; nc],
            xc: vec![DVec2::ZERO; nc],
        });
        // Pre-smoothing from zero, leaving the residual in r.
        level
            .smoother
            .smooth(a, b, x, &mut r, &mut d, &mut dn, true, true);
        level.down.restrict(&r, &mut bc);
        self.vcycle(l + 1, &bc, &mut xc);
        level.down.prolong_add(&xc, x);
        level
            .smoother
            .smooth(a, b, x, &mut r, &mut d, &mut dn, false, false);
        if let Ok(mut g) = level.scratch.lock() {
            *g = Some(Scratch { r, d, dn, bc, xc });
        }
    }
}

/// Number of grid cells needed to cover a length `len` with spacing `h` (at least 1).
fn cells_along(len: f64, h: f64) -> usize {
    let c = (len / h).floor();
    if c.is_finite() && c >= 0.0 {
        c as usize + 1
    } else {
        1
    }
}

/// Bounding box of the finite points (the unit box at the origin when there are none).
fn bbox(points: &[DVec2]) -> (DVec2, DVec2) {
    let (lo, hi) = points.iter().filter(|p| p.is_finite()).fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if lo.is_finite() && hi.is_finite() {
        (lo, hi)
    } else {
        (DVec2::ZERO, DVec2::ONE)
    }
}

impl Transfer {
    /// Interpolation onto `rows` fine rows located in the cells of `grid` by `locate`
    /// (`None`: the row gets no coarse correction).
    fn new(rows: usize, grid: Grid, locate: impl Fn(usize) -> Option<Located> + Sync) -> Transfer {
        assert!(rows < (1 << 30), "at most 2^30 rows");
        let (nx, ny) = (grid.nx as i64, grid.ny as i64);
        // Grid node index of each corner with a nonzero weight (or NONE), and the weights.
        let raw: Vec<([u32; 4], [f32; 2])> = (0..rows)
            .into_par_iter()
            .with_min_len(MIN_LEN)
            .map(|i| {
                let mut idx = [NONE; 4];
                let Some(loc) = locate(i) else {
                    return (idx, [0.0; 2]);
                };
                let st = [loc.s.clamp(0.0, 1.0) as f32, loc.t.clamp(0.0, 1.0) as f32];
                for (k, &wk) in bilinear(st).iter().enumerate() {
                    let x = i64::from(loc.cell[0]) + (k & 1) as i64;
                    let y = i64::from(loc.cell[1]) + (k >> 1) as i64;
                    if wk >= MIN_WEIGHT && (0..nx).contains(&x) && (0..ny).contains(&y) {
                        idx[k] = (y * nx + x) as u32;
                    }
                }
                (idx, st)
            })
            .collect();
        // Active nodes, numbered in grid order (row-major: good locality).
        let mut compact = vec![NONE; grid.nx * grid.ny];
        for (idx, _) in &raw {
            for &g in idx.iter().filter(|&&g| g != NONE) {
                compact[g as usize] = 0;
            }
        }
        let mut coords = Vec::new();
        for (g, c) in compact.iter_mut().enumerate() {
            if *c == 0 {
                *c = coords.len() as u32;
                coords.push([(g % grid.nx) as i32, (g / grid.nx) as i32]);
            }
        }
        let (node, st): (Vec<[u32; 4]>, Vec<[f32; 2]>) = raw
            .into_par_iter()
            .with_min_len(MIN_LEN)
            .map(|(idx, w)| {
                (
                    idx.map(|g| if g == NONE { NONE } else { compact[g as usize] }),
                    w,
                )
            })
            .unzip();
        // Supports by counting sort (in row order within each node: deterministic).
        let nc = coords.len();
        let mut support_start = vec![0usize; nc + 1];
        for idx in &node {
            for &c in idx.iter().filter(|&&c| c != NONE) {
                support_start[c as usize + 1] += 1;
            }
        }
        for c in 0..nc {
            support_start[c + 1] += support_start[c];
        }
        let mut fill = support_start.clone();
        let mut support = vec![0u32; support_start[nc]];
        for (i, idx) in node.iter().enumerate() {
            for (k, &c) in idx.iter().enumerate() {
                if c != NONE {
                    support[fill[c as usize]] = (i * 4 + k) as u32;
                    fill[c as usize] += 1;
                }
            }
        }
        Transfer {
            node,
            st,
            support_start,
            support,
            coords,
            grid,
        }
    }

    /// `out = Pᵀ r` (gather per coarse node).
    fn restrict(&self, r: &[DVec2], out: &mut [DVec2]) {
        out.par_iter_mut()
            .with_min_len(MIN_LEN / 4)
            .enumerate()
            .for_each(|(c, o)| {
                *o = self.support[self.support_start[c]..self.support_start[c + 1]]
                    .iter()
                    .fold(DVec2::ZERO, |s, &e| {
                        let (i, k) = (e as usize >> 2, e as usize & 3);
                        s + bilinear(self.st[i])[k] * r[i]
                    });
            });
    }

    /// `x += P xc`.
    fn prolong_add(&self, xc: &[DVec2], x: &mut [DVec2]) {
        x.par_iter_mut()
            .with_min_len(MIN_LEN)
            .zip(self.node.par_iter().zip(&self.st))
            .for_each(|(xi, (idx, st))| {
                let w = bilinear(*st);
                for k in 0..4 {
                    if idx[k] != NONE {
                        *xi += w[k] * xc[idx[k] as usize];
                    }
                }
            });
    }
}

/// Bilinear weights of the corners (0,0), (1,0), (0,1), (1,1) at local coordinates `st`.
fn bilinear(st: [f32; 2]) -> [f64; 4] {
    let (s, t) = (f64::from(st[0]), f64::from(st[1]));
    [(1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t]
}

/// Half-width of the dense accumulation window of the Galerkin product (in coarse nodes).
const WIN: i32 = 3;
const WIN_SIDE: usize = (2 * WIN + 1) as usize;

/// The Galerkin product `Pᵀ A P` for the interpolation `p` (rows of `a` are its fine rows),
/// assembled per coarse row: each coarse row gathers over the fine rows in its support, adding
/// into a dense window of grid offsets (far couplings, e.g. from long edges, go to a sorted
/// overflow list). Diagonal block first, only nonzero blocks stored.
fn galerkin(a: &BlockMatrix, p: &Transfer) -> BlockMatrix {
    let nc = p.coords.len();
    let starts: Vec<usize> = (0..nc).step_by(CHUNK).collect();
    let parts: Vec<(Vec<usize>, Vec<u32>, Vec<DMat2>)> = starts
        .par_iter()
        .map(|&c0| {
            let c1 = (c0 + CHUNK).min(nc);
            let mut len = Vec::with_capacity(c1 - c0);
            let mut col = Vec::new();
            let mut block = Vec::new();
            let mut win = [DMat2::ZERO; WIN_SIDE * WIN_SIDE];
            let mut win_col = [NONE; WIN_SIDE * WIN_SIDE];
            let mut far: Vec<(u32, DMat2)> = Vec::new();
            for c in c0..c1 {
                let [cx, cy] = p.coords[c];
                for &e in &p.support[p.support_start[c]..p.support_start[c + 1]] {
                    let (i, k) = (e as usize >> 2, e as usize & 3);
                    let wi = bilinear(p.st[i])[k];
                    let r = a.row_start[i]..a.row_start[i + 1];
                    for (&j, b) in a.col[r.clone()].iter().zip(&a.block[r]) {
                        if *b == DMat2::ZERO {
                            continue;
                        }
                        let (nj, wj) = (&p.node[j as usize], bilinear(p.st[j as usize]));
                        for m in 0..4 {
                            let cj = nj[m];
                            if cj == NONE {
                                continue;
                            }
                            let blk = *b * (wi * wj[m]);
                            let [x, y] = p.coords[cj as usize];
                            let (dx, dy) = (x - cx, y - cy);
                            if dx.abs() <= WIN && dy.abs() <= WIN {
                                let s = ((dy + WIN) * (2 * WIN + 1) + dx + WIN) as usize;
                                win[s] += blk;
                                win_col[s] = cj;
                            } else {
                                far.push((cj, blk));
                            }
                        }
                    }
                }
                let before = col.len();
                // Diagonal first (always present), then the window in offset order.
                let centre = (WIN * (2 * WIN + 1) + WIN) as usize;
                col.push(c as u32);
                block.push(win[centre]);
                win[centre] = DMat2::ZERO;
                win_col[centre] = NONE;
                for (w, wc) in win.iter_mut().zip(win_col.iter_mut()) {
                    if *wc != NONE {
                        if *w != DMat2::ZERO {
                            col.push(*wc);
                            block.push(*w);
                        }
                        *w = DMat2::ZERO;
                        *wc = NONE;
                    }
                }
                if !far.is_empty() {
                    far.sort_by_key(|&(cj, _)| cj);
                    let mut it = far.drain(..);
                    let mut cur = it.next();
                    for (cj, blk) in it {
                        match cur.as_mut() {
                            Some((cc, acc)) if *cc == cj => *acc += blk,
                            _ => {
                                if let Some((cc, acc)) = cur.take() {
                                    col.push(cc);
                                    block.push(acc);
                                }
                                cur = Some((cj, blk));
                            }
                        }
                    }
                    if let Some((cc, acc)) = cur {
                        col.push(cc);
                        block.push(acc);
                    }
                }
                len.push(col.len() - before);
            }
            (len, col, block)
        })
        .collect();
    let total: usize = parts.iter().map(|p| p.1.len()).sum();
    let mut m = BlockMatrix {
        row_start: Vec::with_capacity(nc + 1),
        col: Vec::with_capacity(total),
        block: Vec::with_capacity(total),
    };
    m.row_start.push(0);
    let mut acc = 0;
    for (len, col, block) in parts {
        for l in len {
            acc += l;
            m.row_start.push(acc);
        }
        m.col.extend_from_slice(&col);
        m.block.extend_from_slice(&block);
    }
    m
}

/// Inverse of a 2×2 SPD block, regularised when it is (nearly) singular; zero for a zero block.
fn safe_inverse(d: DMat2) -> DMat2 {
    let tr = d.x_axis.x + d.y_axis.y;
    if !(tr.is_finite() && tr > 0.0) {
        return DMat2::ZERO;
    }
    let det = d.determinant();
    if det > 1e-12 * tr * tr {
        d.inverse()
    } else {
        (d + DMat2::from_diagonal(DVec2::splat(1e-6 * tr))).inverse()
    }
}

/// Chebyshev smoother of a fixed degree for `D⁻¹A` on `[λ_max / RATIO, λ_max]`.
struct Chebyshev {
    rows: usize,
    lo: f64,
    hi: f64,
    degree: usize,
}

impl Chebyshev {
    fn new(a: &BlockMatrix, degree: usize, steps: usize, seed: u64) -> Chebyshev {
        let hi = MARGIN * lanczos_max(a, steps, seed);
        let hi = if hi.is_finite() && hi > 0.0 { hi } else { 2.0 };
        Chebyshev {
            rows: a.rows(),
            lo: hi / RATIO,
            hi,
            degree: degree.max(1),
        }
    }

    /// Chebyshev iteration for `A x = b` from `x` (from zero when `zero_start`; then `x` is
    /// only written). When `want_residual`, `r = b − A x` on return. `r`, `d`, `dn` are scratch.
    #[allow(clippy::too_many_arguments)]
    fn smooth(
        &self,
        a: &BlockMatrix,
        b: &[DVec2],
        x: &mut [DVec2],
        r: &mut [DVec2],
        d: &mut Vec<DVec2>,
        dn: &mut Vec<DVec2>,
        zero_start: bool,
        want_residual: bool,
    ) {
        let theta = 0.5 * (self.hi + self.lo);
        let delta = 0.5 * (self.hi - self.lo);
        let sigma = theta / delta;
        let mut rho = 1.0 / sigma;
        if zero_start {
            r.copy_from_slice(b);
            x.par_iter_mut()
                .with_min_len(MIN_LEN)
                .for_each(|v| *v = DVec2::ZERO);
        } else {
            residual(a, b, x, r);
        }
        d.par_iter_mut()
            .with_min_len(MIN_LEN)
            .zip(r.par_iter())
            .enumerate()
            .for_each(|(i, (di, ri))| *di = (safe_inverse(a.diagonal(i)) * *ri) / theta);
        for step in 1..=self.degree {
            let last = step == self.degree;
            if last && !want_residual {
                x.par_iter_mut()
                    .with_min_len(MIN_LEN)
                    .zip(d.par_iter())
                    .for_each(|(xi, di)| *xi += *di);
                break;
            }
            let rho_new = 1.0 / (2.0 * sigma - rho);
            let (c1, c2) = (rho_new * rho, 2.0 * rho_new / delta);
            // One pass: r -= A d, x += d, dn = c1 d + c2 D⁻¹ r.
            let dd: &[DVec2] = d;
            r.par_iter_mut()
                .with_min_len(MIN_LEN)
                .zip(x.par_iter_mut().zip(dn.par_iter_mut()))
                .enumerate()
                .for_each(|(i, (ri, (xi, dni)))| {
                    let rg = a.row_start[i]..a.row_start[i + 1];
                    let diag = a.block[rg.start];
                    let ad = a.col[rg.clone()]
                        .iter()
                        .zip(&a.block[rg])
                        .fold(DVec2::ZERO, |s, (&j, blk)| s + *blk * dd[j as usize]);
                    *ri -= ad;
                    *xi += dd[i];
                    // The diagonal block is inverted on the fly: it is in cache, and storing
                    // D⁻¹ would cost 32 bytes per row.
                    *dni = c1 * dd[i] + c2 * (safe_inverse(diag) * *ri);
                });
            std::mem::swap(d, dn);
            rho = rho_new;
        }
    }
}

/// `r = b − A x`.
fn residual(a: &BlockMatrix, b: &[DVec2], x: &[DVec2], r: &mut [DVec2]) {
    r.par_iter_mut()
        .with_min_len(MIN_LEN)
        .enumerate()
        .for_each(|(i, ri)| {
            let rg = a.row_start[i]..a.row_start[i + 1];
            *ri = a.col[rg.clone()]
                .iter()
                .zip(&a.block[rg])
                .fold(b[i], |s, (&j, blk)| s - *blk * x[j as usize]);
        });
}

/// Estimate of the largest eigenvalue of `D⁻¹A` by `steps` Lanczos steps in the `D` inner
/// product from a seeded random start (an underestimate that converges fast for the top).
fn lanczos_max(a: &BlockMatrix, steps: usize, seed: u64) -> f64 {
    let n = a.rows();
    if n == 0 {
        return 1.0;
    }
    // p = D q; start from random p (one seeded generator per fixed chunk), q = D⁻¹ p.
    let mut p = vec![DVec2::ZERO; n];
    p.par_chunks_mut(4096).enumerate().for_each(|(c, ch)| {
        let mut rng = geometry::Rng::new(seed ^ (c as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        ch.iter_mut()
            .for_each(|v| *v = DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)));
    });
    let mut q: Vec<DVec2> = p
        .par_iter()
        .with_min_len(MIN_LEN)
        .enumerate()
        .map(|(i, v)| safe_inverse(a.diagonal(i)) * *v)
        .collect();
    let nrm = tessellation::dot(&q, &p).sqrt();
    if nrm.is_nan() || nrm <= 0.0 {
        return 1.0;
    }
    scale(&mut q, 1.0 / nrm);
    scale(&mut p, 1.0 / nrm);
    let mut q_prev = vec![DVec2::ZERO; n];
    let mut p_prev = vec![DVec2::ZERO; n];
    let mut u = vec![DVec2::ZERO; n];
    let (mut alpha, mut beta) = (Vec::new(), Vec::new());
    let mut b_prev = 0.0;
    for _ in 0..steps {
        a.mul_vec(&q, &mut u);
        let al = tessellation::dot(&q, &u);
        alpha.push(al);
        // u ← D w = u − α p − β p_prev; q_prev ← w = D⁻¹(D w).
        u.par_iter_mut()
            .with_min_len(MIN_LEN)
            .zip(p.par_iter().zip(&p_prev))
            .for_each(|(ui, (pi, ppi))| *ui -= al * *pi + b_prev * *ppi);
        q_prev
            .par_iter_mut()
            .with_min_len(MIN_LEN)
            .zip(u.par_iter())
            .enumerate()
            .for_each(|(i, (wi, ui))| *wi = safe_inverse(a.diagonal(i)) * *ui);
        let bn = tessellation::dot(&q_prev, &u);
        if bn.is_nan() || bn <= 1e-300 {
            break;
        }
        let bn = bn.sqrt();
        beta.push(bn);
        // Rotate: (q_prev, q) ← (q, w / β), (p_prev, p) ← (p, D w / β).
        std::mem::swap(&mut q, &mut q_prev);
        scale(&mut q, 1.0 / bn);
        std::mem::swap(&mut p, &mut p_prev);
        std::mem::swap(&mut p, &mut u);
        scale(&mut p, 1.0 / bn);
        b_prev = bn;
    }
    beta.truncate(alpha.len().saturating_sub(1));
    tridiagonal_max(&alpha, &beta)
}

/// `v *= f`.
fn scale(v: &mut [DVec2], f: f64) {
    v.par_iter_mut().with_min_len(MIN_LEN).for_each(|x| *x *= f);
}

/// Largest eigenvalue of the symmetric tridiagonal matrix (diagonal `a`, off-diagonal `b`) by
/// Sturm-sequence bisection.
fn tridiagonal_max(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len();
    if n == 0 {
        return 1.0;
    }
    let radius = |i: usize| {
        (if i > 0 { b[i - 1].abs() } else { 0.0 }) + (if i + 1 < n { b[i].abs() } else { 0.0 })
    };
    let mut lo = (0..n)
        .map(|i| a[i] - radius(i))
        .fold(f64::INFINITY, f64::min);
    let mut hi = (0..n)
        .map(|i| a[i] + radius(i))
        .fold(f64::NEG_INFINITY, f64::max);
    // Number of eigenvalues below x.
    let below = |x: f64| {
        let mut count = 0;
        let mut d = 1.0;
        for i in 0..n {
            let off = if i > 0 { b[i - 1] * b[i - 1] } else { 0.0 };
            d = a[i] - x - if i > 0 { off / d } else { 0.0 };
            if d == 0.0 {
                d = -1e-300;
            }
            if d < 0.0 {
                count += 1;
            }
        }
        count
    };
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if below(mid) >= n {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo <= 1e-12 * hi.abs() {
            break;
        }
    }
    hi
}

/// Dense Cholesky factor of a small block matrix (lower triangle, row-major, `n × n` scalars).
struct Cholesky {
    n: usize,
    l: Vec<f64>,
}

impl Cholesky {
    fn new(a: &BlockMatrix) -> Cholesky {
        let n = 2 * a.rows();
        let mut m = vec![0.0; n * n];
        for i in 0..a.rows() {
            for k in a.row_start[i]..a.row_start[i + 1] {
                let j = a.col[k] as usize;
                let b = a.block[k];
                // Symmetrise (the Galerkin rows are summed in different orders).
                for (r, c, v) in [
                    (0, 0, b.x_axis.x),
                    (1, 0, b.x_axis.y),
                    (0, 1, b.y_axis.x),
                    (1, 1, b.y_axis.y),
                ] {
                    m[(2 * i + r) * n + 2 * j + c] += 0.5 * v;
                    m[(2 * j + c) * n + 2 * i + r] += 0.5 * v;
                }
            }
        }
        let max_diag = (0..n).map(|i| m[i * n + i]).fold(0.0f64, f64::max);
        let floor = 1e-12 * max_diag.max(f64::MIN_POSITIVE);
        for i in 0..n {
            m[i * n + i] += floor;
        }
        for j in 0..n {
            let mut djj = m[j * n + j] - (0..j).map(|k| m[j * n + k] * m[j * n + k]).sum::<f64>();
            if djj.is_nan() || djj <= floor {
                djj = floor; // a null direction of a rank-deficient coarse space
            }
            let ljj = djj.sqrt();
            m[j * n + j] = ljj;
            for i in j + 1..n {
                let s = m[i * n + j] - (0..j).map(|k| m[i * n + k] * m[j * n + k]).sum::<f64>();
                m[i * n + j] = s / ljj;
            }
        }
        Cholesky { n, l: m }
    }

    fn solve(&self, b: &[DVec2], x: &mut [DVec2]) {
        let n = self.n;
        let l = &self.l;
        let mut y: Vec<f64> = b.iter().flat_map(|v| [v.x, v.y]).collect();
        for i in 0..n {
            let s = (0..i).map(|k| l[i * n + k] * y[k]).sum::<f64>();
            y[i] = (y[i] - s) / l[i * n + i];
        }
        for i in (0..n).rev() {
            let s = (i + 1..n).map(|k| l[k * n + i] * y[k]).sum::<f64>();
            y[i] = (y[i] - s) / l[i * n + i];
        }
        for (k, v) in x.iter_mut().enumerate() {
            *v = DVec2::new(y[2 * k], y[2 * k + 1]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::{Region, Rng};
    use tessellation::{dot, Delaunay};

    /// A jittered square lattice of spacing `h` inside `region` (at least `h / 4` from its
    /// boundary), in row-major order.
    fn lattice(region: &Region, h: f64, seed: u64) -> Vec<DVec2> {
        let (lo, hi) = region.bbox();
        let mut rng = Rng::new(seed);
        let mut pts = Vec::new();
        let (nx, ny) = (
            ((hi.x - lo.x) / h) as usize + 1,
            ((hi.y - lo.y) / h) as usize + 1,
        );
        for y in 0..ny {
            for x in 0..nx {
                let p = lo
                    + h * DVec2::new(x as f64 + 0.5, y as f64 + 0.5)
                    + 0.3 * h * DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
                if region.signed_distance(p) < -0.25 * h {
                    pts.push(p);
                }
            }
        }
        pts
    }

    /// A 2-D vector "elasticity" on the Delaunay graph: each edge (i, j) inside the region
    /// (midpoint inside, length < 2.5 h) adds the spring `w (e eᵀ + β I)` (unit direction `e`,
    /// weight w in [0.5, 1.5]), plus `shift · I` on the diagonal. With `constrain`, points within
    /// `h` of the boundary may only slide along it: their blocks are projected onto the tangent
    /// and the normal direction gets a penalty of the size of the local diagonal — the structure
    /// of the projected Newton Hessian. SPD.
    fn elasticity(
        region: &Region,
        pts: &[DVec2],
        h: f64,
        shift: f64,
        constrain: bool,
    ) -> BlockMatrix {
        let del = Delaunay::new(pts);
        let n = pts.len();
        let normal: Vec<Option<DVec2>> = pts
            .iter()
            .map(|&p| {
                if !constrain || region.signed_distance(p) < -h {
                    return None;
                }
                let e = 1e-6 * h;
                let g = DVec2::new(
                    region.signed_distance(p + DVec2::X * e)
                        - region.signed_distance(p - DVec2::X * e),
                    region.signed_distance(p + DVec2::Y * e)
                        - region.signed_distance(p - DVec2::Y * e),
                );
                Some(g.normalize())
            })
            .collect();
        let proj = |i: usize| normal[i].map_or(DMat2::IDENTITY, |m| DMat2::IDENTITY - outer(m, m));
        let mut a = BlockMatrix {
            row_start: vec![0],
            ..Default::default()
        };
        for i in 0..n {
            let mut diag = DMat2::from_diagonal(DVec2::splat(shift));
            let mut off = Vec::new();
            for j in del.neighbors(i) {
                let (p, q) = (pts[i], pts[j]);
                let len = p.distance(q);
                if len > 2.5 * h || region.signed_distance(0.5 * (p + q)) >= 0.0 {
                    continue;
                }
                let (lo, hi) = (i.min(j) as u64, i.max(j) as u64);
                let w = Rng::new(lo * 1_000_003 + hi).range(0.5, 1.5);
                let e = (q - p) / len;
                let k = w * (outer(e, e) + DMat2::from_diagonal(DVec2::splat(0.1)));
                diag += k;
                off.push((j as u32, -k));
            }
            let pi = proj(i);
            let penalty = normal[i].map_or(DMat2::ZERO, |m| {
                0.5 * (diag.x_axis.x + diag.y_axis.y) * outer(m, m)
            });
            a.col.push(i as u32);
            a.block.push(pi * diag * pi + penalty);
            for (j, k) in off {
                a.col.push(j);
                a.block.push(pi * k * proj(j as usize));
            }
            a.row_start.push(a.col.len());
        }
        a
    }

    fn outer(a: DVec2, b: DVec2) -> DMat2 {
        DMat2::from_cols(a * b.x, a * b.y)
    }

    fn random_vec(n: usize, seed: u64) -> Vec<DVec2> {
        let mut rng = Rng::new(seed);
        (0..n)
            .map(|_| DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)))
            .collect()
    }

    /// Preconditioned CG from zero to `‖r‖ ≤ tol ‖b‖`; returns (iterations, x).
    fn pcg(
        a: &BlockMatrix,
        b: &[DVec2],
        tol: f64,
        max_iter: usize,
        prec: impl Fn(&[DVec2], &mut [DVec2]),
    ) -> (usize, Vec<DVec2>) {
        let n = b.len();
        let mut x = vec![DVec2::ZERO; n];
        let mut r = b.to_vec();
        let mut z = vec![DVec2::ZERO; n];
        let mut q = vec![DVec2::ZERO; n];
        prec(&r, &mut z);
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        let bnorm = dot(b, b).sqrt();
        for it in 0..max_iter {
            if dot(&r, &r).sqrt() <= tol * bnorm {
                return (it, x);
            }
            a.mul_vec(&p, &mut q);
            let alpha = rz / dot(&p, &q);
            for k in 0..n {
                x[k] += alpha * p[k];
                r[k] -= alpha * q[k];
            }
            prec(&r, &mut z);
            let rz_new = dot(&r, &z);
            let beta = rz_new / rz;
            rz = rz_new;
            for k in 0..n {
                p[k] = z[k] + beta * p[k];
            }
        }
        (max_iter, x)
    }

    fn jacobi(a: &BlockMatrix) -> impl Fn(&[DVec2], &mut [DVec2]) + '_ {
        let dinv: Vec<DMat2> = (0..a.rows()).map(|i| a.diagonal(i).inverse()).collect();
        move |r, z| {
            for (k, zk) in z.iter_mut().enumerate() {
                *zk = dinv[k] * r[k];
            }
        }
    }

    /// (Jacobi iterations, multigrid iterations) of PCG to 1e-8 on a random right-hand side,
    /// checking the multigrid solution's true residual.
    fn iterations(a: &BlockMatrix, pts: &[DVec2], h: f64) -> (usize, usize) {
        let b = random_vec(a.rows(), 7);
        let (jac, _) = pcg(a, &b, 1e-8, 20_000, jacobi(a));
        let mg = Multigrid::new(a, pts, h);
        let (it, x) = pcg(a, &b, 1e-8, 1000, |r, z| mg.apply(r, z));
        let mut ax = vec![DVec2::ZERO; x.len()];
        a.mul_vec(&x, &mut ax);
        let res: Vec<DVec2> = ax.iter().zip(&b).map(|(p, q)| *p - *q).collect();
        assert!(dot(&res, &res).sqrt() <= 2e-8 * dot(&b, &b).sqrt());
        (jac, it)
    }

    fn region_h(name: &str, k: usize) -> (Region, f64) {
        let region = Region::builtin(name).unwrap();
        let h = (region.area() / k as f64).sqrt();
        (region, h)
    }

    #[test]
    fn apply_is_symmetric_positive_and_deterministic() {
        for (name, constrain) in [("circle", false), ("lake", true)] {
            let (region, h) = region_h(name, 6000);
            let pts = lattice(&region, h, 1);
            let a = elasticity(&region, &pts, h, 1e-4, constrain);
            let mg = Multigrid::new(&a, &pts, h);
            assert!(mg.depth() >= 3, "{name}: {:?}", mg.level_sizes());
            let n = pts.len();
            let (r1, r2) = (random_vec(n, 2), random_vec(n, 3));
            let (mut m1, mut m2) = (vec![DVec2::ZERO; n], vec![DVec2::ZERO; n]);
            mg.apply(&r1, &mut m1);
            mg.apply(&r2, &mut m2);
            let (s12, s21) = (dot(&m1, &r2), dot(&r1, &m2));
            let scale = dot(&m1, &m1).sqrt() * dot(&r2, &r2).sqrt();
            assert!((s12 - s21).abs() <= 1e-10 * scale, "{name}: {s12} vs {s21}");
            // Positive on random, smooth (a translation, a rotation) and oscillating fields.
            let smooth: Vec<DVec2> = vec![DVec2::X; n];
            let rot: Vec<DVec2> = pts.iter().map(|p| p.perp()).collect();
            let osc: Vec<DVec2> = (0..n)
                .map(|i| if i % 2 == 0 { DVec2::ONE } else { -DVec2::ONE })
                .collect();
            for r in [&r1, &r2, &smooth, &rot, &osc] {
                let mut m = vec![DVec2::ZERO; n];
                mg.apply(r, &mut m);
                assert!(dot(&m, r) > 0.0, "{name}");
            }
            // The same bits on one thread.
            let one = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            let mut m1b = vec![DVec2::ZERO; n];
            one.install(|| Multigrid::new(&a, &pts, h).apply(&r1, &mut m1b));
            assert!(m1 == m1b, "{name}: result depends on the thread count");
        }
    }

    #[test]
    fn small_systems_are_solved_exactly() {
        let (region, h) = region_h("circle", 150);
        let pts = lattice(&region, h, 4);
        assert!(pts.len() <= COARSEST);
        let a = elasticity(&region, &pts, h, 1e-3, true);
        let mg = Multigrid::new(&a, &pts, h);
        let x = random_vec(pts.len(), 5);
        let mut b = vec![DVec2::ZERO; x.len()];
        a.mul_vec(&x, &mut b);
        let mut y = vec![DVec2::ZERO; x.len()];
        mg.apply(&b, &mut y);
        for (p, q) in x.iter().zip(&y) {
            assert!(p.distance(*q) < 1e-8, "{p} vs {q}");
        }
    }

    #[test]
    fn cg_iterations_stay_flat() {
        for (name, constrain) in [("circle", false), ("lake", true)] {
            let mut counts = Vec::new();
            for k in [2_000, 30_000] {
                let (region, h) = region_h(name, k);
                let pts = lattice(&region, h, 11);
                let a = elasticity(&region, &pts, h, 1e-4, constrain);
                counts.push((pts.len(), iterations(&a, &pts, h)));
            }
            eprintln!("{name}: (points, (jacobi, multigrid)) = {counts:?}");
            let [(_, (j0, m0)), (_, (j1, m1))] = counts[..] else {
                unreachable!()
            };
            assert!(m0 * 3 <= j0 && m1 * 8 <= j1, "{name}: {counts:?}");
            assert!(j1 as f64 >= 2.0 * j0 as f64, "{name}: {counts:?}");
            assert!(m1 as f64 <= 1.3 * m0 as f64 + 2.0, "{name}: {counts:?}");
        }
    }

    fn median_secs(runs: usize, mut f: impl FnMut()) -> f64 {
        let mut t: Vec<f64> = (0..runs)
            .map(|_| {
                let s = std::time::Instant::now();
                f();
                s.elapsed().as_secs_f64()
            })
            .collect();
        t.sort_by(f64::total_cmp);
        t[runs / 2]
    }

    /// Costs at scale: `cargo test --release -p ccvt --lib multigrid::tests::scale -- --ignored
    /// --nocapture` (sizes from `MG_SIZES`, default `1e5 1e6`).
    #[test]
    #[ignore]
    fn scale() {
        let sizes = std::env::var("MG_SIZES").unwrap_or_else(|_| "1e5 1e6".into());
        for k in sizes
            .split_whitespace()
            .map(|w| w.parse::<f64>().unwrap() as usize)
        {
            for (name, constrain) in [("circle", true), ("lake", true)] {
                let (region, h) = region_h(name, k);
                let pts = lattice(&region, h, 11);
                let a = elasticity(&region, &pts, h, 1e-4, constrain);
                let n = pts.len();
                let build = median_secs(3, || drop(Multigrid::new(&a, &pts, h)));
                let mg = Multigrid::new(&a, &pts, h);
                let r = random_vec(n, 3);
                let mut out = vec![DVec2::ZERO; n];
                let apply = median_secs(5, || mg.apply(&r, &mut out));
                let matvec = median_secs(5, || a.mul_vec(&r, &mut out));
                let (it, _) = pcg(&a, &r, 1e-8, 1000, |r, z| mg.apply(r, z));
                let cap = if n > 300_000 { 0 } else { 20_000 };
                let (jac, _) = pcg(&a, &r, 1e-8, cap, jacobi(&a));
                eprintln!(
                    "{name} n={n}: levels {:?}, memory {:.1} MB, build {:.3} s, apply {:.1} ms \
                     = {:.2} mul_vec ({:.1} ms), CG iterations: multigrid {it}, block-Jacobi {}",
                    mg.level_sizes(),
                    mg.memory() as f64 / 1e6,
                    build,
                    apply * 1e3,
                    apply / matvec,
                    matvec * 1e3,
                    if cap == 0 {
                        "skipped".to_string()
                    } else {
                        jac.to_string()
                    },
                );
            }
        }
    }
}
