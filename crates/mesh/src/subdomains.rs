//! The subdomain of each triangle: the parts a region's embedded lines cut it into, numbered
//! by the region's subdomain points ([`Region::subdomain_points`]) as Triangle's `-A` numbers
//! them by regional attributes.
use crate::{line_edges, Mesh, MeshError};
use geometry::predicates::orient;
use geometry::{DVec2, Region};
use std::collections::{HashMap, HashSet};

/// Does a mesh of `region` have subdomains to number: embedded lines that part it, or points
/// that number its parts? The files (and Python's `to_meshio`) number triangles only then, so
/// that a region of one material writes its files as it always did.
///
/// ```
/// use cvtmesh::geometry::{DVec2, Region};
/// let disc = Region::builtin("circle")?;
/// assert!(!cvtmesh::has_subdomains(&disc));
/// assert!(cvtmesh::has_subdomains(&disc.with_subdomain_points([(DVec2::ZERO, 4)])?));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn has_subdomains(region: &Region) -> bool {
    !region.embedded_lines().is_empty() || !region.subdomain_points().is_empty()
}

/// The number of each triangle's subdomain: the triangles joined by edges that are on no
/// embedded line of `region` make one subdomain. Where the region lists subdomain points, a
/// subdomain takes the number of the last point in it, and one without a point 0, as Triangle
/// numbers triangles by its regional attributes (`-A`); where it lists none, the subdomains
/// are numbered 1, 2, … in the order of their lowest vertex of least x (a laminate's layers
/// from left to right), the same whichever method made the mesh. O(T + V + P·T) for P points.
///
/// Fails when the mesh does not follow a line of the region ([`line_edges`]).
///
/// ```
/// use cvtmesh::geometry::{DVec2, EmbeddedLine, LoopRole, Region};
/// let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from).to_vec();
/// let interface = EmbeddedLine { points: vec![DVec2::new(0.5, 0.0), DVec2::new(0.5, 1.0)], marker: 7 };
/// let region = Region::from_loops("two materials", vec![(LoopRole::Outer, square)])?
///     .with_embedded_lines([interface])?;
/// let mesh = cvtmesh::mesh(&region, 400)?.mesh;
/// // Without subdomain points: 1 left of the interface, 2 right of it.
/// let ids = cvtmesh::subdomains(&mesh, &region)?;
/// let left_of = |t: &[u32; 3]| t.iter().all(|&v| mesh.points[v as usize].x <= 0.5);
/// assert!(mesh.triangles.iter().zip(&ids).all(|(t, &id)| (id == 1) == left_of(t)));
/// // A point numbers the part holding it; the part without one is 0, as Triangle's -A has it.
/// let numbered = region.with_subdomain_points([(DVec2::new(0.9, 0.5), 20)])?;
/// let ids = cvtmesh::subdomains(&mesh, &numbered)?;
/// assert!(mesh.triangles.iter().zip(&ids).all(|(t, &id)| id == if left_of(t) { 0 } else { 20 }));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn subdomains(mesh: &Mesh, region: &Region) -> Result<Vec<i64>, MeshError> {
    Ok(subdomains_cut_by(mesh, region, &line_edges(mesh, region)?))
}

/// [`subdomains`] with the mesh's edges along the region's lines given (`line_edges`, which
/// a writer has found already).
pub(crate) fn subdomains_cut_by(
    mesh: &Mesh,
    region: &Region,
    line_edges: &[([u32; 2], i64)],
) -> Vec<i64> {
    let cuts: HashSet<[u32; 2]> = line_edges
        .iter()
        .map(|&([a, b], _)| [a.min(b), a.max(b)])
        .collect();
    let roots = components(mesh, |_, _, edge| !cuts.contains(&edge));
    let points = region.subdomain_points();
    if points.is_empty() {
        // Each subdomain's lowest vertex of least x, and the subdomains in that order.
        let mut lowest_left: HashMap<usize, DVec2> = HashMap::new();
        for (tri, &r) in mesh.triangles.iter().zip(&roots) {
            for &v in tri {
                let p = mesh.points[v as usize];
                let best = lowest_left.entry(r).or_insert(p);
                if (p.x, p.y) < (best.x, best.y) {
                    *best = p;
                }
            }
        }
        let mut order: Vec<(usize, DVec2)> = lowest_left.into_iter().collect();
        order.sort_by(|a, b| {
            (a.1.x.total_cmp(&b.1.x))
                .then(a.1.y.total_cmp(&b.1.y))
                .then(a.0.cmp(&b.0))
        });
        let number: HashMap<usize, i64> = order
            .iter()
            .enumerate()
            .map(|(k, &(r, _))| (r, k as i64 + 1))
            .collect();
        return roots.iter().map(|r| number[r]).collect();
    }
    let mut number: HashMap<usize, i64> = HashMap::new();
    for &(p, id) in points {
        if let Some(t) = holding(mesh, p) {
            number.insert(roots[t], id);
        }
    }
    roots
        .iter()
        .map(|r| number.get(r).copied().unwrap_or(0))
        .collect()
}

