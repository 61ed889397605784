//! Shewchuk's Triangle formats: `.node` (vertices), `.ele` (triangles), `.poly` (segments).
use super::{
    file_err, push_float, push_int, read_mesh_parts, read_text, validate_for_writing, write_files,
    write_lines, MeshFile, Nodes, Producer, Tokens, Walls, F, UNKNOWN_PIECE,
};
use crate::{Mesh, MeshError, VertexMarker};
use geometry::DVec2;
use std::ffi::OsString;
use std::io::Write;
use std::path::{Path, PathBuf};

/// How a `.poly` written here without numbered walls says its segment markers are loops.
const LOOP_SEGMENTS: &str = "marker = loop index + 1";

/// First line of the `.node` files written here; it marks the attributes as exact markers.
const SIGNATURE: &str = "# Triangle .node written by cvtmesh";

fn with_suffix(base: &Path, ext: &str) -> PathBuf {
    let mut s: OsString = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Write `base.node`, `base.ele` and `base.poly` (1-based, as Triangle writes them).
///
/// * `.node`: `index x y kind id param marker` where the three attributes keep the exact
///   [`VertexMarker`] (kind 0 interior, 1 boundary, 2 corner; id = piece or corner index;
///   param = arc length along the loop; −1 for unknown) and the boundary marker is
///   loop index + 1 (0 for interior vertices).
/// * `.ele`: `index a b c`, counter-clockwise.
/// * `.poly`: no vertices (they are in `.node`), the mesh boundary edges as segments with
///   marker loop index + 1, and one hole point inside each hole loop, so that
///   `triangle -p base` re-meshes the same region.
///
/// All three files appear together or not at all.
pub fn write_triangle(mesh: &Mesh, base: &Path) -> Result<(), MeshError> {
    validate_for_writing(mesh, &with_suffix(base, "node"))?;
    write_nodes(&Nodes::linear(mesh, None), base)
}

/// [`write_triangle`] for a mesh of `region`: where the region names its walls by number
/// ([`geometry::Region::piece_markers`], a `.poly`'s segment markers), the boundary markers
/// are those numbers, as Triangle passes its input's markers on: each `.poly` segment carries
/// its wall's, each boundary vertex the marker of the boundary edge it starts (a corner takes
/// the wall that leaves it, counter-clockwise along an outer loop), and the loop index moves
/// to a fourth vertex attribute. Without such numbers the files are [`write_triangle`]'s.
///
/// ```
/// use cvtmesh::io;
/// use cvtmesh::geometry::formats::poly_from_str;
/// // The unit square, its bottom marked 5 and the rest 7.
/// let poly = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 1\n1 1 2 5\n2 2 3 7\n3 3 4 7\n4 4 1 7\n0\n";
/// let region = poly_from_str(poly, "square.poly", "square")?;
/// let points: Vec<cvtmesh::geometry::DVec2> = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(cvtmesh::geometry::DVec2::from).to_vec();
/// let triangles = vec![[0, 1, 2], [0, 2, 3]];
/// let markers = io::markers_from_topology(&points, &triangles);
/// let mut mesh = cvtmesh::Mesh { points, triangles, markers };
/// io::restore_markers(&mut mesh, &region);
/// let base = std::env::temp_dir().join(format!("cvtmesh-doc-walls-{}", std::process::id()));
/// io::write_triangle_on(&mesh, &region, &base)?;
/// let poly = std::fs::read_to_string(base.with_extension("poly"))?;
/// let markers: Vec<&str> = poly.lines().filter(|l| !l.starts_with('#')).skip(2).take(4)
///     .map(|l| l.split_whitespace().last().unwrap()).collect();
/// assert_eq!(markers, ["5", "7", "7", "7"]);
/// // Read back, the mesh is the same, its vertices on the same loops.
/// let back = io::read_mesh(&base.with_extension("node"))?;
/// assert_eq!((back.points, back.markers), (mesh.points, mesh.markers));
/// for ext in ["node", "ele", "poly"] {
///     std::fs::remove_file(base.with_extension(ext))?;
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_triangle_on(
    mesh: &Mesh,
    region: &geometry::Region,
    base: &Path,
) -> Result<(), MeshError> {
    validate_for_writing(mesh, &with_suffix(base, "node"))?;
    write_nodes(&Nodes::linear(mesh, Some(region)), base)
}

/// Write `nodes` as [`write_triangle`] does; six-node triangles list their corners, then the
/// node opposite each corner (Triangle's `-o2` order), and the `.poly` keeps two-node segments.
pub(crate) fn write_nodes(nodes: &Nodes, base: &Path) -> Result<(), MeshError> {
    let node = with_suffix(base, "node");
    let mesh = nodes.linear;
    let segments: Vec<Vec<(u32, u32)>> = nodes
        .lines
        .iter()
        .map(|lines| lines.iter().map(|l| (l[0], l[1])).collect())
        .collect();
    let holes: Vec<DVec2> = segments
        .iter()
        .skip(1)
        .filter_map(|edges| hole_point(mesh, edges))
        .collect();
    // Triangle's order: corners, then the nodes of edges bc, ca, ab.
    let order: &[usize] = if nodes.per_triangle() == 6 {
        &[0, 1, 2, 4, 5, 3]
    } else {
        &[0, 1, 2]
    };
    let walls = nodes.wall_markers();
    let write_node: Producer = Box::new(|w: &mut dyn Write| {
        writeln!(w, "{SIGNATURE}: {} vertices.", nodes.points.len())?;
        let (nattr, last) = match walls {
            None => (3, " | boundary marker (loop index + 1, 0 interior)"),
            Some(_) => (4, ", loop index + 1 (0 interior) | boundary marker (the region's wall number, 0 interior)"),
        };
        writeln!(
            w,
            "# index x y | attributes: kind (0 interior, 1 boundary, 2 corner), piece or corner index, \
             loop arc-length parameter (-1 unknown){last}"
        )?;
        writeln!(w, "{} 2 {nattr} 1", nodes.points.len())?;
        write_lines(w, nodes.points.len(), |i, s| {
            let (p, m) = (nodes.points[i], &nodes.markers[i]);
            let (kind, id, param, marker) = match *m {
                VertexMarker::Interior => (0, 0i64, 0.0, 0),
                VertexMarker::Boundary {
                    loop_index,
                    piece,
                    loop_param,
                } => (1, known_id(piece), known_param(loop_param), loop_index + 1),
                VertexMarker::Corner {
                    loop_index,
                    corner,
                    loop_param,
                } => (2, known_id(corner), known_param(loop_param), loop_index + 1),
            };
            // "{i + 1} {x} {y} {kind} {id} {param} {marker}[ {wall}]", field by field.
            push_int(s, i as i64 + 1);
            for x in [p.x, p.y] {
                s.push(' ');
                push_float(s, x);
            }
            for n in [kind, id] {
                s.push(' ');
                push_int(s, n);
            }
            s.push(' ');
            push_float(s, param);
            s.push(' ');
            push_int(s, marker as i64);
            if let Some((_, by_node)) = &walls {
                s.push(' ');
                push_int(s, by_node[i]);
            }
            s.push('\n');
        })
    });
    let write_ele: Producer = Box::new(|w: &mut dyn Write| {
        writeln!(
            w,
            "# Triangle .ele written by cvtmesh: {} counter-clockwise triangles.",
            nodes.triangles.len()
        )?;
        // A subdomain's number is the triangle's attribute, as Triangle's -A writes it.
        let subdomains = nodes.subdomains.as_deref();
        writeln!(
            w,
            "{} {} {}",
            nodes.triangles.len(),
            order.len(),
            usize::from(subdomains.is_some())
        )?;
        write_lines(w, nodes.triangles.len(), |t, s| {
            let tri = &nodes.triangles[t];
            push_int(s, t as i64 + 1);
            for &k in order {
                s.push(' ');
                push_int(s, i64::from(tri[k]) + 1);
            }
            if let Some(ids) = subdomains {
                s.push(' ');
                push_int(s, ids[t]);
            }
            s.push('\n');
        })
    });
    let write_poly: Producer = Box::new(|w: &mut dyn Write| {
        writeln!(
            w,
            "# Triangle .poly written by cvtmesh: vertices are in the .node file beside it."
        )?;
        writeln!(w, "0 2 0 1")?;
        let nseg: usize = segments.iter().map(Vec::len).sum::<usize>() + nodes.inner.len();
        writeln!(
            w,
            "# segments: the mesh boundary edges, {}",
            if walls.is_some() {
                "marker = the region's wall number"
            } else {
                LOOP_SEGMENTS
            }
        )?;
        writeln!(w, "{nseg} 1")?;
        let mut k = 0;
        for (l, edges) in segments.iter().enumerate() {
            for (e, &(a, b)) in edges.iter().enumerate() {
                k += 1;
                let marker = walls
                    .as_ref()
                    .map_or(l as i64 + 1, |(by_line, _)| by_line[l][e]);
                writeln!(w, "{k} {} {} {marker}", a + 1, b + 1)?;
            }
        }
        if !nodes.inner.is_empty() {
            writeln!(
                w,
                "# the edges along the region's embedded lines, marker = the line's"
            )?;
        }
        for (line, marker) in &nodes.inner {
            k += 1;
            writeln!(w, "{k} {} {} {marker}", line[0] + 1, line[1] + 1)?;
        }
        writeln!(w, "# holes: a point inside each hole loop")?;
        writeln!(w, "{}", holes.len())?;
        for (h, p) in holes.iter().enumerate() {
            writeln!(w, "{} {} {}", h + 1, F(p.x), F(p.y))?;
        }
        // A point in each subdomain with its number (no area bound): Triangle's `-pA` on
        // this file numbers its triangles as the `.ele` beside it does.
        if let Some(ids) = &nodes.subdomains {
            let points = crate::subdomain_points_of(nodes.linear, ids);
            writeln!(
                w,
                "# regional attributes: a point in each subdomain, its number"
            )?;
            writeln!(w, "{}", points.len())?;
            for (r, (p, id)) in points.iter().enumerate() {
                writeln!(w, "{} {} {} {id} -1", r + 1, F(p.x), F(p.y))?;
            }
        }
        Ok(())
    });
    write_files(vec![
        (node, write_node),
        (with_suffix(base, "ele"), write_ele),
        (with_suffix(base, "poly"), write_poly),
    ])
}

fn known_id(id: usize) -> i64 {
    if id == UNKNOWN_PIECE {
        -1
    } else {
        id as i64
    }
}

fn known_param(p: f64) -> f64 {
    if p.is_finite() {
        p
    } else {
        -1.0
    }
}

/// A point just outside the mesh across one of the edges of a hole loop (the mesh lies left of
/// its boundary edges, so the hole is on the right), checked to be in no triangle.
fn hole_point(mesh: &Mesh, edges: &[(u32, u32)]) -> Option<DVec2> {
    let inside_any = |q: DVec2| {
        (0..mesh.triangles.len()).any(|t| {
            let [a, b, c] = mesh.triangle(t);
            let s = [
                (b - a).perp_dot(q - a),
                (c - b).perp_dot(q - b),
                (a - c).perp_dot(q - c),
            ];
            s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
        })
    };
    for &(a, b) in edges.iter().take(8) {
        let (pa, pb) = (mesh.points[a as usize], mesh.points[b as usize]);
        let d = pb - pa;
        let right = DVec2::new(d.y, -d.x);
        for f in [0.1, 1e-2, 1e-3, 1e-4] {
            let q = (pa + pb) * 0.5 + right * f;
            if !inside_any(q) {
                return Some(q);
            }
        }
    }
    None
}

/// [`read_triangle`], and the boundary edges the `.poly` beside `node_path` numbers, by their
/// end vertices as the mesh numbers them, each file read once: the segments and their markers, as Triangle writes them
/// with `-p` (its input's segment markers passed on) and [`write_triangle_on`] with a
/// region's numbered walls. Empty where there is no `.poly`, its segments have no markers, or
/// it is one of ours whose markers are loop numbers ([`write_triangle`]). A segment may name
/// the `.node`'s vertices or list its own (matched to the mesh's by their coordinates); one
/// whose ends are not both mesh vertices is left out.
///
/// ```
/// use cvtmesh::io;
/// let dir = std::env::temp_dir().join(format!("cvtmesh-doc-tri-walls-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// // Triangle's output for the unit square: its bottom segment marked 7, the rest 9.
/// std::fs::write(dir.join("sq.node"), "4 2 0 1\n1 0 0 7\n2 1 0 7\n3 1 1 9\n4 0 1 9\n")?;
/// std::fs::write(dir.join("sq.ele"), "2 3 0\n1 1 2 3\n2 1 3 4\n")?;
/// std::fs::write(dir.join("sq.poly"), "0 2 0 1\n4 1\n1 1 2 7\n2 2 3 9\n3 3 4 9\n4 4 1 9\n0\n")?;
/// let (mesh, walls) = io::read_triangle_with_walls(&dir.join("sq.node"))?;
/// assert_eq!(mesh.num_triangles(), 2);
/// assert_eq!(walls.edges, [([0, 1], 7), ([1, 2], 9), ([2, 3], 9), ([3, 0], 9)]);
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_triangle_with_walls(node_path: &Path) -> Result<(Mesh, Walls), MeshError> {
    read_triangle_file(node_path).map(|f| (f.mesh, f.walls))
}

/// [`read_triangle_with_walls`], with the triangles' node count and a six-node file's edge
/// nodes.
pub(crate) fn read_triangle_file(node_path: &Path) -> Result<MeshFile, MeshError> {
    let node = read_text(node_path)?;
    let ele_path = node_path.with_extension("ele");
    let ele = read_ele_of(&ele_path, node_path)?;
    let (mesh, given) = parse_mesh(&node, &ele, node_path, &ele_path)?;
    let poly_path = node_path.with_extension("poly");
    let mut walls = match poly_path.is_file() {
        true => walls_of(&read_text(&poly_path)?, &poly_path, &given, &mesh)?,
        false => Walls {
            inner: super::inner_edges(&mesh, &given.regions, &[]),
            ..Walls::default()
        },
    };
    walls.subdomains = super::whole_numbers(&given.regions);
    Ok(MeshFile {
        mesh,
        walls,
        triangle_nodes: if given.points.is_some() { 6 } else { 3 },
        edge_nodes: given.edge_nodes,
    })
}

/// The walls of [`read_triangle_with_walls`] from the texts of a `.node`, its `.ele` and the `.poly` beside
/// them; errors name `mesh.node`, `mesh.ele` and `mesh.poly`. The nonzero markers of the
/// `.node`'s boundary vertices are its marked points ([`Walls::points`]), where the `.poly`
/// numbers walls.
///
/// ```
/// // The unit square of two triangles, walls 1 but the bottom (2); vertex 3 marked 5.
/// let node = "4 2 0 1\n1 0 0 2\n2 1 0 1\n3 1 1 5\n4 0 1 1\n";
/// let ele = "2 3 0\n1 1 2 3\n2 1 3 4\n";
/// let poly = "0 2 0 1\n4 1\n1 1 2 2\n2 2 3 1\n3 3 4 1\n4 4 1 1\n0\n";
/// let walls = cvtmesh::io::triangle_walls_from_str(node, ele, poly)?;
/// assert_eq!(walls.edges, [([0, 1], 2), ([1, 2], 1), ([2, 3], 1), ([3, 0], 1)]);
/// assert_eq!(walls.points, [(0, 2), (1, 1), (2, 5), (3, 1)]);
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn triangle_walls_from_str(node: &str, ele: &str, poly: &str) -> Result<Walls, MeshError> {
    let paths = ["mesh.node", "mesh.ele", "mesh.poly"].map(Path::new);
    let (mesh, given) = parse_mesh(node, ele, paths[0], paths[1])?;
    let mut walls = walls_of(poly, paths[2], &given, &mesh)?;
    walls.subdomains = super::whole_numbers(&given.regions);
    Ok(walls)
}

/// The `.node`'s own vertices (where they are not the mesh's: a six-node mesh's) and its
/// numbering base, which a `.poly` beside it refers to.
struct GivenVertices {
    points: Option<Vec<DVec2>>,
    base: usize,
    /// The `.node`'s boundary markers (empty without a marker column).
    markers: Vec<i64>,
    /// A six-node mesh's edge nodes, by the edge's ends as the mesh numbers them.
    edge_nodes: Vec<([u32; 2], DVec2)>,
    /// Each triangle's first `.ele` attribute, by its bits (empty without attributes).
    regions: Vec<i64>,
}

/// The walls the `.poly` text `poly` numbers on `mesh`, whose `.node` listed `given`.
fn walls_of(
    poly: &str,
    poly_path: &Path,
    given: &GivenVertices,
    mesh: &Mesh,
) -> Result<Walls, MeshError> {
    // Between triangles of different materials, whatever the `.poly` says.
    let by_regions = || Walls {
        inner: super::inner_edges(mesh, &given.regions, &[]),
        ..Walls::default()
    };
    // cvtmesh's own `.poly` of a region that numbers no walls marks its boundary segments with
    // their loop: no walls, but its segments inside the mesh are lines still.
    let loop_markers = poly.contains(LOOP_SEGMENTS);
    let mut t = Tokens::new(poly, Some('#'), poly_path);
    let n = t.usize("the number of vertices")?;
    t.usize("the dimension")?;
    let nattr = t.usize("the number of attributes")?;
    let nmark = t.usize("the number of boundary markers (0 or 1)")?;
    let mut own = Vec::with_capacity(n.min(1 << 20));
    let mut own_base = 0;
    for i in 0..n {
        let idx = t.usize("a vertex number")?;
        if i == 0 {
            own_base = idx;
        }
        let p = DVec2::new(t.f64("x")?, t.f64("y")?);
        for _ in 0..nattr + nmark.min(1) {
            t.f64("an attribute or marker")?;
        }
        own.push(p);
    }
    let (vertices, first) = if n == 0 {
        (given.points.as_ref().unwrap_or(&mesh.points), given.base)
    } else {
        (&own, own_base)
    };
    let nseg = t.usize("the number of segments")?;
    let marked = t.usize("the number of segment markers (0 or 1)")? > 0;
    let mut segments = Vec::with_capacity(nseg.min(1 << 20));
    for _ in 0..nseg {
        let line = t.line_no();
        t.usize("a segment number")?;
        let mut end = || -> Result<DVec2, MeshError> {
            let v = t.usize("a segment end point")?;
            v.checked_sub(first)
                .and_then(|k| vertices.get(k))
                .copied()
                .ok_or_else(|| t.err_line(line, format!("segment end point {v} is not a vertex")))
        };
        let (a, b) = (end()?, end()?);
        let marker = if marked {
            t.i64("a segment marker")?
        } else {
            0
        };
        segments.push((a, b, marker));
    }
    let index: std::collections::HashMap<(u64, u64), u32> = mesh
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| ((p.x.to_bits(), p.y.to_bits()), i as u32))
        .collect();
    let at = |p: DVec2| index.get(&(p.x.to_bits(), p.y.to_bits())).copied();
    // Segments between two of the mesh's vertices: those two triangles share are internal
    // segments (Triangle's `-p` keeps them as edges, as a material interface).
    let lines: Vec<[u32; 2]> = segments
        .iter()
        .filter_map(|&(a, b, _)| Some([at(a)?, at(b)?]))
        .collect();
    let inner = super::inner_edges(mesh, &given.regions, &lines);
    let with_markers: Vec<([u32; 2], i64)> = segments
        .iter()
        .filter_map(|&(a, b, m)| Some(([at(a)?, at(b)?], m)))
        .collect();
    let inner_markers = super::inner_markers(&inner, &with_markers);
    let walls = match boundary_walls(mesh, &segments) {
        Some(walls) if marked && !loop_markers => walls,
        // Not this mesh's segments: the region Triangle was given (its `.poly` beside the mesh
        // it made, which Triangle itself names `box.1.node`), or a file of another mesh.
        None => return Ok(by_regions()),
        Some(_) => {
            return Ok(Walls {
                inner,
                inner_markers,
                ..Walls::default()
            })
        }
    };
    // The `.node`'s nonzero markers of boundary vertices: those that differ from the walls at
    // their vertex are points of their own. Inside, Triangle marks the vertices of internal
    // segments too, which are no points anyone placed: those are not read.
    let nodes = given.points.as_ref().unwrap_or(&mesh.points);
    let points = nodes
        .iter()
        .zip(&given.markers)
        .filter(|(_, &m)| m != 0)
        .filter_map(|(p, &m)| Some((at(*p)?, m)))
        .filter(|&(v, _)| mesh.markers[v as usize].on_boundary())
        .collect();
    Ok(Walls {
        edges: walls,
        points,
        inner,
        inner_markers,
        ..Walls::default()
    })
}

