//! Turning command-line words into regions, meshes, methods and densities, with errors that
//! name the problem.
use anyhow::{anyhow, bail, Context, Result};
use cvtmesh::geometry::{Density, Region};
use cvtmesh::{Mesh, Mesher, Method};
use std::path::Path;

/// A region from a file (any supported format) or, if no such file exists, a built-in name.
/// `corner_angle` keeps only corners turning more than that many degrees.
pub fn region(spec: &str, corner_angle: Option<f64>) -> Result<Region> {
    let path = Path::new(spec);
    let region = if path.exists() || spec.contains('.') || spec.contains('/') {
        cvtmesh::geometry::formats::read_region(path)?
    } else {
        Region::builtin(spec)?
    };
    Ok(match corner_angle {
        Some(deg) if !(0.0..180.0).contains(&deg) => {
            bail!("--corner-angle must be in [0, 180) degrees, got {deg}")
        }
        Some(deg) => region.with_corner_angle(deg),
        None => region,
    })
}

/// A mesh from Triangle's .node (+ .ele beside it) or Gmsh's .msh.
pub fn mesh(path: &Path) -> Result<Mesh> {
    Ok(cvtmesh::io::read_mesh(path)?)
}

/// The mesher behind a `--method` word.
pub fn method(name: &str) -> Result<Box<dyn Mesher>> {
    Ok(name.parse::<Method>()?.mesher())
}

/// Parse `--density` (whether it is finite and non-negative on the region is
/// `MeshRequest::validate`'s to check).
pub fn density(expr: Option<&str>) -> Result<Density> {
    let Some(text) = expr else {
        return Ok(Density::Uniform);
    };
    cvtmesh::geometry::expr::density_from_expr(text).map_err(|e| anyhow!("--density '{text}': {e}"))
}

/// Output kind from the extension.
pub fn output_kind(path: &Path) -> Result<&'static str> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    Ok(match ext.as_str() {
        "node" | "ele" => "triangle",
        "msh" => "msh",
        "vtu" => "vtu",
        "obj" => "obj",
        "svg" => "svg",
        "png" => "png",
        _ => bail!(
            "cannot write '{}': unknown extension '.{ext}'; use .node, .msh, .vtu, .obj, .svg or .png",
            path.display()
        ),
    })
}

/// Write a mesh in the format its extension names (temp file + rename in every writer).
pub fn write(mesh: &Mesh, region: &Region, path: &Path, title: &str) -> Result<()> {
    match output_kind(path)? {
        "svg" | "png" => draw(Some(mesh), region, path, title, None),
        _ => Ok(cvtmesh::io::write_mesh(mesh, path)
            .with_context(|| format!("writing {}", path.display()))?),
    }
}

/// Draw a region, or a mesh on it, optionally coloured per triangle.
pub fn draw(
    mesh: Option<&Mesh>,
    region: &Region,
    path: &Path,
    title: &str,
    colour: Option<(Vec<f64>, String)>,
) -> Result<()> {
    let mut panel = render::Panel::new(title, region);
    if let Some(m) = mesh {
        panel = panel.with_mesh(m);
    }
    if let Some((values, label)) = colour {
        panel = panel.with_colour(values, label);
    }
    let layout = render::Layout::new(1).panel_px(1200);
    match output_kind(path)? {
        "png" => render::render_png(&[panel], &layout, path)?,
        "svg" => render::render_svg(&[panel], &layout, path)?,
        _ => bail!("'{}': pictures are .png or .svg", path.display()),
    }
    Ok(())
}
