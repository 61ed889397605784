//! Polish: raise the smallest angles of a finished mesh by moving the interior vertices of its
//! worst triangles, as Gmsh smooths after Frontal-Delaunay.
//!
//! A CCVT mesh's worst triangles sit in the boundary layer, an edge on ∂Ω and the third vertex
//! inside, or three boundary vertices at a corner, where the boundary spacing and the interior
//! lattice meet. Each vertex of a triangle whose smallest angle is below the threshold moves to
//! where the smallest angle of its star (the triangles around it) is largest, found by a
//! pattern search: an interior vertex anywhere in the region, a boundary vertex along its own
//! piece (projected back onto it, never onto a corner). Connectivity stays as it is and a move
//! is kept only if it raises that star's smallest angle, so the mesh's smallest angle never
//! falls; corners, and every vertex of a better triangle, stay where the method put them. A
//! move that would leave an edge of the star not locally Delaunay (a vertex across it inside a
//! triangle's circumcircle) is refused as well, so a Delaunay mesh stays one: its dual is still
//! the Voronoi diagram finite-volume schemes use. So is a move that would take a triangle past
//! the mesh's largest (area, circumcircle, radius ratio) or widen the spread of its cells
//! (areas, radii, shortest edges): the polish trades none of these worst elements for the
//! smallest angle.
//!
//! Cost: one pass over the triangles and one over the vertices' cells, O(K̃), one pass over the
//! triangles per sweep, plus a bounded search per vertex moved (O(log K) more per move that
//! changes the smallest or largest cell).
use crate::types::{
    rows_by_vertex, smallest_angle_cos, triangle_min_angle_deg, Mesh, VertexMarker,
};
use geometry::predicates::circumcenter;
use geometry::{DVec2, Region};
use rayon::prelude::*;
use std::cell::OnceCell;
use std::collections::{BTreeMap, HashMap};

/// The default threshold (degrees): triangles with a smaller angle have their interior
/// vertices polished. Above Gmsh Frontal-Delaunay's smallest angles on graded fields
/// (33.9–37.6°, `docs/performance.md`), below a uniform CCVT mesh's (42° on the circle).
pub const POLISH_BELOW_DEG: f64 = 40.0;

/// Rounds of sweeps (interior vertices, then boundary ones) over the triangles still below the
/// threshold: a vertex moved in one sweep changes its neighbours' stars, which the next
/// revisits.
const SWEEPS: usize = 3;
/// First step of the pattern search, relative to the shortest edge at the vertex, and the step
/// at which it stops.
const FIRST_STEP: f64 = 0.1;
const LAST_STEP: f64 = 4e-3;
/// Directions tried at each step (evenly spaced, the first along the vertex's first edge, so
/// that the search turns with the mesh).
const DIRECTIONS: usize = 8;
/// A vertex lies inside a circumcircle when the in-circle determinant exceeds this multiple of
/// the triangle's longest edge to the fourth power: rounding on cocircular points (a lattice)
/// is not a violation.
const INCIRCLE_TOL: f64 = 1e-10;
/// Least twice-area of a star triangle, relative to its longest edge squared: a move that
/// would flatten one below this is refused.
const MIN_SHAPE: f64 = 1e-6;

/// What [`polish`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct Polished {
    /// Vertices moved (each counted once however many sweeps moved it).
    pub moved: usize,
    /// Smallest angle of the mesh before, in degrees.
    pub before_deg: f64,
    /// Smallest angle after, in degrees (never below `before_deg`).
    pub after_deg: f64,
    /// Each moved vertex's place and marker before (what [`Polished::undo`] restores): a
    /// copy of the moved vertices only, not of the mesh.
    before: Vec<(u32, DVec2, VertexMarker)>,
}

impl Polished {
    /// Put the moved vertices of `mesh` (the mesh [`polish`] was given) back where they were.
    pub fn undo(&self, mesh: &mut Mesh) {
        for &(v, p, m) in &self.before {
            mesh.points[v as usize] = p;
            mesh.markers[v as usize] = m;
        }
    }
}

/// Move the vertices of the triangles whose smallest angle is below `below_deg` to raise the
/// smallest angle around each, keeping every triangle and corner, boundary vertices on their
/// piece (their markers follow; one whose marker names no piece of `region`, as a file's do
/// before [`io::restore_markers`](crate::io::restore_markers), stays) and interior ones inside
/// the region: see the module documentation. A threshold of 0 or less, or NaN (or a mesh with
/// no triangle below it), leaves the mesh as it is; one above 60° takes every triangle, as 60°
/// does (no triangle's smallest angle is larger). A meshing request refuses both
/// ([`MeshRequest::polish`](crate::MeshRequest::polish)). Deterministic: the vertices are
/// visited in the order of their worst triangle's angle.
///
/// ```
/// use cvtmesh::{polish, Mesh, VertexMarker};
/// use cvtmesh::geometry::{DVec2, LoopRole, Region};
///
/// // The unit square cut into four triangles around an off-centre interior vertex.
/// let corners = vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)];
/// let square = Region::from_loops("square", vec![(LoopRole::Outer, corners)])?;
/// let corner = |c: usize, t: f64| VertexMarker::Corner { loop_index: 0, corner: c, loop_param: t };
/// let mut mesh = Mesh {
///     points: vec![
///         DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0),
///         DVec2::new(0.0, 1.0), DVec2::new(0.8, 0.3),
///     ],
///     triangles: vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
///     markers: vec![corner(0, 0.0), corner(1, 1.0), corner(2, 2.0), corner(3, 3.0),
///                   VertexMarker::Interior],
/// };
/// let p = polish(&mut mesh, &square, 40.0);
/// assert_eq!(p.moved, 1);
/// assert!(p.after_deg > 44.9 && p.after_deg > p.before_deg);
/// assert!((mesh.points[4] - DVec2::new(0.5, 0.5)).length() < 1e-2); // the centre
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn polish(mesh: &mut Mesh, region: &Region, below_deg: f64) -> Polished {
    polish_with(mesh, region, below_deg, true, &[])
}

/// [`polish`], with the mesh's extremes of shape held ([`Bounds`]: the worst radius ratio and
/// χ, which do not depend on the spacing) and those of size too if `sized`. A graded mesh's
/// largest and smallest triangles and cells are its size field's coarsest and finest places,
/// not defects: held, they keep its worst angles where the field puts them (a graded L-shape
/// at 10⁵ stayed at 32.8° against Gmsh's 34.6°), so the meshing calls hold sizes for a uniform
/// density only. Left free as well, the shapes worsened (graded lake at 10⁴: χ 0.67 → 1.09).
pub(crate) fn polish_with(
    mesh: &mut Mesh,
    region: &Region,
    below_deg: f64,
    sized: bool,
    held: &[u32],
) -> Polished {
    // Triangles are compared by the cosine of their smallest angle (larger is worse): no
    // inverse trigonometric function in the passes over all triangles or in the search.
    let mut cosine: Vec<f64> = (0..mesh.num_triangles())
        .into_par_iter()
        .map(|t| smallest_angle_cos(mesh.triangle(t)))
        .collect();
    let worst_deg = |mesh: &Mesh, cosine: &[f64]| {
        let worst = (0..cosine.len()).max_by(|&a, &b| cosine[a].total_cmp(&cosine[b]));
        worst.map_or(f64::INFINITY, |t| triangle_min_angle_deg(mesh.triangle(t)))
    };
    let before = worst_deg(mesh, &cosine);
    let limit = below_deg.to_radians().cos();
    let mut moved = Moved {
        flag: vec![false; mesh.num_vertices()],
        before: Vec::new(),
    };
    let mut hold = vec![false; mesh.num_vertices()];
    for &v in held {
        if let Some(h) = hold.get_mut(v as usize) {
            *h = true;
        }
    }
    if below_deg > 0.0 && cosine.iter().any(|&c| c > limit) {
        let stars = Stars::new(mesh);
        let mut bounds = Bounds::of(mesh, &stars, sized);
        // The polish keeps the triangles and a line's vertices on it: its edges are the same
        // in every sweep.
        let lines = Lines::of(mesh, region);
        // Each round moves interior vertices first, then boundary vertices only for the
        // triangles still below the threshold (a boundary vertex off its place costs the cells
        // around it more: see design-notes, "Polish").
        for _ in 0..SWEEPS {
            let mut round = |boundary| {
                let stars = (&stars, &mut bounds);
                sweep(
                    mesh,
                    (region, &lines),
                    stars,
                    (&mut cosine, limit),
                    (&mut moved, &hold),
                    boundary,
                )
            };
            let (inside, along) = (round(false), round(true));
            if !inside && !along {
                break;
            }
        }
    }
    Polished {
        moved: moved.before.len(),
        before_deg: before,
        after_deg: worst_deg(mesh, &cosine),
        before: moved.before,
    }
}

