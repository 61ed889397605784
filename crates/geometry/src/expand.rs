//! The ε-expansion Ω_ε = {x : dist(x, Ω) ≤ ε} of Algorithm 2 (Section 2.4).
//!
//! Method (on the polygonization P of Ω with chord error tol/2):
//! 1. *Raw offset curve* of every ring: each edge shifted by ε along its outward normal,
//!    joined at convex vertices by an arc of radius ε (polygonized to tol/2) and at reflex
//!    vertices by a straight connector. Every point of ∂Ω_ε lies on it.
//! 2. *Arrangement*: all crossings between raw segments are found (grid of candidate pairs)
//!    and the segments are split there.
//! 3. *Classification*: a piece of raw segment is on ∂Ω_ε iff no part of P is nearer to its
//!    midpoint than the edge or vertex it was offset from (exact segment distances), up to
//!    the tol/2 sag of the polygonized arcs.
//! 4. *Tracing*: the kept pieces, all with Ω_ε on their left, are linked into rings; where
//!    several continue from one crossing the rightmost turn is taken (the outermost
//!    envelope), which also steps over pieces misclassified inside by rounding.
//!
//! Parts of the raw curve inside Ω_ε (bays narrower than 2ε, swallow-tails of inward offsets,
//! holes of inradius < ε) drop out in step 3, so the result is a simple polygon: the outer
//! ring (CCW) first, then holes (CW). A hole of Ω shrinks and vanishes once ε exceeds its
//! inradius; a bay of the outer boundary with a narrow mouth may become a new hole.
use crate::crossings::candidate_pairs;
use crate::index::Bvh;
use crate::numeric::segment_crossing;
use crate::polygon::{Polygon, Ring};
use crate::predicates::closest_on_segment;
use crate::predicates::ring_signed_area;
use crate::region::Region;
use glam::DVec2;

/// What a raw segment was offset from.
#[derive(Clone, Copy, Debug)]
enum Source {
    /// Edge index into the polygon's edge list.
    Edge(usize),
    /// A polygon vertex (joint arcs and reflex connectors).
    Vertex(DVec2),
}

#[derive(Clone, Copy, Debug)]
struct RawSeg {
    a: usize,
    b: usize,
    src: Source,
    piece: usize,
}

/// The inward offset by ε of a convex ring whose inside lies to the right of its edges (a
/// hole of Ω): the ring cut by each edge's half-plane {x : (x − pᵢ)·nᵢ ≥ ε}, as vertices each
/// with the ring edge that the offset edge from it lies along; empty when nothing is left.
fn offset_convex_ring(
    pts: &[DVec2],
    eps: f64,
    normal: impl Fn(usize) -> DVec2,
) -> Vec<(DVec2, usize)> {
    let mut cur: Vec<(DVec2, usize)> = pts.iter().enumerate().map(|(i, &p)| (p, i)).collect();
    let mut next = Vec::with_capacity(cur.len() + 1);
    for (i, &p) in pts.iter().enumerate() {
        let ni = normal(i);
        let f = |x: DVec2| (x - p).dot(ni) - eps;
        next.clear();
        for k in 0..cur.len() {
            let ((a, tag), (b, _)) = (cur[k], cur[(k + 1) % cur.len()]);
            let (fa, fb) = (f(a), f(b));
            if fa >= 0.0 {
                next.push((a, tag));
            }
            if (fa >= 0.0) != (fb >= 0.0) {
                // Leaving the half-plane, the edge from the crossing runs along edge i's
                // offset; entering it, along the rest of a's edge.
                let x = a + (b - a) * (fa / (fa - fb));
                next.push((x, if fa >= 0.0 { i } else { tag }));
            }
        }
        std::mem::swap(&mut cur, &mut next);
        if cur.len() < 3 {
            return Vec::new();
        }
    }
    cur
}

/// Union–find over arrangement nodes (crossings that coincide with segment ends).
fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

impl Region {
    /// Ω_ε = {x : dist(x, Ω) ≤ ε} of Section 2.4, polygonized to `tol`; each edge's piece is
    /// the piece of Ω it is nearest to. Holes shrink and vanish when ε exceeds their inradius.
    ///
    /// The result is a simple polygon (outer ring CCW first, holes CW) whose vertices lie
    /// within `tol` of distance ε from Ω. A bay of the outer boundary whose mouth is narrower
    /// than 2ε but which is wider inside becomes a new hole (its `loop_index` is the loop of
    /// its first edge's piece). ε ≤ 0 or NaN gives `polygonize(tol)`; see `expand.rs` for
    /// the method.
    pub fn expand(&self, eps: f64, tol: f64) -> Polygon {
        expand(self, eps, tol)
    }
}

