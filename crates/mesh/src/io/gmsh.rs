//! Gmsh `.msh`: writes 4.1 ASCII; reads 4.1 and 2.2, ASCII and binary (binary files as the
//! ASCII text of the same file, [`super::gmsh_binary`]).
use super::{
    file_err, gmsh_binary, io_err, planar_z, read_mesh_parts, validate_for_writing, write_files,
    write_lines, MeshFile, Nodes, Producer, SizesFile, Tokens, Walls, F,
};
use crate::{Mesh, MeshError, VertexMarker};
use geometry::DVec2;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

/// Write `mesh` as Gmsh 4.1 ASCII.
///
/// Layout: one curve entity per boundary loop (tag = loop index + 1, physical curve of the same
/// tag named `"loop<i>"`) holding that loop's vertices and its boundary edges as 2-node line
/// elements in boundary order; one surface entity (tag 1, physical surface `"domain"`, tag 100)
/// holding the interior vertices and all triangles (type 2, counter-clockwise). Node tags are
/// vertex index + 1, so reading the file back gives the same vertex order.
/// [`write_gmsh_on`] adds a physical curve per boundary piece.
pub fn write_gmsh(mesh: &Mesh, path: &Path) -> Result<(), MeshError> {
    validate_for_writing(mesh, path)?;
    write_nodes(&Nodes::linear(mesh, None), path)
}

/// Write `mesh`, a mesh of `region`, as [`write_gmsh`] does, but with one curve entity per
/// boundary piece (a wall: pieces run from corner to corner, numbered as `cvtmesh regions`
/// lists them), each in two physical curves: its loop's `"loop<i>"` (tag i + 1, as before) and
/// its own `"piece<j>"` (tag j + 1 past the surface's), so a solver reading the file can set a
/// boundary condition per wall. Where the region numbers its walls
/// ([`geometry::Region::piece_markers`], a `.poly`'s segment markers), each piece's curve is
/// also in a third physical curve `"marker<m>"` (tags past the pieces'), one per number.
/// Readers that take an entity's first physical curve, as [`read_gmsh`] does, see the loops.
///
/// ```
/// use cvtmesh::io;
/// use cvtmesh::geometry::{DVec2, LoopRole, Region};
/// let corners = vec![DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(2.0, 1.0), DVec2::Y];
/// let channel = Region::from_loops("channel", vec![(LoopRole::Outer, corners.clone())])?;
/// let triangles = vec![[0, 1, 2], [0, 2, 3]];
/// let mesh = cvtmesh::Mesh { markers: io::markers_from_topology(&corners, &triangles), points: corners, triangles };
/// let path = std::env::temp_dir().join(format!("cvtmesh-doc-pieces-{}.msh", std::process::id()));
/// io::write_gmsh_on(&mesh, &channel, &path)?;
/// let text = std::fs::read_to_string(&path)?;
/// assert!(text.contains("1 1 \"loop0\"") && text.contains("1 104 \"piece3\""));
/// // Read back as any .msh is: the same mesh, every vertex on loop 0.
/// let back = io::read_mesh(&path)?;
/// assert_eq!((&back.points, &back.triangles), (&mesh.points, &mesh.triangles));
/// assert!(back.markers.iter().all(|m| m.loop_index() == Some(0)));
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_gmsh_on(mesh: &Mesh, region: &geometry::Region, path: &Path) -> Result<(), MeshError> {
    validate_for_writing(mesh, path)?;
    write_nodes(&Nodes::linear(mesh, Some(region)), path)
}

/// The physical tag of each of `markers` (sorted, distinct): a positive marker is its own tag
/// (a solver's boundary-condition number), one of 0 or below the `k`-th tag from `first_free`
/// (`k` its rank among `markers`).
fn physical_tags(markers: &[i64], first_free: usize) -> HashMap<i64, usize> {
    markers
        .iter()
        .enumerate()
        .map(|(k, &m)| (m, if m > 0 { m as usize } else { first_free + k }))
        .collect()
}

/// A curve entity of the file: its loop, its piece (when the file has a curve per piece), and
/// its lines (indices into the loop's lines).
struct Curve {
    loop_index: usize,
    piece: Option<usize>,
    lines: Vec<usize>,
}

/// Write `nodes` as Gmsh 4.1 ASCII, laid out as [`write_gmsh`] says (with a curve per piece
/// where `nodes` knows the pieces); six-node triangles are element type 9 and their boundary
/// lines three-node lines (type 8).
pub(crate) fn write_nodes(nodes: &Nodes, path: &Path) -> Result<(), MeshError> {
    let nloops = nodes.lines.len();
    let (line_type, triangle_type) = if nodes.per_triangle() == 6 {
        (8, 9)
    } else {
        (1, 2)
    };
    // Where the region numbers its walls, those numbers are the physical tags of its walls
    // (a solver's boundary conditions name them), and everything else is numbered past them:
    // loops from shift + 1, the surface from shift + 100, the pieces past the surface.
    let shift = nodes
        .piece_markers
        .iter()
        .flatten()
        .chain(nodes.inner.iter().map(|(_, m)| m))
        .fold(0, |top, &m| top.max(m))
        .max(0) as usize;
    // Physical tags 1..=nloops are the loops; keep the surface tag clear of them, and the
    // pieces' tags past it.
    let surface_phys = shift + 100.max(nloops + 1);
    let n = nodes.points.len();
    let by_piece = nodes
        .pieces
        .iter()
        .zip(&nodes.lines)
        .all(|(p, l)| p.len() == l.len())
        && nodes.pieces.iter().any(|p| !p.is_empty());
    let mut curves: Vec<Curve> = Vec::new();
    for (l, lines) in nodes.lines.iter().enumerate() {
        if !by_piece {
            curves.push(Curve {
                loop_index: l,
                piece: None,
                lines: (0..lines.len()).collect(),
            });
            continue;
        }
        // A loop's pieces get curves in the order the loop meets them.
        let mut curve_of: HashMap<usize, usize> = HashMap::new();
        for (k, &j) in nodes.pieces[l].iter().enumerate() {
            let c = *curve_of.entry(j).or_insert_with(|| {
                curves.push(Curve {
                    loop_index: l,
                    piece: Some(j),
                    lines: Vec::new(),
                });
                curves.len() - 1
            });
            curves[c].lines.push(k);
        }
    }
    // Nodes per entity: the curves', then the surface block (index curves.len()).
    let surface = curves.len();
    let mut block_of = vec![surface; n];
    if by_piece {
        // A boundary node goes with the curve of a line it starts (or whose middle it is).
        for (c, curve) in curves.iter().enumerate() {
            for &k in &curve.lines {
                let line = &nodes.lines[curve.loop_index][k];
                for &v in line.iter().take(1).chain(line.get(2)) {
                    block_of[v as usize] = c;
                }
            }
        }
    } else {
        for (v, m) in nodes.markers.iter().enumerate() {
            block_of[v] = m.loop_index().unwrap_or(surface).min(surface);
        }
    }
    // A corner or embedded point with a marker of its own is a point entity of its own (after the surface's
    // block), in a physical point tagged with its marker: where a solver pins a value.
    let pins: Vec<(usize, i64)> = match nodes.wall_markers() {
        Some(_) if by_piece => nodes.own_markers(),
        _ => Vec::new(),
    };
    for (p, &(v, _)) in pins.iter().enumerate() {
        block_of[v] = surface + 1 + p;
    }
    let mut blocks: Vec<Vec<usize>> = vec![Vec::new(); surface + 1 + pins.len()];
    for (v, &b) in block_of.iter().enumerate() {
        blocks[b].push(v);
    }
    let mut pins_named: Vec<i64> = pins.iter().map(|&(_, m)| m).collect();
    pins_named.sort_unstable();
    pins_named.dedup();
    let bbox = |vs: &mut dyn Iterator<Item = usize>| {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for v in vs {
            lo = lo.min(nodes.points[v]);
            hi = hi.max(nodes.points[v]);
        }
        if lo.x > hi.x {
            (DVec2::ZERO, DVec2::ZERO)
        } else {
            (lo, hi)
        }
    };
    let mut pieces_named: Vec<usize> = curves.iter().filter_map(|c| c.piece).collect();
    pieces_named.sort_unstable();
    pieces_named.dedup();
    let piece_phys = |j: usize| surface_phys + 1 + j;
    // The physical surface the region's file gave (Gmsh numbers each dimension's groups
    // apart, so its tag may be a curve's too), else ours.
    let (domain_tag, domain_name) = match &nodes.surface_group {
        Some((tag, name)) => (*tag, name.clone()),
        None => (surface_phys as i64, "domain".to_string()),
    };
    // Where the region numbers its walls, a third physical curve per number, past the pieces'.
    let marker_of = |j: usize| nodes.piece_markers.as_ref().and_then(|m| m.get(j).copied());
    let mut markers_named: Vec<i64> = pieces_named.iter().filter_map(|&j| marker_of(j)).collect();
    // The embedded lines: a curve per marker, in the physical curve of that marker.
    let mut inner_curves: Vec<(i64, Vec<usize>)> = Vec::new();
    for (k, &(_, m)) in nodes.inner.iter().enumerate() {
        match inner_curves.iter_mut().find(|(n, _)| *n == m) {
            Some((_, ks)) => ks.push(k),
            None => inner_curves.push((m, vec![k])),
        }
    }
    inner_curves.sort_by_key(|(m, _)| *m);
    markers_named.extend(inner_curves.iter().map(|(m, _)| *m));
    markers_named.sort_unstable();
    markers_named.dedup();
    // A positive marker is its own tag; 0 or below, a tag past the pieces'.
    let first_marker_phys = piece_phys(pieces_named.last().map_or(0, |&j| j + 1));
    let marker_tags = physical_tags(&markers_named, first_marker_phys);
    let marker_phys = move |m: i64| marker_tags[&m];
    // Physical points are numbered apart from curves: a positive marker is its own tag.
    let first_pin_phys = pins_named.iter().fold(0, |top, &m| top.max(m)).max(0) as usize + 1;
    let pin_tags = physical_tags(&pins_named, first_pin_phys);
    let pin_phys = move |m: i64| pin_tags[&m];
    // Where the region's lines part it into subdomains, a surface per subdomain, in the
    // physical surface its number tags (a number 0 or below, a tag past the others); else one
    // surface for the whole region.
    let mut subdomain_ids: Vec<i64> = nodes.subdomains.clone().unwrap_or_default();
    subdomain_ids.sort_unstable();
    subdomain_ids.dedup();
    let first_free = subdomain_ids.iter().fold(0, |top, &m| top.max(m)).max(0) as usize + 1;
    let subdomain_tags = physical_tags(&subdomain_ids, first_free);
    let surfaces: Vec<(i64, String, Vec<usize>)> = match &nodes.subdomains {
        Some(ids) => {
            let mut members: Vec<Vec<usize>> = vec![Vec::new(); subdomain_ids.len()];
            for (t, id) in ids.iter().enumerate() {
                let s = subdomain_ids
                    .binary_search(id)
                    .expect("every number is listed");
                members[s].push(t);
            }
            subdomain_ids
                .iter()
                .zip(members)
                .map(|(id, ts)| {
                    let name = match nodes.subdomain_names.get(id) {
                        Some(name) => name.clone(),
                        None => format!("subdomain{id}"),
                    };
                    (subdomain_tags[id] as i64, name, ts)
                })
                .collect()
        }
        None => vec![(
            domain_tag,
            domain_name.clone(),
            (0..nodes.triangles.len()).collect(),
        )],
    };
    // Gmsh reads a name up to the next double quote: one inside a name is written as a
    // single quote.
    let marker_name = |m: i64| match nodes.marker_names.get(&m) {
        Some(name) => name.replace('"', "'"),
        None => format!("marker{m}"),
    };
    let produce: Producer = Box::new(move |w: &mut dyn Write| {
        writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
        writeln!(
            w,
            "$PhysicalNames\n{}",
            nloops + surfaces.len() + pieces_named.len() + markers_named.len() + pins_named.len()
        )?;
        for &m in &pins_named {
            writeln!(w, "0 {} \"{}\"", pin_phys(m), marker_name(m))?;
        }
        for l in 0..nloops {
            writeln!(w, "1 {} \"loop{l}\"", shift + l + 1)?;
        }
        for &j in &pieces_named {
            writeln!(w, "1 {} \"piece{j}\"", piece_phys(j))?;
        }
        for &m in &markers_named {
            writeln!(w, "1 {} \"{}\"", marker_phys(m), marker_name(m))?;
        }
        for (tag, name, _) in &surfaces {
            writeln!(w, "2 {tag} \"{}\"", name.replace('"', "'"))?;
        }
        writeln!(w, "$EndPhysicalNames")?;
        writeln!(
            w,
            "$Entities\n{} {} {} 0",
            pins.len(),
            curves.len() + inner_curves.len(),
            surfaces.len()
        )?;
        for (p, &(v, m)) in pins.iter().enumerate() {
            let x = nodes.points[v];
            writeln!(w, "{} {} {} 0 1 {}", p + 1, F(x.x), F(x.y), pin_phys(m))?;
        }
        for (c, curve) in curves.iter().enumerate() {
            let lines = &nodes.lines[curve.loop_index];
            let (lo, hi) = bbox(
                &mut blocks[c].iter().copied().chain(
                    curve
                        .lines
                        .iter()
                        .flat_map(|&k| lines[k].iter().map(|&v| v as usize)),
                ),
            );
            write!(
                w,
                "{} {} {} 0 {} {} 0",
                c + 1,
                F(lo.x),
                F(lo.y),
                F(hi.x),
                F(hi.y)
            )?;
            // The wall's group first: readers that take one physical tag per curve (meshio's
            // `gmsh:physical`) see the boundary-condition numbers.
            match (curve.piece, curve.piece.and_then(marker_of)) {
                (Some(j), Some(m)) => writeln!(
                    w,
                    " 3 {} {} {} 0",
                    marker_phys(m),
                    shift + curve.loop_index + 1,
                    piece_phys(j)
                )?,
                (Some(j), None) => writeln!(w, " 2 {} {} 0", curve.loop_index + 1, piece_phys(j))?,
                (None, _) => writeln!(w, " 1 {} 0", curve.loop_index + 1)?,
            }
        }
        for (i, (m, ks)) in inner_curves.iter().enumerate() {
            let (lo, hi) = bbox(
                &mut ks
                    .iter()
                    .flat_map(|&k| nodes.inner[k].0.iter().map(|&v| v as usize)),
            );
            writeln!(
                w,
                "{} {} {} 0 {} {} 0 1 {} 0",
                curves.len() + 1 + i,
                F(lo.x),
                F(lo.y),
                F(hi.x),
                F(hi.y),
                marker_phys(*m)
            )?;
        }
        for (s, (tag, _, ts)) in surfaces.iter().enumerate() {
            let (lo, hi) = bbox(
                &mut ts
                    .iter()
                    .flat_map(|&t| nodes.triangles[t].iter().map(|&v| v as usize)),
            );
            write!(
                w,
                "{} {} {} 0 {} {} 0 1 {tag}",
                s + 1,
                F(lo.x),
                F(lo.y),
                F(hi.x),
                F(hi.y),
            )?;
            // The whole region's surface is bounded by every wall's curve; a subdomain's
            // curves are not worked out (readers take the elements' surfaces, not these).
            if surfaces.len() == 1 {
                write!(w, " {}", curves.len())?;
                for c in 0..curves.len() {
                    write!(w, " {}", c + 1)?;
                }
            } else {
                write!(w, " 0")?;
            }
            writeln!(w)?;
        }
        writeln!(w, "$EndEntities")?;

        let nonempty = blocks.iter().filter(|b| !b.is_empty()).count();
        writeln!(w, "$Nodes\n{nonempty} {n} {} {n}", n.min(1))?;
        // Points first, as Gmsh orders entities: then curves, then the surface.
        let order = (surface + 1..blocks.len()).chain(0..=surface);
        for (b, vs) in order
            .map(|b| (b, &blocks[b]))
            .filter(|(_, vs)| !vs.is_empty())
        {
            let (dim, tag) = match b {
                b if b < surface => (1, b + 1),
                b if b == surface => (2, 1),
                b => (0, b - surface),
            };
            writeln!(w, "{dim} {tag} 0 {}", vs.len())?;
            write_lines(w, vs.len(), |i, s| {
                let _ = writeln!(s, "{}", vs[i] + 1);
            })?;
            write_lines(w, vs.len(), |i, s| {
                let p = nodes.points[vs[i]];
                let _ = writeln!(s, "{} {} 0", F(p.x), F(p.y));
            })?;
        }
        writeln!(w, "$EndNodes")?;

        let nlines: usize = nodes.lines.iter().map(Vec::len).sum();
        let total = nlines + nodes.inner.len() + nodes.triangles.len() + pins.len();
        let nblocks = curves.iter().filter(|c| !c.lines.is_empty()).count()
            + inner_curves.len()
            + surfaces.iter().filter(|s| !s.2.is_empty()).count()
            + pins.len();
        writeln!(w, "$Elements\n{nblocks} {total} {} {total}", total.min(1))?;
        let mut tag = 0;
        let mut line = String::new();
        let mut element = |w: &mut dyn Write, vs: &[u32]| -> std::io::Result<()> {
            tag += 1;
            line.clear();
            element_line(&mut line, tag, vs);
            w.write_all(line.as_bytes())
        };
        for (p, &(v, _)) in pins.iter().enumerate() {
            writeln!(w, "0 {} 15 1", p + 1)?;
            element(w, &[v as u32])?;
        }
        for (c, curve) in curves
            .iter()
            .enumerate()
            .filter(|(_, c)| !c.lines.is_empty())
        {
            writeln!(w, "1 {} {line_type} {}", c + 1, curve.lines.len())?;
            for &k in &curve.lines {
                element(w, &nodes.lines[curve.loop_index][k])?;
            }
        }
        for (i, (_, ks)) in inner_curves.iter().enumerate() {
            writeln!(w, "1 {} {line_type} {}", curves.len() + 1 + i, ks.len())?;
            for &k in ks {
                element(w, &nodes.inner[k].0)?;
            }
        }
        for (s, (_, _, ts)) in surfaces.iter().enumerate().filter(|(_, s)| !s.2.is_empty()) {
            writeln!(w, "2 {} {triangle_type} {}", s + 1, ts.len())?;
            let first = tag + 1;
            write_lines(w, ts.len(), |i, line| {
                element_line(line, first + i, nodes.triangles[ts[i]])
            })?;
            tag += ts.len();
        }
        writeln!(w, "$EndElements")
    });
    write_files(vec![(path.to_path_buf(), produce)])
}

