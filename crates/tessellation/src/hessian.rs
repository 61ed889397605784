//! Second derivatives of the CVT energy (4) with respect to the generators.
//!
//! With cells clipped to a fixed domain, moving z_j moves only the Voronoi edge e_ij it shares
//! with z_i, so (for ρ continuous) the gradient 2 m_i (z_i − c_i) has the derivatives
//!
//! * ∂²F/∂z_i∂z_j = (2/|z_i − z_j|) ∫_{e_ij ∩ Ω} ρ (x − z_i)(x − z_j)ᵀ ds,
//! * ∂²F/∂z_i²   = 2 m_i I − Σ_j (2/|z_i − z_j|) ∫_{e_ij ∩ Ω} ρ (x − z_i)(x − z_i)ᵀ ds,
//!
//! (boundary edges of the domain do not move). The edge integrals are exact on each part of
//! e_ij inside the domain for constant ρ; a density is taken at the part's midpoint.
use crate::boundary::Boundary;
use crate::cells::{Cells, DomainGrid};
use crate::delaunay::Delaunay;
use crate::sparse::BlockMatrix;
use geometry::{DVec2, Density, Polygon};
use glam::DMat2;
use rayon::prelude::*;

/// The Hessian of the CVT energy of `points` (triangulated by `del`, cells from
/// `clipped_cells` on the same `domain` and `density`) written into `out`, with one block row
/// per Delaunay *vertex* (row and column `v` belong to the point `del.point_of_vertex(v)`; a
/// duplicate or non-finite point has no row): its diagonal in `diag`, its neighbours in the
/// row. Rows in vertex order keep the passes cache-friendly. Parallel over rows; the result
/// does not depend on the thread count.
pub fn energy_hessian(
    del: &Delaunay,
    domain: &Polygon,
    density: &Density,
    cells: &Cells,
    out: &mut BlockMatrix,
) {
    let grid = DomainGrid::new(domain, del.num_vertices());
    energy_hessian_on(del, &grid, density, cells, out);
}

/// [`energy_hessian`] on the domain's `grid` ([`DomainGrid::new`] of the domain with
/// `del.num_vertices()`), for a caller that keeps the grid from one Hessian to the next: the
/// same matrix bit for bit, without building the grid at every call.
///
/// ```
/// use cvtmesh::geometry::{DVec2, Density, Region};
/// use cvtmesh::tessellation::{
///     clipped_cells, energy_hessian, energy_hessian_on, BlockMatrix, Delaunay, DomainGrid,
/// };
/// let region = Region::builtin("circle")?;
/// let domain = region.polygonize(1e-3);
/// let points: Vec<DVec2> = (0..50)
///     .map(|i| DVec2::from_angle(i as f64 * 2.4) * (i as f64 / 50.0).sqrt() * 0.9)
///     .collect();
/// let delaunay = Delaunay::new(&points);
/// let cells = clipped_cells(&points, &delaunay, &domain, &Density::Uniform);
/// let grid = DomainGrid::new(&domain, delaunay.num_vertices());
/// let (mut kept, mut fresh) = (BlockMatrix::default(), BlockMatrix::default());
/// energy_hessian_on(&delaunay, &grid, &Density::Uniform, &cells, &mut kept);
/// energy_hessian(&delaunay, &domain, &Density::Uniform, &cells, &mut fresh);
/// assert_eq!(kept.diag, fresh.diag);
/// assert_eq!(kept.block, fresh.block);
/// # Ok::<(), cvtmesh::geometry::GeometryError>(())
/// ```
pub fn energy_hessian_on(
    del: &Delaunay,
    grid: &DomainGrid,
    density: &Density,
    cells: &Cells,
    out: &mut BlockMatrix,
) {
    let nv = del.num_vertices();
    // A row: the diagonal and the neighbours that are points (not a frame's vertices).
    let counts: Vec<usize> = (0..nv)
        .into_par_iter()
        .map(|v| {
            del.rings
                .of(v)
                .0
                .iter()
                .filter(|&&u| (u as usize) < nv)
                .count()
        })
        .collect();
    out.row_start.clear();
    out.row_start.reserve(nv + 1);
    out.row_start.push(0);
    let mut total = 0;
    for c in counts {
        total += c;
        out.row_start.push(total);
    }
    // Every entry is written below; a longer array is filled in parallel first, so that the
    // pages of fresh memory (150 MB at 10⁶ generators) are not faulted in by one thread.
    fill_to(&mut out.col, total, 0);
    fill_to(&mut out.block, total, glam::Mat2::ZERO);
    fill_to(&mut out.diag, nv, DMat2::ZERO);
    let Some(bnd) = grid.bnd.as_ref() else {
        out.diag.iter_mut().for_each(|d| *d = DMat2::ZERO);
        return;
    };
    let density = (!density.is_uniform()).then_some(density);
    // The masses in vertex order through a compact copy: the cells are in input order, and
    // reading whole cells row by row would miss the cache at nearly every row.
    let by_point: Vec<f64> = cells.cells.par_iter().map(|c| c.mass).collect();
    let mass: Vec<f64> = del
        .point_of_vertex
        .par_iter()
        .map(|&i| by_point[i as usize])
        .collect();
    drop(by_point);
    out.par_rows_mut(Scratch::default, |s, v, diagonal, col, block| {
        let mut c = 0;
        *diagonal = row(del, bnd, density, mass[v], v, s, |u, w| {
            if (u as usize) < nv {
                col[c] = u;
                block[c] = w.as_mat2();
                c += 1;
            }
        });
    });
}