/// The vertices moved so far, and their places and markers before.
struct Moved {
    flag: Vec<bool>,
    before: Vec<(u32, DVec2, VertexMarker)>,
}

/// One sweep: each movable vertex (interior ones, or with `boundary` boundary ones) of the
/// triangles whose smallest angle's cosine exceeds `limit`, worst triangle first, moved to its
/// best place. Whether any moved.
fn sweep(
    mesh: &mut Mesh,
    (region, lines): (&Region, &Lines),
    (stars, bounds): (&Stars, &mut Bounds),
    (cosine, limit): (&mut [f64], f64),
    (moved, hold): (&mut Moved, &[bool]),
    boundary: bool,
) -> bool {
    let mut bad: Vec<(f64, usize)> = cosine
        .iter()
        .enumerate()
        .filter(|(_, c)| **c > limit)
        .map(|(t, c)| (*c, t))
        .collect();
    // Worst first; ties, and the vertices within a triangle, in vertex order: the polish
    // depends on the triangles, not on the order or the rotation they are listed in.
    let sorted = |t: usize| {
        let mut vs = mesh.triangles[t];
        vs.sort_unstable();
        vs
    };
    bad.sort_by(|a, b| b.0.total_cmp(&a.0).then(sorted(a.1).cmp(&sorted(b.1))));
    let mut seen = vec![false; mesh.num_vertices()];
    let embedded = |p: DVec2| lines.fixed.contains(&(p.x.to_bits(), p.y.to_bits()));
    let mut any = false;
    for (_, t) in bad {
        for v in sorted(t) {
            let v = v as usize;
            let slide = lines.slides.get(&(v as u32)).copied();
            // A held vertex inside a straight run of a line slides along it: what holding it
            // keeps, the interface, it keeps.
            let movable = (!hold[v] || slide.is_some())
                && match mesh.markers[v] {
                    // A line's vertex slides with the boundary's, after the interior's.
                    VertexMarker::Interior if slide.is_some() => boundary,
                    // A point the region embeds stays, as a corner does.
                    VertexMarker::Interior => !boundary && !embedded(mesh.points[v]),
                    VertexMarker::Boundary { .. } => boundary,
                    VertexMarker::Corner { .. } => false,
                };
            if seen[v] || !movable {
                continue;
            }
            seen[v] = true;
            let slide = slide.map(|[u, w]| [u, w].map(|x| mesh.points[x as usize]));
            if let Some(p) = best_place(
                mesh,
                (stars, bounds),
                v,
                region,
                (slide, &lines.constrained),
            ) {
                if !moved.flag[v] {
                    moved.flag[v] = true;
                    moved
                        .before
                        .push((v as u32, mesh.points[v], mesh.markers[v]));
                }
                mesh.points[v] = p;
                if let VertexMarker::Boundary { piece, .. } = mesh.markers[v] {
                    mesh.markers[v] = VertexMarker::on_piece(region, p, piece);
                }
                bounds.moved(mesh, stars, v);
                any = true;
                for &s in stars.of(v) {
                    cosine[s as usize] = smallest_angle_cos(mesh.triangle(s as usize));
                }
            }
        }
    }
    any
}

/// What [`polish_within`] did; its `Display` is the note a run reports.
#[derive(Clone, Debug, PartialEq)]
pub struct PolishReport {
    /// What [`polish`] did.
    pub polished: Polished,
    /// The threshold it was given (degrees).
    pub below_deg: f64,
    /// False when the polished mesh left the region and the moves were undone.
    pub kept: bool,
    /// The mesh as left passed [`check_conforming`](crate::check_conforming) against the
    /// region polished in (it is checked when vertices moved and it has at most
    /// [`CONFORMITY_CHECK_LIMIT`](crate::CONFORMITY_CHECK_LIMIT) vertices).
    pub checked: bool,
}

impl std::fmt::Display for PolishReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = &self.polished;
        let vertices = if p.moved == 1 { "vertex" } else { "vertices" };
        if self.kept {
            write!(
                f,
                "polish: {} {vertices} of triangles with an angle below {}° moved, smallest angle {:.2}° -> {:.2}°",
                p.moved, self.below_deg, p.before_deg, p.after_deg
            )
        } else {
            write!(
                f,
                "polish undone: moving {} {vertices} made the mesh leave the region",
                p.moved
            )
        }
    }
}

/// [`polish`], then the conformity check ([`check_conforming`], up to
/// [`CONFORMITY_CHECK_LIMIT`] vertices): a polished mesh that leaves the region (a boundary
/// edge moved across a narrow gap) gets the method's vertices back. What every front end runs
/// (the meshing calls with the extremes of size held for a uniform density only, see
/// `polish_with`).
///
/// ```
/// use cvtmesh::{polish_within, Mesh, VertexMarker};
/// use cvtmesh::geometry::{DVec2, LoopRole, Region};
///
/// let corners = vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)];
/// let square = Region::from_loops("square", vec![(LoopRole::Outer, corners.clone())])?;
/// let corner = |c: usize| VertexMarker::Corner { loop_index: 0, corner: c, loop_param: c as f64 };
/// let mut mesh = Mesh {
///     points: [corners, vec![DVec2::new(0.8, 0.3)]].concat(),
///     triangles: vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
///     markers: vec![corner(0), corner(1), corner(2), corner(3), VertexMarker::Interior],
/// };
/// let report = polish_within(&mut mesh, &square, 40.0);
/// assert!(report.kept && report.checked && report.polished.moved == 1);
/// assert!(report.to_string().starts_with("polish: 1 vertex of"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// [`check_conforming`]: crate::check_conforming
/// [`CONFORMITY_CHECK_LIMIT`]: crate::CONFORMITY_CHECK_LIMIT
pub fn polish_within(mesh: &mut Mesh, region: &Region, below_deg: f64) -> PolishReport {
    within(mesh, region, below_deg, true, &[])
}

/// [`polish_within`] with [`polish_with`]'s choice of bounds.
pub(crate) fn within(
    mesh: &mut Mesh,
    region: &Region,
    below_deg: f64,
    sized: bool,
    held: &[u32],
) -> PolishReport {
    let polished = polish_with(mesh, region, below_deg, sized, held);
    let checks = polished.moved > 0 && mesh.num_vertices() <= crate::CONFORMITY_CHECK_LIMIT;
    let leaves = checks && crate::check_conforming(mesh, region).is_err();
    if leaves {
        polished.undo(mesh);
    }
    PolishReport {
        polished,
        below_deg,
        kept: !leaves,
        checked: checks && !leaves,
    }
}

/// A mesh made elsewhere (read from a file, another tool's), polished against `region`: its
/// boundary markers restored ([`io::restore_markers`](crate::io::restore_markers)), refused if it
/// does not conform to `region` (its boundary vertices could not be placed on it), then
/// [`polish_within`], with the sizes held only if the mesh does not look graded
/// ([`looks_graded`]: a file carries no size field). What `cvtmesh polish` and Python's
/// `Mesh.polished` run.
pub fn polish_restored(
    mesh: &mut Mesh,
    region: &Region,
    below_deg: f64,
) -> Result<PolishReport, crate::ConformityError> {
    polish_restored_holding(mesh, region, below_deg, &[])
}

/// [`polish_restored`] with the vertices `held` where they are: the ends of the edges a file
/// keeps inside the mesh ([`Walls::inner`](crate::io::Walls::inner): a material interface),
/// which moving would take off their line. Those inside a straight run of one of the
/// region's embedded lines (the region the file's triangles cover has its interfaces as
/// lines) slide along it, as boundary vertices slide along the boundary: the interface stays
/// where it is. What `cvtmesh polish` and Python's `Mesh.polished` run on a mesh read from a
/// file.
///
/// ```
/// use cvtmesh::{polish_restored, polish_restored_holding, MeshRequest, Method, Region};
/// let square = Region::builtin("square_hole")?;
/// let request = MeshRequest::points(300).polish(0.0);
/// let mesh = "distmesh".parse::<Method>()?.run(&square, &request)?.mesh;
/// let (mut free, mut held) = (mesh.clone(), mesh.clone());
/// polish_restored(&mut free, &square, 40.0)?;
/// let moved: Vec<u32> = (0..mesh.num_vertices() as u32)
///     .filter(|&v| free.points[v as usize] != mesh.points[v as usize])
///     .collect();
/// assert!(moved.len() > 1);
/// // Held, the first of them stays; the polish goes on around it.
/// polish_restored_holding(&mut held, &square, 40.0, &moved[..1])?;
/// assert_eq!(held.points[moved[0] as usize], mesh.points[moved[0] as usize]);
/// assert_ne!(held.points, mesh.points);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn polish_restored_holding(
    mesh: &mut Mesh,
    region: &Region,
    below_deg: f64,
    held: &[u32],
) -> Result<PolishReport, crate::ConformityError> {
    crate::io::restore_markers(mesh, region);
    crate::check_conforming(mesh, region)?;
    let sized = !looks_graded(mesh);
    Ok(within(mesh, region, below_deg, sized, held))
}

