//! Wavefront `.obj`: `v x y 0` and 1-based `f a b c`.
use super::{
    file_err, planar_z, read_mesh_parts, read_text, validate_for_writing, write_files, Producer, F,
};
use crate::{Mesh, MeshError};
use geometry::DVec2;
use std::io::Write;
use std::path::Path;

/// Write `mesh` as Wavefront OBJ: one `v x y 0` line per vertex, one `f a b c` (1-based,
/// counter-clockwise) per triangle. Markers are not stored.
pub fn write_obj(mesh: &Mesh, path: &Path) -> Result<(), MeshError> {
    validate_for_writing(mesh, path)?;
    let produce: Producer = Box::new(|w: &mut dyn Write| {
        writeln!(
            w,
            "# cvtmesh: {} vertices, {} triangles",
            mesh.points.len(),
            mesh.triangles.len()
        )?;
        for p in &mesh.points {
            writeln!(w, "v {} {} 0", F(p.x), F(p.y))?;
        }
        for [a, b, c] in &mesh.triangles {
            writeln!(w, "f {} {} {}", a + 1, b + 1, c + 1)?;
        }
        Ok(())
    });
    write_files(vec![(path.to_path_buf(), produce)])
}

/// Read a Wavefront OBJ mesh: `v` lines (z must be 0 if present) and triangular `f` lines
/// (`a`, `a/t`, `a/t/n`, `a//n` and negative relative indices are accepted); other statements
/// are ignored, faces with more than three vertices are an error. Triangles come back
/// counter-clockwise; markers come from the mesh topology.
pub fn read_obj(path: &Path) -> Result<Mesh, MeshError> {
    parse(&read_text(path)?, path)
}

/// Parse the text of a Wavefront OBJ mesh, as [`read_obj`] reads a file; errors name
/// `mesh.obj`.
///
/// ```
/// let m = cvtmesh::io::obj_from_str("v 0 0\nv 1 0\nv 0 1\nf 1 2 3\n")?;
/// assert_eq!(m.num_triangles(), 1);
/// # Ok::<(), cvtmesh::MeshError>(())
/// ```
pub fn obj_from_str(text: &str) -> Result<Mesh, MeshError> {
    parse(text, Path::new("mesh.obj"))
}

fn parse(text: &str, path: &Path) -> Result<Mesh, MeshError> {
    let mut points = Vec::new();
    let mut triangles = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let err = |m: String| file_err(path, format!("line {}: {m}", i + 1));
        let line = line.split('#').next().unwrap_or("");
        let mut toks = line.split_whitespace();
        match toks.next() {
            Some("v") => {
                let mut c = Vec::new();
                for t in toks {
                    match t.parse::<f64>() {
                        Ok(v) if v.is_finite() => c.push(v),
                        _ => return Err(err(format!("bad vertex coordinate '{t}'"))),
                    }
                }
                if c.len() < 2 || c.len() > 4 {
                    return Err(err(format!(
                        "a vertex needs x y [z [w]], found {} numbers",
                        c.len()
                    )));
                }
                if c.len() >= 3 {
                    planar_z(c[2]).map_err(err)?;
                }
                points.push(DVec2::new(c[0], c[1]));
            }
            Some("f") => {
                let mut tri = Vec::with_capacity(3);
                for t in toks {
                    let first = t.split('/').next().unwrap_or("");
                    let k: i64 = first
                        .parse()
                        .map_err(|_| err(format!("bad face index '{t}'")))?;
                    // Negative indices count back from the latest vertex.
                    let n = points.len() as i64;
                    let idx = if k > 0 { k - 1 } else { n + k };
                    if k == 0 || idx < 0 || idx >= n {
                        return Err(err(format!(
                            "face index {k} is out of range ({n} vertices so far)"
                        )));
                    }
                    tri.push(idx as u32);
                }
                if tri.len() != 3 {
                    return Err(err(format!(
                        "face with {} vertices; only triangles are supported",
                        tri.len()
                    )));
                }
                triangles.push([tri[0], tri[1], tri[2]]);
            }
            _ => {}
        }
    }
    Ok(read_mesh_parts(points, triangles, None))
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    #[test]
    fn round_trip_preserves_points_triangles_and_loops() {
        assert_round_trip_keeps_loops("sq.obj", write_obj, read_obj);
    }

    #[test]
    fn reads_foreign_syntax() {
        let text = "o thing\nv 0 0 0\nv 1 0\nvt 0 0\nv 1 1 0 1\nf 1/1 3//1 2/1/1\nf -3 -2 -1\n";
        let r = parse(text, Path::new("f.obj")).unwrap();
        assert_eq!(r.points.len(), 3);
        assert_eq!(r.triangles, [[0, 1, 2], [0, 1, 2]]);
    }

    #[test]
    fn bad_files_give_errors_with_line_numbers() {
        let cases = [
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 1\n",
                "line 4: face with 4 vertices",
            ),
            ("v 0 0 0\nf 1 2 3\n", "line 2: face index 2 is out of range"),
            ("v 0 0 0\nf 0 1 1\n", "face index 0"),
            ("v 0 0 1\n", "line 1: z = 1"),
            ("v 0 nan\n", "bad vertex coordinate 'nan'"),
            ("v 0\n", "a vertex needs x y"),
            ("v 0 0\nf a b c\n", "bad face index 'a'"),
        ];
        for (text, want) in cases {
            let e = parse(text, Path::new("bad.obj")).unwrap_err().to_string();
            assert!(e.contains(want), "{e:?} should contain {want:?}");
        }
    }

    proptest::proptest! {
        #[test]
        fn random_text_never_panics(text in "[vf0-9 ./\n-]{0,200}") {
            let _ = parse(&text, Path::new("r.obj"));
        }
    }
}
