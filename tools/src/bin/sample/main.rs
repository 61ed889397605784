//! Draws a 2×3 sample figure of an annulus (region alone, a mesh, the mesh coloured by each
//! triangle's minimum angle, at two densities) plus thin regions, to check the pictures by eye.
//!
//! `cargo run -p cvtmesh-tools --bin sample -- OUT.png` (also writes OUT.svg, and the paper's ten
//! regions as OUT_regions.png, beside it).
// Shared with the render crate's tests, which draw the same mesh.
#[path = "../../../../crates/render/tests/support/polar.rs"]
mod polar;

use geometry::{DVec2, LoopRole, Piece, Region};
use render::{Layout, Panel};
use std::path::PathBuf;

fn min_angles(m: &mesh::Mesh) -> Vec<f64> {
    (0..m.num_triangles())
        .map(|t| mesh::triangle_min_angle_deg(m.triangle(t)))
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "render_sample.png".into()),
    );
    let c = DVec2::ZERO;
    let annulus = Region::new(
        "annulus",
        vec![
            (
                LoopRole::Outer,
                vec![Piece::Circle {
                    center: c,
                    radius: 1.0,
                    ccw: true,
                }],
            ),
            (
                LoopRole::Hole,
                vec![Piece::Circle {
                    center: c,
                    radius: 0.4,
                    ccw: false,
                }],
            ),
        ],
        None,
    )?;
    let coarse = polar::annulus_mesh(c, 0.4, 1.0, 0.1);
    let fine = polar::annulus_mesh(c, 0.4, 1.0, 0.025);
    let v = DVec2::new;
    let line = |a, b| Piece::Line { a, b };
    let strip = Region::new(
        "strip 4:1",
        vec![(
            LoopRole::Outer,
            vec![
                line(v(0.0, 0.0), v(4.0, 0.0)),
                line(v(4.0, 0.0), v(4.0, 1.0)),
                line(v(4.0, 1.0), v(0.0, 1.0)),
                line(v(0.0, 1.0), v(0.0, 0.0)),
            ],
        )],
        None,
    )?;
    // A thin pie slice: two radii and a 20° arc.
    let (a0, a1) = (80f64.to_radians(), 100f64.to_radians());
    let slice = Region::new(
        "slice",
        vec![(
            LoopRole::Outer,
            vec![
                line(v(0.0, 0.0), v(a0.cos(), a0.sin())),
                Piece::Arc {
                    center: v(0.0, 0.0),
                    radius: 1.0,
                    from: a0,
                    to: a1,
                },
                line(v(a1.cos(), a1.sin()), v(0.0, 0.0)),
            ],
        )],
        None,
    )?;
    let panels = [
        Panel::new("annulus (region only)", &annulus),
        Panel::new(
            format!("annulus, {} vertices", coarse.num_vertices()),
            &annulus,
        )
        .with_mesh(&coarse),
        Panel::new("minimum angle", &annulus)
            .with_mesh(&coarse)
            .with_colour(min_angles(&coarse), "min angle (°)"),
        Panel::new(format!("{} triangles", fine.num_triangles()), &annulus)
            .with_mesh(&fine)
            .with_colour(min_angles(&fine), "min angle (°)"),
        Panel::new("strip 4:1", &strip),
        Panel::new("pie slice 20°", &slice),
    ];
    let layout = Layout::new(3)
        .panel_px(360)
        .title("render sample: annulus r = 0.4 … 1");
    let t = std::time::Instant::now();
    render::render_png(&panels, &layout, &out)?;
    render::render_svg(&panels, &layout, &out.with_extension("svg"))?;
    eprintln!("wrote {} and .svg in {:.2?}", out.display(), t.elapsed());

    // The paper's ten regions, as `cvtmesh show` draws them.
    let regions = Region::builtin_names()
        .iter()
        .map(|n| Region::builtin(n))
        .collect::<Result<Vec<_>, _>>()?;
    let panels: Vec<Panel> = regions.iter().map(|r| Panel::new(r.name(), r)).collect();
    let all = out.with_file_name(format!(
        "{}_regions.png",
        out.file_stem()
            .map(|s| s.to_string_lossy())
            .unwrap_or_default()
    ));
    render::render_png(
        &panels,
        &Layout::new(5).panel_px(220).title("The ten regions"),
        &all,
    )?;
    eprintln!("wrote {}", all.display());
    Ok(())
}
