//! Mesh file formats (Triangle .node/.ele, Gmsh .msh 4.1, VTK .vtu, Wavefront .obj).
//! Writers go through a temp file and rename so a failure never leaves a partial file.
//!
//! | extension | write | read |
//! |---|---|---|
//! | `.node`, `.ele` (+ `.poly`) | [`write_triangle`] | [`read_triangle`] |
//! | `.msh` | [`write_gmsh`] (4.1 ASCII) | [`read_gmsh`] (4.1 and 2.2, ASCII and binary) |
//! | `.vtu` | [`write_vtu`] (XML ASCII, with quality fields) | [`read_vtu`] (ASCII, binary, appended; zlib) |
//! | `.obj` | [`write_obj`] | [`read_obj`] |
//!
//! Coordinates are written in Rust's shortest round-trip notation, so writing and reading back
//! reproduces every coordinate bit for bit.
//!
//! Boundary markers: the Triangle files written here keep the full [`VertexMarker`] (as node
//! attributes). The other formats keep only which loop a boundary vertex lies on; a mesh read
//! from them (or from a foreign file) carries [`UNKNOWN_PIECE`] and a NaN `loop_param` in its
//! boundary markers, and [`restore_markers`] fills these in from the region.
use crate::{Mesh, MeshError, Quadratic, VertexMarker};
use geometry::{DVec2, PieceId, Region};
use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

mod gmsh;
mod gmsh_binary;
mod obj;
mod triangle;
mod vtu;

pub use gmsh::{
    gmsh_from_bytes, gmsh_from_str, gmsh_sizes_from_bytes, gmsh_sizes_from_str,
    gmsh_walls_from_bytes, gmsh_walls_from_str, read_gmsh, read_gmsh_sizes, read_gmsh_with_walls,
    write_gmsh, write_gmsh_on,
};
pub use obj::{obj_from_str, read_obj, write_obj};
pub use triangle::{
    read_triangle, read_triangle_sizes, read_triangle_with_walls, triangle_from_str,
    triangle_sizes_from_str, triangle_walls_from_str, write_triangle, write_triangle_on,
};
pub use vtu::{read_vtu, triangle_quality, vtu_from_bytes, write_vtu};

/// The `piece` of a boundary marker read from a file that does not record pieces.
pub const UNKNOWN_PIECE: PieceId = usize::MAX;

/// Extensions [`write_mesh`] understands.
pub const WRITE_EXTENSIONS: &[&str] = &["node", "ele", "poly", "msh", "vtu", "obj"];
/// Extensions [`read_mesh`] understands.
pub const READ_EXTENSIONS: &[&str] = &["node", "ele", "msh", "vtu", "obj"];

/// Write `mesh` in the format named by the extension of `path`: `.node` or `.ele` (Triangle:
/// writes `.node`, `.ele` and `.poly` beside each other), `.msh` (Gmsh 4.1), `.vtu` (VTK) or
/// `.obj` (Wavefront). Pictures (`.svg`, `.png`) are the render crate's.
///
/// ```
/// use cvtmesh::io::{read_mesh, write_mesh};
/// use cvtmesh::{Mesh, MeshError, VertexMarker};
/// use cvtmesh::geometry::DVec2;
///
/// let corner = |i: usize| VertexMarker::Corner { loop_index: 0, corner: i, loop_param: i as f64 };
/// let mesh = Mesh {
///     points: [(0.0, 0.0), (1.0, 0.0), (0.1, 0.7), (0.4, 0.3)]
///         .map(|(x, y)| DVec2::new(x, y))
///         .to_vec(),
///     triangles: vec![[0, 1, 3], [1, 2, 3], [2, 0, 3]],
///     markers: vec![corner(0), corner(1), corner(2), VertexMarker::Interior],
/// };
/// let dir = std::env::temp_dir().join(format!("cvtmesh-doc-io-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// // Triangle files keep every coordinate and marker exactly.
/// write_mesh(&mesh, &dir.join("m.node"))?;
/// assert_eq!(read_mesh(&dir.join("m.node"))?, mesh);
/// // An unknown extension is a file error naming the file.
/// let e = write_mesh(&mesh, &dir.join("m.xyz")).unwrap_err();
/// assert!(matches!(&e, MeshError::File { path, .. } if path.ends_with("m.xyz")));
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_mesh(mesh: &Mesh, path: &Path) -> Result<(), MeshError> {
    match extension(path).as_deref() {
        Some("node") | Some("ele") | Some("poly") => write_triangle(mesh, &path.with_extension("")),
        Some("msh") => write_gmsh(mesh, path),
        Some("vtu") => write_vtu(mesh, path),
        Some("obj") => write_obj(mesh, path),
        _ => Err(unknown_extension(path, "write", WRITE_EXTENSIONS)),
    }
}

/// [`write_mesh`] for a mesh of `region`: a `.msh` file also gets a physical curve per
/// boundary piece ([`write_gmsh_on`]), so a solver can set a condition per wall; where the
/// region names its walls by number ([`Region::piece_markers`], a `.poly`'s segment markers)
/// Triangle's files carry those numbers as their boundary markers, as Triangle itself passes
/// them on ([`write_triangle_on`]), and a `.vtu` a `wall_marker` array. The other formats
/// are written as [`write_mesh`] writes them.
pub fn write_mesh_on(mesh: &Mesh, region: &Region, path: &Path) -> Result<(), MeshError> {
    match extension(path).as_deref() {
        Some("msh") => write_gmsh_on(mesh, region, path),
        Some("node") | Some("ele") | Some("poly") => {
            write_triangle_on(mesh, region, &path.with_extension(""))
        }
        Some("vtu") if region.piece_markers().is_some() => {
            validate_for_writing(mesh, path)?;
            vtu::write_nodes(&Nodes::linear(mesh, Some(region)), path)
        }
        _ => write_mesh(mesh, path),
    }
}

/// Extensions [`write_quadratic`] writes.
pub const QUADRATIC_EXTENSIONS: &[&str] = &["node", "ele", "poly", "msh", "vtu"];

/// Write a mesh of six-node triangles, choosing the format by extension as [`write_mesh`]
/// does: `.msh` (Gmsh element types 9 and 8, the three-node boundary lines; with a physical
/// curve per piece, as [`write_gmsh_on`] writes them, when `q` was placed on a region), `.vtu` (VTK's
/// quadratic triangle, type 22) or `.node`/`.ele` (Triangle's `-o2` layout: corners, then the
/// node opposite each corner; the `.poly` keeps two-node segments). Other formats have no
/// six-node triangle and are refused.
///
/// ```
/// use cvtmesh::{io, Quadratic};
/// let region = cvtmesh::geometry::Region::builtin("circle")?;
/// let mesh = ccvt_free_mesh();
/// # fn ccvt_free_mesh() -> cvtmesh::Mesh {
/// #     let ring: Vec<cvtmesh::geometry::DVec2> = (0..8).map(|k| cvtmesh::geometry::DVec2::from_angle(k as f64 * std::f64::consts::TAU / 8.0)).collect();
/// #     let points = [vec![cvtmesh::geometry::DVec2::ZERO], ring].concat();
/// #     let triangles: Vec<[u32; 3]> = (1..=8).map(|k| [0, k, k % 8 + 1]).collect();
/// #     cvtmesh::Mesh { markers: io::markers_from_topology(&points, &triangles), points, triangles }
/// # }
/// let q = Quadratic::new(&mesh, Some(&region));
/// let path = std::env::temp_dir().join(format!("cvtmesh-doc-p2-{}.msh", std::process::id()));
/// io::write_quadratic(&q, &path)?;
/// // Read back by its corners: the linear mesh.
/// let back = io::read_mesh(&path)?;
/// assert_eq!((back.points, back.triangles), (mesh.points, mesh.triangles));
/// assert!(io::write_quadratic(&q, &path.with_extension("obj")).is_err());
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_quadratic(q: &Quadratic, path: &Path) -> Result<(), MeshError> {
    validate_for_writing(q.linear(), path)?;
    let nodes = Nodes::quadratic(q);
    match extension(path).as_deref() {
        Some("node") | Some("ele") | Some("poly") => {
            triangle::write_nodes(&nodes, &path.with_extension(""))
        }
        Some("msh") => gmsh::write_nodes(&nodes, path),
        Some("vtu") => vtu::write_nodes(&nodes, path),
        _ => Err(unknown_extension(
            path,
            "write six-node triangles to",
            QUADRATIC_EXTENSIONS,
        )),
    }
}

