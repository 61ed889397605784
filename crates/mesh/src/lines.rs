//! Embedded lines in meshes ([`geometry::Region::embedded_lines`]): where their vertices go
//! before a method runs, the edges that follow them after, and the flips that restore one a
//! method's triangulation missed.
use crate::{Mesh, MeshError, MeshRequest, Mesher};
use geometry::predicates::{closest_on_segment, orient, segments_cross};
#[cfg(test)]
use geometry::EmbeddedLine;
use geometry::{DVec2, Region};
use std::collections::HashMap;

/// Samples of the local spacing per segment when its vertices are placed.
const SAMPLES: usize = 16;

/// `region` with the vertices of its embedded lines as embedded points (each with its line's
/// marker): every vertex of a line, and points between them at the local spacing the request
/// asks for (equal shares of ∫ ds / h along each segment), as Gmsh meshes an embedded curve
/// before the surface around it. A line's ends on the boundary are corners already.
pub(crate) fn with_line_points(
    region: &Region,
    request: &MeshRequest,
) -> Result<(Region, Vec<(DVec2, DVec2)>), MeshError> {
    let spacing = request.spacing_at(region);
    let mut points = Vec::new();
    // The pieces between consecutive points along each line, which must become edges.
    let mut pieces = Vec::new();
    for line in region.embedded_lines() {
        for (a, b) in line.segments() {
            let first = points.len();
            points.push((a, line.marker));
            points.extend(split_at_spacing(a, b, &spacing).map(|p| (p, line.marker)));
            let along: Vec<DVec2> = points[first..].iter().map(|&(p, _)| p).chain([b]).collect();
            pieces.extend(along.windows(2).map(|w| (w[0], w[1])));
        }
        points.push((
            *line.points.last().expect("a line has two points"),
            line.marker,
        ));
    }
    let off = 1e-9 * region.diameter();
    points.retain(|&(p, _)| region.signed_distance(p) < -off);
    let region = region
        .clone()
        .with_embedded_points(points)
        .map_err(|e| MeshError::BadRequest(e.to_string()))?;
    Ok((region, pieces))
}

/// What to add to a [`slivers`](crate::slivers) warning on a mesh of `region` by `mesher`:
/// where lines inside cross at a small angle or pass close by each other, a method that places
/// their points at the spacing first leaves slivers, which Delaunay refinement does not
/// ([`Mesher::meshes_embedded_lines`]). `None` for a region without lines, or a method that
/// keeps them itself.
///
/// ```
/// use cvtmesh::geometry::{DVec2, EmbeddedLine, Region};
/// use cvtmesh::{sliver_advice, Method};
/// let crack = EmbeddedLine { points: vec![DVec2::new(-0.5, 0.0), DVec2::new(0.5, 0.1)], marker: 1 };
/// let region = Region::builtin("circle")?.with_embedded_lines([crack])?;
/// assert!(sliver_advice(&region, Method::Ccvt.mesher().as_ref()).is_some());
/// assert!(sliver_advice(&region, Method::Refine.mesher().as_ref()).is_none());
/// assert!(sliver_advice(&Region::builtin("circle")?, Method::Ccvt.mesher().as_ref()).is_none());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sliver_advice(region: &Region, mesher: &dyn Mesher) -> Option<&'static str> {
    (!region.embedded_lines().is_empty() && !mesher.meshes_embedded_lines()).then_some(
        "where lines inside cross at a small angle or pass close by each other, the refine \
         method (--method refine, method=\"refine\") splits them as Triangle does and leaves \
         no sliver",
    )
}

/// The points strictly between `a` and `b` that cut the segment into pieces of about the local
/// spacing `h` (equal shares of ∫ ds / h, by the midpoint rule on 16 samples), in order from
/// `a`; none where the segment is shorter than about one spacing.
///
/// ```
/// use cvtmesh::geometry::DVec2;
/// let (a, b) = (DVec2::ZERO, DVec2::new(1.0, 0.0));
/// let points: Vec<DVec2> = cvtmesh::split_at_spacing(a, b, |_| 0.25).collect();
/// assert_eq!(points, [0.25, 0.5, 0.75].map(|x| DVec2::new(x, 0.0)));
/// // Finer where h is smaller: the left half holds most of the points.
/// let graded: Vec<DVec2> = cvtmesh::split_at_spacing(a, b, |p| 0.02 + 0.2 * p.x).collect();
/// assert!(graded.iter().filter(|p| p.x < 0.5).count() > 2 * graded.iter().filter(|p| p.x >= 0.5).count());
/// ```
pub fn split_at_spacing(
    a: DVec2,
    b: DVec2,
    h: impl Fn(DVec2) -> f64,
) -> impl Iterator<Item = DVec2> {
    // ∫ ds / h, cumulated.
    let len = a.distance(b);
    let mut cumulative = [0.0; SAMPLES + 1];
    for k in 0..SAMPLES {
        let t = (k as f64 + 0.5) / SAMPLES as f64;
        cumulative[k + 1] = cumulative[k] + len / SAMPLES as f64 / h(a + (b - a) * t);
    }
    let n = cumulative[SAMPLES].round().max(1.0) as usize;
    (1..n).map(move |i| {
        let target = cumulative[SAMPLES] * i as f64 / n as f64;
        let k = cumulative
            .partition_point(|&c| c < target)
            .clamp(1, SAMPLES);
        let (c0, c1) = (cumulative[k - 1], cumulative[k]);
        let t = ((k - 1) as f64 + (target - c0) / (c1 - c0)) / SAMPLES as f64;
        a + (b - a) * t
    })
}

