//! A uniform grid over the domain's boundary edges: which edges are near a box, whether a
//! boundary-free square lies inside the domain, and the winding number of a point.
use geometry::predicates::ring_signed_area;
use geometry::{DVec2, PieceId, Polygon};

/// Boxes at least this many squares wide visit only the non-empty squares of each row.
const WIDE_ROW: usize = 16;

/// The domain's edges and a uniform grid indexing them.
pub(crate) struct Boundary {
    /// Edge start points (absolute coordinates).
    pub a: Vec<DVec2>,
    /// Edge end points.
    pub b: Vec<DVec2>,
    /// Boundary piece of each edge.
    pub piece: Vec<PieceId>,
    /// Ring of each edge.
    pub ring: Vec<u32>,
    /// Edge index range [start, end) of each ring.
    pub ring_range: Vec<(u32, u32)>,
    /// Lower-left corner of the grid (also of the box every cell is first clipped to).
    pub lo: DVec2,
    /// Upper-right corner.
    pub hi: DVec2,
    inv_s: f64,
    nx: usize,
    ny: usize,
    /// Slack added when registering edges so rounding never misses a square.
    slack: f64,
    /// CSR lists of edges per square.
    start: Vec<u32>,
    items: Vec<u32>,
    /// Summed-area table of non-empty squares, (nx+1) × (ny+1).
    sat: Vec<u32>,
    /// CSR lists of the columns of non-empty squares per row, in increasing order
    /// ([`Boundary::busy_row`]): the winding number's ray and the rows of a wide box visit
    /// only these.
    busy_start: Vec<u32>,
    busy: Vec<u32>,
    /// For squares without edges: inside the domain.
    inside: Vec<bool>,
}

impl Boundary {
    /// Index the rings of `domain` (rings with fewer than 3 points are ignored) on a grid of
    /// about `target_squares` squares. `None` if the domain has no ring.
    pub fn new(domain: &Polygon, target_squares: usize) -> Option<Boundary> {
        let (mut a, mut b, mut piece, mut ring, mut ring_range) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for r in &domain.rings {
            let n = r.points.len();
            if n < 3 || r.points.iter().any(|p| !p.is_finite()) {
                continue;
            }
            let start = a.len() as u32;
            // Outer rings must run CCW and holes CW (positive winding inside Ω): a ring given
            // the other way round is traversed backwards.
            let reverse = (ring_signed_area(&r.points) > 0.0) == r.hole;
            for k in 0..n {
                let i = if reverse { n - 1 - k } else { k };
                let (p, q) = (r.points[i], r.points[(i + 1) % n]);
                let (p, q) = if reverse { (q, p) } else { (p, q) };
                a.push(p);
                b.push(q);
                piece.push(r.pieces.get(i).copied().unwrap_or(0));
                ring.push(ring_range.len() as u32);
                lo = lo.min(p);
                hi = hi.max(p);
            }
            ring_range.push((start, a.len() as u32));
        }
        if a.is_empty() {
            return None;
        }
        // A margin so that cells are clipped to a box strictly containing the domain.
        let ext = (hi - lo).max_element().max(f64::MIN_POSITIVE);
        let margin = 0.01 * ext;
        lo -= DVec2::splat(margin);
        hi += DVec2::splat(margin);
        let size = hi - lo;
        let target = target_squares.clamp(64, 1 << 22) as f64;
        let s = (size.x * size.y / target)
            .sqrt()
            .max(size.max_element() / 2048.0);
        let nx = ((size.x / s).ceil() as usize).clamp(1, 2048);
        let ny = ((size.y / s).ceil() as usize).clamp(1, 2048);
        let hi = lo + DVec2::new(nx as f64, ny as f64) * s;
        let mut bnd = Boundary {
            a,
            b,
            piece,
            ring,
            ring_range,
            lo,
            hi,
            inv_s: 1.0 / s,
            nx,
            ny,
            slack: 1e-9 * ext,
            start: Vec::new(),
            items: Vec::new(),
            sat: Vec::new(),
            busy_start: Vec::new(),
            busy: Vec::new(),
            inside: Vec::new(),
        };
        bnd.build_index();
        bnd.build_inside();
        Some(bnd)
    }

    fn col(&self, x: f64) -> usize {
        (((x - self.lo.x) * self.inv_s).max(0.0) as usize).min(self.nx - 1)
    }

    fn row(&self, y: f64) -> usize {
        (((y - self.lo.y) * self.inv_s).max(0.0) as usize).min(self.ny - 1)
    }

