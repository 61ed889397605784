//! Tests of the drawing on polygons given directly (independent of `Region`'s geometry).
use crate::frame::{self, Frame};
use crate::scene::{self, format_value, unique_edges, Scene};
use crate::text::Fonts;
use crate::{colormap, png, svg, write_atomic, Layout, RenderError, BOUNDARY_COLOUR};
use geometry::{DVec2, Polygon, Ring};
use mesh::{Mesh, VertexMarker};
use tiny_skia::Pixmap;

fn ring(points: Vec<DVec2>, loop_index: usize, hole: bool) -> Ring {
    let n = points.len();
    Ring {
        points,
        pieces: vec![loop_index; n],
        loop_index,
        hole,
    }
}

fn circle(c: DVec2, r: f64, n: usize, ccw: bool) -> Vec<DVec2> {
    let s = if ccw { 1.0 } else { -1.0 };
    (0..n)
        .map(|i| {
            let a = s * std::f64::consts::TAU * i as f64 / n as f64;
            c + r * DVec2::new(a.cos(), a.sin())
        })
        .collect()
}

fn rect(w: f64, h: f64) -> Polygon {
    let pts = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(w, 0.0),
        DVec2::new(w, h),
        DVec2::new(0.0, h),
    ];
    Polygon {
        rings: vec![ring(pts, 0, false)],
    }
}

fn annulus() -> Polygon {
    Polygon {
        rings: vec![
            ring(circle(DVec2::ZERO, 2.0, 256, true), 0, false),
            ring(circle(DVec2::ZERO, 0.8, 128, false), 1, true),
        ],
    }
}

/// The square [0,4]² with the square hole [1.5,2.5]², and an 8-triangle mesh of it.
fn square_with_hole() -> (Polygon, Mesh) {
    let v = |x, y| DVec2::new(x, y);
    let outer = vec![v(0.0, 0.0), v(4.0, 0.0), v(4.0, 4.0), v(0.0, 4.0)];
    let inner_ccw = vec![v(1.5, 1.5), v(2.5, 1.5), v(2.5, 2.5), v(1.5, 2.5)];
    let mut inner_cw = inner_ccw.clone();
    inner_cw.reverse();
    let poly = Polygon {
        rings: vec![ring(outer.clone(), 0, false), ring(inner_cw, 1, true)],
    };
    let points: Vec<DVec2> = outer.into_iter().chain(inner_ccw).collect();
    let triangles = vec![
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    let markers = (0..8)
        .map(|i| VertexMarker::Corner {
            loop_index: i / 4,
            corner: i,
            loop_param: 0.0,
        })
        .collect();
    (
        poly,
        Mesh {
            points,
            triangles,
            markers,
        },
    )
}

fn scene<'a>(
    title: &str,
    poly: &Polygon,
    mesh: Option<&'a Mesh>,
    colour: Option<&[f64]>,
    px: u32,
) -> Scene<'a> {
    let p = poly.clone();
    scene::build(
        0,
        title,
        Some((poly.bbox(), &move |_| p.clone())),
        mesh,
        colour,
        Some("value"),
        px,
    )
    .unwrap()
}

fn render(scenes: &[Scene], layout: &Layout) -> (Pixmap, Frame) {
    let fonts = Fonts::load().unwrap();
    let frame = frame::compute(scenes, layout, &fonts);
    (png::draw(scenes, layout).unwrap(), frame)
}

fn rgb(p: &Pixmap, x: f32, y: f32) -> [u8; 3] {
    let c = p.pixel(x.floor() as u32, y.floor() as u32).unwrap();
    [c.red(), c.green(), c.blue()]
}

fn is_dark(c: [u8; 3]) -> bool {
    c.iter().all(|&v| v < 90)
}

fn close(a: [u8; 3], b: [u8; 3], tol: u8) -> bool {
    a.iter().zip(&b).all(|(x, y)| x.abs_diff(*y) <= tol)
}

/// Bounding box (x0, y0, x1, y1) of non-white pixels in rows y_from.. of the picture.
fn ink_bbox(p: &Pixmap, y_from: u32) -> (u32, u32, u32, u32) {
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for y in y_from..p.height() {
        for x in 0..p.width() {
            let c = p.pixel(x, y).unwrap();
            if (c.red(), c.green(), c.blue()) != (255, 255, 255) {
                x0 = x0.min(x);
                y0 = y0.min(y);
                x1 = x1.max(x);
                y1 = y1.max(y);
            }
        }
    }
    (x0, y0, x1, y1)
}

