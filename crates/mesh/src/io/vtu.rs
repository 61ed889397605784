//! VTK XML unstructured grid (`.vtu`): written in ASCII, for ParaView and meshio; read in every
//! encoding they write.
use super::{
    file_err, io_err, keep_corners, planar_z, read_mesh_parts, validate_for_writing, write_files,
    MeshFile, Nodes, Producer, Walls, F,
};
use crate::{Mesh, MeshError};
use geometry::DVec2;
use std::io::Write;
use std::path::Path;

/// Per-triangle quality: (smallest angle in degrees, area, q = R/(2r)).
///
/// q is the paper's circle ratio abc / ((b+c−a)(c+a−b)(a+b−c)) (Section 3): 1 for an
/// equilateral triangle, larger for worse ones; a degenerate triangle gets `f64::MAX` so the
/// file stays readable by parsers that reject `inf`.
pub fn triangle_quality(p: [DVec2; 3]) -> (f64, f64, f64) {
    let [a, b, c] = [
        (p[1] - p[2]).length(),
        (p[2] - p[0]).length(),
        (p[0] - p[1]).length(),
    ];
    let area = 0.5 * (p[1] - p[0]).perp_dot(p[2] - p[0]);
    let min_angle = crate::triangle_min_angle_deg(p);
    let denom = (b + c - a) * (c + a - b) * (a + b - c);
    let q = if denom > 0.0 && area != 0.0 {
        (a * b * c / denom).min(f64::MAX)
    } else {
        f64::MAX
    };
    (
        if min_angle.is_finite() {
            min_angle
        } else {
            0.0
        },
        area,
        q,
    )
}

/// Write `mesh` as a VTK XML unstructured grid in ASCII: points (z = 0), triangles (VTK type 5),
/// cell data `min_angle_deg`, `area` and `q` (see [`triangle_quality`]), and point data
/// `boundary_marker` (loop index + 1, 0 for interior vertices). Through
/// [`write_mesh_on`](super::write_mesh_on), a region that numbers its walls
/// ([`geometry::Region::piece_markers`]) adds point data `wall_marker`: each boundary vertex's
/// wall, as Triangle's `.node` gets it.
pub fn write_vtu(mesh: &Mesh, path: &Path) -> Result<(), MeshError> {
    validate_for_writing(mesh, path)?;
    write_nodes(&Nodes::linear(mesh, None), path)
}

/// Write `nodes` as [`write_vtu`] does; six-node triangles are VTK's quadratic triangle (type
/// 22, the same node order), their qualities those of their corners' triangle.
pub(crate) fn write_nodes(nodes: &Nodes, path: &Path) -> Result<(), MeshError> {
    let per = nodes.per_triangle();
    let cell_type = if per == 6 { 22 } else { 5 };
    let produce: Producer = Box::new(|w: &mut dyn Write| {
        let (n, t) = (nodes.points.len(), nodes.triangles.len());
        let quality: Vec<(f64, f64, f64)> = (0..t)
            .map(|k| triangle_quality(nodes.linear.triangle(k)))
            .collect();
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(w, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">")?;
        writeln!(w, "  <UnstructuredGrid>")?;
        writeln!(
            w,
            "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{t}\">"
        )?;
        writeln!(w, "      <PointData Scalars=\"boundary_marker\">")?;
        writeln!(
            w,
            "        <DataArray type=\"Int32\" Name=\"boundary_marker\" format=\"ascii\">"
        )?;
        for m in nodes.markers {
            writeln!(w, "{}", m.loop_index().map_or(0, |l| l + 1))?;
        }
        writeln!(w, "        </DataArray>")?;
        if let Some((_, by_node)) = nodes.wall_markers() {
            writeln!(
                w,
                "        <DataArray type=\"Int64\" Name=\"wall_marker\" format=\"ascii\">"
            )?;
            for m in by_node {
                writeln!(w, "{m}")?;
            }
            writeln!(w, "        </DataArray>")?;
        }
        writeln!(w, "      </PointData>")?;
        writeln!(w, "      <CellData Scalars=\"q\">")?;
        for (name, field) in [("min_angle_deg", 0), ("area", 1), ("q", 2)] {
            writeln!(
                w,
                "        <DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
            )?;
            for q in &quality {
                writeln!(w, "{}", F([q.0, q.1, q.2][field]))?;
            }
            writeln!(w, "        </DataArray>")?;
        }
        if let Some(ids) = &nodes.subdomains {
            writeln!(
                w,
                "        <DataArray type=\"Int32\" Name=\"subdomain\" format=\"ascii\">"
            )?;
            for id in ids {
                writeln!(w, "{id}")?;
            }
            writeln!(w, "        </DataArray>")?;
        }
        writeln!(w, "      </CellData>")?;
        writeln!(w, "      <Points>")?;
        writeln!(w, "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">")?;
        for p in nodes.points {
            writeln!(w, "{} {} 0", F(p.x), F(p.y))?;
        }
        writeln!(w, "        </DataArray>\n      </Points>")?;
        writeln!(w, "      <Cells>")?;
        writeln!(
            w,
            "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
        )?;
        for tri in &nodes.triangles {
            write!(w, "{}", tri[0])?;
            for v in &tri[1..] {
                write!(w, " {v}")?;
            }
            writeln!(w)?;
        }
        writeln!(w, "        </DataArray>")?;
        writeln!(
            w,
            "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
        )?;
        for k in 1..=t {
            writeln!(w, "{}", per * k)?;
        }
        writeln!(w, "        </DataArray>")?;
        writeln!(
            w,
            "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
        )?;
        for _ in 0..t {
            writeln!(w, "{cell_type}")?;
        }
        writeln!(w, "        </DataArray>\n      </Cells>")?;
        writeln!(w, "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>")
    });
    write_files(vec![(path.to_path_buf(), produce)])
}

/// Read a VTK XML unstructured grid (`.vtu`) as ParaView, VTK and meshio write it: ASCII,
/// base64 (`binary`) or appended (raw or base64) data arrays, little- or big-endian, with
/// 32- or 64-bit headers, uncompressed or zlib-compressed, in one piece or several (whose
/// points are concatenated). Triangles (VTK cell type 5) and quadratic triangles (22, read by
/// their corners) make the mesh; vertices and lines are skipped; any other cell is an error.
/// z must be 0. Markers come from the mesh topology ([`super::markers_from_topology`]); the
/// file's point data (`boundary_marker`, `wall_marker`) is not read, and a `.vtu` carries no
/// walls; a cell array `subdomain` (whole numbers, as cvtmesh writes it) numbers the triangles'
/// parts ([`super::read_mesh_with_walls`]).
pub fn read_vtu(path: &Path) -> Result<Mesh, MeshError> {
    read_vtu_file(path).map(|f| f.mesh)
}

/// Parse the bytes of a `.vtu` file, as [`read_vtu`] reads a file; errors name `mesh.vtu`.
///
/// ```
/// let text = r#"<?xml version="1.0"?>
/// <VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">
///   <UnstructuredGrid>
///     <Piece NumberOfPoints="3" NumberOfCells="1">
///       <Points>
///         <DataArray type="Float64" NumberOfComponents="3" format="ascii">
///           0 0 0  1 0 0  0 1 0
///         </DataArray>
///       </Points>
///       <Cells>
///         <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
///         <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
///         <DataArray type="UInt8" Name="types" format="ascii">5</DataArray>
///       </Cells>
///     </Piece>
///   </UnstructuredGrid>
/// </VTKFile>
/// "#;
/// let m = cvtmesh::io::vtu_from_bytes(text.as_bytes())?;
/// assert_eq!((m.num_vertices(), m.num_triangles()), (3, 1));
/// // A quadrangle (VTK cell type 9) is refused, by name.
/// let quad = text.replace("3\" NumberOfCells", "4\" NumberOfCells")
///     .replace("0 1 0\n", "0 1 0  1 1 0\n")
///     .replace("0 1 2<", "0 1 3 2<")
///     .replace(">3<", ">4<")
///     .replace(">5<", ">9<");
/// let e = cvtmesh::io::vtu_from_bytes(quad.as_bytes()).unwrap_err();
/// assert!(e.to_string().contains("quad"), "{e}");
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn vtu_from_bytes(bytes: &[u8]) -> Result<Mesh, MeshError> {
    Ok(parse(bytes, Path::new("mesh.vtu"))?.mesh)
}

/// [`read_vtu`], with the triangles' node count and a six-node file's edge nodes; no walls
/// but the parts a `subdomain` cell array numbers (as [`super::write_mesh_on`] writes it): the
/// edges between two of them are inner lines, and their numbers the triangles' subdomains.
pub(crate) fn read_vtu_file(path: &Path) -> Result<MeshFile, MeshError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, "read", e))?;
    let parsed = parse(&bytes, path)?;
    Ok(MeshFile {
        walls: Walls {
            inner: super::inner_edges(&parsed.mesh, &parsed.subdomains, &[]),
            subdomains: parsed.subdomains,
            ..Walls::default()
        },
        mesh: parsed.mesh,
        triangle_nodes: parsed.triangle_nodes,
        edge_nodes: parsed.edge_nodes,
    })
}

