//! Raster back end (tiny-skia).
use crate::frame::{self, Frame, PanelFrame};
use crate::scene::{edge_width, unique_edges, Outline, Scene};
use crate::text::Fonts;
use crate::{colormap, Layout, RenderError, BOUNDARY_COLOUR, NO_DATA_COLOUR, TEXT_COLOUR};
use geometry::Polygon;
use mesh::Mesh;
use tiny_skia::{
    Color, FillRule, LineCap, LineJoin, Paint, Path, PathBuilder, Pixmap, Rect, Stroke, Transform,
};

/// Draw the figure into a new pixmap.
pub(crate) fn draw(scenes: &[Scene], layout: &Layout) -> Result<Pixmap, RenderError> {
    let fonts = Fonts::load()?;
    let frame = frame::compute(scenes, layout, &fonts);
    let mut pixmap = Pixmap::new(frame.width, frame.height).ok_or(RenderError::TooLarge {
        width: frame.width,
        height: frame.height,
    })?;
    pixmap.fill(Color::WHITE);
    draw_frame(&mut pixmap, scenes, &frame, layout, &fonts);
    Ok(pixmap)
}

pub(crate) fn draw_frame(
    pixmap: &mut Pixmap,
    scenes: &[Scene],
    frame: &Frame,
    layout: &Layout,
    fonts: &Fonts,
) {
    if let Some(t) = &frame.title {
        fonts.draw(pixmap, t, TEXT_COLOUR);
    }
    for (s, pf) in scenes.iter().zip(&frame.panels) {
        draw_panel(pixmap, s, pf, layout, fonts);
    }
}

fn paint(rgb: [u8; 3], anti_alias: bool) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
    p.anti_alias = anti_alias;
    p
}

/// All rings of the region polygon as closed subpaths.
fn rings_path(polygon: &Polygon, pf: &PanelFrame) -> Option<Path> {
    let mut pb = PathBuilder::new();
    for r in &polygon.rings {
        let mut pts = r.points.iter().map(|p| pf.to_px(*p));
        if let Some((x, y)) = pts.next() {
            pb.move_to(x, y);
            for (x, y) in pts {
                pb.line_to(x, y);
            }
            pb.close();
        }
    }
    pb.finish()
}

/// Each of `edges` (vertex pairs of `m`) as an open subpath.
fn segments_path(m: &Mesh, edges: &[(u32, u32)], pf: &PanelFrame) -> Option<Path> {
    let mut pb = PathBuilder::new();
    for &(a, b) in edges {
        let (p, q) = (
            pf.to_px(m.points[a as usize]),
            pf.to_px(m.points[b as usize]),
        );
        pb.move_to(p.0, p.1);
        pb.line_to(q.0, q.1);
    }
    pb.finish()
}

/// Every triangle of `m` as a closed subpath.
fn triangles_path(
    m: &Mesh,
    triangles: impl Iterator<Item = usize>,
    pf: &PanelFrame,
) -> Option<Path> {
    let mut pb = PathBuilder::new();
    for t in triangles {
        let [p, q, r] = m.triangle(t).map(|v| pf.to_px(v));
        pb.move_to(p.0, p.1);
        pb.line_to(q.0, q.1);
        pb.line_to(r.0, r.1);
        pb.close();
    }
    pb.finish()
}

fn draw_panel(pixmap: &mut Pixmap, s: &Scene, pf: &PanelFrame, layout: &Layout, fonts: &Fonts) {
    let id = Transform::identity();
    fonts.draw(pixmap, &pf.title, TEXT_COLOUR);
    let boundary = match (&s.outline, s.mesh) {
        (Outline::Region(polygon), _) => {
            let path = rings_path(polygon, pf);
            // Region tint; even-odd so that holes stay white.
            if let Some(path) = &path {
                pixmap.fill_path(
                    path,
                    &paint(layout.region_tint, true),
                    FillRule::EvenOdd,
                    id,
                    None,
                );
            }
            path
        }
        (Outline::MeshBoundary(edges), Some(m)) => {
            // Without a region the triangles themselves are the tinted area. Colour fills
            // would cover the tint completely, so it is skipped then.
            if s.colours.is_none() {
                if let Some(path) = triangles_path(m, 0..m.num_triangles(), pf) {
                    pixmap.fill_path(
                        &path,
                        &paint(layout.region_tint, false),
                        FillRule::Winding,
                        id,
                        None,
                    );
                }
            }
            segments_path(m, edges, pf)
        }
        (Outline::MeshBoundary(_), None) => None,
    };

    if let Some(m) = s.mesh {
        // Per-triangle colours: one path per colour bin. Not anti-aliased, so that adjacent
        // triangles leave no faint seams; the edge strokes cover the jagged borders.
        if let Some(c) = &s.colours {
            let mut members: Vec<Vec<usize>> = vec![Vec::new(); colormap::BINS + 1];
            for (t, b) in c.bins.iter().enumerate() {
                members[b.unwrap_or(colormap::BINS)].push(t);
            }
            for (slot, ts) in members.into_iter().enumerate() {
                let rgb = if slot == colormap::BINS {
                    NO_DATA_COLOUR
                } else {
                    colormap::bin_colour(slot)
                };
                if let Some(path) = triangles_path(m, ts.into_iter(), pf) {
                    pixmap.fill_path(&path, &paint(rgb, false), FillRule::Winding, id, None);
                }
            }
        }
        // Every edge once, in a single path: one stroke call, thin and anti-aliased.
        let edges = unique_edges(m);
        if let Some(path) = segments_path(m, &edges, pf) {
            let stroke = Stroke {
                width: edge_width(s, &edges, layout),
                ..Stroke::default()
            };
            pixmap.stroke_path(&path, &paint(layout.mesh_colour, true), &stroke, id, None);
        }
    }

    if let Some(path) = &boundary {
        let stroke = Stroke {
            width: layout.boundary_stroke_px,
            line_join: LineJoin::Round,
            line_cap: LineCap::Round,
            ..Stroke::default()
        };
        pixmap.stroke_path(path, &paint(BOUNDARY_COLOUR, true), &stroke, id, None);
    }

    if let Some(bar) = &pf.bar {
        let (x, y, w, h) = bar.rect;
        // One column of the gradient per pixel.
        let n = w.round().max(1.0) as usize;
        for i in 0..n {
            let t = if n > 1 {
                i as f64 / (n - 1) as f64
            } else {
                0.5
            };
            if let Some(r) = Rect::from_xywh(x + i as f32, y, 1.0, h) {
                pixmap.fill_rect(r, &paint(colormap::viridis(t), false), id, None);
            }
        }
        let mut pb = PathBuilder::new();
        if let Some(r) = Rect::from_xywh(x - 0.5, y - 0.5, w + 1.0, h + 1.0) {
            pb.push_rect(r);
        }
        if let Some(path) = pb.finish() {
            let stroke = Stroke {
                width: 1.0,
                ..Stroke::default()
            };
            pixmap.stroke_path(&path, &paint(TEXT_COLOUR, true), &stroke, id, None);
        }
        for t in &bar.texts {
            fonts.draw(pixmap, t, TEXT_COLOUR);
        }
    }
}