/// Above this ratio of the 99th to the 1st percentile of the vertices' shortest edges a mesh
/// looks graded ([`looks_graded`]). Uniform meshes stay below 1.5 (CCVT's 1.1, Triangle's and
/// Gmsh's 1.2–1.45 at 10⁵ vertices); the graded comparison's four fields give 6–22. Not the
/// extremes: a uniform mesh of a polygonized curve has a few short edges where the polygon's
/// vertices fall (Triangle's lake at 10⁵: 13.5 between its extremes).
pub const GRADED_SPREAD: f64 = 3.0;

/// Whether `mesh`'s vertices' shortest edges spread over more than [`GRADED_SPREAD`]: a mesh
/// made for a size field, whose largest and smallest elements are the field's and not defects
/// to hold.
///
/// ```
/// use cvtmesh::{io::markers_from_topology, looks_graded, Mesh};
/// use cvtmesh::geometry::DVec2;
/// // Squares of side 1, 2 and 8 in a row, each cut into two triangles.
/// let xs = [0.0, 1.0, 3.0, 11.0];
/// let points: Vec<DVec2> = xs.iter().flat_map(|&x| [DVec2::new(x, 0.0), DVec2::new(x, 1.0)]).collect();
/// let triangles: Vec<[u32; 3]> = (0..3u32).flat_map(|i| [[2 * i, 2 * i + 2, 2 * i + 3], [2 * i, 2 * i + 3, 2 * i + 1]]).collect();
/// let mesh = Mesh { markers: markers_from_topology(&points, &triangles), points, triangles };
/// // Every vertex has an edge of length 1 (the squares' vertical sides): not graded.
/// assert!(!looks_graded(&mesh));
/// // Two triangles, of sides 1 and 10: graded.
/// let points = vec![DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::new(20.0, 0.0), DVec2::new(30.0, 0.0), DVec2::new(20.0, 10.0)];
/// let triangles = vec![[0, 1, 2], [3, 4, 5]];
/// let two = Mesh { markers: markers_from_topology(&points, &triangles), points, triangles };
/// assert!(looks_graded(&two));
/// ```
pub fn looks_graded(mesh: &Mesh) -> bool {
    let mut shortest = vec![f64::INFINITY; mesh.num_vertices()];
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            let d = mesh.points[a].distance_squared(mesh.points[b]);
            shortest[a] = shortest[a].min(d);
            shortest[b] = shortest[b].min(d);
        }
    }
    shortest.retain(|d| d.is_finite() && *d > 0.0);
    if shortest.is_empty() {
        return false;
    }
    let n = shortest.len();
    let mut at = |q: f64| {
        *shortest
            .select_nth_unstable_by(((q * n as f64) as usize).min(n - 1), f64::total_cmp)
            .1
    };
    let (lo, hi) = (at(0.01), at(0.99));
    hi > GRADED_SPREAD * GRADED_SPREAD * lo
}

/// The triangles around each vertex, in compressed rows.
struct Stars {
    start: Vec<usize>,
    tris: Vec<u32>,
}

impl Stars {
    fn new(mesh: &Mesh) -> Stars {
        let (start, tris) = rows_by_vertex(&mesh.triangles, mesh.num_vertices(), |t, _| t as u32);
        Stars { start, tris }
    }

    fn of(&self, v: usize) -> &[u32] {
        &self.tris[self.start[v]..self.start[v + 1]]
    }

    /// The vertex across edge (a, b) from triangle `t`: the third vertex of the other triangle
    /// on that edge (None on the mesh's boundary).
    fn across(&self, mesh: &Mesh, t: u32, a: u32, b: u32) -> Option<u32> {
        let other = self
            .of(a as usize)
            .iter()
            .find(|&&s| s != t && mesh.triangles[s as usize].contains(&b))?;
        mesh.triangles[*other as usize]
            .into_iter()
            .find(|&u| u != a && u != b)
    }
}

/// Positive when `d` lies inside the circumcircle of the counter-clockwise triangle `q`.
fn incircle(q: [DVec2; 3], d: DVec2) -> f64 {
    let [a, b, c] = q.map(|p| p - d);
    let (la, lb, lc) = (a.length_squared(), b.length_squared(), c.length_squared());
    a.x * (b.y * lc - lb * c.y) - a.y * (b.x * lc - lb * c.x) + la * (b.x * c.y - b.y * c.x)
}

/// A triangle of `v`'s star with the vertex across each of its edges (`u32::MAX` on the
/// mesh's boundary).
struct StarTriangle {
    corners: [u32; 3],
    across: [u32; 3],
    /// Each corner's entry in [`Around`].
    slot: [u8; 3],
}

/// The vertices of a star (the moving vertex and its neighbours) with what their cells have
/// outside the star, which the moving vertex does not change: their area, and the largest
/// squared circumradius of their other triangles.
#[derive(Clone, Copy)]
struct Around {
    len: usize,
    verts: [u32; AROUND],
    cell: [f64; AROUND],
    reach2: [f64; AROUND],
    /// The shortest edge at each, squared.
    nearest2: [f64; AROUND],
}

/// Most vertices a star may have (the moving vertex and its neighbours); a vertex with more
/// neighbours stays where it is.
const AROUND: usize = 24;

/// The cells' bounds allow this factor: a cell's area as checked (the parts outside the star
/// summed apart) and as kept (all summed at once) may differ in the last bits, and a value
/// admitted at an end must not then refuse every later move.
const SLACK: f64 = 1.0 + 1e-12;

/// What a move may not take beyond the mesh as the polish found it: no triangle with a worse
/// radius ratio R/(2r) than the worst there was, and no cell reaching further per shortest
/// edge at its vertex than the farthest-reaching one (a cell's reach: the largest circumradius
/// of its vertex's triangles); with `sized`, also no triangle larger or with a larger
/// circumcircle than the largest there was, and no wider spread, largest over smallest, of the
/// cells' areas, of their reaches or of the vertices' shortest edges. So
/// the polish raises the smallest angle without raising the measures of the largest triangle
/// (α), the worst radius ratio (q), the cells' sizes and shapes (h, μ, ν, χ) and the
/// nearest-neighbour distances (γ): exactly for the triangles and the interior cells of a
/// Delaunay mesh, closely for the boundary cells (whose clipping at curved pieces the mesh
/// does not see).
// Without them, over the ten regions at K = 10⁴ (seeds 1–2), the polish raised α's geometric
// mean by 8.4 % (the horn's and the lake's largest triangles by up to 53 %); with the triangle
// bounds alone, the boundary sweep slid boundary vertices instead and shrank boundary cells
// (the horn's ν up 53 %). Measured in `docs/design-notes.md`, "Polish".
struct Bounds {
    /// The sizes held too (triangle areas and circumcircles, the spreads of the cells); else
    /// only the shapes, which do not depend on the spacing (radius ratio, χ).
    sized: bool,
    twice_area: f64,
    circumradius2: f64,
    ratio: f64,
    /// The largest squared reach per squared shortest edge (χ).
    reach_per_edge2: f64,
    /// Each vertex's cell area, squared reach and squared shortest edge.
    cell: Spread,
    reach2: Spread,
    nearest2: Spread,
}

impl Bounds {
    fn of(mesh: &Mesh, stars: &Stars, sized: bool) -> Bounds {
        let (twice_area, circumradius2, ratio) = (0..mesh.num_triangles())
            .into_par_iter()
            .map(|t| triangle_size(mesh.triangle(t)))
            // A flat triangle of the input has no size to hold the others to.
            .filter(|(a, r2, ratio)| a.is_finite() && r2.is_finite() && ratio.is_finite())
            .reduce(
                || (0.0, 0.0, 0.0),
                |a, b| (a.0.max(b.0), a.1.max(b.1), a.2.max(b.2)),
            );
        let cells: Vec<(f64, f64, f64)> = (0..mesh.num_vertices())
            .into_par_iter()
            .map(|v| match stars.of(v) {
                [] => (f64::NAN, f64::NAN, f64::NAN),
                _ => vertex_cell(mesh, stars, v),
            })
            .collect();
        let reach_per_edge2 = cells
            .iter()
            .map(|c| c.1 / c.2)
            .filter(|x| x.is_finite())
            .fold(0.0, f64::max);
        let unless_sized = |x: f64| if sized { x } else { f64::INFINITY };
        Bounds {
            sized,
            twice_area: unless_sized(twice_area),
            circumradius2: unless_sized(circumradius2),
            ratio,
            reach_per_edge2,
            cell: Spread::new(cells.iter().map(|c| c.0).collect()),
            reach2: Spread::new(cells.iter().map(|c| c.1).collect()),
            nearest2: Spread::new(cells.iter().map(|c| c.2).collect()),
        }
    }