/// What a writer writes: nodes and their markers, triangles of three or six nodes, and each
/// loop's boundary edges as lines of two nodes (or three, the edge's node last).
pub(crate) struct Nodes<'a> {
    /// Every node.
    pub points: &'a [DVec2],
    /// One marker per node.
    pub markers: &'a [VertexMarker],
    /// Each triangle's nodes: its corners counter-clockwise, then (six-node triangles) the
    /// nodes of its edges ab, bc, ca.
    pub triangles: Vec<&'a [u32]>,
    /// Per loop, its boundary lines in boundary order.
    pub lines: Vec<Vec<Vec<u32>>>,
    /// Per loop, the piece of the region each line lies on (empty lists when no region was
    /// given): Gmsh's files then get a physical curve per piece beside the one per loop.
    pub pieces: Vec<Vec<PieceId>>,
    /// Each piece's marker where the region names its walls by number
    /// ([`Region::piece_markers`]): Triangle's files then carry them as boundary markers, and
    /// Gmsh's a physical curve per marker.
    pub piece_markers: Option<Vec<i64>>,
    /// The region's names for its markers ([`Region::marker_name`]).
    pub marker_names: BTreeMap<i64, String>,
    /// Each corner's own marker ([`Region::corner_marker`]), by corner index.
    pub corner_markers: Vec<Option<i64>>,
    /// The region's embedded points with nonzero markers ([`Region::embedded_points`]).
    pub embedded: Vec<(DVec2, i64)>,
    /// The physical surface the triangles go in ([`Region::surface_group`]).
    pub surface_group: Option<(i64, String)>,
    /// The lines along the region's embedded lines ([`crate::line_edges`]), each with its
    /// line's marker: Triangle's `.poly` lists them as segments, Gmsh's files as line
    /// elements in a physical curve per marker.
    pub inner: Vec<(Vec<u32>, i64)>,
    /// Each triangle's subdomain ([`crate::subdomains`]) where the region has lines or
    /// subdomain points: Triangle's `.ele` then carries it as an attribute, Gmsh's files a
    /// physical surface per subdomain, VTK's a cell array.
    pub subdomains: Option<Vec<i64>>,
    /// The region's names for its subdomain numbers ([`Region::subdomain_name`]).
    pub subdomain_names: BTreeMap<i64, String>,
    /// The three-node mesh of the corners.
    pub linear: &'a Mesh,
}

/// The mesh's edges along `region`'s embedded lines, for the writers (none where the mesh
/// does not follow them: a file then has its triangles and walls, as for any region).
fn inner_lines(mesh: &Mesh, region: Option<&Region>) -> Vec<([u32; 2], i64)> {
    region
        .and_then(|r| crate::line_edges(mesh, r).ok())
        .unwrap_or_default()
}

/// Each triangle's subdomain, for the writers, where `region` has subdomains to number and
/// the mesh follows its lines (`inner`: [`inner_lines`], empty where it does not).
fn subdomains_of(
    mesh: &Mesh,
    region: Option<&Region>,
    inner: &[([u32; 2], i64)],
) -> Option<Vec<i64>> {
    let region = region.filter(|r| crate::has_subdomains(r))?;
    if inner.is_empty() && !region.embedded_lines().is_empty() {
        return None;
    }
    Some(crate::subdomains::subdomains_cut_by(mesh, region, inner))
}

/// The region's names for its subdomain numbers, for the writers.
fn subdomain_names_of(region: Option<&Region>) -> BTreeMap<i64, String> {
    let Some(r) = region else {
        return BTreeMap::new();
    };
    r.subdomain_points()
        .iter()
        .filter_map(|&(_, id)| Some((id, r.subdomain_name(id)?.to_string())))
        .collect()
}

/// The region's physical surface, for the writers.
fn surface_group_of(region: Option<&Region>) -> Option<(i64, String)> {
    region
        .and_then(Region::surface_group)
        .map(|(t, n)| (t, n.to_string()))
}

