//! Text from the DejaVu Sans bytes embedded by the `dejavu` crate, laid out and rasterized
//! with ab_glyph (no system fonts).
use crate::RenderError;
use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};
use tiny_skia::Pixmap;

/// The two faces used: regular for panel titles and labels, bold for the figure title.
pub(crate) struct Fonts {
    regular: FontRef<'static>,
    bold: FontRef<'static>,
}

/// One line of text placed in pixel coordinates.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TextItem {
    /// The text.
    pub text: String,
    /// Left edge of the first glyph's advance box.
    pub x: f32,
    /// Baseline.
    pub baseline: f32,
    /// Pixel height (ascent − descent).
    pub size: f32,
    /// Bold face.
    pub bold: bool,
    /// Advance width, as measured.
    pub width: f32,
}

#[cfg(test)]
impl TextItem {
    /// Top of the line box (baseline − ascent).
    pub fn top(&self, fonts: &Fonts) -> f32 {
        self.baseline - fonts.ascent(self.size, self.bold)
    }
}

impl Fonts {
    pub fn load() -> Result<Fonts, RenderError> {
        let regular =
            FontRef::try_from_slice(dejavu::sans::regular()).map_err(|_| RenderError::Font)?;
        let bold = FontRef::try_from_slice(dejavu::sans::bold()).map_err(|_| RenderError::Font)?;
        Ok(Fonts { regular, bold })
    }

    fn face(&self, bold: bool) -> &FontRef<'static> {
        if bold {
            &self.bold
        } else {
            &self.regular
        }
    }

    /// Distance from the top of the line box to the baseline.
    pub fn ascent(&self, size: f32, bold: bool) -> f32 {
        self.face(bold).as_scaled(PxScale::from(size)).ascent()
    }

    /// Advance width of `text` with kerning.
    pub fn measure(&self, text: &str, size: f32, bold: bool) -> f32 {
        let font = self.face(bold).as_scaled(PxScale::from(size));
        let mut x = 0.0;
        let mut prev = None;
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = prev {
                x += font.kern(p, id);
            }
            x += font.h_advance(id);
            prev = Some(id);
        }
        x
    }

    /// A text item whose line box has its top at `top` and is horizontally centred on `cx`.
    pub fn centred(&self, text: &str, cx: f32, top: f32, size: f32, bold: bool) -> TextItem {
        let width = self.measure(text, size, bold);
        self.at(text, cx - 0.5 * width, top, size, bold)
    }

    /// A text item whose line box has its top-left corner at (`x`, `top`).
    pub fn at(&self, text: &str, x: f32, top: f32, size: f32, bold: bool) -> TextItem {
        let width = self.measure(text, size, bold);
        let baseline = top + self.ascent(size, bold);
        TextItem {
            text: text.to_string(),
            x,
            baseline,
            size,
            bold,
            width,
        }
    }

    /// Rasterize `item` onto an opaque pixmap: each glyph's coverage alpha-blends `rgb` over
    /// what is there.
    pub fn draw(&self, pixmap: &mut Pixmap, item: &TextItem, rgb: [u8; 3]) {
        let face = self.face(item.bold);
        let font = face.as_scaled(PxScale::from(item.size));
        let (w, h) = (pixmap.width() as i64, pixmap.height() as i64);
        let data = pixmap.data_mut();
        let mut x = item.x;
        let mut prev = None;
        for c in item.text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = prev {
                x += font.kern(p, id);
            }
            let glyph = id.with_scale_and_position(item.size, point(x, item.baseline));
            x += font.h_advance(id);
            prev = Some(id);
            let Some(outlined) = face.outline_glyph(glyph) else {
                continue;
            };
            let b = outlined.px_bounds();
            let (x0, y0) = (b.min.x as i64, b.min.y as i64);
            outlined.draw(|gx, gy, cov| {
                let (px, py) = (x0 + gx as i64, y0 + gy as i64);
                if px < 0 || py < 0 || px >= w || py >= h {
                    return;
                }
                let a = cov.clamp(0.0, 1.0);
                let i = 4 * (py * w + px) as usize;
                // The pixmap is opaque, so premultiplied equals straight colour here.
                for k in 0..3 {
                    let d = data[i + k] as f32;
                    data[i + k] = (d + a * (rgb[k] as f32 - d)).round() as u8;
                }
            });
        }
    }
}