    /// Whether a triangle of this [`triangle_size`] stays within the triangle bounds.
    fn admits(&self, (a, r2, ratio): (f64, f64, f64)) -> bool {
        a <= self.twice_area && r2 <= self.circumradius2 && ratio <= self.ratio
    }

    /// Whether the cells around a star, as `around` has them after a move, stay within the
    /// cells' bounds.
    fn cells_admit(&self, around: &Around) -> bool {
        let (n, verts) = (around.len, &around.verts[..around.len]);
        (0..n).all(|s| around.reach2[s] <= self.reach_per_edge2 * around.nearest2[s] * SLACK)
            && (!self.sized || self.spreads_admit(verts, around, n))
    }

    /// Whether the spreads of the cells' areas, reaches and shortest edges stay within theirs.
    fn spreads_admit(&self, verts: &[u32], around: &Around, n: usize) -> bool {
        self.cell.admits(verts, &around.cell[..n])
            && self.reach2.admits(verts, &around.reach2[..n])
            && self.nearest2.admits(verts, &around.nearest2[..n])
    }

    /// Vertex `v` moved: its cell's and its neighbours' values again (for the spreads: χ is
    /// checked from the mesh itself).
    fn moved(&mut self, mesh: &Mesh, stars: &Stars, v: usize) {
        if !self.sized {
            return;
        }
        let mut around: Vec<u32> = stars
            .of(v)
            .iter()
            .flat_map(|&t| mesh.triangles[t as usize])
            .collect();
        around.sort_unstable();
        around.dedup();
        for u in around {
            let (cell, reach2, nearest2) = vertex_cell(mesh, stars, u as usize);
            self.cell.set(u as usize, cell);
            self.reach2.set(u as usize, reach2);
            self.nearest2.set(u as usize, nearest2);
        }
    }
}

/// Vertex `v`'s cell area (see [`corners`]), squared reach (the largest circumradius of its
/// triangles) and squared shortest edge.
fn vertex_cell(mesh: &Mesh, stars: &Stars, v: usize) -> (f64, f64, f64) {
    cell_of(mesh, stars.of(v).iter(), v as u32)
}

/// Vertex `u`'s cell area, squared reach and squared shortest edge over the triangles `tris`.
fn cell_of<'a>(mesh: &Mesh, tris: impl Iterator<Item = &'a u32>, u: u32) -> (f64, f64, f64) {
    let (mut reach2, mut nearest2) = (0.0f64, f64::INFINITY);
    let cell = sorted_sum(tris.map(|&t| {
        let c = mesh.triangles[t as usize];
        let k = c.iter().position(|&w| w == u).unwrap_or(0);
        let (part, r2, side2) = corner(mesh.triangle(t as usize), k);
        reach2 = reach2.max(r2);
        nearest2 = nearest2.min(side2);
        part
    }));
    (cell, reach2, nearest2)
}

/// The part of a triangle nearer its corner `v` (the next corners `a`, `b` counter-clockwise
/// when `sign` is 1, its circumcentre `c`): the quadrilateral v, mid(v, a), c, mid(v, b).
#[inline]
fn corner_part(v: DVec2, a: DVec2, b: DVec2, c: DVec2, sign: f64) -> f64 {
    let (ma, mb, cv) = (0.5 * (a - v), 0.5 * (b - v), c - v);
    0.5 * sign * (ma.perp_dot(cv) + cv.perp_dot(mb))
}

/// A value per vertex (NaN for a vertex without triangles, not finite for none), and how widely the values may
/// spread: the largest over the smallest may not exceed what it was when the polish began.
struct Spread {
    value: Vec<f64>,
    /// How many vertices have each value, by [`order_key`]: built only once a vertex that holds
    /// an end changes, or is asked about (most polishes of a CCVT mesh move a few vertices,
    /// none of them at an end, and a million-vertex count costs a tenth of a second).
    count: OnceCell<BTreeMap<i64, u32>>,
    /// The smallest and largest value when the polish began (no bound unless both are
    /// positive and finite), and now.
    first: (f64, f64),
    now: (f64, f64),
}

impl Spread {
    fn new(value: Vec<f64>) -> Spread {
        let now = value
            .par_iter()
            .filter(|x| x.is_finite())
            .fold(
                || (f64::INFINITY, f64::NEG_INFINITY),
                |(lo, hi), &x| (lo.min(x), hi.max(x)),
            )
            .reduce(
                || (f64::INFINITY, f64::NEG_INFINITY),
                |a, b| (a.0.min(b.0), a.1.max(b.1)),
            );
        Spread {
            value,
            count: OnceCell::new(),
            first: now,
            now,
        }
    }

    /// The count of the values, built from them sorted.
    fn count(&self) -> &BTreeMap<i64, u32> {
        self.count.get_or_init(|| {
            let mut keys: Vec<i64> = self
                .value
                .par_iter()
                .filter(|x| x.is_finite())
                .map(|&x| order_key(x))
                .collect();
            keys.par_sort_unstable();
            let mut runs: Vec<(i64, u32)> = Vec::new();
            for k in keys {
                match runs.last_mut() {
                    Some((last, c)) if *last == k => *c += 1,
                    _ => runs.push((k, 1)),
                }
            }
            runs.into_iter().collect()
        })
    }

    /// The smallest and largest value with the vertices `verts` at the values `new`.
    fn ends(&self, verts: &[u32], new: &[f64]) -> (f64, f64) {
        let taken = |k: i64| {
            verts
                .iter()
                .filter(|&&u| order_key(self.value[u as usize]) == k)
                .count() as u32
        };
        // Only where one of them holds an end are the other values walked for the next.
        let left = |(&k, &c): (&i64, &u32)| (c > taken(k)).then(|| from_order_key(k));
        let (mut lo, mut hi) = self.now;
        if taken(order_key(lo)) > 0 {
            lo = self.count().iter().find_map(left).unwrap_or(f64::INFINITY);
        }
        if taken(order_key(hi)) > 0 {
            let rest = self.count().iter().rev().find_map(left);
            hi = rest.unwrap_or(f64::NEG_INFINITY);
        }
        new.iter()
            .fold((lo, hi), |(lo, hi), &x| (lo.min(x), hi.max(x)))
    }

    /// Whether the vertices `verts` may take the values `new`: largest / smallest no more than
    /// it was (compared as products, exact where the ends did not change).
    fn admits(&self, verts: &[u32], new: &[f64]) -> bool {
        let (lo0, hi0) = self.first;
        if !(lo0 > 0.0 && hi0 < f64::INFINITY) {
            return true;
        }
        let (lo, hi) = self.ends(verts, new);
        hi * lo0 <= hi0 * lo * SLACK
    }

    /// Vertex `v`'s value is now `x` (not finite for none: a cell beside a flat triangle of
    /// the input is neither counted nor an end).
    fn set(&mut self, v: usize, x: f64) {
        let old = self.value[v];
        let at_end = old.is_finite()
            && (order_key(old) == order_key(self.now.0) || order_key(old) == order_key(self.now.1));
        if at_end {
            self.count();
        }
        if let Some(count) = self.count.get_mut() {
            if old.is_finite() {
                let k = order_key(old);
                if let Some(c) = count.get_mut(&k) {
                    *c -= 1;
                    if *c == 0 {
                        count.remove(&k);
                    }
                }
            }
            if x.is_finite() {
                *count.entry(order_key(x)).or_insert(0) += 1;
            }
            let end = |e: Option<(&i64, &u32)>, none| e.map_or(none, |(&k, _)| from_order_key(k));
            self.now = (
                end(count.first_key_value(), f64::INFINITY),
                end(count.last_key_value(), f64::NEG_INFINITY),
            );
        } else if x.is_finite() {
            self.now = (self.now.0.min(x), self.now.1.max(x));
        }
        self.value[v] = x;
    }
}

/// A key whose order is `f64::total_cmp`'s.
fn order_key(x: f64) -> i64 {
    let b = x.to_bits() as i64;
    b ^ (((b >> 63) as u64) >> 1) as i64
}

fn from_order_key(k: i64) -> f64 {
    f64::from_bits((k ^ (((k >> 63) as u64) >> 1) as i64) as u64)
}

