//! A uniform grid over the current boundary subsegments, answering "is this point inside the
//! polygon of subsegments?" by casting a ray to the right (even-odd rule) through one grid row,
//! and "which segments come near this point?" by its cell.
use geometry::DVec2;

/// Unordered subsegment key (smaller vertex index first).
pub(crate) type SegKey = (u32, u32);

pub(crate) struct SegGrid {
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<SegKey>>,
}

impl SegGrid {
    /// A grid over the box `lo..hi` with about `target_cells` cells.
    pub(crate) fn new(lo: DVec2, hi: DVec2, target_cells: usize) -> SegGrid {
        let size = (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
        let cell = (size.x * size.y / target_cells.max(1) as f64)
            .sqrt()
            .max(size.max_element() / 4096.0);
        let nx = ((size.x / cell).ceil() as usize).max(1);
        let ny = ((size.y / cell).ceil() as usize).max(1);
        SegGrid {
            origin: lo,
            cell,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
        }
    }

    fn col(&self, x: f64) -> usize {
        (((x - self.origin.x) / self.cell).floor().max(0.0) as usize).min(self.nx - 1)
    }

    fn row(&self, y: f64) -> usize {
        (((y - self.origin.y) / self.cell).floor().max(0.0) as usize).min(self.ny - 1)
    }

    fn span(&self, a: DVec2, b: DVec2) -> (usize, usize, usize, usize) {
        let (lo, hi) = (a.min(b), a.max(b));
        (
            self.col(lo.x),
            self.col(hi.x),
            self.row(lo.y),
            self.row(hi.y),
        )
    }

    pub(crate) fn insert(&mut self, key: SegKey, a: DVec2, b: DVec2) {
        let (c0, c1, r0, r1) = self.span(a, b);
        for r in r0..=r1 {
            for c in c0..=c1 {
                self.cells[r * self.nx + c].push(key);
            }
        }
    }

    pub(crate) fn remove(&mut self, key: SegKey, a: DVec2, b: DVec2) {
        let (c0, c1, r0, r1) = self.span(a, b);
        for r in r0..=r1 {
            for c in c0..=c1 {
                self.cells[r * self.nx + c].retain(|k| *k != key);
            }
        }
    }

    /// The keys in the cell that holds `p` (the nearest cell for a point outside the grid).
    pub(crate) fn near(&self, p: DVec2) -> &[SegKey] {
        &self.cells[self.row(p.y) * self.nx + self.col(p.x)]
    }

    /// Even-odd test of `p` against the subsegments; `pos` gives vertex coordinates.
    /// A crossing is counted only in the grid cell that holds its x-coordinate, so a
    /// subsegment spanning several cells of the row is counted once.
    pub(crate) fn contains(&self, p: DVec2, pos: impl Fn(u32) -> DVec2) -> bool {
        let lo = self.origin;
        let hi = lo + DVec2::new(self.nx as f64, self.ny as f64) * self.cell;
        if p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y {
            return false;
        }
        let r = self.row(p.y);
        let mut inside = false;
        for c in self.col(p.x)..self.nx {
            for &(i, j) in &self.cells[r * self.nx + c] {
                let (a, b) = (pos(i), pos(j));
                if (a.y > p.y) != (b.y > p.y) {
                    let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
                    if x > p.x && self.col(x) == c {
                        inside = !inside;
                    }
                }
            }
        }
        inside
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::{Region, Rng};

    /// The grid's even-odd test agrees with `Polygon::contains` on the lake's 101 edges.
    #[test]
    fn agrees_with_polygon_contains() {
        let region = Region::builtin("lake").unwrap();
        let poly = region.polygonize(1e-9);
        let pts: Vec<DVec2> = poly
            .rings
            .iter()
            .flat_map(|r| r.points.iter().copied())
            .collect();
        let (lo, hi) = poly.bbox();
        let mut grid = SegGrid::new(lo, hi, 400);
        let mut base = 0u32;
        for r in &poly.rings {
            let n = r.points.len() as u32;
            for i in 0..n {
                let (a, b) = (base + i, base + (i + 1) % n);
                grid.insert((a.min(b), a.max(b)), pts[a as usize], pts[b as usize]);
            }
            base += n;
        }
        let mut rng = Rng::new(3);
        let mut inside = 0;
        for _ in 0..20_000 {
            let p = DVec2::new(
                rng.range(lo.x - 5.0, hi.x + 5.0),
                rng.range(lo.y - 5.0, hi.y + 5.0),
            );
            let want = poly.contains(p);
            assert_eq!(grid.contains(p, |v| pts[v as usize]), want, "{p}");
            inside += want as usize;
        }
        assert!(inside > 5_000, "{inside}");
        // Removing the island's edges puts its interior inside.
        let island = &poly.rings[1];
        let off = poly.rings[0].points.len() as u32;
        let n = island.points.len() as u32;
        for i in 0..n {
            let (a, b) = (off + i, off + (i + 1) % n);
            grid.remove((a.min(b), a.max(b)), pts[a as usize], pts[b as usize]);
        }
        let c = island.points.iter().copied().sum::<DVec2>() / n as f64;
        assert!(!poly.contains(c) && grid.contains(c, |v| pts[v as usize]));
    }
}
