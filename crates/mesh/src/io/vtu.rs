//! VTK XML unstructured grid (`.vtu`, ASCII), for ParaView and meshio.
use super::{validate_for_writing, write_files, Nodes, Producer, F};
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
}