impl<'a> Nodes<'a> {
    /// The nodes of a mesh of three-node triangles, with each boundary line's piece of
    /// `region` if given.
    pub fn linear(mesh: &'a Mesh, region: Option<&Region>) -> Nodes<'a> {
        let (groups, pieces, _) = edges_and_pieces_by_loop(mesh, region);
        let inner = inner_lines(mesh, region);
        Nodes {
            pieces,
            piece_markers: region.and_then(Region::piece_markers).map(<[i64]>::to_vec),
            marker_names: names_of(region),
            corner_markers: corner_markers(region),
            embedded: marked_embedded(region),
            surface_group: surface_group_of(region),
            subdomains: subdomains_of(mesh, region, &inner),
            subdomain_names: subdomain_names_of(region),
            inner: inner
                .into_iter()
                .map(|([a, b], m)| (vec![a, b], m))
                .collect(),
            points: &mesh.points,
            markers: &mesh.markers,
            triangles: mesh.triangles.iter().map(|t| &t[..]).collect(),
            lines: groups
                .iter()
                .map(|g| g.iter().map(|&(a, b)| vec![a, b]).collect())
                .collect(),
            linear: mesh,
        }
    }

    /// The nodes of a mesh of six-node triangles.
    pub fn quadratic(q: &'a Quadratic) -> Nodes<'a> {
        let (groups, pieces, _) = edges_and_pieces_by_loop(q.linear(), q.region());
        let inner = inner_lines(q.linear(), q.region());
        Nodes {
            pieces,
            piece_markers: q
                .region()
                .and_then(Region::piece_markers)
                .map(<[i64]>::to_vec),
            marker_names: names_of(q.region()),
            corner_markers: corner_markers(q.region()),
            embedded: marked_embedded(q.region()),
            surface_group: surface_group_of(q.region()),
            subdomains: subdomains_of(q.linear(), q.region(), &inner),
            subdomain_names: subdomain_names_of(q.region()),
            inner: inner
                .into_iter()
                .map(|([a, b], m)| {
                    let mid = q.edge_node(a, b).expect("a line's piece is an edge");
                    (vec![a, b, mid], m)
                })
                .collect(),
            points: &q.points,
            markers: &q.markers,
            triangles: q.triangles.iter().map(|t| &t[..]).collect(),
            lines: groups
                .iter()
                .map(|g| {
                    g.iter()
                        .map(|&(a, b)| {
                            let m = q.edge_node(a, b).expect("a boundary edge is an edge");
                            vec![a, b, m]
                        })
                        .collect()
                })
                .collect(),
            linear: q.linear(),
        }
    }

    /// Nodes per triangle: 3 or 6.
    pub fn per_triangle(&self) -> usize {
        self.triangles.first().map_or(3, |t| t.len())
    }

    /// Each boundary line's marker (per loop, in boundary order) and each node's (0 inside),
    /// where the region names its walls by number: a line takes its piece's, a node the marker
    /// of the line it starts or whose middle it is (so a corner takes the wall that leaves it,
    /// counter-clockwise along an outer loop), a corner with a marker of its own
    /// ([`Region::vertex_markers`]) that one. A wall numbered 0 (a `.poly` segment without a
    /// marker) is 1, as Triangle marks it: on the boundary, 0 is never a marker, so that a
    /// node's marker tells the boundary from the inside.
    pub fn wall_markers(&self) -> Option<(Vec<Vec<i64>>, Vec<i64>)> {
        let pm = self.piece_markers.as_ref()?;
        let by_line: Vec<Vec<i64>> = self
            .pieces
            .iter()
            .map(|ps| {
                ps.iter()
                    .map(|&j| match pm.get(j).copied().unwrap_or(0) {
                        0 => 1,
                        m => m,
                    })
                    .collect()
            })
            .collect();
        if by_line
            .iter()
            .zip(&self.lines)
            .any(|(m, l)| m.len() != l.len())
        {
            return None;
        }
        let mut by_node = vec![0; self.points.len()];
        for (lines, marks) in self.lines.iter().zip(&by_line) {
            for (line, &m) in lines.iter().zip(marks) {
                for &v in line.iter().take(1).chain(line.get(2)) {
                    by_node[v as usize] = m;
                }
            }
        }
        // A vertex of an embedded line takes its marker, as Triangle marks a segment's
        // vertices, unless a wall or a marker of its own names it.
        for (line, m) in &self.inner {
            for &v in line {
                if by_node[v as usize] == 0 {
                    by_node[v as usize] = *m;
                }
            }
        }
        for (v, m) in self.own_markers() {
            by_node[v] = m;
        }
        Some((by_line, by_node))
    }

    /// The nodes with a marker of their own: corners the region marks
    /// ([`Region::vertex_markers`]) and its marked embedded points.
    pub fn own_markers(&self) -> Vec<(usize, i64)> {
        let embedded: HashMap<(u64, u64), i64> = self
            .embedded
            .iter()
            .map(|&(p, m)| ((p.x.to_bits(), p.y.to_bits()), m))
            .collect();
        self.markers
            .iter()
            .enumerate()
            .filter_map(|(v, marker)| match *marker {
                VertexMarker::Corner { corner, .. } => self
                    .corner_markers
                    .get(corner)
                    .copied()
                    .flatten()
                    .map(|m| (v, m)),
                VertexMarker::Interior if !embedded.is_empty() => {
                    let p = self.points[v];
                    embedded
                        .get(&(p.x.to_bits(), p.y.to_bits()))
                        .map(|&m| (v, m))
                }
                _ => None,
            })
            .collect()
    }
}

/// `region`'s embedded points that carry a marker.
fn marked_embedded(region: Option<&Region>) -> Vec<(DVec2, i64)> {
    region.map_or_else(Vec::new, |r| {
        r.embedded_points()
            .iter()
            .copied()
            .filter(|&(_, m)| m != 0)
            .collect()
    })
}

/// The marker of each of `region`'s corners that has one of its own.
fn corner_markers(region: Option<&Region>) -> Vec<Option<i64>> {
    region.map_or_else(Vec::new, |r| {
        (0..r.corners().len()).map(|c| r.corner_marker(c)).collect()
    })
}

/// The names `region` gives its markers.
fn names_of(region: Option<&Region>) -> BTreeMap<i64, String> {
    // Every name the region has, its lines' markers' too: the writers look up those they use.
    region.map_or_else(BTreeMap::new, |r| r.marker_names().clone())
}

/// The files [`write_mesh`] writes for `path`: `.node`, `.ele` and `.poly` of its stem for
/// Triangle's format, else `path` itself.
///
/// ```
/// use cvtmesh::io::files_written;
/// use std::path::{Path, PathBuf};
/// let f = files_written(Path::new("out/coast.node"));
/// assert_eq!(f, ["out/coast.node", "out/coast.ele", "out/coast.poly"].map(PathBuf::from));
/// assert_eq!(files_written(Path::new("m.msh")), [PathBuf::from("m.msh")]);
/// // `.poly` names the same three files, as a Triangle user may name the output.
/// assert_eq!(files_written(Path::new("out/coast.poly")), f);
/// ```
pub fn files_written(path: &Path) -> Vec<std::path::PathBuf> {
    match extension(path).as_deref() {
        Some("node") | Some("ele") | Some("poly") => ["node", "ele", "poly"]
            .iter()
            .map(|e| path.with_extension(e))
            .collect(),
        _ => vec![path.to_path_buf()],
    }
}

/// Read a mesh, choosing the format by extension: `.node`/`.ele` (Triangle, reading both
/// files), `.msh` (Gmsh 4.1 or 2.2 ASCII), `.vtu` (VTK XML unstructured grid, in any of the
/// encodings VTK, ParaView and meshio write: [`read_vtu`]) or `.obj`. Triangles come back
/// counter-clockwise. See [`write_mesh`] for a round trip.
pub fn read_mesh(path: &Path) -> Result<Mesh, MeshError> {
    match extension(path).as_deref() {
        Some("node") | Some("ele") => read_triangle(&path.with_extension("node")),
        Some("msh") => read_gmsh(path),
        Some("vtu") => read_vtu(path),
        Some("obj") => read_obj(path),
        _ => Err(unknown_extension(path, "read", READ_EXTENSIONS)),
    }
}

/// The walls a mesh file numbers: its boundary edges with their markers, and the names it
/// gives those numbers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Walls {
    /// Boundary edges by their end vertices (as the file's mesh numbers them), each with the
    /// marker of its wall.
    pub edges: Vec<([u32; 2], i64)>,
    /// Vertices the file marks, each with its marker: the node of a Gmsh physical point, a
    /// Triangle `.node`'s nonzero boundary markers. Where such a marker differs from the
    /// walls on both sides of its boundary vertex, the vertex is a point of its own
    /// ([`geometry::Region::vertex_markers`]); a marked vertex inside is an embedded point
    /// ([`geometry::Region::embedded_points`]).
    pub points: Vec<(u32, i64)>,
    /// The file's name for a marker, where it gives one (a Gmsh physical curve's name).
    pub names: BTreeMap<i64, String>,
    /// Edges inside the mesh that the file keeps as lines of their own, each with its lower
    /// vertex first, sorted: a Triangle `.poly`'s internal segments, Gmsh line elements off the
    /// boundary, and the edges between triangles the file puts in different regions (a Triangle
    /// `.ele`'s first attribute, Gmsh's physical surfaces, or its surfaces where it has no
    /// physical ones): a material interface, a crack, a line a solver reads values on.
    /// Polishing holds their vertices (`cvtmesh::polish_restored_holding`), and a mesh with
    /// them is not taken as a region to mesh again (`cvtmesh::load_region`), which would lose
    /// them.
    pub inner: Vec<[u32; 2]>,
    /// The marker of each [`Walls::inner`] edge, in its order: a `.poly` segment's marker, the
    /// physical curve of a Gmsh line element; 0 where the file gives none (an edge between
    /// two regions). Empty when no inner edge has one.
    pub inner_markers: Vec<i64>,
    /// Each triangle's number, where the file numbers its triangles as parts of the region (a
    /// Triangle `.ele`'s first attribute where every one is a whole number, the physical
    /// surface of each triangle of a Gmsh mesh with several): a new mesh of the region keeps
    /// them as subdomains (`cvtmesh::subdomain_points_of`). Empty otherwise.
    pub subdomains: Vec<i64>,
    /// The file's name for a subdomain number, where it gives one (a Gmsh physical surface's).
    pub subdomain_names: BTreeMap<i64, String>,
    /// The physical surface the file puts every triangle in, tag and name (a Gmsh mesh's one
    /// physical surface), which a region of the mesh keeps ([`Region::surface_group`]).
    pub surface_group: Option<(i64, String)>,
    /// What the file numbers that these walls do not keep: a Gmsh physical curve whose curves
    /// are in another group too (each boundary edge keeps one wall, the first).
    pub notes: Vec<String>,
}

impl Walls {
    /// The vertices of the [`Walls::inner`] edges, sorted: what polishing holds.
    ///
    /// ```
    /// let walls = cvtmesh::io::Walls { inner: vec![[1, 4], [4, 7]], ..Default::default() };
    /// assert_eq!(walls.inner_vertices(), [1, 4, 7]);
    /// ```
    pub fn inner_vertices(&self) -> Vec<u32> {
        let mut v: Vec<u32> = self.inner.iter().flatten().copied().collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// The marker of each of `inner` (sorted edges, the lower vertex first) that `given` (edges
/// either way round, with markers) gives; empty when it gives none a nonzero one.
pub(crate) fn inner_markers(inner: &[[u32; 2]], given: &[([u32; 2], i64)]) -> Vec<i64> {
    let by_edge: HashMap<[u32; 2], i64> = given
        .iter()
        .map(|&([a, b], m)| ([a.min(b), a.max(b)], m))
        .collect();
    let markers: Vec<i64> = inner
        .iter()
        .map(|e| by_edge.get(e).copied().unwrap_or(0))
        .collect();
    if markers.iter().all(|&m| m == 0) {
        Vec::new()
    } else {
        markers
    }
}

/// [`Walls::subdomains`] from the bits of each triangle's first `.ele` attribute: the
/// attributes where every one is a whole number within 32 bits, else none.
pub(crate) fn whole_numbers(bits: &[i64]) -> Vec<i64> {
    let values = bits.iter().map(|&b| f64::from_bits(b as u64));
    let whole = |a: f64| a.fract() == 0.0 && a.abs() <= f64::from(i32::MAX);
    if values.clone().all(whole) {
        values.map(|a| a as i64).collect()
    } else {
        Vec::new()
    }
}

/// The [`Walls::inner`] edges of `mesh`: those between two triangles whose `regions` (one per
/// triangle, empty for none) differ, and those of `lines` (edges the file lists) that two
/// triangles share.
pub(crate) fn inner_edges(mesh: &Mesh, regions: &[i64], lines: &[[u32; 2]]) -> Vec<[u32; 2]> {
    // Most files have one region and no lines: no edge map over the whole mesh for them.
    if lines.is_empty() && regions.windows(2).all(|w| w[0] == w[1]) {
        return Vec::new();
    }
    // Each edge, its lower vertex first, with the region of the first triangle met and whether
    // a second triangle shares it (with which region).
    let mut seen: std::collections::HashMap<[u32; 2], (i64, Option<i64>)> =
        std::collections::HashMap::with_capacity(3 * mesh.triangles.len() / 2 + 1);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let region = regions.get(t).copied().unwrap_or(0);
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            seen.entry([a.min(b), a.max(b)])
                .and_modify(|e| e.1 = Some(region))
                .or_insert((region, None));
        }
    }
    let mut inner: Vec<[u32; 2]> = seen
        .iter()
        .filter(|(_, &(first, second))| second.is_some_and(|s| s != first))
        .map(|(&e, _)| e)
        .collect();
    inner.extend(
        lines
            .iter()
            .map(|&[a, b]| [a.min(b), a.max(b)])
            .filter(|e| seen.get(e).is_some_and(|s| s.1.is_some())),
    );
    inner.sort_unstable();
    inner.dedup();
    inner
}

/// [`read_mesh`] of one mesh file, and the walls it numbers ([`Walls`]), each file read
/// once: a Gmsh file's physical curves ([`read_gmsh_with_walls`]) or the segment markers of
/// the `.poly` beside a Triangle `.node` ([`read_triangle_with_walls`]); none for `.obj` and
/// for files that number none. With the mesh they make the region to mesh again with the same
/// boundary conditions ([`geometry::Region::from_triangles_marked`],
/// [`geometry::Region::with_marker_names`]).
pub fn read_mesh_with_walls(path: &Path) -> Result<(Mesh, Walls), MeshError> {
    read_mesh_file(path).map(|f| (f.mesh, f.walls))
}

/// A mesh file as [`read_mesh_file`] reads it.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct MeshFile {
    /// The mesh of the triangles' corners.
    pub mesh: Mesh,
    /// The walls the file numbers ([`read_mesh_with_walls`]).
    pub walls: Walls,
    /// Nodes per triangle in the file: 3, or 6 for quadratic triangles (Gmsh's higher orders
    /// more), whose other nodes the mesh leaves out.
    pub triangle_nodes: usize,
    /// A six-node file's edge nodes, by the edge's ends as `mesh` numbers them (sorted, the
    /// lower first), so that writing the mesh back can keep them ([`crate::Quadratic::keeping`]).
    pub edge_nodes: Vec<([u32; 2], DVec2)>,
}