/// One line of `$Elements`: the element's tag, then its nodes (1-based).
fn element_line(s: &mut String, tag: usize, vs: &[u32]) {
    let _ = write!(s, "{tag}");
    for v in vs {
        let _ = write!(s, " {}", v + 1);
    }
    let _ = writeln!(s);
}

/// Read a Gmsh mesh (format 4.1 or 2.2, ASCII or binary, either byte order). Triangles (including higher-order ones, by their
/// corners) become the mesh; points and line elements are read but only used for markers;
/// quadrangles or 3-D elements are an error. Vertices are ordered by node tag, and z must be 0.
///
/// Markers come from the mesh topology ([`super::markers_from_topology`]); the loop index of
/// a vertex on a line element whose physical group is named `"loop<i>"` (as [`write_gmsh`]
/// names them) is taken from that name.
pub fn read_gmsh(path: &Path) -> Result<Mesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, "read", e))?;
    Ok(parse_bytes(&bytes, path, false)?.mesh)
}

/// A Gmsh mesh and a size at each vertex, from the first `$NodeData` view of the file (one
/// value per node, as Gmsh writes a background mesh's sizes): a background mesh for a graded
/// mesh ([`geometry::SizeField::from_mesh`]). The mesh is read as [`read_gmsh`] reads it.
pub fn read_gmsh_sizes(path: &Path) -> Result<(Mesh, Vec<f64>), MeshError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, "read", e))?;
    sizes_from(&bytes, path)
}

/// [`read_gmsh_sizes`] from the text of a file; errors name `mesh.msh`.
///
/// ```
/// let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n\
///     $EndNodes\n$Elements\n1\n1 2 0 1 2 3\n$EndElements\n$NodeData\n1\n\"h\"\n1\n0\n3\n0\n1\n3\n\
///     1 0.1\n2 0.2\n3 0.3\n$EndNodeData\n";
/// let (m, h) = cvtmesh::io::gmsh_sizes_from_str(text)?;
/// assert_eq!((m.num_triangles(), h), (1, vec![0.1, 0.2, 0.3]));
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn gmsh_sizes_from_str(text: &str) -> Result<(Mesh, Vec<f64>), MeshError> {
    sizes_from(text.as_bytes(), Path::new("mesh.msh"))
}

/// [`gmsh_sizes_from_str`] of a file's bytes, ASCII or binary.
///
/// ```
/// // A binary 2.2 file: ASCII lines around little-endian ints and doubles.
/// let mut b = b"$MeshFormat\n2.2 1 8\n".to_vec();
/// b.extend(1i32.to_le_bytes());
/// b.extend(b"\n$EndMeshFormat\n$Nodes\n3\n");
/// for (tag, x, y) in [(1i32, 0.0, 0.0), (2, 1.0, 0.0), (3, 0.0, 1.0)] {
///     b.extend(tag.to_le_bytes());
///     [x, y, 0.0f64].iter().for_each(|v| b.extend(v.to_le_bytes()));
/// }
/// // One block of one triangle (type 2) with no tags: number, then nodes 1, 2, 3.
/// b.extend(b"\n$EndNodes\n$Elements\n1\n");
/// [2, 1, 0, 1, 1, 2, 3].iter().for_each(|v: &i32| b.extend(v.to_le_bytes()));
/// b.extend(b"\n$EndElements\n$NodeData\n1\n\"h\"\n1\n0\n3\n0\n1\n3\n");
/// for (tag, h) in [(1i32, 0.1), (2, 0.2), (3, 0.3)] {
///     b.extend(tag.to_le_bytes());
///     b.extend(f64::to_le_bytes(h));
/// }
/// b.extend(b"\n$EndNodeData\n");
/// let (m, h) = cvtmesh::io::gmsh_sizes_from_bytes(&b)?;
/// assert_eq!((m.num_triangles(), h), (1, vec![0.1, 0.2, 0.3]));
/// // Cut short, it is an error saying where.
/// let e = cvtmesh::io::gmsh_sizes_from_bytes(&b[..b.len() - 30]).unwrap_err().to_string();
/// assert!(e.contains("$NodeData gives 3 values") && e.contains("the file is cut short"), "{e}");
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn gmsh_sizes_from_bytes(bytes: &[u8]) -> Result<(Mesh, Vec<f64>), MeshError> {
    sizes_from(bytes, Path::new("mesh.msh"))
}

fn sizes_from(bytes: &[u8], path: &Path) -> Result<(Mesh, Vec<f64>), MeshError> {
    let f = sizes_file_from(bytes, path)?;
    Ok((f.mesh, f.sizes))
}

/// [`read_gmsh_sizes`], saying which view the sizes are where the file has several.
pub(crate) fn read_gmsh_sizes_file(path: &Path) -> Result<SizesFile, MeshError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, "read", e))?;
    sizes_file_from(&bytes, path)
}

