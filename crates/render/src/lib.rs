//! Pictures of regions and meshes: a grid of titled panels written as PNG (rasterized with
//! tiny-skia, text from the embedded DejaVu Sans font via ab_glyph, so no system libraries or
//! fonts are needed) or as hand-written SVG.
//!
//! Each panel draws one region at its true aspect ratio (same scale in x and y, the longer
//! side of its bounding box spanning [`Layout::panel_px`] pixels): the region filled with a
//! light tint by the even-odd rule (holes stay white), optionally a mesh's triangle edges as
//! thin anti-aliased strokes, optionally a per-triangle fill colour from a value per triangle
//! through the viridis colormap with a colour bar, and the region boundary on top as a thicker
//! dark line. A mesh can also be drawn without its region ([`Panel::for_mesh`]), as Triangle's
//! showme does: the triangles are tinted, the edges of exactly one triangle are drawn in the
//! boundary style, and the mesh's bounding box sets the frame.
//!
//! ```no_run
//! # fn demo(region: &geometry::Region, mesh: &mesh::Mesh) -> Result<(), cvtmesh_render::RenderError> {
//! use cvtmesh_render::{Layout, Panel};
//! let angles: Vec<f64> = vec![45.0; mesh.num_triangles()];
//! let panels = [
//!     Panel::new("region", region),
//!     Panel::new("mesh", region).with_mesh(mesh),
//!     Panel::new("min angle", region).with_mesh(mesh).with_colour(angles, "min angle (°)"),
//!     Panel::for_mesh("mesh alone", mesh),
//! ];
//! let layout = Layout::new(3).panel_px(400).title("Figure 3");
//! cvtmesh_render::render_png(&panels, &layout, std::path::Path::new("fig3.png"))?;
//! cvtmesh_render::render_svg(&panels, &layout, std::path::Path::new("fig3.svg"))?;
//! # Ok(()) }
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod colormap;
mod frame;
mod png;
mod scene;
mod svg;
mod text;

use std::path::{Path, PathBuf};

pub use colormap::viridis;
use geometry::Region;
use mesh::Mesh;

/// Colour of the region boundary (sRGB).
pub const BOUNDARY_COLOUR: [u8; 3] = [0, 0, 0];
/// Colour of text (sRGB).
pub const TEXT_COLOUR: [u8; 3] = [0, 0, 0];
/// Fill colour of triangles whose `colour_by` value is not finite (sRGB).
pub const NO_DATA_COLOUR: [u8; 3] = [190, 190, 190];

/// Errors of the renderers. Bad input is reported, never panicked on.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No panels were given.
    #[error("nothing to draw: no panels")]
    NoPanels,
    /// A layout option is out of range.
    #[error("bad layout: {0}")]
    BadLayout(String),
    /// `colour_by` does not have one value per triangle.
    #[error("panel {panel}: colour_by has {got} values but the mesh has {expected} triangles")]
    ColourCount {
        /// Panel index.
        panel: usize,
        /// Number of triangles.
        expected: usize,
        /// Number of values given.
        got: usize,
    },
    /// `colour_by` was given for a panel without a mesh.
    #[error("panel {0}: colour_by needs a mesh")]
    ColourWithoutMesh(usize),
    /// The mesh has an out-of-range vertex index or a non-finite coordinate.
    #[error("panel {panel}: bad mesh: {reason}")]
    BadMesh {
        /// Panel index.
        panel: usize,
        /// What is wrong.
        reason: String,
    },
    /// The panel has neither a region nor a mesh.
    #[error("panel {0}: nothing to draw: neither a region nor a mesh")]
    EmptyPanel(usize),
    /// The region (with the mesh), or the mesh alone, has an empty or non-finite extent.
    #[error("panel {0}: the region (or mesh) has no finite, non-zero extent")]
    EmptyRegion(usize),
    /// The embedded font could not be parsed.
    #[error("cannot load the embedded DejaVu Sans font")]
    Font,
    /// The picture is too large to allocate.
    #[error("picture of {width}x{height} pixels is too large")]
    TooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// PNG encoding failed.
    #[error("PNG encoding failed: {0}")]
    Encode(String),
    /// Writing the output file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file being written.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// One panel of a figure: a region, optionally with a mesh and per-triangle colours; or a mesh