    /// Every square the segment a–b passes within `slack` of.
    fn squares_of_segment(&self, a: DVec2, b: DVec2, mut f: impl FnMut(usize)) {
        let s = 1.0 / self.inv_s;
        let (ymin, ymax) = (a.y.min(b.y), a.y.max(b.y));
        for r in self.row(ymin - self.slack)..=self.row(ymax + self.slack) {
            let y0 = (self.lo.y + r as f64 * s - self.slack).max(ymin);
            let y1 = (self.lo.y + (r + 1) as f64 * s + self.slack).min(ymax);
            let (x0, x1) = if a.y == b.y || y0 >= y1 {
                (a.x.min(b.x), a.x.max(b.x))
            } else {
                let slope = (b.x - a.x) / (b.y - a.y);
                let xa = a.x + (y0 - a.y) * slope;
                let xb = a.x + (y1 - a.y) * slope;
                (xa.min(xb), xa.max(xb))
            };
            for c in self.col(x0 - self.slack)..=self.col(x1 + self.slack) {
                f(r * self.nx + c);
            }
        }
    }

    fn build_index(&mut self) {
        let nsq = self.nx * self.ny;
        let mut count = vec![0u32; nsq + 1];
        for e in 0..self.a.len() {
            self.squares_of_segment(self.a[e], self.b[e], |q| count[q] += 1);
        }
        let mut start = vec![0u32; nsq + 1];
        for q in 0..nsq {
            start[q + 1] = start[q] + count[q];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[nsq] as usize];
        for e in 0..self.a.len() {
            self.squares_of_segment(self.a[e], self.b[e], |q| {
                items[fill[q] as usize] = e as u32;
                fill[q] += 1;
            });
        }
        let w = self.nx + 1;
        let mut sat = vec![0u32; w * (self.ny + 1)];
        for j in 0..self.ny {
            for i in 0..self.nx {
                let q = j * self.nx + i;
                let occupied = u32::from(start[q + 1] > start[q]);
                sat[(j + 1) * w + i + 1] =
                    occupied + sat[j * w + i + 1] + sat[(j + 1) * w + i] - sat[j * w + i];
            }
        }
        let mut busy_start = Vec::with_capacity(self.ny + 1);
        let mut busy = Vec::new();
        busy_start.push(0);
        for r in 0..self.ny {
            busy.extend((0..self.nx as u32).filter(|&c| {
                let q = r * self.nx + c as usize;
                start[q + 1] > start[q]
            }));
            busy_start.push(busy.len() as u32);
        }
        self.start = start;
        self.items = items;
        self.sat = sat;
        self.busy_start = busy_start;
        self.busy = busy;
    }

    /// Inside flags of the empty squares: the winding number at the square's centre row,
    /// accumulated from the left along each row of squares.
    fn build_inside(&mut self) {
        let s = 1.0 / self.inv_s;
        let mut inside = vec![false; self.nx * self.ny];
        for r in 0..self.ny {
            let y = self.lo.y + (r as f64 + 0.5) * s;
            let mut w = 0i32;
            for c in 0..self.nx {
                let q = r * self.nx + c;
                if self.start[q + 1] == self.start[q] {
                    inside[q] = w > 0;
                } else {
                    w += self.crossings_in_square(q, c, DVec2::new(f64::INFINITY, y));
                }
            }
        }
        self.inside = inside;
    }

