//! The public API on real `Region`s: files written, true aspect ratio, holes left white,
//! boundary drawn dark.
use cvtmesh_render::{Layout, Panel, RenderError};
use geometry::{DVec2, LoopRole, Piece, Region};
use tiny_skia::Pixmap;

#[path = "support/polar.rs"]
mod polar;

fn annulus() -> Region {
    Region::new(
        "annulus",
        vec![
            (
                LoopRole::Outer,
                vec![Piece::Circle {
                    center: DVec2::new(3.0, -1.0),
                    radius: 1.0,
                    ccw: true,
                }],
            ),
            (
                LoopRole::Hole,
                vec![Piece::Circle {
                    center: DVec2::new(3.0, -1.0),
                    radius: 0.4,
                    ccw: false,
                }],
            ),
        ],
        None,
    )
    .unwrap()
}

fn rectangle(w: f64, h: f64) -> Region {
    let v = DVec2::new;
    let c = [v(0.0, 0.0), v(w, 0.0), v(w, h), v(0.0, h)];
    let pieces = (0..4)
        .map(|i| Piece::Line {
            a: c[i],
            b: c[(i + 1) % 4],
        })
        .collect();
    Region::new("rect", vec![(LoopRole::Outer, pieces)], None).unwrap()
}

fn temp_path(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("render-it-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Bounding box (x0, y0, x1, y1) of the non-white pixels.
fn ink_bbox(p: &Pixmap) -> (u32, u32, u32, u32) {
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for y in 0..p.height() {
        for x in 0..p.width() {
            let c = p.pixel(x, y).unwrap();
            if (c.red(), c.green(), c.blue()) != (255, 255, 255) {
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            }
        }
    }
    (x0, y0, x1, y1)
}

fn rgb(p: &Pixmap, x: f64, y: f64) -> [u8; 3] {
    let c = p.pixel(x as u32, y as u32).unwrap();
    [c.red(), c.green(), c.blue()]
}

/// 32 angles around a circle, none on an axis.
fn test_angles() -> impl Iterator<Item = f64> {
    (0..32).map(|k| std::f64::consts::TAU * (k as f64 + 0.25) / 32.0)
}

/// Check an untitled 300 px drawing of an annulus of radii 1 and 0.4 (all ink is the drawing,
/// so its bounding box gives the mapping): a disc 302 px across, white at the centre, dark on
/// both boundary circles. Returns the centre and the pixels per unit.
fn assert_annulus_drawn(pix: &Pixmap) -> (f64, f64, f64) {
    let (x0, y0, x1, y1) = ink_bbox(pix);
    let (w, h) = ((x1 - x0 + 1) as f64, (y1 - y0 + 1) as f64);
    assert!(
        (w - h).abs() <= 1.0 && (w - 302.0).abs() <= 2.0,
        "disc drawn {w}x{h}"
    );
    let (cx, cy) = (x0 as f64 + 0.5 * w, y0 as f64 + 0.5 * h);
    let s = 150.0; // pixels per unit: 300 px over the diameter 2
    assert_eq!(rgb(pix, cx, cy), [255, 255, 255], "hole centre");
    for a in test_angles() {
        for r in [1.0, 0.4] {
            let c = rgb(pix, cx + r * s * a.cos(), cy - r * s * a.sin());
            assert!(
                c.iter().all(|&v| v < 90),
                "boundary r={r} at angle {a}: {c:?}"
            );
        }
    }
    (cx, cy, s)
}

#[test]
fn annulus_png_has_white_hole_and_dark_boundary() {
    let region = annulus();
    let m = polar::annulus_mesh(DVec2::new(3.0, -1.0), 0.4, 1.0, 0.08);
    let panels = [Panel::new("", &region).with_mesh(&m)];
    let path = temp_path("annulus.png");
    cvtmesh_render::render_png(&panels, &Layout::new(1).panel_px(300), &path).unwrap();
    let pix = Pixmap::load_png(&path).unwrap();
    let (cx, cy, s) = assert_annulus_drawn(&pix);
    for a in test_angles() {
        // Inside the hole, away from its boundary: white.
        let c = rgb(&pix, cx + 0.3 * s * a.cos(), cy - 0.3 * s * a.sin());
        assert_eq!(c, [255, 255, 255]);
    }
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn annulus_mesh_alone_is_outlined_by_its_own_boundary() {
    let c = DVec2::new(3.0, -1.0);
    let m = polar::annulus_mesh(c, 0.4, 1.0, 0.08);
    let panels = [Panel::for_mesh("", &m)];
    let layout = Layout::new(1).panel_px(300);
    let pix = Pixmap::decode_png(&cvtmesh_render::png_bytes(&panels, &layout).unwrap()).unwrap();
    // The mesh's bounding box is the disc's (its outer ring has vertices at 0°, 90°, …).
    assert_annulus_drawn(&pix);
    // In SVG the boundary path has one segment per vertex of the two boundary rings.
    let on_ring = |r: f64| {
        m.points
            .iter()
            .filter(|p| ((**p - c).length() - r).abs() < 1e-9)
            .count()
    };
    let ring_vertices = on_ring(1.0) + on_ring(0.4);
    assert!(ring_vertices > 100, "{ring_vertices}");
    let doc = cvtmesh_render::svg_string(&panels, &layout).unwrap();
    let boundary: Vec<&str> = doc
        .lines()
        .filter(|l| l.contains(r#"class="boundary""#))
        .collect();
    assert_eq!(boundary.len(), 1);
    assert_eq!(boundary[0].matches('M').count(), ring_vertices);
    assert!(boundary[0].contains(r##"stroke="#000000""##));
}

#[test]
fn drawn_extent_has_the_regions_aspect_ratio() {
    for (w, h) in [(4.0, 1.0), (1.0, 4.0), (15.7, 6.0)] {
        let region = rectangle(w, h);
        let png =
            cvtmesh_render::png_bytes(&[Panel::new("", &region)], &Layout::new(1).panel_px(400))
                .unwrap();
        let pix = Pixmap::decode_png(&png).unwrap();
        let (x0, y0, x1, y1) = ink_bbox(&pix);
        // Minus the boundary stroke's overhang (1 px each side).
        let (dw, dh) = ((x1 - x0 - 1) as f64, (y1 - y0 - 1) as f64);
        assert!((dw.max(dh) - 400.0).abs() <= 1.5, "{w}x{h} drawn {dw}x{dh}");
        assert!(
            (dw / dh - w / h).abs() <= 0.02 * w / h,
            "{w}x{h} drawn {dw}x{dh}"
        );
    }
}

#[test]
fn svg_file_has_title_and_paths() {
    let region = annulus();
    let m = polar::annulus_mesh(DVec2::new(3.0, -1.0), 0.4, 1.0, 0.2);
    let angles = vec![45.0; m.num_triangles()];
    let panels = [
        Panel::new("region", &region),
        Panel::new("mesh & angles", &region)
            .with_mesh(&m)
            .with_colour(angles, "min angle"),
    ];
    let path = temp_path("fig.svg");
    cvtmesh_render::render_svg(
        &panels,
        &Layout::new(2).panel_px(200).title("Figure 5"),
        &path,
    )
    .unwrap();
    let doc = std::fs::read_to_string(&path).unwrap();
    assert!(doc.starts_with("<?xml") && doc.trim_end().ends_with("</svg>"));
    assert!(doc.contains(">Figure 5</text>") && doc.contains(">mesh &amp; angles</text>"));
    assert_eq!(doc.matches(r#"class="edges""#).count(), 1);
    assert_eq!(doc.matches(r#"class="boundary""#).count(), 2);
    // Two region tints, two boundaries, one edge path, one fill path (a single colour bin).
    assert_eq!(doc.matches("<path").count(), 6);
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn mismatched_colours_are_an_error_and_write_nothing() {
    let region = annulus();
    let m = polar::annulus_mesh(DVec2::new(3.0, -1.0), 0.4, 1.0, 0.2);
    let panels = [Panel::new("x", &region)
        .with_mesh(&m)
        .with_colour(vec![1.0; 3], "v")];
    let path = temp_path("never.png");
    let err = cvtmesh_render::render_png(&panels, &Layout::default(), &path).unwrap_err();
    assert!(
        matches!(
            err,
            RenderError::ColourCount {
                panel: 0,
                got: 3,
                ..
            }
        ),
        "{err}"
    );
    assert!(!path.exists());
}

#[test]
fn polar_mesh_fills_the_annulus_with_ccw_triangles() {
    let c = DVec2::new(3.0, -1.0);
    let m = polar::annulus_mesh(c, 0.4, 1.0, 0.05);
    let exact = std::f64::consts::PI * (1.0 - 0.16);
    assert!((m.area() - exact).abs() < 0.01 * exact, "area {}", m.area());
    for t in 0..m.num_triangles() {
        let [a, b, d] = m.triangle(t);
        assert!((b - a).perp_dot(d - a) > 0.0, "triangle {t} not CCW");
    }
    assert!(m.min_angle_deg() > 25.0, "{}", m.min_angle_deg());
}
