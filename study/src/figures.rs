//! Figures 3–7 (a panel per region and method, methods as rows as in the paper) and one
//! picture per mesh for close inspection.
use crate::output::{figure_png, mesh_png};
use crate::paper::{table_for, TABLES};
use crate::{MethodId, StudyError};
use cvtmesh::geometry::Region;
use cvtmesh::Mesh;
use render::{Layout, Panel};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The meshes to draw: one per (region, K, method) (the lowest seed run).
pub type MeshSet = BTreeMap<(String, usize, MethodId), Mesh>;

/// One of the paper's figures.
#[derive(Clone, Copy, Debug)]
pub struct FigureSpec {
    /// Figure number, 3..=7.
    pub number: u8,
    /// Title above the grid.
    pub title: &'static str,
    /// Panels per row: the regions side by side, or for Fig. 7 the methods left to right.
    pub columns: usize,
    /// True if the regions are the columns and the methods the rows (Figs. 3–6).
    pub methods_as_rows: bool,
}

/// Figures 3–7.
pub const FIGURES: [FigureSpec; 5] = [
    FigureSpec { number: 3, title: "Fig. 3. Meshes for a unit circle (K = 19, 88, 362); rows: methods", columns: 3, methods_as_rows: true },
    FigureSpec { number: 4, title: "Fig. 4. Annulus, square with a circular hole, hexagon with a hexagonal hole; rows: methods", columns: 3, methods_as_rows: true },
    FigureSpec { number: 5, title: "Fig. 5. \"Horn\", super-ellipse, \"bicycle seat\"; rows: methods", columns: 3, methods_as_rows: true },
    FigureSpec { number: 6, title: "Fig. 6. \"Pie slice\" with a circular hole, square with 2 hexagonal holes; rows: methods", columns: 2, methods_as_rows: true },
    FigureSpec { number: 7, title: "Fig. 7. \"Lake\" with an island; left to right, top to bottom: methods", columns: 4, methods_as_rows: false },
];

fn panel_title(method: MethodId, region: &str, k: usize, mesh: &Mesh) -> String {
    format!(
        "{} · {region} K={k} ({} pts, {} tri)",
        method.column(),
        mesh.num_vertices(),
        mesh.num_triangles()
    )
}

/// The panels of one figure in row-major order, with empty region-only panels where a
/// method has no mesh for a region (so the grid stays aligned).
fn figure_panels<'a>(
    spec: &FigureSpec,
    regions: &'a BTreeMap<&'static str, Region>,
    meshes: &'a MeshSet,
    methods: &[MethodId],
) -> Vec<Panel<'a>> {
    let cells: Vec<(&'static str, usize)> = TABLES
        .iter()
        .filter(|t| t.figure == spec.number)
        .map(|t| (t.region, t.k))
        .collect();
    let mut panels = Vec::new();
    for &method in methods {
        for &(region, k) in &cells {
            let Some(r) = regions.get(region) else {
                continue;
            };
            match meshes.get(&(region.to_string(), k, method)) {
                Some(m) => {
                    panels.push(Panel::new(panel_title(method, region, k, m), r).with_mesh(m))
                }
                None if spec.methods_as_rows => panels.push(Panel::new(
                    format!("{} · {region} K={k}: no mesh", method.column()),
                    r,
                )),
                None => {}
            }
        }
    }
    panels
}

/// Draw Figures 3–7 and a picture per mesh under `dir/figures`. Figures without any mesh
/// are skipped. Returns the files written.
pub fn draw_figures(
    dir: &Path,
    regions: &BTreeMap<&'static str, Region>,
    meshes: &MeshSet,
    methods: &[MethodId],
) -> Result<Vec<PathBuf>, StudyError> {
    use rayon::prelude::*;
    let mut written = Vec::new();
    for spec in &FIGURES {
        let has_mesh = meshes
            .keys()
            .any(|(r, k, _)| table_for(r, *k).is_some_and(|t| t.figure == spec.number));
        if !has_mesh {
            continue;
        }
        let used: Vec<MethodId> = methods
            .iter()
            .copied()
            .filter(|m| {
                meshes.keys().any(|(r, k, mm)| {
                    mm == m && table_for(r, *k).is_some_and(|t| t.figure == spec.number)
                })
            })
            .collect();
        let panels = figure_panels(spec, regions, meshes, &used);
        let columns = if spec.methods_as_rows {
            spec.columns
        } else {
            spec.columns.min(panels.len()).max(1)
        };
        let px = if spec.number == 7 { 420 } else { 300 };
        let layout = Layout::new(columns).panel_px(px).title(spec.title);
        let path = figure_png(dir, spec.number);
        crate::output::create_dir(path.parent().unwrap_or(dir))?;
        render::render_png(&panels, &layout, &path)?;
        written.push(path);
    }
    let singles: Vec<(&(String, usize, MethodId), &Mesh)> = meshes
        .iter()
        .filter(|((r, _, _), _)| regions.contains_key(r.as_str()))
        .collect();
    if let Some(((r, k, m), _)) = singles.first() {
        let p = mesh_png(dir, r, *k, *m);
        crate::output::create_dir(p.parent().unwrap_or(dir))?;
    }
    let more: Vec<PathBuf> = singles
        .par_iter()
        .map(|((r, k, m), mesh)| {
            let region = &regions[r.as_str()];
            let title = format!(
                "{}: {r}, K = {k} requested ({} vertices, {} triangles)",
                m.column(),
                mesh.num_vertices(),
                mesh.num_triangles()
            );
            let path = mesh_png(dir, r, *k, *m);
            render::render_png(
                &[Panel::new(title, region).with_mesh(mesh)],
                &Layout::new(1).panel_px(700),
                &path,
            )?;
            Ok(path)
        })
        .collect::<Result<_, StudyError>>()?;
    written.extend(more);
    Ok(written)
}