/// What a `.vtu` file holds for us.
struct Parsed {
    mesh: Mesh,
    triangle_nodes: usize,
    edge_nodes: Vec<([u32; 2], DVec2)>,
    /// Each triangle's number from the `subdomain` cell array (empty without one).
    subdomains: Vec<i64>,
}

/// A VTK cell type's name, for the refusal of a cell that is no triangle.
fn cell_name(t: u64) -> Option<&'static str> {
    Some(match t {
        0 => "empty cell",
        6 => "triangle strip",
        7 => "polygon",
        8 => "pixel",
        9 => "quad",
        10 => "tetra",
        11 => "voxel",
        12 => "hexahedron",
        13 => "wedge",
        14 => "pyramid",
        15 => "pentagonal prism",
        16 => "hexagonal prism",
        23 => "quadratic quad",
        24 => "quadratic tetra",
        25 => "quadratic hexahedron",
        26 => "quadratic wedge",
        27 => "quadratic pyramid",
        28 => "biquadratic quad",
        29 => "triquadratic hexahedron",
        30 => "quadratic linear quad",
        31 => "quadratic linear wedge",
        32 => "biquadratic quadratic wedge",
        33 => "biquadratic quadratic hexahedron",
        34 => "biquadratic triangle",
        36 => "quadratic polygon",
        37 => "triquadratic pyramid",
        42 => "polyhedron",
        69 => "Lagrange triangle",
        70 => "Lagrange quadrilateral",
        71 => "Lagrange tetrahedron",
        72 => "Lagrange hexahedron",
        73 => "Lagrange wedge",
        74 => "Lagrange pyramid",
        76 => "Bezier triangle",
        77 => "Bezier quadrilateral",
        78 => "Bezier tetrahedron",
        79 => "Bezier hexahedron",
        80 => "Bezier wedge",
        81 => "Bezier pyramid",
        _ => return None,
    })
}

/// Cell types of no area, skipped as the Gmsh reader skips points and lines: vertex, poly
/// vertex, line, poly line, quadratic edge, cubic line, Lagrange and Bezier curves.
const SKIPPED_CELLS: &[u64] = &[1, 2, 3, 4, 21, 35, 68, 75];

/// The scalar type of a DataArray.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &[u8]) -> Option<Scalar> {
        use Scalar::*;
        Some(match name {
            b"Int8" | b"Char" => I8,
            b"UInt8" | b"UnsignedChar" => U8,
            b"Int16" => I16,
            b"UInt16" => U16,
            b"Int32" => I32,
            b"UInt32" => U32,
            b"Int64" => I64,
            b"UInt64" => U64,
            b"Float32" => F32,
            b"Float64" => F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        use Scalar::*;
        match self {
            I8 | U8 => 1,
            I16 | U16 => 2,
            I32 | U32 | F32 => 4,
            I64 | U64 | F64 => 8,
        }
    }

    fn signed(self) -> bool {
        matches!(self, Scalar::I8 | Scalar::I16 | Scalar::I32 | Scalar::I64)
    }

    fn float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// The unsigned integer of `b` (at most 8 bytes) in the file's byte order.
fn uint(b: &[u8], big: bool) -> u64 {
    let fold = |u: u64, &x: &u8| (u << 8) | u64::from(x);
    if big {
        b.iter().fold(0, fold)
    } else {
        b.iter().rev().fold(0, fold)
    }
}

/// One value of type `s` from its bytes, as an integer (ints) or a float (floats).
fn int_value(s: Scalar, b: &[u8], big: bool) -> i128 {
    let u = uint(b, big);
    let bits = 8 * b.len() as u32;
    if s.signed() && u >> (bits - 1) & 1 == 1 {
        i128::from(u) - (1i128 << bits)
    } else {
        i128::from(u)
    }
}

fn float_value(s: Scalar, b: &[u8], big: bool) -> f64 {
    match s {
        Scalar::F32 => f64::from(f32::from_bits(uint(b, big) as u32)),
        Scalar::F64 => f64::from_bits(uint(b, big)),
        _ => int_value(s, b, big) as f64,
    }
}

/// How a DataArray stores its values.
#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Binary,
    Appended(u64),
}

/// The arrays of a piece that make the mesh, and the cell array that numbers its parts.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    Points,
    Connectivity,
    Offsets,
    Types,
    Subdomain,
}

impl Role {
    fn name(self) -> &'static str {
        match self {
            Role::Points => "Points",
            Role::Connectivity => "connectivity",
            Role::Offsets => "offsets",
            Role::Types => "types",
            Role::Subdomain => "subdomain",
        }
    }
}

/// A DataArray as the XML describes it, with its text (empty for appended data).
struct Array {
    role: Role,
    scalar: Scalar,
    components: u64,
    format: Format,
    text: Vec<u8>,
    /// Line of its tag, for messages.
    line: usize,
}

impl Array {
    /// The words of an ASCII array's text.
    fn tokens(&self) -> impl Iterator<Item = &[u8]> {
        self.text
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty())
    }
}

/// A `<Piece>`: its counts and arrays.
#[derive(Default)]
struct Piece {
    points: u64,
    cells: u64,
    arrays: Vec<Array>,
}

impl Piece {
    fn array(&self, role: Role) -> Option<&Array> {
        self.arrays.iter().find(|a| a.role == role)
    }
}

/// The compressor named by `<VTKFile compressor=...>`.
#[derive(Clone, PartialEq)]
enum Compressor {
    None,
    Zlib,
    Other(String),
}

/// How the binary data of the file is laid out.
struct Layout<'a> {
    big: bool,
    header64: bool,
    compressor: Compressor,
    /// The bytes after the `_` of `<AppendedData>`, and whether they are base64.
    appended: Option<(&'a [u8], bool)>,
}