/// One point in each part of `mesh` whose triangles a file numbers alike (`numbers`, one per
/// triangle: a Triangle `.ele`'s attribute, a Gmsh physical surface), with that number: the
/// centroid of the part's first triangle. The subdomain points of the region the mesh covers
/// ([`Region::with_subdomain_points`]), so that a new mesh of it, or a polished one, numbers
/// its triangles as the file did. None where `numbers` is not one per triangle.
///
/// ```
/// use cvtmesh::{io, DVec2, Mesh};
/// // Two triangles of the unit square, numbered 10 and 20.
/// let points = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from).to_vec();
/// let triangles = vec![[0, 1, 2], [0, 2, 3]];
/// let mesh = Mesh { markers: io::markers_from_topology(&points, &triangles), points, triangles };
/// let points = cvtmesh::subdomain_points_of(&mesh, &[10, 20]);
/// assert_eq!(points, [(DVec2::new(2.0, 1.0) / 3.0, 10), (DVec2::new(1.0, 2.0) / 3.0, 20)]);
/// ```
pub fn subdomain_points_of(mesh: &Mesh, numbers: &[i64]) -> Vec<(DVec2, i64)> {
    if numbers.len() != mesh.triangles.len() {
        return Vec::new();
    }
    let roots = components(mesh, |s, t, _| numbers[s] == numbers[t]);
    roots
        .iter()
        .enumerate()
        .filter(|&(t, &r)| r == t)
        .map(|(t, _)| {
            let corners = mesh.triangles[t].map(|v| mesh.points[v as usize]);
            (corners.iter().sum::<DVec2>() / 3.0, numbers[t])
        })
        .collect()
}

/// Each triangle's part, named by its part's first triangle: the parts of `mesh` whose
/// triangles meet across edges `joined(s, t, edge)` accepts, `s` and `t` the triangles on
/// either side. O(T) expected.
fn components(mesh: &Mesh, joined: impl Fn(usize, usize, [u32; 2]) -> bool) -> Vec<usize> {
    let n = mesh.triangles.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let mut first_at: HashMap<[u32; 2], usize> = HashMap::with_capacity(3 * n / 2);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let key = [a.min(b), a.max(b)];
            match first_at.get(&key) {
                Some(&s) if joined(s, t, key) => {
                    let (rs, rt) = (root(&mut parent, s), root(&mut parent, t));
                    // The smaller index is the root: the part is named by its first triangle
                    // whatever order the edges are met in.
                    parent[rs.max(rt)] = rs.min(rt);
                }
                Some(_) => {}
                None => {
                    first_at.insert(key, t);
                }
            }
        }
    }
    (0..n).map(|t| root(&mut parent, t)).collect()
}

/// The root of `x` in the union–find forest `parent`, halving the path.
fn root(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// The triangle holding `p`, else (a point between a curved wall and the chords that mesh
/// it) the one whose centroid is nearest; None for a mesh without triangles.
fn holding(mesh: &Mesh, p: DVec2) -> Option<usize> {
    let corners = |t: &[u32; 3]| t.map(|v| mesh.points[v as usize]);
    mesh.triangles
        .iter()
        .position(|t| {
            let [a, b, c] = corners(t);
            orient(a, b, p) >= 0.0 && orient(b, c, p) >= 0.0 && orient(c, a, p) >= 0.0
        })
        .or_else(|| {
            let centroid = |t: &[u32; 3]| corners(t).iter().sum::<DVec2>() / 3.0;
            (0..mesh.triangles.len()).min_by(|&s, &t| {
                let d = |k: usize| centroid(&mesh.triangles[k]).distance_squared(p);
                d(s).total_cmp(&d(t))
            })
        })
}
