//! From generators to a conforming mesh (CCVT "From generators to a mesh").
use crate::delaunay::hilbert_order;
use geometry::predicates::triangle_signed_area;
use geometry::{DVec2, Region};
use mesh::{Mesh, MeshError, VertexMarker};
use rayon::prelude::*;
use spade::handles::{FixedFaceHandle, FixedVertexHandle, PossiblyOuterTag};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::collections::VecDeque;

/// Marker of each point: corner if within `tol` of a corner, boundary if within `tol` of the
/// boundary (with its piece, loop and arc-length position), interior otherwise.
///
/// The points are not moved: callers that need them exactly on the boundary project them first.
/// A non-finite point is marked interior.
pub fn mark_vertices(points: &[DVec2], region: &Region, tol: f64) -> Vec<VertexMarker> {
    points
        .par_iter()
        .map(|&p| {
            if !p.is_finite() {
                return VertexMarker::Interior;
            }
            let bp = region.project(p);
            if bp.distance.is_nan() || bp.distance > tol {
                return VertexMarker::Interior;
            }
            // The nearest corner within tol (or the one the projection landed on).
            let near_corner = region
                .corners()
                .iter()
                .enumerate()
                .map(|(i, c)| (c.pos.distance(p), i))
                .filter(|&(d, _)| d <= tol)
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, i)| i)
                .or(bp.corner);
            match near_corner {
                Some(i) => {
                    let c = &region.corners()[i];
                    VertexMarker::Corner {
                        loop_index: c.loop_index,
                        corner: i,
                        loop_param: c.loop_param,
                    }
                }
                None => VertexMarker::Boundary {
                    loop_index: bp.loop_index,
                    piece: bp.piece,
                    loop_param: bp.loop_param,
                },
            }
        })
        .collect()
}

/// Inside triangles with an area below this fraction of the mean are treated as degenerate
/// (`mesh::check_conforming` rejects 1e-10).
const DEGENERATE: f64 = 1e-9;

/// How many times the triangulation is rebuilt after dropping or nudging offending points.
const MAX_ATTEMPTS: usize = 8;

/// Triangulate `points` so the mesh conforms to `region`: a constrained Delaunay triangulation
/// in which consecutive boundary vertices along each loop (ordered by `loop_param`) are joined
/// by constraint edges, triangles outside the region or inside holes are removed, and
/// degenerate triangles are not produced. Passes `mesh::check_conforming`.
///
/// The output can have fewer points than the input; these are dropped (and the rest renumbered
/// in input order):
/// - duplicates of an earlier point (a boundary point is kept in preference to an interior one);
/// - interior points outside the polygon of boundary chords (between a chord and a convex piece
///   of the boundary, or in a hole), which no inside triangle could use;
/// - interior points lying on a boundary chord or forming a degenerate (near zero-area)
///   triangle with one;
/// - one of two boundary points within rounding of each other, and the middle one of three
///   nearly collinear boundary points (never a corner).
///
/// Points are never moved. (Nearly collinear boundary points make no slivers: spade's exact
/// Delaunay predicates flip them away.)
///
/// Errors (`MeshError::BadRequest`): lengths differ, a non-finite point, a marker naming a
/// loop the region does not have, a loop with fewer than 3 boundary vertices, constraint edges
/// that would cross (boundary vertices too coarse for the boundary's curvature, or loops too
/// close), a constraint edge that leaves the region (a skipped corner), a boundary vertex that
/// does not end up joined to exactly two boundary neighbours, or a degenerate triangle of three
/// boundary vertices whose widest angle is at a corner.
pub fn conforming_mesh(
    points: &[DVec2],
    markers: &[VertexMarker],
    region: &Region,
) -> Result<Mesh, MeshError> {
    validate(points, markers, region)?;
    constrained(points, markers, region)
}