fn parse(bytes: &[u8], path: &Path) -> Result<Parsed, MeshError> {
    let err = |m: String| file_err(path, m);
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let (layout, pieces) = scan(bytes).map_err(err)?;
    let mut points: Vec<DVec2> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    // Six-node triangles' edge nodes: triangle, its edge (from corner k to k + 1), node.
    let mut edge_places: Vec<(usize, usize, u32)> = Vec::new();
    let mut quadratic = false;
    // Each triangle's number where every piece with triangles has a `subdomain` cell array.
    let mut numbers: Option<Vec<f64>> = Some(Vec::new());
    for (k, piece) in pieces.iter().enumerate() {
        let at = |m: String| {
            if pieces.len() > 1 {
                err(format!("piece {}: {m}", k + 1))
            } else {
                err(m)
            }
        };
        let base = points.len() as u64;
        // Vertex indices are u32.
        if base
            .checked_add(piece.points)
            .is_none_or(|n| n > u64::from(u32::MAX))
        {
            return Err(at(format!(
                "{} points: more than a mesh can hold (2^32)",
                piece.points
            )));
        }
        let need = |role: Role| {
            piece
                .array(role)
                .ok_or_else(|| at(format!("no '{}' DataArray", role.name())))
        };
        if piece.points > 0 {
            let a = need(Role::Points)?;
            if a.components != 3 {
                return Err(at(format!(
                    "line {}: Points have NumberOfComponents=\"{}\"; VTK points have 3",
                    a.line, a.components
                )));
            }
            let xyz = floats(a, &layout).map_err(at)?;
            if xyz.len() as u64 != piece.points.saturating_mul(3) {
                return Err(at(format!(
                    "line {}: Points hold {} numbers, but NumberOfPoints=\"{}\" needs 3 per point",
                    a.line,
                    xyz.len(),
                    piece.points
                )));
            }
            points.reserve(xyz.len() / 3);
            for (i, p) in xyz.chunks_exact(3).enumerate() {
                if !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()) {
                    return Err(at(format!(
                        "point {i} ({} {} {}) is not finite",
                        p[0], p[1], p[2]
                    )));
                }
                planar_z(p[2]).map_err(|m| at(format!("point {i}: {m}")))?;
                points.push(DVec2::new(p[0], p[1]));
            }
        }
        if piece.cells == 0 {
            continue;
        }
        let conn = uints(need(Role::Connectivity)?, &layout).map_err(at)?;
        let offsets = uints(need(Role::Offsets)?, &layout).map_err(at)?;
        let types = uints(need(Role::Types)?, &layout).map_err(at)?;
        let cell_numbers = match piece.array(Role::Subdomain) {
            Some(a) => {
                let v = floats(a, &layout).map_err(at)?;
                if v.len() as u64 != piece.cells {
                    return Err(at(format!(
                        "line {}: the subdomain array holds {} values for NumberOfCells=\"{}\"",
                        a.line,
                        v.len(),
                        piece.cells
                    )));
                }
                Some(v)
            }
            None => None,
        };
        if types.len() as u64 != piece.cells {
            return Err(at(format!(
                "{} cell types for NumberOfCells=\"{}\"",
                types.len(),
                piece.cells
            )));
        }
        // Each offset ends its cell; a list that also starts the first (n + 1 entries from 0)
        // is read too.
        let ends = match offsets.len() as u64 {
            n if n == piece.cells => &offsets[..],
            n if n == piece.cells + 1 && offsets[0] == 0 => &offsets[1..],
            n => {
                return Err(at(format!(
                    "{n} offsets for NumberOfCells=\"{}\"",
                    piece.cells
                )))
            }
        };
        let mut start = 0u64;
        for (c, (&end, &t)) in ends.iter().zip(&types).enumerate() {
            if end < start || end > conn.len() as u64 {
                return Err(at(format!(
                    "cell {c}: offset {end} is {} (connectivity has {} entries)",
                    if end < start {
                        format!("below the previous one, {start}")
                    } else {
                        "past the connectivity's end".to_string()
                    },
                    conn.len()
                )));
            }
            let nodes = &conn[start as usize..end as usize];
            start = end;
            let corners = match t {
                5 | 22 => {
                    let want = if t == 5 { 3 } else { 6 };
                    if nodes.len() != want {
                        return Err(at(format!(
                            "cell {c}: a {} with {} nodes, not {want}",
                            if t == 5 {
                                "triangle"
                            } else {
                                "quadratic triangle"
                            },
                            nodes.len()
                        )));
                    }
                    let mut global = [0u32; 6];
                    for (g, &v) in global.iter_mut().zip(nodes) {
                        if v >= piece.points {
                            return Err(at(format!(
                                "cell {c} refers to point {v}, but the piece has {} points",
                                piece.points
                            )));
                        }
                        // Below the point count, which fits in u32.
                        *g = (base + v) as u32;
                    }
                    if t == 22 {
                        quadratic = true;
                        for (e, &node) in global[3..].iter().enumerate() {
                            edge_places.push((triangles.len(), e, node));
                        }
                    }
                    [global[0], global[1], global[2]]
                }
                t if SKIPPED_CELLS.contains(&t) => continue,
                t => {
                    let what = match cell_name(t) {
                        Some(n) if n.starts_with(['a', 'e', 'i', 'o', 'u']) => format!("an {n}"),
                        Some(n) => format!("a {n}"),
                        None => "a cell".to_string(),
                    };
                    return Err(at(format!(
                        "cell {c} is {what} (VTK cell type {t}): only triangles (types 5 and \
                         22) can be read; split the cells into triangles (ParaView's \
                         Triangulate filter)"
                    )));
                }
            };
            triangles.push(corners);
            match (&mut numbers, &cell_numbers) {
                (Some(n), Some(v)) => n.push(v[c]),
                _ => numbers = None,
            }
        }
        if start != conn.len() as u64 {
            return Err(at(format!(
                "the last offset is {start}, but connectivity has {} entries",
                conn.len()
            )));
        }
    }
    if triangles.is_empty() && !points.is_empty() {
        return Err(err(
            "the file has no triangles (VTK cell types 5 and 22)".to_string()
        ));
    }
    let mut edge_nodes = Vec::new();
    if quadratic {
        // Where the edge nodes are, before the nodes that are no corners go: the mesh is its
        // corners' triangles.
        let places: Vec<DVec2> = edge_places
            .iter()
            .map(|&(_, _, v)| points[v as usize])
            .collect();
        let kept = keep_corners(points.len(), &mut triangles);
        points = kept.iter().map(|&i| points[i]).collect();
        edge_nodes = edge_places
            .iter()
            .zip(places)
            .map(|(&(t, e, _), p)| {
                let (a, b) = (triangles[t][e], triangles[t][(e + 1) % 3]);
                ([a.min(b), a.max(b)], p)
            })
            .collect();
        edge_nodes.sort_unstable_by_key(|e| e.0);
        edge_nodes.dedup_by_key(|e| e.0);
    }
    let bits: Vec<i64> = numbers
        .unwrap_or_default()
        .iter()
        .map(|v| v.to_bits() as i64)
        .collect();
    Ok(Parsed {
        mesh: read_mesh_parts(points, triangles, None),
        triangle_nodes: if quadratic { 6 } else { 3 },
        edge_nodes,
        subdomains: super::whole_numbers(&bits),
    })
}

/// The values of a float array (or of an integer array, as floats).
fn floats(a: &Array, layout: &Layout) -> Result<Vec<f64>, String> {
    let what = |m: String| format!("line {}: {}: {m}", a.line, a.role.name());
    if a.format == Format::Ascii {
        let mut out = Vec::new();
        for tok in a.tokens() {
            let s = std::str::from_utf8(tok).unwrap_or("");
            let v = if a.scalar == Scalar::F32 {
                s.parse::<f32>().map(f64::from).ok()
            } else {
                s.parse::<f64>().ok()
            };
            out.push(v.ok_or_else(|| {
                what(format!(
                    "'{}' is not a number",
                    String::from_utf8_lossy(tok)
                ))
            })?);
        }
        return Ok(out);
    }
    let (data, size) = binary_values(a, layout).map_err(what)?;
    Ok(data
        .chunks_exact(size)
        .map(|b| float_value(a.scalar, b, layout.big))
        .collect())
}

/// The bytes of a binary array and the size of each of its values, which they must fill.
fn binary_values(a: &Array, layout: &Layout) -> Result<(Vec<u8>, usize), String> {
    let data = binary(a, layout)?;
    let size = a.scalar.size();
    if data.len() % size != 0 {
        return Err(format!(
            "{} bytes are no whole number of {size}-byte values",
            data.len()
        ));
    }
    Ok((data, size))
}

/// The values of an integer array, none negative.
fn uints(a: &Array, layout: &Layout) -> Result<Vec<u64>, String> {
    let what = |m: String| format!("line {}: {}: {m}", a.line, a.role.name());
    if a.scalar.float() {
        return Err(what(
            "the values are floating-point; an integer type is needed".to_string(),
        ));
    }
    let check =
        |v: i128| u64::try_from(v).map_err(|_| what(format!("{v} is not an index or count")));
    if a.format == Format::Ascii {
        let mut out = Vec::new();
        for tok in a.tokens() {
            let v = std::str::from_utf8(tok)
                .ok()
                .and_then(|s| s.parse::<i128>().ok())
                .ok_or_else(|| {
                    what(format!(
                        "'{}' is not an integer",
                        String::from_utf8_lossy(tok)
                    ))
                })?;
            out.push(check(v)?);
        }
        return Ok(out);
    }
    let (data, size) = binary_values(a, layout).map_err(what)?;
    data.chunks_exact(size)
        .map(|b| check(int_value(a.scalar, b, layout.big)))
        .collect()
}

/// The data bytes of a binary or appended array: after its header, inflated if compressed.
fn binary(a: &Array, layout: &Layout) -> Result<Vec<u8>, String> {
    let mut src = match a.format {
        Format::Ascii => return Err("ASCII data is no binary data".to_string()),
        Format::Binary => Source::Base64(Base64::new(&a.text, 0)),
        Format::Appended(offset) => {
            let (data, base64) = layout.appended.ok_or(
                "the array's data is appended, but the file has no <AppendedData>".to_string(),
            )?;
            let at = usize::try_from(offset)
                .ok()
                .filter(|&o| o <= data.len())
                .ok_or_else(|| {
                    format!(
                        "offset {offset} is past the end of the appended data ({} bytes)",
                        data.len()
                    )
                })?;
            if base64 {
                Source::Base64(Base64::new(data, at))
            } else {
                Source::Raw { data, pos: at }
            }
        }
    };
    let header = |src: &mut Source| -> Result<u64, String> {
        let mut b = Vec::with_capacity(8);
        src.take(if layout.header64 { 8 } else { 4 }, &mut b)?;
        Ok(uint(&b, layout.big))
    };
    match &layout.compressor {
        Compressor::None => {
            let n = header(&mut src)?;
            let mut out = Vec::with_capacity((n as usize).min(1 << 20));
            src.take(n, &mut out)?;
            Ok(out)
        }
        Compressor::Other(name) => Err(format!(
            "the data is compressed with {name}, which is not supported: save the file \
             uncompressed or with zlib (vtkZLibDataCompressor; meshio: compression=None or \
             \"zlib\")"
        )),
        Compressor::Zlib => {
            let blocks = header(&mut src)?;
            let block_size = header(&mut src)?;
            let last_size = header(&mut src)?;
            let mut sizes = Vec::with_capacity((blocks as usize).min(1 << 20));
            for _ in 0..blocks {
                sizes.push(header(&mut src)?);
            }
            let mut out = Vec::new();
            let mut compressed = Vec::new();
            for (k, &csize) in sizes.iter().enumerate() {
                // The last block is shorter when the header says so (0: as long as the others).
                let size = if k + 1 == sizes.len() && last_size != 0 {
                    last_size
                } else {
                    block_size
                };
                let size = usize::try_from(size)
                    .map_err(|_| format!("block {k} of {size} bytes is too large"))?;
                compressed.clear();
                src.take(csize, &mut compressed)?;
                let block =
                    miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(&compressed, size)
                        .map_err(|e| {
                            format!(
                                "block {k} is not zlib data of {size} bytes ({:?})",
                                e.status
                            )
                        })?;
                if block.len() != size {
                    return Err(format!(
                        "block {k} inflates to {} bytes, not the {size} its header gives",
                        block.len()
                    ));
                }
                out.extend_from_slice(&block);
            }
            Ok(out)
        }
    }
}