/// [`read_mesh_with_walls`], with the file's triangles' order and edge nodes. A `.vtu` carries
/// no walls: its [`MeshFile::walls`] is empty (the `boundary_marker` and `wall_marker` point
/// data [`write_mesh_on`] writes are not read back).
///
/// ```
/// use cvtmesh::io;
/// let dir = std::env::temp_dir().join(format!("cvtmesh_doc_p2_{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// // One six-node triangle: its corners, then a node on each edge.
/// std::fs::write(dir.join("t.node"), "6 2 0 0\n1 0 0\n2 1 0\n3 0 1\n4 0.5 0.5\n5 0 0.5\n6 0.5 0\n")?;
/// std::fs::write(dir.join("t.ele"), "1 6 0\n1 1 2 3 4 5 6\n")?;
/// let file = io::read_mesh_file(&dir.join("t.node"))?;
/// assert_eq!(file.triangle_nodes, 6);
/// assert_eq!((file.mesh.num_vertices(), file.mesh.num_triangles()), (3, 1));
/// // Node 4 is opposite corner 1, on the edge of corners 2 and 3.
/// assert_eq!(file.edge_nodes[2], ([1, 2], cvtmesh::geometry::DVec2::new(0.5, 0.5)));
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_mesh_file(path: &Path) -> Result<MeshFile, MeshError> {
    match extension(path).as_deref() {
        Some("msh") => gmsh::read_gmsh_file(path),
        Some("node") | Some("ele") => triangle::read_triangle_file(&path.with_extension("node")),
        Some("vtu") => vtu::read_vtu_file(path),
        _ => Ok(MeshFile {
            mesh: read_mesh(path)?,
            walls: Walls::default(),
            triangle_nodes: 3,
            edge_nodes: Vec::new(),
        }),
    }
}

/// Whether `path` names a file [`read_mesh`] reads (by its extension).
///
/// ```
/// use cvtmesh::io::names_mesh;
/// use std::path::Path;
/// assert!(names_mesh(Path::new("run3/out.MSH")) && names_mesh(Path::new("a.ele")));
/// assert!(!names_mesh(Path::new("lake")) && !names_mesh(Path::new("region.poly")));
/// ```
pub fn names_mesh(path: &Path) -> bool {
    extension(path).is_some_and(|e| READ_EXTENSIONS.contains(&e.as_str()))
}

/// Extensions [`read_sizes`] understands.
pub const SIZE_EXTENSIONS: &[&str] = &["node", "ele", "msh"];

/// Whether `path` names a file [`read_sizes`] reads (by its extension), as opposed to, say,
/// an expression given where a size field is asked for.
///
/// ```
/// use cvtmesh::io::names_sizes;
/// use std::path::Path;
/// assert!(names_sizes(Path::new("run3/sizes.NODE")) && names_sizes(Path::new("bg.msh")));
/// assert!(!names_sizes(Path::new("0.01 + 0.1*x")) && !names_sizes(Path::new("0.08")));
/// ```
pub fn names_sizes(path: &Path) -> bool {
    extension(path).is_some_and(|e| SIZE_EXTENSIONS.contains(&e.as_str()))
}

/// A mesh and a size at each of its vertices, as [`read_sizes`] reads them.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct SizesFile {
    /// The mesh.
    pub mesh: Mesh,
    /// The size at each of its vertices.
    pub sizes: Vec<f64>,
    /// Where the file holds several views (Gmsh's `$NodeData`), which one the sizes are, for
    /// the user to hear.
    pub view: Option<String>,
}

/// A mesh and a size at each of its vertices, for a size field given on a mesh (an adaptive
/// solver's sizes on its last mesh, a background mesh; [`geometry::SizeField::from_mesh`]):
/// a Triangle `.node` whose first attribute is the size, with its `.ele`
/// ([`read_triangle_sizes`]), or a Gmsh `.msh` with a `$NodeData` view of one value per node
/// ([`read_gmsh_sizes`]: the first, as Gmsh takes a background mesh's, with a note naming it
/// where the file has several).
///
/// ```
/// let dir = std::env::temp_dir().join(format!("cvtmesh-doc-sizes-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let view = |name: &str, h: f64| format!("$NodeData\n1\n\"{name}\"\n1\n0\n3\n0\n1\n3\n1 {h}\n2 {h}\n3 {h}\n$EndNodeData\n");
/// let mesh = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 0 1 2 3\n$EndElements\n";
/// std::fs::write(dir.join("bg.msh"), format!("{mesh}{}{}", view("error", 1e-3), view("h", 0.1)))?;
/// let f = cvtmesh::io::read_sizes(&dir.join("bg.msh"))?;
/// assert_eq!(f.sizes, [1e-3; 3]);
/// assert!(f.view.unwrap().contains("its first $NodeData view, \"error\", of 2 (the others: \"h\")"));
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_sizes(path: &Path) -> Result<SizesFile, MeshError> {
    match extension(path).as_deref() {
        Some("node") | Some("ele") => {
            let (mesh, sizes) = read_triangle_sizes(&path.with_extension("node"))?;
            Ok(SizesFile {
                mesh,
                sizes,
                view: None,
            })
        }
        Some("msh") => gmsh::read_gmsh_sizes_file(path),
        _ => Err(unknown_extension(path, "read sizes from", SIZE_EXTENSIONS)),
    }
}

/// Each vertex's marker as the mesh files carry it (the boundary-marker column of a Triangle
/// `.node`, Triangle's own `pointmarkerlist`), where `region` numbers its walls
/// ([`Region::piece_markers`]): a boundary vertex takes the marker of the wall leaving it
/// (counter-clockwise along an outer loop), a corner with a marker of its own
/// ([`Region::vertex_markers`]) that one, an interior vertex 0. `None` where the region
/// numbers no walls. `mesh` is a mesh of `region` (its corner markers index its corners).
///
/// ```
/// use cvtmesh::io;
/// use cvtmesh::geometry::formats::poly_from_str;
/// use cvtmesh::geometry::DVec2;
/// // The unit square, bottom wall 2, the others 1, and its bottom-left vertex marked 9.
/// let poly = "4 2 0 1\n1 0 0 9\n2 1 0 2\n3 1 1 1\n4 0 1 1\n4 1\n1 1 2 2\n2 2 3 1\n3 3 4 1\n4 4 1 1\n0\n";
/// let r = poly_from_str(poly, "sq.poly", "sq")?.with_default_corners();
/// let points = vec![DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y, DVec2::splat(0.5)];
/// let triangles = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
/// let mut mesh = cvtmesh::Mesh { markers: io::markers_from_topology(&points, &triangles), points, triangles };
/// io::restore_markers(&mut mesh, &r);
/// assert_eq!(io::vertex_markers(&mesh, &r), Some(vec![9, 1, 1, 1, 0]));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn vertex_markers(mesh: &Mesh, region: &Region) -> Option<Vec<i64>> {
    Nodes::linear(mesh, Some(region))
        .wall_markers()
        .map(|(_, by_node)| by_node)
}

/// Fill in the boundary markers of a mesh read from a file: every vertex marked as on the
/// boundary is projected onto `region` and gets that piece, loop, arc-length parameter, and
/// becomes a `Corner` when it coincides with a region corner. Interior vertices stay interior.
pub fn restore_markers(mesh: &mut Mesh, region: &Region) {
    for (p, m) in mesh.points.iter().zip(mesh.markers.iter_mut()) {
        if !m.on_boundary() {
            continue;
        }
        let bp = region.project(*p);
        *m = match bp.corner {
            Some(corner) => VertexMarker::Corner {
                loop_index: bp.loop_index,
                corner,
                loop_param: bp.loop_param,
            },
            None => VertexMarker::Boundary {
                loop_index: bp.loop_index,
                piece: bp.piece,
                loop_param: bp.loop_param,
            },
        };
    }
}

/// Boundary markers from the mesh alone, for files that do not record them: a vertex is on the
/// boundary when it ends an edge used by only one triangle. Each connected chain of such edges
/// is a loop; loop 0 is the one enclosing the largest signed area (the outer boundary of a
/// mesh with CCW triangles), the others follow in order of their smallest vertex index.
/// Pieces are [`UNKNOWN_PIECE`] and `loop_param` is NaN.
pub fn markers_from_topology(points: &[DVec2], triangles: &[[u32; 3]]) -> Vec<VertexMarker> {
    let n = points.len();
    let edges = crate::types::single_edges(triangles);
    // Union-find over the boundary edges groups vertices into loops.
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for &(a, b) in &edges {
        let (ra, rb) = (find(&mut parent, a as usize), find(&mut parent, b as usize));
        if ra != rb {
            parent[ra.max(rb)] = ra.min(rb);
        }
    }
    // Per component: twice the signed area and the smallest vertex (the root, by construction).
    let mut area: HashMap<usize, f64> = HashMap::new();
    for &(a, b) in &edges {
        let root = find(&mut parent, a as usize);
        *area.entry(root).or_insert(0.0) += points[a as usize].perp_dot(points[b as usize]);
    }
    let mut roots: Vec<usize> = area.keys().copied().collect();
    roots.sort_unstable();
    if let Some(outer) = roots
        .iter()
        .enumerate()
        .max_by(|x, y| area[x.1].total_cmp(&area[y.1]).then(y.0.cmp(&x.0)))
        .map(|(i, _)| i)
    {
        let r = roots.remove(outer);
        roots.insert(0, r);
    }
    let loop_of: HashMap<usize, usize> = roots.iter().enumerate().map(|(i, &r)| (r, i)).collect();
    let mut on_boundary = vec![false; n];
    for &(a, b) in &edges {
        on_boundary[a as usize] = true;
        on_boundary[b as usize] = true;
    }
    (0..n)
        .map(|v| {
            if on_boundary[v] {
                let loop_index = loop_of[&find(&mut parent, v)];
                VertexMarker::Boundary {
                    loop_index,
                    piece: UNKNOWN_PIECE,
                    loop_param: f64::NAN,
                }
            } else {
                VertexMarker::Interior
            }
        })
        .collect()
}