/// [`conforming_mesh`] for validated input.
fn constrained(
    points: &[DVec2],
    markers: &[VertexMarker],
    region: &Region,
) -> Result<Mesh, MeshError> {
    let mut keep = vec![true; points.len()];
    for _ in 0..MAX_ATTEMPTS {
        match attempt(points, markers, &keep, region)? {
            Attempt::Done(mesh) => return Ok(mesh),
            Attempt::Retry { drop } => {
                for i in drop {
                    keep[i] = false;
                }
            }
        }
    }
    Err(MeshError::BadRequest(format!(
        "could not remove degenerate triangles after {MAX_ATTEMPTS} attempts"
    )))
}

/// What every path to a conforming mesh asks of its input: a marker per point, finite points,
/// markers that name the region's loops.
fn validate(points: &[DVec2], markers: &[VertexMarker], region: &Region) -> Result<(), MeshError> {
    let bad = |m: String| Err(MeshError::BadRequest(m));
    if points.len() != markers.len() {
        return bad(format!(
            "{} points but {} markers",
            points.len(),
            markers.len()
        ));
    }
    if points.len() >= u32::MAX as usize {
        return bad("too many points".into());
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return bad(format!("point {i} is not finite"));
    }
    let nloops = region.loops().len();
    for (i, m) in markers.iter().enumerate() {
        if let (Some(l), Some(t)) = (m.loop_index(), m.loop_param()) {
            if l >= nloops || !t.is_finite() {
                return bad(format!(
                    "point {i}: marker {m:?} does not fit a region with {nloops} loops"
                ));
            }
        }
    }
    Ok(())
}

/// Each loop's boundary points (input indices) in arc-length order (ties by index): the
/// chords of consecutive ones, cyclically, are the mesh's boundary edges.
fn boundary_loops(
    owner: impl Iterator<Item = usize>,
    markers: &[VertexMarker],
    nloops: usize,
) -> Vec<Vec<usize>> {
    let mut loops: Vec<Vec<(f64, usize)>> = vec![Vec::new(); nloops];
    for i in owner {
        if let (Some(l), Some(t)) = (markers[i].loop_index(), markers[i].loop_param()) {
            loops[l].push((t, i));
        }
    }
    loops
        .into_iter()
        .map(|mut lp| {
            lp.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            lp.into_iter().map(|(_, i)| i).collect()
        })
        .collect()
}

/// Where the chord a–b leaves the region by more than `share` of its length (a curved
/// stretch's sagitta, as `mesh::check_conforming` allows it), skipping part of the boundary.
fn chord_leaves(region: &Region, a: DVec2, b: DVec2, share: f64) -> Option<DVec2> {
    let allowance = 1e-9 * region.diameter() + share * a.distance(b);
    (1..8)
        .map(|s| a.lerp(b, s as f64 / 8.0))
        .find(|&x| region.signed_distance(x) > allowance)
}

/// [`conforming_mesh`] from a Delaunay triangulation at hand of about the same points (an
/// iteration's last, which is repaired to `points` by flips unless it is at them already): where every boundary chord is
/// one of its edges and no triangle inside the chords is degenerate, the constrained
/// triangulation is this one, and the mesh is read off it in O(K) instead of K insertions.
/// Anywhere else (a chord that is not an edge, duplicate points, a thin place) the result is
/// [`conforming_mesh`]'s. The triangles are those [`conforming_mesh`] gives, up to the choice
/// of diagonal between exactly cocircular points, in another order.
pub fn conforming_mesh_from(
    del: &mut crate::Delaunay,
    points: &[DVec2],
    markers: &[VertexMarker],
    region: &Region,
) -> Result<Mesh, MeshError> {
    validate(points, markers, region)?;
    if !del.is_at(points) {
        del.rebuild(points);
    }
    match read_off(del, points, markers, region) {
        Some(mesh) => Ok(mesh),
        None => constrained(points, markers, region),
    }
}