/// Bytes read in order from raw appended data or base64 text.
enum Source<'a> {
    Raw { data: &'a [u8], pos: usize },
    Base64(Base64<'a>),
}

impl Source<'_> {
    /// Append the next `n` bytes to `out`.
    fn take(&mut self, n: u64, out: &mut Vec<u8>) -> Result<(), String> {
        match self {
            Source::Raw { data, pos } => {
                let end = usize::try_from(n)
                    .ok()
                    .and_then(|n| pos.checked_add(n))
                    .filter(|&e| e <= data.len())
                    .ok_or_else(|| {
                        format!(
                            "{n} bytes at byte {pos} run past the end of the appended data ({} bytes)",
                            data.len()
                        )
                    })?;
                out.extend_from_slice(&data[*pos..end]);
                *pos = end;
                Ok(())
            }
            Source::Base64(b) => {
                for _ in 0..n {
                    out.push(b.next_byte()?);
                }
                Ok(())
            }
        }
    }
}

/// A base64 decoder that skips whitespace and reads on past padding: VTK and meshio may
/// encode an array's header and its data as two streams, each padded, one after the other.
struct Base64<'a> {
    text: &'a [u8],
    pos: usize,
    buf: [u8; 3],
    have: usize,
    used: usize,
}

impl<'a> Base64<'a> {
    fn new(text: &'a [u8], pos: usize) -> Self {
        Base64 {
            text,
            pos,
            buf: [0; 3],
            have: 0,
            used: 0,
        }
    }

    fn next_byte(&mut self) -> Result<u8, String> {
        if self.used == self.have {
            self.group()?;
        }
        self.used += 1;
        Ok(self.buf[self.used - 1])
    }

    /// Decode the next group of four characters.
    fn group(&mut self) -> Result<(), String> {
        let mut sextets = [0u8; 4];
        let mut pads = 0;
        let mut k = 0;
        while k < 4 {
            let Some(&c) = self.text.get(self.pos) else {
                return Err("the base64 data ends early".to_string());
            };
            self.pos += 1;
            if c.is_ascii_whitespace() {
                continue;
            }
            let v = match c {
                b'A'..=b'Z' => c - b'A',
                b'a'..=b'z' => c - b'a' + 26,
                b'0'..=b'9' => c - b'0' + 52,
                b'+' => 62,
                b'/' => 63,
                b'=' if k >= 2 => {
                    pads += 1;
                    0
                }
                _ => {
                    return Err(format!(
                        "the base64 data ends early or is corrupt ('{}' at byte {})",
                        c.escape_ascii(),
                        self.pos - 1
                    ))
                }
            };
            if pads > 0 && c != b'=' {
                return Err("base64 padding '=' in the middle of a group".to_string());
            }
            sextets[k] = v;
            k += 1;
        }
        let [a, b, c, d] = sextets;
        self.buf = [a << 2 | b >> 4, b << 4 | c >> 2, c << 6 | d];
        self.have = 3 - pads;
        self.used = 0;
        Ok(())
    }
}

/// The line of byte `pos` (1-based).
fn line_of(s: &[u8], pos: usize) -> usize {
    1 + s[..pos.min(s.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

/// One piece of the XML before `<AppendedData>`.
enum Item<'a> {
    Text(&'a [u8]),
    Start {
        name: &'a [u8],
        attrs: Vec<(&'a [u8], &'a [u8])>,
        empty: bool,
    },
    End(&'a [u8]),
}

/// A scanner for the little XML a `.vtu` uses: elements, attributes quoted with ' or ",
/// text; comments, processing instructions and declarations are skipped, CDATA is text.
struct Scanner<'a> {
    s: &'a [u8],
    pos: usize,
}

fn find(s: &[u8], from: usize, needle: &[u8]) -> Option<usize> {
    s.get(from..)?
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|p| from + p)
}

impl<'a> Scanner<'a> {
    fn err(&self, pos: usize, m: &str) -> String {
        format!("line {}: malformed XML: {m}", line_of(self.s, pos))
    }

    fn next(&mut self) -> Result<Option<Item<'a>>, String> {
        let s = self.s;
        loop {
            let start = self.pos;
            if start >= s.len() {
                return Ok(None);
            }
            if s[start] != b'<' {
                let end = s[start..]
                    .iter()
                    .position(|&b| b == b'<')
                    .map_or(s.len(), |p| start + p);
                self.pos = end;
                return Ok(Some(Item::Text(&s[start..end])));
            }
            let rest = &s[start..];
            let skip_to = |close: &[u8], what: &str| {
                find(s, start + 2, close)
                    .map(|p| p + close.len())
                    .ok_or_else(|| self.err(start, &format!("{what} never closed")))
            };
            if rest.starts_with(b"<!--") {
                self.pos = skip_to(b"-->", "a comment")?;
            } else if rest.starts_with(b"<![CDATA[") {
                let end = skip_to(b"]]>", "a CDATA section")?;
                self.pos = end;
                return Ok(Some(Item::Text(&s[start + 9..end - 3])));
            } else if rest.starts_with(b"<?") {
                self.pos = skip_to(b"?>", "a processing instruction")?;
            } else if rest.starts_with(b"<!") {
                self.pos = skip_to(b">", "a declaration")?;
            } else if rest.starts_with(b"</") {
                let mut i = start + 2;
                let name_start = i;
                while i < s.len() && !s[i].is_ascii_whitespace() && s[i] != b'>' {
                    i += 1;
                }
                let name = &s[name_start..i];
                while i < s.len() && s[i].is_ascii_whitespace() {
                    i += 1;
                }
                if s.get(i) != Some(&b'>') || name.is_empty() {
                    return Err(self.err(start, "a closing tag is not closed by '>'"));
                }
                self.pos = i + 1;
                return Ok(Some(Item::End(name)));
            } else {
                return self.start_tag(start).map(Some);
            }
        }
    }

    fn start_tag(&mut self, start: usize) -> Result<Item<'a>, String> {
        let s = self.s;
        let name_end = |mut i: usize| {
            while i < s.len()
                && !s[i].is_ascii_whitespace()
                && !matches!(s[i], b'>' | b'/' | b'=' | b'<')
            {
                i += 1;
            }
            i
        };
        let mut i = name_end(start + 1);
        let name = &s[start + 1..i];
        if name.is_empty() {
            return Err(self.err(start, "'<' starts no tag"));
        }
        let mut attrs = Vec::new();
        loop {
            while i < s.len() && s[i].is_ascii_whitespace() {
                i += 1;
            }
            match s.get(i) {
                None => {
                    return Err(self.err(
                        start,
                        &format!("the file ends inside <{}>", String::from_utf8_lossy(name)),
                    ))
                }
                Some(b'>') => {
                    self.pos = i + 1;
                    return Ok(Item::Start {
                        name,
                        attrs,
                        empty: false,
                    });
                }
                Some(b'/') if s.get(i + 1) == Some(&b'>') => {
                    self.pos = i + 2;
                    return Ok(Item::Start {
                        name,
                        attrs,
                        empty: true,
                    });
                }
                _ => {}
            }
            let key_start = i;
            i = name_end(i);
            let key = &s[key_start..i];
            while i < s.len() && s[i].is_ascii_whitespace() {
                i += 1;
            }
            if key.is_empty() || s.get(i) != Some(&b'=') {
                return Err(self.err(i, "expected an attribute name=\"value\""));
            }
            i += 1;
            while i < s.len() && s[i].is_ascii_whitespace() {
                i += 1;
            }
            let quote = match s.get(i) {
                Some(&q @ (b'"' | b'\'')) => q,
                _ => return Err(self.err(i, "an attribute value is not quoted")),
            };
            let value_end = s[i + 1..]
                .iter()
                .position(|&b| b == quote)
                .map(|p| i + 1 + p)
                .ok_or_else(|| self.err(i, "an attribute value is never closed"))?;
            attrs.push((key, &s[i + 1..value_end]));
            i = value_end + 1;
        }
    }
}