/// alone ([`Panel::for_mesh`]).
#[derive(Clone, Debug)]
pub struct Panel<'a> {
    /// Title drawn above the panel.
    pub title: String,
    /// The mesh to draw, if any (`None`: just the region).
    pub mesh: Option<&'a Mesh>,
    /// The region: its boundary is drawn from `Region::polygonize`. `None` (a panel from
    /// [`Panel::for_mesh`]): the mesh's own boundary edges are drawn instead, and the mesh
    /// alone sets the frame; a panel with neither region nor mesh is
    /// [`RenderError::EmptyPanel`].
    pub region: Option<&'a Region>,
    /// One value per triangle (e.g. its minimum angle), shown as the triangle's fill colour
    /// through the viridis colormap scaled from the minimum to the maximum finite value.
    /// Non-finite values are drawn grey ([`NO_DATA_COLOUR`]).
    pub colour_by: Option<Vec<f64>>,
    /// Label of the colour bar (e.g. "min angle (°)").
    pub colour_label: Option<String>,
}

impl<'a> Panel<'a> {
    /// A panel showing just `region`.
    pub fn new(title: impl Into<String>, region: &'a Region) -> Panel<'a> {
        Panel {
            title: title.into(),
            mesh: None,
            region: Some(region),
            colour_by: None,
            colour_label: None,
        }
    }
    /// A panel showing `mesh` without its region: the triangles are tinted, the edges of
    /// exactly one triangle (the outer boundary and the holes' boundaries of a conforming
    /// mesh) are drawn in the boundary style, and the mesh's bounding box sets the frame. For
    /// a mesh read from a file whose region is not at hand.
    pub fn for_mesh(title: impl Into<String>, mesh: &'a Mesh) -> Panel<'a> {
        Panel {
            title: title.into(),
            mesh: Some(mesh),
            region: None,
            colour_by: None,
            colour_label: None,
        }
    }
    /// Draw this mesh's triangles.
    pub fn with_mesh(mut self, mesh: &'a Mesh) -> Panel<'a> {
        self.mesh = Some(mesh);
        self
    }
    /// Fill each triangle by its value (one per triangle), with a labelled colour bar.
    pub fn with_colour(mut self, values: Vec<f64>, label: impl Into<String>) -> Panel<'a> {
        self.colour_by = Some(values);
        self.colour_label = Some(label.into());
        self
    }
}

/// How panels are arranged and drawn. Build with [`Layout::new`] and the builder methods;
/// all fields have sensible defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// Panels per row (the last row may be partly empty). Default 3.
    pub columns: usize,
    /// Pixels spanned by the longer side of each region's bounding box. Default 400.
    pub panel_px: u32,
    /// Title of the whole figure, drawn above the grid. Default none.
    pub title: Option<String>,
    /// Pixel height of panel titles (`None`: `panel_px / 24`, clamped to 11..=22).
    pub font_px: Option<f32>,
    /// Width of mesh edges in pixels. Default 0.7; strokes wider than 1 px are much slower.
    /// Thinned automatically when the average edge is shorter than 5 px, so dense meshes
    /// do not turn solid.
    pub mesh_stroke_px: f32,
    /// Width of the region boundary in pixels. Default 2.
    pub boundary_stroke_px: f32,
    /// Tint filling the region (sRGB). Default light blue.
    pub region_tint: [u8; 3],
    /// Colour of mesh edges (sRGB). Default dark grey.
    pub mesh_colour: [u8; 3],
}

impl Default for Layout {
    fn default() -> Self {
        Layout {
            columns: 3,
            panel_px: 400,
            title: None,
            font_px: None,
            mesh_stroke_px: 0.7,
            boundary_stroke_px: 2.0,
            region_tint: [220, 231, 247],
            mesh_colour: [45, 45, 45],
        }
    }
}

impl Layout {
    /// Defaults with `columns` panels per row.
    pub fn new(columns: usize) -> Layout {
        Layout {
            columns,
            ..Layout::default()
        }
    }
    /// Set [`Layout::panel_px`].
    pub fn panel_px(mut self, px: u32) -> Layout {
        self.panel_px = px;
        self
    }
    /// Set the figure title.
    pub fn title(mut self, title: impl Into<String>) -> Layout {
        self.title = Some(title.into());
        self
    }
    /// Set the panel title size in pixels.
    pub fn font_px(mut self, px: f32) -> Layout {
        self.font_px = Some(px);
        self
    }
    /// Set the mesh edge width in pixels.
    pub fn mesh_stroke_px(mut self, px: f32) -> Layout {
        self.mesh_stroke_px = px;
        self
    }
    /// Set the boundary width in pixels.
    pub fn boundary_stroke_px(mut self, px: f32) -> Layout {
        self.boundary_stroke_px = px;
        self
    }
    /// Set the region tint.
    pub fn region_tint(mut self, rgb: [u8; 3]) -> Layout {
        self.region_tint = rgb;
        self
    }
    /// Set the mesh edge colour.
    pub fn mesh_colour(mut self, rgb: [u8; 3]) -> Layout {
        self.mesh_colour = rgb;
        self
    }