/// The mesh of the Delaunay triangles inside the boundary chords, or None where the
/// constrained triangulation would differ or the full path has something to drop or report.
fn read_off(
    del: &crate::Delaunay,
    points: &[DVec2],
    markers: &[VertexMarker],
    region: &Region,
) -> Option<Mesh> {
    use crate::topology::NONE;
    let n = points.len();
    if del.num_vertices() != n || (0..n).any(|i| del.vertex_index(i).is_none()) {
        return None;
    }
    let topo = del.topology()?;
    let vertex = |i: usize| del.vertex_index(i).expect("every point is a vertex") as u32;
    // Chords as sorted vertex pairs; each must be a Delaunay edge and stay in the region.
    let mut chords: Vec<(u32, u32)> = Vec::new();
    for lp in boundary_loops(0..n, markers, region.loops().len()) {
        if lp.len() < 3 {
            return None;
        }
        for k in 0..lp.len() {
            let (u, w) = (lp[k], lp[(k + 1) % lp.len()]);
            let (vu, vw) = (vertex(u), vertex(w));
            if !del.ring(vu as usize).contains(&vw)
                || chord_leaves(region, points[u], points[w], mesh::EDGE_ALLOWANCE).is_some()
            {
                return None;
            }
            chords.push((vu.min(vw), vu.max(vw)));
        }
    }
    chords.sort_unstable();
    chords.dedup();
    // Most edges have an end on no chord: a flag per vertex spares them the search (two
    // tests per edge of every triangle, 12 million at 10⁶ vertices).
    let mut on_chord = vec![false; del.pos.len()];
    for &(a, b) in &chords {
        on_chord[a as usize] = true;
        on_chord[b as usize] = true;
    }
    let is_chord = |a: u32, b: u32| {
        on_chord.get(a as usize) == Some(&true)
            && on_chord.get(b as usize) == Some(&true)
            && chords.binary_search(&(a.min(b), a.max(b))).is_ok()
    };
    // Inside by parity, as `classify_faces`: from the triangles on the hull (or touching a
    // frame vertex), outside, toggling across chords.
    let nv = n as u32;
    let ntri = topo.tri.len();
    const UNSET: u8 = 2;
    let mut state = vec![UNSET; ntri];
    let mut queue = VecDeque::new();
    for (t, tri) in topo.tri.iter().enumerate() {
        if tri.iter().any(|&v| v >= nv) {
            state[t] = 0;
            queue.push_back(t);
        } else if let Some(k) = (0..3).find(|&k| topo.adj[t][k] == NONE) {
            state[t] = u8::from(is_chord(tri[(k + 1) % 3], tri[(k + 2) % 3]));
            queue.push_back(t);
        }
    }
    while let Some(t) = queue.pop_front() {
        let tri = topo.tri[t];
        for k in 0..3 {
            let u = topo.adj[t][k];
            if u == NONE || state[u as usize] != UNSET {
                continue;
            }
            let cross = is_chord(tri[(k + 1) % 3], tri[(k + 2) % 3]);
            state[u as usize] = state[t] ^ u8::from(cross);
            queue.push_back(u as usize);
        }
    }
    if state.contains(&UNSET) {
        return None;
    }
    // The chords close: across every edge the two sides differ exactly where it is a chord.
    let consistent = (0..ntri).into_par_iter().all(|t| {
        let tri = topo.tri[t];
        (0..3).all(|k| {
            let u = topo.adj[t][k];
            u == NONE
                || (state[t] != state[u as usize]) == is_chord(tri[(k + 1) % 3], tri[(k + 2) % 3])
        })
    });
    if !consistent {
        return None;
    }
    let inner: Vec<[u32; 3]> = (0..ntri)
        .filter(|&t| state[t] == 1)
        .map(|t| topo.tri[t])
        .collect();
    if inner.iter().flatten().any(|&v| v >= nv) {
        return None;
    }
    let at = |v: u32| points[del.point_of_vertex(v as usize)];
    let mean_area = region.area() / inner.len().max(1) as f64;
    if inner
        .par_iter()
        .any(|t| triangle_signed_area(at(t[0]), at(t[1]), at(t[2])) <= DEGENERATE * mean_area)
    {
        return None;
    }
    // Vertices used by inside triangles, renumbered in input order.
    let mut used = vec![false; n];
    for &v in inner.iter().flatten() {
        used[del.point_of_vertex(v as usize)] = true;
    }
    let order: Vec<usize> = (0..n).filter(|&i| used[i]).collect();
    let mut new_index = vec![u32::MAX; n];
    for (k, &i) in order.iter().enumerate() {
        new_index[i] = k as u32;
    }
    Some(Mesh {
        points: order.iter().map(|&i| points[i]).collect(),
        triangles: inner
            .par_iter()
            .map(|t| t.map(|v| new_index[del.point_of_vertex(v as usize)]))
            .collect(),
        markers: order.iter().map(|&i| markers[i]).collect(),
    })
}