/// A triangle's |twice-area|, squared circumradius and radius ratio R/(2r) (1 when
/// equilateral; not finite for a flat one).
#[inline]
fn triangle_size(q: [DVec2; 3]) -> (f64, f64, f64) {
    let q = rotated(q, first_corner(q));
    let mut e2 = [
        (q[1] - q[0]).length_squared(),
        (q[2] - q[1]).length_squared(),
        (q[0] - q[2]).length_squared(),
    ];
    // In one order whatever corner the triangle is listed from: the bounds compare values to
    // the last bit.
    let (lo, hi) = (e2[0].min(e2[1]), e2[0].max(e2[1]));
    e2 = [lo.min(e2[2]), hi.min(e2[2]).max(lo), hi.max(e2[2])];
    let twice_area = (q[1] - q[0]).perp_dot(q[2] - q[0]).abs();
    // R = abc / (4A) and r = A / s (s the half-perimeter), so R / (2r) = abc·s / (8A²).
    let circumradius2 = e2[0] * e2[1] * e2[2] / (4.0 * twice_area * twice_area);
    let (a, b, c) = (e2[0].sqrt(), e2[1].sqrt(), e2[2].sqrt());
    let ratio = a * b * c * (a + b + c) / (4.0 * twice_area * twice_area);
    (twice_area, circumradius2, ratio)
}

/// What each corner of triangle `q` gives its vertex's cell: its part of the triangle, nearer
/// to it than to the other two corners (the quadrilateral corner, midpoint of one side,
/// circumcentre, midpoint of the other, signed: a corner beyond an obtuse angle's circumcentre
/// gets a negative part; the parts sum to the triangle's area and their sums over a vertex's
/// triangles are its cell), its squared distance to the circumcentre (the circumradius, for
/// the cell's reach) and the shorter of its two sides, squared. Computed from one corner
/// whatever corner the triangle is listed from.
#[inline]
fn corners(q: [DVec2; 3]) -> [(f64, f64, f64); 3] {
    let (c, sign) = centre_and_sign(q);
    [0, 1, 2].map(|i| corner_of(q, i, c, sign))
}

/// [`corners`]`(q)[i]` alone: a vertex's cell reads one corner of each of its triangles.
#[inline]
fn corner(q: [DVec2; 3], i: usize) -> (f64, f64, f64) {
    let (c, sign) = centre_and_sign(q);
    corner_of(q, i, c, sign)
}

/// The circumcentre of `q` and the sign of its orientation, computed from the corner
/// [`first_corner`] names whatever corner `q` is listed from.
#[inline]
fn centre_and_sign(q: [DVec2; 3]) -> (DVec2, f64) {
    let r = rotated(q, first_corner(q));
    (
        circumcenter(r[0], r[1], r[2]),
        (r[1] - r[0]).perp_dot(r[2] - r[0]).signum(),
    )
}

/// Corner `i`'s part, squared distance to the circumcentre `c` and shorter side squared.
#[inline]
fn corner_of(q: [DVec2; 3], i: usize, c: DVec2, sign: f64) -> (f64, f64, f64) {
    let (v, a, b) = (q[i], q[(i + 1) % 3], q[(i + 2) % 3]);
    let side2 = (a - v).length_squared().min((b - v).length_squared());
    (
        corner_part(v, a, b, c, sign),
        (c - v).length_squared(),
        side2,
    )
}

/// The corner of `q` a computation starts from, whatever corner it is listed from: the least
/// in (x, y) order.
#[inline]
fn first_corner(q: [DVec2; 3]) -> usize {
    let before = |a: DVec2, b: DVec2| a.x < b.x || (a.x == b.x && a.y < b.y);
    let k = usize::from(before(q[1], q[0]));
    if before(q[2], q[k]) {
        2
    } else {
        k
    }
}

/// `q` listed from its corner `k` (the same orientation).
#[inline]
fn rotated<T: Copy>(q: [T; 3], k: usize) -> [T; 3] {
    [q[k], q[(k + 1) % 3], q[(k + 2) % 3]]
}

/// A sum of parts in one order whatever order they come in (on the stack for up to 32).
fn sorted_sum(parts: impl Iterator<Item = f64>) -> f64 {
    let (mut stack, mut n, mut spill) = ([0.0; 32], 0, Vec::new());
    for x in parts {
        if n < stack.len() {
            stack[n] = x;
            n += 1;
        } else {
            spill.push(x);
        }
    }
    let all = if spill.is_empty() {
        &mut stack[..n]
    } else {
        spill.extend_from_slice(&stack);
        &mut spill[..]
    };
    all.sort_unstable_by(f64::total_cmp);
    all.iter().sum()
}

/// The cosine of the smallest angle of `v`'s star with `v` at `p` (the largest of its
/// triangles' [`smallest_angle_cos`]), or None where a star triangle would be flat or turned
/// over. With `held` = (bounds, around, best): also None unless the cosine is below `best` (a
/// better place), every star triangle stays within the [`Bounds`], no vertex across one of its
/// edges lies inside its circumcircle, and the cells around stay within the bounds.
fn star_cos(
    mesh: &Mesh,
    star: &[StarTriangle],
    v: usize,
    p: DVec2,
    held: Option<(&Bounds, &Around, f64)>,
) -> Option<f64> {
    let at = |u: u32| {
        if u as usize == v {
            p
        } else {
            mesh.points[u as usize]
        }
    };
    let mut worst = f64::NEG_INFINITY;
    for t in star {
        let q = t.corners.map(at);
        let twice_area = (q[1] - q[0]).perp_dot(q[2] - q[0]);
        let longest = longest_side2(q);
        // Also refuses a NaN area.
        if twice_area.partial_cmp(&(MIN_SHAPE * longest)) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        worst = worst.max(smallest_angle_cos(q));
    }
    let Some((bounds, around, best)) = held else {
        return Some(worst);
    };
    // Most places tried are no better: the bounds are checked only for those that are.
    if worst >= best {
        return None;
    }
    // The cells around: what lies outside the star, plus each star triangle's parts.
    let mut cells = *around;
    for t in star {
        let q = t.corners.map(at);
        let size = triangle_size(q);
        if !bounds.admits(size) {
            return None;
        }
        let longest = longest_side2(q);
        let tol = INCIRCLE_TOL * longest * longest;
        if t.across
            .iter()
            .any(|&d| d != u32::MAX && incircle(q, at(d)) > tol)
        {
            return None;
        }
        for (k, (part, r2, side2)) in corners(q).into_iter().enumerate() {
            let s = t.slot[k] as usize;
            cells.cell[s] += part;
            cells.reach2[s] = cells.reach2[s].max(r2);
            cells.nearest2[s] = cells.nearest2[s].min(side2);
        }
    }
    bounds.cells_admit(&cells).then_some(worst)
}

#[inline]
fn longest_side2(q: [DVec2; 3]) -> f64 {
    let (a, b, c) = (
        (q[1] - q[0]).length_squared(),
        (q[2] - q[1]).length_squared(),
        (q[0] - q[2]).length_squared(),
    );
    a.max(b).max(c)
}

/// What the polish keeps of the region's embedded lines, found once per polish.
struct Lines {
    /// The vertices that may slide along a line, each with its two neighbours along it:
    /// those inside a straight run of a line (placed between the line's own vertices, which
    /// stay, with its ends, junctions and crossings).
    slides: HashMap<u32, [u32; 2]>,
    /// A line's edges, by their sorted ends: constrained, the triangles either side of one
    /// need not pass the Delaunay test across it, as the boundary's need not.
    constrained: std::collections::HashSet<[u32; 2]>,
    /// Where the other vertices on the lines and the points the region embeds are, by their
    /// coordinates' bits: they stay.
    fixed: std::collections::HashSet<(u64, u64)>,
}

impl Lines {
    fn of(mesh: &Mesh, region: &Region) -> Lines {
        let edges = crate::lines::line_edges(mesh, region).unwrap_or_default();
        let bits = |p: DVec2| (p.x.to_bits(), p.y.to_bits());
        let kept: std::collections::HashSet<(u64, u64)> = region
            .embedded_lines()
            .iter()
            .flat_map(|l| l.points.iter().copied())
            .chain(region.embedded_points().iter().map(|(q, _)| *q))
            .map(bits)
            .collect();
        let mut along: HashMap<u32, Vec<u32>> = HashMap::new();
        for ([a, b], _) in &edges {
            along.entry(*a).or_default().push(*b);
            along.entry(*b).or_default().push(*a);
        }
        let slides = along
            .into_iter()
            .filter_map(|(v, n)| match n[..] {
                [u, w] if !kept.contains(&bits(mesh.points[v as usize])) => Some((v, [u, w])),
                _ => None,
            })
            .collect();
        Lines {
            slides,
            constrained: edges
                .iter()
                .map(|&([a, b], _)| [a.min(b), a.max(b)])
                .collect(),
            fixed: region
                .embedded_points()
                .iter()
                .map(|(q, _)| *q)
                .chain(
                    edges
                        .iter()
                        .flat_map(|(e, _)| e.map(|v| mesh.points[v as usize])),
                )
                .map(bits)
                .collect(),
        }
    }
}