/// Each boundary edge of `mesh` with the marker of the `.poly` segment between its ends; `None`
/// if some boundary edge is no segment: the segments are not of this mesh's boundary.
fn boundary_walls(mesh: &Mesh, segments: &[(DVec2, DVec2, i64)]) -> Option<Vec<([u32; 2], i64)>> {
    use std::collections::HashMap;
    let key = |p: DVec2| (p.x.to_bits(), p.y.to_bits());
    let exact: HashMap<_, i64> = segments
        .iter()
        .flat_map(|&(a, b, m)| [((key(a), key(b)), m), ((key(b), key(a)), m)])
        .collect();
    mesh.boundary_edges()
        .iter()
        .map(|e| {
            let (u, v) = (mesh.points[e.a as usize], mesh.points[e.b as usize]);
            let marker = exact.get(&(key(u), key(v))).copied()?;
            Some(([e.a, e.b], marker))
        })
        .collect()
}

/// Read a Triangle mesh: `node_path` (the `.node` file) and the `.ele` file beside it.
///
/// Accepts 0- or 1-based numbering, `#` comments, any number of attribute columns, with or
/// without a boundary-marker column, and second-order (6-node) triangles (their corners; the
/// nodes on edges are dropped).
/// Markers: files written by [`write_triangle`] restore the exact [`VertexMarker`]s; for other
/// files they come from the mesh topology ([`super::markers_from_topology`]), since the meaning
/// of foreign markers is up to their author.
pub fn read_triangle(node_path: &Path) -> Result<Mesh, MeshError> {
    let node_text = read_text(node_path)?;
    let ele_path = node_path.with_extension("ele");
    let ele_text = read_ele_of(&ele_path, node_path)?;
    Ok(parse_mesh(&node_text, &ele_text, node_path, &ele_path)?.0)
}

