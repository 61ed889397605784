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
                }
                Err(e) => print!(" {a}°: failed ({e}) |"),
            }
        }
        println!();
    }
    Ok(())
}