/// Where `v` raises its star's smallest angle most, by a pattern search (None if nowhere
/// better was found, or the vertex has no triangles). With `slide` (the vertex's neighbours
/// along an embedded line) it moves along the line between them.
fn best_place(
    mesh: &Mesh,
    (stars, bounds): (&Stars, &Bounds),
    v: usize,
    region: &Region,
    (slide, constrained): (Option<[DVec2; 2]>, &std::collections::HashSet<[u32; 2]>),
) -> Option<DVec2> {
    let mut verts: Vec<u32> = vec![v as u32];
    // In one order whatever order the triangles are listed in: the cells are sums.
    let mut tris = stars.of(v).to_vec();
    tris.sort_unstable_by_key(|&t| {
        let mut c = mesh.triangles[t as usize];
        c.sort_unstable();
        c
    });
    let star: Vec<StarTriangle> = tris
        .iter()
        .map(|&t| {
            let c = mesh.triangles[t as usize];
            StarTriangle {
                corners: c,
                across: [0, 1, 2].map(|i| {
                    let (a, b) = (c[i], c[(i + 1) % 3]);
                    if constrained.contains(&[a.min(b), a.max(b)]) {
                        u32::MAX
                    } else {
                        stars.across(mesh, t, a, b).unwrap_or(u32::MAX)
                    }
                }),
                slot: c.map(|u| match verts.iter().position(|&w| w == u) {
                    Some(s) => s as u8,
                    None => {
                        verts.push(u);
                        (verts.len() - 1) as u8
                    }
                }),
            }
        })
        .collect();
    if verts.len() > AROUND {
        return None;
    }
    let around = {
        let in_star = |t: u32| mesh.triangles[t as usize].contains(&(v as u32));
        let outside = |u: u32| stars.of(u as usize).iter().filter(move |&&t| !in_star(t));
        let mut around = Around {
            len: verts.len(),
            verts: [0; AROUND],
            cell: [0.0; AROUND],
            reach2: [0.0; AROUND],
            nearest2: [f64::INFINITY; AROUND],
        };
        for (s, &u) in verts.iter().enumerate() {
            around.verts[s] = u;
            let cell = cell_of(mesh, outside(u), u);
            (around.cell[s], around.reach2[s], around.nearest2[s]) = cell;
        }
        around
    };
    let start = mesh.points[v];
    // The start is not held to the Delaunay test (a method's mesh need not pass it exactly),
    // nor to the bounds, which it meets by their making.
    let mut best = star_cos(mesh, &star, v, start, None)?;
    let piece = match mesh.markers[v] {
        VertexMarker::Interior => None,
        // A piece the region does not have (a file's marker before `io::restore_markers`):
        // held fixed, as a corner is.
        VertexMarker::Boundary { piece, .. } if piece >= region.pieces().len() => return None,
        VertexMarker::Boundary { piece, .. } => Some(piece),
        VertexMarker::Corner { .. } => return None,
    };
    // The shortest edge at v sets the scale. An interior vertex tries DIRECTIONS directions
    // turned from its edge to its lowest-numbered neighbour (whatever order the triangles are
    // listed in); a boundary vertex slides toward either boundary neighbour (the ends of its
    // star's edges with no triangle across), back onto its piece.
    let mut shortest = f64::INFINITY;
    let mut first: Option<(u32, DVec2)> = None;
    let mut along = Vec::new();
    for t in &star {
        for i in 0..3 {
            let (a, b) = (t.corners[i], t.corners[(i + 1) % 3]);
            let u = if a as usize == v {
                b
            } else if b as usize == v {
                a
            } else {
                continue;
            };
            let e = mesh.points[u as usize] - start;
            shortest = shortest.min(e.length());
            if first.is_none_or(|(w, _)| u < w) {
                first = Some((u, e));
            }
            if t.across[i] == u32::MAX {
                along.push(e.try_normalize()?);
            }
        }
    }
    let dirs: Vec<DVec2> = match (piece, slide) {
        (None, Some([u, w])) => {
            let d = (w - u).try_normalize()?;
            vec![d, -d]
        }
        (None, None) => {
            let axis = first?.1.try_normalize()?;
            (0..DIRECTIONS)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / DIRECTIONS as f64;
                    DVec2::from_angle(a).rotate(axis)
                })
                .collect()
        }
        (Some(_), _) => along,
    };
    let place = |p: DVec2, q: DVec2| -> Option<DVec2> {
        match piece {
            // Back onto the line (a rounding away), strictly between the neighbours.
            None if slide.is_some() => {
                let [u, w] = slide?;
                let t = (q - u).dot(w - u) / u.distance_squared(w);
                let r = u + (w - u) * t;
                (t > 0.0 && t < 1.0 && region.contains(r)).then_some(r)
            }
            None => region.contains(q).then_some(q),
            // Not onto a corner, nor past a bend of a sampled piece (the edge would cut it).
            Some(j) => {
                let bp = region.project_onto_piece(q, j);
                (bp.corner.is_none() && region.chain_vertex_between(p, bp.point, j).is_none())
                    .then_some(bp.point)
            }
        }
    };
    let mut p = start;
    let mut step = FIRST_STEP * shortest;
    while step > LAST_STEP * shortest {
        let mut improved = false;
        for d in &dirs {
            let q = p + *d * step;
            if let Some(c) = star_cos(mesh, &star, v, q, Some((bounds, &around, best))) {
                if c < best {
                    // The region is asked only for a candidate that would be kept; a boundary
                    // vertex's projection moves it, and is judged again.
                    let kept = place(p, q).and_then(|r| {
                        let c = if r == q {
                            Some(c)
                        } else {
                            star_cos(mesh, &star, v, r, Some((bounds, &around, best)))
                        };
                        c.filter(|&c| c < best).map(|c| (c, r))
                    });
                    if let Some((c, r)) = kept {
                        (best, p, improved) = (c, r, true);
                    }
                }
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    (p != start).then_some(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One corner alone is that corner of all three, bit for bit, whatever corner a triangle
    /// is listed from.
    #[test]
    fn one_corner_is_that_corner_of_the_three() {
        let mut rng = geometry::Rng::new(4);
        for _ in 0..10_000 {
            let q = [(); 3].map(|_| DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)));
            let all = corners(q);
            for (i, c) in all.iter().enumerate() {
                let one = corner(q, i);
                assert_eq!(
                    [one.0.to_bits(), one.1.to_bits(), one.2.to_bits()],
                    [c.0.to_bits(), c.1.to_bits(), c.2.to_bits()]
                );
            }
        }
    }

    /// The square [lo, hi]² as a region.
    fn square(lo: f64, hi: f64) -> Region {
        let c = [(lo, lo), (hi, lo), (hi, hi), (lo, hi)].map(|(x, y)| DVec2::new(x, y));
        Region::from_loops("square", vec![(geometry::LoopRole::Outer, c.to_vec())]).unwrap()
    }

    /// A structured triangulation of the unit square (n × n cells, each cut along a diagonal),
    /// its interior vertices displaced by `jitter(i, j)`.
    fn grid(n: usize, jitter: impl Fn(usize, usize) -> DVec2) -> (Mesh, Region) {
        let square = square(0.0, 1.0);
        let mut points = Vec::new();
        let mut markers = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let x = DVec2::new(i as f64, j as f64) / n as f64;
                let edge = i == 0 || j == 0 || i == n || j == n;
                if edge {
                    // Held fixed as corners are (polish tells only interior, boundary and
                    // corner vertices apart).
                    markers.push(VertexMarker::Corner {
                        loop_index: 0,
                        corner: 0,
                        loop_param: 0.0,
                    });
                    points.push(x);
                } else {
                    markers.push(VertexMarker::Interior);
                    points.push(x + jitter(i, j) / n as f64);
                }
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                // Each cell cut along its Delaunay diagonal.
                let [a, b, c, d] = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                let q = [a, b, c].map(|u| points[u as usize]);
                if incircle(q, points[d as usize]) > 0.0 {
                    triangles.push([a, b, d]);
                    triangles.push([b, c, d]);
                } else {
                    triangles.push([a, b, c]);
                    triangles.push([a, c, d]);
                }
            }
        }
        (
            Mesh {
                points,
                triangles,
                markers,
            },
            square,
        )
    }

    fn area(mesh: &Mesh) -> f64 {
        (0..mesh.num_triangles())
            .map(|t| {
                let q = mesh.triangle(t);
                0.5 * (q[1] - q[0]).perp_dot(q[2] - q[0])
            })
            .sum()
    }

    /// A jitter of up to `amplitude` cell widths, one per `salt`.
    fn salted(amplitude: f64, salt: usize) -> impl Fn(usize, usize) -> DVec2 {
        move |i, j| {
            let s = ((i * 7919 + j * 104_729 + salt * 31) % 1000) as f64 / 1000.0;
            DVec2::from_angle(std::f64::consts::TAU * s) * amplitude * (0.3 + 0.7 * s)
        }
    }

    /// A deterministic jitter of up to `a` cell widths.
    fn wobble(a: f64) -> impl Fn(usize, usize) -> DVec2 {
        salted(a, 0)
    }

    /// Every interior edge locally Delaunay (within the polish's own tolerance).
    fn is_delaunay(mesh: &Mesh) -> bool {
        let stars = Stars::new(mesh);
        (0..mesh.num_triangles() as u32).all(|t| {
            let c = mesh.triangles[t as usize];
            let q = mesh.triangle(t as usize);
            let longest = (0..3)
                .map(|i| (q[(i + 1) % 3] - q[i]).length_squared())
                .fold(0.0, f64::max);
            (0..3).all(|i| {
                stars.across(mesh, t, c[i], c[(i + 1) % 3]).is_none_or(|d| {
                    incircle(q, mesh.points[d as usize]) <= INCIRCLE_TOL * longest * longest
                })
            })
        })
    }

    #[test]
    fn the_smallest_angle_rises_and_the_mesh_stays_a_delaunay_triangulation_of_the_square() {
        let (mut mesh, square) = grid(12, wobble(0.2));
        assert!(is_delaunay(&mesh));
        let triangles = mesh.triangles.clone();
        let boundary: Vec<(usize, DVec2)> = (0..mesh.num_vertices())
            .filter(|&v| mesh.markers[v] != VertexMarker::Interior)
            .map(|v| (v, mesh.points[v]))
            .collect();
        let p = polish(&mut mesh, &square, 40.0);
        assert!(p.moved > 0);
        // A right isosceles triangle has 45°: without the jitter the grid's smallest angle.
        assert!(p.before_deg < 36.0, "{p:?}");
        assert!(p.after_deg > p.before_deg + 3.0, "{p:?}");
        assert!(is_delaunay(&mesh));
        let now = (0..mesh.num_triangles())
            .map(|t| triangle_min_angle_deg(mesh.triangle(t)))
            .fold(f64::INFINITY, f64::min);
        assert!((now - p.after_deg).abs() < 1e-9, "{now} {p:?}");
        assert_eq!(mesh.triangles, triangles);
        for (v, x) in boundary {
            assert_eq!(mesh.points[v], x);
        }
        for t in 0..mesh.num_triangles() {
            let q = mesh.triangle(t);
            assert!(
                (q[1] - q[0]).perp_dot(q[2] - q[0]) > 0.0,
                "triangle {t} turned over"
            );
        }
        assert!((area(&mesh) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn nothing_moves_without_a_triangle_below_the_threshold_or_at_threshold_zero() {
        let (mut mesh, square) = grid(6, |_, _| DVec2::ZERO);
        let before = mesh.points.clone();
        let p = polish(&mut mesh, &square, 40.0);
        assert_eq!(p.moved, 0);
        assert!((p.before_deg - 45.0).abs() < 1e-9 && p.after_deg == p.before_deg);
        assert_eq!(mesh.points, before);
        let (mut jittered, _) = grid(6, wobble(0.2));
        let before = jittered.points.clone();
        for below in [0.0, -10.0, f64::NAN] {
            assert_eq!(polish(&mut jittered, &square, below).moved, 0, "{below}");
            assert_eq!(jittered.points, before);
        }
    }

    #[test]
    fn a_threshold_above_sixty_degrees_polishes_as_sixty_does() {
        let (mut at_sixty, square) = grid(8, wobble(0.2));
        let mut above = at_sixty.clone();
        let p = polish(&mut at_sixty, &square, 60.0);
        assert!(p.moved > 0);
        assert_eq!(polish(&mut above, &square, 75.0).moved, p.moved);
        assert_eq!(above.points, at_sixty.points);
    }

    #[test]
    fn polishing_turns_with_the_mesh() {
        // A jittered grid of the unit square, and the same mesh and square turned by 0.7 rad
        // about the origin: the polished vertices turn with it.
        let turn = |p: DVec2| DVec2::from_angle(0.7).rotate(p);
        let (mut plain, square) = grid(8, wobble(0.2));
        let mut turned = plain.clone();
        turned.points.iter_mut().for_each(|p| *p = turn(*p));
        let corners = square_corners().map(turn).to_vec();
        let tilted = Region::from_loops("tilted", vec![(geometry::LoopRole::Outer, corners)]);
        let p = polish(&mut plain, &square, 40.0);
        let q = polish(&mut turned, &tilted.unwrap(), 40.0);
        assert!(p.moved > 5 && p.moved == q.moved, "{p:?} {q:?}");
        assert!((p.after_deg - q.after_deg).abs() < 1e-9, "{p:?} {q:?}");
        for (a, b) in plain.points.iter().zip(&turned.points) {
            assert!((turn(*a) - *b).length() < 1e-9, "{a} {b}");
        }
    }

    #[test]
    fn a_boundary_vertex_slides_along_its_piece() {
        // A grid of the unit square whose bottom side's vertices lie on piece 0, one of them
        // crowded toward its right-hand neighbour: no place of the interior vertices alone
        // lifts the thin triangles there, so it slides back along its side.
        let n = 6;
        let (mut mesh, square) = grid(n, wobble(0.15));
        for i in 1..n {
            let b = DVec2::new(i as f64 / n as f64, 0.0);
            mesh.markers[i] = VertexMarker::on_piece(&square, b, 0);
        }
        let crowded = DVec2::new((3.0 + 0.4) / n as f64, 0.0);
        mesh.points[3] = crowded;
        mesh.markers[3] = VertexMarker::on_piece(&square, crowded, 0);
        let p = polish(&mut mesh, &square, 40.0);
        assert!(p.after_deg > p.before_deg + 5.0, "{p:?}");
        let moved = mesh.points[3];
        assert!(
            moved.y == 0.0 && moved.x < crowded.x - 0.1 / n as f64,
            "{moved}"
        );
        assert_eq!(mesh.markers[3], VertexMarker::on_piece(&square, moved, 0));
        assert!(
            matches!(mesh.markers[3], VertexMarker::Boundary { loop_param, .. } if (loop_param - moved.x).abs() < 1e-12)
        );
        for c in square_corners() {
            assert!(mesh.points.contains(&c));
        }
    }

    /// A mesh's extremes, computed from scratch: its triangles' largest area, circumradius and
    /// radius ratio; the smallest and largest cell area (sums of [`corners`]), reach
    /// (largest circumradius around a vertex) and shortest edge at a vertex; the largest reach
    /// per shortest edge.
    #[derive(Debug)]
    struct Extremes {
        area: f64,
        circumradius: f64,
        ratio: f64,
        cell: (f64, f64),
        reach: (f64, f64),
        nearest: (f64, f64),
        reach_per_edge: f64,
    }

    fn extremes(mesh: &Mesh) -> Extremes {
        let none = (f64::INFINITY, 0.0);
        let mut e = Extremes {
            area: 0.0,
            circumradius: 0.0,
            ratio: 0.0,
            cell: none,
            reach: none,
            nearest: none,
            reach_per_edge: 0.0,
        };
        let n = mesh.num_vertices();
        let (mut cell, mut reach, mut nearest) =
            (vec![0.0; n], vec![0.0f64; n], vec![f64::INFINITY; n]);
        for (t, c) in mesh.triangles.iter().enumerate() {
            let q = mesh.triangle(t);
            let sides = [0, 1, 2].map(|i| q[(i + 1) % 3].distance(q[i]));
            let area = 0.5 * (q[1] - q[0]).perp_dot(q[2] - q[0]).abs();
            let r = q[0].distance(circumcenter(q[0], q[1], q[2]));
            let inradius = area / (0.5 * (sides[0] + sides[1] + sides[2]));
            e.area = e.area.max(area);
            e.circumradius = e.circumradius.max(r);
            e.ratio = e.ratio.max(r / (2.0 * inradius));
            let parts = corners(q);
            for k in 0..3 {
                let v = c[k] as usize;
                cell[v] += parts[k].0;
                reach[v] = reach[v].max(r);
                nearest[v] = nearest[v].min(sides[k].min(sides[(k + 2) % 3]));
            }
        }
        let widen = |(lo, hi): (f64, f64), x: f64| (lo.min(x), hi.max(x));
        for v in 0..n {
            e.cell = widen(e.cell, cell[v]);
            e.reach = widen(e.reach, reach[v]);
            e.nearest = widen(e.nearest, nearest[v]);
            e.reach_per_edge = e.reach_per_edge.max(reach[v] / nearest[v]);
        }
        e
    }

    fn square_corners() -> [DVec2; 4] {
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| DVec2::new(x, y))
    }

    #[test]
    fn the_smallest_angle_by_its_cosine_agrees_with_the_angle() {
        let tri =
            |a: (f64, f64), b: (f64, f64), c: (f64, f64)| [a, b, c].map(|(x, y)| DVec2::new(x, y));
        let h = 3f64.sqrt() / 2.0;
        assert!((smallest_angle_cos(tri((0.0, 0.0), (1.0, 0.0), (0.5, h))) - 0.5).abs() < 1e-15);
        assert_eq!(
            smallest_angle_cos(tri((0.0, 0.0), (1.0, 0.0), (2.0, 0.0))),
            1.0
        );
        assert_eq!(
            smallest_angle_cos(tri((0.0, 0.0), (0.0, 0.0), (1.0, 0.0))),
            1.0
        );
        for (k, q) in [
            tri((0.0, 0.0), (1.0, 0.0), (1.0, 1.0)),
            tri((0.1, -0.3), (2.0, 0.4), (0.7, 0.9)),
            tri((0.0, 0.0), (5.0, 0.1), (2.5, 0.3)),
        ]
        .into_iter()
        .enumerate()
        {
            let deg = smallest_angle_cos(q).acos().to_degrees();
            assert!((deg - triangle_min_angle_deg(q)).abs() < 1e-9, "{k}: {deg}");
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// On any jittered grid: the smallest angle never falls, no triangle turns over, the
        /// triangles still tile the square, and a Delaunay mesh stays Delaunay.
        #[test]
        fn polish_never_lowers_the_smallest_angle(
            n in 3usize..9,
            amplitude in 0.0f64..0.2,
            salt in 0usize..1000,
            below in 30.0f64..60.0,
        ) {
            let (mut mesh, square) = grid(n, salted(amplitude, salt));
            let delaunay = is_delaunay(&mesh);
            let p = polish(&mut mesh, &square, below);
            proptest::prop_assert!(p.after_deg >= p.before_deg - 1e-9, "{:?}", p);
            for t in 0..mesh.num_triangles() {
                let q = mesh.triangle(t);
                proptest::prop_assert!((q[1] - q[0]).perp_dot(q[2] - q[0]) > 0.0);
            }
            proptest::prop_assert!((area(&mesh) - 1.0).abs() < 1e-12);
            proptest::prop_assert!(!delaunay || is_delaunay(&mesh));
        }

        /// On any jittered grid, its bottom side's vertices free to slide along it: no
        /// triangle comes out with a larger area or circumcircle or a worse radius ratio than
        /// the mesh's largest before, no cell reaching further per shortest edge, and the
        /// cells' areas, reaches and shortest edges spread no wider (largest over smallest).
        #[test]
        fn polish_keeps_the_extremes_of_the_triangles_and_cells(
            n in 3usize..9,
            amplitude in 0.05f64..0.3,
            salt in 0usize..1000,
            below in 35.0f64..60.0,
        ) {
            let (mut mesh, square) = grid(n, salted(amplitude, salt));
            for i in 1..n {
                let s = ((i * 31 + salt) % 100) as f64 / 100.0;
                let b = DVec2::new((i as f64 + amplitude * (s - 0.5)) / n as f64, 0.0);
                mesh.points[i] = b;
                mesh.markers[i] = VertexMarker::on_piece(&square, b, 0);
            }
            let before = extremes(&mesh);
            let p = polish(&mut mesh, &square, below);
            let after = extremes(&mesh);
            let tol = 1e-12;
            let spread = |(lo, hi): (f64, f64)| hi / lo;
            for (a, b, what) in [
                (after.area, before.area, "area"),
                (after.circumradius, before.circumradius, "circumradius"),
                (after.ratio, before.ratio, "radius ratio"),
                (after.reach_per_edge, before.reach_per_edge, "reach per edge"),
                (spread(after.cell), spread(before.cell), "cells' areas"),
                (spread(after.reach), spread(before.reach), "cells' reaches"),
                (spread(after.nearest), spread(before.nearest), "shortest edges"),
            ] {
                proptest::prop_assert!(a <= b * (1.0 + tol) + 1e-15, "{} {} > {} {:?}", what, a, b, p);
            }
        }

        /// The polish depends on the triangles, not on the order or the rotation in which they
        /// are listed: the same places and markers whatever the listing.
        #[test]
        fn polish_ignores_how_the_triangles_are_listed(
            n in 3usize..9,
            amplitude in 0.05f64..0.25,
            salt in 0usize..1000,
            seed in 0u64..u64::MAX,
        ) {
            let (mut mesh, square) = grid(n, salted(amplitude, salt));
            let mut listed = mesh.clone();
            let mut rng = geometry::Rng::new(seed);
            for t in (1..listed.triangles.len()).rev() {
                listed.triangles.swap(t, rng.below(t + 1));
            }
            for tri in listed.triangles.iter_mut() {
                tri.rotate_left(rng.below(3));
            }
            let (p, q) = (polish(&mut mesh, &square, 40.0), polish(&mut listed, &square, 40.0));
            proptest::prop_assert_eq!(p.moved, q.moved);
            proptest::prop_assert_eq!(&mesh.points, &listed.points);
            proptest::prop_assert_eq!(&mesh.markers, &listed.markers);
        }
    }

    #[test]
    fn a_flat_triangle_of_the_input_holds_nothing_else() {
        // A jittered grid with one interior vertex put on the line through two of its
        // neighbours: its triangle is flat, its cells and sizes have no value, and the polish
        // still raises the smallest angle elsewhere, within the other triangles' extremes.
        let (mut mesh, square) = grid(8, wobble(0.2));
        let t = (0..mesh.num_triangles())
            .find(|&t| {
                mesh.triangles[t]
                    .iter()
                    .any(|&v| mesh.markers[v as usize] == VertexMarker::Interior)
            })
            .unwrap();
        let c = mesh.triangles[t];
        let k = c
            .iter()
            .position(|&v| mesh.markers[v as usize] == VertexMarker::Interior)
            .unwrap();
        let (a, b) = (
            mesh.points[c[(k + 1) % 3] as usize],
            mesh.points[c[(k + 2) % 3] as usize],
        );
        mesh.points[c[k] as usize] = 0.5 * (a + b);
        let flat = mesh.points[c[k] as usize];
        let sizes = |m: &Mesh| {
            (0..m.num_triangles())
                .map(|t| triangle_size(m.triangle(t)))
                .filter(|s| s.0 > 1e-12)
                .fold([0.0f64; 3], |hi, s| {
                    [hi[0].max(s.0), hi[1].max(s.1), hi[2].max(s.2)]
                })
        };
        let largest = sizes(&mesh);
        let p = polish(&mut mesh, &square, 40.0);
        assert!(p.moved > 0, "{p:?}");
        assert_eq!(mesh.points[c[k] as usize], flat);
        let now = sizes(&mesh);
        assert!(
            (0..3).all(|i| now[i] <= largest[i]),
            "{now:?} > {largest:?}"
        );
    }

    #[test]
    fn undo_restores_the_mesh_polish_was_given() {
        let (original, square) = grid(10, wobble(0.2));
        let mut mesh = original.clone();
        let p = polish(&mut mesh, &square, 40.0);
        assert!(p.moved > 0 && mesh.points != original.points);
        p.undo(&mut mesh);
        assert_eq!(mesh.points, original.points);
        assert_eq!(mesh.markers, original.markers);
    }

    #[test]
    fn a_boundary_marker_of_an_unknown_piece_holds_its_vertex() {
        // Markers as a file without them gives (io::markers_from_topology): every boundary
        // vertex on an unknown piece. Polish moves interior vertices only, and does not panic.
        let (mut mesh, square) = grid(6, wobble(0.2));
        for m in mesh.markers.iter_mut() {
            if m.on_boundary() {
                *m = VertexMarker::Boundary {
                    loop_index: 0,
                    piece: crate::io::UNKNOWN_PIECE,
                    loop_param: f64::NAN,
                };
            }
        }
        let before = mesh.clone();
        let p = polish(&mut mesh, &square, 50.0);
        assert!(p.moved > 0);
        for v in 0..mesh.num_vertices() {
            if before.markers[v].on_boundary() {
                assert_eq!(mesh.points[v], before.points[v]);
            }
        }
    }

    #[test]
    fn the_same_mesh_gives_the_same_bytes() {
        let (mut a, square) = grid(10, wobble(0.2));
        let mut b = a.clone();
        polish(&mut a, &square, 40.0);
        polish(&mut b, &square, 40.0);
        assert_eq!(a.points, b.points);
    }
}
