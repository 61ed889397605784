//! Subdomains: the parts a region's embedded lines cut it into, numbered by points inside them
//! (Triangle's regional attributes), are each triangle's number in the mesh and its files, and
//! come back from the files.
use cvtmesh::geometry::formats::poly_from_str;
use cvtmesh::geometry::predicates::orient;
use cvtmesh::io::{read_mesh_with_walls, write_mesh_on};
use cvtmesh::{region_of_mesh, subdomains, DVec2, MeshRequest, Method, Region};
use std::collections::BTreeMap;

/// A laminate of three layers, x < 0.3, 0.3 < x < 0.7, x > 0.7, the outer two numbered 10 and
/// the middle one 20 by its regional attributes (the third with an area constraint).
const LAMINATE: &str = "8 2 0 1\n1 0 0 0\n2 0.3 0 0\n3 0.7 0 0\n4 1 0 0\n5 1 1 0\n6 0.7 1 0\n\
    7 0.3 1 0\n8 0 1 0\n10 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 5 2\n5 5 6 3\n6 6 7 3\n7 7 8 3\n\
    8 8 1 4\n9 2 7 5\n10 3 6 5\n0\n3\n1 0.1 0.5 10 -1\n2 0.5 0.5 20 -1\n3 0.9 0.5 10 0.01\n";

/// The area of the triangles of each number.
fn area_by_number(mesh: &cvtmesh::Mesh, ids: &[i64]) -> BTreeMap<i64, f64> {
    let mut areas = BTreeMap::new();
    for (t, &id) in mesh.triangles.iter().zip(ids) {
        let [a, b, c] = t.map(|v| mesh.points[v as usize]);
        *areas.entry(id).or_insert(0.0) += 0.5 * orient(a, b, c);
    }
    areas
}

/// The unit square parted at x = 0.5 by a line marked 7, with the JSON `subdomains` given.
fn square_split_at_half(subdomains: &str) -> Region {
    let json = format!(
        r#"{{"loops": [{{"segments": [{{"kind": "polyline",
        "points": [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]}}]}}],
        "lines": [{{"points": [[0.5, 0], [0.5, 1]], "marker": 7}}],
        "subdomains": {subdomains}}}"#
    );
    Region::from_json_str(&json, "two").unwrap()
}

