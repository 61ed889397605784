//! Region input formats besides the project JSON: Triangle .poly, GeoJSON, plain loop lists,
//! and [`Region::from_file`], which reads any of them and the project JSON.
//!
//! Every format gives straight-edged loops; each edge becomes a [`Piece::Line`] (edges that
//! meet where the boundary goes straight on join into one) and every vertex where the boundary
//! turns (by more than 1e-9 rad) is a corner, so a polygon keeps all of its vertices as
//! corners, as Triangle users expect ([`Region::with_default_corners`]
//! keeps only the real turns, as the command line and the Python package do by default).
//! Loops may come in either orientation (they are oriented here: outer CCW, holes CW); a
//! closing copy of a loop's first point is dropped, any other repeated consecutive point is
//! refused with its position (a zero-length edge the user should see).
//!
//! A file may hold several disjoint parts. GeoJSON says which ring is a hole; a loop list and
//! a `.poly` do not, so nesting decides: a loop inside no other loop is an outer loop, a loop
//! inside an outer loop is one of its holes, and a loop inside a hole is an island, a part of
//! its own.
use crate::build::new_region;
use crate::error::GeometryError;
use crate::piece::Piece;
use crate::predicates::{point_in_ring, ring_signed_area, segment_distance};
use crate::region::Region;
use crate::types::LoopRole;
use glam::DVec2;
use serde_json::Value;
use std::collections::HashMap;
use std::path::Path;

/// Extensions [`Region::from_file`] reads by their format (any other is read as JSON if
/// the file holds a JSON object).
pub const REGION_EXTENSIONS: &[&str] = &["json", "geojson", "poly", "txt", "xy", "dat"];

/// Smallest turning angle (radians) that makes a polygon vertex a corner.
const CORNER_TURN: f64 = 1e-9;

/// GeoJSON object types that hold (or wrap) polygons.
const GEOJSON_TYPES: &[&str] = &[
    "Polygon",
    "MultiPolygon",
    "Feature",
    "FeatureCollection",
    "GeometryCollection",
];

impl Region {
    /// A polygonal region from its loops' vertices: `(LoopRole::Outer, points)` and
    /// `(LoopRole::Hole, points)`, each loop listed once around (either direction; a closing
    /// copy of the first point is dropped); several outer loops make several parts. Every
    /// vertex where the boundary turns is a corner ([`Region::with_corner_angle`] and
    /// [`Region::with_default_corners`] keep fewer). The checks of [`Region::new`] apply:
    /// finite points, no repeated vertex, simple loops that do not cross, roles that agree
    /// with nesting.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, LoopRole, Region};
    /// let square = vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)];
    /// let hole: Vec<DVec2> = square.iter().map(|&p| 0.4 + 0.2 * p).collect();
    /// let r = Region::from_loops("frame", vec![(LoopRole::Outer, square), (LoopRole::Hole, hole)])?;
    /// assert!((r.area() - 0.96).abs() < 1e-12);
    /// assert_eq!(r.corners().len(), 8);
    /// assert!(!r.contains(DVec2::new(0.5, 0.5)));
    /// // A bow tie is refused, with the crossing named.
    /// let bow = vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)];
    /// assert!(Region::from_loops("bow", vec![(LoopRole::Outer, bow)]).is_err());
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn from_loops(
        name: &str,
        loops: Vec<(LoopRole, Vec<DVec2>)>,
    ) -> Result<Region, GeometryError> {
        let loops = loops.into_iter().map(|(r, p)| (Some(r), p)).collect();
        polygon_region(name, name, loops)
    }

    /// [`Region::from_loops`] with its walls numbered as a `.poly`'s segment markers number
    /// them: each loop's `markers` give the marker of each of its edges (edge `i` runs from
    /// point `i` to the next), which become the pieces' markers
    /// ([`Region::piece_markers`]); a vertex where the marker changes is a corner, so a mesh
    /// has a vertex there and no mesh edge lies on two walls. One marker per point of its loop
    /// (after a closing copy of the first point is dropped), within Triangle's and Gmsh's
    /// 32-bit range.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, LoopRole, Region};
    /// // A channel: inlet 1 on the left, walls 2, outlet 3 on the right, the bottom wall split
    /// // at x = 1 where a heated stretch 4 begins.
    /// let pts = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)].map(|(x, y)| DVec2::new(x, y));
    /// let r = Region::from_loops_marked("channel", vec![(LoopRole::Outer, pts.to_vec(), vec![2, 4, 3, 2, 1])])?;
    /// assert_eq!(r.piece_markers(), Some(&[2, 4, 3, 2, 1][..]));
    /// // The straight bottom side turns at no vertex, yet (1, 0) is a corner: the marker changes.
    /// assert!(r.corners().iter().any(|c| c.pos == DVec2::X));
    /// let e = Region::from_loops_marked("short", vec![(LoopRole::Outer, pts.to_vec(), vec![1, 2])]).unwrap_err();
    /// assert!(e.to_string().contains("2 markers for its 5 edges"), "{e}");
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn from_loops_marked(
        name: &str,
        loops: Vec<(LoopRole, Vec<DVec2>, Vec<i64>)>,
    ) -> Result<Region, GeometryError> {
        let mut markers = SegmentMarkers::new();
        let mut rings = Vec::with_capacity(loops.len());
        for (l, (role, mut pts, marks)) in loops.into_iter().enumerate() {
            if pts.len() > 1 && pts.first() == pts.last() {
                pts.pop();
            }
            if marks.len() != pts.len() {
                return Err(GeometryError::Invalid {
                    region: name.to_string(),
                    message: format!(
                        "loop {l} has {} markers for its {} edges (one per edge, edge i from \
                         point i to the next)",
                        marks.len(),
                        pts.len()
                    ),
                });
            }
            let n = pts.len();
            for (i, &m) in marks.iter().enumerate() {
                markers.insert(segment_key(pts[i], pts[(i + 1) % n]), m);
            }
            rings.push((Some(role), pts));
        }
        marked_polygon_region(name, name, rings, Some(markers), &VertexMarkers::new())
    }

    /// Read a region file in any supported format, chosen by the extension (case-insensitive):
    ///
    /// | extension | format |
    /// | --- | --- |
    /// | `.json` | the project's JSON schema (that of the built-in regions, see `regions/SOURCES.md` in this crate), or GeoJSON when its top-level `"type"` is a GeoJSON polygon type |
    /// | `.geojson` | GeoJSON ([`read_geojson`](crate::formats::read_geojson)) |
    /// | `.poly` | Triangle's `.poly` ([`read_poly`](crate::formats::read_poly)) |
    /// | `.txt`, `.xy`, `.dat` | a plain loop list ([`read_loops`](crate::formats::read_loops)) |
    ///
    /// A file with another extension (or none) is read as JSON if its content is a JSON
    /// object, otherwise the error lists the supported extensions. The region is named after
    /// the file stem unless the file names it. Only the project schema describes curved
    /// pieces; the other formats give straight edges, every turning vertex a corner.
    ///
    /// ```
    /// use cvtmesh::geometry::Region;
    /// let dir = std::env::temp_dir().join(format!("cvtmesh-doc-from-file-{}", std::process::id()));
    /// std::fs::create_dir_all(&dir)?;
    /// // A Triangle .poly: a 4 × 2 rectangle (four vertices, four segments, no holes).
    /// let poly = dir.join("rect.poly");
    /// std::fs::write(&poly, "4 2 0 0\n1 0 0\n2 4 0\n3 4 2\n4 0 2\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")?;
    /// let r = Region::from_file(&poly)?;
    /// assert_eq!(r.name(), "rect");
    /// assert_eq!(r.area(), 8.0);
    /// assert_eq!(r.corners().len(), 4);
    /// // The same rectangle with a 1 × 1 square hole as a plain loop list.
    /// let loops = dir.join("rect.xy");
    /// std::fs::write(&loops, "0 0\n4 0\n4 2\n0 2\n\n1 0.5\n2 0.5\n2 1.5\n1 1.5\n")?;
    /// let r = Region::from_file(&loops)?;
    /// assert_eq!((r.loops().len(), r.area()), (2, 7.0));
    /// assert!(r.contains(cvtmesh::geometry::DVec2::new(3.0, 1.0)));
    /// assert!(!r.contains(cvtmesh::geometry::DVec2::new(1.5, 1.0)));
    /// std::fs::remove_dir_all(&dir)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_file(path: &Path) -> Result<Region, GeometryError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("json") => json_region(&read_text(path)?, path),
            Some("geojson") => read_geojson(path),
            Some("poly") => read_poly(path),
            Some("txt") | Some("xy") | Some("dat") => read_loops(path),
            _ => match read_text(path) {
                Ok(text) if serde_json::from_str::<Value>(&text).is_ok_and(|v| v.is_object()) => {
                    json_region(&text, path)
                }
                _ => Err(GeometryError::UnknownFormat {
                    path: label(path),
                    extension: ext,
                }),
            },
        }
    }
}

/// Read a region file in any supported format: the same as [`Region::from_file`], which
/// documents the formats.
pub fn read_region(path: &Path) -> Result<Region, GeometryError> {
    Region::from_file(path)
}

/// JSON text of the file `path`: GeoJSON or the project schema.
fn json_region(text: &str, path: &Path) -> Result<Region, GeometryError> {
    if is_geojson(text) {
        geojson_from_str(text, &label(path), &stem(path))
    } else {
        crate::file::parse(text, &label(path), &stem(path))
    }
}

/// Read a Triangle `.poly` file (vertices, segments, holes). A `.poly` whose vertex count is
/// 0 takes its vertices from the `.node` file beside it, as Triangle does.
pub fn read_poly(path: &Path) -> Result<Region, GeometryError> {
    let text = read_text(path)?;
    let node_path = path.with_extension("node");
    let poly = parse_poly(&text, &label(path), &mut || {
        Ok((read_text(&node_path)?, label(&node_path)))
    })?;
    poly_region(&stem(path), &label(path), poly)
}