fn sizes_file_from(bytes: &[u8], path: &Path) -> Result<SizesFile, MeshError> {
    let Parsed {
        mesh, sizes, views, ..
    } = parse_bytes(bytes, path, true)?;
    let sizes = sizes.ok_or_else(|| {
        file_err(
            path,
            "no $NodeData section: the size at each vertex is read from the first $NodeData \
             view (one value per node)",
        )
    })?;
    // Gmsh's background field reads a file's first view too; with several, say which.
    let view = (views.len() > 1).then(|| {
        let quoted = |v: &[String]| {
            v.iter()
                .map(|n| format!("\"{n}\""))
                .collect::<Vec<_>>()
                .join(", ")
        };
        format!(
            "{}: the sizes are its first $NodeData view, {}, of {} (the others: {}), as Gmsh \
             takes a background mesh's first view",
            path.display(),
            quoted(&views[..1]),
            views.len(),
            quoted(&views[1..])
        )
    });
    Ok(SizesFile { mesh, sizes, view })
}

/// Parse the text of a Gmsh ASCII mesh, as [`read_gmsh`] reads a file; errors name
/// `mesh.msh`. A binary file is not text: [`gmsh_from_bytes`] reads either.
///
/// ```
/// let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 0 1 2 3\n$EndElements\n";
/// let m = cvtmesh::io::gmsh_from_str(text)?;
/// assert_eq!((m.num_vertices(), m.num_triangles()), (3, 1));
/// assert!(cvtmesh::io::gmsh_from_str("$MeshFormat\n").is_err());
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn gmsh_from_str(text: &str) -> Result<Mesh, MeshError> {
    gmsh_from_bytes(text.as_bytes())
}

/// Parse the bytes of a Gmsh mesh, ASCII or binary, as [`read_gmsh`] reads a file; errors
/// name `mesh.msh` (and, in a binary file, the byte where the fault is).
///
/// ```
/// // A binary 4.1 file, big-endian (the int after the format line tells the order).
/// let mut b = b"$MeshFormat\n4.1 1 8\n".to_vec();
/// b.extend(1i32.to_be_bytes());
/// b.extend(b"\n$EndMeshFormat\n$Nodes\n");
/// // One block (surface 1, not parametric) of nodes 1 to 3: size_t counts and tags.
/// [1u64, 3, 1, 3].iter().for_each(|v| b.extend(v.to_be_bytes()));
/// [2i32, 1, 0].iter().for_each(|v| b.extend(v.to_be_bytes()));
/// [3u64, 1, 2, 3].iter().for_each(|v| b.extend(v.to_be_bytes()));
/// [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0f64].iter().for_each(|v| b.extend(v.to_be_bytes()));
/// b.extend(b"\n$EndNodes\n$Elements\n");
/// [1u64, 1, 1, 1].iter().for_each(|v| b.extend(v.to_be_bytes()));
/// [2i32, 1, 2].iter().for_each(|v| b.extend(v.to_be_bytes()));
/// [1u64, 1, 1, 2, 3].iter().for_each(|v| b.extend(v.to_be_bytes()));
/// b.extend(b"\n$EndElements\n");
/// let m = cvtmesh::io::gmsh_from_bytes(&b)?;
/// assert_eq!((m.num_vertices(), m.num_triangles()), (3, 1));
/// // A count past the end of the file is refused before anything is made for it.
/// let at = b.windows(9).position(|w| w == b"$Elements").unwrap() + 10;
/// b[at..at + 8].copy_from_slice(&u64::MAX.to_be_bytes());
/// let e = cvtmesh::io::gmsh_from_bytes(&b).unwrap_err().to_string();
/// assert!(e.contains("$Elements gives 18446744073709551615 element blocks"), "{e}");
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn gmsh_from_bytes(bytes: &[u8]) -> Result<Mesh, MeshError> {
    Ok(parse_bytes(bytes, Path::new("mesh.msh"), false)?.mesh)
}

/// The boundary lines of a Gmsh mesh that carry a wall number, by their end vertices (as
/// [`read_gmsh`] numbers them): the `m` of a physical curve named `"marker<m>"` (as
/// [`write_gmsh_on`] writes a region's numbered walls), else, in a file not written here, the
/// line's first physical tag, which is how a Gmsh user numbers a boundary condition; and the
/// nodes of point elements in physical points, with their tags read the same way
/// ([`Walls::points`]). A mesh and its walls are the region to mesh again with the same
/// boundary conditions ([`geometry::Region::from_triangles_pinned`]).
///
/// ```
/// // A unit square of two triangles; its bottom line in physical curve 7, the rest in 9.
/// let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n\
///     4 0 1 0\n$EndNodes\n$Elements\n6\n1 1 2 7 1 1 2\n2 1 2 9 2 2 3\n3 1 2 9 2 3 4\n\
///     4 1 2 9 2 4 1\n5 2 2 0 1 1 2 3\n6 2 2 0 1 1 3 4\n$EndElements\n";
/// let walls = cvtmesh::io::gmsh_walls_from_str(text)?;
/// assert_eq!(walls.edges, [([0, 1], 7), ([1, 2], 9), ([2, 3], 9), ([3, 0], 9)]);
/// // Named groups give their names.
/// let named = text.replace("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n",
///     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n1 7 \"heated\"\n$EndPhysicalNames\n");
/// let walls = cvtmesh::io::gmsh_walls_from_str(&named)?;
/// assert_eq!(walls.names.get(&7).map(String::as_str), Some("heated"));
/// // A point element (type 15) on node 3 in physical point 21 "pin": a point of its own.
/// let pinned = named.replace("$Elements\n6\n", "$Elements\n7\n0 15 2 21 5 3\n")
///     .replace("1\n1 7 \"heated\"", "2\n1 7 \"heated\"\n0 21 \"pin\"");
/// let walls = cvtmesh::io::gmsh_walls_from_str(&pinned)?;
/// assert_eq!(walls.points, [(2, 21)]);
/// assert_eq!(walls.names.get(&21).map(String::as_str), Some("pin"));
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn gmsh_walls_from_str(text: &str) -> Result<Walls, MeshError> {
    gmsh_walls_from_bytes(text.as_bytes())
}

/// [`gmsh_walls_from_str`] of a file's bytes, ASCII or binary.
pub fn gmsh_walls_from_bytes(bytes: &[u8]) -> Result<Walls, MeshError> {
    Ok(parse_bytes(bytes, Path::new("mesh.msh"), false)?.walls)
}

/// [`read_gmsh`] and [`gmsh_walls_from_str`] of a file, read once.
pub fn read_gmsh_with_walls(path: &Path) -> Result<(Mesh, Walls), MeshError> {
    read_gmsh_file(path).map(|f| (f.mesh, f.walls))
}

/// [`read_gmsh_with_walls`], with the triangles' node count and a six-node file's edge nodes.
pub(crate) fn read_gmsh_file(path: &Path) -> Result<MeshFile, MeshError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, "read", e))?;
    let parsed = parse_bytes(&bytes, path, false)?;
    Ok(MeshFile {
        mesh: parsed.mesh,
        walls: parsed.walls,
        triangle_nodes: parsed.triangle_nodes,
        edge_nodes: parsed.edge_nodes,
    })
}

/// Element kinds the reader distinguishes.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Kind {
    Point,
    Line,
    Triangle,
    Other(&'static str),
}

/// Nodes per element and kind for Gmsh element types 1..=28.
pub(super) fn element_type(t: i64) -> Option<(usize, Kind)> {
    use Kind::*;
    Some(match t {
        15 => (1, Point),
        1 => (2, Line),
        8 => (3, Line),
        26 => (4, Line),
        27 => (5, Line),
        28 => (6, Line),
        2 => (3, Triangle),
        9 => (6, Triangle),
        20 => (9, Triangle),
        21 => (10, Triangle),
        22 => (12, Triangle),
        23 | 24 => (15, Triangle),
        25 => (21, Triangle),
        3 => (4, Other("quadrangle")),
        10 => (9, Other("quadrangle")),
        16 => (8, Other("quadrangle")),
        4 => (4, Other("tetrahedron")),
        11 => (10, Other("tetrahedron")),
        5 => (8, Other("hexahedron")),
        12 => (27, Other("hexahedron")),
        17 => (20, Other("hexahedron")),
        6 => (6, Other("prism")),
        13 => (18, Other("prism")),
        18 => (15, Other("prism")),
        7 => (5, Other("pyramid")),
        14 => (14, Other("pyramid")),
        19 => (13, Other("pyramid")),
        _ => return None,
    })
}

/// What the sections of a file contribute.
#[derive(Default)]
struct Raw {
    nodes: Vec<(u64, DVec2)>,
    triangles: Vec<[u64; 3]>,
    /// Line elements: end nodes and physical tag (0 if none).
    lines: Vec<(u64, u64, i64)>,
    /// Line elements with a wall number ([`curve_groups`]): end nodes and the number.
    walls: Vec<(u64, u64, i64)>,
    /// Point elements with a number ([`curve_groups`] of the point): node and number.
    pins: Vec<(u64, i64)>,
    /// The file's names of wall numbers.
    wall_names: std::collections::BTreeMap<i64, String>,
    names: HashMap<(i64, i64), String>,
    /// The first `$NodeData` view, when asked for: (node tag, value).
    node_data: Option<Vec<(u64, f64)>>,
    /// The names of every `$NodeData` view, in the file's order, when sizes are asked for.
    views: Vec<String>,
    /// Six-node triangles' edge nodes: the edge's corner tags and the node's tag.
    edge_nodes: Vec<([u64; 2], u64)>,
    /// Each triangle's region: its physical surface, or its surface where that has none.
    triangle_regions: Vec<i64>,
    /// Physical curves that no line keeps as its wall, each with the walls its lines keep.
    unkept: std::collections::BTreeMap<i64, std::collections::BTreeSet<i64>>,
    /// The most nodes a triangle element had (3, 6, 10, ...): above 3, the nodes that are no
    /// corners go.
    triangle_nodes: usize,
}

/// What a Gmsh file holds for us: the mesh, with `sizes` the first `$NodeData` view's value
/// at each of its vertices (None when the file has no such view), and the boundary lines that
/// carry a wall number.
struct Parsed {
    mesh: Mesh,
    sizes: Option<Vec<f64>>,
    /// The names of the `$NodeData` views, when sizes were asked for.
    views: Vec<String>,
    walls: Walls,
    triangle_nodes: usize,
    edge_nodes: Vec<([u32; 2], DVec2)>,
}

/// Parse a file's bytes: a binary file as the ASCII text of the same file, with its errors
/// naming the byte of the file they are about.
fn parse_bytes(bytes: &[u8], path: &Path, sizes: bool) -> Result<Parsed, MeshError> {
    // A UTF-8 byte-order mark, as Windows editors save one, is no part of the format.
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match gmsh_binary::ascii_of_binary(bytes, path)? {
        Some(ascii) => parse(&ascii.text, path, sizes).map_err(|e| ascii.locate(e)),
        None => parse(&String::from_utf8_lossy(bytes), path, sizes),
    }
}

