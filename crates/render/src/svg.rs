//! Vector back end: a hand-written SVG document with the same geometry as the PNG.
use crate::frame::{self, PanelFrame};
use crate::scene::{edge_width, unique_edges, Outline, Scene};
use crate::text::{Fonts, TextItem};
use crate::{colormap, Layout, RenderError, BOUNDARY_COLOUR, NO_DATA_COLOUR, TEXT_COLOUR};
use mesh::Mesh;
use std::fmt::Write;

const FONT_FAMILY: &str = "DejaVu Sans, Verdana, Arial, sans-serif";

pub(crate) fn draw(scenes: &[Scene], layout: &Layout) -> Result<String, RenderError> {
    let fonts = Fonts::load()?;
    let frame = frame::compute(scenes, layout, &fonts);
    let mut out = String::new();
    let (w, h) = (frame.width, frame.height);
    // Writing to a String cannot fail, so the fmt::Results below are ignored.
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    let _ = writeln!(
        out,
        r#"<rect x="0" y="0" width="{w}" height="{h}" fill="white"/>"#
    );
    if let Some(t) = &frame.title {
        text(&mut out, t);
    }
    for (i, (s, pf)) in scenes.iter().zip(&frame.panels).enumerate() {
        panel(&mut out, i, s, pf, layout);
    }
    out.push_str("</svg>\n");
    Ok(out)
}

fn hex(rgb: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2])
}

/// Escape text for XML character data and attribute values.
pub(crate) fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&apos;"),
            // Control characters other than tab/newline are not allowed in XML 1.0.
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => {}
            c => o.push(c),
        }
    }
    o
}

fn text(out: &mut String, t: &TextItem) {
    let weight = if t.bold { r#" font-weight="bold""# } else { "" };
    let _ = writeln!(
        out,
        r#"<text x="{:.2}" y="{:.2}" font-family="{FONT_FAMILY}" font-size="{:.2}"{weight} fill="{}">{}</text>"#,
        t.x,
        t.baseline,
        // ab_glyph sizes are ascent−descent; SVG font-size is the em size (DejaVu: 1.164 em).
        t.size / 1.164,
        hex(TEXT_COLOUR),
        escape(&t.text)
    );
}

fn push_pt(d: &mut String, cmd: char, p: (f32, f32)) {
    let _ = write!(d, "{cmd}{:.2} {:.2}", p.0, p.1);
}

/// Path data of triangles `ts` of `m`, one closed subpath each.
fn triangles_d(d: &mut String, m: &Mesh, ts: impl Iterator<Item = usize>, pf: &PanelFrame) {
    for t in ts {
        let [p, q, r] = m.triangle(t).map(|v| pf.to_px(v));
        push_pt(d, 'M', p);
        push_pt(d, 'L', q);
        push_pt(d, 'L', r);
        d.push('Z');
    }
}

/// Path data of `edges` (vertex pairs of `m`), one open subpath each.
fn segments_d(m: &Mesh, edges: &[(u32, u32)], pf: &PanelFrame) -> String {
    let mut d = String::with_capacity(edges.len() * 32);
    for &(a, b) in edges {
        push_pt(&mut d, 'M', pf.to_px(m.points[a as usize]));
        push_pt(&mut d, 'L', pf.to_px(m.points[b as usize]));
    }
    d
}

fn panel(out: &mut String, index: usize, s: &Scene, pf: &PanelFrame, layout: &Layout) {
    let _ = writeln!(out, r#"<g id="panel{index}">"#);
    text(out, &pf.title);

    let boundary = match (&s.outline, s.mesh) {
        (Outline::Region(polygon), _) => {
            let mut d = String::new();
            for r in &polygon.rings {
                for (k, p) in r.points.iter().enumerate() {
                    push_pt(&mut d, if k == 0 { 'M' } else { 'L' }, pf.to_px(*p));
                }
                if !r.points.is_empty() {
                    d.push('Z');
                }
            }
            if !d.is_empty() {
                let _ = writeln!(
                    out,
                    r#"<path class="region" d="{d}" fill="{}" fill-rule="evenodd" stroke="none"/>"#,
                    hex(layout.region_tint)
                );
            }
            d
        }
        (Outline::MeshBoundary(edges), Some(m)) => {
            // Without a region the triangles are the tinted area; colour fills would cover
            // it completely, so it is left out then.
            if s.colours.is_none() && m.num_triangles() > 0 {
                let mut d = String::with_capacity(m.num_triangles() * 48);
                triangles_d(&mut d, m, 0..m.num_triangles(), pf);
                let _ = writeln!(
                    out,
                    r#"<path class="region" d="{d}" fill="{}" stroke="none"/>"#,
                    hex(layout.region_tint)
                );
            }
            segments_d(m, edges, pf)
        }
        (Outline::MeshBoundary(_), None) => String::new(),
    };

    if let Some(m) = s.mesh {
        if let Some(c) = &s.colours {
            let mut paths: Vec<String> = vec![String::new(); colormap::BINS + 1];
            for (t, b) in c.bins.iter().enumerate() {
                triangles_d(
                    &mut paths[b.unwrap_or(colormap::BINS)],
                    m,
                    [t].into_iter(),
                    pf,
                );
            }
            for (slot, d) in paths.iter().enumerate() {
                if d.is_empty() {
                    continue;
                }
                let rgb = if slot == colormap::BINS {
                    NO_DATA_COLOUR
                } else {
                    colormap::bin_colour(slot)
                };
                let _ = writeln!(
                    out,
                    r#"<path class="fill" d="{d}" fill="{}" stroke="none"/>"#,
                    hex(rgb)
                );
            }
        }
        let edges = unique_edges(m);
        let d = segments_d(m, &edges, pf);
        if !d.is_empty() {
            let _ = writeln!(
                out,
                r#"<path class="edges" d="{d}" fill="none" stroke="{}" stroke-width="{:.3}"/>"#,
                hex(layout.mesh_colour),
                edge_width(s, &edges, layout)
            );
        }
    }

    if !boundary.is_empty() {
        let _ = writeln!(
            out,
            r#"<path class="boundary" d="{boundary}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-linejoin="round" stroke-linecap="round"/>"#,
            hex(BOUNDARY_COLOUR),
            layout.boundary_stroke_px
        );
    }

    if let Some(bar) = &pf.bar {
        let (x, y, w, h) = bar.rect;
        let _ = writeln!(
            out,
            r#"<defs><linearGradient id="viridis{index}" x1="0" y1="0" x2="1" y2="0">"#
        );
        for k in 0..=8 {
            let t = k as f64 / 8.0;
            let _ = writeln!(
                out,
                r#"<stop offset="{t:.3}" stop-color="{}"/>"#,
                hex(colormap::viridis(t))
            );
        }
        let _ = writeln!(out, "</linearGradient></defs>");
        let _ = writeln!(
            out,
            r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" fill="url(#viridis{index})" stroke="{}" stroke-width="1"/>"#,
            hex(TEXT_COLOUR)
        );
        for t in &bar.texts {
            text(out, t);
        }
    }
    let _ = writeln!(out, "</g>");
}
