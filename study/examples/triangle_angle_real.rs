//! Which `-q` bound the paper's Triangle runs used: the real Triangle (through
//! `scripts/real_peers.py`, given the boundary two ways) and our TRIANGLE (`refine`) at several
//! bounds on every paper table, scored by the exact measures, against the paper's TRIANGLE
//! column (τ and d at the paper's length scale; Table 6's misprinted γ and h left out).
//!
//! `cargo run --release -p study --example triangle_angle_real [-- 20,25,28,30 [PYTHON]]`
//! (PYTHON: an interpreter with triangle and gmsh; default as `study --real-peers`).
use cvtmesh::{MeshRequest, Mesher, Refine, Region};
use study::paper::{untrustworthy, PaperTables, TABLES};
use study::peers::{self, at_paper_scale, Peer, TriangleSettings};
use study::{Measure, MethodId};

/// "Near": within ±30 % of the value compared with, as `fidelity.md` counts.
const NEAR: f64 = 0.30;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let angles: Vec<f64> = args
        .next()
        .unwrap_or_else(|| "20,25,28,30".into())
        .split(',')
        .map(|a| a.trim().parse())
        .collect::<Result<_, _>>()?;
    let python = args
        .next()
        .map_or_else(peers::default_python, std::path::PathBuf::from);
    let tools = peers::check_python(&python)?;
    let paper = PaperTables::embedded()?;
    let scratch = std::env::temp_dir().join(format!("triangle-angle-real-{}", std::process::id()));
    // real: Triangle splits its boundary, straight edges given whole (as `--real-peers`);
    // real h: straight edges given split at the spacing of K too; real h -Y: that boundary
    // kept as given; ours: refine.
    let variants = ["real", "real h", "real h -Y", "ours"];
    // values[angle][variant][table] = the 14 measures (NaN when a run failed).
    let mut values = vec![vec![Vec::new(); variants.len()]; angles.len()];
    println!("table region K | paper K β q | per bound and variant: K β q");
    for t in &TABLES {
        let region = Region::builtin(t.region)?;
        let cell = |m| {
            paper
                .cell(t.number, m, MethodId::Triangle)
                .map_or(f64::NAN, |c| c.value)
        };
        print!(
            "{:2} {:14} {:4} | {:4} {:.2} {:.2} |",
            t.number,
            t.region,
            t.k,
            cell(Measure::K),
            cell(Measure::Beta),
            cell(Measure::Q)
        );
        for (ai, &a) in angles.iter().enumerate() {
            for (vi, v) in variants.iter().enumerate() {
                let row: [f64; 14] = match *v {
                    "ours" => {
                        let r = Refine {
                            min_angle_deg: a,
                            ..Refine::default()
                        };
                        let res = r.mesh(&region, &MeshRequest::points(t.k), &mut |_| {})?;
                        cvtmesh::measures(&res.mesh, &region)?.values()
                    }
                    _ => {
                        let settings = TriangleSettings {
                            min_angle_deg: a,
                            split_boundary: !v.ends_with("-Y"),
                            sample_straight: v.contains(" h"),
                        };
                        match peers::run_peer(&tools, &scratch, t, Peer::Triangle, &settings) {
                            Ok(r) => Measure::ALL.map(|m| r.value(m)),
                            Err(e) => {
                                eprintln!("table {} at {a}° ({v}): {e}", t.number);
                                [f64::NAN; 14]
                            }
                        }
                    }
                };
                print!(
                    " {a}° {v}: {:.0} {:.2} {:.2} |",
                    row[Measure::K.index()],
                    row[Measure::Beta.index()],
                    row[Measure::Q.index()]
                );
                values[ai][vi].push((t, row));
            }
        }
        println!();
    }
    let _ = std::fs::remove_dir_all(&scratch);

    println!("\nThe paper's TRIANGLE numbers within ±30 % of each variant's (n of cells), and the median of paper ÷ variant:");
    let shown = [Measure::Beta, Measure::Q, Measure::Alpha, Measure::P];
    print!("bound variant    |");
    for m in shown {
        print!(" {:>14} |", m.symbol());
    }
    println!(" {:>14} |", "all 12");
    for (ai, &a) in angles.iter().enumerate() {
        for (vi, v) in variants.iter().enumerate() {
            print!("{a:>4}° {v:<10} |");
            let stat = |ms: &[Measure]| {
                let mut near = 0;
                let mut n = 0;
                let mut ratios = Vec::new();
                for (t, row) in &values[ai][vi] {
                    for &m in ms {
                        let Some(c) = paper.cell(t.number, m, MethodId::Triangle) else {
                            continue;
                        };
                        if untrustworthy(t.number, m) {
                            continue;
                        }
                        let x = at_paper_scale(t.region, m, row[m.index()]);
                        n += 1;
                        if (c.value - x).abs() <= NEAR * x.abs() {
                            near += 1;
                        }
                        if (c.value / x).is_finite() {
                            ratios.push(c.value / x);
                        }
                    }
                }
                ratios.sort_by(f64::total_cmp);
                format!("{near:>3}/{n:<3} {:>5.2}", study::fidelity::median(&ratios))
            };
            for m in shown {
                print!(" {:>14} |", stat(&[m]));
            }
            println!(" {:>14} |", stat(&Measure::QUALITY));
        }
    }
    Ok(())
}