/// The vertices of `n` that the triangles' corners use, in order (a six-node file's nodes on
/// edges are not vertices), with the triangles renumbered to them.
pub(crate) fn keep_corners(n: usize, triangles: &mut [[u32; 3]]) -> Vec<usize> {
    let mut new_index = vec![u32::MAX; n];
    for t in triangles.iter() {
        for &v in t {
            new_index[v as usize] = 0;
        }
    }
    let mut kept = Vec::new();
    for (i, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = kept.len() as u32;
            kept.push(i);
        }
    }
    for t in triangles.iter_mut() {
        for v in t.iter_mut() {
            *v = new_index[*v as usize];
        }
    }
    kept
}

/// Boundary edges per loop, each edge's piece per loop, and the number of loops.
type ByLoop = (Vec<Vec<(u32, u32)>>, Vec<Vec<PieceId>>, usize);

/// Boundary edges grouped by loop, each group ordered along the loop parameter of its start
/// vertex (so that files list edges in boundary order); each edge's piece of `region` in a
/// second list of the same shape (empty lists without a region); and the number of loops.
pub(crate) fn edges_and_pieces_by_loop(mesh: &Mesh, region: Option<&Region>) -> ByLoop {
    let edges = mesh.boundary_edges();
    let pieces = region.map(|r| mesh.pieces_of(&edges, r));
    let nloops = mesh
        .markers
        .iter()
        .filter_map(|m| m.loop_index())
        .map(|l| l + 1)
        .chain(edges.iter().map(|e| e.loop_index + 1))
        .max()
        .unwrap_or(0);
    let mut groups = vec![Vec::new(); nloops];
    let mut piece_groups = vec![Vec::new(); nloops];
    for (k, e) in edges.iter().enumerate() {
        groups[e.loop_index].push((e.a, e.b));
        if let Some(p) = &pieces {
            piece_groups[e.loop_index].push(p[k]);
        }
    }
    (groups, piece_groups, nloops)
}

/// The mesh-file error for `path`.
pub(crate) fn file_err(path: &Path, message: impl Into<String>) -> MeshError {
    MeshError::File {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// The error for an operating-system failure to `action` (e.g. "read") the file `path`.
pub(crate) fn io_err(path: &Path, action: impl Into<String>, cause: std::io::Error) -> MeshError {
    MeshError::Io {
        path: path.to_path_buf(),
        action: action.into(),
        cause,
    }
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
}

fn unknown_extension(path: &Path, verb: &str, supported: &[&str]) -> MeshError {
    let list: Vec<String> = supported.iter().map(|e| format!(".{e}")).collect();
    let found = match extension(path) {
        Some(e) => format!("extension '.{e}'"),
        None => "no extension".to_string(),
    };
    file_err(
        path,
        format!(
            "cannot {verb} a mesh with {found}; supported: {}",
            list.join(", ")
        ),
    )
}

/// Check what a writer relies on, so that writing never panics and never writes an unreadable
/// file: a marker per vertex, finite coordinates, triangle indices in range.
pub(crate) fn validate_for_writing(mesh: &Mesh, path: &Path) -> Result<(), MeshError> {
    if mesh.markers.len() != mesh.points.len() {
        return Err(file_err(
            path,
            format!(
                "mesh has {} vertices but {} markers",
                mesh.points.len(),
                mesh.markers.len()
            ),
        ));
    }
    if let Some(i) = mesh.points.iter().position(|p| !p.is_finite()) {
        return Err(file_err(
            path,
            format!("vertex {i} is not finite: {}", mesh.points[i]),
        ));
    }
    let n = mesh.points.len();
    if let Some(t) = mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&v| v as usize >= n))
    {
        return Err(file_err(
            path,
            format!("triangle {t} refers to a vertex beyond the {n} vertices"),
        ));
    }
    Ok(())
}

/// A float in its shortest round-trip form: plain decimals for ordinary magnitudes, scientific
/// notation for very small or large ones (Rust's `{}` never uses an exponent). The text of `{}`
/// for zero and magnitudes in [10⁻⁵, 10¹⁶) and of `{:e}` otherwise, but for the rounding of a
/// tie ([`float_text`]).
pub(crate) struct F(pub f64);

impl fmt::Display for F {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(float_text(&mut ryu::Buffer::new(), self.0))
    }
}

/// Appends `x` as [`F`] displays it, without the formatting machinery: the millions of
/// coordinates of a large mesh's files.
pub(crate) fn push_float(s: &mut String, x: f64) {
    s.push_str(float_text(&mut ryu::Buffer::new(), x));
}

/// [`F`]'s text of `x`, from Ryū: the shortest digits that read back to `x` (the nearest such
/// when there are several; of two equally near, the even one, where the standard library takes
/// the larger: 1748266582941778.2 for 1748266582941778.25), placed as `F` places them: plain for
/// magnitudes in [10⁻⁵, 10¹⁶), with an exponent (`1.5e-7`, `1e300`) otherwise; but for Ryū's
/// `.0` after a whole number. A fraction of the standard library's time: a third of writing a
/// million-vertex `.node` file.
fn float_text(buf: &mut ryu::Buffer, x: f64) -> &str {
    if x.is_nan() {
        "NaN"
    } else if x.is_infinite() {
        if x > 0.0 {
            "inf"
        } else {
            "-inf"
        }
    } else {
        let text = buf.format_finite(x);
        text.strip_suffix(".0").unwrap_or(text)
    }
}

/// Appends `v` in decimal, as `{}` formats it: the millions of indices of a large mesh's files
/// without the formatting machinery's cost per argument (a third of writing them).
pub(crate) fn push_int(s: &mut String, v: i64) {
    s.push_str(itoa::Buffer::new().format(v));
}

/// A file's contents, produced into a writer.
pub(crate) type Producer<'a> = Box<dyn FnOnce(&mut dyn Write) -> std::io::Result<()> + 'a>;

/// Write lines `0..n`, line `i` appended to a buffer by `line(i, buffer)`: formatted in
/// parallel chunks and written in order, so the bytes are those of writing the lines one by
/// one, in a fraction of the time for the 10⁵–10⁶ lines of a large mesh. A batch at a time is
/// held in memory, not the file.
pub(crate) fn write_lines(
    w: &mut dyn Write,
    n: usize,
    line: impl Fn(usize, &mut String) + Sync,
) -> std::io::Result<()> {
    use rayon::prelude::*;
    const CHUNK: usize = 4096;
    const BATCH: usize = 16 * CHUNK;
    for start in (0..n).step_by(BATCH) {
        let end = (start + BATCH).min(n);
        let parts: Vec<String> = (start..end)
            .step_by(CHUNK)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|from| {
                let mut s = String::with_capacity(64 * CHUNK);
                for i in from..(from + CHUNK).min(end) {
                    line(i, &mut s);
                }
                s
            })
            .collect();
        for part in parts {
            w.write_all(part.as_bytes())?;
        }
    }
    Ok(())
}

