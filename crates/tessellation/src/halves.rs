//! A fresh Delaunay triangulation built on two threads: the points left of their median
//! abscissa and those right of it are triangulated apart, inside the same frame, and joined.
//!
//! Why the join is exact: a triangle of one half whose circumcircle lies strictly on its own
//! side of the median line has no point of the other half in its circle, so it is a triangle
//! of the whole set's triangulation (kept). What the kept triangles leave open (the hole,
//! along the line and around the frame) is covered by whole-set triangles whose corners are
//! all corners of triangles not kept: a vertex whose triangles were all kept has its whole
//! star kept. Those triangles have empty circles, so they are Delaunay triangles of these
//! corners alone; they are found in that small triangulation by walking from the edges the
//! kept triangles leave open. The cost beyond the two halves' insertions is linear in the
//! kept triangles (tested in parallel) and the hole's few thousand vertices.
use crate::topology::{Topology, NONE};
use geometry::predicates::circumcenter;
use geometry::DVec2;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};

/// Triangulate the vertices `0..m` at `pos` (in the order of their numbers, which should be
/// spatially coherent, e.g. Hilbert order) inside the convex frame `m..pos.len()` (CCW, around
/// all of them), as inserting them one by one into the frame's fan would. None when a
/// vertex cannot be inserted (a duplicate, a point outside the frame) or the halves cannot be
/// joined; the caller then inserts one by one.
pub(crate) fn triangulate_in_halves(pos: &[DVec2], m: usize) -> Option<Topology> {
    let n = pos.len();
    let fan: Vec<u32> = (m..n).map(|v| v as u32).collect();
    let mut xs: Vec<f64> = pos[..m].par_iter().map(|p| p.x).collect();
    let x_mid = *xs.select_nth_unstable_by(m / 2, f64::total_cmp).1;
    drop(xs);
    let (left, right): (Vec<u32>, Vec<u32>) = (0..m as u32)
        .into_par_iter()
        .partition(|&v| pos[v as usize].x < x_mid);
    if left.len() < m / 4 || right.len() < m / 4 {
        return None;
    }
    let (ta, tb) = rayon::join(
        || insert_all(pos, &fan, n, &left),
        || insert_all(pos, &fan, n, &right),
    );
    let halves = [ta?, tb?];
    // A triangle is kept when its circle lies on its half's side of the line, with a margin
    // against the rounding of its centre (a triangle dropped wrongly only enlarges the hole).
    let keep = |t: &Topology, side: f64| -> Vec<bool> {
        t.tri
            .par_iter()
            .map(|&[a, b, c]| {
                let (a, b, c) = (pos[a as usize], pos[b as usize], pos[c as usize]);
                let o = circumcenter(a, b, c);
                let r2 = o.distance_squared(a);
                let d = side * (x_mid - o.x);
                o.is_finite() && d > 0.0 && d * d > r2 * (1.0 + 1e-6)
            })
            .collect()
    };
    let kept = [keep(&halves[0], 1.0), keep(&halves[1], -1.0)];
    if kept.iter().all(|k| !k.contains(&true)) {
        return None;
    }
    // Corners of the triangles not kept: the hole's vertices, triangulated alone.
    let dropped: [Vec<u32>; 2] = [0, 1].map(|h| {
        (0..halves[h].tri.len() as u32)
            .into_par_iter()
            .filter(|&t| !kept[h][t as usize])
            .collect()
    });
    let mut corners: Vec<u32> = (0..2)
        .flat_map(|h| {
            let t = &halves[h];
            dropped[h].iter().flat_map(move |&u| t.tri[u as usize])
        })
        .filter(|&v| (v as usize) < m)
        .collect();
    corners.sort_unstable();
    corners.dedup();
    let hole = insert_all(pos, &fan, n, &corners)?;
    // Directed edges (x, y) of the hole's triangulation, the triangle on their left.
    let mut hole_edge: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * hole.tri.len());
    for (s, t) in hole.tri.iter().enumerate() {
        for k in 0..3 {
            hole_edge.insert((t[(k + 1) % 3], t[(k + 2) % 3]), s as u32);
        }
    }
    // New numbers: the kept triangles of the left half, of the right half, then the hole's.
    let (idx_a, starts_a, after_a) = ranks(&kept[0], 0);
    let (idx_b, starts_b, after_b) = ranks(&kept[1], after_a);
    let (idx, starts) = ([idx_a, idx_b], [starts_a, starts_b]);
    // The rim: each edge (x, y) of a kept triangle (on its left) whose neighbour its half did
    // not keep, with the kept triangle's new number. Across it lies the hole, or a triangle the
    // other half kept (only possible between two frame vertices: the halves share no other).
    let rim: HashMap<(u32, u32), u32> = (0..2)
        .flat_map(|h| {
            let (halves, kept, idx) = (&halves, &kept, &idx);
            dropped[h].iter().flat_map(move |&u| {
                let t = &halves[h];
                (0..3).filter_map(move |j| {
                    let nb = t.adj[u as usize][j];
                    (nb != NONE && kept[h][nb as usize]).then(|| {
                        let tri = t.tri[nb as usize];
                        let k = (0..3).find(|&k| t.adj[nb as usize][k] == u).unwrap_or(0);
                        ((tri[(k + 1) % 3], tri[(k + 2) % 3]), idx[h][nb as usize])
                    })
                })
            })
        })
        .collect();
    let is_frame = |v: u32| v as usize >= m;
    // The hole's triangles: from each rim edge's other side, across every edge but the rim.
    let mut in_hole = vec![NONE; hole.tri.len()];
    let mut queue: Vec<u32> = Vec::new();
    let mut order: Vec<u32> = Vec::new();
    for (&(x, y), _) in rim.iter() {
        if rim.contains_key(&(y, x)) {
            // Two kept triangles, one of each half, across a frame edge.
            continue;
        }
        let &s = hole_edge.get(&(y, x))?;
        if in_hole[s as usize] == NONE {
            in_hole[s as usize] = 0;
            queue.push(s);
        }
    }
    while let Some(s) = queue.pop() {
        order.push(s);
        let t = hole.tri[s as usize];
        for k in 0..3 {
            let (a, b) = (t[(k + 1) % 3], t[(k + 2) % 3]);
            if rim.contains_key(&(b, a)) {
                continue;
            }
            let u = hole.adj[s as usize][k];
            if u != NONE && in_hole[u as usize] == NONE {
                in_hole[u as usize] = 0;
                queue.push(u);
            }
        }
    }
    order.sort_unstable();
    for (k, &s) in order.iter().enumerate() {
        in_hole[s as usize] = after_b + k as u32;
    }
    let total = after_b as usize + order.len();
    let mut out = Topology::default();
    (0..total)
        .into_par_iter()
        .map(|_| ([NONE; 3], [NONE; 3]))
        .unzip_into_vecs(&mut out.tri, &mut out.adj);
    // Across edge (x, y) of a triangle, where its own half did not keep the neighbour.
    let across_rim = |x: u32, y: u32| -> Option<u32> {
        match rim.get(&(y, x)) {
            Some(&t) if is_frame(x) && is_frame(y) => Some(t),
            _ => hole_edge
                .get(&(y, x))
                .map(|&s| in_hole[s as usize])
                .filter(|&s| s != NONE),
        }
    };
    let failed = AtomicBool::new(false);
    for h in 0..2 {
        let t = &halves[h];
        // Each chunk of the half's triangles fills its own stretch of the new arrays.
        let (lo, hi) = (starts[h][0] as usize, [after_a, after_b][h] as usize);
        let mut slices = Vec::with_capacity(starts[h].len());
        let (mut tri, mut adj) = (&mut out.tri[lo..hi], &mut out.adj[lo..hi]);
        for (c, &start) in starts[h].iter().enumerate() {
            let end = starts[h].get(c + 1).map_or(hi, |&e| e as usize);
            let len = end - start as usize;
            let (ta, tr) = std::mem::take(&mut tri).split_at_mut(len);
            let (aa, ar) = std::mem::take(&mut adj).split_at_mut(len);
            slices.push((c, ta, aa));
            (tri, adj) = (tr, ar);
        }
        slices.into_par_iter().for_each(|(c, tri_out, adj_out)| {
            let first = c * CHUNK;
            let last = (first + CHUNK).min(t.tri.len());
            for (w, u) in (first..last).filter(|&u| kept[h][u]).enumerate() {
                let tri = t.tri[u];
                let mut adj = [NONE; 3];
                for k in 0..3 {
                    let nb = t.adj[u][k];
                    adj[k] = if nb == NONE {
                        NONE
                    } else if kept[h][nb as usize] {
                        idx[h][nb as usize]
                    } else {
                        across_rim(tri[(k + 1) % 3], tri[(k + 2) % 3]).unwrap_or_else(|| {
                            failed.store(true, Ordering::Relaxed);
                            NONE
                        })
                    };
                }
                tri_out[w] = tri;
                adj_out[w] = adj;
            }
        });
    }
    if failed.into_inner() {
        return None;
    }
    for (k_new, &s) in order.iter().enumerate() {
        let tri = hole.tri[s as usize];
        let mut adj = [NONE; 3];
        for k in 0..3 {
            let (a, b) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
            adj[k] = match rim.get(&(b, a)) {
                Some(&t) => t,
                None => {
                    let u = hole.adj[s as usize][k];
                    if u == NONE {
                        NONE
                    } else if in_hole[u as usize] != NONE {
                        in_hole[u as usize]
                    } else {
                        return None;
                    }
                }
            };
        }
        out.tri[after_b as usize + k_new] = tri;
        out.adj[after_b as usize + k_new] = adj;
    }
    // Each vertex's triangle: the one its half had, if kept; else the first kept one around
    // it, or the first of the hole's (the same whatever the number of threads).
    let side = |v: usize| usize::from(v < m && pos[v].x >= x_mid);
    let found = |v: usize| -> u32 {
        let own = [side(v), 1 - side(v)];
        let first_kept = own.iter().find_map(|&h| {
            star(&halves[h], v as u32).find_map(|t| kept[h][t as usize].then(|| idx[h][t as usize]))
        });
        first_kept
            .or_else(|| {
                star(&hole, v as u32)
                    .map(|s| in_hole[s as usize])
                    .find(|&s| s != NONE)
            })
            .unwrap_or(NONE)
    };
    out.v2t = (0..n)
        .into_par_iter()
        .map(|v| {
            let (h, t) = (side(v), halves[side(v)].v2t[v]);
            if t != NONE && kept[h][t as usize] {
                idx[h][t as usize]
            } else {
                found(v)
            }
        })
        .collect();
    // The links the join made (at the rim and in the hole) are mutual; the others are the
    // halves' own.
    let joined: Vec<u32> = rim.values().copied().chain(after_b..total as u32).collect();
    let linked = joined.par_iter().all(|&t| mutual(&out, t as usize));
    (linked && out.v2t.par_iter().all(|&t| t != NONE)).then_some(out)
}