    /// Signed crossings of the horizontal line y = p.y by edges of square `q` (column `c`),
    /// left of p.x, counted only in the column where the crossing lies (so each once).
    /// Downward edges count +1: seen from a point inside a CCW ring, the ring's left side runs
    /// downwards.
    fn crossings_in_square(&self, q: usize, c: usize, p: DVec2) -> i32 {
        let mut w = 0;
        for &e in &self.items[self.start[q] as usize..self.start[q + 1] as usize] {
            let (a, b) = (self.a[e as usize], self.b[e as usize]);
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
                if x < p.x && self.col(x) == c {
                    w += if b.y < a.y { 1 } else { -1 };
                }
            }
        }
        w
    }

    /// Winding number of the boundary (all rings) around `p` (1 inside the domain, 0 outside,
    /// for a point that is not on the boundary), by a ray to the left through one grid row.
    pub fn winding(&self, p: DVec2) -> i32 {
        let r = self.row(p.y);
        let cmax = self.col(p.x);
        // Squares without edges add nothing: only the row's non-empty ones are visited.
        let busy = self.busy_row(r);
        busy.iter()
            .map(|&c| c as usize)
            .take_while(|&c| c <= cmax)
            .map(|c| self.crossings_in_square(r * self.nx + c, c, p))
            .sum()
    }

    /// Inside flag of `p`: from its square when that square has no edges, else by a ray walk.
    /// For a point not on the boundary.
    pub fn inside(&self, p: DVec2) -> bool {
        let q = self.row(p.y) * self.nx + self.col(p.x);
        if self.start[q + 1] == self.start[q] && p.cmpge(self.lo).all() && p.cmple(self.hi).all() {
            self.inside[q]
        } else {
            self.winding(p) > 0
        }
    }

    /// Square index range (inclusive) overlapped by the box [lo, hi]; `None` if the box is not
    /// entirely within the grid.
    fn square_range(&self, lo: DVec2, hi: DVec2) -> Option<(usize, usize, usize, usize)> {
        if !(lo.x >= self.lo.x && lo.y >= self.lo.y && hi.x <= self.hi.x && hi.y <= self.hi.y) {
            return None;
        }
        Some((
            self.col(lo.x),
            self.row(lo.y),
            self.col(hi.x),
            self.row(hi.y),
        ))
    }

    /// True if the box [lo, hi] (absolute) lies in boundary-free squares inside the domain.
    pub fn box_inside(&self, lo: DVec2, hi: DVec2) -> bool {
        let Some((i0, j0, i1, j1)) =
            self.square_range(lo - DVec2::splat(self.slack), hi + DVec2::splat(self.slack))
        else {
            return false;
        };
        let w = self.nx + 1;
        let s = &self.sat;
        let occupied =
            s[(j1 + 1) * w + i1 + 1] + s[j0 * w + i0] - s[j0 * w + i1 + 1] - s[(j1 + 1) * w + i0];
        occupied == 0 && self.inside[j0 * self.nx + i0]
    }

    /// Calls `f` with every edge registered in a square overlapping [lo, hi] (possibly several
    /// times). The box is clamped to the grid.
    pub fn edges_near(&self, lo: DVec2, hi: DVec2, mut f: impl FnMut(u32)) {
        let (i0, j0, i1, j1) = (
            self.col(lo.x),
            self.row(lo.y),
            self.col(hi.x),
            self.row(hi.y),
        );
        let mut square = |q: usize| {
            for &e in &self.items[self.start[q] as usize..self.start[q + 1] as usize] {
                f(e);
            }
        };
        for j in j0..=j1 {
            if i1 - i0 < WIDE_ROW {
                (i0..=i1).for_each(|i| square(j * self.nx + i));
            } else {
                // A wide box (the convex cell of a generator on a shore facing land): only the
                // row's non-empty squares, in the same order.
                let busy = self.busy_row(j);
                let first = busy.partition_point(|&c| (c as usize) < i0);
                busy[first..]
                    .iter()
                    .map(|&c| c as usize)
                    .take_while(|&c| c <= i1)
                    .for_each(|c| square(j * self.nx + c));
            }
        }
    }

    /// Calls `f` with every edge registered in a square that the segment a–b passes (within
    /// the registration slack), possibly more than once: every edge that meets the segment is
    /// among them. Where the segment runs diagonally across many squares, far fewer squares
    /// than [`Boundary::edges_near`] on its bounding box.
    pub fn edges_along(&self, a: DVec2, b: DVec2, mut f: impl FnMut(u32)) {
        self.squares_of_segment(a, b, |q| {
            for &e in &self.items[self.start[q] as usize..self.start[q + 1] as usize] {
                f(e);
            }
        });
    }

    /// The columns of row `r`'s non-empty squares, in increasing order.
    fn busy_row(&self, r: usize) -> &[u32] {
        &self.busy[self.busy_start[r] as usize..self.busy_start[r + 1] as usize]
    }

    /// Number of edges.
    pub fn num_edges(&self) -> usize {
        self.a.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::Ring;

    fn square_with_hole() -> Polygon {
        let outer = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(4.0, 4.0),
            DVec2::new(0.0, 4.0),
        ];
        let hole = vec![
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 3.0),
            DVec2::new(3.0, 3.0),
            DVec2::new(3.0, 1.0),
        ];
        Polygon {
            rings: vec![
                Ring {
                    points: outer,
                    pieces: vec![0, 1, 2, 3],
                    loop_index: 0,
                    hole: false,
                },
                Ring {
                    points: hole,
                    pieces: vec![4; 4],
                    loop_index: 1,
                    hole: true,
                },
            ],
        }
    }

    #[test]
    fn winding_numbers_and_inside_flags() {
        let poly = square_with_hole();
        let bnd = Boundary::new(&poly, 400).unwrap();
        for (p, w) in [
            ((0.5, 0.5), 1),
            ((2.0, 2.0), 0),
            ((3.5, 2.0), 1),
            ((-0.5, 2.0), 0),
            ((4.01, 1.0), 0),
        ] {
            assert_eq!(bnd.winding(DVec2::new(p.0, p.1)), w, "{p:?}");
        }
        // Boundary-free boxes: inside the ring band, in the hole, outside.
        assert!(bnd.box_inside(DVec2::new(0.3, 0.3), DVec2::new(0.7, 0.7)));
        assert!(!bnd.box_inside(DVec2::new(1.7, 1.7), DVec2::new(2.3, 2.3)));
        assert!(bnd.box_inside(DVec2::new(0.3, 0.3), DVec2::new(1.2, 0.7)));
        assert!(!bnd.box_inside(DVec2::new(0.3, 0.3), DVec2::new(1.2, 1.2)));
        assert!(!bnd.box_inside(DVec2::new(-9.0, 0.3), DVec2::new(0.7, 0.7)));
    }

    /// The lake (many rings) polygonized, its box, and a grid of about `squares` squares on it.
    fn lake_grid(squares: usize) -> (Polygon, Boundary, DVec2, DVec2) {
        let region = geometry::Region::builtin("lake").unwrap();
        let poly = region.polygonize(1e-3 * region.diameter());
        let bnd = Boundary::new(&poly, squares).unwrap();
        let (lo, hi) = poly.bbox();
        (poly, bnd, lo, hi)
    }

    #[test]
    fn winding_numbers_agree_with_the_polygon_on_a_lake_with_islands() {
        // Many rings, so grid rows with many non-empty squares and empty ones between them.
        let mut rng = geometry::Rng::new(5);
        for target in [100, 10_000] {
            let (poly, bnd, lo, hi) = lake_grid(target);
            let (mut inside, mut outside) = (0, 0);
            for _ in 0..4000 {
                let p = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
                let w = bnd.winding(p);
                assert!(w == 0 || w == 1, "winding {w} at {p}");
                assert_eq!(w == 1, poly.contains(p), "at {p}");
                if w == 1 {
                    inside += 1;
                } else {
                    outside += 1;
                }
            }
            assert!(inside > 100 && outside > 100, "{inside} / {outside}");
        }
    }

    #[test]
    fn edges_along_a_segment_include_every_edge_it_crosses() {
        // Long segments across the lake and its islands, at every angle: each edge that meets
        // one (by a brute-force test over all edges) is reported, in far fewer squares than
        // the segment's bounding box holds.
        let (_, bnd, lo, hi) = lake_grid(100_000);
        let mut rng = geometry::Rng::new(9);
        let (mut along, mut in_box) = (0usize, 0usize);
        for _ in 0..300 {
            let p = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
            let q = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
            let mut seen = vec![false; bnd.num_edges()];
            bnd.edges_along(p, q, |e| {
                seen[e as usize] = true;
                along += 1;
            });
            bnd.edges_near(p.min(q), p.max(q), |_| in_box += 1);
            for (e, (&a, &b)) in bnd.a.iter().zip(&bnd.b).enumerate() {
                let side = |u: DVec2, v: DVec2, w: DVec2| (v - u).perp_dot(w - u);
                let crosses =
                    side(p, q, a) * side(p, q, b) <= 0.0 && side(a, b, p) * side(a, b, q) <= 0.0;
                assert!(
                    !crosses || seen[e],
                    "edge {e} crosses {p}–{q} but was not reported"
                );
            }
        }
        assert!(
            4 * along < in_box,
            "{along} edges along against {in_box} in the boxes"
        );
    }

    #[test]
    fn edges_near_a_wide_box_are_those_of_every_square_in_order() {
        // Boxes from a square wide to the whole lake: the same calls, in the same order, as a
        // walk over every square of the box.
        let (_, bnd, lo, hi) = lake_grid(100_000);
        let mut rng = geometry::Rng::new(11);
        let mut wide = 0;
        for round in 0..400 {
            let size = (hi - lo) * (0.001 + 0.999 * (round as f64 / 400.0));
            let a = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
            let b = a + size * DVec2::new(rng.uniform(), rng.uniform());
            let mut got = Vec::new();
            bnd.edges_near(a, b, |e| got.push(e));
            let mut every: Vec<u32> = Vec::new();
            for j in bnd.row(a.y)..=bnd.row(b.y) {
                for i in bnd.col(a.x)..=bnd.col(b.x) {
                    let q = j * bnd.nx + i;
                    every.extend(&bnd.items[bnd.start[q] as usize..bnd.start[q + 1] as usize]);
                }
            }
            assert_eq!(got, every, "box {a} – {b}");
            wide += usize::from(bnd.col(b.x) - bnd.col(a.x) >= WIDE_ROW);
        }
        assert!(wide > 100, "{wide} wide boxes");
    }

    #[test]
    fn every_square_a_segment_crosses_is_registered() {
        let poly = square_with_hole();
        let bnd = Boundary::new(&poly, 1000).unwrap();
        // Sample points along each edge: the square containing each must list the edge.
        for e in 0..bnd.num_edges() {
            for k in 0..=100 {
                let p = bnd.a[e].lerp(bnd.b[e], k as f64 / 100.0);
                let mut found = false;
                bnd.edges_near(p, p, |f| found |= f as usize == e);
                assert!(found, "edge {e} missing at {p}");
            }
        }
    }
}