#[test]
fn png_has_frame_size_and_true_aspect_ratio() {
    for (w, h) in [(4.0, 1.0), (1.0, 4.0), (15.7, 6.0)] {
        let poly = rect(w, h);
        let s = [scene("", &poly, None, None, 400)];
        let layout = Layout::new(1).panel_px(400);
        let (pix, frame) = render(&s, &layout);
        assert_eq!((pix.width(), pix.height()), (frame.width, frame.height));
        let bytes = pix.encode_png().unwrap();
        let back = Pixmap::decode_png(&bytes).unwrap();
        assert_eq!((back.width(), back.height()), (frame.width, frame.height));
        // The title is empty, so the only ink is the region (tint + boundary stroke, which
        // overhangs the rectangle by half its width on each side).
        let (x0, y0, x1, y1) = ink_bbox(&pix, 0);
        let (dw, dh) = ((x1 - x0 + 1) as f64 - 2.0, (y1 - y0 + 1) as f64 - 2.0);
        assert!(
            (dw.max(dh) - 400.0).abs() <= 1.5,
            "{w}x{h}: drawn {dw}x{dh}"
        );
        assert!(
            (dw / dh - w / h).abs() < 0.02 * (w / h),
            "{w}x{h}: drawn {dw}x{dh}"
        );
    }
}

#[test]
fn boundary_is_dark_hole_is_white_interior_is_tinted() {
    let poly = annulus();
    let s = [scene("annulus", &poly, None, None, 300)];
    let layout = Layout::new(1).panel_px(300);
    let (pix, frame) = render(&s, &layout);
    let pf = &frame.panels[0];
    for r in &poly.rings {
        for p in r.points.iter().step_by(8) {
            let (x, y) = pf.to_px(*p);
            let c = rgb(&pix, x, y);
            assert!(is_dark(c), "boundary pixel at {p} is {c:?}");
        }
    }
    let (cx, cy) = pf.to_px(DVec2::ZERO);
    assert_eq!(
        rgb(&pix, cx, cy),
        [255, 255, 255],
        "hole centre must stay white"
    );
    let (ax, ay) = pf.to_px(DVec2::new(0.0, 1.4));
    assert_eq!(rgb(&pix, ax, ay), layout.region_tint);
    let (ox, oy) = pf.to_px(DVec2::new(1.9, 1.9));
    assert_eq!(
        rgb(&pix, ox, oy),
        [255, 255, 255],
        "outside the disc must be white"
    );
    assert_eq!(BOUNDARY_COLOUR, [0, 0, 0]);
}

#[test]
fn mesh_edges_drawn_and_hole_left_empty() {
    let (poly, mesh) = square_with_hole();
    let s = [scene("mesh", &poly, Some(&mesh), None, 200)];
    let layout = Layout::new(1).panel_px(200).mesh_stroke_px(1.0);
    let (pix, frame) = render(&s, &layout);
    let pf = &frame.panels[0];
    let (cx, cy) = pf.to_px(DVec2::new(2.0, 2.0));
    assert_eq!(rgb(&pix, cx, cy), [255, 255, 255]);
    // The midpoint of the diagonal edge 0–5 lies on a mesh edge: darker than the tint.
    let (ex, ey) = pf.to_px((mesh.points[0] + mesh.points[5]) * 0.5);
    let c = rgb(&pix, ex, ey);
    assert!(c[0] < layout.region_tint[0] - 60, "edge pixel {c:?}");
    // Well inside a triangle, away from edges: plain tint.
    let [a, b, d] = mesh.triangle(0);
    let (tx, ty) = pf.to_px((a + b + d) / 3.0);
    assert_eq!(rgb(&pix, tx, ty), layout.region_tint);
}

/// A scene of `mesh` alone, as `Panel::for_mesh` gives.
fn mesh_scene<'a>(mesh: &'a Mesh, colour: Option<&[f64]>, px: u32) -> Scene<'a> {
    scene::build(0, "mesh", None, Some(mesh), colour, Some("value"), px).unwrap()
}