fn expand(region: &Region, eps: f64, tol: f64) -> Polygon {
    let diam = region.diameter();
    let tol = tol.max(1e-9 * diam);
    if !(eps > 0.0 && eps.is_finite()) {
        return region.polygonize(tol);
    }
    let ptol = 0.5 * tol;
    let poly = region.polygonize(ptol);

    // Edges of P with their pieces, and a hierarchy for exact distances to P.
    let edges: Vec<(DVec2, DVec2, usize)> = poly.edges().collect();
    let boxes: Vec<(DVec2, DVec2)> = edges
        .iter()
        .map(|(a, b, _)| (a.min(*b), a.max(*b)))
        .collect();
    let bvh = Bvh::build(&boxes, (0..edges.len() as u32).collect());
    let dist_to_p = |x: DVec2| -> f64 {
        bvh.nearest(x, |e, _| {
            let (a, b, _) = edges[e as usize];
            closest_on_segment(a, b, x).2
        })
        .map_or(f64::INFINITY, |(_, d2)| d2.sqrt())
    };
    let scale = poly
        .rings
        .iter()
        .flat_map(|r| &r.points)
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()))
        + eps
        + diam;
    let eta = 1e-12 * scale;
    // Chords of the joint arcs sag by up to tol/2, so where two of them cross at a shallow
    // angle the exact distances cannot tell which is outside to better than that: pieces
    // inside by less than `zeta` are kept, and the rightmost-turn tracing steps over them.
    let zeta = ptol + eta;

    // 1. Raw offset curves: per ring a cyclic list of (point, source, piece), where the
    // source and piece describe the segment from that point to the next.
    let mut nodes: Vec<DVec2> = Vec::new();
    let mut raw: Vec<RawSeg> = Vec::new();
    let step = 2.0 * (1.0 - ptol / eps).max(-1.0).acos();
    let mut edge_base = 0;
    for ring in &poly.rings {
        let pts = &ring.points;
        let n = pts.len();
        if n < 3 {
            edge_base += n;
            continue;
        }
        let dir = |i: usize| (pts[(i + 1) % n] - pts[i]).normalize_or_zero();
        let normal = |i: usize| {
            let d = dir(i);
            DVec2::new(d.y, -d.x)
        };
        // Reflex vertices: where the offsets of the two edges cross inside both, cut them
        // there (the parts beyond lie within ε of the other edge). trim[j] = (crossing,
        // length cut from the end of edge j − 1, length cut from the start of edge j).
        let mut trim: Vec<Option<(DVec2, f64, f64)>> = vec![None; n];
        for (j, t) in trim.iter_mut().enumerate() {
            let i = (j + n - 1) % n;
            let (di, dj) = (dir(i), dir(j));
            let (ni, nj) = (normal(i), normal(j));
            let c = 1.0 + ni.dot(nj);
            if di.perp_dot(dj) < 0.0 && c > 1e-9 {
                let x = pts[j] + eps * (ni + nj) / c;
                *t = Some((
                    x,
                    (pts[j] + eps * ni - x).dot(di).max(0.0),
                    (x - pts[j] - eps * nj).dot(dj).max(0.0),
                ));
            }
        }
        let edge_len = |i: usize| pts[i].distance(pts[(i + 1) % n]);
        let convex_hole = ring.hole && trim.iter().all(Option::is_some);
        let mut swallowed = false;
        loop {
            let mut changed = false;
            for i in 0..n {
                let j = (i + 1) % n;
                let cut = trim[i].map_or(0.0, |t| t.2) + trim[j].map_or(0.0, |t| t.1);
                if cut > edge_len(i) && (trim[i].is_some() || trim[j].is_some()) {
                    trim[i] = None;
                    trim[j] = None;
                    changed = true;
                }
            }
            swallowed |= changed;
            if !changed {
                break;
            }
        }
        let mut cyc: Vec<(DVec2, Source, usize)> = Vec::new();
        // An edge of a convex hole swallowed by its neighbours' crossing: the trims above
        // are dropped and the untrimmed offsets, near the hole's closing each an edge long
        // around a remnant far smaller, cross one another by the thousand. The hole's offset
        // is its polygon cut by every edge's offset half-plane instead (empty once it closes).
        if convex_hole && swallowed {
            for (q, i) in offset_convex_ring(pts, eps, normal) {
                cyc.push((q, Source::Edge(edge_base + i), ring.pieces[i]));
            }
        } else {
            for i in 0..n {
                let j = (i + 1) % n;
                let v = pts[j];
                let (ni, nj) = (normal(i), normal(j));
                let start = trim[i].map_or(pts[i] + eps * ni, |t| t.0);
                cyc.push((start, Source::Edge(edge_base + i), ring.pieces[i]));
                if trim[j].is_some() {
                    continue;
                }
                // Joint at v: an arc of radius ε at a convex vertex, a straight connector at
                // a reflex one. Its first half belongs to the incoming piece, the rest to the
                // outgoing.
                let turn = dir(i).perp_dot(dir(j));
                let sweep = ni.perp_dot(nj).atan2(ni.dot(nj));
                let m = if turn > 0.0 && step > 0.0 {
                    ((sweep / step).ceil() as usize).max(1)
                } else {
                    1
                };
                let a0 = ni.y.atan2(ni.x);
                for k in 0..m {
                    let q = if k == 0 {
                        v + eps * ni
                    } else {
                        let th = a0 + sweep * k as f64 / m as f64;
                        v + eps * DVec2::new(th.cos(), th.sin())
                    };
                    let piece = if 2 * k < m {
                        ring.pieces[i]
                    } else {
                        ring.pieces[j]
                    };
                    cyc.push((q, Source::Vertex(v), piece));
                }
            }
        }
        // Merge coincident consecutive points (zero-length segments).
        let mut kept: Vec<(DVec2, Source, usize)> = Vec::with_capacity(cyc.len());
        for c in cyc {
            match kept.last_mut() {
                Some(last) if last.0 == c.0 => *last = c,
                _ => kept.push(c),
            }
        }
        while kept.len() > 1 && kept[kept.len() - 1].0 == kept[0].0 {
            kept.pop();
        }
        let base = nodes.len();
        let len = kept.len();
        for (k, (q, src, piece)) in kept.into_iter().enumerate() {
            nodes.push(q);
            raw.push(RawSeg {
                a: base + k,
                b: base + (k + 1) % len,
                src,
                piece,
            });
        }
        edge_base += n;
    }

    // 2. Crossings.
    let segs: Vec<(DVec2, DVec2)> = raw.iter().map(|s| (nodes[s.a], nodes[s.b])).collect();
    let mut splits: Vec<Vec<(f64, usize)>> = vec![Vec::new(); raw.len()];
    let mut parent: Vec<usize> = (0..nodes.len()).collect();
    candidate_pairs(&segs, 0.0, |i, j| {
        let (si, sj) = (raw[i], raw[j]);
        if si.a == sj.a || si.a == sj.b || si.b == sj.a || si.b == sj.b {
            return true;
        }
        if let Some((t, u)) = segment_crossing(segs[i].0, segs[i].1, segs[j].0, segs[j].1) {
            let x = nodes.len();
            nodes.push(segs[i].0 + (segs[i].1 - segs[i].0) * t);
            parent.push(x);
            splits[i].push((t, x));
            splits[j].push((u, x));
        }
        true
    });
    // Crossings at a segment end coincide with that end's node.
    for (k, s) in raw.iter().enumerate() {
        for &(t, x) in &splits[k] {
            let end = if t <= 0.0 || nodes[x] == nodes[s.a] {
                Some(s.a)
            } else if t >= 1.0 || nodes[x] == nodes[s.b] {
                Some(s.b)
            } else {
                None
            };
            if let Some(e) = end {
                let (rx, re) = (find(&mut parent, x), find(&mut parent, e));
                parent[rx] = re;
            }
        }
    }

    // 3. Sub-segments, classified by their midpoints.
    struct Sub {
        a: usize,
        b: usize,
        piece: usize,
        len: f64,
    }
    let mut subs: Vec<Sub> = Vec::new();
    for (k, s) in raw.iter().enumerate() {
        let mut cuts = std::mem::take(&mut splits[k]);
        cuts.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut chain = vec![s.a];
        chain.extend(cuts.iter().map(|c| c.1));
        chain.push(s.b);
        for w in chain.windows(2) {
            let (a, b) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
            if a == b || nodes[a] == nodes[b] {
                continue;
            }
            let m = 0.5 * (nodes[a] + nodes[b]);
            let d_src = match s.src {
                Source::Edge(e) => closest_on_segment(edges[e].0, edges[e].1, m).2.sqrt(),
                Source::Vertex(v) => m.distance(v),
            };
            if dist_to_p(m) >= d_src - zeta {
                subs.push(Sub {
                    a,
                    b,
                    piece: s.piece,
                    len: nodes[a].distance(nodes[b]),
                });
            }
        }
    }

    // 4. Tracing, longest pieces first, rightmost turn at branchings.
    let mut out_edges: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for (k, s) in subs.iter().enumerate() {
        out_edges[s.a].push(k);
    }
    let mut order: Vec<usize> = (0..subs.len()).collect();
    order.sort_by(|&x, &y| subs[y].len.total_cmp(&subs[x].len));
    let mut used = vec![false; subs.len()];
    let mut rings: Vec<(Vec<DVec2>, Vec<usize>)> = Vec::new();
    for &s0 in &order {
        if used[s0] {
            continue;
        }
        used[s0] = true;
        let mut path = vec![s0];
        let mut cur = s0;
        let closed = loop {
            let node = subs[cur].b;
            if node == subs[s0].a {
                break true;
            }
            let din = nodes[subs[cur].b] - nodes[subs[cur].a];
            let next = out_edges[node]
                .iter()
                .copied()
                .filter(|&e| !used[e])
                .min_by(|&x, &y| {
                    turn_angle(din, &nodes, &subs[x]).total_cmp(&turn_angle(din, &nodes, &subs[y]))
                });
            match next {
                Some(e) => {
                    used[e] = true;
                    path.push(e);
                    cur = e;
                }
                None => break false,
            }
        };
        if closed {
            let points: Vec<DVec2> = path.iter().map(|&e| nodes[subs[e].a]).collect();
            let pieces: Vec<usize> = path.iter().map(|&e| subs[e].piece).collect();
            rings.push((points, pieces));
        }
    }
    fn turn_angle(din: DVec2, nodes: &[DVec2], s: &Sub) -> f64 {
        let d = nodes[s.b] - nodes[s.a];
        let a = din.perp_dot(d).atan2(din.dot(d));
        if a <= -std::f64::consts::PI + 1e-15 {
            std::f64::consts::PI
        } else {
            a
        }
    }

    // Outer ring: the largest positive one; holes: negative rings at least tol/2 "thick"
    // (2·area/perimeter, the radius for a disk), which drops slivers between nearly
    // coincident raw pieces.
    let areas: Vec<f64> = rings.iter().map(|r| ring_signed_area(&r.0)).collect();
    let Some(outer) = (0..rings.len())
        .filter(|&k| areas[k] > 0.0)
        .max_by(|&x, &y| areas[x].total_cmp(&areas[y]))
    else {
        return region.polygonize(tol);
    };
    let mut result = Vec::new();
    let dedupe = |(pts, pcs): (Vec<DVec2>, Vec<usize>)| {
        let (mut p2, mut c2) = (Vec::with_capacity(pts.len()), Vec::with_capacity(pts.len()));
        for (p, c) in pts.into_iter().zip(pcs) {
            // Two points within `eta` make one: the edge between them vanishes and the edge
            // from the merged point is the one from the second, with its piece (keeping the
            // first's put a whole edge on the piece of a speck where two offsets meet, and
            // Algorithm 2's constrained phase projected its cells onto the wrong piece).
            if p2.last().is_some_and(|q: &DVec2| q.distance(p) <= eta) {
                *c2.last_mut().expect("a point was kept") = c;
                continue;
            }
            p2.push(p);
            c2.push(c);
        }
        while p2.len() > 1 && p2[0].distance(p2[p2.len() - 1]) <= eta {
            p2.pop();
            c2.pop();
        }
        (p2, c2)
    };
    let (pts, pcs) = dedupe(rings[outer].clone());
    result.push(Ring {
        points: pts,
        pieces: pcs,
        loop_index: 0,
        hole: false,
    });
    for (k, r) in rings.into_iter().enumerate() {
        let perimeter: f64 = (0..r.0.len())
            .map(|i| r.0[i].distance(r.0[(i + 1) % r.0.len()]))
            .sum();
        if k == outer || areas[k] >= 0.0 || -2.0 * areas[k] <= 0.5 * tol * perimeter {
            continue;
        }
        let (pts, pcs) = dedupe(r);
        if pts.len() < 3 {
            continue;
        }
        let loop_index = region.piece_loop(pcs[0]);
        result.push(Ring {
            points: pts,
            pieces: pcs,
            loop_index,
            hole: true,
        });
    }
    Polygon { rings: result }
}