/// The mesh of a `.node` and an `.ele` text, errors naming the two paths, and the vertices
/// the `.node` listed.
fn parse_mesh(
    node: &str,
    ele: &str,
    node_path: &Path,
    ele_path: &Path,
) -> Result<(Mesh, GivenVertices), MeshError> {
    let (points, base, exact, _, column) = parse_node(node, node_path)?;
    let (mut triangles, opposite, regions) = parse_ele(ele, ele_path, points.len(), base)?;
    let second = opposite.is_some();
    let mut given = GivenVertices {
        points: second.then(|| points.clone()),
        base,
        markers: column,
        edge_nodes: Vec::new(),
        regions,
    };
    let (corners, exact) = corners_of(second, points, &mut triangles, exact.unwrap_or_default());
    // Each edge's node, by the edge's ends as the mesh numbers them: the node opposite a
    // corner lies on the edge of the other two.
    if let (Some(opposite), Some(all)) = (opposite, &given.points) {
        for (t, far) in triangles.iter().zip(opposite) {
            for k in 0..3 {
                let (a, b) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                given
                    .edge_nodes
                    .push(([a.min(b), a.max(b)], all[far[k] as usize]));
            }
        }
        given.edge_nodes.sort_unstable_by_key(|e| e.0);
        given.edge_nodes.dedup_by_key(|e| e.0);
    }
    let mesh = read_mesh_parts(corners, triangles, (!exact.is_empty()).then_some(exact));
    Ok((mesh, given))
}