/// A fresh temporary path beside `target` (hidden, unique per process and call), or None if
/// `target` has no file name.
fn temp_beside(target: &Path) -> Option<PathBuf> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name = target.file_name()?;
    Some(target.with_file_name(format!(
        ".{}.{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    )))
}

/// Write `bytes` to `path` through a temporary file beside it and a rename: a reader never
/// sees a partial file, and a failure leaves the previous file (if any) and no temporary file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = temp_beside(path)
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"))?;
    let result = File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes).and_then(|_| f.sync_all()))
        .and_then(|_| fs::rename(&tmp, path));
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Write every file to a temp file beside its target, and only when all of them are complete
/// rename them into place: a failure leaves no partial (or missing-partner) output behind.
pub(crate) fn write_files(jobs: Vec<(PathBuf, Producer<'_>)>) -> Result<(), MeshError> {
    let mut written: Vec<(PathBuf, PathBuf)> = Vec::new();
    let cleanup = |written: &[(PathBuf, PathBuf)]| {
        for (tmp, _) in written {
            let _ = fs::remove_file(tmp);
        }
    };
    for (target, produce) in jobs {
        let Some(tmp) = temp_beside(&target) else {
            cleanup(&written);
            return Err(file_err(&target, "not a file name"));
        };
        let result = (|| -> std::io::Result<()> {
            let mut w = BufWriter::new(File::create(&tmp)?);
            produce(&mut w)?;
            let file = w.into_inner().map_err(|e| e.into_error())?;
            file.sync_all()
        })();
        if let Err(e) = result {
            let _ = fs::remove_file(&tmp);
            cleanup(&written);
            return Err(io_err(&target, "write", e));
        }
        written.push((tmp, target));
    }
    // Renames cannot be made atomic together; refuse the foreseeable failure (a directory in
    // the way) before any rename, and move the first file (.node, the one readers open) last.
    if let Some((_, target)) = written.iter().find(|(_, t)| t.is_dir()) {
        let target = target.clone();
        cleanup(&written);
        return Err(file_err(&target, "is a directory"));
    }
    if written.len() > 1 {
        written.rotate_left(1);
    }
    for i in 0..written.len() {
        let (tmp, target) = &written[i];
        if let Err(e) = fs::rename(tmp, target) {
            cleanup(&written[i..]);
            return Err(io_err(target, "move the finished file into place", e));
        }
    }
    Ok(())
}

/// Read a whole text file, with the error naming it.
pub(crate) fn read_text(path: &Path) -> Result<String, MeshError> {
    let bytes = fs::read(path).map_err(|e| io_err(path, "read", e))?;
    let mut text = String::from_utf8(bytes).map_err(|e| {
        file_err(
            path,
            format!(
                "not a text file (invalid UTF-8 at byte {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })?;
    // Editors on Windows start UTF-8 files with a byte-order mark, which no format here has.
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}

/// The mesh a reader found: every triangle made counter-clockwise (files from other tools may
/// use either orientation), with the file's exact markers if it has them, else markers from
/// the topology.
pub(crate) fn read_mesh_parts(
    points: Vec<DVec2>,
    mut triangles: Vec<[u32; 3]>,
    exact_markers: Option<Vec<VertexMarker>>,
) -> Mesh {
    for t in &mut triangles {
        let [a, b, c] = t.map(|v| points[v as usize]);
        if (b - a).perp_dot(c - a) < 0.0 {
            t.swap(1, 2);
        }
    }
    let markers = exact_markers.unwrap_or_else(|| markers_from_topology(&points, &triangles));
    Mesh {
        points,
        triangles,
        markers,
    }
}

/// The z coordinate of a vertex read from a 3-D format: anything but 0 is an error message.
pub(crate) fn planar_z(z: f64) -> Result<(), String> {
    if z == 0.0 {
        Ok(())
    } else {
        Err(format!(
            "z = {z}: only planar meshes in the plane z = 0 are supported"
        ))
    }
}

/// Whitespace-separated tokens of a text, with 1-based line numbers, skipping `comment`-started
/// line tails. Parse errors name the line. Scans bytes (token boundaries are ASCII), so large
/// mesh files are read without decoding characters.
pub(crate) struct Tokens<'a> {
    text: &'a str,
    pos: usize,
    /// Line of `pos` (1-based).
    line: usize,
    /// Line of the last token taken.
    tok_line: usize,
    comment: Option<u8>,
    path: &'a Path,
}

impl<'a> Tokens<'a> {
    pub(crate) fn new(text: &'a str, comment: Option<char>, path: &'a Path) -> Self {
        let comment = comment.filter(char::is_ascii).map(|c| c as u8);
        Tokens {
            text,
            pos: 0,
            line: 1,
            tok_line: 1,
            comment,
            path,
        }
    }

    /// Skip whitespace and comments to the next token; false at the end of the text.
    fn skip(&mut self) -> bool {
        let b = self.text.as_bytes();
        while self.pos < b.len() {
            let c = b[self.pos];
            if c == b'\n' {
                self.line += 1;
                self.pos += 1;
            } else if c.is_ascii_whitespace() {
                self.pos += 1;
            } else if Some(c) == self.comment {
                while self.pos < b.len() && b[self.pos] != b'\n' {
                    self.pos += 1;
                }
            } else {
                return true;
            }
        }
        false
    }

    /// Line number of the next token (of the end of the text if there is none).
    pub(crate) fn line_no(&mut self) -> usize {
        self.skip();
        self.line
    }

    /// An error at the next token's line.
    pub(crate) fn err(&mut self, message: impl fmt::Display) -> MeshError {
        let line = self.line_no();
        self.err_line(line, message)
    }

    /// An error on a given line.
    pub(crate) fn err_line(&self, line: usize, message: impl fmt::Display) -> MeshError {
        file_err(self.path, format!("line {line}: {message}"))
    }

    /// The next token, if any.
    pub(crate) fn peek(&mut self) -> Option<&'a str> {
        if !self.skip() {
            return None;
        }
        let b = self.text.as_bytes();
        let mut end = self.pos;
        while end < b.len() && !b[end].is_ascii_whitespace() && Some(b[end]) != self.comment {
            end += 1;
        }
        Some(&self.text[self.pos..end])
    }

    /// The next token, or an error saying what was expected.
    pub(crate) fn next(&mut self, what: &str) -> Result<&'a str, MeshError> {
        match self.peek() {
            Some(t) => {
                self.pos += t.len();
                self.tok_line = self.line;
                Ok(t)
            }
            None => Err(file_err(
                self.path,
                format!("unexpected end of file, expected {what}"),
            )),
        }
    }

    /// The next token as a non-negative integer.
    pub(crate) fn usize(&mut self, what: &str) -> Result<usize, MeshError> {
        let t = self.next(what)?;
        t.parse().map_err(|_| {
            self.err_line(
                self.tok_line,
                format!("expected {what} (a non-negative integer), found '{t}'"),
            )
        })
    }

    /// The next token as a (possibly negative) integer.
    pub(crate) fn i64(&mut self, what: &str) -> Result<i64, MeshError> {
        let t = self.next(what)?;
        t.parse().map_err(|_| {
            self.err_line(
                self.tok_line,
                format!("expected {what} (an integer), found '{t}'"),
            )
        })
    }

    /// The next token as a finite float.
    pub(crate) fn f64(&mut self, what: &str) -> Result<f64, MeshError> {
        let t = self.next(what)?;
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.err_line(self.tok_line, format!("{what} is not finite: '{t}'"))),
            Err(_) => Err(self.err_line(
                self.tok_line,
                format!("expected {what} (a number), found '{t}'"),
            )),
        }
    }

    /// The rest of the current line (after the last token taken), trimmed, and move past it.
    pub(crate) fn rest_of_line(&mut self) -> &'a str {
        let b = self.text.as_bytes();
        let start = self.pos;
        while self.pos < b.len() && b[self.pos] != b'\n' {
            self.pos += 1;
        }
        let rest = &self.text[start..self.pos];
        if self.pos < b.len() {
            self.pos += 1;
            self.line += 1;
        }
        rest.trim()
    }
}

#[cfg(test)]
pub(crate) mod test_util {
    use super::*;
    use std::f64::consts::PI;

    /// A temp directory removed on drop (no tempfile dependency).
    pub struct TempDir(pub PathBuf);

