//! Exact nearest-neighbour queries on a uniform bucket grid.
//!
//! Used for γ_k (nearest other point) and for assigning Monte-Carlo samples to their nearest
//! generator. Unlike the Delaunay triangulation, which merges duplicate points, the grid sees
//! every input point, so a duplicated point correctly gets γ_k = 0.
use geometry::DVec2;
use rayon::prelude::*;

/// Points bucketed into a grid of roughly one point per cell (CSR layout).
pub(crate) struct PointGrid<'a> {
    points: &'a [DVec2],
    origin: DVec2,
    cell: f64,
    nx: i64,
    ny: i64,
    /// `start[c]..start[c + 1]` indexes `items` for grid cell `c = iy * nx + ix`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl<'a> PointGrid<'a> {
    /// Bucket `points` (all finite, at least one).
    pub(crate) fn new(points: &'a [DVec2]) -> Self {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for p in points {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let n = points.len().max(1) as f64;
        let ext = hi - lo;
        // ~1 point per cell; the second term bounds the cell count for (nearly) collinear sets.
        let mut cell = (ext.x * ext.y / n).sqrt().max(ext.x.max(ext.y) / n);
        if !(cell > 0.0 && cell.is_finite()) {
            cell = 1.0; // all points coincide
        }
        let nx = (ext.x / cell) as i64 + 1;
        let ny = (ext.y / cell) as i64 + 1;
        let mut grid = PointGrid {
            points,
            origin: lo,
            cell,
            nx,
            ny,
            start: vec![0; (nx * ny) as usize + 1],
            items: vec![0; points.len()],
        };
        let ids: Vec<usize> = points.iter().map(|p| grid.flat(grid.coords(*p))).collect();
        for &c in &ids {
            grid.start[c + 1] += 1;
        }
        for c in 0..(nx * ny) as usize {
            grid.start[c + 1] += grid.start[c];
        }
        let mut fill = grid.start.clone();
        for (i, &c) in ids.iter().enumerate() {
            grid.items[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        grid
    }

    /// Unclamped integer cell coordinates of `p`.
    fn coords(&self, p: DVec2) -> (i64, i64) {
        let q = (p - self.origin) / self.cell;
        (q.x.floor() as i64, q.y.floor() as i64)
    }

    /// Flat index of an in-range (clamped) cell.
    fn flat(&self, (ix, iy): (i64, i64)) -> usize {
        (iy.clamp(0, self.ny - 1) * self.nx + ix.clamp(0, self.nx - 1)) as usize
    }

    /// The point nearest to `p` other than `skip`, with its squared distance. Ties go to the
    /// lower index, so the answer does not depend on the visiting order.
    pub(crate) fn nearest(&self, p: DVec2, skip: Option<usize>) -> Option<(usize, f64)> {
        let (cx, cy) = self.coords(p);
        let mut best: Option<(usize, f64)> = None;
        let consider = |cell: usize, best: &mut Option<(usize, f64)>| {
            for &i in &self.items[self.start[cell] as usize..self.start[cell + 1] as usize] {
                let i = i as usize;
                if Some(i) == skip {
                    continue;
                }
                let d2 = (self.points[i] - p).length_squared();
                let better = match *best {
                    None => true,
                    Some((j, b)) => d2 < b || (d2 == b && i < j),
                };
                if better {
                    *best = Some((i, d2));
                }
            }
        };
        // First ring that can touch the grid.
        let gap = |c: i64, n: i64| {
            if c < 0 {
                -c
            } else if c >= n {
                c - n + 1
            } else {
                0
            }
        };
        let r0 = gap(cx, self.nx).max(gap(cy, self.ny));
        let mut r = r0;
        loop {
            let (x0, x1) = ((cx - r).max(0), (cx + r).min(self.nx - 1));
            let (y0, y1) = ((cy - r).max(0), (cy + r).min(self.ny - 1));
            if x0 <= x1 && y0 <= y1 {
                for y in [cy - r, cy + r] {
                    if (0..self.ny).contains(&y) {
                        for x in x0..=x1 {
                            consider((y * self.nx + x) as usize, &mut best);
                        }
                    }
                    if r == 0 {
                        break;
                    }
                }
                for x in [cx - r, cx + r] {
                    if r > 0 && (0..self.nx).contains(&x) {
                        for y in (cy - r + 1).max(0)..=(cy + r - 1).min(self.ny - 1) {
                            consider((y * self.nx + x) as usize, &mut best);
                        }
                    }
                }
            }
            // Every point in a ring beyond r is at least r cells away from p.
            if let Some((_, d2)) = best {
                let bound = r as f64 * self.cell;
                if d2 <= bound * bound {
                    return best;
                }
            }
            let covers =
                cx - r <= 0 && cy - r <= 0 && cx + r >= self.nx - 1 && cy + r >= self.ny - 1;
            if covers {
                return best;
            }
            r += 1;
        }
    }
}

/// γ_k = min_{j≠k} |z_k − z_j| for every point (0 for a duplicated point). Needs ≥ 2 points.
pub(crate) fn nearest_neighbor_distances(points: &[DVec2]) -> Vec<f64> {
    let grid = PointGrid::new(points);
    (0..points.len())
        .into_par_iter()
        .map(|k| {
            grid.nearest(points[k], Some(k))
                .map_or(f64::INFINITY, |(_, d2)| d2.sqrt())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::Rng;

    fn brute(points: &[DVec2], p: DVec2, skip: Option<usize>) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (i, q) in points.iter().enumerate() {
            if Some(i) == skip {
                continue;
            }
            let d2 = (*q - p).length_squared();
            if !matches!(best, Some((_, b)) if b <= d2) {
                best = Some((i, d2));
            }
        }
        best
    }

    #[test]
    fn grid_matches_brute_force() {
        let mut rng = Rng::new(11);
        for &(n, spread) in &[(2usize, 1.0), (7, 1.0), (300, 1.0), (300, 1e-9), (200, 1e6)] {
            // A clustered set: half uniform, half in a small blob, plus a duplicate.
            let mut pts: Vec<DVec2> = (0..n)
                .map(|i| {
                    let s = if i % 2 == 0 { spread } else { spread * 0.01 };
                    DVec2::new(rng.range(0.0, s), rng.range(0.0, 3.0 * s))
                })
                .collect();
            pts.push(pts[0]);
            let grid = PointGrid::new(&pts);
            for k in 0..pts.len() {
                let a = grid.nearest(pts[k], Some(k)).unwrap();
                let b = brute(&pts, pts[k], Some(k)).unwrap();
                assert_eq!(a.1, b.1, "n={n} k={k}");
            }
            // Queries far outside the grid, too.
            for _ in 0..50 {
                let q = DVec2::new(rng.range(-5.0, 5.0) * spread, rng.range(-5.0, 5.0) * spread);
                assert_eq!(
                    grid.nearest(q, None).unwrap(),
                    brute(&pts, q, None).unwrap()
                );
            }
            let g = nearest_neighbor_distances(&pts);
            assert_eq!(g[0], 0.0);
            assert_eq!(g[pts.len() - 1], 0.0);
            for (k, &d) in g.iter().enumerate() {
                let nearest = brute(&pts, pts[k], Some(k)).unwrap().1.sqrt();
                assert_eq!(d, nearest, "n={n} k={k}");
            }
        }
    }

    #[test]
    fn collinear_and_coincident_sets() {
        let line: Vec<DVec2> = (0..50).map(|i| DVec2::new(i as f64 * 0.1, 2.0)).collect();
        let g = nearest_neighbor_distances(&line);
        assert!(g.iter().all(|&d| (d - 0.1).abs() < 1e-12));
        let same = vec![DVec2::new(1.0, 1.0); 5];
        assert!(nearest_neighbor_distances(&same).iter().all(|&d| d == 0.0));
    }
}
