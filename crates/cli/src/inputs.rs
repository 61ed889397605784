//! Turning command-line words into regions, meshes, methods and densities, with errors that
//! name the problem.
use anyhow::{anyhow, bail, Result};
use cvtmesh::geometry::{Density, Region, SizeField, Threshold, Toward};
use cvtmesh::io::Walls;
use cvtmesh::{Mesh, Mesher, Method};
use std::path::{Path, PathBuf};

/// Pixels spanned by the longer side of a picture's bounding box, unless `show --px` says.
pub const PICTURE_PX: u32 = 1200;

/// `raw` with its corners chosen, and a line saying how many were kept: `corner_angle` keeps
/// only corners turning more than that many degrees; without it a region whose corners were
/// computed keeps those turning more than the default ([`Region::with_default_corners`]).
pub fn with_corners(raw: Region, corner_angle: Option<f64>) -> Result<(Region, String)> {
    let all = raw.corners().len();
    let region = match corner_angle {
        Some(deg) => with_corner_angle(raw, deg)?,
        None => raw.with_default_corners(),
    };
    let kept = region.corners().len();
    let line = match (corner_angle, region.corner_threshold()) {
        (Some(deg), _) => format!(
            "corners: {kept} of {all} kept (--corner-angle {deg}: turning by more than {deg}°)"
        ),
        (None, Some(deg)) => format!(
            "corners: {kept} of {all} kept (turning by more than {deg}°, the default for computed corners; --corner-angle 0 keeps all)"
        ),
        (None, None) => format!("corners: {kept} (as the region lists them)"),
    };
    Ok((region, line))
}

/// `raw` with the points of `--embed X,Y[:M]` embedded ([`Region::with_embedded_points`]).
pub fn with_points(raw: Region, specs: &[String]) -> Result<Region> {
    if specs.is_empty() {
        return Ok(raw);
    }
    let mut points = Vec::with_capacity(specs.len());
    for s in specs {
        let (xy, marker) = match s.split_once(':') {
            Some((xy, m)) => (
                xy,
                m.trim()
                    .parse::<i64>()
                    .map_err(|_| anyhow!("--embed {s}: the marker after ':' must be an integer"))?,
            ),
            None => (s.as_str(), 0),
        };
        let (x, y) = xy
            .split_once(',')
            .ok_or_else(|| anyhow!("--embed {s}: expected X,Y or X,Y:MARKER"))?;
        let number = |t: &str| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| anyhow!("--embed {s}: '{t}' is not a finite number"))
        };
        points.push((cvtmesh::DVec2::new(number(x)?, number(y)?), marker));
    }
    Ok(raw.with_embedded_points(points)?)
}

/// A positive, finite number given to `flag`.
pub fn positive(flag: &str, word: &str) -> Result<f64> {
    match word.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => bail!("{flag} needs a positive number or `auto`, got '{word}'"),
    }
}

/// A region from a file (any supported format) or, if no such file exists, a built-in name.
/// `corner_angle` keeps only corners turning more than that many degrees.
pub fn region(spec: &str, corner_angle: Option<f64>) -> Result<Region> {
    let region = cvtmesh::load_region(spec)?;
    for note in region.notes() {
        eprintln!("warning: {note}");
    }
    match corner_angle {
        Some(deg) => with_corner_angle(region, deg),
        None => Ok(region),
    }
}

fn with_corner_angle(region: Region, deg: f64) -> Result<Region> {
    if !(0.0..180.0).contains(&deg) {
        bail!("--corner-angle must be in [0, 180) degrees, got {deg}")
    }
    Ok(region.with_corner_angle(deg))
}