fn attr<'a>(attrs: &[(&[u8], &'a [u8])], key: &[u8]) -> Option<&'a [u8]> {
    attrs.iter().find(|(k, _)| *k == key).map(|(_, v)| *v)
}

fn count(attrs: &[(&[u8], &[u8])], key: &str, line: usize) -> Result<Option<u64>, String> {
    attr(attrs, key.as_bytes())
        .map(|v| {
            std::str::from_utf8(v)
                .ok()
                .and_then(|s| s.trim().parse::<u64>().ok())
                .ok_or_else(|| {
                    format!(
                        "line {line}: {key}=\"{}\" is not a count",
                        String::from_utf8_lossy(v)
                    )
                })
        })
        .transpose()
}

/// The file's layout and its pieces, from its XML (up to `<AppendedData>`, whose bytes are
/// not XML).
fn scan(s: &[u8]) -> Result<(Layout<'_>, Vec<Piece>), String> {
    let mut sc = Scanner { s, pos: 0 };
    let mut stack: Vec<&[u8]> = Vec::new();
    let mut layout: Option<Layout> = None;
    let mut pieces: Vec<Piece> = Vec::new();
    let mut current: Option<Array> = None;
    let mut closed = false;
    let mut appended_seen = false;
    while let Some(item) = sc.next()? {
        let tag_at = sc.pos;
        match item {
            Item::Text(t) => {
                if stack.last() == Some(&&b"DataArray"[..]) {
                    if let Some(a) = current.as_mut() {
                        a.text.extend_from_slice(t);
                    }
                } else if stack.is_empty() && !t.iter().all(u8::is_ascii_whitespace) {
                    return Err(format!(
                        "line {}: not a VTK XML file: text outside <VTKFile>",
                        line_of(s, tag_at)
                    ));
                }
            }
            Item::Start { name, attrs, empty } => {
                let line = line_of(s, tag_at);
                let parent = stack.last().copied();
                if stack.is_empty() {
                    if closed || name != b"VTKFile" {
                        return Err(format!(
                            "line {line}: not a VTK XML file: <{}> where <VTKFile> was expected",
                            String::from_utf8_lossy(name)
                        ));
                    }
                    layout = Some(file_layout(&attrs, line)?);
                }
                match name {
                    b"Piece" if parent == Some(&b"UnstructuredGrid"[..]) => {
                        pieces.push(Piece {
                            points: count(&attrs, "NumberOfPoints", line)?.unwrap_or(0),
                            cells: count(&attrs, "NumberOfCells", line)?.unwrap_or(0),
                            arrays: Vec::new(),
                        });
                    }
                    b"DataArray" if current.is_none() && stack.len() >= 2 => {
                        let grand = stack[stack.len() - 2];
                        let role = match (grand, parent, attr(&attrs, b"Name")) {
                            (b"Piece", Some(b"Points"), _) => Some(Role::Points),
                            (b"Piece", Some(b"Cells"), Some(b"connectivity")) => {
                                Some(Role::Connectivity)
                            }
                            (b"Piece", Some(b"Cells"), Some(b"offsets")) => Some(Role::Offsets),
                            (b"Piece", Some(b"Cells"), Some(b"types")) => Some(Role::Types),
                            (b"Piece", Some(b"CellData"), Some(b"subdomain")) => {
                                Some(Role::Subdomain)
                            }
                            _ => None,
                        };
                        if let Some(role) = role {
                            let a = array(role, &attrs, line)?;
                            if empty {
                                add_array(&mut pieces, a)?;
                            } else {
                                current = Some(a);
                            }
                        }
                    }
                    b"AppendedData" if parent == Some(&b"VTKFile"[..]) && !empty => {
                        let encoding = attr(&attrs, b"encoding").unwrap_or(b"raw");
                        let base64 = match encoding {
                            b"raw" => false,
                            b"base64" => true,
                            e => {
                                return Err(format!(
                                    "line {line}: AppendedData encoding \"{}\" is neither raw nor base64",
                                    String::from_utf8_lossy(e)
                                ))
                            }
                        };
                        let underscore =
                            s[tag_at..].iter().position(|&b| b == b'_').ok_or_else(|| {
                                format!("line {line}: no '_' starts the appended data")
                            })?;
                        if let Some(l) = layout.as_mut() {
                            l.appended = Some((&s[tag_at + underscore + 1..], base64));
                        }
                        appended_seen = true;
                        break;
                    }
                    _ => {}
                }
                if !empty {
                    stack.push(name);
                }
            }
            Item::End(name) => {
                let Some(open) = stack.pop() else {
                    return Err(format!(
                        "line {}: malformed XML: </{}> closes nothing",
                        line_of(s, tag_at),
                        String::from_utf8_lossy(name)
                    ));
                };
                if open != name {
                    return Err(format!(
                        "line {}: malformed XML: </{}> closes <{}>",
                        line_of(s, tag_at),
                        String::from_utf8_lossy(name),
                        String::from_utf8_lossy(open)
                    ));
                }
                if name == b"DataArray" {
                    if let Some(a) = current.take() {
                        add_array(&mut pieces, a)?;
                    }
                }
                if stack.is_empty() {
                    closed = true;
                }
            }
        }
    }
    let layout = layout.ok_or("not a VTK XML file: no <VTKFile> element")?;
    if !closed && !appended_seen {
        return Err("the file ends before </VTKFile> (truncated?)".to_string());
    }
    Ok((layout, pieces))
}

/// Add a DataArray to the last piece, which must not have one of its role yet.
fn add_array(pieces: &mut [Piece], a: Array) -> Result<(), String> {
    let Some(piece) = pieces.last_mut() else {
        return Err(format!("line {}: a DataArray outside <Piece>", a.line));
    };
    if piece.array(a.role).is_some() {
        return Err(format!(
            "line {}: a second '{}' DataArray in one piece",
            a.line,
            a.role.name()
        ));
    }
    piece.arrays.push(a);
    Ok(())
}

/// A DataArray's description from its attributes.
fn array(role: Role, attrs: &[(&[u8], &[u8])], line: usize) -> Result<Array, String> {
    let ty = attr(attrs, b"type").unwrap_or(b"");
    let scalar = Scalar::from_name(ty).ok_or_else(|| {
        format!(
            "line {line}: {}: DataArray type \"{}\" is not a number type",
            role.name(),
            String::from_utf8_lossy(ty)
        )
    })?;
    let format = match attr(attrs, b"format").unwrap_or(b"ascii") {
        b"ascii" => Format::Ascii,
        b"binary" => Format::Binary,
        b"appended" => Format::Appended(count(attrs, "offset", line)?.ok_or_else(|| {
            format!(
                "line {line}: {}: an appended DataArray has no offset",
                role.name()
            )
        })?),
        f => {
            return Err(format!(
                "line {line}: {}: DataArray format \"{}\" is not ascii, binary or appended",
                role.name(),
                String::from_utf8_lossy(f)
            ))
        }
    };
    Ok(Array {
        role,
        scalar,
        components: count(attrs, "NumberOfComponents", line)?.unwrap_or(1),
        format,
        text: Vec::new(),
        line,
    })
}