fn parse(text: &str, path: &Path, sizes: bool) -> Result<Parsed, MeshError> {
    let mut t = Tokens::new(text, None, path);
    if t.peek() != Some("$MeshFormat") {
        return Err(t.err("not a Gmsh mesh: expected '$MeshFormat'"));
    }
    t.next("$MeshFormat")?;
    let version = t.next("the format version")?;
    let file_type = t.next("the file type")?;
    // Binary files (type 1) reach this parser as the ASCII text of the same file.
    if file_type != "0" {
        return Err(t.err(format!(
            "file type {file_type} is neither 0 (ASCII) nor 1 (binary)"
        )));
    }
    let v2 = match version {
        "4.1" => false,
        "2.2" | "2.1" | "2.0" | "2" => true,
        _ => {
            return Err(t.err(format!(
                "format version {version} is not supported; use 4.1 or 2.2"
            )))
        }
    };
    t.rest_of_line();
    expect_end(&mut t, "$EndMeshFormat")?;
    let mut raw = Raw::default();
    let mut entities = Entities::default();
    while let Some(section) = t.peek() {
        let line = t.line_no();
        t.next("a section")?;
        match section {
            "$PhysicalNames" => {
                let n = t.usize("the number of physical names")?;
                for _ in 0..n {
                    let dim = t.i64("a physical dimension")?;
                    let tag = t.i64("a physical tag")?;
                    let name = t.rest_of_line().trim_matches('"').to_string();
                    raw.names.insert((dim, tag), name);
                }
                expect_end(&mut t, "$EndPhysicalNames")?;
            }
            "$Entities" if !v2 => {
                entities = parse_entities(&mut t, &raw.names)?;
                expect_end(&mut t, "$EndEntities")?;
            }
            "$Nodes" => {
                if v2 {
                    parse_nodes_v2(&mut t, &mut raw)?
                } else {
                    parse_nodes_v4(&mut t, &mut raw)?
                }
                expect_end(&mut t, "$EndNodes")?;
            }
            "$Elements" => {
                if v2 {
                    parse_elements_v2(&mut t, &mut raw)?
                } else {
                    parse_elements_v4(&mut t, &mut raw, &entities)?
                }
                expect_end(&mut t, "$EndElements")?;
            }
            "$ParametricNodes" => {
                return Err(t.err_line(
                    line,
                    "the nodes are in $ParametricNodes (saved with Mesh.SaveParametric = 1), \
                     which this reader does not read; save the mesh without parametric \
                     coordinates",
                ))
            }
            "$NodeData" if sizes && raw.node_data.is_none() => {
                let (name, data) = parse_node_data(&mut t)?;
                raw.views.push(name);
                raw.node_data = Some(data);
                expect_end(&mut t, "$EndNodeData")?;
            }
            s if s.starts_with('$') && !s.starts_with("$End") => {
                // A section this reader does not need ($NodeData, $Periodic, ...): skip it,
                // a later view's name kept for the note on which view the sizes are.
                if s == "$NodeData" && sizes {
                    raw.views.push(view_name(&mut t)?);
                }
                let end = format!("$End{}", &s[1..]);
                loop {
                    match t.peek() {
                        Some(tok) if tok == end => break,
                        Some(_) => {
                            t.rest_of_line();
                        }
                        None => return Err(t.err_line(line, format!("section {s} has no {end}"))),
                    }
                }
                t.next(&end)?;
            }
            s => {
                return Err(t.err_line(
                    line,
                    format!("expected a section such as $Nodes, found '{s}'"),
                ))
            }
        }
    }
    assemble(raw, path)
}

/// A `$NodeData` section's string tags (each a quoted string on a line of its own), the first
/// the view's name ("" without one).
fn view_name(t: &mut Tokens) -> Result<String, MeshError> {
    let strings = t.usize("the number of string tags")?;
    t.rest_of_line();
    let mut name = String::new();
    for k in 0..strings {
        if t.peek().is_none() {
            return Err(t.err("unexpected end of file in $NodeData's string tags"));
        }
        let line = t.rest_of_line();
        if k == 0 {
            name = line.trim().trim_matches('"').to_string();
        }
    }
    Ok(name)
}

/// A `$NodeData` section's header (string, real and integer tags: the view's name, its time,
/// then time step, components, count and maybe a partition) and its values, which must be one
/// per node.
fn parse_node_data(t: &mut Tokens) -> Result<(String, Vec<(u64, f64)>), MeshError> {
    let name = view_name(t)?;
    let reals = t.usize("the number of real tags")?;
    for _ in 0..reals {
        t.f64("a real tag")?;
    }
    let ints = t.usize("the number of integer tags")?;
    let mut tags = Vec::with_capacity(ints.min(16));
    for _ in 0..ints {
        tags.push(t.i64("an integer tag")?);
    }
    let (components, count) = match tags[..] {
        [_, c, n, ..] => (c, n),
        _ => {
            return Err(t.err(format!(
                "$NodeData has {ints} integer tags; expected the time step, the number of \
                 components and the number of values"
            )))
        }
    };
    if components != 1 {
        return Err(t.err(format!(
            "$NodeData has {components} components per node; a size field needs 1"
        )));
    }
    let count =
        usize::try_from(count).map_err(|_| t.err(format!("$NodeData has {count} values")))?;
    let mut values = Vec::with_capacity(count.min(1 << 20));
    for _ in 0..count {
        let tag = t.usize("a node tag")? as u64;
        let value = node_value(t)?;
        if !(value > 0.0 && value < f64::INFINITY) {
            return Err(t.err(format!(
                "$NodeData gives node {tag} the size {value}; sizes must be positive and finite"
            )));
        }
        values.push((tag, value));
    }
    Ok((name, values))
}

/// A `$NodeData` value. meshio 5.3 under NumPy 2 writes each value of an ASCII file as the
/// repr of a NumPy scalar, `np.float64(0.1)`; its number is the value Gmsh would read.
fn node_value(t: &mut Tokens) -> Result<f64, MeshError> {
    let wrapped = t
        .peek()
        .and_then(|tok| tok.strip_prefix("np.float64(")?.strip_suffix(')'))
        .and_then(|inner| inner.parse::<f64>().ok());
    match wrapped {
        Some(v) => {
            t.next("a node value")?;
            Ok(v)
        }
        None => t.f64("a node value"),
    }
}

fn expect_end(t: &mut Tokens, end: &str) -> Result<(), MeshError> {
    match t.peek() {
        Some(tok) if tok == end => {
            t.next(end)?;
            Ok(())
        }
        Some(tok) => Err(t.err(format!("expected {end}, found '{tok}'"))),
        None => Err(t.err(format!("unexpected end of file, expected {end}"))),
    }
}

/// What the physical groups `phys` of a curve (`names` naming them) say of it: the group
/// that names its loop (one named `loop<i>`, as this module writes them; else the first), and
/// its wall, with the wall's name where the file gives one: the `m` of a group named
/// `marker<m>`; else the first group that is not one of this module's loops or pieces (a
/// group of ours naming a wall by name, or any group of a file not written here: how a Gmsh
/// user numbers a boundary condition); none in a file of ours whose region numbered no walls.
/// A point entity's groups give its marker the same way (`dim` 0; its loop tag is unused).
fn curve_groups(names: &HashMap<(i64, i64), String>, dim: i64, phys: &[i64]) -> CurveGroups {
    let named = |p: &i64| names.get(&(dim, *p)).map(String::as_str);
    let ours = |n: &str, prefix: &str| {
        n.strip_prefix(prefix)
            .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
    };
    let loop_tag = phys
        .iter()
        .copied()
        .find(|p| named(p).is_some_and(|n| ours(n, "loop")))
        .or(phys.first().copied())
        .unwrap_or(0);
    let generic = phys
        .iter()
        .find_map(|p| named(p)?.strip_prefix("marker")?.parse().ok());
    let wall = match generic {
        Some(m) => Some((m, None)),
        None => phys
            .iter()
            .find(|p| !named(p).is_some_and(|n| ours(n, "loop") || ours(n, "piece")))
            .filter(|&&p| p != 0)
            .map(|p| (*p, named(p).map(str::to_string))),
    };
    // The other groups of a user's file: a curve also in "all_boundary", say.
    let others = match (&wall, generic) {
        (Some((w, _)), None) => phys
            .iter()
            .copied()
            .filter(|p| {
                *p != 0
                    && p != w
                    && !named(p)
                        .is_some_and(|n| ours(n, "loop") || ours(n, "piece") || ours(n, "marker"))
            })
            .collect(),
        _ => Vec::new(),
    };
    CurveGroups {
        loop_tag,
        wall,
        others,
    }
}

/// A curve's physical groups, as [`curve_groups`] reads them.
#[derive(Clone, Default)]
struct CurveGroups {
    loop_tag: i64,
    wall: Option<(i64, Option<String>)>,
    /// The groups a user's file also puts the curve in, which no wall keeps.
    others: Vec<i64>,
}

/// 4.1 `$Entities`: each point's and curve's groups ([`curve_groups`]), by (dimension, tag).
fn parse_entities(
    t: &mut Tokens,
    names: &HashMap<(i64, i64), String>,
) -> Result<Entities, MeshError> {
    let counts = [
        t.usize("the number of point entities")?,
        t.usize("the number of curve entities")?,
        t.usize("the number of surface entities")?,
        t.usize("the number of volume entities")?,
    ];
    let mut curve_phys = HashMap::new();
    let mut surface_lists: Vec<(i64, Vec<i64>)> = Vec::new();
    for (dim, &count) in counts.iter().enumerate() {
        for _ in 0..count {
            let tag = t.i64("an entity tag")?;
            let ncoords = if dim == 0 { 3 } else { 6 };
            for _ in 0..ncoords {
                t.f64("an entity coordinate")?;
            }
            let nphys = t.usize("the number of physical tags")?;
            let mut phys = Vec::with_capacity(nphys.min(8));
            for _ in 0..nphys {
                phys.push(t.i64("a physical tag")?);
            }
            if dim <= 1 && !phys.is_empty() {
                curve_phys.insert((dim, tag), curve_groups(names, dim as i64, &phys));
            }
            if dim == 2 && !phys.is_empty() {
                surface_lists.push((tag, phys));
            }
            if dim > 0 {
                let nb = t.usize("the number of bounding entities")?;
                for _ in 0..nb {
                    t.i64("a bounding entity tag")?;
                }
            }
        }
    }
    // A surface in several physical groups takes the first, but not one that every surface
    // is in beside groups of their own (a catch-all "domain" over per-material groups), which
    // would make the materials one.
    let mut holding: HashMap<i64, usize> = HashMap::new();
    for (_, phys) in &surface_lists {
        let mut own = phys.clone();
        own.sort_unstable();
        own.dedup();
        for p in own {
            *holding.entry(p).or_default() += 1;
        }
    }
    let several = surface_lists.iter().any(|(_, l)| l.len() > 1);
    let everywhere = |p: i64| several && holding[&p] == surface_lists.len();
    let surface_phys = surface_lists
        .iter()
        .map(|(tag, phys)| {
            let own = phys.iter().copied().find(|&p| !everywhere(p));
            (*tag, own.unwrap_or(phys[0]))
        })
        .collect();
    Ok(Entities {
        curve_phys,
        surface_phys,
    })
}

/// What 4.1's `$Entities` tells the elements: each point's and curve's groups
/// ([`curve_groups`]), by (dimension, tag), and each surface's first physical tag.
#[derive(Default)]
struct Entities {
    curve_phys: HashMap<(usize, i64), CurveGroups>,
    surface_phys: HashMap<i64, i64>,
}

fn read_xyz(t: &mut Tokens) -> Result<DVec2, MeshError> {
    let line = t.line_no();
    let x = t.f64("x")?;
    let y = t.f64("y")?;
    let z = t.f64("z")?;
    planar_z(z).map_err(|m| t.err_line(line, m))?;
    Ok(DVec2::new(x, y))
}