/// Parse `.poly` text (`label` names it in errors, `name` is the region's name). The vertices
/// must be in the text itself.
pub fn poly_from_str(text: &str, label: &str, name: &str) -> Result<Region, GeometryError> {
    let poly = parse_poly(text, label, &mut || {
        Err(GeometryError::Parse {
            path: label.to_string(),
            message: "the vertex count is 0, so the vertices are in a separate .node file; \
                      read the .poly through its path"
                .into(),
        })
    })?;
    poly_region(name, label, poly)
}

/// [`polygon_region`] with each piece's marker from `markers` (0 where it has none), and a
/// corner wherever the marker changes along a loop, so that no mesh edge lies on two walls.
/// A vertex of `vertex_markers` whose marker differs from both its segments' (1 for both
/// where the segments have none, the marker Triangle gives an unmarked boundary) is a corner
/// with that marker ([`Region::vertex_markers`]); where the segments have no markers, such a
/// vertex gives every piece the marker 1.
pub(crate) fn marked_polygon_region(
    name: &str,
    label: &str,
    loops: Loops,
    mut markers: Option<SegmentMarkers>,
    vertex_markers: &VertexMarkers,
) -> Result<Region, GeometryError> {
    // Triangle's markers and Gmsh's physical tags are 32-bit integers: a wider number could
    // not be written as one.
    // The smallest such number is named, whatever order the maps list them in.
    let wide = markers
        .iter()
        .flat_map(|m| m.values())
        .chain(vertex_markers.values())
        .filter(|&&m| i32::try_from(m).is_err())
        .min();
    if let Some(m) = wide {
        return Err(invalid(
            label,
            format!(
                "marker {m} is outside the 32-bit range of Triangle's markers and Gmsh's \
                 physical tags"
            ),
        ));
    }
    let segment = |m: &Option<SegmentMarkers>, a: DVec2, b: DVec2| match m {
        Some(m) => m.get(&segment_key(a, b)).copied(),
        None => Some(1),
    };
    let mut pinned: Vec<(DVec2, i64)> = Vec::new();
    for (_, pts) in &loops {
        let n = pts.len();
        // One marker on every vertex of a loop flags the loop as boundary (meshpy's
        // `point_markers` of 1, say), not each vertex as a point.
        let first = vertex_markers.get(&key(pts[0]));
        if first.is_some() && pts.iter().all(|p| vertex_markers.get(&key(*p)) == first) {
            continue;
        }
        for i in 0..n {
            let (prev, p, next) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
            if let Some(&v) = vertex_markers.get(&key(p)) {
                let own = Some(v);
                if own != segment(&markers, prev, p) && own != segment(&markers, p, next) {
                    pinned.push((p, v));
                }
            }
        }
    }
    if markers.is_none() && !pinned.is_empty() {
        markers = Some(
            loops
                .iter()
                .flat_map(|(_, pts)| {
                    let n = pts.len();
                    (0..n).map(move |i| (segment_key(pts[i], pts[(i + 1) % n]), 1))
                })
                .collect(),
        );
    }
    let mut changes: Vec<DVec2> = match &markers {
        Some(m) => loops
            .iter()
            .flat_map(|(_, pts)| {
                let n = pts.len();
                (0..n).filter_map(move |i| {
                    let (prev, p, next) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
                    (m.get(&segment_key(prev, p)) != m.get(&segment_key(p, next))).then_some(p)
                })
            })
            .collect(),
        None => Vec::new(),
    };
    changes.extend(pinned.iter().map(|&(p, _)| p));
    let mut region = polygon_region_with(name, label, loops, &changes)?;
    pinned.sort_by_key(|&(p, _)| key(p));
    pinned.dedup_by_key(|(p, _)| key(*p));
    region.vertex_markers = pinned;
    if let Some(m) = markers {
        // A piece is one segment or a straight run of them, all with one marker (a change is
        // a corner): the marker of the segment that leaves its start along it. 0 (Triangle's
        // "no marker") where that segment has none.
        // In the segments' sorted order, not the map's: of two segments leaving a vertex in
        // the same direction (an overlap), the same one gives its marker every run.
        let mut sorted: Vec<(&(Key, Key), &i64)> = m.iter().collect();
        sorted.sort_unstable();
        let mut leaving: HashMap<Key, Vec<(DVec2, i64)>> = HashMap::new();
        for (&(a, b), &marker) in sorted {
            let (pa, pb) = (from_key(a), from_key(b));
            leaving.entry(a).or_default().push((pb, marker));
            leaving.entry(b).or_default().push((pa, marker));
        }
        region.markers = region
            .pieces
            .iter()
            .map(|p| {
                let (a, b) = (p.start(), p.end());
                let along = (b - a).normalize_or_zero();
                leaving.get(&key(a)).map_or(0, |out| {
                    out.iter()
                        .max_by(|x, y| {
                            let d = |q: DVec2| (q - a).normalize_or_zero().dot(along);
                            d(x.0).total_cmp(&d(y.0))
                        })
                        .map_or(0, |&(_, marker)| marker)
                })
            })
            .collect();
    }
    Ok(region)
}

/// The region of a `.poly`'s loops, nesting deciding the roles, checked against its hole
/// points as Triangle would use them: every hole loop must hold a hole point (else Triangle
/// meshes its inside, an internal boundary a region cannot express), and no hole point may
/// lie in a part that is meshed (Triangle would eat that part). Segment markers become the
/// pieces' markers, and every vertex where the marker changes a corner (a mesh vertex), so that
/// no mesh edge straddles two walls.
fn poly_region(name: &str, label: &str, mut poly: Poly) -> Result<Region, GeometryError> {
    let build = |poly: &Poly| {
        marked_polygon_region(
            name,
            label,
            poly.loops.clone(),
            poly.segment_markers.clone(),
            &poly.vertex_markers,
        )
    };
    // Only a file with vertices on no segment can need a second build: the others hand their
    // loops over.
    let mut region = if poly.embedded.is_empty() {
        marked_polygon_region(
            name,
            label,
            std::mem::take(&mut poly.loops),
            poly.segment_markers.take(),
            &poly.vertex_markers,
        )?
    } else {
        build(&poly)?
    };
    let off = 1e-9 * region.diameter();
    // A vertex on no segment's ends that lies on one splits it, as Triangle splits a segment
    // through a vertex: with a marker of its own it is then a corner that keeps it.
    let on_boundary: Vec<DVec2> = poly
        .embedded
        .iter()
        .map(|&(p, _)| p)
        .filter(|&p| region.signed_distance(p).abs() <= off)
        .collect();
    if !on_boundary.is_empty() {
        for p in on_boundary {
            split_segment_at(&mut poly, p, off);
        }
        region = build(&poly)?;
    }
    // One outside Ω or in a hole is in no triangle of Triangle's mesh either (the triangles
    // there are eaten): not kept.
    let inside: Vec<(DVec2, i64)> = poly
        .embedded
        .iter()
        .copied()
        .filter(|&(p, _)| region.signed_distance(p) < -off)
        .collect();
    // Segments in a hole or outside are in no triangle of Triangle's mesh, and one leaving
    // the region keeps its part inside: cut at the boundary.
    let given: f64 = poly.lines.iter().map(|l| l.length()).sum();
    let (lines, cut) = region.cut_lines(std::mem::take(&mut poly.lines));
    let kept: f64 = lines.iter().map(|l| l.length()).sum();
    let mut region = region
        .with_embedded_points(inside)?
        .with_embedded_lines(lines)?;
    if cut > 0 {
        region.notes.push(format!(
            "{label}: {cut} segment{} in a hole or outside the region, wholly or in part ({:.6} \
             of the {:.6} total length of the segments inside), {} in no triangle there, as \
             Triangle eats {}: only the parts inside are kept",
            if cut == 1 { "" } else { "s" },
            given - kept,
            given,
            if cut == 1 { "is" } else { "are" },
            if cut == 1 { "it" } else { "them" },
        ));
    }
    // A regional attribute in a hole or outside numbers no triangle in Triangle either.
    let (kept, lost): (Vec<_>, Vec<_>) = poly
        .subdomains
        .iter()
        .partition(|&&(p, _)| region.signed_distance(p) < -off);
    region = region.with_subdomain_points(kept)?;
    if !lost.is_empty() {
        region.notes.push(format!(
            "{label}: {} regional attribute{} in a hole or outside the region, in no \
             triangle: not used",
            lost.len(),
            if lost.len() == 1 { " lies" } else { "s lie" }
        ));
    }
    if poly.area_constraints > 0 {
        region.notes.push(format!(
            "{label}: its {} area {} not used: cvtmesh takes sizes from a size field (an area \
             bound A is an edge length of about √(4A/√3): size, --size; size_field, \
             --size-field for sizes that vary)",
            poly.area_constraints,
            if poly.area_constraints == 1 {
                "constraint is"
            } else {
                "constraints are"
            }
        ));
    }
    let holes = &poly.holes;
    for &(line, h) in holes {
        if region.contains(h) {
            return Err(parse_err(
                label,
                line,
                format!("hole point {h} lies in the region, not inside any hole loop"),
            ));
        }
    }
    let poly = region.polygonize(0.0);
    for ring in poly.rings.iter().filter(|r| r.hole) {
        if !holes.iter().any(|&(_, h)| point_in_ring(h, &ring.points)) {
            return Err(invalid(
                label,
                format!(
                    "the inner loop through {} has no hole point: internal boundaries are not supported (add a hole point inside it if it is a hole)",
                    ring.points[0]
                ),
            ));
        }
    }
    Ok(region)
}

