//! Which minimum-angle bound makes our TRIANGLE (`refine`) look like the paper's: for every
//! paper table, K, β and q of `refine` at several bounds, next to the paper's TRIANGLE column.
//!
//! `cargo run --release -p study --example triangle_angle [-- 20,25,28,30,33]`
use cvtmesh::{MeshRequest, Mesher, Refine, Region};
use study::paper::{PaperTables, TABLES};
use study::{Measure, MethodId};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let angles: Vec<f64> = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "20,25,28,30,33".into())
        .split(',')
        .map(|a| a.trim().parse())
        .collect::<Result<_, _>>()?;
    let paper = PaperTables::embedded()?;
    let value = |t: u8, m: Measure| {
        paper
            .cell(t, m, MethodId::Triangle)
            .map_or(f64::NAN, |c| c.value)
    };
    println!("table region K | paper K β q | per bound: K β q");
    let mut worst = Vec::new();
    for t in &TABLES {
        let region = Region::builtin(t.region)?;
        print!(
            "{:2} {:14} {:4} | {:4} {:.2} {:.2} |",
            t.number,
            t.region,
            t.k,
            value(t.number, Measure::K),
            value(t.number, Measure::Beta),
            value(t.number, Measure::Q)
        );
        for &a in &angles {
            let r = Refine {
                min_angle_deg: a,
                ..Refine::default()
            };
            match r.mesh(&region, &MeshRequest::points(t.k), &mut |_| {}) {
                Ok(res) => {
                    let m = cvtmesh::measures(&res.mesh, &region)?;
                    print!(" {a}°: {} {:.2} {:.2} |", m.k, m.beta, m.q);
                    if a == angles[0] {
                        worst.push((t.number, smallest_angle(&res.mesh)));
                    }
                }
                Err(e) => print!(" {a}°: failed ({e}) |"),
            }
        }
        println!();
    }
    println!("Smallest angle at the first bound, and where (its vertices' markers):");
    for (t, (deg, at)) in worst {
        println!("  table {t:2}: {deg:.1}° at {at}");
    }
    Ok(())
}

/// The smallest angle of the mesh in degrees, and its triangle's vertices with their markers.
fn smallest_angle(mesh: &cvtmesh::Mesh) -> (f64, String) {
    let mut best = (f64::INFINITY, String::new());
    for t in &mesh.triangles {
        let p = t.map(|v| mesh.points[v as usize]);
        let angle = |a: cvtmesh::DVec2, b: cvtmesh::DVec2, c: cvtmesh::DVec2| {
            let (u, v) = (b - a, c - a);
            u.perp_dot(v).abs().atan2(u.dot(v)).to_degrees()
        };
        let deg = angle(p[0], p[1], p[2])
            .min(angle(p[1], p[2], p[0]))
            .min(angle(p[2], p[0], p[1]));
        if deg < best.0 {
            let at = t
                .iter()
                .map(|&v| {
                    let q = mesh.points[v as usize];
                    let kind = match mesh.markers[v as usize] {
                        cvtmesh::VertexMarker::Interior => "interior",
                        cvtmesh::VertexMarker::Boundary { .. } => "boundary",
                        _ => "corner",
                    };
                    format!("({:.3}, {:.3}) {kind}", q.x, q.y)
                })
                .collect::<Vec<_>>()
                .join(", ");
            best = (deg, at);
        }
    }
    best
}