/// The triangles around vertex `v` of `t` (counter-clockwise from its own triangle, then
/// clockwise from there where the star is open).
fn star(t: &Topology, v: u32) -> impl Iterator<Item = u32> + '_ {
    let slot = move |s: u32| t.tri[s as usize].iter().position(|&x| x == v).unwrap_or(0);
    let t0 = t.v2t.get(v as usize).copied().unwrap_or(NONE);
    let turn = move |dir: usize| {
        let mut s = t0;
        let mut n = 0;
        std::iter::from_fn(move || {
            if s == NONE || n > t.tri.len() {
                return None;
            }
            let here = s;
            s = t.adj[s as usize][(slot(s) + dir) % 3];
            n += 1;
            if s == t0 {
                s = NONE;
            }
            Some(here)
        })
    };
    turn(1).chain(turn(2).skip(1))
}

/// Triangles per chunk of the passes that number and copy the kept triangles.
const CHUNK: usize = 1 << 16;

/// The new numbers of the triangles `keep` marks (from `base` on, in order; `NONE` for the
/// others), the first new number of each chunk of `CHUNK` triangles, and the next free one.
fn ranks(keep: &[bool], base: u32) -> (Vec<u32>, Vec<u32>, u32) {
    let counts: Vec<u32> = keep
        .par_chunks(CHUNK)
        .map(|c| c.iter().filter(|&&k| k).count() as u32)
        .collect();
    let mut starts = Vec::with_capacity(counts.len());
    let mut next = base;
    for c in counts {
        starts.push(next);
        next += c;
    }
    let mut idx = vec![NONE; keep.len()];
    idx.par_chunks_mut(CHUNK)
        .zip(keep.par_chunks(CHUNK))
        .zip(starts.par_iter())
        .for_each(|((idx, keep), &start)| {
            let mut r = start;
            for (i, &k) in idx.iter_mut().zip(keep) {
                if k {
                    *i = r;
                    r += 1;
                }
            }
        });
    (idx, starts, next)
}

