//! Candidate pairs of segments whose (padded) bounding boxes overlap, via a uniform grid.
//! Used to find self-intersections (validation) and offset-curve crossings (expansion).
use glam::DVec2;

/// Calls `f(i, j)` (i < j) once for every pair of segments whose bounding boxes, padded by
/// `pad`, overlap. Stops early when `f` returns false.
pub(crate) fn candidate_pairs(
    segs: &[(DVec2, DVec2)],
    pad: f64,
    mut f: impl FnMut(usize, usize) -> bool,
) {
    let n = segs.len();
    if n < 2 {
        return;
    }
    let boxes: Vec<(DVec2, DVec2)> = segs
        .iter()
        .map(|(a, b)| (a.min(*b) - pad, a.max(*b) + pad))
        .collect();
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for (l, h) in &boxes {
        lo = lo.min(*l);
        hi = hi.max(*h);
    }
    let ext = (hi - lo).max_element().max(f64::MIN_POSITIVE);
    // Cell size: the median segment extent, bounded so the grid has at most ~8n cells.
    let mut sizes: Vec<f64> = boxes.iter().map(|(l, h)| (*h - *l).max_element()).collect();
    let mid = n / 2;
    sizes.select_nth_unstable_by(mid, f64::total_cmp);
    let mut h = sizes[mid].max(ext / 4096.0);
    let cells = |h: f64| {
        (
            ((hi.x - lo.x) / h).floor() as usize + 1,
            ((hi.y - lo.y) / h).floor() as usize + 1,
        )
    };
    let (mut nx, mut ny) = cells(h);
    let cap = 8 * n + 64;
    if (nx as f64) * (ny as f64) > cap as f64 {
        h *= ((nx as f64) * (ny as f64) / cap as f64).sqrt() * 1.01;
        (nx, ny) = cells(h);
    }
    let cell_of = |p: DVec2| {
        let c = ((p - lo) / h).floor();
        (
            (c.x.max(0.0) as usize).min(nx - 1),
            (c.y.max(0.0) as usize).min(ny - 1),
        )
    };
    // Compressed cell lists.
    let mut count = vec![0u32; nx * ny + 1];
    let ranges: Vec<((usize, usize), (usize, usize))> = boxes
        .iter()
        .map(|(l, h)| (cell_of(*l), cell_of(*h)))
        .collect();
    for &((x0, y0), (x1, y1)) in &ranges {
        for y in y0..=y1 {
            for x in x0..=x1 {
                count[y * nx + x + 1] += 1;
            }
        }
    }
    for i in 1..count.len() {
        count[i] += count[i - 1];
    }
    let mut fill = count.clone();
    let mut list = vec![0u32; count[nx * ny] as usize];
    for (i, &((x0, y0), (x1, y1))) in ranges.iter().enumerate() {
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c = y * nx + x;
                list[fill[c] as usize] = i as u32;
                fill[c] += 1;
            }
        }
    }
    for cy in 0..ny {
        for cx in 0..nx {
            let c = cy * nx + cx;
            let items = &list[count[c] as usize..count[c + 1] as usize];
            for (k, &i) in items.iter().enumerate() {
                let (li, hi_) = boxes[i as usize];
                for &j in &items[k + 1..] {
                    let (lj, hj) = boxes[j as usize];
                    if li.x > hj.x || lj.x > hi_.x || li.y > hj.y || lj.y > hi_.y {
                        continue;
                    }
                    // Report each pair only in the cell holding the low corner of the overlap.
                    if cell_of(li.max(lj)) != (cx, cy) {
                        continue;
                    }
                    let (a, b) = if i < j { (i, j) } else { (j, i) };
                    if !f(a as usize, b as usize) {
                        return;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_every_overlapping_pair_once() {
        let mut rng = crate::rng::Rng::new(11);
        let segs: Vec<(DVec2, DVec2)> = (0..300)
            .map(|_| {
                let a = DVec2::new(rng.range(0.0, 10.0), rng.range(0.0, 10.0));
                let d = DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
                    * if rng.uniform() < 0.1 { 5.0 } else { 0.5 };
                (a, a + d)
            })
            .collect();
        let mut got = std::collections::HashSet::new();
        candidate_pairs(&segs, 0.0, |i, j| {
            assert!(got.insert((i, j)), "pair reported twice");
            true
        });
        for i in 0..segs.len() {
            for j in i + 1..segs.len() {
                let (li, hi) = (segs[i].0.min(segs[i].1), segs[i].0.max(segs[i].1));
                let (lj, hj) = (segs[j].0.min(segs[j].1), segs[j].0.max(segs[j].1));
                let overlap = !(li.x > hj.x || lj.x > hi.x || li.y > hj.y || lj.y > hi.y);
                assert_eq!(overlap, got.contains(&(i, j)), "{i} {j}");
            }
        }
    }
}