/// The text of `ele_path`, its errors saying whose triangles it holds.
fn read_ele_of(ele_path: &Path, node_path: &Path) -> Result<String, MeshError> {
    read_text(ele_path).map_err(|e| match e {
        MeshError::File { path, message } => MeshError::File {
            path,
            message: format!("{message} (the triangles of {})", node_path.display()),
        },
        MeshError::Io { path, cause, .. } => MeshError::Io {
            path,
            action: format!("read the triangles of {}", node_path.display()),
            cause,
        },
        e => e,
    })
}

/// Parse a Triangle mesh from the texts of its `.node` and `.ele` files, as [`read_triangle`]
/// reads them; errors name `mesh.node` and `mesh.ele`.
///
/// ```
/// let m = cvtmesh::io::triangle_from_str("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "1 3 0\n1 1 2 3\n")?;
/// assert_eq!((m.num_vertices(), m.num_triangles()), (3, 1));
/// assert!(cvtmesh::io::triangle_from_str("3 2 0 0\n", "").is_err());
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn triangle_from_str(node_text: &str, ele_text: &str) -> Result<Mesh, MeshError> {
    let (node_path, ele_path) = (Path::new("mesh.node"), Path::new("mesh.ele"));
    Ok(parse_mesh(node_text, ele_text, node_path, ele_path)?.0)
}