    impl TempDir {
        pub fn new(tag: &str) -> TempDir {
            static N: AtomicUsize = AtomicUsize::new(0);
            let dir = std::env::temp_dir().join(format!(
                "mesh-io-{tag}-{}-{}",
                std::process::id(),
                N.fetch_add(1, Ordering::Relaxed)
            ));
            fs::create_dir_all(&dir).unwrap();
            TempDir(dir)
        }
        pub fn path(&self, name: &str) -> PathBuf {
            self.0.join(name)
        }
        /// Names of the files in the directory, sorted.
        pub fn files(&self) -> Vec<String> {
            let mut v: Vec<String> = fs::read_dir(&self.0)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            v.sort();
            v
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    /// Write [`square_with_hole`] to `file` in a temp directory and read it back: points and
    /// triangles come back unchanged and every vertex keeps its loop. Returns the mesh read.
    pub fn assert_round_trip_keeps_loops(
        file: &str,
        write: fn(&Mesh, &Path) -> Result<(), MeshError>,
        read: fn(&Path) -> Result<Mesh, MeshError>,
    ) -> Mesh {
        let dir = TempDir::new(file);
        let m = square_with_hole();
        let p = dir.path(file);
        write(&m, &p).unwrap();
        let r = read(&p).unwrap();
        assert_eq!(r.points, m.points);
        assert_eq!(r.triangles, m.triangles);
        for (a, b) in r.markers.iter().zip(&m.markers) {
            assert_eq!(a.loop_index(), b.loop_index());
        }
        r
    }

    /// A conforming mesh of the square [0, 3]² with the square hole [1, 2]², on a 7×7 grid of
    /// spacing 1/2 whose coordinates are perturbed to awkward floats (not short decimals), with
    /// full markers: outer loop 0, hole loop 1, the eight square corners as `Corner`s.
    pub fn square_with_hole() -> Mesh {
        let n = 7usize;
        let id = |i: usize, j: usize| (j * n + i) as u32;
        let in_hole_cell = |i: usize, j: usize| (2..4).contains(&i) && (2..4).contains(&j);
        let mut points = Vec::new();
        let mut markers = Vec::new();
        let corners_outer = [(0, 0), (6, 0), (6, 6), (0, 6)];
        let corners_hole = [(2, 2), (2, 4), (4, 4), (4, 2)];
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
                let outer = i == 0 || j == 0 || i == n - 1 || j == n - 1;
                let hole = (2..=4).contains(&i) && (2..=4).contains(&j) && !(i == 3 && j == 3);
                // Wiggle interior points by irrational amounts to exercise exact round trips.
                let p = if outer || hole {
                    DVec2::new(x, y)
                } else {
                    DVec2::new(
                        x + 0.01 * (PI * x + 1.0).sin() / 3.0,
                        y + 1e-7 * (y * y + 0.1).sqrt(),
                    )
                };
                points.push(p);
                let loop_param = x * 3.0 + y / 7.0;
                markers.push(
                    if let Some(c) = corners_outer.iter().position(|&c| c == (i, j)) {
                        VertexMarker::Corner {
                            loop_index: 0,
                            corner: c,
                            loop_param,
                        }
                    } else if let Some(c) = corners_hole.iter().position(|&c| c == (i, j)) {
                        VertexMarker::Corner {
                            loop_index: 1,
                            corner: 4 + c,
                            loop_param,
                        }
                    } else if outer {
                        VertexMarker::Boundary {
                            loop_index: 0,
                            piece: (i + j) % 4,
                            loop_param,
                        }
                    } else if hole {
                        VertexMarker::Boundary {
                            loop_index: 1,
                            piece: 4 + (i * j) % 4,
                            loop_param,
                        }
                    } else {
                        VertexMarker::Interior
                    },
                );
            }
        }
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                if in_hole_cell(i, j) {
                    continue;
                }
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                if (i + j) % 2 == 0 {
                    triangles.push([a, b, c]);
                    triangles.push([a, c, d]);
                } else {
                    triangles.push([a, b, d]);
                    triangles.push([b, c, d]);
                }
            }
        }
        // The hole centre (3, 3) is in no triangle: drop it, renumbering the later vertices.
        let centre = id(3, 3);
        points.remove(centre as usize);
        markers.remove(centre as usize);
        for t in &mut triangles {
            for v in t.iter_mut() {
                if *v > centre {
                    *v -= 1;
                }
            }
        }
        Mesh {
            points,
            triangles,
            markers,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_util::*;
    use super::*;

    /// A byte-order mark at the start of a Triangle or Wavefront file (what editors on Windows
    /// write) is skipped, not read as the first number.
    #[test]
    fn a_byte_order_mark_is_skipped() {
        let dir = TempDir::new("bom");
        let (node, ele) = ("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "1 3 0\n1 1 2 3\n");
        fs::write(dir.path("t.node"), format!("\u{feff}{node}")).unwrap();
        fs::write(dir.path("t.ele"), format!("\u{feff}{ele}")).unwrap();
        let m = read_mesh(&dir.path("t.node")).unwrap();
        assert_eq!((m.num_vertices(), m.num_triangles()), (3, 1));
        fs::write(
            dir.path("t.obj"),
            "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        )
        .unwrap();
        let m = read_mesh(&dir.path("t.obj")).unwrap();
        assert_eq!((m.num_vertices(), m.num_triangles()), (3, 1));
    }

    /// Integers are appended as `{}` writes them, at the extremes and signs too.
    #[test]
    fn push_int_writes_what_display_writes() {
        let mut rng = geometry::Rng::new(11);
        let mut values = vec![
            0,
            1,
            -1,
            9,
            10,
            -10,
            99,
            100,
            i64::MAX,
            i64::MIN,
            i64::MIN + 1,
        ];
        values.extend((0..10_000).map(|_| (rng.uniform() * 2e18 - 1e18) as i64));
        values.extend((0..10_000).map(|_| rng.below(1000) as i64 - 500));
        for v in values {
            let mut s = String::from("x");
            push_int(&mut s, v);
            assert_eq!(s, format!("x{v}"));
        }
    }

    #[test]
    fn lines_formatted_in_parallel_are_written_in_order() {
        // Across several batches and a ragged last chunk: the bytes of writing one by one.
        use std::fmt::Write as _;
        let line = |i: usize, s: &mut String| {
            let _ = writeln!(s, "{} {} {}", i + 1, F(i as f64 * 0.1), i % 7);
        };
        for n in [0, 1, 4095, 150_001] {
            let mut one_by_one = String::new();
            for i in 0..n {
                line(i, &mut one_by_one);
            }
            let mut out: Vec<u8> = Vec::new();
            write_lines(&mut out, n, line).unwrap();
            assert!(out == one_by_one.as_bytes(), "{n} lines");
        }
    }

    #[test]
    fn float_format_round_trips_exactly() {
        for x in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1.0 / 3.0,
            -2.5e-7,
            1e-300,
            6.02e23,
            f64::MAX,
            f64::MIN_POSITIVE,
            123456.789,
        ] {
            let s = F(x).to_string();
            assert_eq!(
                s.parse::<f64>().unwrap().to_bits(),
                x.to_bits(),
                "{x} -> {s}"
            );
            assert!(s.len() < 26, "{s}");
        }
        assert_eq!(F(0.5).to_string(), "0.5");
        assert_eq!(F(1e-7).to_string(), "1e-7");
    }

    /// What `F` writes but for ties: `{}` for zero and magnitudes in [1e-5, 1e16), `{:e}`
    /// otherwise.
    fn std_text(x: f64) -> String {
        let a = x.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) {
            format!("{x}")
        } else {
            format!("{x:e}")
        }
    }

    #[test]
    fn float_text_is_the_standard_librarys_but_for_ties() {
        let mut rng = geometry::Rng::new(5);
        let mut values = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            10.0,
            100.0,
            0.1,
            1e-5,
            9.999999999999999e-6,
            1e16,
            9999999999999998.0,
            1e15,
            123456789012345680.0,
            5e-324,
            f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1.0 / 3.0,
            2.0f64.powi(60),
        ];
        // Every bit pattern's exponent, coordinates of ordinary meshes, integers, and decimals
        // with few digits.
        for _ in 0..300_000 {
            let bits = (rng.uniform() * 2f64.powi(32)) as u64
                | (((rng.uniform() * 2f64.powi(32)) as u64) << 32);
            values.push(f64::from_bits(bits));
            values.push((rng.uniform() - 0.5) * 2000.0);
            values.push(((rng.uniform() - 0.5) * 2e6).round());
            values.push(((rng.uniform() - 0.5) * 2e4).round() / 1000.0);
            values.push(rng.uniform() * 10f64.powi((rng.uniform() * 44.0) as i32 - 22));
        }
        let (mut pushed, mut ties) = (String::new(), 0);
        for &x in &values {
            let expected = std_text(x);
            let text = F(x).to_string();
            pushed.clear();
            push_float(&mut pushed, x);
            assert_eq!(pushed, text);
            if text != expected {
                // Two shortest texts equally near x: the same length, both read back to x.
                ties += 1;
                assert_eq!(text.len(), expected.len(), "{text} for {expected}");
                assert_eq!(
                    text.parse::<f64>().unwrap().to_bits(),
                    x.to_bits(),
                    "{text}"
                );
            }
        }
        assert!(
            ties < values.len() / 1000,
            "{ties} of {} differ",
            values.len()
        );
        // Exactly halfway between the two 17-digit texts.
        let tie = 1_748_266_582_941_778.0 + 0.25;
        assert_eq!(F(tie).to_string(), "1748266582941778.2");
        assert_eq!(std_text(tie), "1748266582941778.3");
        assert_eq!(F(-0.0).to_string(), "-0");
        assert_eq!(F(123.0).to_string(), "123");
    }

    #[test]
    fn test_mesh_is_a_valid_mesh_of_its_region() {
        let m = square_with_hole();
        assert_eq!(m.num_vertices(), 48);
        assert_eq!(m.num_triangles(), 2 * 36 - 2 * 4);
        assert!((m.area() - 8.0).abs() < 1e-12);
        for t in 0..m.num_triangles() {
            let [a, b, c] = m.triangle(t);
            assert!((b - a).perp_dot(c - a) > 0.0);
        }
        // Every boundary edge joins marked vertices of one loop.
        for (a, b) in crate::types::single_edges(&m.triangles) {
            let (la, lb) = (
                m.markers[a as usize].loop_index(),
                m.markers[b as usize].loop_index(),
            );
            assert!(la.is_some() && la == lb, "edge {a}-{b}");
        }
    }

    #[test]
    fn topology_markers_find_outer_loop_and_hole() {
        let m = square_with_hole();
        let inferred = markers_from_topology(&m.points, &m.triangles);
        for (i, (got, want)) in inferred.iter().zip(&m.markers).enumerate() {
            assert_eq!(got.loop_index(), want.loop_index(), "vertex {i}");
            if let VertexMarker::Boundary {
                piece, loop_param, ..
            } = *got
            {
                assert_eq!(piece, UNKNOWN_PIECE);
                assert!(loop_param.is_nan());
            }
        }
        // Renumbering the vertices so that the hole comes first must not change which loop is 0.
        let n = m.points.len() as u32;
        let rev = |v: u32| n - 1 - v;
        let points: Vec<DVec2> = m.points.iter().rev().copied().collect();
        let tris: Vec<[u32; 3]> = m.triangles.iter().map(|t| t.map(rev)).collect();
        let inferred = markers_from_topology(&points, &tris);
        for v in 0..n {
            assert_eq!(
                inferred[rev(v) as usize].loop_index(),
                m.markers[v as usize].loop_index()
            );
        }
    }

    #[test]
    fn dispatch_by_extension_and_unknown_extension_errors() {
        let dir = TempDir::new("dispatch");
        let m = square_with_hole();
        for name in ["a.node", "b.ele", "c.msh", "d.vtu", "e.OBJ"] {
            write_mesh(&m, &dir.path(name)).unwrap();
        }
        assert_eq!(
            dir.files(),
            ["a.ele", "a.node", "a.poly", "b.ele", "b.node", "b.poly", "c.msh", "d.vtu", "e.OBJ"]
        );
        for name in ["a.node", "b.ele", "c.msh", "d.vtu", "e.OBJ"] {
            let r = read_mesh(&dir.path(name)).unwrap();
            assert_eq!(r.points, m.points, "{name}");
            assert_eq!(r.triangles, m.triangles, "{name}");
        }
        let e = write_mesh(&m, &dir.path("f.stl")).unwrap_err().to_string();
        assert!(
            e.contains("'.stl'") && e.contains(".node, .ele, .poly, .msh, .vtu, .obj"),
            "{e}"
        );
        let e = write_mesh(&m, &dir.path("noext")).unwrap_err().to_string();
        assert!(e.contains("no extension"), "{e}");
        let e = read_mesh(&dir.path("f.stl")).unwrap_err().to_string();
        assert!(e.contains(".node, .ele, .msh, .vtu, .obj"), "{e}");
        assert_eq!(dir.files().len(), 9, "failed writes must create nothing");
    }

    #[test]
    fn missing_directory_is_an_error_and_creates_nothing() {
        let dir = TempDir::new("missing");
        let m = square_with_hole();
        for name in ["x.node", "x.msh", "x.vtu", "x.obj"] {
            let target = dir.path("no-such-dir").join(name);
            let e = write_mesh(&m, &target).unwrap_err();
            assert!(matches!(e, MeshError::Io { .. }), "{e}");
            assert_eq!(e.path(), Some(target.as_path()));
            assert!(e.to_string().contains("no-such-dir"), "{e}");
            // The OS reason is in the message once, and not repeated by a source chain.
            assert!(e.to_string().contains("cannot write: "), "{e}");
            assert!(std::error::Error::source(&e).is_none());
            assert!(!target.exists());
        }
        assert!(dir.files().is_empty());
    }

    #[test]
    fn failed_write_keeps_the_previous_file_and_leaves_no_temp() {
        let dir = TempDir::new("keep");
        let m = square_with_hole();
        let path = dir.path("m.msh");
        write_mesh(&m, &path).unwrap();
        let before = fs::read(&path).unwrap();
        let mut bad = m.clone();
        bad.points[5].x = f64::NAN;
        let e = write_mesh(&bad, &path).unwrap_err().to_string();
        assert!(e.contains("vertex 5 is not finite"), "{e}");
        bad = m.clone();
        bad.triangles[0][1] = 999;
        assert!(write_mesh(&bad, &path)
            .unwrap_err()
            .to_string()
            .contains("triangle 0"));
        assert_eq!(fs::read(&path).unwrap(), before);
        assert_eq!(dir.files(), ["m.msh"]);
    }

    #[test]
    fn atomic_write_replaces_the_file_and_a_failure_leaves_it() {
        let dir = TempDir::new("atomic");
        let path = dir.path("t.csv");
        write_atomic(&path, b"first").unwrap();
        write_atomic(&path, b"second").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"second");
        // A directory in the way: the rename fails, and the temporary file goes.
        let blocked = dir.path("sub");
        fs::create_dir(&blocked).unwrap();
        fs::write(blocked.join("x"), b"keep").unwrap();
        assert!(write_atomic(&blocked, b"x").is_err());
        assert!(write_atomic(Path::new("/"), b"x").is_err());
        assert_eq!(fs::read(&path).unwrap(), b"second");
        assert_eq!(dir.files(), ["sub", "t.csv"]);
    }

    #[test]
    fn producer_failure_removes_every_temp_file() {
        let dir = TempDir::new("producer");
        let ok: Producer = Box::new(|w| w.write_all(b"fine"));
        let bad: Producer = Box::new(|w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("disk full"))
        });
        let e = write_files(vec![(dir.path("a.txt"), ok), (dir.path("b.txt"), bad)]).unwrap_err();
        assert!(e.to_string().contains("disk full"), "{e}");
        assert!(dir.files().is_empty(), "{:?}", dir.files());
    }

    #[test]
    fn a_directory_in_the_way_changes_no_file() {
        let dir = TempDir::new("dirway");
        let m = square_with_hole();
        let base = dir.path("m.node");
        write_mesh(&m, &base).unwrap();
        let node_before = fs::read(&base).unwrap();
        fs::remove_file(dir.path("m.poly")).unwrap();
        fs::create_dir(dir.path("m.poly")).unwrap();
        let mut moved = m.clone();
        moved.points[0].x += 0.25;
        let e = write_mesh(&moved, &base).unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        assert_eq!(fs::read(&base).unwrap(), node_before, ".node was replaced");
        assert!(
            !dir.files().iter().any(|f| f.ends_with(".tmp")),
            "{:?}",
            dir.files()
        );
    }

    #[test]
    fn tokens_report_line_numbers() {
        let p = Path::new("t.txt");
        let mut t = Tokens::new("# head\n\n 3  4.5 # c\nfoo\n", Some('#'), p);
        assert_eq!(t.usize("count").unwrap(), 3);
        assert_eq!(t.f64("x").unwrap(), 4.5);
        let e = t.f64("y").unwrap_err().to_string();
        assert_eq!(e, "t.txt: line 4: expected y (a number), found 'foo'");
        let e = t.next("z").unwrap_err().to_string();
        assert!(e.contains("unexpected end of file, expected z"), "{e}");
    }

    #[test]
    fn read_back_meshes_conform_after_restoring_markers() {
        let region = geometry::formats::loops_from_str(
            "0 0\n3 0\n3 3\n0 3\n\n1 1\n1 2\n2 2\n2 1\n",
            "test",
            "square_hole",
        )
        .unwrap();
        let m = square_with_hole();
        crate::check_conforming(&m, &region).unwrap();
        let dir = TempDir::new("restore");
        for name in ["m.node", "m.msh", "m.obj"] {
            write_mesh(&m, &dir.path(name)).unwrap();
            let mut r = read_mesh(&dir.path(name)).unwrap();
            crate::check_conforming(&r, &region).unwrap_or_else(|e| panic!("{name}: {e}"));
            restore_markers(&mut r, &region);
            crate::check_conforming(&r, &region).unwrap();
            let corners = r
                .markers
                .iter()
                .filter(|m| matches!(m, VertexMarker::Corner { .. }))
                .count();
            assert_eq!(corners, 8, "{name}");
            for (p, mk) in r.points.iter().zip(&r.markers) {
                match *mk {
                    VertexMarker::Interior => assert!(region.signed_distance(*p) < -1e-9),
                    VertexMarker::Boundary {
                        loop_index,
                        piece,
                        loop_param,
                    } => {
                        assert_eq!(region.piece_loop(piece), loop_index);
                        assert!(
                            loop_param >= 0.0 && loop_param <= region.loops()[loop_index].length
                        );
                        let (q, _) = region.pieces()[piece].closest_point(*p);
                        assert!(
                            (q - *p).length() < 1e-12,
                            "{name}: {p} is not on piece {piece}"
                        );
                    }
                    VertexMarker::Corner {
                        loop_index, corner, ..
                    } => {
                        assert_eq!(region.corners()[corner].pos, *p);
                        assert_eq!(region.corners()[corner].loop_index, loop_index);
                    }
                }
            }
        }
    }

    /// Manual interoperability check (needs `python3` with `meshio`): meshio must read our
    /// `.msh` and `.vtu` files to the same triangles, and find the quality fields.
    #[test]
    #[ignore = "needs python3 with meshio"]
    fn meshio_reads_msh_and_vtu() {
        let dir = TempDir::new("meshio");
        let m = square_with_hole();
        write_mesh(&m, &dir.path("m.msh")).unwrap();
        write_mesh(&m, &dir.path("m.vtu")).unwrap();
        let script = r#"
import sys, meshio
for f in sys.argv[1:]:
    m = meshio.read(f)
    tris = [c.data for c in m.cells if c.type == "triangle"][0]
    print(f.rsplit(".", 1)[1], len(m.points), len(tris), sorted(m.cell_data.keys()), sorted(m.point_data.keys()))
    for t in tris:
        print(" ".join(repr(float(v)) for i in t for v in m.points[i][:2]))
"#;
        let out = std::process::Command::new("python3")
            .arg("-c")
            .arg(script)
            .arg(dir.path("m.msh"))
            .arg(dir.path("m.vtu"))
            .output()
            .expect("python3 runs");
        assert!(
            out.status.success(),
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        let mut want: Vec<Vec<f64>> = (0..m.num_triangles())
            .map(|t| m.triangle(t).iter().flat_map(|p| [p.x, p.y]).collect())
            .collect();
        want.sort_by(|a, b| a.partial_cmp(b).unwrap());
        // meshio may print notices of its own; our output starts at the "msh"/"vtu" headers.
        let mut lines = text.lines();
        for ext in ["msh ", "vtu "] {
            let head = lines
                .find(|l| l.starts_with(ext))
                .unwrap_or_else(|| panic!("{text}"));
            println!("{head}");
            assert!(head.contains(" 48 64 "), "{head}\n{text}");
            let mut got: Vec<Vec<f64>> = (0..64)
                .map(|_| {
                    lines
                        .next()
                        .unwrap()
                        .split(' ')
                        .map(|s| s.parse().unwrap())
                        .collect()
                })
                .collect();
            got.sort_by(|a, b| a.partial_cmp(b).unwrap());
            assert_eq!(got, want, "{head}");
        }
        assert!(
            text.contains("'area', 'min_angle_deg', 'q'") && text.contains("'boundary_marker'"),
            "{text}"
        );

        // And the other way: Gmsh files written by meshio (4.1 and 2.2 ASCII) read back here.
        let script = r#"
import sys, meshio
m = meshio.read(sys.argv[1])
meshio.write(sys.argv[2], m, file_format="gmsh", binary=False)
meshio.write(sys.argv[3], m, file_format="gmsh22", binary=False)
"#;
        let status = std::process::Command::new("python3")
            .args(["-c", script])
            .args([dir.path("m.vtu"), dir.path("w41.msh"), dir.path("w22.msh")])
            .status()
            .expect("python3 runs");
        assert!(status.success());
        for name in ["w41.msh", "w22.msh"] {
            let r = read_mesh(&dir.path(name)).unwrap();
            assert_eq!(r.points, m.points, "{name}");
            assert_eq!(r.triangles, m.triangles, "{name}");
            for (a, b) in r.markers.iter().zip(&m.markers) {
                assert_eq!(a.loop_index(), b.loop_index(), "{name}");
            }
        }
    }
}
