//! A straight-edged approximation of a region whose edges remember which boundary piece
//! they came from; this is what Voronoi cells are clipped against.
use crate::predicates::{point_in_ring, ring_signed_area};
use crate::types::PieceId;
use glam::DVec2;

/// One closed ring (implicitly closed: the last point joins the first).
#[derive(Clone, Debug, PartialEq)]
pub struct Ring {
    /// Vertices; outer ring CCW, hole rings CW.
    pub points: Vec<DVec2>,
    /// `pieces[i]` is the boundary piece of the edge `points[i] → points[i+1]`.
    pub pieces: Vec<PieceId>,
    /// Index of the region loop this ring approximates.
    pub loop_index: usize,
    /// True for a hole.
    pub hole: bool,
}

/// Outer ring first, then holes. Produced by `Region::polygonize` and `Region::expand`.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// The rings.
    pub rings: Vec<Ring>,
}

impl Polygon {
    /// Area (outer minus holes), by the shoelace formula.
    pub fn area(&self) -> f64 {
        self.rings.iter().map(|r| ring_signed_area(&r.points)).sum()
    }

    /// Area centroid.
    pub fn centroid(&self) -> DVec2 {
        let (mut a, mut c) = (0.0, DVec2::ZERO);
        for r in &self.rings {
            let n = r.points.len();
            for i in 0..n {
                let (p, q) = (r.points[i], r.points[(i + 1) % n]);
                let w = p.perp_dot(q);
                a += w;
                c += (p + q) * w;
            }
        }
        c / (3.0 * a)
    }

    /// Even-odd point-in-polygon over all rings.
    pub fn contains(&self, p: DVec2) -> bool {
        self.rings
            .iter()
            .fold(false, |inside, r| inside != point_in_ring(p, &r.points))
    }

    /// Axis-aligned bounding box (min, max).
    pub fn bbox(&self) -> (DVec2, DVec2) {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for p in self.rings.iter().flat_map(|r| &r.points) {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (lo, hi)
    }

    /// Every edge as (a, b, piece).
    pub fn edges(&self) -> impl Iterator<Item = (DVec2, DVec2, PieceId)> + '_ {
        self.rings.iter().flat_map(|r| {
            let n = r.points.len();
            (0..n).map(move |i| (r.points[i], r.points[(i + 1) % n], r.pieces[i]))
        })
    }
}