/// Read a GeoJSON file: a Polygon, MultiPolygon, Feature, FeatureCollection or
/// GeometryCollection. Every polygon it holds is a part of the region (the first ring of each
/// its outer boundary, the rest its holes); polygons must not overlap.
pub fn read_geojson(path: &Path) -> Result<Region, GeometryError> {
    geojson_from_str(&read_text(path)?, &label(path), &stem(path))
}

/// Parse GeoJSON text (see [`read_geojson`]).
pub fn geojson_from_str(text: &str, label: &str, name: &str) -> Result<Region, GeometryError> {
    let loops = parse_geojson(text, label)?;
    polygon_region(name, label, loops)
}

/// Read a plain loop list: one `x y` (or `x, y`) per line, loops separated by blank lines,
/// `#` comments. Nesting decides the roles: a loop inside no other loop (or inside a hole) is
/// an outer loop, one inside an outer loop is a hole of it. A loop may repeat its first point
/// at the end.
pub fn read_loops(path: &Path) -> Result<Region, GeometryError> {
    loops_from_str(&read_text(path)?, &label(path), &stem(path))
}

/// Parse a plain loop list (see [`read_loops`]).
pub fn loops_from_str(text: &str, label: &str, name: &str) -> Result<Region, GeometryError> {
    let loops = parse_loops(text, label)?;
    polygon_region(name, label, loops)
}

/// Loops with their roles, or `None` where nesting decides.
pub(crate) type Loops = Vec<(Option<LoopRole>, Vec<DVec2>)>;

/// Rings whose roles nesting decides.
fn by_nesting(rings: Vec<Vec<DVec2>>) -> Loops {
    rings.into_iter().map(|r| (None, r)).collect()
}

fn label(path: &Path) -> String {
    path.display().to_string()
}

fn stem(path: &Path) -> String {
    path.file_stem().map_or_else(
        || "region".to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

fn read_text(path: &Path) -> Result<String, GeometryError> {
    let bytes = std::fs::read(path).map_err(|source| GeometryError::Io {
        path: label(path),
        source,
    })?;
    let mut text = String::from_utf8(bytes).map_err(|e| GeometryError::Parse {
        path: label(path),
        message: format!(
            "not a text file (invalid UTF-8 at byte {})",
            e.utf8_error().valid_up_to()
        ),
    })?;
    // Editors on Windows start UTF-8 files with a byte-order mark, which no format here has.
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}

fn parse_err(label: &str, line: usize, message: impl std::fmt::Display) -> GeometryError {
    GeometryError::Parse {
        path: label.to_string(),
        message: format!("line {line}: {message}"),
    }
}

fn invalid(label: &str, message: impl Into<String>) -> GeometryError {
    GeometryError::Invalid {
        region: label.to_string(),
        message: message.into(),
    }
}

fn is_geojson(text: &str) -> bool {
    serde_json::from_str::<Value>(text)
        .ok()
        .and_then(|v| {
            v.get("type")
                .and_then(Value::as_str)
                .map(|t| GEOJSON_TYPES.contains(&t))
        })
        .unwrap_or(false)
}

/// Drop a closing copy of the first point (GeoJSON rings repeat it); any other repeated
/// consecutive vertex is a zero-length edge, which users want reported, not silently mended.
fn dedup_closed(points: &mut Vec<DVec2>) -> Result<(), DVec2> {
    if points.len() > 1 && points.first() == points.last() {
        points.pop();
    }
    match points.windows(2).find(|w| w[0] == w[1]) {
        Some(w) => Err(w[0]),
        None => Ok(()),
    }
}

/// Build the region from straight loops: check sizes, orient, make line pieces and corners.
/// Geometric validity (simple, non-crossing, holes inside) is [`Region::new`]'s to check.
pub(crate) fn polygon_region(
    name: &str,
    label: &str,
    loops: Loops,
) -> Result<Region, GeometryError> {
    polygon_region_with(name, label, loops, &[])
}

/// [`polygon_region`] with the vertices at `corners` corners too, however little the boundary
/// turns there.
fn polygon_region_with(
    name: &str,
    label: &str,
    loops: Loops,
    corners_too: &[DVec2],
) -> Result<Region, GeometryError> {
    let corners_too: std::collections::HashSet<Key> = corners_too.iter().map(|&p| key(p)).collect();
    let mut out = Vec::with_capacity(loops.len());
    let mut corners = Vec::new();
    for (k, (role, mut pts)) in loops.into_iter().enumerate() {
        if let Some(p) = pts.iter().find(|p| !p.is_finite()) {
            return Err(invalid(
                label,
                format!("loop {k} has a non-finite point {p}"),
            ));
        }
        if let Err(p) = dedup_closed(&mut pts) {
            return Err(invalid(
                label,
                format!(
                    "loop {k} has duplicate consecutive vertices at ({}, {})",
                    p.x, p.y
                ),
            ));
        }
        if pts.len() < 3 {
            return Err(invalid(
                label,
                format!(
                    "loop {k} has {} distinct points; a loop needs at least 3",
                    pts.len()
                ),
            ));
        }
        let area = ring_signed_area(&pts);
        if area == 0.0 || !area.is_finite() {
            // A symmetric figure-eight has zero area too: report its crossing if it has one.
            let pieces = (0..pts.len())
                .map(|i| Piece::Line {
                    a: pts[i],
                    b: pts[(i + 1) % pts.len()],
                })
                .collect();
            if let Err(GeometryError::Invalid { message, .. }) =
                Region::new(name, vec![(LoopRole::Outer, pieces)], None)
            {
                return Err(invalid(label, message));
            }
            return Err(invalid(label, format!("loop {k} encloses no area")));
        }
        if role.is_some_and(|r| (area > 0.0) != (r == LoopRole::Outer)) {
            pts.reverse();
        }
        // A vertex where the boundary goes straight on (a straight wall drawn, or meshed,
        // in several segments) joins its two segments into one piece: a piece per segment
        // would end at points no corner holds. One of `corners_too` stays, as a corner.
        let turns = |i: usize, pts: &[DVec2]| {
            let n = pts.len();
            let (u, v) = (pts[i] - pts[(i + n - 1) % n], pts[(i + 1) % n] - pts[i]);
            u.perp_dot(v).atan2(u.dot(v)).abs() > CORNER_TURN
        };
        let kept: Vec<bool> = (0..pts.len())
            .map(|i| turns(i, &pts) || corners_too.contains(&key(pts[i])))
            .collect();
        if kept.iter().filter(|&&k| k).count() >= 3 {
            let mut k = kept.iter();
            pts.retain(|_| *k.next().expect("one flag per point"));
        }
        let n = pts.len();
        for i in 0..n {
            if turns(i, &pts) || corners_too.contains(&key(pts[i])) {
                corners.push(pts[i]);
            }
        }
        let pieces = (0..n)
            .map(|i| Piece::Line {
                a: pts[i],
                b: pts[(i + 1) % n],
            })
            .collect();
        out.push((role, pieces));
    }
    let mut region = new_region(name, out, Some(corners)).map_err(|e| match e {
        // Name the file, not just the region, so that the user knows what to fix.
        GeometryError::Invalid { message, .. } => invalid(label, message),
        e => e,
    })?;
    region.corners_computed = true;
    Ok(region)
}

/// Non-empty lines with `#` comments removed, with 1-based line numbers.
fn records(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.split('#').next().unwrap_or("");
        let toks: Vec<&str> = l.split_whitespace().collect();
        (!toks.is_empty()).then_some((i + 1, toks))
    })
}

fn num<T: std::str::FromStr>(
    label: &str,
    line: usize,
    tok: Option<&&str>,
    what: &str,
) -> Result<T, GeometryError> {
    let tok = tok.ok_or_else(|| parse_err(label, line, format!("missing {what}")))?;
    tok.parse()
        .map_err(|_| parse_err(label, line, format!("expected {what}, found '{tok}'")))
}

