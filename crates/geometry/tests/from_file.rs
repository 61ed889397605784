//! `Region::from_file` reads every supported format: the project JSON, GeoJSON (as `.geojson`
//! and as `.json`), Triangle `.poly` and plain loop lists (`.txt`, `.xy`, `.dat`), and gives the
//! same region for the same shape.
use cvtmesh_geometry::{DVec2, GeometryError, LoopRole, Region};
use std::path::{Path, PathBuf};

/// A fresh directory under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> TempDir {
        let dir =
            std::env::temp_dir().join(format!("geometry-from-file-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The 4 × 4 square with the square hole [1, 2]² in every format.
const PROJECT_JSON: &str = r#"{"loops": [
  {"role": "outer", "segments": [{"kind": "polyline", "points": [[0,0],[4,0],[4,4],[0,4],[0,0]]}]},
  {"role": "hole", "segments": [{"kind": "polyline", "points": [[1,1],[1,2],[2,2],[2,1],[1,1]]}]}
]}"#;
const GEOJSON: &str = r#"{"type": "Polygon", "coordinates": [
  [[0,0],[4,0],[4,4],[0,4],[0,0]], [[1,1],[1,2],[2,2],[2,1],[1,1]]
]}"#;
const POLY: &str = "# square with a square hole\n\
    8 2 0 0\n\
    1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 1 1\n6 2 1\n7 2 2\n8 1 2\n\
    8 0\n\
    1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 8\n8 8 5\n\
    1\n1 1.5 1.5\n";
const LOOPS: &str = "# outer\n0 0\n4 0\n4 4\n0 4\n\n# hole\n1 1\n2 1\n2 2\n1 2\n";

fn assert_square_with_hole(r: &Region, what: &str) {
    assert_eq!(r.area(), 15.0, "{what}");
    assert_eq!(r.loops().len(), 2, "{what}");
    assert_eq!(r.loops()[0].role, LoopRole::Outer, "{what}");
    assert_eq!(r.loops()[1].role, LoopRole::Hole, "{what}");
    assert_eq!(r.corners().len(), 8, "{what}");
    assert_eq!(r.perimeter(), 20.0, "{what}");
    assert!(r.contains(DVec2::new(3.0, 3.0)), "{what}");
    assert!(!r.contains(DVec2::new(1.5, 1.5)), "{what}");
    assert!(
        (r.signed_distance(DVec2::new(3.0, 0.5)) + 0.5).abs() < 1e-15,
        "{what}"
    );
}