/// The binary layout `<VTKFile>` declares.
fn file_layout<'a>(attrs: &[(&[u8], &[u8])], line: usize) -> Result<Layout<'a>, String> {
    let lossy = |v: &[u8]| String::from_utf8_lossy(v).into_owned();
    match attr(attrs, b"type") {
        Some(b"UnstructuredGrid") => {}
        Some(t) => {
            return Err(format!(
                "line {line}: a VTK {} file: only an UnstructuredGrid (.vtu) is read",
                lossy(t)
            ))
        }
        None => return Err(format!("line {line}: <VTKFile> has no type")),
    }
    // An attribute of two values, the first the default: whether it has the second.
    let second = |key: &str, [first, other]: [&str; 2]| {
        let v = attr(attrs, key.as_bytes()).unwrap_or(first.as_bytes());
        match v {
            _ if v == first.as_bytes() => Ok(false),
            _ if v == other.as_bytes() => Ok(true),
            _ => Err(format!(
                "line {line}: {key} \"{}\" is neither {first} nor {other}",
                lossy(v)
            )),
        }
    };
    let big = second("byte_order", ["LittleEndian", "BigEndian"])?;
    let header64 = second("header_type", ["UInt32", "UInt64"])?;
    let compressor = match attr(attrs, b"compressor").unwrap_or(b"") {
        b"" => Compressor::None,
        b"vtkZLibDataCompressor" => Compressor::Zlib,
        c => Compressor::Other(lossy(c)),
    };
    Ok(Layout {
        big,
        header64,
        compressor,
        appended: None,
    })
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;
    use std::fs;

    #[test]
    fn quality_of_known_triangles() {
        let eq = [DVec2::ZERO, DVec2::X, DVec2::new(0.5, 3f64.sqrt() / 2.0)];
        let (ang, area, q) = triangle_quality(eq);
        assert!((ang - 60.0).abs() < 1e-12 && (area - 3f64.sqrt() / 4.0).abs() < 1e-15);
        assert!((q - 1.0).abs() < 1e-12, "{q}");
        // Right isosceles: sides 1, 1, √2 → q = √2 / ((2−√2)·√2·√2) = 1/(2−√2)/√2.
        let (ang, area, q) = triangle_quality([DVec2::ZERO, DVec2::X, DVec2::Y]);
        let s = 2f64.sqrt();
        assert!((ang - 45.0).abs() < 1e-12 && (area - 0.5).abs() < 1e-15);
        assert!((q - s / ((2.0 - s) * 2.0)).abs() < 1e-12, "{q}");
        let (_, area, q) = triangle_quality([DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)]);
        assert_eq!((area, q), (0.0, f64::MAX));
    }

    /// The values of one named DataArray.
    fn array(text: &str, name: &str) -> Vec<f64> {
        let start = text.find(&format!("Name=\"{name}\"")).unwrap();
        let body = &text[start..];
        let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
        body.split_whitespace()
            .map(|s| s.parse().unwrap())
            .collect()
    }

    #[test]
    fn file_holds_points_cells_and_fields() {
        let dir = TempDir::new("vtu");
        let m = square_with_hole();
        let p = dir.path("sq.vtu");
        write_vtu(&m, &p).unwrap();
        let text = fs::read_to_string(&p).unwrap();
        assert!(text.contains("NumberOfPoints=\"48\" NumberOfCells=\"64\""));
        let pts = array(&text, "Points");
        assert_eq!(pts.len(), 3 * 48);
        for (i, q) in m.points.iter().enumerate() {
            assert_eq!(
                (pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]),
                (q.x, q.y, 0.0)
            );
        }
        let conn = array(&text, "connectivity");
        let tris: Vec<[u32; 3]> = conn
            .chunks(3)
            .map(|c| [c[0] as u32, c[1] as u32, c[2] as u32])
            .collect();
        assert_eq!(tris, m.triangles);
        assert_eq!(array(&text, "offsets").last(), Some(&192.0));
        assert!(array(&text, "types").iter().all(|&t| t == 5.0));
        let area: f64 = array(&text, "area").iter().sum();
        assert!((area - m.area()).abs() < 1e-12);
        assert!(array(&text, "q").iter().all(|&q| q >= 1.0 - 1e-12));
        let min_angle = array(&text, "min_angle_deg")
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        assert!((min_angle - m.min_angle_deg()).abs() < 1e-9);
        let marks = array(&text, "boundary_marker");
        assert_eq!(marks.iter().filter(|&&v| v == 1.0).count(), 24);
        assert_eq!(marks.iter().filter(|&&v| v == 2.0).count(), 8);
    }

    // --- Reading ---

    use crate::{Quadratic, VertexMarker};

    /// Base64 with padding, as VTK and meshio write it.
    fn b64(bytes: &[u8]) -> String {
        const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut s = String::new();
        for c in bytes.chunks(3) {
            let n = c.len();
            let v = (u32::from(c[0]) << 16)
                | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
                | u32::from(*c.get(2).unwrap_or(&0));
            for k in 0..4 {
                s.push(if k <= n {
                    A[(v >> (18 - 6 * k) & 63) as usize] as char
                } else {
                    '='
                });
            }
        }
        s
    }

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Enc {
        Ascii,
        Binary,
        AppendedRaw,
        AppendedBase64,
    }

    /// How [`build`] writes a file.
    #[derive(Clone, Copy, Debug)]
    struct Opts {
        enc: Enc,
        header64: bool,
        big: bool,
        zlib: bool,
        /// Base64 of an uncompressed array's header and data as two padded streams.
        split: bool,
        /// Points as Float32.
        f32: bool,
    }

    const PLAIN: Opts = Opts {
        enc: Enc::Ascii,
        header64: false,
        big: false,
        zlib: false,
        split: false,
        f32: false,
    };

    /// One piece: points, connectivity, offsets, types.
    type RawPiece = (Vec<[f64; 3]>, Vec<i64>, Vec<i64>, Vec<u8>);

    /// A `.vtu` of `pieces` written as `o` says, in the ways VTK and meshio write them: the
    /// points in Float64 (or Float32), connectivity Int32, offsets UInt64, types UInt8; zlib
    /// data in blocks of 16 bytes, so that arrays take several.
    fn build(pieces: &[RawPiece], o: Opts) -> Vec<u8> {
        let int = |v: u64, size: usize| -> Vec<u8> {
            let b = v.to_le_bytes()[..size].to_vec();
            if o.big {
                b.into_iter().rev().collect()
            } else {
                b
            }
        };
        let hs = if o.header64 { 8 } else { 4 };
        // Header and data bytes of one array.
        let payload = |data: &[u8]| -> (Vec<u8>, Vec<u8>) {
            if !o.zlib {
                return (int(data.len() as u64, hs), data.to_vec());
            }
            let blocks: Vec<Vec<u8>> = data
                .chunks(16)
                .map(|b| miniz_oxide::deflate::compress_to_vec_zlib(b, 6))
                .collect();
            let mut header = int(blocks.len() as u64, hs);
            header.extend(int(16, hs));
            header.extend(int((data.len() % 16) as u64, hs));
            for b in &blocks {
                header.extend(int(b.len() as u64, hs));
            }
            (header, blocks.concat())
        };
        let mut appended_raw: Vec<u8> = Vec::new();
        let mut appended_b64 = String::new();
        let mut xml = String::new();
        let mut array = |xml: &mut String, attrs: &str, values: Vec<String>, data: Vec<u8>| {
            let format = match o.enc {
                Enc::Ascii => "ascii",
                Enc::Binary => "binary",
                _ => "appended",
            };
            let (header, data) = payload(&data);
            match o.enc {
                Enc::Ascii => {
                    xml.push_str(&format!(
                        "<DataArray {attrs} format=\"{format}\">\n{}\n</DataArray>\n",
                        values.join(" ")
                    ));
                }
                Enc::Binary => {
                    let text = if o.split || o.zlib {
                        b64(&header) + &b64(&data)
                    } else {
                        b64(&[header, data].concat())
                    };
                    xml.push_str(&format!(
                        "<DataArray {attrs} format=\"{format}\">\n  {text}\n</DataArray>\n"
                    ));
                }
                Enc::AppendedRaw => {
                    xml.push_str(&format!(
                        "<DataArray {attrs} format=\"{format}\" offset=\"{}\"/>\n",
                        appended_raw.len()
                    ));
                    appended_raw.extend(header);
                    appended_raw.extend(data);
                }
                Enc::AppendedBase64 => {
                    xml.push_str(&format!(
                        "<DataArray {attrs} format=\"{format}\" offset=\"{}\"/>\n",
                        appended_b64.len()
                    ));
                    appended_b64 += &(b64(&header) + &b64(&data));
                }
            }
        };
        let order = if o.big { "BigEndian" } else { "LittleEndian" };
        let header = if o.header64 { "UInt64" } else { "UInt32" };
        let comp = if o.zlib {
            " compressor=\"vtkZLibDataCompressor\""
        } else {
            ""
        };
        xml.push_str(&format!("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"{order}\" header_type=\"{header}\"{comp}>\n<UnstructuredGrid>\n"));
        for (points, conn, offsets, types) in pieces {
            xml.push_str(&format!(
                "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<PointData>\n",
                points.len(),
                types.len()
            ));
            // Point data the reader skips.
            array(
                &mut xml,
                "type=\"Int32\" Name=\"boundary_marker\"",
                points.iter().map(|_| "1".to_string()).collect(),
                points.iter().flat_map(|_| int(1, 4)).collect(),
            );
            xml.push_str("</PointData>\n<Points>\n");
            let flat: Vec<f64> = points.iter().flatten().copied().collect();
            let (ty, data): (&str, Vec<u8>) = if o.f32 {
                let d = flat
                    .iter()
                    .flat_map(|&v| int(u64::from((v as f32).to_bits()), 4))
                    .collect();
                ("Float32", d)
            } else {
                (
                    "Float64",
                    flat.iter().flat_map(|&v| int(v.to_bits(), 8)).collect(),
                )
            };
            array(
                &mut xml,
                &format!("type=\"{ty}\" Name=\"Points\" NumberOfComponents=\"3\""),
                flat.iter().map(|v| format!("{v:?}")).collect(),
                data,
            );
            xml.push_str("</Points>\n<Cells>\n");
            array(
                &mut xml,
                "type=\"Int32\" Name=\"connectivity\"",
                conn.iter().map(i64::to_string).collect(),
                conn.iter().flat_map(|&v| int(v as u64, 4)).collect(),
            );
            array(
                &mut xml,
                "type=\"UInt64\" Name=\"offsets\"",
                offsets.iter().map(i64::to_string).collect(),
                offsets.iter().flat_map(|&v| int(v as u64, 8)).collect(),
            );
            array(
                &mut xml,
                "type=\"UInt8\" Name=\"types\"",
                types.iter().map(u8::to_string).collect(),
                types.to_vec(),
            );
            xml.push_str("</Cells>\n</Piece>\n");
        }
        xml.push_str("</UnstructuredGrid>\n");
        let mut out = xml.into_bytes();
        match o.enc {
            Enc::AppendedRaw => {
                out.extend(b"<AppendedData encoding=\"raw\">\n   _");
                out.extend(&appended_raw);
                out.extend(b"\n</AppendedData>\n");
            }
            Enc::AppendedBase64 => {
                out.extend(b"<AppendedData encoding=\"base64\">\n   _");
                out.extend(appended_b64.as_bytes());
                out.extend(b"\n</AppendedData>\n");
            }
            _ => {}
        }
        out.extend(b"</VTKFile>\n");
        out
    }

    /// The unit square of four triangles around (0.1, 0.7), and, as a second piece, the
    /// square beside it of two triangles (one clockwise), with a vertex and a line cell.
    fn two_pieces() -> Vec<RawPiece> {
        let p = |x: f64, y: f64| [x, y, 0.0];
        vec![
            (
                vec![
                    p(0.0, 0.0),
                    p(1.0, 0.0),
                    p(1.0, 1.0),
                    p(0.0, 1.0),
                    p(0.1, 0.7),
                ],
                vec![0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4],
                vec![3, 6, 9, 12],
                vec![5; 4],
            ),
            (
                vec![p(1.0, 0.0), p(2.0, 0.0), p(2.0, 1.0), p(1.0, 1.0)],
                vec![0, 1, 2, 2, 0, 3, 1, 0, 1],
                vec![3, 6, 7, 9],
                vec![5, 5, 1, 3],
            ),
        ]
    }

    /// The mesh [`two_pieces`] reads to: the second piece's points after the first's.
    fn check_two_pieces(m: &Mesh, f32: bool) {
        let want = [
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (0.1, 0.7),
            (1.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
        ];
        let got: Vec<(f64, f64)> = m.points.iter().map(|p| (p.x, p.y)).collect();
        let want: Vec<(f64, f64)> = want
            .iter()
            .map(|&(x, y)| {
                if f32 {
                    (x as f32 as f64, y as f32 as f64)
                } else {
                    (x, y)
                }
            })
            .collect();
        assert_eq!(got, want);
        assert_eq!(
            m.triangles,
            [
                [0, 1, 4],
                [1, 2, 4],
                [2, 3, 4],
                [3, 0, 4],
                [5, 6, 7],
                [7, 8, 5]
            ]
        );
        assert_eq!(m.markers.len(), 9);
        assert_eq!(m.markers[4], VertexMarker::Interior);
    }

    #[test]
    fn own_files_read_back_bit_for_bit() {
        let r = assert_round_trip_keeps_loops("m.vtu", write_vtu, read_vtu);
        assert_eq!(r.num_triangles(), 64);
        // With a wall_marker array too (written for a region that numbers its walls).
        let dir = TempDir::new("vtu-read");
        let m = square_with_hole();
        let p = dir.path("m.vtu");
        write_vtu(&m, &p).unwrap();
        let file = super::super::read_mesh_file(&p).unwrap();
        assert_eq!((file.triangle_nodes, file.edge_nodes.len()), (3, 0));
        assert_eq!(file.walls, Walls::default());
        let bits = |m: &Mesh| -> Vec<[u64; 2]> {
            m.points
                .iter()
                .map(|p| [p.x.to_bits(), p.y.to_bits()])
                .collect()
        };
        assert_eq!(bits(&file.mesh), bits(&m));
    }

    #[test]
    fn own_quadratic_files_read_back_as_their_corners_with_their_edge_nodes() {
        let dir = TempDir::new("vtu-p2");
        let m = square_with_hole();
        let mut q = Quadratic::new(&m, None);
        // A node off its edge's middle, as on a curved boundary.
        let moved = q.edge_node(0, 1).unwrap() as usize;
        q.points[moved].y -= 0.01;
        let p = dir.path("q.vtu");
        super::super::write_quadratic(&q, &p).unwrap();
        let file = super::super::read_mesh_file(&p).unwrap();
        assert_eq!(file.mesh.points, m.points);
        assert_eq!(file.mesh.triangles, m.triangles);
        assert_eq!(file.triangle_nodes, 6);
        let edges = q.points.len() - m.points.len();
        assert_eq!(file.edge_nodes.len(), edges);
        for &([a, b], at) in &file.edge_nodes {
            let node = q.edge_node(a, b).unwrap() as usize;
            assert_eq!(q.points[node], at, "edge {a}-{b}");
        }
        let again = Quadratic::new(&file.mesh, None).keeping(&file.edge_nodes);
        assert_eq!(again.points, q.points);
    }

    #[test]
    fn meshio_files_read_in_every_encoding() {
        let square = |m: &Mesh| {
            let pts: Vec<(f64, f64)> = m.points.iter().map(|p| (p.x, p.y)).collect();
            assert_eq!(
                pts,
                [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.1, 0.7)]
            );
            assert_eq!(m.triangles, [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]);
        };
        square(&vtu_from_bytes(include_bytes!("../../tests/data/vtu/meshio_ascii.vtu")).unwrap());
        // One base64 stream of a UInt32 or UInt64 header and the data.
        square(
            &vtu_from_bytes(include_bytes!("../../tests/data/vtu/meshio_binary32.vtu")).unwrap(),
        );
        square(
            &vtu_from_bytes(include_bytes!("../../tests/data/vtu/meshio_binary64.vtu")).unwrap(),
        );
        // zlib, the header and the blocks as two streams; a vertex and two lines skipped.
        square(
            &vtu_from_bytes(include_bytes!("../../tests/data/vtu/meshio_zlib_mixed.vtu")).unwrap(),
        );
        let e = vtu_from_bytes(include_bytes!("../../tests/data/vtu/meshio_quad.vtu"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("mesh.vtu: ") && e.contains("cell 2 is a quad (VTK cell type 9)"),
            "{e}"
        );
    }

    #[test]
    fn meshio_six_node_triangles_read_as_their_corners() {
        let dir = TempDir::new("vtu-meshio6");
        let p = dir.path("t6.vtu");
        fs::write(
            &p,
            include_bytes!("../../tests/data/vtu/meshio_triangle6_zlib.vtu"),
        )
        .unwrap();
        let file = super::super::read_mesh_file(&p).unwrap();
        assert_eq!(file.triangle_nodes, 6);
        assert_eq!(
            file.mesh.points,
            [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y]
        );
        assert_eq!(file.mesh.triangles, [[0, 1, 2], [0, 2, 3]]);
        let h = |x, y| DVec2::new(x, y);
        assert_eq!(
            file.edge_nodes,
            [
                ([0, 1], h(0.5, 0.0)),
                ([0, 2], h(0.5, 0.5)),
                ([0, 3], h(0.0, 0.5)),
                ([1, 2], h(1.0, 0.5)),
                ([2, 3], h(0.5, 1.0)),
            ]
        );
    }

    /// Every encoding, header, byte order and compression [`build`] writes.
    fn every_layout() -> Vec<Opts> {
        let mut all = Vec::new();
        for enc in [
            Enc::Ascii,
            Enc::Binary,
            Enc::AppendedRaw,
            Enc::AppendedBase64,
        ] {
            for bits in 0..16u32 {
                let o = Opts {
                    enc,
                    header64: bits & 1 != 0,
                    big: bits & 2 != 0,
                    zlib: bits & 4 != 0,
                    split: bits & 8 != 0,
                    f32: false,
                };
                if enc != Enc::Ascii || bits == 0 {
                    all.push(o);
                }
            }
        }
        all
    }

    #[test]
    fn hand_made_files_read_in_every_layout() {
        for o in every_layout() {
            let bytes = build(&two_pieces(), o);
            let m = vtu_from_bytes(&bytes)
                .unwrap_or_else(|e| panic!("{o:?}: {e}\n{}", String::from_utf8_lossy(&bytes)));
            check_two_pieces(&m, false);
            let m = vtu_from_bytes(&build(&two_pieces(), Opts { f32: true, ..o })).unwrap();
            check_two_pieces(&m, true);
        }
    }

    #[test]
    fn xml_comments_quotes_and_attribute_order_do_not_matter() {
        let text = "\u{feff}<?xml version='1.0' encoding='UTF-8'?>\n<!-- <VTKFile type=\"PolyData\"> -->\n\
            <!DOCTYPE vtu>\n<VTKFile header_type = 'UInt64' type='UnstructuredGrid'>\n\
            <UnstructuredGrid><!-- a comment --><FieldData><DataArray type='Float64' Name='TIME' NumberOfTuples='1' format='ascii'>0</DataArray></FieldData>\n\
            <Piece NumberOfCells='1' NumberOfPoints='3'>\n<Points>\n\
            <DataArray format='ascii' NumberOfComponents='3' type='Float32'>0 0 0<!-- 9 9 9 --> 1 0 0\n<![CDATA[0 1 0]]></DataArray>\n\
            </Points>\n<Cells>\n<DataArray Name=\"types\" type=\"Int64\">5</DataArray>\n\
            <DataArray format=\"ascii\" Name=\"offsets\" type=\"Int16\">\n0 3\n</DataArray>\n\
            <DataArray Name='connectivity' type='UInt16' format='ascii'><InformationKey name='x' location='y'>7</InformationKey>0 2 1</DataArray>\n\
            </Cells></Piece></UnstructuredGrid></VTKFile>\n";
        let m = vtu_from_bytes(text.as_bytes()).unwrap();
        assert_eq!(m.points, [DVec2::ZERO, DVec2::X, DVec2::Y]);
        // Made counter-clockwise.
        assert_eq!(m.triangles, [[0, 1, 2]]);
    }

    #[test]
    fn other_compressors_and_cells_are_refused_by_name() {
        let o = Opts {
            enc: Enc::Binary,
            zlib: true,
            ..PLAIN
        };
        for c in ["vtkLZ4DataCompressor", "vtkLZMADataCompressor"] {
            let text = String::from_utf8(build(&two_pieces(), o))
                .unwrap()
                .replace("vtkZLibDataCompressor", c);
            let e = vtu_from_bytes(text.as_bytes()).unwrap_err().to_string();
            assert!(
                e.contains(c) && e.contains("uncompressed or with zlib"),
                "{e}"
            );
        }
        let mut pieces = two_pieces();
        pieces[1].3[3] = 10;
        let e = vtu_from_bytes(&build(&pieces, PLAIN))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("piece 2: cell 3 is a tetra (VTK cell type 10)")
                && e.contains("Triangulate"),
            "{e}"
        );
        pieces[1].3[3] = 99;
        let e = vtu_from_bytes(&build(&pieces, PLAIN))
            .unwrap_err()
            .to_string();
        assert!(e.contains("cell 3 is a cell (VTK cell type 99)"), "{e}");
        let e = vtu_from_bytes(b"<VTKFile type='PolyData'></VTKFile>")
            .unwrap_err()
            .to_string();
        assert!(e.contains("a VTK PolyData file"), "{e}");
        let only_lines: Vec<RawPiece> = vec![(
            vec![[0.0; 3], [1.0, 0.0, 0.0]],
            vec![0, 1],
            vec![2],
            vec![3],
        )];
        let e = vtu_from_bytes(&build(&only_lines, PLAIN))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no triangles"), "{e}");
    }

    #[test]
    fn inconsistent_files_are_errors_that_say_what_is_wrong() {
        type Edit = fn(&mut RawPiece);
        let cases: Vec<(Edit, &str)> = vec![
            (
                |p| p.1[4] = 5,
                "cell 1 refers to point 5, but the piece has 5 points",
            ),
            (|p| p.1[4] = -1, "-1 is not an index or count"),
            (
                |p| p.2[1] = 2,
                "cell 1: offset 2 is below the previous one, 3",
            ),
            (|p| p.2[3] = 13, "offset 13 is past the connectivity's end"),
            (
                |p| {
                    p.2[3] = 11;
                    p.3[3] = 3;
                },
                "the last offset is 11, but connectivity has 12 entries",
            ),
            (|p| p.2[2] = 8, "cell 2: a triangle with 2 nodes, not 3"),
            (|p| p.3.push(5), "4 offsets for NumberOfCells=\"5\""),
            (|p| p.0[2][2] = 0.5, "point 2: z = 0.5: only planar meshes"),
            (|p| p.0[3][0] = f64::NAN, "point 3 (NaN 1 0) is not finite"),
            (|p| p.3[0] = 22, "a quadratic triangle with 3 nodes, not 6"),
        ];
        for (edit, want) in cases {
            let mut pieces = two_pieces();
            pieces.truncate(1);
            edit(&mut pieces[0]);
            for o in [
                PLAIN,
                Opts {
                    enc: Enc::AppendedRaw,
                    ..PLAIN
                },
            ] {
                let e = vtu_from_bytes(&build(&pieces, o))
                    .map(|_| ())
                    .unwrap_err()
                    .to_string();
                assert!(e.contains(want), "{o:?}: {e}");
            }
        }
        // The count the Piece gives is not trusted for an allocation.
        let text = String::from_utf8(build(&two_pieces()[..1], PLAIN))
            .unwrap()
            .replace("NumberOfPoints=\"5\"", "NumberOfPoints=\"4000000000\"");
        let e = vtu_from_bytes(text.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("Points hold 15 numbers"), "{e}");
        let fewer = text
            .replace("4000000000", "5")
            .replace("NumberOfCells=\"4\"", "NumberOfCells=\"3\"");
        let e = vtu_from_bytes(fewer.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("4 cell types for NumberOfCells=\"3\""), "{e}");
        let text = text.replace("4000000000", "99999999999999999999");
        let e = vtu_from_bytes(text.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("is not a count"), "{e}");
    }

    #[test]
    fn truncated_and_corrupt_files_are_errors_not_panics() {
        let pieces = two_pieces();
        for o in every_layout() {
            let bytes = build(&pieces, o);
            // Where the data ends: every shorter prefix lacks some of it.
            let needed = match o.enc {
                Enc::AppendedRaw | Enc::AppendedBase64 => {
                    bytes.len() - "\n</AppendedData>\n</VTKFile>\n".len()
                }
                _ => bytes.len() - 2,
            };
            for n in 0..bytes.len() {
                let r = vtu_from_bytes(&bytes[..n]);
                assert!(n >= needed || r.is_err(), "{o:?}: prefix of {n} bytes read");
            }
            // Every byte changed, each way that matters to a parser (in fewer layouts: the
            // byte order and header width change only the numbers read).
            if o.split || o.header64 != o.big {
                continue;
            }
            let mut copy = bytes.clone();
            for i in 0..bytes.len() {
                for b in [b'<', b'"', 0xff, bytes[i] ^ 0x01] {
                    copy[i] = b;
                    let _ = vtu_from_bytes(&copy);
                }
                copy[i] = bytes[i];
            }
        }
    }

    #[test]
    fn corrupt_binary_data_names_the_array() {
        let o = Opts {
            enc: Enc::Binary,
            zlib: true,
            ..PLAIN
        };
        let text = String::from_utf8(build(&two_pieces(), o)).unwrap();
        // The first block of the first piece's connectivity, made not zlib.
        let at = text.find("Name=\"connectivity\"").unwrap();
        let start = at + text[at..].find(">\n  ").unwrap() + 4;
        // Past the header (three items and four sizes of 4 bytes: 28 bytes, 40 characters).
        let mut bad = text.clone().into_bytes();
        bad[start + 44] = if bad[start + 44] == b'A' { b'B' } else { b'A' };
        let e = vtu_from_bytes(&bad).unwrap_err().to_string();
        assert!(e.contains("connectivity") && e.contains("block 0"), "{e}");
        let mut bad = text.into_bytes();
        bad[start + 3] = b'*';
        let e = vtu_from_bytes(&bad).unwrap_err().to_string();
        assert!(e.contains("connectivity") && e.contains("base64"), "{e}");
        // Appended data missing.
        let bytes = build(
            &two_pieces(),
            Opts {
                enc: Enc::AppendedRaw,
                ..PLAIN
            },
        );
        let cut = find(&bytes, 0, b"<AppendedData").unwrap();
        let e = vtu_from_bytes(&bytes[..cut]).unwrap_err().to_string();
        assert!(e.contains("ends before </VTKFile>"), "{e}");
        let e = vtu_from_bytes(&[&bytes[..cut], b"</VTKFile>"].concat())
            .unwrap_err()
            .to_string();
        assert!(e.contains("no <AppendedData>"), "{e}");
    }

    #[test]
    fn read_mesh_reads_vtu_files_and_names_them_in_errors() {
        let dir = TempDir::new("vtu-dispatch");
        let p = dir.path("bad.vtu");
        fs::write(&p, "<VTKFile type='UnstructuredGrid'><UnstructuredGrid>").unwrap();
        let e = super::super::read_mesh(&p).unwrap_err();
        assert!(
            matches!(&e, MeshError::File { path, .. } if path == &p),
            "{e}"
        );
        assert!(e.to_string().contains("truncated"), "{e}");
        fs::write(&p, build(&two_pieces(), PLAIN)).unwrap();
        check_two_pieces(&super::super::read_mesh(&p).unwrap(), false);
    }
}