/// `v` with length `n`: cut, or filled with `value` in parallel if it is shorter.
fn fill_to<T: Copy + Send + Sync>(v: &mut Vec<T>, n: usize, value: T) {
    if v.len() >= n {
        v.truncate(n);
    } else {
        (0..n).into_par_iter().map(|_| value).collect_into_vec(v);
    }
}

/// Rows `rows` (Delaunay vertices, sorted) of the Hessian of [`energy_hessian`], restricted to
/// the columns in `rows`: row and column `r` of `out` belong to vertex `rows[r]`. This is the
/// Hessian of the energy with every other generator held fixed (an active set). `grid` is
/// the domain's [`DomainGrid`] for `del.num_vertices()`.
pub fn energy_hessian_rows(
    del: &Delaunay,
    grid: &DomainGrid,
    density: &Density,
    cells: &Cells,
    rows: &[u32],
    out: &mut BlockMatrix,
) {
    debug_assert!(rows.windows(2).all(|w| w[0] < w[1]), "rows sorted");
    out.row_start.clear();
    out.col.clear();
    out.block.clear();
    out.diag.clear();
    out.row_start.push(0);
    let Some(bnd) = grid.bnd.as_ref() else {
        out.diag.resize(rows.len(), DMat2::ZERO);
        out.row_start.resize(rows.len() + 1, 0);
        return;
    };
    let density = (!density.is_uniform()).then_some(density);
    // Each vertex's row, u32::MAX for those not in `rows` (frame vertices included).
    let mut row_of = vec![u32::MAX; del.pos.len()];
    for (r, &v) in rows.iter().enumerate() {
        row_of[v as usize] = r as u32;
    }
    let row_of = &row_of;
    // Rows in parallel (fixed chunks, each a block matrix of its own), then concatenated.
    let parts: Vec<BlockMatrix> = rows
        .par_chunks(512)
        .map(|chunk| {
            let mut s = Scratch::default();
            let mut m = BlockMatrix::default();
            for &v in chunk {
                let mass = cells.cells[del.point_of_vertex[v as usize] as usize].mass;
                let d = row(del, bnd, density, mass, v as usize, &mut s, |u, w| {
                    let c = row_of[u as usize];
                    if c != u32::MAX {
                        m.col.push(c);
                        m.block.push(w.as_mat2());
                    }
                });
                m.diag.push(d);
                m.row_start.push(m.col.len());
            }
            m
        })
        .collect();
    for m in parts {
        let base = out.col.len();
        out.diag.extend(m.diag);
        out.row_start.extend(m.row_start.iter().map(|l| base + l));
        out.col.extend(m.col);
        out.block.extend(m.block);
    }
}

/// Per-row scratch: neighbours, circumcentres, parts of an edge inside the domain.
#[derive(Default)]
struct Scratch {
    nb: Vec<(u32, DVec2)>,
    cc: Vec<Option<DVec2>>,
    parts: Vec<(f64, f64)>,
    ts: Vec<f64>,
}