fn bits(p: DVec2) -> (u64, u64) {
    (p.x.to_bits(), p.y.to_bits())
}

/// Each vertex by its coordinates' bits: a line's points are vertices at exactly their places.
fn vertices_by_position(mesh: &Mesh) -> HashMap<(u64, u64), u32> {
    mesh.points
        .iter()
        .enumerate()
        .map(|(v, p)| (bits(*p), v as u32))
        .collect()
}

/// The mesh edges along the region's embedded lines, each with its line's marker, line by
/// line and in order along each; or where a line has no mesh edge running along it.
///
/// ```
/// use cvtmesh::geometry::{DVec2, EmbeddedLine, LoopRole, Region};
/// let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from).to_vec();
/// let interface = EmbeddedLine { points: vec![DVec2::new(0.5, 0.0), DVec2::new(0.5, 1.0)], marker: 7 };
/// let region = Region::from_loops("two materials", vec![(LoopRole::Outer, square)])?
///     .with_embedded_lines([interface])?;
/// let result = cvtmesh::mesh(&region, 400)?;
/// let edges = cvtmesh::line_edges(&result.mesh, &region)?;
/// // The edges run from the bottom wall to the top one, each on x = 0.5.
/// let length: f64 = edges.iter().map(|&([a, b], _)| result.mesh.points[a as usize].distance(result.mesh.points[b as usize])).sum();
/// assert!((length - 1.0).abs() < 1e-12 && edges.iter().all(|&(_, m)| m == 7));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn line_edges(mesh: &Mesh, region: &Region) -> Result<Vec<([u32; 2], i64)>, MeshError> {
    if region.embedded_lines().is_empty() {
        return Ok(Vec::new());
    }
    let at = vertices_by_position(mesh);
    let neighbours = neighbours(mesh);
    let off = 1e-9 * region.diameter();
    let missing = |i: usize, p: DVec2, what: &str| MeshError::Failed {
        method: "mesh".into(),
        message: format!(
            "embedded line {i} has no mesh {what} at ({}, {}): the mesh does not follow it; \
             ask for more points, or keep the line off the boundary",
            p.x, p.y
        ),
    };
    let mut edges = Vec::new();
    for (i, line) in region.embedded_lines().iter().enumerate() {
        for (a, b) in line.segments() {
            let (&va, &vb) = match (at.get(&bits(a)), at.get(&bits(b))) {
                (Some(va), Some(vb)) => (va, vb),
                (None, _) => return Err(missing(i, a, "vertex")),
                (_, None) => return Err(missing(i, b, "vertex")),
            };
            let along = |p: DVec2| (p - a).dot(b - a) / a.distance_squared(b);
            let mut cur = va;
            while cur != vb {
                let t0 = along(mesh.points[cur as usize]);
                let next = neighbours[cur as usize]
                    .iter()
                    .copied()
                    .filter(|&v| {
                        let p = mesh.points[v as usize];
                        closest_on_segment(a, b, p).0.distance(p) <= off && along(p) > t0
                    })
                    .min_by(|&u, &v| {
                        along(mesh.points[u as usize]).total_cmp(&along(mesh.points[v as usize]))
                    });
                let Some(next) = next else {
                    return Err(missing(i, mesh.points[cur as usize], "edge along it from"));
                };
                edges.push(([cur, next], line.marker));
                cur = next;
            }
        }
    }
    Ok(edges)
}

/// Each vertex's neighbours along the mesh's edges.
fn neighbours(mesh: &Mesh) -> Vec<Vec<u32>> {
    let mut n: Vec<Vec<u32>> = vec![Vec::new(); mesh.points.len()];
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            n[a as usize].push(b);
            n[b as usize].push(a);
        }
    }
    for v in &mut n {
        v.sort_unstable();
        v.dedup();
    }
    n
}