#[test]
fn boundary_edges_of_a_mesh_with_a_hole_are_its_loops_edges() {
    let (_, mut mesh) = square_with_hole();
    // Vertices 0–3 are the outer square, 4–7 the hole, each in order around its loop.
    let loops = |first: u32| (0..4).map(move |i| (first + i, first + (i + 1) % 4));
    let mut expected: Vec<(u32, u32)> = loops(0)
        .chain(loops(4))
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    expected.sort_unstable();
    assert_eq!(scene::boundary_edges(&mesh), expected);
    // Orientation and vertex order within a triangle do not matter.
    mesh.triangles[3].reverse();
    mesh.triangles[6].rotate_left(1);
    assert_eq!(scene::boundary_edges(&mesh), expected);
    // Dropping a triangle opens its two inner edges to the boundary and closes none.
    let [a, b, c] = mesh.triangles.remove(0);
    let got = scene::boundary_edges(&mesh);
    assert_eq!(got.len(), expected.len() + 1, "{got:?}");
    assert!(!got.contains(&(a.min(b), a.max(b))), "{got:?}");
    for (p, q) in [(b, c), (c, a)] {
        assert!(got.contains(&(p.min(q), p.max(q))), "{got:?}");
    }
}

#[test]
fn mesh_alone_is_framed_by_its_box_and_outlined_by_its_boundary_edges() {
    let (poly, mesh) = square_with_hole();
    let s = [mesh_scene(&mesh, None, 200)];
    assert_eq!((s[0].lo, s[0].hi), poly.bbox());
    assert_eq!(s[0].scale, 200.0 / 4.0);
    let layout = Layout::new(1)
        .panel_px(200)
        .mesh_stroke_px(1.0)
        .boundary_stroke_px(6.0);
    let (pix, frame) = render(&s, &layout);
    let pf = &frame.panels[0];
    let px = |p: DVec2| pf.to_px(p);
    // 2 px inside the outer and the hole boundary: within the thick boundary stroke.
    let off = 2.0 / 50.0;
    for p in [
        DVec2::new(1.0, off),
        DVec2::new(4.0 - off, 3.0),
        DVec2::new(2.0, 1.5 - off),
        DVec2::new(2.5 + off, 2.2),
    ] {
        let (x, y) = px(p);
        let c = rgb(&pix, x, y);
        assert!(is_dark(c), "boundary pixel at {p} is {c:?}");
    }
    // 2 px beside the interior edge 0–5: not in the boundary style.
    let mid = (mesh.points[0] + mesh.points[5]) * 0.5;
    let (x, y) = px(mid + DVec2::new(off, -off));
    let c = rgb(&pix, x, y);
    assert!(!is_dark(c), "interior edge drawn as boundary: {c:?}");
    // The triangles are tinted, the hole is not.
    let [a, b, d] = mesh.triangle(0);
    let (x, y) = px((a + b + d) / 3.0);
    assert_eq!(rgb(&pix, x, y), layout.region_tint);
    let (x, y) = px(DVec2::new(2.0, 2.0));
    assert_eq!(rgb(&pix, x, y), [255, 255, 255]);

    let doc = svg::draw(&s, &layout).unwrap();
    check_xml(&doc).unwrap_or_else(|e| panic!("malformed SVG: {e}\n{doc}"));
    let boundary = doc
        .lines()
        .find(|l| l.contains(r#"class="boundary""#))
        .unwrap();
    assert_eq!(boundary.matches('M').count(), 8, "{boundary}");
    let tint = doc
        .lines()
        .find(|l| l.contains(r#"class="region""#))
        .unwrap();
    assert_eq!(
        tint.matches('Z').count(),
        8,
        "one tinted subpath per triangle"
    );
}

#[test]
fn mesh_alone_coloured_draws_fills_bar_and_boundary() {
    let (_, mesh) = square_with_hole();
    let values: Vec<f64> = (0..8).map(|i| 30.0 + i as f64).collect();
    let s = [mesh_scene(&mesh, Some(&values), 200)];
    let layout = Layout::new(1).panel_px(200);
    let (pix, frame) = render(&s, &layout);
    let pf = &frame.panels[0];
    assert!(pf.bar.is_some());
    let [a, b, d] = mesh.triangle(7);
    let (x, y) = pf.to_px((a + b + d) / 3.0);
    assert_eq!(rgb(&pix, x, y), colormap::viridis(1.0));
    let (x, y) = pf.to_px(DVec2::new(0.0, 2.0));
    assert!(is_dark(rgb(&pix, x, y)));
    let doc = svg::draw(&s, &layout).unwrap();
    assert_eq!(doc.matches(r#"class="boundary""#).count(), 1);
    assert_eq!(
        doc.matches(r#"class="region""#).count(),
        0,
        "the colour fills replace the tint"
    );
}

#[test]
fn colour_by_fills_triangles_and_draws_bar() {
    let (poly, mesh) = square_with_hole();
    let values: Vec<f64> = (0..8).map(|i| 30.0 + i as f64).collect();
    let s = [scene("colours", &poly, Some(&mesh), Some(&values), 200)];
    let layout = Layout::new(1).panel_px(200);
    let (pix, frame) = render(&s, &layout);
    let pf = &frame.panels[0];
    let centroid_px = |t: usize| {
        let [a, b, c] = mesh.triangle(t);
        pf.to_px((a + b + c) / 3.0)
    };
    let (x, y) = centroid_px(0);
    assert_eq!(rgb(&pix, x, y), colormap::viridis(0.0));
    let (x, y) = centroid_px(7);
    assert_eq!(rgb(&pix, x, y), colormap::viridis(1.0));
    let (x, y) = centroid_px(4);
    assert_eq!(
        rgb(&pix, x, y),
        colormap::bin_colour(colormap::bin(34.0, 30.0, 37.0).unwrap())
    );

    let bar = pf.bar.as_ref().expect("colour bar");
    let (bx, by, bw, bh) = bar.rect;
    assert!(close(
        rgb(&pix, bx + 1.5, by + 0.5 * bh),
        colormap::viridis(0.0),
        6
    ));
    assert!(close(
        rgb(&pix, bx + bw - 1.5, by + 0.5 * bh),
        colormap::viridis(1.0),
        6
    ));
    let labels: Vec<&str> = bar.texts.iter().map(|t| t.text.as_str()).collect();
    assert_eq!(labels, ["value", "30", "37"]);
    // The labels are drawn: dark pixels inside each text box.
    let fonts = Fonts::load().unwrap();
    for t in &bar.texts {
        assert!(
            dark_pixels(&pix, t.x, t.top(&fonts), t.width, t.size) > 5,
            "label {:?} not drawn",
            t.text
        );
    }
}

#[test]
fn nan_values_are_grey_and_all_nan_is_accepted() {
    let (poly, mesh) = square_with_hole();
    let mut values = vec![f64::NAN; 8];
    let s = [scene("nan", &poly, Some(&mesh), Some(&values), 200)];
    let (pix, frame) = render(&s, &Layout::new(1).panel_px(200));
    let [a, b, c] = mesh.triangle(3);
    let (x, y) = frame.panels[0].to_px((a + b + c) / 3.0);
    assert_eq!(rgb(&pix, x, y), crate::NO_DATA_COLOUR);
    let texts: Vec<&str> = frame.panels[0]
        .bar
        .as_ref()
        .unwrap()
        .texts
        .iter()
        .map(|t| t.text.as_str())
        .collect();
    assert_eq!(texts, ["value", "n/a", "n/a"]);
    values[2] = 1.0;
    let s = [scene("one", &poly, Some(&mesh), Some(&values), 200)];
    let (pix, frame) = render(&s, &Layout::new(1).panel_px(200));
    let [a, b, c] = mesh.triangle(2);
    let (x, y) = frame.panels[0].to_px((a + b + c) / 3.0);
    let mid = rgb(&pix, x, y);
    assert_eq!(mid, colormap::bin_colour(colormap::BINS / 2));
    assert!(
        close(mid, colormap::viridis(0.5), 4),
        "a constant value maps to mid-scale"
    );
}

fn dark_pixels(p: &Pixmap, x: f32, top: f32, w: f32, h: f32) -> usize {
    let mut n = 0;
    for y in top.floor() as u32..(top + h).ceil() as u32 {
        for x in x.floor() as u32..(x + w).ceil() as u32 {
            if let Some(c) = p.pixel(x, y) {
                if c.red() < 128 && c.green() < 128 && c.blue() < 128 {
                    n += 1;
                }
            }
        }
    }
    n
}

#[test]
fn titles_put_dark_pixels_in_their_boxes() {
    let poly = rect(2.0, 1.0);
    let fonts = Fonts::load().unwrap();
    let layout = Layout::new(2).panel_px(200).title("Figure 3: CVT meshes");
    let s = [
        scene("Lloyd, K = 100", &poly, None, None, 200),
        scene("", &poly, None, None, 200),
    ];
    let (pix, frame) = render(&s, &layout);
    let ft = frame.title.as_ref().unwrap();
    assert!(dark_pixels(&pix, ft.x, ft.top(&fonts), ft.width, ft.size) > 100);
    let t0 = &frame.panels[0].title;
    let inked = dark_pixels(&pix, t0.x, t0.top(&fonts), t0.width, t0.size);
    assert!(inked > 50, "panel title has only {inked} dark pixels");
    // Same box in the untitled panel, shifted by one column: nothing there.
    let dx = frame.panels[1].origin.0 as f32 - frame.panels[0].origin.0 as f32;
    assert_eq!(
        dark_pixels(&pix, t0.x + dx, t0.top(&fonts), t0.width, t0.size),
        0
    );
    // Text stays inside the picture and does not overlap the drawing.
    assert!(t0.top(&fonts) + t0.size <= frame.panels[0].origin.1 as f32);
    assert!(ft.x >= 0.0 && ft.x + ft.width <= frame.width as f32);
}

#[test]
fn grid_places_panels_in_rows_and_columns() {
    let poly = rect(1.0, 1.0);
    let s: Vec<Scene> = (0..5)
        .map(|i| scene(&format!("p{i}"), &poly, None, None, 100))
        .collect();
    let layout = Layout::new(3).panel_px(100);
    let fonts = Fonts::load().unwrap();
    let f = frame::compute(&s, &layout, &fonts);
    let o: Vec<(f64, f64)> = f.panels.iter().map(|p| p.origin).collect();
    assert_eq!(o[0].1, o[1].1);
    assert_eq!(o[1].1, o[2].1);
    assert!(o[0].0 < o[1].0 && o[1].0 < o[2].0);
    assert_eq!(o[3].0, o[0].0);
    assert_eq!(o[4].0, o[1].0);
    assert!(o[3].1 >= o[0].1 + 100.0);
    assert!(f.width as f64 >= 3.0 * 100.0 && f.height as f64 >= 2.0 * 100.0);
    // Drawings never overlap.
    for i in 0..5 {
        for j in i + 1..5 {
            let (a, b) = (o[i], o[j]);
            assert!((a.0 - b.0).abs() >= 100.0 || (a.1 - b.1).abs() >= 100.0);
        }
    }
}

#[test]
fn same_input_gives_same_bytes() {
    let (poly, mesh) = square_with_hole();
    let values: Vec<f64> = (0..8).map(f64::from).collect();
    let s = [scene("a", &poly, Some(&mesh), Some(&values), 150)];
    let layout = Layout::new(1).panel_px(150).title("t");
    let a = png::draw(&s, &layout).unwrap().encode_png().unwrap();
    let b = png::draw(&s, &layout).unwrap().encode_png().unwrap();
    assert_eq!(a, b);
    assert_eq!(
        svg::draw(&s, &layout).unwrap(),
        svg::draw(&s, &layout).unwrap()
    );
}

/// Minimal XML well-formedness check: balanced, properly nested tags, quoted attributes,
/// no raw `<` or unknown `&` in text or attribute values.
fn check_xml(doc: &str) -> Result<usize, String> {
    let mut stack: Vec<String> = Vec::new();
    let mut elements = 0;
    let mut rest = doc.trim_start();
    if let Some(r) = rest.strip_prefix("<?xml") {
        rest = &r[r.find("?>").ok_or("unterminated declaration")? + 2..];
    }
    let check_text = |t: &str| -> Result<(), String> {
        let mut s = t;
        while let Some(i) = s.find('&') {
            let e = &s[i..];
            let end = e.find(';').ok_or(format!("bad entity in {t:?}"))?;
            if !["&amp;", "&lt;", "&gt;", "&quot;", "&apos;"].contains(&&e[..=end]) {
                return Err(format!("unknown entity {}", &e[..=end]));
            }
            s = &e[end + 1..];
        }
        Ok(())
    };
    while !rest.is_empty() {
        let lt = rest.find('<').unwrap_or(rest.len());
        check_text(&rest[..lt])?;
        if stack.is_empty() && !rest[..lt].trim().is_empty() {
            return Err("text outside the root element".into());
        }
        rest = &rest[lt..];
        if rest.is_empty() {
            break;
        }
        let gt = rest.find('>').ok_or("unterminated tag")?;
        let tag = &rest[1..gt];
        rest = &rest[gt + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack.pop().ok_or(format!("unexpected </{name}>"))?;
            if open != name.trim() {
                return Err(format!("</{name}> closes <{open}>"));
            }
            continue;
        }
        let (body, self_closing) = match tag.strip_suffix('/') {
            Some(b) => (b, true),
            None => (tag, false),
        };
        let name_end = body.find(char::is_whitespace).unwrap_or(body.len());
        let name = &body[..name_end];
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == ':')
        {
            return Err(format!("bad element name {name:?}"));
        }
        if stack.is_empty() && elements > 0 {
            return Err("second root element".into());
        }
        let mut attrs = body[name_end..].trim();
        while !attrs.is_empty() {
            let eq = attrs
                .find('=')
                .ok_or(format!("attribute without value in <{name}>"))?;
            let v = attrs[eq + 1..]
                .strip_prefix('"')
                .ok_or(format!("unquoted attribute in <{name}>"))?;
            let close = v.find('"').ok_or("unterminated attribute")?;
            if v[..close].contains('<') {
                return Err("'<' in attribute".into());
            }
            check_text(&v[..close])?;
            attrs = v[close + 1..].trim_start();
        }
        elements += 1;
        if !self_closing {
            stack.push(name.to_string());
        }
    }
    if let Some(open) = stack.pop() {
        return Err(format!("<{open}> never closed"));
    }
    Ok(elements)
}

#[test]
fn xml_checker_rejects_malformed_documents() {
    assert!(check_xml(r#"<svg a="1"><g></g></svg>"#).is_ok());
    assert!(check_xml(r#"<svg><g></svg>"#).is_err());
    assert!(check_xml(r#"<svg a=1></svg>"#).is_err());
    assert!(check_xml(r#"<svg>a & b</svg>"#).is_err());
    assert!(check_xml(r#"<svg></svg><svg></svg>"#).is_err());
}

#[test]
fn svg_is_well_formed_with_titles_and_paths() {
    let (poly, mesh) = square_with_hole();
    let values: Vec<f64> = (0..8).map(f64::from).collect();
    let s = [
        scene("Mesh <A> & \"B\"", &poly, Some(&mesh), None, 150),
        scene("colours", &poly, Some(&mesh), Some(&values), 150),
        scene("region", &poly, None, None, 150),
    ];
    let layout = Layout::new(2).panel_px(150).title("Figure 4");
    let doc = svg::draw(&s, &layout).unwrap();
    let n = check_xml(&doc).unwrap_or_else(|e| panic!("malformed SVG: {e}\n{doc}"));
    assert!(n > 10);
    assert!(doc.contains("Mesh &lt;A&gt; &amp; &quot;B&quot;"));
    assert!(doc.contains(">Figure 4</text>"));
    assert_eq!(
        doc.matches(r#"class="edges""#).count(),
        2,
        "one combined edge path per mesh panel"
    );
    assert_eq!(doc.matches(r#"class="boundary""#).count(), 3);
    assert_eq!(doc.matches(r#"fill-rule="evenodd""#).count(), 3);
    // The combined edge path has one M..L.. segment per unique edge (16 here).
    let edges_line = doc
        .lines()
        .find(|l| l.contains(r#"class="edges""#))
        .unwrap();
    assert_eq!(edges_line.matches('M').count(), 16);
    // Every triangle is filled exactly once across the colour-bin paths.
    let fills: usize = doc
        .lines()
        .filter(|l| l.contains(r#"class="fill""#))
        .map(|l| l.matches('Z').count())
        .sum();
    assert_eq!(fills, 8);
    let fonts = Fonts::load().unwrap();
    let f = frame::compute(&s, &layout, &fonts);
    assert!(doc.contains(&format!(r#"width="{}" height="{}""#, f.width, f.height)));
}

#[test]
fn unique_edges_counts_each_edge_once() {
    let (_, mesh) = square_with_hole();
    // 8 triangles: 24 half-edges, 8 on the boundary, so (24 + 8) / 2 edges.
    let e = unique_edges(&mesh);
    assert_eq!(e.len(), 16);
    assert!(e.iter().all(|&(a, b)| a < b));
}

#[test]
fn bad_input_is_an_error() {
    let (poly, mesh) = square_with_hole();
    fn build<'a>(
        poly: &Polygon,
        m: Option<&'a Mesh>,
        c: Option<&[f64]>,
        bbox: (DVec2, DVec2),
    ) -> Result<Scene<'a>, RenderError> {
        let p = poly.clone();
        scene::build(3, "x", Some((bbox, &move |_| p.clone())), m, c, None, 100)
    }
    let bbox = poly.bbox();
    assert!(matches!(
        build(&poly, Some(&mesh), Some(&[1.0, 2.0]), bbox),
        Err(RenderError::ColourCount {
            panel: 3,
            expected: 8,
            got: 2
        })
    ));
    assert!(matches!(
        build(&poly, None, Some(&[1.0]), bbox),
        Err(RenderError::ColourWithoutMesh(3))
    ));
    let mut bad = mesh.clone();
    bad.triangles[2][1] = 99;
    assert!(matches!(
        build(&poly, Some(&bad), None, bbox),
        Err(RenderError::BadMesh { panel: 3, .. })
    ));
    let mut bad = mesh.clone();
    bad.points[1].x = f64::NAN;
    assert!(matches!(
        build(&poly, Some(&bad), None, bbox),
        Err(RenderError::BadMesh { .. })
    ));
    let point = (DVec2::ONE, DVec2::ONE);
    assert!(matches!(
        build(&poly, None, None, point),
        Err(RenderError::EmptyRegion(3))
    ));
    let inf = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    assert!(matches!(
        build(&poly, None, None, inf),
        Err(RenderError::EmptyRegion(3))
    ));
    // Without a region: nothing at all, a mesh without vertices, a mesh on one point.
    assert!(matches!(
        scene::build(3, "x", None, None, None, None, 100),
        Err(RenderError::EmptyPanel(3))
    ));
    let empty = Mesh {
        points: vec![],
        triangles: vec![],
        markers: vec![],
    };
    assert!(matches!(
        scene::build(3, "x", None, Some(&empty), None, None, 100),
        Err(RenderError::EmptyRegion(3))
    ));
    let mut degenerate = mesh.clone();
    degenerate.points.iter_mut().for_each(|p| *p = DVec2::ONE);
    assert!(matches!(
        scene::build(3, "x", None, Some(&degenerate), None, None, 100),
        Err(RenderError::EmptyRegion(3))
    ));
    assert!(matches!(
        scene::build(3, "x", None, Some(&bad), None, None, 100),
        Err(RenderError::BadMesh { panel: 3, .. })
    ));

    assert!(matches!(
        scene::from_panels(&[], &Layout::default()),
        Err(RenderError::NoPanels)
    ));
    for layout in [
        Layout::new(0),
        Layout::default().panel_px(3),
        Layout::default().mesh_stroke_px(0.0),
        Layout::default().boundary_stroke_px(f32::NAN),
        Layout::default().font_px(-1.0),
    ] {
        assert!(
            matches!(
                scene::from_panels(&[], &layout),
                Err(RenderError::BadLayout(_))
            ),
            "{layout:?}"
        );
    }
}

#[test]
fn edges_thin_out_on_dense_meshes() {
    let (poly, mesh) = square_with_hole();
    let layout = Layout::default();
    let coarse = scene("", &poly, Some(&mesh), None, 400);
    let e = unique_edges(&mesh);
    assert_eq!(
        scene::edge_width(&coarse, &e, &layout),
        layout.mesh_stroke_px
    );
    // 6 px for the whole 4-unit square: the mean edge (2.5 units) is under 4 px on screen.
    let dense = scene("", &poly, Some(&mesh), None, 6);
    let w = scene::edge_width(&dense, &e, &layout);
    assert!(w < layout.mesh_stroke_px && w >= 0.15, "{w}");
}

#[test]
fn atomic_write_replaces_file_and_leaves_no_temp() {
    let dir = std::env::temp_dir().join(format!("render-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("out.png");
    write_atomic(&path, b"first").unwrap();
    write_atomic(&path, b"second").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"second");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
    let missing = dir.join("no/such/dir/out.png");
    assert!(matches!(
        write_atomic(&missing, b"x"),
        Err(RenderError::Io { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn value_labels_are_short() {
    assert_eq!(format_value(0.0), "0");
    assert_eq!(format_value(31.4159), "31.42");
    assert_eq!(format_value(60.0), "60");
    assert_eq!(format_value(0.98765), "0.9877");
    assert_eq!(format_value(-2.5), "-2.5");
    assert_eq!(format_value(1.5e-6), "1.50e-6");
    assert_eq!(format_value(123456.0), "1.23e5");
}