/// Row `v` (whose cell has `mass`) of the Hessian: calls `emit(u, block)` for every ring
/// neighbour `u` (frame vertices included) and returns the diagonal block.
fn row(
    del: &Delaunay,
    bnd: &Boundary,
    density: Option<&Density>,
    mass: f64,
    v: usize,
    s: &mut Scratch,
    mut emit: impl FnMut(u32, DMat2),
) -> DMat2 {
    let Scratch { nb, cc, parts, ts } = s;
    let z = del.pos[v];
    nb.clear();
    cc.clear();
    let (ring, outer) = del.rings.of(v);
    nb.extend(ring.iter().map(|&u| (u, del.pos[u as usize])));
    // Circumcentre of face k = (v, n_k, n_k+1), or None for the outer face.
    for (k, &o) in outer.iter().enumerate() {
        let next = nb[(k + 1) % nb.len()];
        cc.push((!o).then(|| crate::cells::canonical_circumcenter((v as u32, z), nb[k], next)));
    }
    let m = nb.len();
    // Every Voronoi edge lies in boundary-free squares: no clipping needed.
    let inner = cc.iter().all(|c| c.is_some()) && {
        let (lo, hi) = cc.iter().flatten().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), c| (lo.min(*c), hi.max(*c)),
        );
        bnd.box_inside(lo, hi)
    };
    let mut diag = DMat2::from_diagonal(DVec2::splat(2.0 * mass));
    for k in 0..m {
        let (u, zj) = nb[k];
        let prev = (k + m - 1) % m;
        let ray = |c: DVec2, third: DVec2| {
            let mut d = (zj - z).perp().normalize_or_zero();
            if d.dot(third - z) > 0.0 {
                d = -d;
            }
            let reach = (bnd.hi - bnd.lo).length() + (c - bnd.lo).length();
            c + d * reach
        };
        let seg = match (cc[prev], cc[k]) {
            (Some(p), Some(q)) => Some((p, q)),
            (Some(p), None) => Some((p, ray(p, nb[prev].1))),
            (None, Some(q)) => Some((ray(q, nb[(k + 1) % m].1), q)),
            (None, None) => None,
        };
        let mut wij = DMat2::ZERO;
        let dist = (zj - z).length();
        if let Some((p, q)) = seg.filter(|(p, q)| p.is_finite() && q.is_finite()) {
            if dist > 0.0 {
                if inner {
                    parts.clear();
                    parts.push((0.0, 1.0));
                } else {
                    inside_parts(bnd, p, q, parts, ts);
                }
                for &(t0, t1) in parts.iter() {
                    let (a, b) = (p.lerp(q, t0), p.lerp(q, t1));
                    let (wa, wb) = edge_integrals(a, b, z, zj, density);
                    wij += wa * (2.0 / dist);
                    diag -= wb * (2.0 / dist);
                }
            }
        }
        emit(u, wij);
    }
    diag
}

/// (∫ ρ (x − zi)(x − zj)ᵀ ds, ∫ ρ (x − zi)(x − zi)ᵀ ds) over the segment a–b: the exact
/// integrals of the polynomial factors times ρ at the segment's midpoint (exact for constant
/// ρ). The Hessian only shapes Newton's direction, which the energy then accepts or rejects,
/// so one evaluation of ρ per edge is enough (docs/design-notes.md, "The density's Hessian at
/// the midpoint").
fn edge_integrals(
    a: DVec2,
    b: DVec2,
    zi: DVec2,
    zj: DVec2,
    density: Option<&Density>,
) -> (DMat2, DMat2) {
    let len = (b - a).length();
    let (ua, ub) = (a - zi, b - zi);
    let w = zi - zj;
    let outer = |u: DVec2, v: DVec2| DMat2::from_cols(u * v.x, u * v.y);
    // ∫ u uᵀ for u linear along the segment, and ∫ u.
    let uu = (outer(ua, ua) + outer(ub, ub)) * (len / 3.0)
        + (outer(ua, ub) + outer(ub, ua)) * (len / 6.0);
    let u1 = (ua + ub) * (0.5 * len);
    let (uu, u1) = match density {
        None => (uu, u1),
        Some(d) => {
            let rho = d.at(zi + 0.5 * (ua + ub));
            (uu * rho, u1 * rho)
        }
    };
    // x − zj = (x − zi) + (zi − zj).
    (uu + outer(u1, w), uu)
}