/// Make every one of `pieces` (consecutive points along the region's embedded lines, as
/// [`with_line_points`] placed them) an edge of the mesh, by flipping the edges that cross it
/// (a Delaunay triangulation of points spaced along a line has those edges unless a point off
/// the line crowds it). False where a piece could not be restored (or one of its points is no
/// vertex). Each round is O(V + pieces), and each flip scans the triangles: O(T) per missing
/// piece, for the rare mesh that [`line_edges`] finds missing one.
pub(crate) fn restore_line_edges(mesh: &mut Mesh, pieces: &[(DVec2, DVec2)]) -> bool {
    let at = vertices_by_position(mesh);
    let Some(ends): Option<Vec<(u32, u32)>> = pieces
        .iter()
        .map(|(p, q)| Some((*at.get(&bits(*p))?, *at.get(&bits(*q))?)))
        .collect()
    else {
        return false;
    };
    for _ in 0..64 {
        let neighbours = neighbours(mesh);
        let absent: Vec<(u32, u32)> = ends
            .iter()
            .copied()
            .filter(|&(u, v)| !neighbours[u as usize].contains(&v))
            .collect();
        if absent.is_empty() {
            return true;
        }
        let mut flipped = false;
        for (u, v) in absent {
            flipped |= flip_one_crossing(mesh, u, v);
        }
        if !flipped {
            return false;
        }
    }
    false
}

/// Flip one edge that crosses the segment from vertex `u` to vertex `v` and whose two
/// triangles make a convex quadrilateral; false if there is none.
fn flip_one_crossing(mesh: &mut Mesh, u: u32, v: u32) -> bool {
    let (a, b) = (mesh.points[u as usize], mesh.points[v as usize]);
    let (lo, hi) = (a.min(b), a.max(b));
    let near: Vec<usize> = (0..mesh.triangles.len())
        .filter(|&t| {
            let ps = mesh.triangles[t].map(|w| mesh.points[w as usize]);
            let (tlo, thi) = (ps[0].min(ps[1]).min(ps[2]), ps[0].max(ps[1]).max(ps[2]));
            tlo.x <= hi.x && tlo.y <= hi.y && thi.x >= lo.x && thi.y >= lo.y
        })
        .collect();
    let mut by_edge: HashMap<(u32, u32), (usize, u32)> = HashMap::new();
    for &t in &near {
        let tri = mesh.triangles[t];
        for k in 0..3 {
            by_edge.insert((tri[k], tri[(k + 1) % 3]), (t, tri[(k + 2) % 3]));
        }
    }
    // In the triangles' order, not the map's: the same mesh flips the same edge every run.
    let edges = near.iter().flat_map(|&t| {
        let tri = mesh.triangles[t];
        (0..3).map(move |k| (tri[k], tri[(k + 1) % 3], t, tri[(k + 2) % 3]))
    });
    for (p, q, t1, w) in edges {
        let Some(&(t2, x)) = by_edge.get(&(q, p)) else {
            continue;
        };
        let (pp, qp) = (mesh.points[p as usize], mesh.points[q as usize]);
        if !segments_cross(a, b, pp, qp) {
            continue;
        }
        let (wp, xp) = (mesh.points[w as usize], mesh.points[x as usize]);
        // The quadrilateral p, x, q, w is convex where both new triangles turn left.
        if orient(pp, xp, wp) > 0.0 && orient(xp, qp, wp) > 0.0 {
            mesh.triangles[t1] = [p, x, w];
            mesh.triangles[t2] = [x, q, w];
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::markers_from_topology;

    #[test]
    fn a_crossing_edge_is_flipped_onto_the_line() {
        // A unit square split along the diagonal (0,0)-(1,1); the line runs along the other.
        let points = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .map(DVec2::from)
            .to_vec();
        let triangles = vec![[0, 1, 2], [0, 2, 3]];
        let mut mesh = Mesh {
            markers: markers_from_topology(&points, &triangles),
            points: points.clone(),
            triangles,
        };
        let region = Region::from_loops("sq", vec![(geometry::LoopRole::Outer, points)])
            .unwrap()
            .with_embedded_lines([EmbeddedLine {
                points: vec![DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)],
                marker: 3,
            }])
            .unwrap();
        assert!(line_edges(&mesh, &region).is_err());
        assert!(restore_line_edges(&mut mesh, &[(DVec2::X, DVec2::Y)]));
        assert_eq!(line_edges(&mesh, &region).unwrap(), [([1, 3], 3)]);
        assert!((mesh.area() - 1.0).abs() < 1e-15);
        for t in &mesh.triangles {
            let p = t.map(|v| mesh.points[v as usize]);
            assert!(orient(p[0], p[1], p[2]) > 0.0);
        }
    }
}