/// A Triangle mesh and a size at each vertex, its first attribute (a background mesh for a
/// graded mesh, [`geometry::SizeField::from_mesh`]): `node_path` and the `.ele` beside it,
/// read as [`read_triangle`] reads them.
pub fn read_triangle_sizes(node_path: &Path) -> Result<(Mesh, Vec<f64>), MeshError> {
    let node_text = read_text(node_path)?;
    let ele_path = node_path.with_extension("ele");
    let ele_text = read_ele_of(&ele_path, node_path)?;
    sizes_from(&node_text, &ele_text, node_path, &ele_path)
}

/// [`read_triangle_sizes`] from the texts of the two files; errors name `mesh.node` and
/// `mesh.ele`.
///
/// ```
/// use cvtmesh::io::triangle_sizes_from_str;
/// let node = "3 2 1 0\n1 0 0 0.1\n2 1 0 0.2\n3 0 1 0.3\n";
/// let (m, h) = triangle_sizes_from_str(node, "1 3 0\n1 1 2 3\n")?;
/// assert_eq!((m.num_triangles(), h), (1, vec![0.1, 0.2, 0.3]));
/// // Without an attribute there is no size to read.
/// let e = triangle_sizes_from_str("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "1 3 0\n1 1 2 3\n");
/// assert!(e.unwrap_err().to_string().contains("no attribute"));
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn triangle_sizes_from_str(
    node_text: &str,
    ele_text: &str,
) -> Result<(Mesh, Vec<f64>), MeshError> {
    sizes_from(
        node_text,
        ele_text,
        Path::new("mesh.node"),
        Path::new("mesh.ele"),
    )
}

fn sizes_from(
    node_text: &str,
    ele_text: &str,
    node_path: &Path,
    ele_path: &Path,
) -> Result<(Mesh, Vec<f64>), MeshError> {
    let (points, base, exact, sizes, _) = parse_node(node_text, node_path)?;
    if exact.is_some() {
        return Err(file_err(
            node_path,
            "its attributes are cvtmesh's vertex markers, not sizes; give the size at each \
             vertex as the first attribute of a .node file of your own",
        ));
    }
    if sizes.len() != points.len() {
        return Err(file_err(
            node_path,
            "the vertices have no attribute: the size at each vertex is read from the first \
             attribute column",
        ));
    }
    if let Some((i, h)) = sizes
        .iter()
        .enumerate()
        .find(|(_, &h)| !(h > 0.0 && h < f64::INFINITY))
    {
        return Err(file_err(
            node_path,
            format!(
                "the size of vertex {} is {h}; sizes must be positive and finite",
                i + base
            ),
        ));
    }
    let (mut triangles, opposite, _) = parse_ele(ele_text, ele_path, points.len(), base)?;
    let (points, sizes) = corners_of(opposite.is_some(), points, &mut triangles, sizes);
    Ok((read_mesh_parts(points, triangles, None), sizes))
}

/// Vertices, the index base, our exact markers, and the first attribute of every vertex
/// (empty without attributes).
/// Vertices, the index base (0 or 1), the exact markers when the file is one of ours, the
/// first attribute of each vertex (if any) and the boundary-marker column (empty without one).
type NodeFile = (
    Vec<DVec2>,
    usize,
    Option<Vec<VertexMarker>>,
    Vec<f64>,
    Vec<i64>,
);

/// Vertices, the index base (0 or 1), and the exact markers when the file is one of ours.
fn parse_node(text: &str, path: &Path) -> Result<NodeFile, MeshError> {
    let mut t = Tokens::new(text, Some('#'), path);
    let n = t.usize("the number of vertices")?;
    let dim = t.usize("the dimension")?;
    if dim != 2 {
        return Err(t.err(format!("dimension is {dim}; only 2 is supported")));
    }
    let nattr = t.usize("the number of attributes")?;
    let nmark = t.usize("the number of boundary markers (0 or 1)")?;
    if nmark > 1 {
        return Err(t.err(format!(
            "{nmark} boundary-marker columns; Triangle allows 0 or 1"
        )));
    }
    // Our files keep the loop in the marker column, or (when the marker column holds the
    // region's wall numbers) in a fourth attribute.
    let ours = text.starts_with(SIGNATURE) && (nattr == 3 || nattr == 4) && nmark == 1;
    let mut points = Vec::with_capacity(n.min(1 << 20));
    let mut markers = Vec::with_capacity(if ours { n.min(1 << 20) } else { 0 });
    let mut first_attr = Vec::with_capacity(if nattr > 0 { n.min(1 << 20) } else { 0 });
    let mut column = Vec::with_capacity(if nmark == 1 { n.min(1 << 20) } else { 0 });
    let mut base = 0;
    for i in 0..n {
        let line = t.line_no();
        let idx = t.usize("a vertex number")?;
        if i == 0 {
            if idx > 1 {
                return Err(t.err_line(
                    line,
                    format!("first vertex is numbered {idx}; Triangle numbers from 0 or 1"),
                ));
            }
            base = idx;
        } else if idx != base + i {
            return Err(t.err_line(
                line,
                format!(
                    "vertex number {idx}, expected {} (consecutive numbering)",
                    base + i
                ),
            ));
        }
        let x = t.f64("x")?;
        let y = t.f64("y")?;
        points.push(DVec2::new(x, y));
        let mut attrs = [0.0; 4];
        for a in 0..nattr {
            let v = t.f64("an attribute")?;
            if let Some(slot) = attrs.get_mut(a) {
                *slot = v;
            }
        }
        if nattr > 0 {
            first_attr.push(attrs[0]);
        }
        let marker = if nmark == 1 {
            let m = t.i64("a boundary marker")?;
            column.push(m);
            m
        } else {
            0
        };
        if ours {
            let (attrs, marker) = match attrs {
                [kind, id, param, l] if nattr == 4 && l.fract() == 0.0 && l.abs() < 9.0e15 => {
                    ([kind, id, param], l as i64)
                }
                [_, _, _, _] if nattr == 4 => {
                    return Err(t.err_line(line, "marker attributes are inconsistent"))
                }
                [kind, id, param, _] => ([kind, id, param], marker),
            };
            match decode_marker(attrs, marker) {
                Some(m) => markers.push(m),
                None => return Err(t.err_line(line, "marker attributes are inconsistent")),
            }
        }
    }
    Ok((points, base, ours.then_some(markers), first_attr, column))
}