fn coord(label: &str, line: usize, tok: Option<&&str>, axis: &str) -> Result<f64, GeometryError> {
    let v: f64 = num(label, line, tok, &format!("a number for {axis}"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(parse_err(label, line, format!("{axis} is not finite")))
    }
}

/// Vertex list of a `.poly` or `.node` section: points, the index base (0 or 1), and each
/// vertex's marker (0 where the section has none) from the column `marker_column`.
fn parse_vertices<'a>(
    recs: &mut impl Iterator<Item = (usize, Vec<&'a str>)>,
    label: &str,
    (n, marker_column): (usize, Option<usize>),
    last_line: usize,
) -> Result<(Vec<DVec2>, usize, Vec<i64>), GeometryError> {
    let mut pts = Vec::with_capacity(n.min(1 << 16));
    let mut markers = Vec::with_capacity(n.min(1 << 16));
    let mut base = 0;
    for i in 0..n {
        let (line, t) = recs.next().ok_or_else(|| {
            parse_err(
                label,
                last_line,
                format!("file ends after {i} of {n} vertices"),
            )
        })?;
        let idx: usize = num(label, line, t.first(), "a vertex number")?;
        if i == 0 {
            if idx > 1 {
                return Err(parse_err(
                    label,
                    line,
                    format!("first vertex is numbered {idx}; Triangle numbers from 0 or 1"),
                ));
            }
            base = idx;
        } else if idx != base + i {
            return Err(parse_err(
                label,
                line,
                format!("vertex number {idx}, expected {}", base + i),
            ));
        }
        pts.push(DVec2::new(
            coord(label, line, t.get(1), "x")?,
            coord(label, line, t.get(2), "y")?,
        ));
        // A missing marker is 0, as Triangle reads it.
        markers.push(match marker_column.and_then(|c| t.get(c).map(|_| c)) {
            Some(c) => num(label, line, t.get(c), "a vertex marker")?,
            None => 0,
        });
    }
    Ok((pts, base, markers))
}

/// The header `n dim nattr nmarkers` of a vertex section: the vertex count and the column of
/// the vertices' markers, if they have one (after x, y and the attributes).
fn vertex_header(
    label: &str,
    line: usize,
    t: &[&str],
) -> Result<(usize, Option<usize>), GeometryError> {
    let n: usize = num(label, line, t.first(), "the number of vertices")?;
    if let Some(d) = t.get(1) {
        if *d != "2" {
            return Err(parse_err(
                label,
                line,
                format!("dimension is {d}; only 2 is supported"),
            ));
        }
    }
    let nattr: usize = match t.get(2) {
        Some(_) => num(label, line, t.get(2), "the number of vertex attributes")?,
        None => 0,
    };
    let nmarkers: usize = match t.get(3) {
        Some(_) => num(
            label,
            line,
            t.get(3),
            "the number of vertex markers (0 or 1)",
        )?,
        None => 0,
    };
    if nmarkers > 1 {
        return Err(parse_err(
            label,
            line,
            format!("{nmarkers} vertex-marker columns; Triangle allows 0 or 1"),
        ));
    }
    Ok((n, (nmarkers == 1).then(|| nattr.saturating_add(3))))
}

type NodeSource<'a> = dyn FnMut() -> Result<(String, String), GeometryError> + 'a;

/// Hole points of a `.poly`, with their line numbers.
type HolePoints = Vec<(usize, DVec2)>;

/// What a `.poly` says: its loops, hole points, segment markers (if it has a column for them)
/// and nonzero vertex markers.
#[derive(Debug)]
struct Poly {
    loops: Loops,
    holes: HolePoints,
    segment_markers: Option<SegmentMarkers>,
    vertex_markers: VertexMarkers,
    /// The `.poly`'s own vertices on no segment, with their markers: points to keep inside.
    embedded: Vec<(DVec2, i64)>,
    /// The regional attributes' points and numbers.
    subdomains: Vec<(DVec2, i64)>,
    /// How many regions have a positive area constraint.
    area_constraints: usize,
    /// Segments that bound no loop (with the region on both sides, on neither, or crossing
    /// the boundary), joined into polylines: the region keeps their parts inside.
    lines: Vec<crate::EmbeddedLine>,
}

/// A `.poly`'s nonzero vertex markers, by the vertex's coordinates.
pub(crate) type VertexMarkers = HashMap<Key, i64>;

/// A `.poly`'s segment markers, by the segment's end points (either order): how Triangle users
/// name walls for boundary conditions.
pub(crate) type SegmentMarkers = HashMap<(Key, Key), i64>;
pub(crate) type Key = (u64, u64);

pub(crate) fn key(p: DVec2) -> Key {
    (p.x.to_bits(), p.y.to_bits())
}

fn from_key((x, y): Key) -> DVec2 {
    DVec2::new(f64::from_bits(x), f64::from_bits(y))
}

pub(crate) fn segment_key(a: DVec2, b: DVec2) -> (Key, Key) {
    let (a, b) = (key(a), key(b));
    (a.min(b), a.max(b))
}

fn parse_poly(text: &str, label: &str, node_file: &mut NodeSource) -> Result<Poly, GeometryError> {
    let last_line = text.lines().count().max(1);
    let mut recs = records(text);
    let (line, head) = recs
        .next()
        .ok_or_else(|| parse_err(label, 1, "empty file: expected the vertex header"))?;
    let header = vertex_header(label, line, &head)?;
    let (verts, base, vertex_marks) = if header.0 == 0 {
        let (node_text, node_label) = node_file()?;
        let node_last = node_text.lines().count().max(1);
        let mut nrecs = records(&node_text);
        let (nline, nhead) = nrecs
            .next()
            .ok_or_else(|| parse_err(&node_label, 1, "empty file: expected the vertex header"))?;
        let nheader = vertex_header(&node_label, nline, &nhead)?;
        parse_vertices(&mut nrecs, &node_label, nheader, node_last)?
    } else {
        parse_vertices(&mut recs, label, header, last_line)?
    };

    let (line, t) = recs
        .next()
        .ok_or_else(|| parse_err(label, last_line, "file ends before the segment header"))?;
    let nseg: usize = num(label, line, t.first(), "the number of segments")?;
    let marked = match t.get(1) {
        None => false,
        Some(_) => {
            let m: usize = num(
                label,
                line,
                t.get(1),
                "the number of segment markers (0 or 1)",
            )?;
            if m > 1 {
                return Err(parse_err(
                    label,
                    line,
                    format!("{m} segment-marker columns; Triangle allows 0 or 1"),
                ));
            }
            m == 1
        }
    };
    let mut markers: SegmentMarkers = HashMap::new();
    // Vertices with equal coordinates are one vertex (some files repeat a loop's first vertex).
    let mut canon: HashMap<(u64, u64), usize> = HashMap::new();
    let ids: Vec<usize> = verts
        .iter()
        .enumerate()
        .map(|(i, p)| *canon.entry((p.x.to_bits(), p.y.to_bits())).or_insert(i))
        .collect();
    let mut seen: HashMap<(usize, usize), usize> = HashMap::new();
    let mut segments: Vec<(usize, usize, usize)> = Vec::with_capacity(nseg.min(1 << 16)); // (a, b, line)
    for s in 0..nseg {
        let (line, t) = recs.next().ok_or_else(|| {
            parse_err(
                label,
                last_line,
                format!("file ends after {s} of {nseg} segments"),
            )
        })?;
        let end = |k: usize| -> Result<usize, GeometryError> {
            let v: usize = num(label, line, t.get(k), "a segment end point")?;
            if v < base || v - base >= verts.len() {
                return Err(parse_err(
                    label,
                    line,
                    format!("segment end point {v} is not a vertex number"),
                ));
            }
            Ok(ids[v - base])
        };
        let (a, b) = (end(1)?, end(2)?);
        if a == b {
            return Err(parse_err(label, line, "segment joins a vertex to itself"));
        }
        if marked {
            let m: i64 = num(label, line, t.get(3), "a segment marker")?;
            markers.insert(segment_key(verts[a], verts[b]), m);
        }
        if let Some(prev) = seen.insert((a.min(b), a.max(b)), line) {
            return Err(parse_err(
                label,
                line,
                format!("segment repeats the segment on line {prev}"),
            ));
        }
        segments.push((a, b, line));
    }
    if segments.is_empty() {
        return Err(invalid(
            label,
            "no segments: a .poly region needs its boundary as closed loops of segments",
        ));
    }

    let (line, t) = recs
        .next()
        .ok_or_else(|| parse_err(label, last_line, "file ends before the hole header"))?;
    let nholes: usize = num(label, line, t.first(), "the number of holes")?;
    let mut holes = Vec::new();
    for h in 0..nholes {
        let (line, t) = recs.next().ok_or_else(|| {
            parse_err(
                label,
                last_line,
                format!("file ends after {h} of {nholes} holes"),
            )
        })?;
        holes.push((
            line,
            DVec2::new(
                coord(label, line, t.get(1), "x")?,
                coord(label, line, t.get(2), "y")?,
            ),
        ));
    }
    // As Triangle reads the segments: those with the region on one side bound it, those with
    // the region on both sides are lines inside it to keep (a material interface, a crack, an
    // inclusion's outline), and of those in a hole, outside or leaving the region the parts
    // inside are kept.
    let hole_points: Vec<DVec2> = holes.iter().map(|&(_, h)| h).collect();
    let pairs: Vec<(usize, usize)> = segments.iter().map(|&(a, b, _)| (a, b)).collect();
    let sides = crate::faces::classify(&verts, &pairs, &hole_points);
    let mut adj: HashMap<usize, Vec<(usize, usize)>> = HashMap::new(); // vertex → (neighbour, line)
    let mut order = Vec::new();
    for (&(a, b, line), _) in segments
        .iter()
        .zip(&sides)
        .filter(|(_, &side)| side == crate::faces::Side::Boundary)
    {
        for (u, v) in [(a, b), (b, a)] {
            let e = adj.entry(u).or_default();
            if e.is_empty() {
                order.push(u);
            }
            e.push((v, line));
        }
    }
    for &v in &order {
        let e = &adj[&v];
        if e.len() == 1 {
            return Err(parse_err(
                label,
                e[0].1,
                format!(
                    "open polyline: vertex {} at {} ends the segments without closing a loop",
                    v + base,
                    verts[v]
                ),
            ));
        }
        if e.len() > 2 {
            return Err(parse_err(
                label,
                e[2].1,
                format!(
                    "vertex {} at {} is on {} boundary segments: two loops of the boundary \
                     touch there; cvtmesh meshes regions bounded by simple loops, one per \
                     outer boundary or hole",
                    v + base,
                    verts[v],
                    e.len()
                ),
            ));
        }
    }
    // Walk each cycle.
    let mut rings: Vec<Vec<DVec2>> = Vec::new();
    let mut done: HashMap<usize, bool> = HashMap::new();
    for &start in &order {
        if done.contains_key(&start) {
            continue;
        }
        let (mut prev, mut cur) = (usize::MAX, start);
        let mut ring = Vec::new();
        loop {
            done.insert(cur, true);
            ring.push(verts[cur]);
            let e = &adj[&cur];
            let next = if e[0].0 != prev { e[0].0 } else { e[1].0 };
            prev = cur;
            cur = next;
            if cur == start {
                break;
            }
        }
        rings.push(ring);
    }
    if rings.is_empty() {
        if let Some(&(line, h)) = holes.first() {
            return Err(parse_err(
                label,
                line,
                format!("hole point {h} lies in the region, not inside any hole loop"),
            ));
        }
        // Segments that enclose nothing: most likely a loop left open.
        let mut degree: HashMap<usize, (usize, usize)> = HashMap::new();
        for &(a, b, line) in &segments {
            for v in [a, b] {
                degree.entry(v).or_insert((0, line)).0 += 1;
            }
        }
        if let Some((v, (_, line))) = pairs
            .iter()
            .flat_map(|&(a, b)| [a, b])
            .map(|v| (v, degree[&v]))
            .find(|(_, (d, _))| *d == 1)
        {
            return Err(parse_err(
                label,
                line,
                format!(
                    "open polyline: vertex {} at {} ends the segments without closing a loop",
                    v + base,
                    verts[v]
                ),
            ));
        }
        return Err(invalid(
            label,
            "no segment bounds the region: every segment has the region on both sides or on \
             neither (a hole point in every face?)",
        ));
    }
    // Lines inside, and segments in a hole, outside or leaving the region, whose parts inside
    // Triangle keeps (`poly_region` cuts them at the boundary).
    let inner: Vec<(usize, usize)> = pairs
        .iter()
        .zip(&sides)
        .filter(|(_, &side)| side != crate::faces::Side::Boundary)
        .map(|(&p, _)| p)
        .collect();
    let marked_inner: Vec<(usize, usize, i64)> = inner
        .iter()
        .map(|&(a, b)| {
            let m = markers.get(&segment_key(verts[a], verts[b])).copied();
            (a, b, m.unwrap_or(0))
        })
        .collect();
    let lines = crate::EmbeddedLine::join(&verts, &marked_inner, |v| adj.contains_key(&v));
    // Regional attributes and area constraints may follow: `index x y attribute area`. An
    // attribute numbers the subdomain holding the point, as Triangle's `-A` spreads it; an
    // area constraint is not used (the user hears it). Which loops are holes is for nesting to
    // decide and the hole points to confirm (`poly_region`).
    let nregions = recs
        .next()
        .and_then(|(_, t)| t.first().and_then(|n| n.parse::<usize>().ok()))
        .unwrap_or(0);
    let mut subdomains = Vec::new();
    let mut area_constraints = 0;
    for r in 0..nregions {
        let (line, t) = recs.next().ok_or_else(|| {
            parse_err(
                label,
                last_line,
                format!("file ends after {r} of {nregions} regional attributes"),
            )
        })?;
        let p = DVec2::new(
            coord(label, line, t.get(1), "x")?,
            coord(label, line, t.get(2), "y")?,
        );
        // Triangle reads x, y, the attribute and the area bound of every region.
        let a: f64 = num(label, line, t.get(3), "a regional attribute")?;
        if a.fract() != 0.0 || a.abs() > f64::from(i32::MAX) {
            return Err(parse_err(
                label,
                line,
                format!(
                    "regional attribute {a} is not a whole number within 32 bits: \
                     cvtmesh numbers subdomains by integers, as Gmsh's physical surfaces"
                ),
            ));
        }
        subdomains.push((p, a as i64));
        if t.get(4)
            .and_then(|s| s.parse::<f64>().ok())
            .is_some_and(|x| x > 0.0)
        {
            area_constraints += 1;
        }
    }
    // A vertex repeated with equal coordinates keeps the first nonzero marker it is given.
    let mut vertex_markers = VertexMarkers::new();
    for (p, &m) in verts.iter().zip(&vertex_marks) {
        if m != 0 {
            vertex_markers.entry(key(*p)).or_insert(m);
        }
    }
    // Triangle keeps every input vertex: one on no segment is a point inside to keep. Not so
    // for vertices from the `.node` beside the `.poly` (a mesh's `.poly` takes them from its
    // `.node`): those are the old mesh's vertices, not points anyone placed.
    let mut embedded = Vec::new();
    if header.0 > 0 {
        for (i, p) in verts.iter().enumerate() {
            if ids[i] == i && !pairs.iter().any(|&(a, b)| a == i || b == i) {
                embedded.push((*p, vertex_marks[i]));
            }
        }
    }
    Ok(Poly {
        loops: by_nesting(rings),
        holes,
        segment_markers: marked.then_some(markers),
        vertex_markers,
        embedded,
        subdomains,
        area_constraints,
        lines,
    })
}

/// Insert `p` into the loop segment within `off` of it (the first found), the two halves
/// keeping the segment's marker; nothing if `p` is one of that segment's ends.
fn split_segment_at(poly: &mut Poly, p: DVec2, off: f64) {
    for (_, pts) in poly.loops.iter_mut() {
        let n = pts.len();
        let Some(i) = (0..n).find(|&i| segment_distance(p, pts[i], pts[(i + 1) % n]) <= off) else {
            continue;
        };
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        if a.distance(p) <= off || b.distance(p) <= off {
            return;
        }
        pts.insert(i + 1, p);
        if let Some(markers) = poly.segment_markers.as_mut() {
            if let Some(m) = markers.remove(&segment_key(a, b)) {
                markers.insert(segment_key(a, p), m);
                markers.insert(segment_key(p, b), m);
            }
        }
        return;
    }
}

fn parse_geojson(text: &str, label: &str) -> Result<Loops, GeometryError> {
    let v: Value = serde_json::from_str(text).map_err(|e| GeometryError::Parse {
        path: label.to_string(),
        message: format!("invalid JSON: {e}"),
    })?;
    let bad = |m: String| GeometryError::Parse {
        path: label.to_string(),
        message: m,
    };
    let polygons = find_polygons(&v).map_err(bad)?;
    let several = polygons.len() > 1;
    let mut loops = Vec::new();
    for (p, rings) in polygons.iter().enumerate() {
        // Name the polygon only where there are several, so a single polygon's rings read as
        // in the file.
        let ring_name = |k: usize| {
            if several {
                format!("polygon {p}, ring {k}")
            } else {
                format!("ring {k}")
            }
        };
        let rings = rings
            .as_array()
            .ok_or_else(|| bad("polygon coordinates must be an array of rings".into()))?;
        if rings.is_empty() {
            return Err(bad(if several {
                format!("polygon {p} has no rings")
            } else {
                "the polygon has no rings".into()
            }));
        }
        for (k, ring) in rings.iter().enumerate() {
            let positions = ring
                .as_array()
                .ok_or_else(|| bad(format!("{} is not an array of positions", ring_name(k))))?;
            let mut pts = Vec::with_capacity(positions.len());
            for (i, pos) in positions.iter().enumerate() {
                let xy = pos
                    .as_array()
                    .filter(|a| a.len() >= 2)
                    .and_then(|a| Some(DVec2::new(a[0].as_f64()?, a[1].as_f64()?)));
                pts.push(xy.ok_or_else(|| {
                    bad(format!("{}, position {i}: expected [x, y]", ring_name(k)))
                })?);
            }
            if pts.first() != pts.last() {
                return Err(bad(format!(
                    "{} is not closed: GeoJSON rings end with a copy of their first position (open polyline)",
                    ring_name(k)
                )));
            }
            let role = if k == 0 {
                LoopRole::Outer
            } else {
                LoopRole::Hole
            };
            loops.push((Some(role), pts));
        }
    }
    Ok(loops)
}

/// The coordinates (arrays of rings) of every polygon in a GeoJSON object, each a part of
/// the region.
fn find_polygons(v: &Value) -> Result<Vec<&Value>, String> {
    let mut found = Vec::new();
    collect_polygons(v, 0, &mut found)?;
    if found.is_empty() {
        return Err("the GeoJSON object contains no Polygon or MultiPolygon".into());
    }
    Ok(found)
}

/// Every polygon's coordinates in a GeoJSON object, in document order.
fn collect_polygons<'v>(
    v: &'v Value,
    depth: usize,
    found: &mut Vec<&'v Value>,
) -> Result<(), String> {
    if depth > 8 {
        return Err("GeoJSON objects nested too deeply".into());
    }
    let ty = v
        .get("type")
        .and_then(Value::as_str)
        .ok_or("expected a GeoJSON object with a \"type\"")?;
    let missing = |field: &str| format!("{ty} has no \"{field}\"");
    match ty {
        "Polygon" => found.push(v.get("coordinates").ok_or_else(|| missing("coordinates"))?),
        "MultiPolygon" => {
            let polygons = v
                .get("coordinates")
                .ok_or_else(|| missing("coordinates"))?
                .as_array()
                .ok_or_else(|| "MultiPolygon coordinates are not an array".to_string())?;
            if polygons.is_empty() {
                return Err("MultiPolygon has no polygons".into());
            }
            found.extend(polygons.iter());
        }
        "Feature" => collect_polygons(
            v.get("geometry").ok_or_else(|| missing("geometry"))?,
            depth + 1,
            found,
        )?,
        "FeatureCollection" | "GeometryCollection" => {
            let field = if ty == "FeatureCollection" {
                "features"
            } else {
                "geometries"
            };
            let items = v
                .get(field)
                .and_then(Value::as_array)
                .ok_or_else(|| missing(field))?;
            for item in items {
                // Points, lines and null geometries carry no area: they are skipped, while a
                // malformed polygon is still reported.
                let kind = item
                    .get("geometry")
                    .unwrap_or(item)
                    .get("type")
                    .and_then(Value::as_str);
                if matches!(
                    kind,
                    Some(
                        "Polygon"
                            | "MultiPolygon"
                            | "Feature"
                            | "FeatureCollection"
                            | "GeometryCollection"
                    )
                ) {
                    collect_polygons(item, depth + 1, found)?;
                }
            }
        }
        other => {
            return Err(format!(
                "GeoJSON type {other} is not a polygon (expected {})",
                GEOJSON_TYPES.join(", ")
            ))
        }
    }
    Ok(())
}

