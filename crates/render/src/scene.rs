//! A panel resolved to what is drawn: the boundary (the region's polygon, or the mesh's own
//! boundary edges), the mesh and its colours, the world bounding box and the world→pixel
//! scale. Validation of user input happens here.
use crate::{colormap, Layout, Panel, RenderError};
use geometry::{DVec2, Polygon};
use mesh::Mesh;

/// Per-triangle colours, already binned.
pub(crate) struct Colours {
    /// Bin of each triangle (`None`: non-finite value).
    pub bins: Vec<Option<usize>>,
    /// Smallest and largest finite value (`None` if there is none).
    pub range: Option<(f64, f64)>,
    /// Colour bar label.
    pub label: Option<String>,
}

/// What is tinted and outlined in the boundary style.
pub(crate) enum Outline {
    /// The region's polygonized boundary: rings filled by the even-odd rule, then stroked.
    Region(Polygon),
    /// No region: the mesh's triangles are tinted and its boundary edges (vertex pairs) stroked.
    MeshBoundary(Vec<(u32, u32)>),
}

/// A panel ready to draw.
pub(crate) struct Scene<'a> {
    pub title: String,
    pub outline: Outline,
    pub mesh: Option<&'a Mesh>,
    pub colours: Option<Colours>,
    /// World bounding box of region and mesh.
    pub lo: DVec2,
    pub hi: DVec2,
    /// Pixels per world unit.
    pub scale: f64,
}

impl Scene<'_> {
    /// Drawing size in pixels (true aspect ratio).
    pub fn draw_size(&self) -> (f64, f64) {
        let e = (self.hi - self.lo) * self.scale;
        (e.x, e.y)
    }
}

/// A region as [`build`] takes it: its bounding box and a polygonizer (chord error → polygon).
pub(crate) type RegionSource<'r> = ((DVec2, DVec2), &'r dyn Fn(f64) -> Polygon);

/// Resolve every panel (polygonizing each region to a quarter-pixel chord error).
pub(crate) fn from_panels<'a>(
    panels: &[Panel<'a>],
    layout: &Layout,
) -> Result<Vec<Scene<'a>>, RenderError> {
    layout.validate()?;
    if panels.is_empty() {
        return Err(RenderError::NoPanels);
    }
    panels
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let region = p.region.map(|r| (r.bbox(), move |tol| r.polygonize(tol)));
            build(
                i,
                &p.title,
                region
                    .as_ref()
                    .map(|(bbox, f)| (*bbox, f as &dyn Fn(f64) -> Polygon)),
                p.mesh,
                p.colour_by.as_deref(),
                p.colour_label.as_deref(),
                layout.panel_px,
            )
        })
        .collect()
}

/// Build one scene from a region, a mesh, or both. Without a region the mesh alone sets the
/// frame and its boundary edges stand in for the region's boundary.
pub(crate) fn build<'a>(
    index: usize,
    title: &str,
    region: Option<RegionSource>,
    mesh: Option<&'a Mesh>,
    colour_by: Option<&[f64]>,
    colour_label: Option<&str>,
    panel_px: u32,
) -> Result<Scene<'a>, RenderError> {
    if region.is_none() && mesh.is_none() {
        return Err(RenderError::EmptyPanel(index));
    }
    let (mut lo, mut hi) = region.map_or(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |r| r.0,
    );
    if let Some(m) = mesh {
        check_mesh(index, m)?;
        for p in &m.points {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
    }
    let ext = hi - lo;
    let long = ext.x.max(ext.y);
    if !(lo.is_finite() && hi.is_finite() && long > 0.0) {
        return Err(RenderError::EmptyRegion(index));
    }
    let scale = panel_px as f64 / long;
    let outline = match (region, mesh) {
        (Some((_, polygonize)), _) => Outline::Region(polygonize(0.25 / scale)),
        (None, Some(m)) => Outline::MeshBoundary(boundary_edges(m)),
        (None, None) => unreachable!("refused above"),
    };
    let colours = match (colour_by, mesh) {
        (None, _) => None,
        (Some(_), None) => return Err(RenderError::ColourWithoutMesh(index)),
        (Some(v), Some(m)) => {
            if v.len() != m.num_triangles() {
                return Err(RenderError::ColourCount {
                    panel: index,
                    expected: m.num_triangles(),
                    got: v.len(),
                });
            }
            let range =
                v.iter()
                    .filter(|x| x.is_finite())
                    .fold(None, |acc: Option<(f64, f64)>, &x| {
                        Some(acc.map_or((x, x), |(a, b)| (a.min(x), b.max(x))))
                    });
            let (a, b) = range.unwrap_or((0.0, 0.0));
            let bins = v.iter().map(|&x| colormap::bin(x, a, b)).collect();
            Some(Colours {
                bins,
                range,
                label: colour_label.map(str::to_string),
            })
        }
    };
    Ok(Scene {
        title: title.to_string(),
        outline,
        mesh,
        colours,
        lo,
        hi,
        scale,
    })
}