/// Insert `vs` (in this order) into the fan of the frame `fan`: None when one fails.
fn insert_all(pos: &[DVec2], fan: &[u32], n: usize, vs: &[u32]) -> Option<Topology> {
    let mut t = Topology::default();
    t.convex_fan(fan, n);
    let (mut hint, mut budget) = (0, usize::MAX);
    for &v in vs {
        t.insert(pos, v, hint, &mut budget).ok()?;
        hint = t.v2t[v as usize];
        // Only repairs read what the insertions touched.
        t.touched.clear();
    }
    Some(t)
}

/// Triangle `u`'s neighbour links are mutual, across the same two vertices.
fn mutual(t: &Topology, u: usize) -> bool {
    (0..3).all(|k| {
        let nb = t.adj[u][k];
        if nb == NONE {
            return true;
        }
        let (a, b) = (t.tri[u][(k + 1) % 3], t.tri[u][(k + 2) % 3]);
        let (o, q) = (t.tri.get(nb as usize), t.adj.get(nb as usize));
        let (Some(o), Some(q)) = (o, q) else {
            return false;
        };
        (0..3).any(|j| q[j] == u as u32 && o[(j + 1) % 3] == b && o[(j + 2) % 3] == a)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::Rng;

    /// The points with the frame `Delaunay` puts around them (a regular octagon, CCW).
    fn framed(points: Vec<DVec2>) -> Vec<DVec2> {
        let (lo, hi) = points.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let (c, diag) = crate::delaunay::frame_around(lo, hi);
        let mut pos = points;
        pos.extend(crate::delaunay::frame(c, diag));
        pos
    }

    /// Each triangle rotated to start at its smallest vertex, sorted.
    fn triangles(t: &Topology) -> Vec<[u32; 3]> {
        let mut out: Vec<[u32; 3]> = t
            .tri
            .iter()
            .map(|&[a, b, c]| {
                let k = [a, b, c].iter().enumerate().min_by_key(|x| x.1).unwrap().0;
                [[a, b, c][k], [a, b, c][(k + 1) % 3], [a, b, c][(k + 2) % 3]]
            })
            .collect();
        out.sort_unstable();
        out
    }

    /// The joined halves are the triangulation that inserting every point into the frame's fan
    /// gives, with mutual links and every vertex in a triangle: on random points, on two
    /// clusters of different density, on a jittered hexagonal lattice (as a start lays it out)
    /// and on points crowding a circle (where the hull's slivers cross the median line).
    #[test]
    fn the_joined_halves_are_the_triangulation_of_all_points() {
        let mut rng = Rng::new(3);
        let mut sets: Vec<Vec<DVec2>> = Vec::new();
        sets.push(
            (0..6000)
                .map(|_| DVec2::new(rng.range(0.0, 2.0), rng.range(0.0, 1.0)))
                .collect(),
        );
        sets.push(
            (0..6000)
                .map(|i| {
                    let p = DVec2::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0));
                    if i % 4 == 0 {
                        p
                    } else {
                        p * 0.05 + DVec2::new(0.7, 0.2)
                    }
                })
                .collect(),
        );
        let h = 0.013;
        let (u, v) = (
            DVec2::from_angle(0.3) * h,
            DVec2::from_angle(0.3 + std::f64::consts::FRAC_PI_3) * h,
        );
        let mut lattice = Vec::new();
        for i in -90..90 {
            for j in -90..90 {
                let p = u * i as f64 + v * j as f64;
                if p.length() < 1.0 {
                    lattice.push(p + DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 1e-9);
                }
            }
        }
        sets.push(lattice);
        sets.push(
            (0..5000)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / 5000.0;
                    DVec2::from_angle(a) * if i % 2 == 0 { 1.0 } else { rng.range(0.0, 1.0) }
                })
                .collect(),
        );
        for points in sets {
            let m = points.len();
            let pos = framed(points);
            let fan: Vec<u32> = (m..pos.len()).map(|v| v as u32).collect();
            let one_by_one =
                insert_all(&pos, &fan, pos.len(), &(0..m as u32).collect::<Vec<_>>()).unwrap();
            let joined = triangulate_in_halves(&pos, m).expect("joined");
            assert!((0..joined.tri.len()).all(|t| mutual(&joined, t)));
            assert_eq!(joined.v2t.len(), pos.len());
            for (v, &t) in joined.v2t.iter().enumerate() {
                assert!(joined.tri[t as usize].contains(&(v as u32)), "vertex {v}");
            }
            assert_eq!(triangles(&joined), triangles(&one_by_one), "{m} points");
        }
    }

    /// A duplicate point (which insertion one by one merges) or all points on one line leaves
    /// the join to the caller.
    #[test]
    fn duplicates_and_a_degenerate_split_are_left_to_the_caller() {
        let mut rng = Rng::new(4);
        let mut points = crate::unit_square_points(&mut rng, 3000);
        points.push(points[17]);
        let m = points.len();
        assert!(triangulate_in_halves(&framed(points), m).is_none());
        let column: Vec<DVec2> = (0..3000)
            .map(|i| DVec2::new(0.5, i as f64 + rng.range(0.0, 0.5)))
            .collect();
        assert!(triangulate_in_halves(&framed(column), 3000).is_none());
    }
}