fn parse_nodes_v4(t: &mut Tokens, raw: &mut Raw) -> Result<(), MeshError> {
    let nblocks = t.usize("the number of node blocks")?;
    t.usize("the number of nodes")?;
    t.usize("the smallest node tag")?;
    t.usize("the largest node tag")?;
    for _ in 0..nblocks {
        let dim = t.usize("an entity dimension")?;
        t.i64("an entity tag")?;
        let parametric = t.usize("the parametric flag")?;
        let count = t.usize("the number of nodes in the block")?;
        let mut tags = Vec::with_capacity(count.min(1 << 20));
        for _ in 0..count {
            tags.push(t.usize("a node tag")? as u64);
        }
        for tag in tags {
            let p = read_xyz(t)?;
            if parametric == 1 {
                for _ in 0..dim {
                    t.f64("a parametric coordinate")?;
                }
            }
            raw.nodes.push((tag, p));
        }
    }
    Ok(())
}

fn parse_nodes_v2(t: &mut Tokens, raw: &mut Raw) -> Result<(), MeshError> {
    let n = t.usize("the number of nodes")?;
    for _ in 0..n {
        let tag = t.usize("a node tag")? as u64;
        let p = read_xyz(t)?;
        raw.nodes.push((tag, p));
    }
    Ok(())
}

/// Read one element's nodes and file it under its kind.
fn add_element(
    t: &mut Tokens,
    raw: &mut Raw,
    line: usize,
    etype: i64,
    groups: &CurveGroups,
    region: i64,
) -> Result<(), MeshError> {
    let Some((nn, kind)) = element_type(etype) else {
        return Err(t.err_line(line, format!("element type {etype} is not supported")));
    };
    if let Kind::Other(name) = kind {
        return Err(t.err_line(
            line,
            format!("{name} elements are not supported: only triangle meshes can be read"),
        ));
    }
    let mut nodes = [0u64; 3];
    let mut on_edges = [0u64; 3];
    for k in 0..nn {
        let v = t.usize("a node tag")? as u64;
        // Higher-order elements list their corner nodes first; a six-node triangle then the
        // nodes of its edges (0, 1), (1, 2), (2, 0).
        if let Some(slot) = nodes.get_mut(k) {
            *slot = v;
        } else if let Some(slot) = on_edges.get_mut(k - 3) {
            *slot = v;
        }
    }
    if kind == Kind::Triangle && nn == 6 {
        for (k, &node) in on_edges.iter().enumerate() {
            raw.edge_nodes.push(([nodes[k], nodes[(k + 1) % 3]], node));
        }
    }
    match kind {
        Kind::Line => {
            raw.lines.push((nodes[0], nodes[1], groups.loop_tag));
            if let Some((w, name)) = &groups.wall {
                for &other in &groups.others {
                    raw.unkept.entry(other).or_default().insert(*w);
                }
                raw.walls.push((nodes[0], nodes[1], *w));
                if let Some(name) = name {
                    raw.wall_names.insert(*w, name.clone());
                }
            }
        }
        Kind::Triangle => {
            raw.triangles.push(nodes);
            raw.triangle_regions.push(region);
            raw.triangle_nodes = raw.triangle_nodes.max(nn);
        }
        Kind::Point => {
            if let Some((m, name)) = &groups.wall {
                raw.pins.push((nodes[0], *m));
                if let Some(name) = name {
                    raw.wall_names.insert(*m, name.clone());
                }
            }
        }
        _ => {}
    }
    Ok(())
}

fn parse_elements_v4(t: &mut Tokens, raw: &mut Raw, entities: &Entities) -> Result<(), MeshError> {
    let nblocks = t.usize("the number of element blocks")?;
    t.usize("the number of elements")?;
    t.usize("the smallest element tag")?;
    t.usize("the largest element tag")?;
    for _ in 0..nblocks {
        let dim = t.usize("an entity dimension")?;
        let entity = t.i64("an entity tag")?;
        let etype = t.i64("an element type")?;
        let count = t.usize("the number of elements in the block")?;
        let none = CurveGroups::default();
        let groups = entities.curve_phys.get(&(dim, entity)).unwrap_or(&none);
        let region = entities
            .surface_phys
            .get(&entity)
            .map_or(entity, |&p| -p.abs() - 1);
        for _ in 0..count {
            let line = t.line_no();
            t.usize("an element tag")?;
            add_element(t, raw, line, etype, groups, region)?;
        }
    }
    Ok(())
}

fn parse_elements_v2(t: &mut Tokens, raw: &mut Raw) -> Result<(), MeshError> {
    let n = t.usize("the number of elements")?;
    for _ in 0..n {
        let line = t.line_no();
        t.usize("an element tag")?;
        let etype = t.i64("an element type")?;
        let ntags = t.usize("the number of tags")?;
        let (mut phys, mut elementary) = (0, 0);
        for k in 0..ntags {
            let v = t.i64("a tag")?;
            match k {
                0 => phys = v,
                1 => elementary = v,
                _ => {}
            }
        }
        let dim = if etype == 15 { 0 } else { 1 };
        let groups = curve_groups(&raw.names, dim, &[phys]);
        // The physical surface, else the surface (the two numberings kept apart).
        let region = if phys != 0 {
            -phys.abs() - 1
        } else {
            elementary
        };
        add_element(t, raw, line, etype, &groups, region)?;
    }
    Ok(())
}