fn check_mesh(index: usize, m: &Mesh) -> Result<(), RenderError> {
    let bad = |reason: String| {
        Err(RenderError::BadMesh {
            panel: index,
            reason,
        })
    };
    if let Some(p) = m.points.iter().position(|p| !p.is_finite()) {
        return bad(format!("vertex {p} is not finite"));
    }
    let n = m.points.len();
    if let Some(t) = m
        .triangles
        .iter()
        .position(|t| t.iter().any(|&v| v as usize >= n))
    {
        return bad(format!("triangle {t} refers to a vertex beyond {n}"));
    }
    Ok(())
}

/// Every undirected edge of the mesh once, so shared edges are not stroked twice (a double
/// anti-aliased stroke would look darker than a boundary-adjacent one).
pub(crate) fn unique_edges(m: &Mesh) -> Vec<(u32, u32)> {
    let mut keys: Vec<u64> = Vec::with_capacity(3 * m.triangles.len());
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (a, b) = if a < b { (a, b) } else { (b, a) };
            keys.push(((a as u64) << 32) | b as u64);
        }
    }
    keys.sort_unstable();
    keys.dedup();
    keys.into_iter()
        .map(|k| ((k >> 32) as u32, k as u32))
        .collect()
}

/// The edges of exactly one triangle, each once as (smaller, larger) vertex index, sorted. For
/// a conforming mesh these are the edges of its boundary loops, outer and holes alike.
pub(crate) fn boundary_edges(m: &Mesh) -> Vec<(u32, u32)> {
    let mut edges: Vec<(u32, u32)> = m
        .boundary_edges()
        .iter()
        .map(|e| (e.a.min(e.b), e.a.max(e.b)))
        .collect();
    edges.sort_unstable();
    edges
}

/// Mesh edge width in pixels: the layout's width, thinned when edges are short on screen
/// (mean edge under 5 px) so that a dense mesh stays readable instead of turning solid.
pub(crate) fn edge_width(scene: &Scene, edges: &[(u32, u32)], layout: &Layout) -> f32 {
    let Some(m) = scene.mesh else {
        return layout.mesh_stroke_px;
    };
    if edges.is_empty() {
        return layout.mesh_stroke_px;
    }
    let total: f64 = edges
        .iter()
        .map(|&(a, b)| (m.points[a as usize] - m.points[b as usize]).length())
        .sum();
    let mean_px = total / edges.len() as f64 * scene.scale;
    let w = if mean_px < 5.0 {
        layout.mesh_stroke_px as f64 * mean_px / 5.0
    } else {
        layout.mesh_stroke_px as f64
    };
    w.max(0.15) as f32
}

/// Short label of a value: about four significant digits, scientific for very large or
/// small magnitudes.
pub(crate) fn format_value(v: f64) -> String {
    if v == 0.0 {
        return "0".to_string();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.2e}");
    }
    let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}