/// The region `spec` names, or without one the region the triangles of `mesh` (read from
/// `path`, which numbers `walls`) cover, named after the file.
pub fn region_of(
    spec: Option<&str>,
    path: &Path,
    (mesh, walls): (&Mesh, &Walls),
) -> Result<Region> {
    if let Some(spec) = spec {
        return region(spec, None);
    }
    let region = cvtmesh::region_of_mesh(mesh, walls, path)
        .map_err(|e| anyhow!("no --region given, and the mesh is no region: {e}"))?;
    for note in region.notes() {
        eprintln!("warning: {note}");
    }
    Ok(region)
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

/// Parse `--size-field`: an expression, or a mesh file with a size at each vertex (its name
/// ends in `.node`, `.ele` or `.msh`). An expression's positivity on the region is checked
/// with the request.
pub fn size_field(text: &str, region: &Region) -> Result<SizeField> {
    if cvtmesh::io::names_sizes(Path::new(text)) {
        // The reader's errors name the file.
        let file =
            cvtmesh::io::read_sizes(Path::new(text)).map_err(|e| anyhow!("--size-field: {e}"))?;
        if let Some(view) = &file.view {
            eprintln!("note: {view}");
        }
        let (mesh, sizes) = (file.mesh, file.sizes);
        return SizeField::from_mesh(region, &mesh.points, &mesh.triangles, &sizes)
            .map_err(|e| anyhow!("--size-field {text}: {e}"));
    }
    SizeField::from_expr(text).map_err(|e| {
        // `sizes.txt` or `run3/h.h5` fails as an expression at its dot: say what was meant.
        let file_like = Path::new(text)
            .extension()
            .and_then(|x| x.to_str())
            .is_some_and(|x| {
                x.starts_with(|c: char| c.is_ascii_alphabetic())
                    && x.chars().all(|c| c.is_ascii_alphanumeric())
            })
            && !text.contains(|c: char| c.is_whitespace() || "+*^()".contains(c));
        if file_like {
            let what = if Path::new(text).exists() {
                "a file of another format"
            } else {
                "no such file"
            };
            anyhow!(
                "--size-field '{text}': {what}; a size field is an expression in x and y or a \
                 mesh with a size at each vertex (.node with .ele, or .msh)"
            )
        } else {
            anyhow!("--size-field: {e}")
        }
    })
}

/// The mesh files an argument reads where a mesh may be named (a region, a `--size-field`): a
/// Triangle `.node` with its `.ele`, a Gmsh `.msh`, a `.vtu` or an `.obj`, or none for anything
/// else (a region file, a built-in name, an expression).
pub fn mesh_files(text: &str) -> Vec<PathBuf> {
    let path = Path::new(text);
    if !cvtmesh::io::names_mesh(path) {
        Vec::new()
    } else if path.extension().is_some_and(|e| {
        ["msh", "vtu", "obj"]
            .iter()
            .any(|x| e.eq_ignore_ascii_case(x))
    }) {
        vec![path.to_path_buf()]
    } else {
        vec![path.with_extension("node"), path.with_extension("ele")]
    }
}

/// The size field of `--size-field` and `--size-toward`/`--size-threshold` (the smaller of the
/// two where both are given), or `None` for a uniform mesh.
pub fn graded_field(
    expr: Option<&str>,
    toward: &[String],
    threshold: Option<&str>,
    region: &Region,
) -> Result<Option<SizeField>> {
    let by_expr = expr.map(|e| size_field(e, region)).transpose()?;
    let by_distance = if toward.is_empty() {
        None
    } else {
        let targets = toward
            .iter()
            .map(|t| {
                t.parse::<Toward>()
                    .map_err(|e| anyhow!("--size-toward {e}"))
            })
            .collect::<Result<Vec<_>>>()?;
        let t = threshold.ok_or_else(|| anyhow!("--size-toward needs --size-threshold"))?;
        let v: Vec<f64> = t
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| {
                anyhow!("--size-threshold '{t}': expected four numbers HMIN,HMAX,DMIN,DMAX")
            })?;
        let [size_min, size_max, dist_min, dist_max] = v[..] else {
            bail!("--size-threshold '{t}': expected four numbers HMIN,HMAX,DMIN,DMAX");
        };
        let threshold = Threshold {
            size_min,
            size_max,
            dist_min,
            dist_max,
        };
        Some(SizeField::threshold(region, &targets, threshold)?)
    };
    Ok(match (by_expr, by_distance) {
        (Some(a), Some(b)) => Some(a.min(&b, region)?),
        (a, b) => a.or(b),
    })
}

/// Output kind from the extension.
pub fn output_kind(path: &Path) -> Result<&'static str> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    Ok(match ext.as_str() {
        "node" | "ele" | "poly" => "triangle",
        "msh" => "msh",
        "vtu" => "vtu",
        "obj" => "obj",
        "svg" => "svg",
        "png" => "png",
        "" => bail!(
            "cannot write '{}': no extension to choose the format by; use .node, .msh, .vtu, .obj, .svg or .png",
            path.display()
        ),
        _ => bail!(
            "cannot write '{}': unknown extension '.{ext}'; use .node, .msh, .vtu, .obj, .svg or .png",
            path.display()
        ),
    })
}

