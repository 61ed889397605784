//! Where everything goes, in pixels: the figure title, then a grid of cells, each with the
//! panel title, the drawing and (optionally) a colour bar row. Shared by both back ends so the
//! PNG and SVG of a figure have the same geometry.
use crate::scene::{format_value, Scene};
use crate::text::{Fonts, TextItem};
use crate::Layout;
use geometry::DVec2;

/// A colour bar row: label, minimum, gradient, maximum.
pub(crate) struct BarFrame {
    /// Gradient rectangle (x, y, w, h).
    pub rect: (f32, f32, f32, f32),
    /// Label, min and max texts.
    pub texts: Vec<TextItem>,
}

/// One panel's placement.
pub(crate) struct PanelFrame {
    /// Panel title.
    pub title: TextItem,
    /// Top-left corner of the drawing.
    pub origin: (f64, f64),
    /// World bounding box corner mapped to `origin` is (lo.x, hi.y).
    pub lo: DVec2,
    pub hi: DVec2,
    pub scale: f64,
    pub bar: Option<BarFrame>,
}

impl PanelFrame {
    /// World point → pixel (y down).
    pub fn to_px(&self, p: DVec2) -> (f32, f32) {
        (
            (self.origin.0 + (p.x - self.lo.x) * self.scale) as f32,
            (self.origin.1 + (self.hi.y - p.y) * self.scale) as f32,
        )
    }
}

/// The whole figure.
pub(crate) struct Frame {
    pub width: u32,
    pub height: u32,
    pub title: Option<TextItem>,
    pub panels: Vec<PanelFrame>,
}

/// Panel title size in pixels.
pub(crate) fn title_px(layout: &Layout) -> f32 {
    layout
        .font_px
        .unwrap_or_else(|| (layout.panel_px as f32 / 24.0).clamp(11.0, 22.0))
}

pub(crate) fn compute(scenes: &[Scene], layout: &Layout, fonts: &Fonts) -> Frame {
    let f = title_px(layout);
    let small = (0.85 * f).max(9.0);
    let big = 1.3 * f;
    let pad = (0.7 * f).max(0.5 * layout.boundary_stroke_px + 2.0).round();
    let gap = (0.5 * small).round();
    let bar_h = (0.8 * small).round();

    // Natural size of each cell, and the contents' widths for centring later.
    struct Cell {
        w: f32,
        h: f32,
        draw: (f64, f64),
        bar_texts: Option<[String; 3]>,
        bar_row_w: f32,
        bar_w: f32,
    }
    let cells: Vec<Cell> = scenes
        .iter()
        .map(|s| {
            let draw = s.draw_size();
            let title_w = fonts.measure(&s.title, f, false);
            let (bar_texts, bar_w, bar_row_w) = match &s.colours {
                None => (None, 0.0, 0.0),
                Some(c) => {
                    let (lo, hi) = match c.range {
                        Some((a, b)) => (format_value(a), format_value(b)),
                        None => ("n/a".to_string(), "n/a".to_string()),
                    };
                    let label = c.label.clone().unwrap_or_default();
                    let bar_w = (0.5 * draw.0 as f32).clamp(100.0, 260.0).round();
                    let mut row = fonts.measure(&lo, small, false)
                        + gap
                        + bar_w
                        + gap
                        + fonts.measure(&hi, small, false);
                    if !label.is_empty() {
                        row += fonts.measure(&label, small, false) + 2.0 * gap;
                    }
                    (Some([label, lo, hi]), bar_w, row)
                }
            };
            let content_w = (draw.0 as f32).max(title_w).max(bar_row_w);
            let mut h = pad + f + 0.5 * pad + draw.1 as f32 + pad;
            if bar_texts.is_some() {
                h += gap + 0.5 * layout.boundary_stroke_px + small.max(bar_h);
            }
            Cell {
                w: (content_w + 2.0 * pad).ceil(),
                h: h.ceil(),
                draw,
                bar_texts,
                bar_row_w,
                bar_w,
            }
        })
        .collect();

    let cols = layout.columns.min(scenes.len()).max(1);
    let rows = scenes.len().div_ceil(cols);
    let mut col_w = vec![0.0f32; cols];
    let mut row_h = vec![0.0f32; rows];
    for (i, c) in cells.iter().enumerate() {
        col_w[i % cols] = col_w[i % cols].max(c.w);
        row_h[i / cols] = row_h[i / cols].max(c.h);
    }
    let grid_w: f32 = col_w.iter().sum();
    let grid_h: f32 = row_h.iter().sum();

    let (title, top, width) = match &layout.title {
        Some(t) => {
            let tw = fonts.measure(t, big, true);
            let width = grid_w.max(tw + 2.0 * pad).ceil();
            let item = fonts.centred(t, 0.5 * width, pad, big, true);
            (Some(item), (pad + big).ceil(), width)
        }
        None => (None, 0.0, grid_w),
    };
    let x_grid = ((width - grid_w) * 0.5).floor();

    let panels = scenes
        .iter()
        .zip(&cells)
        .enumerate()
        .map(|(i, (s, c))| {
            let (col, row) = (i % cols, i / cols);
            let cx0 = x_grid + col_w[..col].iter().sum::<f32>();
            let cy0 = top + row_h[..row].iter().sum::<f32>();
            let centre = cx0 + 0.5 * col_w[col];
            let title = fonts.centred(&s.title, centre, cy0 + pad, f, false);
            let oy = cy0 + pad + f + 0.5 * pad;
            let ox = (centre - 0.5 * c.draw.0 as f32).round();
            let oy = oy.round();
            let bar = c.bar_texts.as_ref().map(|[label, lo, hi]| {
                let row_top = oy + c.draw.1 as f32 + gap + 0.5 * layout.boundary_stroke_px;
                let mut x = (centre - 0.5 * c.bar_row_w).round();
                let mut texts = Vec::new();
                if !label.is_empty() {
                    let t = fonts.at(label, x, row_top, small, false);
                    x += t.width + 2.0 * gap;
                    texts.push(t);
                }
                let t = fonts.at(lo, x, row_top, small, false);
                x += t.width + gap;
                texts.push(t);
                let rect = (
                    x.round(),
                    (row_top + 0.5 * (small - bar_h)).round(),
                    c.bar_w,
                    bar_h,
                );
                x += c.bar_w + gap;
                texts.push(fonts.at(hi, x, row_top, small, false));
                BarFrame { rect, texts }
            });
            PanelFrame {
                title,
                origin: (ox as f64, oy as f64),
                lo: s.lo,
                hi: s.hi,
                scale: s.scale,
                bar,
            }
        })
        .collect();

    Frame {
        width: width.ceil() as u32,
        height: (top + grid_h).ceil() as u32,
        title,
        panels,
    }
}