#[test]
fn every_format_gives_the_same_region() {
    let dir = TempDir::new("formats");
    let files = [
        dir.write("project.json", PROJECT_JSON),
        dir.write("geo.geojson", GEOJSON),
        dir.write("geo_as.json", GEOJSON),
        dir.write("triangle.poly", POLY),
        dir.write("loops.txt", LOOPS),
        dir.write("loops.XY", LOOPS),
        dir.write("loops.dat", &LOOPS.replace(' ', ", ")),
    ];
    for f in &files {
        let r = Region::from_file(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let stem = f.file_stem().unwrap().to_str().unwrap();
        assert_eq!(r.name(), stem);
        assert_square_with_hole(&r, stem);
    }
}

#[test]
fn the_project_schema_keeps_curved_pieces_and_the_file_name() {
    let dir = TempDir::new("curved");
    let p = dir.write(
        "disc.json",
        r#"{"loops": [{"segments": [{"kind": "circle", "center": [1, 2], "radius": 3}]}]}"#,
    );
    let r = Region::from_file(&p).unwrap();
    assert_eq!(r.name(), "disc");
    assert!((r.area() - 9.0 * std::f64::consts::PI).abs() < 1e-12);
    assert!(r.corners().is_empty());
    let named = dir.write(
        "x.json",
        &PROJECT_JSON.replacen('{', r#"{"name": "holey","#, 1),
    );
    assert_eq!(Region::from_file(&named).unwrap().name(), "holey");
    // The built-in files themselves.
    let hex = Path::new(env!("CARGO_MANIFEST_DIR")).join("regions/hex_hole.json");
    let r = Region::from_file(&hex).unwrap();
    let b = Region::builtin("hex_hole").unwrap();
    assert_eq!(
        (r.name(), r.area(), r.corners()),
        (b.name(), b.area(), b.corners())
    );
}

#[test]
fn other_extensions_are_read_as_json_or_rejected() {
    let dir = TempDir::new("other");
    let p = dir.write("region.cfg", PROJECT_JSON);
    assert_square_with_hole(&Region::from_file(&p).unwrap(), "region.cfg");
    let p = dir.write("noext", GEOJSON);
    assert_square_with_hole(&Region::from_file(&p).unwrap(), "noext");
    let p = dir.write("shape.stl", "solid x\nendsolid x\n");
    let e = Region::from_file(&p).unwrap_err().to_string();
    assert!(
        e.contains("'.stl'") && e.contains(".poly") && e.contains(".geojson"),
        "{e}"
    );
    let e = Region::from_file(&dir.0.join("missing.poly")).unwrap_err();
    assert!(matches!(e, GeometryError::Io { .. }), "{e}");
    // Each reader's errors name the file.
    let p = dir.write("bad.poly", "4 2 0 0\n1 0 0\n");
    let e = Region::from_file(&p).unwrap_err().to_string();
    assert!(e.contains("bad.poly"), "{e}");
    let p = dir.write("bad.txt", "0 0\n1\n");
    let e = Region::from_file(&p).unwrap_err().to_string();
    assert!(e.contains("bad.txt") && e.contains("line 2"), "{e}");
}

/// A byte-order mark at the start (what editors on Windows write) is not part of the text: every
/// format reads as without it.
#[test]
fn a_byte_order_mark_is_skipped() {
    let dir = TempDir::new("bom");
    for (name, text) in [
        ("bom.json", PROJECT_JSON),
        ("bom.geojson", GEOJSON),
        ("bom.poly", POLY),
        ("bom.txt", LOOPS),
    ] {
        let path = dir.write(name, &format!("\u{feff}{text}"));
        let r = Region::from_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_square_with_hole(&r.with_default_corners(), name);
    }
}

/// A disc given as two arcs that meet smoothly, its walls numbered by the segments' `marker`:
/// the junctions, which no turning makes corners, are corners (a mesh keeps a vertex there,
/// so no boundary edge lies on both walls), and each piece carries its wall's number, through
/// the command line's default corner angle too. Without markers the smooth junctions are no
/// corners.
#[test]
fn segment_markers_number_the_walls_and_keep_their_junctions() {
    let arcs = |m: [&str; 2]| {
        format!(
            r#"{{"loops": [{{"segments": [
            {{"kind": "arc", "center": [0, 0], "radius": 1, "from_deg": 0, "to_deg": 180{}}},
            {{"kind": "arc", "center": [0, 0], "radius": 1, "from_deg": 180, "to_deg": 360{}}}]}}]}}"#,
            m[0], m[1]
        )
    };
    let plain = Region::from_json_str(&arcs(["", ""]), "disc").unwrap();
    assert!(plain.corners().is_empty() && plain.piece_markers().is_none());
    let marked =
        Region::from_json_str(&arcs([r#", "marker": 7"#, r#", "marker": 9"#]), "disc").unwrap();
    for r in [marked.clone(), marked.with_default_corners()] {
        let mut at: Vec<(i64, i64)> = r
            .corners()
            .iter()
            .map(|c| (c.pos.x.round() as i64, c.pos.y.round() as i64))
            .collect();
        at.sort_unstable();
        assert_eq!(at, [(-1, 0), (1, 0)]);
        let mut markers = r.piece_markers().unwrap().to_vec();
        markers.sort_unstable();
        assert_eq!(markers, [7, 9]);
        // The upper arc is wall 7.
        let upper = r.project(DVec2::new(0.0, 1.0)).piece;
        assert_eq!(r.piece_markers().unwrap()[upper], 7);
    }
    // One segment marked: the other's pieces get 0, Triangle's "no marker".
    let one = Region::from_json_str(&arcs([r#", "marker": 7"#, ""]), "disc").unwrap();
    let mut markers = one.piece_markers().unwrap().to_vec();
    markers.sort_unstable();
    assert_eq!(markers, [0, 7]);
    let e = Region::from_json_str(&arcs([r#", "marker": 1.5"#, ""]), "disc").unwrap_err();
    assert!(e.to_string().contains("segments[0].marker is 1.5"), "{e}");
}

/// A `.poly`'s segments that leave the square keep their parts inside, as Triangle eats the
/// triangles outside and the segments with them: one from inside out, one through the whole
/// square (its vertices both outside), and one wholly outside; a note gives the length cut.
#[test]
fn a_poly_s_segments_leaving_the_region_keep_their_parts_inside() {
    let text = "9 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 0.5 0.25\n6 1.5 0.25\n\
                7 -0.5 0.5\n8 1.5 0.75\n9 2 2\n\
                7 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 7 8\n7 8 9\n0\n";
    let region = cvtmesh_geometry::formats::poly_from_str(text, "cut.poly", "cut").unwrap();
    let lines: Vec<Vec<DVec2>> = region
        .embedded_lines()
        .iter()
        .map(|l| l.points.clone())
        .collect();
    let v = DVec2::new;
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert_eq!(lines[0], [v(0.5, 0.25), v(1.0, 0.25)]);
    let through = &lines[1];
    assert_eq!(through.len(), 2);
    assert!(through[0].distance(v(0.0, 0.5625)) < 1e-15, "{through:?}");
    assert!(through[1].distance(v(1.0, 0.6875)) < 1e-15, "{through:?}");
    // The cuts are corners of the walls, where the lines end.
    for p in [lines[0][1], through[0], through[1]] {
        assert!(region.corners().iter().any(|c| c.pos == p), "{p}");
    }
    let cut =
        0.5 + (4.0f64 + 0.0625).sqrt() - (1.0f64 + 0.015625).sqrt() + (0.25f64 + 1.5625).sqrt();
    let note = region.notes().join("\n");
    assert!(note.contains(&format!("{cut:.6} of the")), "{note}");
}