/// Refuse an output whose directory does not exist, or takes no new file, before any work
/// rather than after it: a file is created there (as the writers create their temporary files
/// beside the output) and removed.
pub fn check_directory(output: &Path) -> Result<()> {
    let dir = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        bail!(
            "cannot write '{}': no directory '{}'; nothing written",
            output.display(),
            dir.display()
        );
    }
    let probe = dir.join(format!(".cvtmesh-probe.{}.tmp", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => bail!(
            "cannot write '{}': the directory '{}' takes no new file ({e}); nothing written",
            output.display(),
            dir.display()
        ),
    }
    Ok(())
}

/// Refuse an output that would replace an input file: `-o coast.node` writes `coast.poly`
/// beside it, which is the region itself when the region was read from `coast.poly`.
pub fn check_not_input(output: &Path, inputs: &[&Path]) -> Result<()> {
    let inputs: Vec<_> = inputs
        .iter()
        .filter_map(|p| std::fs::canonicalize(p).ok())
        .collect();
    for file in cvtmesh::io::files_written(output) {
        if let Ok(c) = std::fs::canonicalize(&file) {
            if inputs.contains(&c) {
                let why = if file.as_path() == output {
                    ""
                } else {
                    " (Triangle's format writes .node, .ele and .poly files of that name)"
                };
                bail!(
                    "writing '{}' would replace the input file '{}'{why}; choose another output \
                     name; nothing written",
                    output.display(),
                    file.display()
                );
            }
        }
    }
    Ok(())
}

/// Whether the format `path` names holds six-node triangles ([`cvtmesh::io::write_quadratic`]).
pub fn holds_six_nodes(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        cvtmesh::io::QUADRATIC_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str())
    })
}

/// Write `mesh`, with the six-node triangles of `quadratic` where given (the same mesh's), in
/// the format the extension names.
pub fn write_order(
    mesh: &Mesh,
    quadratic: Option<&cvtmesh::Quadratic>,
    region: &Region,
    path: &Path,
    title: &str,
) -> Result<()> {
    match quadratic {
        Some(q) => written(cvtmesh::io::write_quadratic(q, path), path),
        None => write(mesh, region, path, title),
    }
}

/// Write a mesh in the format its extension names (temp file + rename in every writer).
pub fn write(mesh: &Mesh, region: &Region, path: &Path, title: &str) -> Result<()> {
    match output_kind(path)? {
        "svg" | "png" => draw(Some(mesh), region, path, title, None, PICTURE_PX),
        _ => written(cvtmesh::io::write_mesh_on(mesh, region, path), path),
    }
}

/// A mesh writer's result, its error naming the file `path`.
pub fn written(result: Result<(), cvtmesh::MeshError>, path: &Path) -> Result<()> {
    result.map_err(|e| {
        // Most of the writer's errors name the file already.
        let named = e.to_string().contains(&path.display().to_string());
        let e = anyhow::Error::new(e);
        if named {
            e
        } else {
            e.context(format!("writing {}", path.display()))
        }
    })
}

/// Draw a region, or a mesh on it, optionally coloured per triangle, `px` pixels across.
pub fn draw(
    mesh: Option<&Mesh>,
    region: &Region,
    path: &Path,
    title: &str,
    colour: Option<(Vec<f64>, String)>,
    px: u32,
) -> Result<()> {
    let mut panel = render::Panel::new(title, region);
    if let Some(m) = mesh {
        panel = panel.with_mesh(m);
    }
    picture(panel, colour, path, px)
}

/// Draw a mesh without its region: its own boundary edges stand in for the region's.
pub fn draw_mesh(
    mesh: &Mesh,
    path: &Path,
    title: &str,
    colour: Option<(Vec<f64>, String)>,
    px: u32,
) -> Result<()> {
    picture(render::Panel::for_mesh(title, mesh), colour, path, px)
}

/// Write one panel, optionally coloured per triangle, as the picture `path` names.
fn picture(
    mut panel: render::Panel,
    colour: Option<(Vec<f64>, String)>,
    path: &Path,
    px: u32,
) -> Result<()> {
    if let Some((values, label)) = colour {
        panel = panel.with_colour(values, label);
    }
    let layout = render::Layout::new(1).panel_px(px);
    match output_kind(path)? {
        "png" => render::render_png(&[panel], &layout, path)?,
        "svg" => render::render_svg(&[panel], &layout, path)?,
        _ => bail!("'{}': pictures are .png or .svg", path.display()),
    }
    Ok(())
}