    fn validate(&self) -> Result<(), RenderError> {
        let bad = |m: &str| Err(RenderError::BadLayout(m.to_string()));
        if self.columns == 0 {
            return bad("columns must be at least 1");
        }
        if !(16..=20_000).contains(&self.panel_px) {
            return bad("panel_px must be in 16..=20000");
        }
        if let Some(f) = self.font_px {
            if !(f.is_finite() && (4.0..=400.0).contains(&f)) {
                return bad("font_px must be in 4..=400");
            }
        }
        for (name, w) in [
            ("mesh_stroke_px", self.mesh_stroke_px),
            ("boundary_stroke_px", self.boundary_stroke_px),
        ] {
            if !(w.is_finite() && w > 0.0 && w <= 50.0) {
                return Err(RenderError::BadLayout(format!("{name} must be in (0, 50]")));
            }
        }
        Ok(())
    }
}

/// Render the panels to PNG bytes.
pub fn png_bytes(panels: &[Panel], layout: &Layout) -> Result<Vec<u8>, RenderError> {
    let scenes = scene::from_panels(panels, layout)?;
    let pixmap = png::draw(&scenes, layout)?;
    pixmap
        .encode_png()
        .map_err(|e| RenderError::Encode(e.to_string()))
}

/// Render the panels to an SVG document.
pub fn svg_string(panels: &[Panel], layout: &Layout) -> Result<String, RenderError> {
    let scenes = scene::from_panels(panels, layout)?;
    svg::draw(&scenes, layout)
}

/// Render the panels as a PNG file at `path` (written to a temporary file beside it, then
/// renamed, so a reader never sees a partial picture).
pub fn render_png(panels: &[Panel], layout: &Layout, path: &Path) -> Result<(), RenderError> {
    let bytes = png_bytes(panels, layout)?;
    write_atomic(path, &bytes)
}

/// Render the panels as an SVG file at `path` (temporary file, then rename).
pub fn render_svg(panels: &[Panel], layout: &Layout, path: &Path) -> Result<(), RenderError> {
    let text = svg_string(panels, layout)?;
    write_atomic(path, text.as_bytes())
}

/// Write `bytes` to a temporary file in `path`'s directory, then rename it over `path`.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), RenderError> {
    mesh::io::write_atomic(path, bytes).map_err(|source| RenderError::Io {
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests;