/// Inverse of the attribute encoding of [`write_triangle`].
fn decode_marker([kind, id, param]: [f64; 3], marker: i64) -> Option<VertexMarker> {
    let id = if id == -1.0 {
        UNKNOWN_PIECE
    } else if id >= 0.0 && id.fract() == 0.0 && id < 9.0e15 {
        id as usize
    } else {
        return None;
    };
    let loop_param = if param == -1.0 { f64::NAN } else { param };
    let loop_index = marker.checked_sub(1).and_then(|l| usize::try_from(l).ok());
    let kind = [0.0, 1.0, 2.0].iter().position(|&k| k == kind)?;
    match (kind, loop_index) {
        (0, None) if marker == 0 => Some(VertexMarker::Interior),
        (1, Some(loop_index)) => Some(VertexMarker::Boundary {
            loop_index,
            piece: id,
            loop_param,
        }),
        (2, Some(loop_index)) => Some(VertexMarker::Corner {
            loop_index,
            corner: id,
            loop_param,
        }),
        _ => None,
    }
}

/// Triangles by three vertices each.
type Triples = Vec<[u32; 3]>;

/// The triangles of an `.ele` file by their corners, and for six-node triangles the node
/// opposite each corner (Triangle's `-o2` order).
fn parse_ele(
    text: &str,
    path: &Path,
    nvert: usize,
    base: usize,
) -> Result<(Triples, Option<Triples>, Vec<i64>), MeshError> {
    let mut t = Tokens::new(text, Some('#'), path);
    let ntri = t.usize("the number of triangles")?;
    let per = t.usize("the number of nodes per triangle")?;
    if per != 3 && per != 6 {
        return Err(t.err(format!(
            "{per} nodes per triangle; only 3 or 6 are supported"
        )));
    }
    let nattr = t.usize("the number of attributes")?;
    let mut triangles = Vec::with_capacity(ntri.min(1 << 20));
    let mut opposite = Vec::with_capacity(if per == 6 { ntri.min(1 << 20) } else { 0 });
    // The first attribute (Triangle's regional attribute, `-A`: a material) by its bits.
    let mut regions = Vec::with_capacity(if nattr > 0 { ntri.min(1 << 20) } else { 0 });
    for _ in 0..ntri {
        let line = t.line_no();
        t.usize("a triangle number")?;
        let mut tri = [0u32; 3];
        let mut far = [0u32; 3];
        for k in 0..per {
            let v = t.usize("a vertex number")?;
            if v < base || v - base >= nvert {
                return Err(t.err_line(
                    line,
                    format!("vertex {v} is out of range (the .node file has {nvert} vertices from {base})"),
                ));
            }
            match k {
                0..3 => tri[k] = (v - base) as u32,
                _ => far[k - 3] = (v - base) as u32,
            }
        }
        for k in 0..nattr {
            let a = t.f64("a triangle attribute")?;
            if k == 0 {
                regions.push(a.to_bits() as i64);
            }
        }
        triangles.push(tri);
        if per == 6 {
            opposite.push(far);
        }
    }
    Ok((triangles, (per == 6).then_some(opposite), regions))
}