enum Attempt {
    Done(Mesh),
    /// Drop these points, then try again.
    Retry {
        drop: Vec<usize>,
    },
}

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

fn attempt(
    pos: &[DVec2],
    markers: &[VertexMarker],
    keep: &[bool],
    region: &Region,
) -> Result<Attempt, MeshError> {
    let bad = |m: String| Err(MeshError::BadRequest(m));
    let mut cdt = Cdt::new();
    // owner[v]: the input point that vertex v stands for.
    let mut owner: Vec<usize> = Vec::with_capacity(pos.len());
    for &i in &hilbert_order(pos) {
        let i = i as usize;
        if !keep[i] {
            continue;
        }
        let before = cdt.num_vertices();
        let h = cdt
            .insert(Point2::new(pos[i].x, pos[i].y))
            .map_err(|e| MeshError::BadRequest(format!("point {i} at {}: {e:?}", pos[i])))?;
        if cdt.num_vertices() > before {
            owner.push(i);
        } else if !markers[owner[h.index()]].on_boundary() && markers[i].on_boundary() {
            owner[h.index()] = i;
        }
    }

    // Boundary vertices of each loop in arc-length order, joined cyclically by constraints.
    let mut vertex_of = vec![usize::MAX; pos.len()];
    for (v, &i) in owner.iter().enumerate() {
        vertex_of[i] = v;
    }
    let loops: Vec<Vec<usize>> =
        boundary_loops(owner.iter().copied(), markers, region.loops().len())
            .into_iter()
            .map(|lp| lp.into_iter().map(|i| vertex_of[i]).collect())
            .collect();
    for (l, lp) in loops.iter().enumerate() {
        if lp.len() < 3 {
            return bad(format!(
                "boundary loop {l} has {} boundary vertices and at least 3 are needed to close \
                 it: the mesh's spacing is too coarse for this loop, and a larger K would follow it",
                lp.len()
            ));
        }
        for k in 0..lp.len() {
            let (u, w) = (lp[k], lp[(k + 1) % lp.len()]);
            let (hu, hw) = (
                FixedVertexHandle::from_index(u),
                FixedVertexHandle::from_index(w),
            );
            if !cdt.can_add_constraint(hu, hw) {
                let (a, b) = (pos[owner[u]], pos[owner[w]]);
                return bad(format!(
                    "boundary edge ({}, {}) – ({}, {}) of loop {l} crosses another boundary edge: the boundary \
                     vertices are too coarse for the boundary's curvature (or two loops are too close)",
                    a.x, a.y, b.x, b.y
                ));
            }
            cdt.add_constraint(hu, hw);
            // A chord that leaves the region by more than a curved piece's sagitta allows
            // (the allowance of `mesh::check_conforming`) skips part of the boundary.
            let (a, b) = (pos[owner[u]], pos[owner[w]]);
            let far = chord_leaves(region, a, b, mesh::EDGE_ALLOWANCE).and_then(|_| {
                let share = mesh::chord_allowance(region, &markers[owner[u]], &markers[owner[w]]);
                chord_leaves(region, a, b, share)
            });
            if let Some(x) = far {
                return bad(format!(
                    "boundary edge ({}, {}) – ({}, {}) of loop {l} leaves the region near ({}, {}): the boundary \
                     vertices skip a corner or a bend, or are too coarse for the boundary's curvature there: more \
                     points, or a smaller corner angle (which keeps the bend as a corner), would follow it",
                    a.x, a.y, b.x, b.y, x.x, x.y
                ));
            }
        }
    }

    // Constraint edges must join boundary vertices in simple loops; an interior vertex on a
    // chord is dropped.
    let mut drop = Vec::new();
    let mut degree = vec![0u32; owner.len()];
    for e in cdt.undirected_edges().filter(|e| e.is_constraint_edge()) {
        for v in e.vertices() {
            degree[v.fix().index()] += 1;
        }
    }
    for (v, &i) in owner.iter().enumerate() {
        if markers[i].on_boundary() {
            if degree[v] != 2 {
                let p = pos[i];
                return bad(format!(
                    "boundary vertex {i} at ({}, {}) has {} boundary neighbours instead of 2: another boundary \
                     vertex lies on a boundary edge (boundary too coarse, or loops too close)",
                    p.x, p.y, degree[v]
                ));
            }
        } else if degree[v] > 0 {
            drop.push(i);
        }
    }
    if !drop.is_empty() {
        return Ok(Attempt::Retry { drop });
    }

    // Inside faces: flood fill from the outer face, toggling across constraint edges.
    let inside = classify_faces(&cdt);
    let inner: Vec<FixedFaceHandle<spade::handles::InnerTag>> = cdt
        .fixed_inner_faces()
        .filter(|f| inside[f.index()])
        .collect();
    let mean_area = region.area() / inner.len().max(1) as f64;
    for &f in &inner {
        let face = cdt.face(f);
        let vs = face.vertices().map(|v| v.fix().index());
        let p = vs.map(|v| pos[owner[v]]);
        let area = triangle_signed_area(p[0], p[1], p[2]);
        if area > DEGENERATE * mean_area {
            continue;
        }
        // Interior points of a degenerate triangle go (one on a chord, or hugging one), except
        // where two boundary points lie within rounding of each other (a method may put them
        // there): then one of the pair, the one at the wider angle, goes, and so does the
        // middle one of three nearly collinear boundary points. Corners stay.
        let angle = |k: usize| {
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            a.angle_to(b).abs()
        };
        let widest = (0..3)
            .max_by(|&x, &y| angle(x).total_cmp(&angle(y)))
            .expect("three vertices");
        let w = owner[vs[widest]];
        let side = |k: usize| p[(k + 1) % 3].distance(p[(k + 2) % 3]);
        let (shortest, longest) = (0..3).fold((f64::INFINITY, 0.0f64), |(lo, hi), k| {
            (lo.min(side(k)), hi.max(side(k)))
        });
        // The pair: the widest angle sits at one end of the shortest side, whose other end is a
        // boundary point too.
        let pair = (0..3).any(|k| {
            k != widest
                && markers[owner[vs[k]]].on_boundary()
                && p[k].distance(p[widest]) == shortest
                && shortest < 1e-6 * longest
        });
        let interior: Vec<usize> = vs
            .iter()
            .map(|&v| owner[v])
            .filter(|&i| !markers[i].on_boundary())
            .collect();
        let droppable = matches!(markers[w], VertexMarker::Boundary { .. });
        if droppable && (pair || interior.is_empty()) {
            drop.push(w);
            continue;
        }
        if !interior.is_empty() {
            drop.extend(interior);
            continue;
        }
        return bad(format!(
            "boundary vertices {}, {} and {} near ({}, {}) form a degenerate triangle (area {area:e}): the region \
             is too thin there for these boundary vertices",
            owner[vs[0]], owner[vs[1]], owner[vs[2]], p[0].x, p[0].y
        ));
    }
    if !drop.is_empty() {
        drop.sort_unstable();
        drop.dedup();
        return Ok(Attempt::Retry { drop });
    }

    // Output: vertices used by inside faces, renumbered in input order.
    let mut used = vec![false; owner.len()];
    for &f in &inner {
        for v in cdt.face(f).vertices() {
            used[v.fix().index()] = true;
        }
    }
    let mut order: Vec<usize> = (0..owner.len()).filter(|&v| used[v]).collect();
    order.sort_unstable_by_key(|&v| owner[v]);
    let mut new_index = vec![u32::MAX; owner.len()];
    for (k, &v) in order.iter().enumerate() {
        new_index[v] = k as u32;
    }
    let triangles = inner
        .iter()
        .map(|&f| cdt.face(f).vertices().map(|v| new_index[v.fix().index()]))
        .collect();
    Ok(Attempt::Done(Mesh {
        points: order.iter().map(|&v| pos[owner[v]]).collect(),
        triangles,
        markers: order.iter().map(|&v| markers[owner[v]]).collect(),
    }))
}