fn assemble(mut raw: Raw, path: &Path) -> Result<Parsed, MeshError> {
    raw.nodes.sort_by_key(|n| n.0);
    if let Some(w) = raw.nodes.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(file_err(path, format!("node tag {} appears twice", w[0].0)));
    }
    if raw.triangles.is_empty() && !raw.nodes.is_empty() {
        return Err(file_err(
            path,
            "the file has no triangle elements (once a model has a physical group, Gmsh saves \
             only the elements of physical groups: add a physical surface, or set \
             Mesh.SaveAll = 1)",
        ));
    }
    // Where the edge nodes were, before they go with the other nodes that are no corners.
    let edge_places: Vec<([u64; 2], DVec2)> = if raw.edge_nodes.is_empty() {
        Vec::new()
    } else {
        let place: HashMap<u64, DVec2> = raw.nodes.iter().copied().collect();
        let mut found = Vec::with_capacity(raw.edge_nodes.len());
        for &(ends, node) in &raw.edge_nodes {
            let p = place.get(&node).copied().ok_or_else(|| {
                file_err(
                    path,
                    format!("an element refers to node {node}, which is not in $Nodes"),
                )
            })?;
            found.push((ends, p));
        }
        found
    };
    if raw.triangle_nodes > 3 {
        // The mesh is the corners' triangles: the nodes on edges and inside go, with their
        // values, so a six-node mesh reads as the three-node mesh of its corners.
        let mut corners: Vec<u64> = raw.triangles.iter().flatten().copied().collect();
        corners.sort_unstable();
        corners.dedup();
        let corner = |tag: &u64| corners.binary_search(tag).is_ok();
        raw.nodes.retain(|n| corner(&n.0));
        raw.lines.retain(|(a, b, _)| corner(a) && corner(b));
        raw.walls.retain(|(a, b, _)| corner(a) && corner(b));
        raw.pins.retain(|(a, _)| corner(a));
        if let Some(data) = raw.node_data.as_mut() {
            data.retain(|(tag, _)| corner(tag));
        }
    }
    // Node tags are usually dense (1..=n): index them with a table, else with a hash map.
    let max_tag = raw.nodes.last().map_or(0, |n| n.0);
    let dense: Option<Vec<u32>> = (max_tag <= 4 * raw.nodes.len() as u64 + 1024).then(|| {
        let mut table = vec![u32::MAX; max_tag as usize + 1];
        for (i, n) in raw.nodes.iter().enumerate() {
            table[n.0 as usize] = i as u32;
        }
        table
    });
    let sparse: HashMap<u64, u32> = match dense {
        Some(_) => HashMap::new(),
        None => raw
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (n.0, i as u32))
            .collect(),
    };
    let lookup = |tag: u64| {
        let found = match &dense {
            Some(table) => table.get(tag as usize).copied().filter(|&i| i != u32::MAX),
            None => sparse.get(&tag).copied(),
        };
        found.ok_or_else(|| {
            file_err(
                path,
                format!("an element refers to node {tag}, which is not in $Nodes"),
            )
        })
    };
    let points: Vec<DVec2> = raw.nodes.iter().map(|n| n.1).collect();
    let mut triangles = Vec::with_capacity(raw.triangles.len());
    for tri in &raw.triangles {
        triangles.push([lookup(tri[0])?, lookup(tri[1])?, lookup(tri[2])?]);
    }
    let mut mesh = read_mesh_parts(points, triangles, None);
    for &(a, b, phys) in &raw.lines {
        let named = raw
            .names
            .get(&(1, phys))
            .and_then(|s| s.strip_prefix("loop"))
            .and_then(|s| s.parse::<usize>().ok());
        if let Some(loop_index) = named {
            for v in [lookup(a)?, lookup(b)?] {
                let m = &mut mesh.markers[v as usize];
                *m = match *m {
                    VertexMarker::Boundary {
                        piece, loop_param, ..
                    } => VertexMarker::Boundary {
                        loop_index,
                        piece,
                        loop_param,
                    },
                    _ => VertexMarker::Boundary {
                        loop_index,
                        piece: super::UNKNOWN_PIECE,
                        loop_param: f64::NAN,
                    },
                };
            }
        }
    }
    let sizes = match raw.node_data.take() {
        None => None,
        Some(data) => {
            let mut sizes = vec![None; mesh.points.len()];
            for (tag, value) in data {
                let i = lookup(tag).map_err(|_| {
                    file_err(
                        path,
                        format!("$NodeData gives a value for node {tag}, which is not in $Nodes"),
                    )
                })?;
                if sizes[i as usize].replace(value).is_some() {
                    return Err(file_err(
                        path,
                        format!("$NodeData gives node {tag} two values"),
                    ));
                }
            }
            let values: Option<Vec<f64>> = sizes.iter().copied().collect();
            match values {
                Some(v) => Some(v),
                None => {
                    let i = sizes.iter().position(Option::is_none).unwrap_or(0);
                    return Err(file_err(
                        path,
                        format!("$NodeData gives no value for node {}", raw.nodes[i].0),
                    ));
                }
            }
        }
    };
    let mut lines = Vec::with_capacity(raw.lines.len());
    for &(a, b, _) in &raw.lines {
        lines.push([lookup(a)?, lookup(b)?]);
    }
    let inner = super::inner_edges(&mesh, &raw.triangle_regions, &lines);
    let mut edges = Vec::with_capacity(raw.walls.len());
    let mut inner_marked = Vec::new();
    for &(a, b, w) in &raw.walls {
        let (a, b) = (lookup(a)?, lookup(b)?);
        // A curve group inside the mesh (an interface) numbers no wall of the region, but
        // the line it is.
        if inner.binary_search(&[a.min(b), a.max(b)]).is_err() {
            edges.push(([a, b], w));
        } else {
            inner_marked.push(([a, b], w));
        }
    }
    let inner_markers = super::inner_markers(&inner, &inner_marked);
    let mut points = Vec::with_capacity(raw.pins.len());
    for &(a, m) in &raw.pins {
        points.push((lookup(a)?, m));
    }
    // One physical surface over every triangle: the region's, kept through a new mesh.
    let surface_group = match raw.triangle_regions.first() {
        Some(&r) if r < 0 && raw.triangle_regions.iter().all(|&q| q == r) => {
            let tag = -(r + 1);
            let name = raw.names.get(&(2, tag)).cloned();
            Some((tag, name.unwrap_or_else(|| format!("surface{tag}"))))
        }
        _ => None,
    };
    let notes = raw
        .unkept
        .iter()
        .map(|(group, kept)| {
            let name = raw
                .names
                .get(&(1, *group))
                .map_or(String::new(), |n| format!(" \"{n}\""));
            let kept: Vec<String> = kept.iter().map(|k| k.to_string()).collect();
            format!(
                "physical curve {group}{name} is not kept: its curves are in physical curve{} \
                 {} as well, and a boundary edge keeps one wall, the first",
                if kept.len() == 1 { "" } else { "s" },
                kept.join(", ")
            )
        })
        .collect();
    // Several physical surfaces number the triangles as parts (a surface without a physical
    // group leaves them unnumbered).
    let physical = |r: i64| (r < 0).then_some(-(r + 1));
    let subdomains = match raw.triangle_regions.first() {
        Some(&r) if surface_group.is_none() && physical(r).is_some() => raw
            .triangle_regions
            .iter()
            .map(|&q| physical(q))
            .collect::<Option<Vec<i64>>>()
            .unwrap_or_default(),
        _ => Vec::new(),
    };
    let subdomain_names = subdomains
        .iter()
        .filter_map(|&n| Some((n, raw.names.get(&(2, n))?.clone())))
        .collect();
    let walls = Walls {
        edges,
        points,
        names: std::mem::take(&mut raw.wall_names),
        inner,
        inner_markers,
        subdomains,
        subdomain_names,
        surface_group,
        notes,
    };
    let mut edge_nodes = Vec::with_capacity(edge_places.len());
    for (ends, p) in edge_places {
        let (a, b) = (lookup(ends[0])?, lookup(ends[1])?);
        edge_nodes.push(([a.min(b), a.max(b)], p));
    }
    edge_nodes.sort_unstable_by_key(|e| e.0);
    edge_nodes.dedup_by_key(|e| e.0);
    Ok(Parsed {
        mesh,
        sizes,
        views: std::mem::take(&mut raw.views),
        walls,
        triangle_nodes: raw.triangle_nodes,
        edge_nodes,
    })
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;
    use std::fs;

    #[test]
    fn round_trip_preserves_points_triangles_and_loops() {
        assert_round_trip_keeps_loops("sq.msh", write_gmsh, read_gmsh);
    }

    #[test]
    fn loop_names_decide_loop_numbers() {
        // Swap the roles in the file: loop names must win over the topology's numbering.
        let dir = TempDir::new("msh-names");
        let m = square_with_hole();
        let p = dir.path("sq.msh");
        write_gmsh(&m, &p).unwrap();
        let text = fs::read_to_string(&p)
            .unwrap()
            .replace("\"loop0\"", "\"loopX\"")
            .replace("\"loop1\"", "\"loop0\"");
        fs::write(&p, text.replace("\"loopX\"", "\"loop1\"")).unwrap();
        let r = read_gmsh(&p).unwrap();
        assert_eq!(r.markers.len(), m.markers.len());
        for (a, b) in r.markers.iter().zip(&m.markers) {
            assert_eq!(a.loop_index(), b.loop_index().map(|l| 1 - l));
        }
    }

    #[test]
    fn file_structure_is_gmsh_4_1() {
        let dir = TempDir::new("msh-struct");
        let m = square_with_hole();
        let p = dir.path("sq.msh");
        write_gmsh(&m, &p).unwrap();
        let text = fs::read_to_string(&p).unwrap();
        assert!(text.starts_with("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n"));
        assert!(text.contains("1 1 \"loop0\"\n1 2 \"loop1\"\n2 100 \"domain\"\n"));
        assert!(text.contains("$Entities\n0 2 1 0\n"));
        // 3 node blocks (2 loops + interior) with 48 nodes; 2 line blocks + 1 triangle block.
        assert!(text.contains("$Nodes\n3 48 1 48\n1 1 0 24\n"));
        assert!(text.contains("$Elements\n3 96 1 96\n1 1 1 24\n"));
        assert!(text.contains("\n2 1 2 64\n"));
    }

    #[test]
    fn reads_gmsh_2_2_with_cw_and_second_order_triangles() {
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Comments\nanything here\n$EndComments\n\
                    $Nodes\n5\n10 0 0 0\n20 1 0 0\n30 1 1 0\n40 0 1 0\n50 0.5 0.5 0\n$EndNodes\n\
                    $Elements\n3\n1 15 2 0 1 10\n2 1 2 7 1 10 20\n3 2 2 0 3 10 40 30\n$EndElements\n";
        let r = parse(text, Path::new("v2.msh"), false)
            .map(|r| r.mesh)
            .unwrap();
        assert_eq!(r.points.len(), 5);
        assert_eq!(r.points[1], DVec2::new(1.0, 0.0));
        assert_eq!(r.triangles, [[0, 2, 3]]);
        let text4 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n2 1 1 3\n1\n2\n3\n\
                     0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n2 1 9 1\n1 1 2 3 1 2 3\n$EndElements\n";
        let r = parse(text4, Path::new("p.msh"), false)
            .map(|r| r.mesh)
            .unwrap();
        assert_eq!(r.triangles, [[0, 1, 2]]);
        // Sparse node tags (looked up through a hash map), listed out of order.
        let sparse = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n9000000000 0 1 0\n7 0 0 0\n\
                      123456789 1 0 0\n$EndNodes\n$Elements\n1\n1 2 0 7 123456789 9000000000\n$EndElements\n";
        let r = parse(sparse, Path::new("s.msh"), false)
            .map(|r| r.mesh)
            .unwrap();
        assert_eq!(r.points, [DVec2::ZERO, DVec2::X, DVec2::Y]);
        assert_eq!(r.triangles, [[0, 1, 2]]);
        assert!(r.markers.iter().all(|m| m.loop_index() == Some(0)));
    }

    /// Two triangles of a square in different physical surfaces (2.2: each element's first
    /// tag), or in different surfaces without physical ones (4.1's entity blocks), share
    /// their diagonal as an interface; a line element inside the mesh is one too, and it
    /// numbers no wall of the region.
    /// A rectangle as Gmsh users group it: curves in `inlet` 11 or `walls` 12 and all of them
    /// in `all_boundary` 99 as well, the surface in `fluid` 1. The walls keep 11 and 12 and
    /// say that 99 is not kept; the surface group is kept, tag and name.
    #[test]
    fn a_curve_in_two_groups_is_named_and_the_surface_group_kept() {
        let text = include_str!("../../tests/data/msh/overlapping_groups.msh");
        let walls = gmsh_walls_from_str(text).unwrap();
        let mut markers: Vec<i64> = walls.edges.iter().map(|e| e.1).collect();
        markers.sort_unstable();
        assert_eq!(markers, [11, 12, 12, 12]);
        assert_eq!(walls.surface_group, Some((1, "fluid".to_string())));
        assert_eq!(walls.notes.len(), 1);
        assert!(walls.notes[0].starts_with("physical curve 99 \"all_boundary\" is not kept: its curves are in physical curves 11, 12 as well"), "{}", walls.notes[0]);
        // One group per curve: nothing to note.
        let ours = text.replace("2 12 99", "1 12").replace("2 11 99", "1 11");
        assert!(gmsh_walls_from_str(&ours).unwrap().notes.is_empty());
        // Saved with a byte-order mark (a Windows editor's), the same file.
        let marked = gmsh_walls_from_str(&format!("\u{feff}{text}")).unwrap();
        assert_eq!(marked, walls);
    }

    #[test]
    fn edges_between_surfaces_and_lines_inside_are_inner() {
        let nodes = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n";
        let v2 = |tags: [&str; 2], line: &str| {
            format!(
                "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n{nodes}$Elements\n{}\n1 2 2 {} 1 2 3\n2 2 2 {} 1 3 4\n{line}$EndElements\n",
                if line.is_empty() { 2 } else { 3 },
                tags[0],
                tags[1]
            )
        };
        let inner = |text: &str| parse(text, Path::new("t.msh"), false).unwrap().walls.inner;
        assert_eq!(inner(&v2(["10 1", "20 1"], "")), [[0, 2]]);
        assert!(inner(&v2(["10 1", "10 1"], "")).is_empty());
        assert_eq!(inner(&v2(["0 1", "0 2"], "")), [[0, 2]]);
        let with_line = parse(
            &v2(["10 1", "10 1"], "3 1 2 5 5 1 3\n"),
            Path::new("t.msh"),
            false,
        )
        .unwrap();
        assert_eq!(with_line.walls.inner, [[0, 2]]);
        assert!(with_line.walls.edges.is_empty());
        let v4 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n\
                  $Elements\n2 2 1 2\n2 1 2 1\n1 1 2 3\n2 2 2 1\n2 1 3 4\n$EndElements\n";
        assert_eq!(inner(v4), [[0, 2]]);
    }

    #[test]
    fn bad_files_give_errors_with_line_numbers() {
        let head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
        let cases = [
            ("hello", "line 1: not a Gmsh mesh"),
            ("$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", "the binary int after the format line is"),
            ("$MeshFormat\n4.1 2 8\n$EndMeshFormat\n", "file type 2 is neither 0 (ASCII) nor 1 (binary)"),
            ("$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", "version 3.0 is not supported"),
            (&format!("{head}$Nodes\n1 1 1 1\n2 1 0 1\n1\n0 0 0.5\n$EndNodes\n"), "line 8: z = 0.5"),
            (&format!("{head}$Nodes\n1 1 1 1\n2 1 0 1\n1\n0 x 0\n$EndNodes\n"), "line 8: expected y"),
            (&format!("{head}$Nodes\n1 1 1 1\n2 1 0 1\n1\n0 0 0\n"), "expected $EndNodes"),
            (&format!("{head}$Elements\n1 1 1 1\n2 1 3 1\n1 1 2 3 4\n$EndElements\n"), "line 7: quadrangle"),
            (&format!("{head}$Elements\n1 1 1 1\n2 1 99 1\n1 1 2 3\n$EndElements\n"), "line 7: element type 99"),
            (&format!("{head}$Nodes\n0 0 0 0\n$EndNodes\n$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 3\n$EndElements\n"), "refers to node 1"),
            (&format!("{head}$Nodes\n1 1 1 1\n2 1 0 1\n1\n0 0 0\n$EndNodes\n"), "no triangle elements (once a model has a physical group"),
            (&format!("{head}$ParametricNodes\n1 1 1 1\n$EndParametricNodes\n"), "line 4: the nodes are in $ParametricNodes"),
            (&format!("{head}$Foo\n1 2 3\n"), "section $Foo has no $EndFoo"),
            (&format!("{head}junk\n"), "line 4: expected a section"),
        ];
        for (text, want) in cases {
            let e = parse_bytes(text.as_bytes(), Path::new("bad.msh"), false)
                .map(|r| r.mesh)
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("bad.msh: ") && e.contains(want),
                "{e:?} should contain {want:?}"
            );
        }
    }

    /// Binary files and their ASCII twins, written by the same tool from the same mesh
    /// (`crates/mesh/tests/data/msh/`). `gmsh*`: Gmsh 4.15's Python API, a unit square with a
    /// square hole (0.4–0.6) built from points and lines with a mesh size of 0.5, in physical
    /// curves 7 "inflow" (the bottom), 8 "wall" (the other outer sides) and 9 (unnamed: the
    /// hole), physical point 21 "pin" (the origin) and physical surface 100 "domain", saved
    /// with `Mesh.MshFileVersion` 4.1 or 2.2 and `Mesh.Binary` 0 or 1; `gmsh*_sizes*` is
    /// `gmsh.view.write` of a "NodeData" view of 0.05 + 0.1 x + 0.2 y at every node, with
    /// `PostProcessing.SaveMesh` = 1. `meshio*`: meshio 5.3's `write(..., file_format="gmsh"
    /// or "gmsh22", binary=False or True)` of a unit square of four triangles about
    /// (0.1, 0.7): `plain` the triangles alone, `physical` with its sides as lines in
    /// `gmsh:physical` 3 "bottom" and 5 "top" (4.1 needs `gmsh:dim_tags`), `sizes` with point
    /// data "h" of 0.1 to 0.5.
    fn fixture(name: &str) -> &'static [u8] {
        match name {
            "gmsh41_ascii" => include_bytes!("../../tests/data/msh/gmsh41_ascii.msh"),
            "gmsh41_binary" => include_bytes!("../../tests/data/msh/gmsh41_binary.msh"),
            "gmsh22_ascii" => include_bytes!("../../tests/data/msh/gmsh22_ascii.msh"),
            "gmsh22_binary" => include_bytes!("../../tests/data/msh/gmsh22_binary.msh"),
            "gmsh41_sizes_ascii" => include_bytes!("../../tests/data/msh/gmsh41_sizes_ascii.msh"),
            "gmsh41_sizes_binary" => include_bytes!("../../tests/data/msh/gmsh41_sizes_binary.msh"),
            "gmsh22_sizes_ascii" => include_bytes!("../../tests/data/msh/gmsh22_sizes_ascii.msh"),
            "gmsh22_sizes_binary" => include_bytes!("../../tests/data/msh/gmsh22_sizes_binary.msh"),
            "meshio41_plain_ascii" => {
                include_bytes!("../../tests/data/msh/meshio41_plain_ascii.msh")
            }
            "meshio41_plain_binary" => {
                include_bytes!("../../tests/data/msh/meshio41_plain_binary.msh")
            }
            "meshio22_plain_ascii" => {
                include_bytes!("../../tests/data/msh/meshio22_plain_ascii.msh")
            }
            "meshio22_plain_binary" => {
                include_bytes!("../../tests/data/msh/meshio22_plain_binary.msh")
            }
            "meshio41_physical_ascii" => {
                include_bytes!("../../tests/data/msh/meshio41_physical_ascii.msh")
            }
            "meshio41_physical_binary" => {
                include_bytes!("../../tests/data/msh/meshio41_physical_binary.msh")
            }
            "meshio22_physical_ascii" => {
                include_bytes!("../../tests/data/msh/meshio22_physical_ascii.msh")
            }
            "meshio22_physical_binary" => {
                include_bytes!("../../tests/data/msh/meshio22_physical_binary.msh")
            }
            "meshio41_sizes_ascii" => {
                include_bytes!("../../tests/data/msh/meshio41_sizes_ascii.msh")
            }
            "meshio41_sizes_binary" => {
                include_bytes!("../../tests/data/msh/meshio41_sizes_binary.msh")
            }
            "meshio22_sizes_ascii" => {
                include_bytes!("../../tests/data/msh/meshio22_sizes_ascii.msh")
            }
            "meshio22_sizes_binary" => {
                include_bytes!("../../tests/data/msh/meshio22_sizes_binary.msh")
            }
            _ => panic!("no fixture {name}"),
        }
    }

    const TWINS: [&str; 10] = [
        "gmsh41",
        "gmsh22",
        "gmsh41_sizes",
        "gmsh22_sizes",
        "meshio41_plain",
        "meshio22_plain",
        "meshio41_physical",
        "meshio22_physical",
        "meshio41_sizes",
        "meshio22_sizes",
    ];

    /// Everything a read gives, as text: markers of a foreign file hold NaN, which `==`
    /// would never find equal.
    fn everything(p: &Parsed) -> String {
        format!(
            "{:?} {:?} {:?} {:?} {} {:?}",
            p.mesh, p.sizes, p.views, p.walls, p.triangle_nodes, p.edge_nodes
        )
    }

    /// [`everything`] but the coordinates and sizes, and those within `tol` of `want`'s.
    fn same_within(got: &Parsed, want: &Parsed, tol: f64) -> Result<(), String> {
        let shape = |p: &Parsed| {
            format!(
                "{:?} {:?} {:?} {:?} {:?} {} {}",
                p.mesh.triangles,
                p.mesh.markers,
                p.views,
                p.walls,
                p.sizes.as_ref().map(Vec::len),
                p.triangle_nodes,
                p.edge_nodes.len()
            )
        };
        if shape(got) != shape(want) {
            return Err(format!("{}\nis not\n{}", shape(got), shape(want)));
        }
        let values = |p: &Parsed| -> Vec<f64> {
            let xy = p.mesh.points.iter().flat_map(|q| [q.x, q.y]);
            xy.chain(p.sizes.iter().flatten().copied()).collect()
        };
        let (a, b) = (values(got), values(want));
        match a.iter().zip(&b).position(|(a, b)| (a - b).abs() > tol) {
            Some(k) if a.len() == b.len() => Err(format!("value {k}: {} is not {}", a[k], b[k])),
            _ if a.len() != b.len() => Err("not as many values".into()),
            _ => Ok(()),
        }
    }

    #[test]
    fn binary_files_read_as_their_ascii_twins() {
        for name in TWINS {
            let path = Path::new("t.msh");
            let ascii = fixture(&format!("{name}_ascii"));
            let binary = fixture(&format!("{name}_binary"));
            assert!(std::str::from_utf8(binary).is_err(), "{name} is binary");
            for sizes in [false, true] {
                if sizes && !name.contains("sizes") {
                    continue;
                }
                let a = parse_bytes(ascii, path, sizes).unwrap();
                let b = parse_bytes(binary, path, sizes).unwrap();
                if name.starts_with("meshio") {
                    // meshio's ASCII has 17 digits, which give every double back.
                    assert_eq!(everything(&a), everything(&b), "{name}, sizes {sizes}");
                } else {
                    // Gmsh's has 16 (`%.16g`), one rounding off the double it wrote in binary
                    // (0.2711324865408619 for 0.27113248654086186).
                    same_within(&b, &a, 1e-16).unwrap_or_else(|e| panic!("{name}, {sizes}: {e}"));
                    assert_ne!(
                        everything(&a),
                        everything(&b),
                        "{name}: 16 digits were enough"
                    );
                }
            }
        }
        // What the twins hold, so that equal reads are no two empty ones.
        let gmsh = parse_bytes(fixture("gmsh41_binary"), Path::new("g.msh"), false).unwrap();
        assert_eq!(gmsh.mesh.points.len(), 20);
        assert_eq!(gmsh.mesh.points[0], DVec2::ZERO);
        let loops: std::collections::BTreeSet<_> = gmsh
            .mesh
            .markers
            .iter()
            .filter_map(|m| m.loop_index())
            .collect();
        assert_eq!(loops.len(), 2, "the square and its hole");
        let walls: std::collections::BTreeSet<i64> = gmsh.walls.edges.iter().map(|e| e.1).collect();
        assert_eq!(walls, [7, 8, 9].into());
        assert_eq!(gmsh.walls.points, [(0, 21)]);
        assert_eq!(gmsh.walls.names[&7], "inflow");
        let v2 = parse_bytes(fixture("gmsh22_binary"), Path::new("g.msh"), false).unwrap();
        assert_eq!(
            everything(&v2),
            everything(&gmsh),
            "2.2 and 4.1 of one mesh, in binary"
        );
        let (m, h) = sizes_from(fixture("gmsh22_sizes_binary"), Path::new("g.msh")).unwrap();
        for (p, h) in m.points.iter().zip(&h) {
            assert!(
                (h - (0.05 + 0.1 * p.x + 0.2 * p.y)).abs() < 1e-15,
                "{p} {h}"
            );
        }
        let (m, h) = sizes_from(fixture("meshio41_sizes_binary"), Path::new("m.msh")).unwrap();
        assert_eq!((m.num_triangles(), h), (4, vec![0.1, 0.2, 0.3, 0.4, 0.5]));
        let walls = parse_bytes(
            fixture("meshio22_physical_binary"),
            Path::new("m.msh"),
            false,
        )
        .unwrap()
        .walls;
        assert_eq!(
            walls.edges,
            [([0, 1], 3), ([1, 2], 3), ([2, 3], 5), ([3, 0], 5)]
        );
        assert_eq!(walls.names[&5], "top");
    }

    #[test]
    fn read_gmsh_reads_binary_files() {
        let dir = TempDir::new("msh-binary");
        let p = dir.path("b.msh");
        fs::write(&p, fixture("gmsh41_sizes_binary")).unwrap();
        let bytes = fixture("gmsh41_sizes_binary");
        assert_eq!(
            format!("{:?}", read_gmsh(&p).unwrap()),
            format!("{:?}", gmsh_from_bytes(bytes).unwrap())
        );
        let (m, walls) = read_gmsh_with_walls(&p).unwrap();
        assert_eq!(m.num_triangles(), 28);
        assert_eq!(
            format!("{walls:?}"),
            format!("{:?}", gmsh_walls_from_bytes(bytes).unwrap())
        );
        assert_eq!(walls.names[&8], "wall");
        assert_eq!(
            read_gmsh_sizes(&p).unwrap().1,
            gmsh_sizes_from_bytes(bytes).unwrap().1
        );
        let file = read_gmsh_sizes_file(&p).unwrap();
        assert_eq!((file.sizes.len(), file.view), (20, None));
    }

    /// A square of two triangles, its bottom a line in physical curve 7, as a binary 4.1 file
    /// in either byte order and with a `size_t` of 8 or 4 bytes.
    fn square_v4(big: bool, size_t: usize) -> Vec<u8> {
        let mut b = format!("$MeshFormat\n4.1 1 {size_t}\n").into_bytes();
        let int = |b: &mut Vec<u8>, v: i32| {
            b.extend(if big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            })
        };
        let size = |b: &mut Vec<u8>, v: u64| {
            let bytes = if big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            b.extend(if big {
                &bytes[8 - size_t..]
            } else {
                &bytes[..size_t]
            });
        };
        let double = |b: &mut Vec<u8>, v: f64| {
            b.extend(if big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            })
        };
        int(&mut b, 1);
        b.extend(b"\n$EndMeshFormat\n$Entities\n");
        for n in [0, 1, 1, 0] {
            size(&mut b, n);
        }
        // Curve 3 in physical 7, bounded by no points; surface 1 in physical 100.
        int(&mut b, 3);
        for v in [0.0, 0.0, 0.0, 1.0, 0.0, 0.0] {
            double(&mut b, v);
        }
        size(&mut b, 1);
        int(&mut b, 7);
        size(&mut b, 0);
        int(&mut b, 1);
        for v in [0.0, 0.0, 0.0, 1.0, 1.0, 0.0] {
            double(&mut b, v);
        }
        size(&mut b, 1);
        int(&mut b, 100);
        size(&mut b, 1);
        int(&mut b, 3);
        b.extend(b"\n$EndEntities\n$Nodes\n");
        for n in [1, 4, 1, 4] {
            size(&mut b, n);
        }
        for v in [2, 1, 0] {
            int(&mut b, v);
        }
        size(&mut b, 4);
        for tag in 1..=4 {
            size(&mut b, tag);
        }
        for v in [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0] {
            double(&mut b, v);
        }
        b.extend(b"\n$EndNodes\n$Elements\n");
        for n in [2, 3, 1, 3] {
            size(&mut b, n);
        }
        for v in [1, 3, 1] {
            int(&mut b, v);
        }
        size(&mut b, 1);
        for v in [1, 1, 2] {
            size(&mut b, v);
        }
        for v in [2, 1, 2] {
            int(&mut b, v);
        }
        size(&mut b, 2);
        for v in [2, 1, 2, 3, 3, 1, 3, 4] {
            size(&mut b, v);
        }
        b.extend(b"\n$EndElements\n");
        b
    }

    #[test]
    fn binary_files_read_in_either_byte_order_and_size() {
        let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 1 1 0\n\
                    3 0 0 0 1 0 0 1 7 0\n1 0 0 0 1 1 0 1 100 1 3\n$EndEntities\n\
                    $Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n\
                    $Elements\n2 3 1 3\n1 3 1 1\n1 1 2\n2 1 2 2\n2 1 2 3\n3 1 3 4\n$EndElements\n";
        let want = everything(&parse(text, Path::new("s.msh"), false).unwrap());
        assert!(want.contains("edges: [([0, 1], 7)]"), "{want}");
        for big in [false, true] {
            for size_t in [8, 4] {
                let bytes = square_v4(big, size_t);
                let got = parse_bytes(&bytes, Path::new("s.msh"), false).unwrap();
                assert_eq!(everything(&got), want, "big-endian {big}, size_t {size_t}");
            }
        }
    }

    #[test]
    fn bad_binary_files_name_the_fault_and_its_byte() {
        let good = square_v4(false, 8);
        let find = |b: &[u8], s: &str| b.windows(s.len()).position(|w| w == s.as_bytes()).unwrap();
        let err = |b: &[u8]| {
            parse_bytes(b, Path::new("b.msh"), false)
                .map(|_| ())
                .unwrap_err()
                .to_string()
        };
        let nodes = find(&good, "$Nodes\n") + 7;
        let elements = find(&good, "$Elements\n") + 10;
        let mut cases: Vec<(Vec<u8>, String)> = Vec::new();
        let mut with = |at: usize, bytes: &[u8], want: String| {
            let mut b = good.clone();
            b[at..at + bytes.len()].copy_from_slice(bytes);
            cases.push((b, want));
        };
        with(18, b"6", "binary data size 6 is not supported".into());
        with(
            20,
            &[2, 0, 0, 0],
            "byte 20: the binary int after the format line is [02, 00, 00, 00]".into(),
        );
        // The number of node blocks, and of the nodes of the first block (after 32 bytes of
        // counts and 12 of the block's ints).
        with(
            nodes,
            &u64::MAX.to_le_bytes(),
            format!(
                "byte {}: $Nodes gives 18446744073709551615 node blocks",
                nodes + 32
            ),
        );
        with(
            nodes + 44,
            &(1u64 << 40).to_le_bytes(),
            format!("byte {}: $Nodes gives 1099511627776 nodes", nodes + 52),
        );
        with(
            nodes + 40,
            &[2, 0, 0, 0],
            format!(
                "byte {}: a node block of dimension 2 has the parametric flag 2",
                nodes + 40
            ),
        );
        // The third node's z: the parser's error, at the byte its line came from.
        let z = nodes + 52 + 32 + 2 * 24 + 16;
        with(
            z,
            &0.5f64.to_le_bytes(),
            format!("byte {}: z = 0.5", z - 16),
        );
        // The first element block's type: 99 is none, 3 a quadrangle (the parser's).
        with(
            elements + 40,
            &[99, 0, 0, 0],
            format!("byte {}: element type 99 is not supported", elements + 40),
        );
        // A node that is not in $Nodes.
        with(
            elements + 52 + 8,
            &[9, 0, 0, 0],
            "refers to node 9, which is not in $Nodes".into(),
        );
        // One block fewer than the section holds: its bytes are where $EndElements should be.
        with(
            elements,
            &[1],
            format!(
                "byte {}: expected $EndElements after the binary data of $Elements",
                elements + 76
            ),
        );
        for (bytes, want) in cases {
            let e = err(&bytes);
            assert!(
                e.starts_with("b.msh: ") && e.contains(&want),
                "{e:?} should contain {want:?}"
            );
        }
        let e = err(&good[..good.len() - 20]);
        let want = format!(
            "byte {}: $Elements gives 2 elements of 32 bytes or more, but 58 bytes are left",
            good.len() - 78
        );
        assert!(e.contains(&want), "{e}");
        let e = err(&good[..elements + 20]);
        let want = format!(
            "byte {}: the file ends in $Elements, in the smallest element tag (8 bytes, 4 left)",
            elements + 16
        );
        assert!(e.contains(&want), "{e}");
        // A 2.2 file: an element block claiming more elements than the section.
        let mut v2 = fixture("meshio22_plain_binary").to_vec();
        let at = find(&v2, "$Elements\n4\n") + 12;
        v2[at + 4] = 5;
        assert!(err(&v2).contains(&format!(
            "byte {at}: a block of 5 elements, past the 4 the section gives"
        )));
        // A section that never ends.
        let open = [&good[..nodes], b"\x00\x01"].concat();
        let e = err(&[&good[..find(&good, "$Nodes")], b"$Periodic\n\x00\x01"].concat());
        assert!(e.contains("section $Periodic has no $EndPeriodic"), "{e}");
        assert!(err(&open).contains("the file ends in $Nodes"));
        // A binary section the reader skips: left out.
        let periodic = [
            &good[..find(&good, "$Nodes")],
            b"$Periodic\n\x07\xff\x00\n$EndPeriodic\n",
            &good[find(&good, "$Nodes")..],
        ]
        .concat();
        let p = parse_bytes(&periodic, Path::new("b.msh"), false).unwrap();
        assert_eq!(p.mesh.triangles.len(), 2);
    }

    #[test]
    fn every_truncation_of_a_binary_file_is_an_error() {
        // Each has a mesh and a view: no cut before the view's end leaves a file to read.
        for name in [
            "gmsh41_sizes_binary",
            "gmsh22_sizes_binary",
            "meshio41_sizes_binary",
            "meshio22_sizes_binary",
        ] {
            let bytes = fixture(name);
            let last = bytes.len() - b"$EndNodeData\n".len();
            assert_eq!(&bytes[last..], b"$EndNodeData\n");
            for n in 0..=last {
                let cut = sizes_from(&bytes[..n], Path::new("t.msh"));
                assert!(cut.is_err(), "{name} cut at {n} of {} read", bytes.len());
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn random_bytes_never_panic(bytes in proptest::collection::vec(proptest::num::u8::ANY, 0..300)) {
            let _ = parse(&String::from_utf8_lossy(&bytes), Path::new("r.msh"), false).map(|r| r.mesh);
        }

        #[test]
        fn corrupted_binary_files_never_panic(
            which in 0..4usize,
            flips in proptest::collection::vec((proptest::num::usize::ANY, 1..=255u8), 1..6),
            cut in proptest::num::usize::ANY,
        ) {
            let names = ["gmsh41_sizes", "gmsh22_sizes", "meshio41_physical", "meshio22_physical"];
            let mut bytes = fixture(&format!("{}_binary", names[which])).to_vec();
            for (at, x) in flips {
                let n = bytes.len();
                bytes[at % n] ^= x;
            }
            bytes.truncate(cut % (bytes.len() + 1) + bytes.len() / 2);
            for sizes in [false, true] {
                let _ = parse_bytes(&bytes, Path::new("r.msh"), sizes).map(|r| r.mesh);
            }
        }

        #[test]
        fn random_numbers_after_a_valid_header_never_panic(body in "[0-9 \n.$a-zA-Z-]{0,200}") {
            let _ = parse(&format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n{body}"), Path::new("r.msh"), false).map(|r| r.mesh);
            let _ = parse(&format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Elements\n{body}"), Path::new("r.msh"), false).map(|r| r.mesh);
            let _ = parse(&format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n{body}"), Path::new("r.msh"), false).map(|r| r.mesh);
            let _ = sizes_from(format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$NodeData\n{body}").as_bytes(), Path::new("r.msh"));
        }
    }

    /// A square of two triangles (nodes tagged 10, 20, 30, 40) and a `$NodeData` body.
    fn with_node_data(version: &str, data: &str) -> String {
        let mesh = if version == "2.2" {
            "$Nodes\n4\n10 0 0 0\n20 1 0 0\n30 1 1 0\n40 0 1 0\n$EndNodes\n\
             $Elements\n2\n1 2 0 10 20 30\n2 2 0 10 30 40\n$EndElements\n"
        } else {
            "$Nodes\n1 4 10 40\n2 1 0 4\n10\n20\n30\n40\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n\
             $Elements\n1 2 1 2\n2 1 2 2\n1 10 20 30\n2 10 30 40\n$EndElements\n"
        };
        format!("$MeshFormat\n{version} 0 8\n$EndMeshFormat\n{mesh}$NodeData\n{data}$EndNodeData\n")
    }

    #[test]
    fn sizes_come_from_the_first_node_data_view_in_node_order() {
        // Gmsh 4.1 writes a fourth integer tag (the partition); values in any order.
        let data = "1\n\"size\"\n1\n0\n4\n0\n1\n4\n0\n30 0.3\n10 0.1\n40 0.4\n20 0.2\n";
        for version in ["2.2", "4.1"] {
            let text = with_node_data(version, data)
                + "$NodeData\n1\n\"other\"\n1\n0\n3\n0\n1\n1\n10 9\n$EndNodeData\n";
            let (m, h) = sizes_from(text.as_bytes(), Path::new("bg.msh")).unwrap();
            assert_eq!(m.num_triangles(), 2, "{version}");
            assert_eq!(h, [0.1, 0.2, 0.3, 0.4], "{version}");
            // The mesh reader alone still skips the view.
            assert_eq!(
                parse(&text, Path::new("bg.msh"), false).unwrap().sizes,
                None
            );
        }
    }

    /// meshio 5.3 under NumPy 2 writes `$NodeData` values as `np.float64(0.25)`: read as the
    /// numbers they hold, as in the file meshio meant to write.
    #[test]
    fn numpy_scalar_reprs_in_node_data_are_their_numbers() {
        let data = "1\n\"size\"\n1\n0\n4\n0\n1\n4\n0\n30 0.3\n10 0.1\n40 0.4\n20 0.2\n";
        let plain = with_node_data("4.1", data);
        let repr = plain
            .replace("10 0.1\n", "10 np.float64(0.1)\n")
            .replace("20 0.2\n", "20 np.float64(0.2)\n");
        assert_ne!(plain, repr);
        let (m1, h1) = gmsh_sizes_from_str(&repr).unwrap();
        let (m2, h2) = gmsh_sizes_from_str(&plain).unwrap();
        assert_eq!((m1.points, m1.triangles, h1), (m2.points, m2.triangles, h2));
        let bad = plain.replace("10 0.1\n", "10 np.float64(x)\n");
        assert!(gmsh_sizes_from_str(&bad)
            .unwrap_err()
            .to_string()
            .contains("np.float64(x)"));
    }

    #[test]
    fn bad_node_data_is_refused_naming_the_problem() {
        let view = |values: &str, components: u32, count: u32| {
            format!("1\n\"h\"\n1\n0\n3\n0\n{components}\n{count}\n{values}")
        };
        let cases = [
            (view("10 1\n20 1\n30 1\n", 1, 3), "no value for node 40"),
            (
                view("10 1\n20 1\n30 1\n40 1\n50 1\n", 1, 5),
                "node 50, which is not in $Nodes",
            ),
            (view("10 1\n20 1\n30 1\n10 2\n", 1, 4), "node 10 two values"),
            (view("10 1 0 0\n", 3, 1), "3 components per node"),
            (view("10 x\n", 1, 1), "expected a node value"),
            (
                view("10 1\n20 -1\n30 1\n40 1\n", 1, 4),
                "node 20 the size -1",
            ),
            ("1\n\"h\"\n0\n1\n0\n".to_string(), "1 integer tags"),
            (
                "999999999999\n\"h\"\n".to_string(),
                "end of file in $NodeData's string tags",
            ),
        ];
        for (data, want) in cases {
            let e = sizes_from(with_node_data("2.2", &data).as_bytes(), Path::new("bg.msh"))
                .unwrap_err();
            assert!(e.to_string().contains(want), "{e} should contain {want:?}");
        }
        let no_view = with_node_data("2.2", "").replace("$NodeData\n$EndNodeData\n", "");
        let e = sizes_from(no_view.as_bytes(), Path::new("bg.msh")).unwrap_err();
        assert!(e.to_string().contains("no $NodeData section"), "{e}");
    }
}