fn parse_loops(text: &str, label: &str) -> Result<Loops, GeometryError> {
    let mut loops: Vec<Vec<DVec2>> = Vec::new();
    let mut current: Vec<DVec2> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        if raw.trim().is_empty() {
            if !current.is_empty() {
                loops.push(std::mem::take(&mut current));
            }
            continue;
        }
        let content = raw.split('#').next().unwrap_or("");
        let toks: Vec<&str> = content
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .collect();
        if toks.is_empty() {
            continue; // a comment line neither adds a point nor ends a loop
        }
        if toks.len() != 2 {
            return Err(parse_err(
                label,
                line,
                format!("expected two numbers 'x y', found {} fields", toks.len()),
            ));
        }
        current.push(DVec2::new(
            coord(label, line, toks.first(), "x")?,
            coord(label, line, toks.get(1), "y")?,
        ));
    }
    if !current.is_empty() {
        loops.push(current);
    }
    if loops.is_empty() {
        return Err(invalid(label, "no points: expected loops of 'x y' lines"));
    }
    Ok(by_nesting(loops))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn no_node() -> impl FnMut() -> Result<(String, String), GeometryError> {
        || {
            Err(GeometryError::Parse {
                path: "x".into(),
                message: "no node file".into(),
            })
        }
    }

    fn poly(text: &str) -> Result<Region, GeometryError> {
        poly_from_str(text, "t.poly", "t")
    }

    /// Ring areas (positive) in order, to compare parses independent of start point/orientation.
    fn areas(loops: &Loops) -> Vec<(Option<LoopRole>, f64)> {
        loops
            .iter()
            .map(|(r, p)| (*r, ring_signed_area(p).abs()))
            .collect()
    }

    /// Loop roles and areas of a region.
    fn region_areas(r: &Region) -> Vec<(LoopRole, f64)> {
        r.polygonize(0.0)
            .rings
            .iter()
            .zip(r.loops())
            .map(|(ring, l)| (l.role, ring_signed_area(&ring.points).abs()))
            .collect()
    }

    const SQUARE_HOLE_POLY: &str = "# square with a square hole\n\
        8 2 0 1\n\
        1 0 0 1\n2 4 0 1\n3 4 4 1\n4 0 4 1\n\
        5 1 1 2\n6 2 1 2\n7 2 2 2\n8 1 2 2\n\
        8 1\n\
        1 5 6 2\n2 1 2 1\n3 3 4 1\n4 6 7 2\n5 2 3 1\n6 4 1 1\n7 8 5 2\n8 7 8 2\n\
        1\n1 1.5 1.5\n";

    #[test]
    fn poly_assembles_loops_and_finds_the_hole() {
        let r = poly(SQUARE_HOLE_POLY).unwrap();
        assert_eq!(
            region_areas(&r),
            [(LoopRole::Outer, 16.0), (LoopRole::Hole, 1.0)]
        );
        assert_eq!(r.loops()[0].pieces.len(), 4);
        // Without the hole point Triangle meshes the inner square too, its outline kept as
        // edges: an inclusion, a closed embedded line.
        let no_hole = SQUARE_HOLE_POLY.replace("\n1\n1 1.5 1.5\n", "\n0\n");
        let r = poly(&no_hole).unwrap();
        assert_eq!(region_areas(&r), [(LoopRole::Outer, 16.0)]);
        let lines = r.embedded_lines();
        assert_eq!(lines.len(), 1);
        assert!(
            lines[0].is_closed() && lines[0].points.len() == 5,
            "{lines:?}"
        );
        assert!((lines[0].length() - 4.0).abs() < 1e-12);
        // 0-based numbering, duplicate coincident vertex closing a loop, trailing attributes.
        let zero =
            "5 2 1 0\n0 0 0 9\n1 3 0 9\n2 0 3 9\n3 0 0 9\n4 9 9 9\n3 0\n0 0 1\n1 1 2\n2 2 3\n0\n";
        assert_eq!(region_areas(&poly(zero).unwrap()), [(LoopRole::Outer, 4.5)]);
    }

    /// A 3 × 1 channel with a square hole: the bottom wall three collinear segments marked 1,
    /// 4, 1 (a heated strip in the middle), the outlet 3, the top 1, the inlet 2, the hole 9;
    /// listed clockwise, so the outer loop is turned round.
    const MARKED: &str = "10 2 0 0\n1 0 0\n2 1 0\n3 2 0\n4 3 0\n5 3 1\n6 0 1\n\
        7 1.4 0.4\n8 1.6 0.4\n9 1.6 0.6\n10 1.4 0.6\n\
        10 1\n1 6 5 1\n2 5 4 3\n3 4 3 1\n4 3 2 4\n5 2 1 1\n6 1 6 2\n\
        7 7 8 9\n8 8 9 9\n9 9 10 9\n10 10 7 9\n1\n1 1.5 0.5\n";

    #[test]
    fn poly_segment_markers_name_the_pieces_and_their_changes_are_corners() {
        let r = poly(MARKED).unwrap();
        let at = |x: f64, y: f64| DVec2::new(x, y);
        // Each piece's marker is that of the segment it is, whatever the orientation.
        let marker_of = |a: DVec2, b: DVec2| {
            let m = r.piece_markers().unwrap();
            let j = r
                .pieces()
                .iter()
                .position(|p| {
                    let (s, e) = (p.start(), p.end());
                    (s == a && e == b) || (s == b && e == a)
                })
                .unwrap();
            m[j]
        };
        assert_eq!(marker_of(at(1.0, 0.0), at(2.0, 0.0)), 4);
        assert_eq!(marker_of(at(2.0, 0.0), at(3.0, 0.0)), 1);
        assert_eq!(marker_of(at(0.0, 1.0), at(0.0, 0.0)), 2);
        assert_eq!(marker_of(at(1.6, 0.6), at(1.4, 0.6)), 9);
        // The strip's ends are corners whatever the corner angle; (3, 1) turns too.
        for deg in [0.0, 30.0, 90.0, 179.0] {
            let c = r.with_corner_angle(deg);
            let pos: Vec<DVec2> = c.corners().iter().map(|c| c.pos).collect();
            for p in [at(1.0, 0.0), at(2.0, 0.0), at(0.0, 0.0), at(3.0, 0.0)] {
                assert!(pos.contains(&p), "{deg}°: no corner at {p}");
            }
            let m = c.piece_markers().unwrap();
            assert_eq!(m.len(), c.pieces().len());
            assert_eq!(m.iter().filter(|&&m| m == 4).count(), 1);
        }
        // Without markers in the file, none.
        let plain = MARKED.replace("10 1\n1 6 5 1", "10 0\n1 6 5 1");
        assert!(poly(&plain).unwrap().piece_markers().is_none());
        // A second marker column is Triangle's error.
        let e = poly(&MARKED.replace("10 1\n1 6", "10 2\n1 6"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("segment-marker columns"), "{e}");
    }

    /// A 4 × 1 channel whose bottom wall is three collinear segments (marker 1), the other
    /// walls 1, 2 (inlet) and 3 (outlet); vertex markers in the last column.
    fn pinned_channel(v2: i64, v3: i64, segments: bool) -> String {
        let seg = if segments {
            "6 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 5 3\n5 5 6 1\n6 6 1 2\n"
        } else {
            "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 5\n5 5 6\n6 6 1\n"
        };
        format!("6 2 1 1\n1 0 0 0.5 1\n2 1.5 0 0.5 {v2}\n3 2.5 0 0.5 {v3}\n4 4 0 0.5 1\n5 4 1 0.5 1\n6 0 1 0.5 1\n{seg}0\n")
    }

    #[test]
    fn a_poly_vertex_lying_on_a_segment_splits_it_as_triangle_does() {
        let at = |x: f64, y: f64| DVec2::new(x, y);
        // The channel's bottom wall is one segment 1 → 4 (marker 1); vertices 2 and 3 lie on
        // it, ends of no segment: 2 marked 7 (a probe on the wall), 3 marked 0.
        let seg = "4 1\n1 1 4 1\n2 4 5 3\n3 5 6 1\n4 6 1 2\n";
        let text = pinned_channel(7, 0, true).replacen(
            "6 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 5 3\n5 5 6 1\n6 6 1 2\n",
            seg,
            1,
        );
        let r = poly(&text).unwrap();
        assert_eq!(r.vertex_markers(), &[(at(1.5, 0.0), 7)]);
        assert!(r.embedded_points().is_empty(), "{:?}", r.embedded_points());
        let k = r.corners().iter().position(|c| c.pos == at(1.5, 0.0));
        assert_eq!(k.and_then(|k| r.corner_marker(k)), Some(7));
        // The halves keep the wall's marker; the unmarked vertex is the wall's.
        let m = r.piece_markers().unwrap();
        assert_eq!(m.iter().filter(|&&m| m == 1).count(), m.len() - 2);
        assert!((r.area() - 4.0).abs() < 1e-12);
        // Unsplit (no vertex on the wall) the probe is no corner at all.
        let plain = text.replacen("2 1.5 0 0.5 7", "2 1.5 0.5 0.5 7", 1);
        let r = poly(&plain).unwrap();
        assert!(r.corners().iter().all(|c| c.pos != at(1.5, 0.0)));
        assert_eq!(r.embedded_points().len(), 1);
    }

    #[test]
    fn poly_vertex_markers_of_their_own_pin_corners() {
        let at = |x: f64, y: f64| DVec2::new(x, y);
        let r = poly(&pinned_channel(7, 1, true)).unwrap();
        // Vertex 2 marks itself 7 on a wall marked 1: a corner with marker 7; vertex 3 is
        // marked as its wall is and pins nothing (Triangle writes such files).
        assert_eq!(r.vertex_markers(), &[(at(1.5, 0.0), 7)]);
        for deg in [0.0, 90.0, 179.0] {
            let c = r.with_corner_angle(deg);
            let k = c.corners().iter().position(|c| c.pos == at(1.5, 0.0));
            assert_eq!(k.and_then(|k| c.corner_marker(k)), Some(7), "{deg}°");
            assert!(!c.corners().iter().any(|c| c.pos == at(2.5, 0.0)), "{deg}°");
        }
        // Simplification drops a vertex 0.001 off the bottom wall's line but keeps the
        // pinned vertex, a corner with its marker.
        let bent =
            poly(&pinned_channel(7, 1, true).replacen("3 2.5 0 ", "3 2.5 0.001 ", 1)).unwrap();
        let s = bent.simplified(0.1).unwrap();
        assert_eq!(s.vertices, (6, 5));
        assert_eq!(s.region.vertex_markers(), r.vertex_markers());
        let k = s
            .region
            .corners()
            .iter()
            .position(|c| c.pos == at(1.5, 0.0));
        assert_eq!(k.and_then(|k| s.region.corner_marker(k)), Some(7));
        // Without segment markers the walls are Triangle's 1: a vertex marked 1 pins nothing,
        // one marked 5 pins itself and gives every piece the marker 1.
        let plain = poly(&pinned_channel(1, 1, false)).unwrap();
        assert!(plain.vertex_markers().is_empty() && plain.piece_markers().is_none());
        let one = poly(&pinned_channel(5, 1, false)).unwrap();
        assert_eq!(one.vertex_markers(), &[(at(1.5, 0.0), 5)]);
        assert!(one.piece_markers().unwrap().iter().all(|&m| m == 1));
        // A marker no 32-bit integer holds is refused, by name.
        let e = poly(&pinned_channel(7, 1, true).replacen("0.5 7", "0.5 5000000000", 1))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("marker 5000000000") && e.contains("32-bit"),
            "{e}"
        );
        let e = poly(&pinned_channel(7, 1, true).replacen("4 5 3", "4 5 -3000000000", 1))
            .unwrap_err()
            .to_string();
        assert!(e.contains("marker -3000000000"), "{e}");
        // Two vertex-marker columns are Triangle's error, a missing marker a parse error.
        let e = poly(&pinned_channel(7, 1, true).replacen("6 2 1 1", "6 2 1 2", 1))
            .unwrap_err()
            .to_string();
        assert!(e.contains("vertex-marker columns"), "{e}");
        let e = poly(&pinned_channel(7, 1, true).replacen("0.5 7", "0.5 x", 1))
            .unwrap_err()
            .to_string();
        assert!(e.contains("vertex marker"), "{e}");
        // A missing marker is 0, as Triangle reads it: nothing pinned.
        let missing = poly(&pinned_channel(7, 1, true).replacen("0.5 7", "0.5", 1)).unwrap();
        assert!(missing.vertex_markers().is_empty());
        // One marker on every vertex of a loop (meshpy's point markers of 1 on walls marked 2
        // and 3) flags the loop, and pins nothing.
        let flagged = pinned_channel(1, 1, true).replacen(
            "1 1 2 1\n2 2 3 1\n3 3 4 1\n",
            "1 1 2 2\n2 2 3 2\n3 3 4 2\n",
            1,
        );
        let r = poly(&flagged).unwrap();
        assert!(r.vertex_markers().is_empty(), "{:?}", r.vertex_markers());
    }

    #[test]
    fn poly_vertices_on_no_segment_are_points_kept_inside() {
        let at = |x: f64, y: f64| DVec2::new(x, y);
        // The channel with two more vertices: 7 inside (marker 9), 8 inside unmarked.
        let text = pinned_channel(1, 1, true)
            .replacen("6 2 1 1", "8 2 1 1", 1)
            .replacen(
                "6 0 1 0.5 1\n",
                "6 0 1 0.5 1\n7 1 0.5 0.5 9\n8 3 0.25 0.5 0\n",
                1,
            );
        let r = poly(&text).unwrap();
        assert_eq!(
            r.embedded_points(),
            &[(at(1.0, 0.5), 9), (at(3.0, 0.25), 0)]
        );
        assert_eq!(
            r.with_corner_angle(90.0).embedded_points(),
            r.embedded_points()
        );
        assert_eq!(r.parts()[0].region.embedded_points(), r.embedded_points());
        // Outside the region or in a hole a vertex is in no triangle of Triangle's mesh
        // either: not kept.
        let out = text.replacen("7 1 0.5", "7 5 0.5", 1);
        assert_eq!(poly(&out).unwrap().embedded_points(), &[(at(3.0, 0.25), 0)]);
        let hole = poly(
            &SQUARE_HOLE_POLY
                .replacen("8 2 0 1\n", "9 2 0 1\n", 1)
                .replacen("8 1 2 2\n", "8 1 2 2\n9 1.5 1.5 0\n", 1),
        );
        assert!(hole.unwrap().embedded_points().is_empty());
        // A marked point numbers its node, so the walls take Triangle's 1.
        let plain = text.replacen(
            "6 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 5 3\n5 5 6 1\n6 6 1 2\n",
            "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 5\n5 5 6\n6 6 1\n",
            1,
        );
        let r = poly(&plain).unwrap();
        assert!(r.piece_markers().unwrap().iter().all(|&m| m == 1));
        // Vertices taken from the .node beside the .poly (a mesh's) are not kept.
        let mut node = || {
            Ok((
                "4 2 0 0\n1 0 0\n2 2 0\n3 0 2\n4 0.5 0.5\n".to_string(),
                "t.node".to_string(),
            ))
        };
        let p = parse_poly(
            "0 2 0 0\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n",
            "t.poly",
            &mut node,
        );
        assert!(p.unwrap().embedded.is_empty());
    }

    #[test]
    fn poly_with_vertices_in_a_node_file() {
        let text = "0 2 0 0\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n";
        let mut node = || {
            Ok((
                "3 2 0 0\n1 0 0\n2 2 0\n3 0 2\n".to_string(),
                "t.node".to_string(),
            ))
        };
        let loops = parse_poly(text, "t.poly", &mut node).unwrap().loops;
        assert_eq!(areas(&loops), [(None, 2.0)]);
        let e = parse_poly(text, "t.poly", &mut no_node())
            .unwrap_err()
            .to_string();
        assert!(e.contains("no node file"), "{e}");
        let e = poly(text).unwrap_err().to_string();
        assert!(e.contains("separate .node file"), "{e}");
    }

    #[test]
    fn poly_errors_name_file_and_line() {
        let cases = [
            ("", "line 1: empty file"),
            ("3 3 0 0\n", "line 1: dimension is 3"),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n",
                "line 3: file ends after 2 of 3 vertices",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 nan\n3 0 1\n",
                "line 3: y is not finite",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n2 0\n1 1 2\n2 2 3\n0\n",
                "open polyline",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 7\n0\n",
                "line 8: segment end point 7",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 1\n3 3 1\n0\n",
                "line 7: segment repeats the segment on line 6",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 0\n1 2 2\n0\n",
                "joins a vertex to itself",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n",
                "file ends before the hole header",
            ),
            (
                "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n1\n1 0.1 0.1\n",
                "line 10: hole point",
            ),
            (
                "3 2 0 0\n1 0 0\n3 1 0\n",
                "line 3: vertex number 3, expected 2",
            ),
            ("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n0\n", "no segments"),
            (
                "\u{0}\u{1}garbage\u{7f}",
                "line 1: expected the number of vertices",
            ),
        ];
        for (text, want) in cases {
            let e = poly(text).unwrap_err().to_string();
            assert!(
                e.contains("t.poly") && e.contains(want),
                "{e:?} should contain {want:?}"
            );
        }
        // Two separate squares are two parts, as Triangle meshes them.
        let two = "8 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n5 5 0\n6 6 0\n7 6 1\n8 5 1\n\
                   8 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 8\n8 8 5\n0\n";
        let r = poly(two).unwrap();
        assert_eq!((r.num_parts(), r.area()), (2, 5.0));
        // Two triangles touching at a vertex: a bow tie's two loops.
        let bow = "5 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 2 0\n5 2 1\n6 0\n1 1 2\n2 2 3\n3 3 1\n4 2 4\n5 4 5\n6 5 2\n0\n";
        let e = poly(bow).unwrap_err().to_string();
        assert!(
            e.contains("on 4 boundary segments") && e.contains("touch there"),
            "{e}"
        );
    }

    #[test]
    fn geojson_polygon_multipolygon_and_wrappers() {
        let ring = "[[0,0],[4,0],[4,4],[0,4],[0,0]]";
        let hole = "[[1,1],[1,2],[2,2],[2,1],[1,1]]";
        let poly = format!("{{\"type\":\"Polygon\",\"coordinates\":[{ring},{hole}]}}");
        let want = [(Some(LoopRole::Outer), 16.0), (Some(LoopRole::Hole), 1.0)];
        assert_eq!(areas(&parse_geojson(&poly, "g").unwrap()), want);
        let multi = format!("{{\"type\":\"MultiPolygon\",\"coordinates\":[[{ring},{hole}]]}}");
        assert_eq!(areas(&parse_geojson(&multi, "g").unwrap()), want);
        // Every polygon is a part: overlapping ones are refused by the region's checks.
        let two =
            format!("{{\"type\":\"MultiPolygon\",\"coordinates\":[[{ring},{hole}],[{ring}]]}}");
        assert_eq!(parse_geojson(&two, "g").unwrap().len(), 3);
        let e = geojson_from_str(&two, "g", "g").unwrap_err().to_string();
        assert!(e.contains("loop 0 (outer) and loop 2 (outer)"), "{e}");
        let feature = format!("{{\"type\":\"Feature\",\"properties\":{{}},\"geometry\":{poly}}}");
        assert_eq!(areas(&parse_geojson(&feature, "g").unwrap()), want);
        let point =
            "{\"type\":\"Feature\",\"geometry\":{\"type\":\"Point\",\"coordinates\":[1,2]}}";
        let coll = format!("{{\"type\":\"FeatureCollection\",\"features\":[{point},{feature}]}}");
        assert_eq!(areas(&parse_geojson(&coll, "g").unwrap()), want);
        let both = format!(
            "{{\"type\":\"FeatureCollection\",\"features\":[{feature},{point},{feature}]}}"
        );
        assert_eq!(parse_geojson(&both, "g").unwrap().len(), 4);
        assert!(
            is_geojson(&coll)
                && is_geojson(&poly)
                && !is_geojson("{\"name\":\"circle\",\"loops\":[]}")
        );
        // 3-D positions keep x and y.
        let z = "{\"type\":\"Polygon\",\"coordinates\":[[[0,0,5],[1,0,5],[0,1,5],[0,0,5]]]}";
        assert_eq!(
            areas(&parse_geojson(z, "g").unwrap()),
            [(Some(LoopRole::Outer), 0.5)]
        );
    }

    #[test]
    fn geojson_errors() {
        let cases = [
            (
                "{\"type\":\"Polygon\",\"coordinates\":[[[0,0],[1,0],[0,1]]]}",
                "not closed",
            ),
            (
                "{\"type\":\"Polygon\",\"coordinates\":[[[0,0],[1,0],[0,\"a\"],[0,0]]]}",
                "ring 0, position 2",
            ),
            ("{\"type\":\"Polygon\",\"coordinates\":[]}", "no rings"),
            (
                "{\"type\":\"LineString\",\"coordinates\":[[0,0],[1,1]]}",
                "LineString is not a polygon",
            ),
            (
                "{\"type\":\"FeatureCollection\",\"features\":[]}",
                "contains no Polygon",
            ),
            (
                "{\"type\":\"Polygon\",\"coordinates\":[[0,0],",
                "invalid JSON",
            ),
            ("[1,2,3]", "expected a GeoJSON object"),
        ];
        for (text, want) in cases {
            let e = parse_geojson(text, "g.geojson").unwrap_err().to_string();
            assert!(
                e.contains("g.geojson") && e.contains(want),
                "{e:?} should contain {want:?}"
            );
        }
        let e = parse_geojson(
            "{\n\"type\": \"Polygon\",\n  \"coordinates\": [[[0, 0] [1, 0]]]}",
            "g",
        )
        .unwrap_err();
        assert!(e.to_string().contains("line 3"), "{e}");
    }

    #[test]
    fn plain_loops_with_commas_comments_and_blank_lines() {
        let text =
            "# outer\n0 0\n4, 0\n4,4\n0 4\n0 0\n\n\n# hole\n1 1   # a point\n1 2\n2\t2\n2 1\n";
        let loops = parse_loops(text, "l.txt").unwrap();
        assert_eq!(loops.len(), 2);
        assert_eq!(
            loops[0].1.len(),
            5,
            "the closing point is dropped later, in polygon_region"
        );
        assert_eq!(areas(&loops), [(None, 16.0), (None, 1.0)]);
        let cases = [
            ("0 0\n1 0\n1 1 1\n", "line 3: expected two numbers"),
            ("0 0\n1 x\n", "line 2: expected a number for y"),
            ("0 0\nNaN 1\n", "line 2: x is not finite"),
            ("# nothing\n\n", "no points"),
            ("\u{fffd}\u{1} z\n", "line 1: expected a number for x"),
        ];
        for (text, want) in cases {
            let e = parse_loops(text, "l.txt").unwrap_err().to_string();
            assert!(
                e.contains("l.txt") && e.contains(want),
                "{e:?} should contain {want:?}"
            );
        }
    }

    #[test]
    fn corners_are_the_turning_vertices() {
        // Collinear midpoints are not corners; the four square corners are.
        let pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        let r = Region::from_loops("square", vec![(LoopRole::Outer, pts.to_vec())]).unwrap();
        let mut corners: Vec<(f64, f64)> = r.corners().iter().map(|c| (c.pos.x, c.pos.y)).collect();
        corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(corners, [(0.0, 0.0), (0.0, 2.0), (2.0, 0.0), (2.0, 2.0)]);
        // Collinear edges join into one piece between corners.
        assert_eq!(r.pieces().len(), 4);
        // A turn of about 1e-6 rad (the threshold is 1e-9) makes a corner.
        let bent = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 1e-6),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        let r = Region::from_loops("bent", vec![(LoopRole::Outer, bent.to_vec())]).unwrap();
        assert_eq!((r.corners().len(), r.pieces().len()), (5, 5));
    }

    proptest::proptest! {
        #[test]
        fn random_bytes_never_panic_the_parsers(bytes in proptest::collection::vec(proptest::num::u8::ANY, 0..300)) {
            let text = String::from_utf8_lossy(&bytes);
            let _ = poly(&text);
            let _ = parse_geojson(&text, "r");
            let _ = parse_loops(&text, "r");
        }

        #[test]
        fn random_numeric_text_never_panics_the_parsers(text in "[0-9 \n#.,-]{0,200}") {
            let _ = poly(&text);
            let _ = parse_loops(&text, "r");
            let _ = parse_geojson(&format!("{{\"type\":\"Polygon\",\"coordinates\":[[{text}]]}}"), "r");
        }
    }

    // ---- End to end through Region::new ----

    struct TempFile(std::path::PathBuf);
    impl TempFile {
        fn new(name: &str, contents: &[u8]) -> TempFile {
            static N: AtomicUsize = AtomicUsize::new(0);
            let dir = std::env::temp_dir().join(format!(
                "geometry-formats-{}-{}",
                std::process::id(),
                N.fetch_add(1, Ordering::Relaxed)
            ));
            std::fs::create_dir_all(&dir).unwrap();
            let p = dir.join(name);
            std::fs::write(&p, contents).unwrap();
            TempFile(p)
        }
    }
    impl Drop for TempFile {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(self.0.parent().unwrap());
        }
    }

    fn assert_square_with_hole(r: &Region, name: &str) {
        assert_eq!(r.name(), name);
        assert_eq!(r.loops().len(), 2);
        assert_eq!(r.loops()[0].role, LoopRole::Outer);
        assert_eq!(r.loops()[1].role, LoopRole::Hole);
        assert!((r.area() - 15.0).abs() < 1e-12, "area {}", r.area());
        assert!((r.perimeter() - 20.0).abs() < 1e-12);
        assert_eq!(r.corners().len(), 8);
        assert_eq!(r.pieces().len(), 8);
    }

    #[test]
    fn every_format_reads_the_same_region() {
        let ring = "[[0,0],[0,4],[4,4],[4,0],[0,0]]"; // clockwise: must be reoriented
        let hole = "[[1,1],[2,1],[2,2],[1,2],[1,1]]";
        let geo = format!("{{\"type\":\"Feature\",\"geometry\":{{\"type\":\"Polygon\",\"coordinates\":[{ring},{hole}]}}}}");
        let files = [
            TempFile::new("a.poly", SQUARE_HOLE_POLY.as_bytes()),
            TempFile::new("b.geojson", geo.as_bytes()),
            TempFile::new("c.json", geo.as_bytes()),
            TempFile::new("d.txt", b"0 0\n2 0\n4 0\n4 4\n0 4\n\n1 1\n1 2\n2 2\n2 1\n"),
            TempFile::new(
                "e.XY",
                b"0,0\n4,0\n4,4\n0,4\n0,0\n\n1,1\n1,2\n2,2\n2,1\n1,1\n",
            ),
        ];
        for (f, name) in files.iter().zip(["a", "b", "c", "d", "e"]) {
            // In d, the boundary goes straight on at (2, 0): its two segments are one piece.
            let r = read_region(&f.0).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_square_with_hole(&r, name);
        }
    }

    #[test]
    fn project_json_still_goes_to_the_project_reader() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("regions/hex_hole.json");
        let r = read_region(&dir).unwrap();
        assert_eq!(r.name(), "hex_hole");
        assert_eq!(r.loops().len(), 2);
    }

    #[test]
    fn read_region_errors() {
        let e = read_region(Path::new("shape.stl")).unwrap_err().to_string();
        assert!(
            e.contains("'.stl'") && e.contains(".geojson") && e.contains(".poly"),
            "{e}"
        );
        let e = read_region(Path::new("/no/such/file.poly")).unwrap_err();
        assert!(matches!(e, GeometryError::Io { .. }), "{e}");
        let bin = TempFile::new("bin.txt", &[0xff, 0xfe, 0x00, 0x12]);
        assert!(read_region(&bin.0)
            .unwrap_err()
            .to_string()
            .contains("not a text file"));
        let few = TempFile::new("few.txt", b"0 0\n1 0\n0 0\n");
        let e = read_region(&few.0).unwrap_err().to_string();
        assert!(
            e.contains("few.txt") && e.contains("2 distinct points"),
            "{e}"
        );
        let dup = TempFile::new("dup.txt", b"0 0\n1 0\n1 0\n0 1\n");
        let e = read_region(&dup.0).unwrap_err().to_string();
        assert!(
            e.contains("dup.txt") && e.contains("duplicate consecutive vertices at (1, 0)"),
            "{e}"
        );
        let header = TempFile::new("header.txt", b"x y\n0 0\n1 0\n0 1\n");
        let e = read_region(&header.0).unwrap_err().to_string();
        assert!(
            e.contains("line 1: expected a number for x, found 'x'"),
            "{e}"
        );
        let flat = TempFile::new("flat.txt", b"0 0\n1 0\n2 0\n");
        let e = read_region(&flat.0).unwrap_err().to_string();
        assert!(e.contains("folds back on itself at (0, 0)"), "{e}");
        // A self-intersecting bow tie is caught by Region::new and names the file.
        let bow = TempFile::new("bow.txt", b"0 0\n1 1\n1 0\n0 1\n");
        let e = read_region(&bow.0).unwrap_err();
        assert!(
            matches!(e, GeometryError::Invalid { .. }) && e.to_string().contains("bow.txt"),
            "{e}"
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        #[test]
        fn random_small_polygons_never_panic(coords in proptest::collection::vec(-3i8..3, 6..16)) {
            // Small integer coordinates make collinear, repeated and crossing points common.
            let text: String = coords.chunks(2).filter(|c| c.len() == 2).map(|c| format!("{} {}\n", c[0], c[1])).collect();
            let _ = loops_from_str(&text, "r", "r");
        }
    }
}