/// A six-node mesh's corners: the vertices its triangles' corners use (the nodes on edges are
/// not vertices), with `values` per vertex kept alongside. Nothing changes for three-node
/// triangles.
fn corners_of<T: Copy>(
    second_order: bool,
    points: Vec<DVec2>,
    triangles: &mut [[u32; 3]],
    values: Vec<T>,
) -> (Vec<DVec2>, Vec<T>) {
    if !second_order {
        return (points, values);
    }
    let kept = super::keep_corners(points.len(), triangles);
    let values = if values.len() == points.len() {
        kept.iter().map(|&i| values[i]).collect()
    } else {
        values
    };
    (kept.iter().map(|&i| points[i]).collect(), values)
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;
    use std::fs;

    #[test]
    fn round_trip_is_exact_including_markers() {
        let dir = TempDir::new("tri");
        let m = square_with_hole();
        write_triangle(&m, &dir.path("sq")).unwrap();
        assert_eq!(dir.files(), ["sq.ele", "sq.node", "sq.poly"]);
        // The header names the columns, the marker after the attributes.
        let text = std::fs::read_to_string(dir.path("sq.node")).unwrap();
        assert!(
            text.lines().nth(1).unwrap().ends_with(
                "loop arc-length parameter (-1 unknown) | boundary marker (loop index + 1, 0 interior)"
            ),
            "{text}"
        );
        let r = read_triangle(&dir.path("sq.node")).unwrap();
        assert_eq!(r, m);
        for (a, b) in r.points.iter().zip(&m.points) {
            assert_eq!(
                (a.x.to_bits(), a.y.to_bits()),
                (b.x.to_bits(), b.y.to_bits())
            );
        }
    }

    #[test]
    fn unknown_pieces_and_params_round_trip() {
        let dir = TempDir::new("tri-unknown");
        let mut m = square_with_hole();
        m.markers = super::super::markers_from_topology(&m.points, &m.triangles);
        write_triangle(&m, &dir.path("u")).unwrap();
        let r = read_triangle(&dir.path("u.node")).unwrap();
        assert_eq!(r.markers.len(), m.markers.len());
        for (a, b) in r.markers.iter().zip(&m.markers) {
            assert_eq!(a.loop_index(), b.loop_index());
            if let VertexMarker::Boundary {
                piece, loop_param, ..
            } = *a
            {
                assert_eq!(piece, UNKNOWN_PIECE);
                assert!(loop_param.is_nan());
            }
        }
    }

    /// The region Triangle was given, beside the mesh it made under the same name: its
    /// segments run from corner to corner across the mesh's boundary edges, so they are not
    /// the mesh's walls and are not read as such (they had been applied to the mesh's
    /// vertices by position, making every boundary edge a wall of its own).
    #[test]
    fn a_poly_of_other_segments_beside_a_mesh_is_not_its_walls() {
        let dir = TempDir::new("pslg");
        // The unit square with a vertex halfway along its bottom side.
        fs::write(
            dir.path("m.node"),
            "5 2 0 1\n1 0 0 1\n2 0.5 0 1\n3 1 0 1\n4 1 1 1\n5 0 1 1\n",
        )
        .unwrap();
        fs::write(dir.path("m.ele"), "3 3 0\n1 1 2 5\n2 2 4 5\n3 2 3 4\n").unwrap();
        let pslg = "4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n4 1\n1 1 2 7\n2 2 3 8\n3 3 4 8\n4 4 1 8\n0\n";
        fs::write(dir.path("m.poly"), pslg).unwrap();
        let (mesh, walls) = read_triangle_with_walls(&dir.path("m.node")).unwrap();
        assert_eq!(mesh.num_triangles(), 3);
        assert_eq!(walls, Walls::default());
        // The mesh's own segments, in Triangle's mesh `.poly` (no vertices of its own).
        let own = "0 2 0 1\n5 1\n1 1 2 7\n2 2 3 7\n3 3 4 8\n4 4 5 8\n5 5 1 8\n0\n";
        fs::write(dir.path("m.poly"), own).unwrap();
        let (_, walls) = read_triangle_with_walls(&dir.path("m.node")).unwrap();
        let mut markers: Vec<i64> = walls.edges.iter().map(|e| e.1).collect();
        markers.sort_unstable();
        assert_eq!(markers, [7, 7, 8, 8, 8]);
        assert!(walls.inner.is_empty());
        // With an internal segment from (0.5, 0) to (1, 1), as Triangle's `-p` writes one: an
        // inner edge, no wall.
        let inside = "0 2 0 1\n6 1\n1 1 2 7\n2 2 3 7\n3 3 4 8\n4 4 5 8\n5 5 1 8\n6 2 4 3\n0\n";
        fs::write(dir.path("m.poly"), inside).unwrap();
        let (_, walls) = read_triangle_with_walls(&dir.path("m.node")).unwrap();
        assert_eq!((walls.edges.len(), walls.inner.clone()), (5, vec![[1, 3]]));
        // Materials in the `.ele` (its first attribute) meet along that edge too.
        fs::remove_file(dir.path("m.poly")).unwrap();
        fs::write(
            dir.path("m.ele"),
            "3 3 1\n1 1 2 5 1\n2 2 4 5 1\n3 2 3 4 2\n",
        )
        .unwrap();
        let (_, walls) = read_triangle_with_walls(&dir.path("m.node")).unwrap();
        assert_eq!(walls.inner, [[1, 3]]);
    }

    #[test]
    fn poly_lists_boundary_segments_and_a_point_in_the_hole() {
        let dir = TempDir::new("tri-poly");
        let m = square_with_hole();
        write_triangle(&m, &dir.path("sq")).unwrap();
        let poly = fs::read_to_string(dir.path("sq.poly")).unwrap();
        let rows: Vec<Vec<f64>> = poly
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows[0], [0.0, 2.0, 0.0, 1.0]);
        assert_eq!(rows[1], [32.0, 1.0], "24 outer + 8 hole edges");
        let segs = &rows[2..34];
        assert_eq!(segs.iter().filter(|s| s[3] == 1.0).count(), 24);
        assert_eq!(segs.iter().filter(|s| s[3] == 2.0).count(), 8);
        for s in segs {
            let (a, b) = (s[1] as usize - 1, s[2] as usize - 1);
            assert_eq!(m.markers[a].loop_index(), Some(s[3] as usize - 1));
            assert_eq!(m.markers[b].loop_index(), Some(s[3] as usize - 1));
        }
        assert_eq!(rows[34], [1.0]);
        let (hx, hy) = (rows[35][1], rows[35][2]);
        assert!(
            hx > 1.0 && hx < 2.0 && hy > 1.0 && hy < 2.0,
            "hole point ({hx}, {hy})"
        );
    }

    #[test]
    fn reads_zero_based_files_with_comments_attributes_and_cw_triangles() {
        let dir = TempDir::new("tri-foreign");
        // A unit square split into two triangles, one of them clockwise; 0-based; one attribute.
        fs::write(
            dir.path("f.node"),
            "# a comment\n4 2 1 1\n0 0 0 7.5 1\n1 1 0 7.5 1 # trailing\n\n2 1 1 7.5 1\n3 0 1 7.5 1\n",
        )
        .unwrap();
        fs::write(dir.path("f.ele"), "2 3 1\n0 0 1 2 9\n1 0 3 2 9\n").unwrap();
        let r = read_triangle(&dir.path("f.node")).unwrap();
        assert_eq!(r.points[2], DVec2::new(1.0, 1.0));
        assert_eq!(r.triangles, [[0, 1, 2], [0, 2, 3]]);
        assert!((r.area() - 1.0).abs() < 1e-15);
        assert!(r.markers.iter().all(|m| m.loop_index() == Some(0)));
        // Second-order triangles keep their corners.
        fs::write(dir.path("g.node"), "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n").unwrap();
        fs::write(dir.path("g.ele"), "1 6 0\n1 1 2 3 1 2 3\n").unwrap();
        assert_eq!(
            read_triangle(&dir.path("g.node")).unwrap().triangles,
            [[0, 1, 2]]
        );
    }

    #[test]
    fn bad_files_give_errors_with_line_numbers() {
        let dir = TempDir::new("tri-bad");
        let ele = "1 3 0\n1 1 2 3\n";
        let cases = [
            (
                "3 2 0 0\n1 0 0\n2 1 0\n",
                ele,
                "unexpected end of file",
                "b.node",
            ),
            ("3 3 0 0\n", ele, "dimension is 3", "b.node"),
            (
                "3 2 0 0\n1 0 0\n2 1 x\n3 0 1\n",
                ele,
                "line 3: expected y",
                "b.node",
            ),
            (
                "3 2 0 0\n1 0 0\n3 1 0\n3 0 1\n",
                ele,
                "line 3: vertex number 3, expected 2",
                "b.node",
            ),
            (
                "3 2 0 0\n5 0 0\n",
                ele,
                "line 2: first vertex is numbered 5",
                "b.node",
            ),
            (
                "3 2 0 0\n1 0 0\n2 nan 0\n3 0 1\n",
                ele,
                "line 3: x is not finite",
                "b.node",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n",
                "1 3 0\n1 1 2 4\n",
                "line 2: vertex 4 is out of range",
                "b.ele",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n",
                "1 4 0\n1 1 2 3 4\n",
                "4 nodes per triangle",
                "b.ele",
            ),
            (
                "\u{fffd}garbage",
                ele,
                "expected the number of vertices",
                "b.node",
            ),
        ];
        for (node, ele, want, file) in cases {
            fs::write(dir.path("b.node"), node).unwrap();
            fs::write(dir.path("b.ele"), ele).unwrap();
            let e = read_triangle(&dir.path("b.node")).unwrap_err().to_string();
            assert!(e.contains(want), "{e:?} should contain {want:?}");
            // The file at fault is named, not its partner.
            let other = if file == "b.node" { "b.ele" } else { "b.node" };
            assert!(
                e.contains(file) && !e.contains(other),
                "{e}: should name {file}"
            );
        }
        // Our signature with impossible marker attributes is an error, not a panic.
        for bad in [
            "3 7 0 1",
            "1 0 0 -9223372036854775808",
            "1 2.5 0 1",
            "0 0 0 1",
        ] {
            fs::write(
                dir.path("b.node"),
                format!("{SIGNATURE}\n1 2 3 1\n1 0 0 {bad}\n"),
            )
            .unwrap();
            let e = read_triangle(&dir.path("b.node")).unwrap_err().to_string();
            assert!(
                e.contains("line 3: marker attributes are inconsistent"),
                "{e}"
            );
        }
        fs::remove_file(dir.path("b.ele")).unwrap();
        let e = read_triangle(&dir.path("b.node")).unwrap_err().to_string();
        assert!(e.contains("b.ele") && e.contains("the triangles of"), "{e}");
    }

    proptest::proptest! {
        #[test]
        fn random_bytes_never_panic(node in proptest::collection::vec(proptest::num::u8::ANY, 0..200),
                                    ele in "[0-9 \n#.-]{0,80}") {
            let p = Path::new("r.node");
            if let Ok(text) = std::str::from_utf8(&node) {
                if let Ok((pts, base, _, _, _)) = parse_node(text, p) {
                    let _ = parse_ele(&ele, Path::new("r.ele"), pts.len(), base);
                }
            }
            let _ = parse_node(&format!("3 2 0 0\n{ele}"), p);
            let _ = parse_ele(&ele, Path::new("r.ele"), 3, 1);
        }
    }

    #[test]
    fn a_poly_beside_the_mesh_numbers_its_walls() {
        // The unit square, 0-based, its bottom 7 and the rest 9.
        let node = "4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n";
        let ele = "2 3 0\n0 0 1 2\n1 0 2 3\n";
        let by_node = "0 2 0 0\n4 1\n0 0 1 7\n1 1 2 9\n2 2 3 9\n3 3 0 9\n0\n";
        let want = [([0, 1], 7), ([1, 2], 9), ([2, 3], 9), ([3, 0], 9)];
        assert_eq!(
            triangle_walls_from_str(node, ele, by_node).unwrap().edges,
            want
        );
        // Its own vertices (1-based, in another order), matched by their coordinates.
        let own =
            "4 2 0 0\n1 1 1\n2 0 1\n3 0 0\n4 1 0\n4 1\n1 3 4 7\n2 4 1 9\n3 1 2 9\n4 2 3 9\n0\n";
        assert_eq!(triangle_walls_from_str(node, ele, own).unwrap().edges, want);
        // No markers, or ours naming loops: no walls.
        let unmarked = "0 2 0 1\n4 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n0\n";
        assert!(triangle_walls_from_str(node, ele, unmarked)
            .unwrap()
            .edges
            .is_empty());
        let ours = format!("# segments: the mesh boundary edges, {LOOP_SEGMENTS}\n{by_node}");
        assert!(triangle_walls_from_str(node, ele, &ours)
            .unwrap()
            .edges
            .is_empty());
        // A segment naming no vertex is an error with its line.
        let bad = by_node.replace("3 3 0 9", "3 3 8 9");
        let e = triangle_walls_from_str(node, ele, &bad)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("mesh.poly") && e.contains("line 6") && e.contains("8"),
            "{e}"
        );
    }

    #[test]
    fn sizes_are_the_first_attribute_and_markers_are_not_sizes() {
        let node = "# a background mesh\n4 2 2 1\n0 0 0 0.1 7 1\n1 1 0 0.2 7 1\n2 1 1 0.3 7 1\n3 0 1 0.4 7 1\n";
        let ele = "2 3 0\n0 0 1 2\n1 0 2 3\n";
        let (m, h) = triangle_sizes_from_str(node, ele).unwrap();
        assert_eq!((m.num_vertices(), m.num_triangles()), (4, 2));
        assert_eq!(h, [0.1, 0.2, 0.3, 0.4]);
        // A bad size is named by the file's own vertex number.
        let e = triangle_sizes_from_str(&node.replace("2 1 1 0.3", "2 1 1 0"), ele).unwrap_err();
        assert!(e.to_string().contains("size of vertex 2 is 0"), "{e}");
        // A file of ours keeps markers in its attributes.
        let dir = TempDir::new("tri-sizes");
        let base = dir.path("ours");
        write_triangle(&square_with_hole(), &base).unwrap();
        let e = read_triangle_sizes(&base.with_extension("node")).unwrap_err();
        assert!(e.to_string().contains("vertex markers, not sizes"), "{e}");
    }
}