/// Inside flags by face index: a breadth-first walk from the outer face that toggles the flag
/// whenever it crosses a constraint edge (the boundary loops are closed, so parity is
/// consistent).
fn classify_faces(cdt: &Cdt) -> Vec<bool> {
    const UNSET: u8 = 2;
    let mut state = vec![UNSET; cdt.num_all_faces()];
    let outer: FixedFaceHandle<PossiblyOuterTag> = cdt.outer_face().fix();
    state[outer.index()] = 0;
    let mut queue = VecDeque::new();
    for e in cdt.directed_edges() {
        if e.face().is_outer() {
            let g = e.rev().face();
            if let Some(g) = g.as_inner() {
                let gi = g.fix().index();
                if state[gi] == UNSET {
                    state[gi] = u8::from(e.is_constraint_edge());
                    queue.push_back(g.fix());
                }
            }
        }
    }
    while let Some(f) = queue.pop_front() {
        let sf = state[f.index()];
        for e in cdt.face(f).adjacent_edges() {
            if let Some(g) = e.rev().face().as_inner() {
                let gi = g.fix().index();
                if state[gi] == UNSET {
                    state[gi] = sf ^ u8::from(e.is_constraint_edge());
                    queue.push_back(g.fix());
                }
            }
        }
    }
    state.into_iter().map(|s| s == 1).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Delaunay;

    /// The unit circle's boundary at 48 points and a jittered lattice kept 0.5 spacing inside.
    fn disc() -> (Region, Vec<DVec2>, Vec<VertexMarker>) {
        let region = Region::builtin("circle").unwrap();
        let mut pts: Vec<DVec2> = (0..48)
            .map(|i| DVec2::from_angle(std::f64::consts::TAU * i as f64 / 48.0))
            .collect();
        let h = std::f64::consts::TAU / 48.0;
        let mut rng = geometry::Rng::new(3);
        for i in -20..=20 {
            for j in -20..=20 {
                let p = DVec2::new(i as f64 + 0.5 * j as f64, j as f64 * 0.75f64.sqrt()) * h
                    + DVec2::new(rng.range(-0.1, 0.1), rng.range(-0.1, 0.1)) * h;
                if p.length() < 1.0 - 0.5 * h {
                    pts.push(p);
                }
            }
        }
        let markers = mark_vertices(&pts, &region, 1e-12);
        (region, pts, markers)
    }

    #[test]
    fn a_disc_is_read_off_its_delaunay_triangulation() {
        let (region, pts, markers) = disc();
        let del = Delaunay::new(&pts);
        let mesh = read_off(&del, &pts, &markers, &region).expect("every chord is an edge");
        let full = conforming_mesh(&pts, &markers, &region).unwrap();
        assert_eq!(
            (mesh.points.len(), mesh.triangles.len()),
            (pts.len(), full.triangles.len())
        );
        mesh::check_conforming(&mesh, &region).unwrap();
    }

    #[test]
    fn a_point_on_a_chord_sends_the_mesh_to_the_constrained_triangulation() {
        let (region, mut pts, mut markers) = disc();
        // Halfway along the chord from boundary point 0 to 1, an interior point: the chord is
        // no Delaunay edge, and the full path drops the point.
        pts.push(pts[0].lerp(pts[1], 0.5));
        markers.push(VertexMarker::Interior);
        let del = Delaunay::new(&pts);
        assert!(read_off(&del, &pts, &markers, &region).is_none());
        let mesh = conforming_mesh_from(&mut Delaunay::new(&pts), &pts, &markers, &region).unwrap();
        assert_eq!(mesh.points.len(), pts.len() - 1);
    }
}
