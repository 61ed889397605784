//! Which segments of a planar straight-line graph (a Triangle `.poly`) bound the region and
//! which lie inside it, by Triangle's rule: the region is every face of the graph's plane
//! subdivision that a hole point does not eat, short of the unbounded face.
use crate::predicates::{point_in_ring, ring_signed_area};
use glam::DVec2;

/// Where a segment lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// The region on one side only: part of a boundary loop.
    Boundary,
    /// The region on both sides: a line inside it (an interface, a crack, an inclusion).
    Inside,
    /// The region on neither side (in a hole or outside): no triangle has it.
    Outside,
}

/// Each of `segments` (pairs of indices into `points`, no two equal, none crossing another)
/// classified against the faces of the subdivision they make, the faces holding a point of
/// `holes` removed.
pub(crate) fn classify(
    points: &[DVec2],
    segments: &[(usize, usize)],
    holes: &[DVec2],
) -> Vec<Side> {
    let m = segments.len();
    // Half-edge 2s runs from segments[s].0 to .1, 2s + 1 back.
    let from = |h: usize| {
        let (a, b) = segments[h / 2];
        if h % 2 == 0 {
            a
        } else {
            b
        }
    };
    let to = |h: usize| from(h ^ 1);
    // The half-edges leaving each vertex, counter-clockwise by angle.
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); points.len()];
    for h in 0..2 * m {
        out[from(h)].push(h);
    }
    let angle = |h: usize| {
        let d = points[to(h)] - points[from(h)];
        d.y.atan2(d.x)
    };
    for hs in &mut out {
        hs.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
    }
    let mut rank = vec![0; 2 * m];
    for hs in &out {
        for (k, &h) in hs.iter().enumerate() {
            rank[h] = k;
        }
    }
    // The face on each half-edge's left: after u → v, the half-edge leaving v just clockwise
    // of v → u.
    let next = |h: usize| {
        let v = to(h);
        let hs = &out[v];
        hs[(rank[h ^ 1] + hs.len() - 1) % hs.len()]
    };
    let mut face = vec![usize::MAX; 2 * m];
    let mut rings: Vec<Vec<usize>> = Vec::new();
    for h0 in 0..2 * m {
        if face[h0] != usize::MAX {
            continue;
        }
        let (f, mut h, mut ring) = (rings.len(), h0, Vec::new());
        while face[h] == usize::MAX {
            face[h] = f;
            ring.push(from(h));
            h = next(h);
        }
        rings.push(ring);
    }
    let polygon = |f: usize| -> Vec<DVec2> { rings[f].iter().map(|&v| points[v]).collect() };
    let area: Vec<f64> = (0..rings.len())
        .map(|f| ring_signed_area(&polygon(f)))
        .collect();
    // Connected components, so that a face of one never counts as holding its own vertices.
    let mut comp: Vec<usize> = (0..points.len()).collect();
    fn root(c: &mut [usize], mut v: usize) -> usize {
        while c[v] != v {
            c[v] = c[c[v]];
            v = c[v];
        }
        v
    }
    for &(a, b) in segments {
        let (ra, rb) = (root(&mut comp, a), root(&mut comp, b));
        comp[ra] = rb;
    }
    let face_comp: Vec<usize> = rings.iter().map(|r| root(&mut comp, r[0])).collect();
    // The smallest bounded face (positive area) holding `p`, among those of other components
    // than `not` (none for a hole point).
    let holding = |p: DVec2, not: Option<usize>| {
        (0..rings.len())
            .filter(|&f| area[f] > 0.0 && Some(face_comp[f]) != not)
            .filter(|&f| point_in_ring(p, &polygon(f)))
            .min_by(|&f, &g| area[f].total_cmp(&area[g]))
    };
    let eaten: Vec<usize> = holes.iter().filter_map(|&h| holding(h, None)).collect();
    let inside: Vec<bool> = (0..rings.len())
        .map(|f| {
            if area[f] > 0.0 {
                !eaten.contains(&f)
            } else {
                // A component's outer face is the face of the others it lies in.
                holding(points[rings[f][0]], Some(face_comp[f]))
                    .is_some_and(|g| !eaten.contains(&g))
            }
        })
        .collect();
    (0..m)
        .map(|s| match (inside[face[2 * s]], inside[face[2 * s + 1]]) {
            (true, true) => Side::Inside,
            (false, false) => Side::Outside,
            _ => Side::Boundary,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(p: &[(f64, f64)]) -> Vec<DVec2> {
        p.iter().map(|&q| DVec2::from(q)).collect()
    }

    #[test]
    fn an_interface_is_inside_and_the_outline_is_boundary() {
        // A square split by a vertical segment from (0.5, 0) to (0.5, 1).
        let p = pts(&[
            (0.0, 0.0),
            (0.5, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.5, 1.0),
            (0.0, 1.0),
        ]);
        let s = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 0), (1, 4)];
        let sides = classify(&p, &s, &[]);
        assert_eq!(&sides[..6], &[Side::Boundary; 6]);
        assert_eq!(sides[6], Side::Inside);
        // A hole point in the right half eats it: the interface becomes boundary, the right
        // half's outline outside.
        let sides = classify(&p, &s, &[DVec2::new(0.8, 0.5)]);
        assert_eq!(sides[6], Side::Boundary);
        assert_eq!(sides[1], Side::Outside);
    }

    #[test]
    fn an_inclusion_without_a_hole_point_is_inside_and_with_one_a_hole() {
        let p = pts(&[
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (0.4, 0.4),
            (0.6, 0.4),
            (0.6, 0.6),
            (0.4, 0.6),
            (0.45, 0.45),
            (0.55, 0.45),
        ]);
        let s = [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (4, 5),
            (5, 6),
            (6, 7),
            (7, 4),
            (8, 9),
        ];
        let sides = classify(&p, &s, &[]);
        assert_eq!(
            sides,
            [[Side::Boundary; 4], [Side::Inside; 4]]
                .concat()
                .into_iter()
                .chain([Side::Inside])
                .collect::<Vec<_>>()
        );
        // A crack floating inside the inclusion, then the inclusion made a hole: the crack
        // goes with it.
        let sides = classify(&p, &s, &[DVec2::new(0.5, 0.55)]);
        assert_eq!(&sides[4..8], &[Side::Boundary; 4]);
        assert_eq!(sides[8], Side::Outside);
    }
}