/// Parameter intervals of the segment p–q inside the domain (written into `out`; `ts` is
/// scratch for the crossing parameters).
fn inside_parts(bnd: &Boundary, p: DVec2, q: DVec2, out: &mut Vec<(f64, f64)>, ts: &mut Vec<f64>) {
    out.clear();
    // Nothing lies outside the boundary's box: clip to it first (Liang–Barsky).
    let d = q - p;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (pk, dk, lo, hi) in [
        (p.x, d.x, bnd.lo.x, bnd.hi.x),
        (p.y, d.y, bnd.lo.y, bnd.hi.y),
    ] {
        if dk == 0.0 {
            if pk < lo || pk > hi {
                return;
            }
        } else {
            let (a, b) = ((lo - pk) / dk, (hi - pk) / dk);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
    }
    if t0 >= t1 {
        return;
    }
    let (a, b) = (p + d * t0, p + d * t1);
    let (lo, hi) = (a.min(b), a.max(b));
    if bnd.box_inside(lo, hi) {
        out.push((t0, t1));
        return;
    }
    ts.clear();
    ts.extend([t0, t1]);
    // Only the squares the segment passes: a Voronoi edge of a shore generator can run far
    // across land, and its bounding box then holds thousands of squares.
    bnd.edges_along(a, b, |e| {
        let (ea, eb) = (bnd.a[e as usize], bnd.b[e as usize]);
        let (r, s) = (d, eb - ea);
        let den = r.perp_dot(s);
        if den != 0.0 {
            let t = (ea - p).perp_dot(s) / den;
            let u = (ea - p).perp_dot(r) / den;
            if (0.0..=1.0).contains(&u) && t > t0 && t < t1 {
                ts.push(t);
            }
        }
    });
    ts.sort_by(f64::total_cmp);
    ts.dedup();
    for w in ts.windows(2) {
        if w[1] > w[0] && bnd.inside(p + d * (0.5 * (w[0] + w[1]))) {
            match out.last_mut() {
                Some(last) if last.1 == w[0] => last.1 = w[1],
                _ => out.push((w[0], w[1])),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cells::clipped_cells;
    use geometry::{Region, Rng};

    /// Gradient of the energy: 2 m_i (z_i − c_i).
    fn gradient(points: &[DVec2], domain: &Polygon, density: &Density) -> Vec<DVec2> {
        let del = Delaunay::new(points);
        let cells = clipped_cells(points, &del, domain, density);
        points
            .iter()
            .zip(&cells.cells)
            .map(|(z, c)| 2.0 * c.mass * (*z - c.mass_centroid))
            .collect()
    }

    /// The Hessian agrees with central differences of the gradient, also for cells cut by the
    /// boundary of a region with a hole; with a density to the accuracy of taking ρ at each
    /// edge's midpoint.
    #[test]
    fn matches_finite_differences_of_the_gradient() {
        let graded = Density::Function(std::sync::Arc::new(|p: DVec2| {
            (0.8 * p.x + 0.5 * p.y).exp()
        }));
        for (name, density, tol) in [
            ("circle", Density::Uniform, 1e-4),
            ("lake", Density::Uniform, 1e-4),
            ("annulus", Density::Uniform, 1e-4),
            // ρ varies by 10 % across a cell here; Simpson's rule on ρ gave 4e-4 and the
            // midpoint gives 3e-2, where ignoring ρ would be off by its whole variation.
            ("circle", graded.clone(), 5e-2),
            ("annulus", graded, 5e-2),
        ] {
            let region = Region::builtin(name).unwrap();
            let domain = region.polygonize(1e-4);
            let (lo, hi) = region.bbox();
            let mut rng = Rng::new(3);
            let mut pts = Vec::new();
            while pts.len() < 300 {
                let p = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
                if region.signed_distance(p) < 0.0 {
                    pts.push(p);
                }
            }
            let del = Delaunay::new(&pts);
            let cells = clipped_cells(&pts, &del, &domain, &density);
            let mut h = BlockMatrix::default();
            energy_hessian(&del, &domain, &density, &cells, &mut h);
            assert_eq!(h.rows(), pts.len());
            let scale = (hi - lo).length() * 1e-7;
            let mut worst: f64 = 0.0;
            let mut norm: f64 = 0.0;
            for j in (0..pts.len()).step_by(7) {
                for axis in [DVec2::X, DVec2::Y] {
                    let (mut a, mut b) = (pts.clone(), pts.clone());
                    a[j] += axis * scale;
                    b[j] -= axis * scale;
                    let (ga, gb) = (
                        gradient(&a, &domain, &density),
                        gradient(&b, &domain, &density),
                    );
                    let vj = del.vertex_of_point[j];
                    for i in 0..pts.len() {
                        let fd = (ga[i] - gb[i]) / (2.0 * scale);
                        let vi = del.vertex_of_point[i] as usize;
                        let an = h.get(vi, vj as usize) * axis;
                        worst = worst.max((fd - an).length());
                        norm = norm.max(fd.length());
                    }
                }
            }
            assert!(
                worst < tol * norm,
                "{name}: Hessian differs from finite differences by {worst:e} (scale {norm:e})"
            );
        }
    }

    /// The matrix is symmetric: block (i, j) is the transpose of block (j, i).
    #[test]
    fn is_symmetric() {
        let region = Region::builtin("pie_hole").unwrap();
        let domain = region.polygonize(1e-4);
        let pts: Vec<DVec2> = {
            let (lo, hi) = region.bbox();
            let mut rng = Rng::new(8);
            std::iter::repeat_with(|| DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y)))
                .filter(|p| region.signed_distance(*p) < 0.0)
                .take(500)
                .collect()
        };
        let del = Delaunay::new(&pts);
        let cells = clipped_cells(&pts, &del, &domain, &Density::Uniform);
        let mut h = BlockMatrix::default();
        energy_hessian(&del, &domain, &Density::Uniform, &cells, &mut h);
        let find = |i: usize, j: usize| {
            (h.row_start[i]..h.row_start[i + 1])
                .find(|&k| h.col[k] as usize == j)
                .map(|k| h.block[k].as_dmat2())
        };
        for i in 0..h.rows() {
            for k in h.row_start[i]..h.row_start[i + 1] {
                let j = h.col[k] as usize;
                assert_ne!(i, j, "the diagonal is kept apart");
                let back = find(j, i).expect("neighbour relation is symmetric");
                let diff = (h.block[k].as_dmat2() - back.transpose()).abs_diff_eq(
                    DMat2::ZERO,
                    1e-6 * back
                        .abs()
                        .to_cols_array()
                        .iter()
                        .fold(0.0, |m: f64, x| m.max(*x)),
                );
                assert!(diff, "block ({i},{j}) is not the transpose of ({j},{i})");
            }
        }
    }

    /// The rows of an active set are the full Hessian's rows restricted to the set's columns:
    /// every block and diagonal, near ∂Ω (a hole) and inside, with ρ ≡ 1 and with a density.
    #[test]
    fn active_rows_are_the_full_hessian_restricted() {
        let graded = Density::Function(std::sync::Arc::new(|p: DVec2| (0.8 * p.x).exp()));
        for density in [Density::Uniform, graded] {
            let region = Region::builtin("pie_hole").unwrap();
            let domain = region.polygonize(1e-4);
            let (lo, hi) = region.bbox();
            let mut rng = Rng::new(4);
            let pts: Vec<DVec2> =
                std::iter::repeat_with(|| DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y)))
                    .filter(|p| region.signed_distance(*p) < 0.0)
                    .take(1500)
                    .collect();
            let del = Delaunay::new(&pts);
            let cells = clipped_cells(&pts, &del, &domain, &density);
            let mut full = BlockMatrix::default();
            energy_hessian(&del, &domain, &density, &cells, &mut full);
            // A cluster (the vertices nearest one point) and scattered vertices.
            let centre = pts[0];
            let mut rows: Vec<u32> = (0..del.num_vertices() as u32)
                .filter(|&v| {
                    let p = del.pos[v as usize];
                    p.distance(centre) < 0.4 || v % 11 == 0
                })
                .collect();
            rows.sort_unstable();
            assert!(rows.len() > 600, "{} rows", rows.len());
            let grid = DomainGrid::new(&domain, del.num_vertices());
            let mut part = BlockMatrix::default();
            energy_hessian_rows(&del, &grid, &density, &cells, &rows, &mut part);
            let close = |a: DMat2, b: DMat2, tol: f64| {
                let scale = b
                    .abs()
                    .to_cols_array()
                    .iter()
                    .fold(1e-300, |m: f64, x| m.max(*x));
                (a - b)
                    .abs()
                    .to_cols_array()
                    .iter()
                    .all(|x| *x <= tol * scale)
            };
            let mut shared = 0;
            for (r, &v) in rows.iter().enumerate() {
                let v = v as usize;
                assert!(close(part.diag[r], full.diag[v], 1e-9), "diagonal of {v}");
                let mut expected: Vec<(u32, DMat2)> = (full.row_start[v]..full.row_start[v + 1])
                    .filter_map(|k| {
                        let c = rows.binary_search(&full.col[k]).ok()?;
                        Some((c as u32, full.block[k].as_dmat2()))
                    })
                    .collect();
                let mut got: Vec<(u32, DMat2)> = (part.row_start[r]..part.row_start[r + 1])
                    .map(|k| (part.col[k], part.block[k].as_dmat2()))
                    .collect();
                expected.sort_by_key(|e| e.0);
                got.sort_by_key(|e| e.0);
                assert_eq!(got.len(), expected.len(), "columns of {v}");
                for ((c, a), (d, b)) in got.iter().zip(&expected) {
                    assert_eq!(c, d);
                    assert!(close(*a, *b, 1e-5), "block ({v}, {c})");
                }
                shared += got.len();
            }
            assert!(shared > 2 * rows.len(), "{shared} blocks between rows");
        }
    }
}