/// A fresh directory of this test process, named for `what`.
fn scratch(what: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("cvtmesh-{what}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn assert_layers(areas: &BTreeMap<i64, f64>, what: &str) {
    assert_eq!(areas.len(), 2, "{what}: {areas:?}");
    assert!((areas[&10] - 0.6).abs() < 1e-12, "{what}: {areas:?}");
    assert!((areas[&20] - 0.4).abs() < 1e-12, "{what}: {areas:?}");
}

#[test]
fn a_poly_s_regional_attributes_number_the_triangles_of_every_method() {
    let region = poly_from_str(LAMINATE, "laminate.poly", "laminate").unwrap();
    assert_eq!(region.subdomain_points().len(), 3);
    assert!(
        region
            .notes()
            .iter()
            .any(|n| n.contains("1 area constraint is not used")),
        "{:?}",
        region.notes()
    );
    for method in [
        Method::Ccvt,
        Method::Ccvt1,
        Method::Refine,
        Method::Distmesh,
    ] {
        let mesh = method
            .run(&region, &MeshRequest::points(400).seed(2))
            .unwrap_or_else(|e| panic!("{method}: {e}"))
            .mesh;
        let ids = subdomains(&mesh, &region).unwrap();
        assert_eq!(ids.len(), mesh.triangles.len());
        // No triangle straddles an interface: each number's triangles tile its layers.
        assert_layers(&area_by_number(&mesh, &ids), &method.to_string());
    }
}

#[test]
fn without_points_the_parts_are_numbered_from_the_left_whatever_the_method() {
    let region = poly_from_str(LAMINATE, "laminate.poly", "laminate").unwrap();
    let lines = region.embedded_lines().to_vec();
    let unnumbered = poly_from_str(
        &LAMINATE.replace(
            "\n3\n1 0.1 0.5 10 -1\n2 0.5 0.5 20 -1\n3 0.9 0.5 10 0.01\n",
            "\n0\n",
        ),
        "l.poly",
        "l",
    )
    .unwrap();
    assert!(unnumbered.subdomain_points().is_empty());
    assert_eq!(unnumbered.embedded_lines(), &lines[..]);
    for method in [Method::Ccvt, Method::Refine] {
        let mesh = method
            .run(&unnumbered, &MeshRequest::points(300))
            .unwrap()
            .mesh;
        let ids = subdomains(&mesh, &unnumbered).unwrap();
        let areas = area_by_number(&mesh, &ids);
        let expected = [(1, 0.3), (2, 0.4), (3, 0.3)];
        assert_eq!(areas.len(), 3, "{method}: {areas:?}");
        for (id, area) in expected {
            assert!((areas[&id] - area).abs() < 1e-12, "{method}: {areas:?}");
        }
    }
    // A region without lines is one subdomain.
    let square = Region::builtin("square_hole").unwrap();
    let mesh = cvtmesh::mesh(&square, 200).unwrap().mesh;
    assert!(subdomains(&mesh, &square)
        .unwrap()
        .iter()
        .all(|&id| id == 1));
}

#[test]
fn the_files_carry_the_numbers_and_a_new_mesh_of_a_file_keeps_them() {
    let region = poly_from_str(LAMINATE, "laminate.poly", "laminate").unwrap();
    let mesh = cvtmesh::mesh(&region, 300).unwrap().mesh;
    let dir = scratch("subdomains");
    for name in ["m.node", "m.msh", "m.vtu"] {
        let path = dir.join(name);
        write_mesh_on(&mesh, &region, &path).unwrap();
        let (read, walls) = read_mesh_with_walls(&path).unwrap();
        assert_eq!(walls.subdomains.len(), read.triangles.len(), "{name}");
        assert_layers(&area_by_number(&read, &walls.subdomains), name);
        // The region the file's triangles cover keeps the interfaces and the numbers: a new
        // mesh of it, three times as fine, numbers its layers as the first one did.
        let again = region_of_mesh(&read, &walls, &path).unwrap();
        assert_eq!(again.embedded_lines().len(), 2, "{name}");
        let finer = cvtmesh::mesh(&again, 900).unwrap().mesh;
        let ids = subdomains(&finer, &again).unwrap();
        assert_layers(
            &area_by_number(&finer, &ids),
            &format!("{name} meshed again"),
        );
    }
    // The .poly beside the .node lists a point in each subdomain with its number, as
    // Triangle's regional attributes: read as a region (Triangle's `-pA` input), it gives the
    // same numbers to a new mesh.
    let poly = Region::from_file(&dir.join("m.poly")).unwrap();
    let mut numbers: Vec<i64> = poly.subdomain_points().iter().map(|p| p.1).collect();
    numbers.sort_unstable();
    assert_eq!(numbers, [10, 10, 20]);
    let again = cvtmesh::mesh(&poly, 500).unwrap().mesh;
    let ids = subdomains(&again, &poly).unwrap();
    assert_layers(&area_by_number(&again, &ids), "the written .poly meshed");
    // VTK's cells carry them as a cell array.
    let vtu = dir.join("m.vtu");
    write_mesh_on(&mesh, &region, &vtu).unwrap();
    let text = std::fs::read_to_string(&vtu).unwrap();
    let ids = subdomains(&mesh, &region).unwrap();
    let array = text
        .split("Name=\"subdomain\" format=\"ascii\">\n")
        .nth(1)
        .and_then(|rest| rest.split("</DataArray>").next())
        .expect("a subdomain array");
    let written: Vec<i64> = array
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    assert_eq!(written, ids);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_region_without_lines_or_points_writes_its_files_as_before() {
    let square = Region::builtin("square_hole").unwrap();
    let mesh = cvtmesh::mesh(&square, 200).unwrap().mesh;
    let dir = scratch("no-subdomains");
    write_mesh_on(&mesh, &square, &dir.join("m.node")).unwrap();
    let ele = std::fs::read_to_string(dir.join("m.ele")).unwrap();
    assert!(ele
        .lines()
        .any(|l| l == format!("{} 3 0", mesh.triangles.len())));
    let (_, walls) = read_mesh_with_walls(&dir.join("m.node")).unwrap();
    assert!(walls.subdomains.is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_subdomain_points_are_refused_by_name() {
    let json = |subdomains: &str| {
        format!(
            r#"{{"loops": [{{"segments": [{{"kind": "polyline",
                "points": [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]}}]}}],
             "lines": [{{"points": [[0.5, 0], [0.5, 1]]}}],
             "subdomains": {subdomains}}}"#
        )
    };
    let ok = Region::from_json_str(&json(r#"[{"point": [0.25, 0.5], "id": 4}]"#), "r").unwrap();
    assert_eq!(ok.subdomain_points(), &[(DVec2::new(0.25, 0.5), 4)]);
    // A whole number written as a float is that number, as in a .poly.
    let float = Region::from_json_str(&json(r#"[{"point": [0.25, 0.5], "id": 4.0}]"#), "r");
    assert_eq!(float.unwrap().subdomain_points(), ok.subdomain_points());
    for (given, said) in [
        (r#"[{"point": [0.5, 0.5], "id": 4}]"#, "on an embedded line"),
        (r#"[{"point": [2, 0.5], "id": 4}]"#, "outside the region"),
        (
            r#"[{"point": [0, 0.5], "id": 4}]"#,
            "on the region's boundary",
        ),
        (
            r#"[{"point": [0.2, 0.5], "id": 1.5}]"#,
            "expected an integer",
        ),
        (r#"[{"point": [0.2, 0.5]}]"#, "missing field 'id'"),
        (r#"[{"point": [0.2, 0.5], "id": 9999999999}]"#, "32-bit"),
        (r#"{"point": [0.2, 0.5]}"#, "must be a list"),
    ] {
        let e = Region::from_json_str(&json(given), "r")
            .unwrap_err()
            .to_string();
        assert!(e.contains(said), "{given}: {e}");
    }
    // A .poly's attribute that is no whole number is refused, naming its line.
    let half = LAMINATE.replace("2 0.5 0.5 20 -1", "2 0.5 0.5 2.5 -1");
    let e = poly_from_str(&half, "l.poly", "l").unwrap_err().to_string();
    assert!(
        e.contains("regional attribute 2.5 is not a whole number"),
        "{e}"
    );
    assert!(e.contains("line 24"), "{e}");
    // A region without its attribute is refused, as Triangle refuses it.
    let bare = LAMINATE.replace("2 0.5 0.5 20 -1", "2 0.5 0.5");
    let e = poly_from_str(&bare, "l.poly", "l").unwrap_err().to_string();
    assert!(
        e.contains("missing a regional attribute") && e.contains("line 24"),
        "{e}"
    );
}

#[test]
fn subdomain_names_are_the_physical_surfaces_names_and_survive_a_new_mesh() {
    let region = square_split_at_half(
        r#"[{"point": [0.25, 0.5], "id": 10, "name": "steel"},
            {"point": [0.75, 0.5], "id": 20, "name": "rubber"}]"#,
    );
    assert_eq!(region.subdomain_name(10), Some("steel"));
    let mesh = cvtmesh::mesh(&region, 300).unwrap().mesh;
    let dir = scratch("subdomain-names");
    let first = dir.join("first.msh");
    write_mesh_on(&mesh, &region, &first).unwrap();
    let text = std::fs::read_to_string(&first).unwrap();
    assert!(text.contains("2 10 \"steel\"\n") && text.contains("2 20 \"rubber\"\n"));
    // Read back, meshed again and written: the same names on the same numbers.
    let (read, walls) = read_mesh_with_walls(&first).unwrap();
    let again = region_of_mesh(&read, &walls, &first).unwrap();
    assert_eq!(again.subdomain_name(20), Some("rubber"));
    let second = dir.join("second.msh");
    let finer = cvtmesh::mesh(&again, 600).unwrap().mesh;
    write_mesh_on(&finer, &again, &second).unwrap();
    let text = std::fs::read_to_string(&second).unwrap();
    assert!(text.contains("2 10 \"steel\"\n") && text.contains("2 20 \"rubber\"\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_catch_all_physical_surface_beside_the_materials_leaves_them_apart() {
    // Gmsh users often put every surface in a "domain" group as well as one per material:
    // each surface is then in two groups, and the catch-all one, listed first, made the whole
    // mesh one material.
    let region = square_split_at_half(
        r#"[{"point": [0.25, 0.5], "id": 10}, {"point": [0.75, 0.5], "id": 20}]"#,
    );
    let mesh = cvtmesh::mesh(&region, 200).unwrap().mesh;
    let dir = scratch("catch-all");
    let path = dir.join("two.msh");
    write_mesh_on(&mesh, &region, &path).unwrap();
    // Each surface entity's physical tags: the catch-all 100 first, then its material.
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let entities = lines.iter().position(|l| l == "$Entities").unwrap();
    let counts: Vec<usize> = lines[entities + 1]
        .split(' ')
        .map(|w| w.parse().unwrap())
        .collect();
    let surfaces = entities + 2 + counts[0] + counts[1];
    for line in &mut lines[surfaces..surfaces + counts[2]] {
        let w: Vec<&str> = line.split(' ').collect();
        assert_eq!(w[7], "1", "one physical tag: {line}");
        *line = [&w[..7], &["2", "100"], &w[8..]].concat().join(" ");
    }
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let (read, walls) = read_mesh_with_walls(&path).unwrap();
    let areas = area_by_number(&read, &walls.subdomains);
    assert_eq!(
        areas.keys().copied().collect::<Vec<_>>(),
        [10, 20],
        "{areas:?}"
    );
    assert!(areas.values().all(|a| (a - 0.5).abs() < 1e-12), "{areas:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_named_line_and_a_name_with_quotes_are_written_so_gmsh_reads_them() {
    // A solver selects the interface by its name: the .msh names the line's physical curve as
    // the region names its marker, and a double quote in a name (which would end it for Gmsh)
    // becomes a single one.
    let region =
        square_split_at_half(r#"[{"point": [0.25, 0.5], "id": 10, "name": "my \"rock\""}]"#)
            .with_marker_names([(7, "interface".to_string())]);
    let mesh = cvtmesh::mesh(&region, 200).unwrap().mesh;
    let dir = scratch("line-names");
    let path = dir.join("two.msh");
    write_mesh_on(&mesh, &region, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("1 7 \"interface\"\n"), "{text}");
    assert!(text.contains("2 10 \"my 'rock'\"\n"));
    let (_, walls) = read_mesh_with_walls(&path).unwrap();
    assert_eq!(
        walls.subdomain_names.get(&10).map(String::as_str),
        Some("my 'rock'")
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
