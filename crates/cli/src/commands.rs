//! The four subcommands.
use crate::inputs;
use anyhow::{anyhow, bail, Result};
use clap::{ArgGroup, Args};
use cvtmesh::geometry::Region;
use cvtmesh::{MeshRequest, Method, Size};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Instant;

const DEFAULT_TOL: f64 = 1e-4;
/// The default gradation limit of size fields: mmg's default ratio of 1.3 between adjacent
/// edges, as a slope.
const GRADATION: f64 = 0.3;
/// Largest `--sampled` count.
const MAX_SAMPLES: usize = 100_000_000;

/// `cvtmesh mesh`.
#[derive(Args)]
#[command(group(ArgGroup::new("graded").multiple(true).args(["size_field", "size_toward"])))]
#[command(group(
    ArgGroup::new("how_many")
        .required(true)
        .multiple(true)
        .args(["points", "size", "size_field", "size_toward"])
))]
pub struct MeshArgs {
    /// Region file (.json, .geojson, .poly, .txt loop list), built-in name (see `cvtmesh regions`), or a mesh (.node/.ele, .msh, .vtu, .obj): the region its triangles cover, to mesh again.
    region: String,
    /// Number of vertices K (one of --points, --size, --size-field and --size-toward is
    /// required; with a size field, the field's shape is kept and scaled to K vertices).
    #[arg(long, short = 'n', conflicts_with = "size")]
    points: Option<usize>,
    /// Target edge length h of a uniform mesh; K follows from the region's area (instead of
    /// --points; a graded mesh takes --size-field or --size-toward).
    #[arg(
        long,
        conflicts_with_all = ["graded", "density", "size_threshold", "size_min", "size_max"],
        allow_negative_numbers = true
    )]
    size: Option<f64>,
    /// Target edge length for graded meshes: a function of x and y, e.g.
    /// '0.01 + 0.1*sqrt(x^2+y^2)', or a mesh with a size at each vertex (Triangle FILE.node
    /// whose first attribute is h, with FILE.ele; Gmsh FILE.msh with a $NodeData view),
    /// linear on its triangles, as an adaptive solver leaves them or Gmsh takes a background
    /// mesh; K follows from the field, (2/√3)∫h⁻², unless --points is given [default: none,
    /// a uniform mesh].
    #[arg(
        long,
        value_name = "EXPR|MESH",
        conflicts_with = "density",
        allow_hyphen_values = true
    )]
    size_field: Option<String>,
    /// Refine toward a boundary loop (`loop:0` the outer one, `loop:1` the first hole, ...; in a
    /// region of several parts each outer loop is followed by its holes), one boundary piece
    /// (`piece:J`, a wall: `cvtmesh regions REGION` lists them), the walls a `.poly` marks
    /// with one number (`marker:M`, its segment marker; lines so marked too), a line inside (`line:L`, a material
    /// interface: `regions` lists them too) or a point (`point:X,Y`); repeat for several. The size grows with the distance as
    /// --size-threshold says (Gmsh's Distance + Threshold), and the smaller of this and
    /// --size-field is used [default: none].
    #[arg(
        long,
        value_name = "loop:I|piece:J|marker:M|line:L|point:X,Y",
        conflicts_with = "density",
        requires = "size_threshold"
    )]
    size_toward: Vec<String>,
    /// For --size-toward: HMIN,HMAX,DMIN,DMAX: edge length HMIN up to distance DMIN, HMAX from
    /// DMAX on, linear between [default: none].
    #[arg(
        long,
        value_name = "HMIN,HMAX,DMIN,DMAX",
        requires = "size_toward",
        allow_hyphen_values = true
    )]
    size_threshold: Option<String>,
    /// A point inside the region that the mesh keeps as a vertex (a source, a probe), with an
    /// optional marker for the files (`X,Y:M`); repeat for several. A `.poly`'s vertices on no
    /// segment are such points too [default: none].
    #[arg(long, value_name = "X,Y[:M]", allow_hyphen_values = true)]
    embed: Vec<String>,
    #[command(flatten)]
    bounds: FieldBounds,
    // The names come from `Method::ALL`, so the help cannot fall behind the list of methods.
    #[arg(long, short = 'm', help = method_help(), default_value_t = Method::default().to_string())]
    method: String,
    /// Density ρ(x, y) for graded meshes, e.g. '1 + 10*exp(-((x-0.5)^2+y^2)/0.01)'
    /// [default: 1, a uniform mesh].
    #[arg(long)]
    density: Option<String>,
    /// Seed of every random choice.
    #[arg(long, default_value_t = MeshRequest::points(0).seed)]
    seed: u64,
    /// Convergence tolerance: largest generator move relative to the mean spacing (CVT methods;
    /// DistMesh keeps its original dptol, refinement is not iterative).
    #[arg(long, default_value = "1e-4", allow_negative_numbers = true)]
    tol: f64,
    /// Iteration cap of each phase: CCVT's Algorithm 2 runs several (ε-phases, then the
    /// constrained one), and the iterations printed are their sum.
    #[arg(long, default_value_t = MeshRequest::points(0).max_iter)]
    max_iter: usize,
    /// Stop iterating after this many seconds and write the mesh reached, marked not
    /// converged (every method; CCVT ends each phase with one more step) [default: none].
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    time_limit: Option<f64>,
    /// Keep only corners whose turning angle exceeds this (degrees); 0 keeps every vertex where
    /// the boundary turns. The default applies where the corners are computed (polygon files);
    /// built-in regions and JSON with "corners" keep theirs [default: 30, or the corners the
    /// region lists].
    #[arg(long, allow_negative_numbers = true)]
    corner_angle: Option<f64>,
    /// Simplify a digitized boundary and lines inside first (Douglas–Peucker): drop the
    /// vertices that lie within TOL of the simplified boundary or line, so that a coastline or
    /// an interface with more vertices than the mesh has can be meshed coarsely; `auto` is a
    /// quarter of the spacing. The mesh is of the simplified region, which stays within the
    /// printed distance of the original [default: none, the boundary as given].
    #[arg(long, value_name = "TOL|auto", allow_negative_numbers = true)]
    simplify: Option<String>,
    /// Polish: move the vertices of triangles with an angle below this many degrees to raise
    /// the smallest angle around them (boundary vertices along the boundary, corners fixed),
    /// keeping the triangles (and a Delaunay mesh Delaunay); 0 keeps every vertex where the
    /// method put it.
    #[arg(long, value_name = "DEGREES", default_value_t = MeshRequest::points(0).polish_below_deg, allow_negative_numbers = true)]
    polish: f64,
    /// Element order: 1 writes three-node triangles; 2 six-node (quadratic) triangles with a
    /// node on every edge, on the region's exact boundary (arcs, circles, curves) where the
    /// edge is a boundary edge, as P2 finite elements use them (.msh, .vtu or .node/.ele).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=2))]
    order: u8,
    /// Fail (exit 1, mesh still written) if the iteration cap is reached before convergence;
    /// refuse (before any work) a region narrower than half the spacing somewhere, and (nothing
    /// written) a mesh that leaves out a tenth of the region or has triangles flatter than 1°.
    #[arg(long)]
    strict: bool,
    /// No progress bar.
    #[arg(long, short)]
    quiet: bool,
    /// Output file; the format follows the extension (.svg and .png pictures draw the region
    /// 1200 px along the longer side of its bounding box, with a margin and a title around).
    #[arg(long, short)]
    output: PathBuf,
}

/// `--method`'s help: every name (and alias) of [`Method::ALL`], the default first.
fn method_help() -> String {
    let names: Vec<String> = Method::ALL
        .iter()
        .map(|m| match m.aliases() {
            [] => m.name().to_string(),
            aliases => format!("{} (or {})", m.name(), aliases.join(", ")),
        })
        .collect();
    format!(
        "Method: {}; {} is Algorithm 2 with Newton's method",
        names.join(", "),
        Method::default()
    )
}

/// The request `a` makes of `region`, and for a size field a line saying the K it gives.
/// The request of `mesh`'s options for `region`; `named` is the region whose loops and pieces
/// `--size-toward` numbers (the region as given, with its corners, before any simplification:
/// what `cvtmesh regions` lists).
fn request(a: &MeshArgs, region: &Region, named: &Region) -> Result<(MeshRequest, Option<String>)> {
    let graded = inputs::graded_field(
        a.size_field.as_deref(),
        &a.size_toward,
        a.size_threshold.as_deref(),
        named,
    )?;
    let (request, line) = match graded {
        Some(field) => {
            let (r, field, note) = MeshRequest::bounded_size_field(
                &field,
                region,
                a.bounds.size_min,
                a.bounds.size_max,
                Some(a.bounds.gradation),
                a.points,
            )?;
            let mut line = format!(
                "size field: K = {} ({:.0} asked for by the field)",
                r.size.points(region),
                field.predicted_points(region)
            );
            if let Some(note) = note {
                line.push_str(&format!("\nnote: {note}"));
            }
            if let Some(u) = field.unresolved(region) {
                line.push_str(&format!("\nwarning: {}", u.for_mesh()));
            }
            (r, Some(line))
        }
        None => {
            let size = match (a.points, a.size) {
                (Some(k), _) => Size::Points(k),
                (None, Some(h)) => Size::EdgeLength(h),
                (None, None) => bail!("give --points K, --size H or --size-field EXPR"),
            };
            let r = MeshRequest {
                size,
                density: inputs::density(a.density.as_deref())?,
                ..MeshRequest::points(0)
            };
            (r, None)
        }
    };
    Ok((
        request
            .seed(a.seed)
            .tol(a.tol)
            .max_iter(a.max_iter)
            .polish(a.polish),
        line,
    ))
}

/// `cvtmesh mesh`: mesh, report, write.
pub fn mesh(a: MeshArgs) -> Result<()> {
    inputs::output_kind(&a.output)?;
    inputs::check_directory(&a.output)?;
    if a.order == 2 && !inputs::holds_six_nodes(&a.output) {
        bail!(
            "--order 2 writes six-node triangles, which '{}' cannot hold; use .msh, .vtu or .node",
            a.output.display()
        );
    }
    // A region or a size field given as a mesh is read from its files (.node with .ele).
    let field_files = a.size_field.iter().flat_map(|f| inputs::mesh_files(f));
    let read: Vec<PathBuf> = std::iter::once(PathBuf::from(&a.region))
        .chain(inputs::mesh_files(&a.region))
        .chain(field_files)
        .collect();
    let read: Vec<&Path> = read.iter().map(|p| p.as_path()).collect();
    inputs::check_not_input(&a.output, &read)?;
    let method = inputs::method(&a.method)?;
    let raw = inputs::with_points(inputs::region(&a.region, None)?, &a.embed)?;
    let (mut region, mut corners) = inputs::with_corners(raw.clone(), a.corner_angle)?;
    let named = region.clone();
    if let Some(spec) = &a.simplify {
        let tol = match spec.as_str() {
            "auto" => request(&a, &region, &named)?.0.simplify_tolerance(&region),
            t => inputs::positive("--simplify", t)?,
        };
        let s = raw.simplified(tol)?;
        eprintln!("{s}");
        (region, corners) = inputs::with_corners(s.region, a.corner_angle)?;
    }
    eprintln!("{corners}");
    if region.num_parts() > 1 {
        eprintln!(
            "region: {} disjoint parts, meshed one by one with K shared by area",
            region.num_parts()
        );
    }
    // Timed from here: building the size field (distance queries onto its background grid) is
    // part of meshing, as it is inside Gmsh's `generate`.
    let start = Instant::now();
    let (request, field_line) = request(&a, &region, &named)?;
    if let Some(line) = field_line {
        eprintln!("{line}");
    }
    let k = request.validate_whole(&region)?;
    if let Some(thin) = cvtmesh::thin_feature(&region, &request) {
        if a.strict {
            bail!("--strict: {thin}; nothing written");
        }
        eprintln!("warning: {thin}");
    }
    if a.tol != DEFAULT_TOL {
        let why = match method.name() {
            "distmesh" => "DistMesh stops at its original dptol = 1e-3·h0",
            "refine" => "refinement is not iterative",
            _ => "",
        };
        if !why.is_empty() {
            eprintln!("note: --tol does not apply to {}: {why}", method.name());
        }
    }
    let request = match a.time_limit {
        Some(s) => request.time_limit_secs(s)?,
        None => request,
    };
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(a.max_iter as u64)
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed})")
            .expect("static template")
            .progress_chars("=> "),
    );
    bar.set_prefix(format!("{} K={k}", method.name()));
    let result = method.mesh_parts(&region, &request, &mut |p| {
        bar.set_position(p.iteration as u64);
        bar.set_message(format!("energy {:.6e}  move {:.2e}", p.energy, p.max_move));
    })?;
    bar.finish_and_clear();
    let seconds = start.elapsed().as_secs_f64();
    if let Some(short) = cvtmesh::short_coverage(&result.mesh, &region) {
        if a.strict {
            bail!("--strict: {short}; nothing written");
        }
        eprintln!("warning: {short}");
    }
    let (min_angle, slivers) = cvtmesh::min_angle_and_slivers(&result.mesh, &region);
    if let Some(slivers) = slivers {
        let advice = cvtmesh::sliver_advice(&region, method.as_ref())
            .map(|a| format!("; {a}"))
            .unwrap_or_default();
        if a.strict {
            bail!("--strict: {slivers}{advice}; nothing written");
        }
        eprintln!("warning: {slivers}{advice}");
    }
    // `mesh_parts` has checked that the mesh conforms (up to CONFORMITY_CHECK_LIMIT vertices).
    let title = format!(
        "{} {} K={}",
        region.name(),
        method.name(),
        result.mesh.num_vertices()
    );
    let quadratic = (a.order == 2).then(|| cvtmesh::Quadratic::new(&result.mesh, Some(&region)));
    inputs::write_order(&result.mesh, quadratic.as_ref(), &region, &a.output, &title)?;
    for note in &result.notes {
        eprintln!("note: {note}");
    }
    // Only the CVT methods minimise an energy; the others report none.
    let energy = match result.energy_history.last() {
        Some(e) if e.is_finite() => format!(" energy={e:.6e}"),
        _ => String::new(),
    };
    outln!(
        "K={} K~={} min-angle={:.2}deg iterations={}{} {} {:.2}s -> {}",
        result.mesh.num_vertices(),
        result.mesh.num_triangles(),
        min_angle,
        result.iterations,
        energy,
        if result.converged {
            "converged"
        } else if result.iterations >= a.max_iter {
            "NOT CONVERGED (iteration cap reached)"
        } else if request.out_of_time() {
            "NOT CONVERGED (time limit reached)"
        } else {
            // The method stopped on a rule of its own (CCVT: ε did not settle; refinement:
            // the area-bound search was capped), which its notes name.
            "NOT CONVERGED (see the notes)"
        },
        seconds,
        a.output.display()
    );
    if a.strict && !result.converged {
        let why = if result.iterations >= a.max_iter {
            format!("a phase reached the iteration cap {}", a.max_iter)
        } else if request.out_of_time() {
            "the time limit reached".to_string()
        } else {
            "see the notes".to_string()
        };
        bail!(
            "--strict: {} did not converge ({} iterations, {why}; mesh written anyway)",
            method.name(),
            result.iterations,
        );
    }
    Ok(())
}

/// `cvtmesh polish`.
#[derive(Args)]
pub struct PolishArgs {
    /// Mesh: Triangle FILE.node (with FILE.ele beside it), Gmsh FILE.msh, VTK FILE.vtu or Wavefront FILE.obj;
    /// its boundary vertices are those the file marks, or those on an edge of one triangle.
    mesh: PathBuf,
    /// The region the mesh is of (file or built-in name): boundary vertices slide along it
    /// [default: the region the mesh's triangles cover, every vertex where its boundary turns
    /// a corner, so the boundary stays as it is].
    #[arg(long, short)]
    region: Option<String>,
    /// Move the vertices of triangles with an angle below this many degrees.
    #[arg(long, value_name = "DEGREES", default_value_t = cvtmesh::POLISH_BELOW_DEG, allow_negative_numbers = true)]
    below: f64,
    /// Output file; the format follows the extension, as for `mesh`.
    #[arg(long, short)]
    output: PathBuf,
}

/// `cvtmesh polish`: a mesh from any tool, polished as `mesh` polishes its own.
pub fn polish(a: PolishArgs) -> Result<()> {
    let kind = inputs::output_kind(&a.output)?;
    inputs::check_directory(&a.output)?;
    inputs::check_not_input(&a.output, &[a.mesh.as_path()])?;
    if !(0.0..=60.0).contains(&a.below) {
        bail!(
            "--below must be an angle from 0 to 60 degrees, got {}",
            a.below
        );
    }
    let file = cvtmesh::io::read_mesh_file(&a.mesh)?;
    let mut mesh = file.mesh;
    let region = inputs::region_of(a.region.as_deref(), &a.mesh, (&mesh, &file.walls))?;
    // Where the vertices were, to tell a higher-order file's edges the polish left alone.
    let unpolished = match file.triangle_nodes {
        3 => Vec::new(),
        _ => mesh.points.clone(),
    };
    let start = Instant::now();
    // Lines the file keeps inside the mesh (a material interface) stay where they are: their
    // vertices are held, or slide along a straight run of a line of the region.
    let held = file.walls.inner_vertices();
    if !held.is_empty() {
        eprintln!(
            "note: {} vertices on the {} edges the file keeps inside the mesh (an \
             interface, a line of its own) stay on them",
            held.len(),
            file.walls.inner.len()
        );
    }
    let report = match cvtmesh::polish_restored_holding(&mut mesh, &region, a.below, &held) {
        Ok(report) => report,
        Err(e) => bail!(
            "the mesh does not conform to region '{}' ({e}): its boundary vertices cannot be placed on the region; nothing written",
            region.name()
        ),
    };
    if !report.kept {
        eprintln!("note: {report}");
    }
    let title = format!("{} polished K={}", region.name(), mesh.num_vertices());
    // Higher-order triangles in, six-node triangles out: the file's edge nodes stay where
    // neither end moved; the others are placed as `mesh --order 2` places them.
    let n = file.triangle_nodes;
    let picture = matches!(kind, "svg" | "png");
    let quadratic = (n > 3 && inputs::holds_six_nodes(&a.output)).then(|| {
        let still = |v: u32| mesh.points[v as usize] == unpolished[v as usize];
        let kept: Vec<_> = file
            .edge_nodes
            .iter()
            .filter(|([u, v], _)| still(*u) && still(*v))
            .copied()
            .collect();
        let placed = file.edge_nodes.len() - kept.len();
        let what = match n {
            6 => "six-node triangles".to_string(),
            _ => format!("{n}-node triangles written as six-node ones"),
        };
        eprintln!(
            "note: {what}: {} edge nodes kept, {placed} placed again at the moved vertices' \
             edges (midpoints; on the boundary of --region for boundary edges)",
            kept.len()
        );
        cvtmesh::Quadratic::new(&mesh, Some(&region)).keeping(&kept)
    });
    if n > 3 && quadratic.is_none() && !picture {
        eprintln!(
            "note: {n}-node triangles written as three-node ones: '{}' holds no edge nodes",
            a.output.display()
        );
    }
    inputs::write_order(&mesh, quadratic.as_ref(), &region, &a.output, &title)?;
    outln!(
        "K={} K~={} moved={} min-angle={:.2}deg -> {:.2}deg {:.2}s -> {}",
        mesh.num_vertices(),
        mesh.num_triangles(),
        if report.kept {
            report.polished.moved
        } else {
            0
        },
        report.polished.before_deg,
        if report.kept {
            report.polished.after_deg
        } else {
            report.polished.before_deg
        },
        start.elapsed().as_secs_f64(),
        a.output.display()
    );
    Ok(())
}

/// `cvtmesh measure`.
#[derive(Args)]
#[command(group(ArgGroup::new("graded").multiple(true).args(["size_field", "size_toward"])))]
pub struct MeasureArgs {
    /// Mesh: Triangle FILE.node (with FILE.ele beside it), Gmsh FILE.msh, VTK FILE.vtu or Wavefront FILE.obj.
    mesh: PathBuf,
    /// The region the mesh is of (file or built-in name) [default: the region the mesh's
    /// triangles cover].
    #[arg(long, short)]
    region: Option<String>,
    /// Two CSV lines (header, values at full precision) instead of a table.
    #[arg(long)]
    csv: bool,
    /// Also print the paper-style Monte-Carlo estimate with this many samples (seed 1)
    /// [default: none, exact measures only].
    #[arg(long)]
    sampled: Option<usize>,
    /// Coordinate scale for the sampled estimate (the paper's circle/annulus τ, d match 0.5).
    #[arg(
        long,
        default_value_t = 1.0,
        requires = "sampled",
        allow_negative_numbers = true
    )]
    scale: f64,
    /// Also print how well the edges follow this size field h(x, y) (an expression or a mesh
    /// with a size at each vertex, as for `mesh`): the share of edges with length/h in
    /// [1/√2, √2], the efficiency index, the smallest angles, and the vertex count the field
    /// asks for [default: none].
    #[arg(long, value_name = "EXPR|MESH", allow_hyphen_values = true)]
    size_field: Option<String>,
    /// As for `mesh`: measure against the distance field toward this loop, piece, marker, line or point (with
    /// --size-threshold; the smaller of this and --size-field where both are given)
    /// [default: none].
    #[arg(
        long,
        value_name = "loop:I|piece:J|marker:M|line:L|point:X,Y",
        requires = "size_threshold"
    )]
    size_toward: Vec<String>,
    /// As for `mesh`: HMIN,HMAX,DMIN,DMAX of --size-toward's field [default: none].
    #[arg(
        long,
        value_name = "HMIN,HMAX,DMIN,DMAX",
        requires = "size_toward",
        allow_hyphen_values = true
    )]
    size_threshold: Option<String>,
    /// As for `mesh`: the corner angle that numbers the pieces --size-toward piece:J names
    /// [default: as `mesh` does].
    #[arg(long, requires = "size_toward", allow_negative_numbers = true)]
    corner_angle: Option<f64>,
    /// The bounds of the field measured against, as `mesh` takes them: the same options
    /// measure the field `mesh` meshed.
    #[command(flatten)]
    bounds: FieldBounds,
}

/// How a size field is bounded, for `mesh` and `measure` alike.
#[derive(Args)]
pub struct FieldBounds {
    /// Smallest edge length of the size field, which the mesh keeps (`mesh` refuses it with
    /// --points, which scales the field) [default: none].
    #[arg(long, requires = "graded", allow_negative_numbers = true)]
    size_min: Option<f64>,
    /// Largest edge length of the size field, which the mesh keeps (`mesh` refuses it with
    /// --points) [default: none].
    #[arg(long, requires = "graded", allow_negative_numbers = true)]
    size_max: Option<f64>,
    /// Largest gradient of the size field's edge length: sizes grow by at most this much per
    /// unit of distance, h(x) = min_y h(y) + g|x − y| (`inf` leaves the field as given).
    #[arg(long, default_value_t = GRADATION, requires = "graded", allow_negative_numbers = true)]
    gradation: f64,
}

/// `cvtmesh measure`: the 12 measures of Section 3.
pub fn measure(a: MeasureArgs) -> Result<()> {
    let file = cvtmesh::io::read_mesh_file(&a.mesh)?;
    if file.triangle_nodes > 3 {
        eprintln!(
            "note: {}-node triangles measured as the three-node mesh of their corners",
            file.triangle_nodes
        );
    }
    let (mesh, walls) = (file.mesh, file.walls);
    let region = inputs::region_of(a.region.as_deref(), &a.mesh, (&mesh, &walls))?;
    let fit = cvtmesh::measurable(&mesh, &region)
        .map_err(|e| anyhow!("{e}; without --region the mesh's own is measured"))?;
    if let Some(e) = fit {
        eprintln!(
            "warning: the mesh does not conform to region '{}': {e}",
            region.name()
        );
    }
    if let Some(slivers) = cvtmesh::slivers_in_region(&mesh, &region) {
        eprintln!("warning: {slivers}");
    }
    let m = cvtmesh::metrics::measures(&mesh, &region)?;
    let sampled = match a.sampled {
        Some(n) if n > MAX_SAMPLES => bail!("--sampled {n} is more than {MAX_SAMPLES} samples"),
        Some(n) => Some(cvtmesh::metrics::sampled_measures(
            &mesh,
            &region,
            &cvtmesh::metrics::SampleParams {
                samples: n,
                seed: 1,
                scale: a.scale,
            },
        )?),
        None => None,
    };
    if let Some(s) = sampled.filter(|s| s.nu.is_infinite() || s.mu.is_infinite()) {
        eprintln!(
            "note: some cells got none of the {} samples, so their sampled area and reach are 0 \
             and ν, μ inf (as in the paper's QUALITY library); take --sampled well above K = {}",
            a.sampled.unwrap_or(0),
            s.k
        );
    }
    // Loops and pieces numbered as `mesh` numbers them: on the region with its corners.
    let named = if a.size_toward.is_empty() {
        region.clone()
    } else {
        inputs::with_corners(region.clone(), a.corner_angle)?.0
    };
    let field = inputs::graded_field(
        a.size_field.as_deref(),
        &a.size_toward,
        a.size_threshold.as_deref(),
        &named,
    )?;
    let field = field
        .map(|f| {
            let b = &a.bounds;
            f.bounded(&region, b.size_min, b.size_max, Some(b.gradation))
        })
        .transpose()?;
    let conformity = match &field {
        Some(field) => {
            field.check(&region).map_err(cvtmesh::MeshError::from)?;
            // Sizes are read where the edges are: off the grid of a sampled field, from an
            // expression itself.
            if field.is_sampled() {
                if let Some(u) = field.unresolved(&region) {
                    eprintln!(
                        "warning: {u}: edges near that point are measured against the smoothed \
                         sizes"
                    );
                }
            }
            Some(cvtmesh::metrics::size_conformity(&mesh, field, &region)?)
        }
        None => None,
    };
    if a.csv {
        outln!("{}", cvtmesh::metrics::Measures::csv_header());
        outln!("{}", m.csv_row());
        if let Some(s) = sampled {
            outln!("{}", s.csv_row());
        }
        if let Some(c) = conformity {
            outln!("{}", cvtmesh::metrics::SizeConformity::NAMES.join(","));
            let v: Vec<String> = c.values().iter().map(|v| v.to_string()).collect();
            outln!("{}", v.join(","));
        }
        return Ok(());
    }
    outln!("mesh {}  region {}", a.mesh.display(), region.name());
    let names = cvtmesh::metrics::Measures::NAMES;
    let values = m.values();
    let svalues = sampled.map(|s| s.values());
    // K and K̃ are counts: whole numbers, not in the measures' scientific form.
    let shown = |name: &str, v: f64| match name {
        "K" | "Ktilde" => format!("{v:>14}"),
        _ => format!("{v:>14.6e}"),
    };
    for (i, name) in names.iter().enumerate() {
        match svalues {
            Some(s) => outln!(
                "{name:>8}  {}  sampled {}",
                shown(name, values[i]),
                shown(name, s[i])
            ),
            None => outln!("{name:>8}  {}", shown(name, values[i])),
        }
    }
    // What Triangle's and Gmsh's users read first; β is it in another form.
    outln!("smallest angle {:.2}°", mesh.min_angle_deg());
    if let Some(c) = conformity {
        let toward = a.size_toward.join(" ");
        let threshold = a.size_threshold.as_deref().unwrap_or_default();
        match (&a.size_field, toward.is_empty()) {
            (Some(text), true) => outln!("size field '{text}':"),
            (None, _) => outln!("size field toward {toward} ({threshold}):"),
            (Some(text), false) => {
                outln!("size field min('{text}', toward {toward} ({threshold})):")
            }
        }
        for (name, v) in cvtmesh::metrics::SizeConformity::NAMES
            .iter()
            .zip(c.values())
        {
            match *name {
                "edges" | "vertices" => outln!("{name:>18}  {v:>14}"),
                _ => outln!("{name:>18}  {v:>14.6}"),
            }
        }
    }
    Ok(())
}

/// `cvtmesh show`.
#[derive(Args)]
pub struct ShowArgs {
    /// A mesh (.node/.ele, .msh, .vtu, .obj) or a region (file or built-in name).
    input: String,
    /// The region of a mesh, whose boundary is drawn over it [default: none: the mesh's own
    /// boundary, the edges of exactly one triangle, is drawn, as Triangle's showme does].
    #[arg(long, short)]
    region: Option<String>,
    /// Colour triangles by: min-angle, q (circle ratio R/2r), area [default: none, uniform tint].
    #[arg(long)]
    colour: Option<String>,
    /// Pixels spanned by the longer side of the drawing's bounding box (the picture adds a
    /// margin and a title around it).
    #[arg(long, default_value_t = inputs::PICTURE_PX, value_parser = clap::value_parser!(u32).range(100..=20_000))]
    px: u32,
    /// Output picture (.png or .svg).
    #[arg(long, short)]
    output: PathBuf,
}

/// `cvtmesh show`: a picture of a region or mesh.
pub fn show(a: ShowArgs) -> Result<()> {
    if !matches!(inputs::output_kind(&a.output), Ok("png" | "svg")) {
        bail!(
            "cannot write '{}': show writes .png or .svg",
            a.output.display()
        );
    }
    inputs::check_directory(&a.output)?;
    let input = PathBuf::from(&a.input);
    let is_mesh = input.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        cvtmesh::io::READ_EXTENSIONS
            .iter()
            .any(|m| m.eq_ignore_ascii_case(e))
    });
    if !is_mesh {
        if a.colour.is_some() {
            bail!("--colour needs a mesh, but '{}' is a region", a.input);
        }
        let region = inputs::region(&a.input, None)?;
        return inputs::draw(None, &region, &a.output, region.name(), None, a.px);
    }
    let region = a
        .region
        .as_deref()
        .map(|spec| inputs::region(spec, None))
        .transpose()?;
    let mesh = inputs::mesh(&input)?;
    let colour = match a.colour.as_deref() {
        None => None,
        Some(c) => Some((triangle_values(&mesh, c)?, c.to_string())),
    };
    let name = match &region {
        Some(r) => r.name().to_string(),
        None => input
            .file_name()
            .map_or_else(|| a.input.clone(), |f| f.to_string_lossy().into_owned()),
    };
    let title = format!(
        "{name} K={} K~={}",
        mesh.num_vertices(),
        mesh.num_triangles()
    );
    match &region {
        Some(r) => inputs::draw(Some(&mesh), r, &a.output, &title, colour, a.px),
        None => inputs::draw_mesh(&mesh, &a.output, &title, colour, a.px),
    }
}

fn triangle_values(mesh: &cvtmesh::Mesh, what: &str) -> Result<Vec<f64>> {
    // (min angle in degrees, area, q = R/(2r)), shared with the .vtu writer.
    let pick: fn((f64, f64, f64)) -> f64 = match what {
        "min-angle" => |t| t.0,
        "area" => |t| t.1,
        "q" => |t| t.2,
        other => bail!("unknown --colour '{other}'; choose min-angle, q or area"),
    };
    Ok((0..mesh.num_triangles())
        .map(|t| pick(cvtmesh::io::triangle_quality(mesh.triangle(t))))
        .collect())
}

/// `cvtmesh dual`.
#[derive(Args)]
pub struct DualArgs {
    /// Mesh: Triangle FILE.node (with FILE.ele beside it), Gmsh FILE.msh, VTK FILE.vtu or Wavefront FILE.obj.
    mesh: PathBuf,
    /// Print each vertex's control volume (`vertex,x,y,volume`) instead of each edge's face
    /// (`a,b,length,face,boundary`).
    #[arg(long)]
    volumes: bool,
}

/// `cvtmesh dual`: the Voronoi dual restricted to the mesh as CSV on standard output, vertices
/// numbered from 0 in the file's order.
pub fn dual(a: DualArgs) -> Result<()> {
    let mesh = cvtmesh::io::read_mesh_file(&a.mesh)?.mesh;
    let d = cvtmesh::Dual::new(&mesh).map_err(|e| anyhow!("{}: {e}", a.mesh.display()))?;
    if a.volumes {
        outln!("vertex,x,y,volume");
        for (v, (p, vol)) in mesh.points.iter().zip(&d.volumes).enumerate() {
            outln!("{v},{:?},{:?},{vol:?}", p.x, p.y);
        }
    } else {
        outln!("a,b,length,face,boundary");
        for (e, [u, w]) in d.edges.iter().enumerate() {
            outln!(
                "{u},{w},{:?},{:?},{}",
                d.lengths[e],
                d.faces[e],
                u8::from(d.on_boundary[e])
            );
        }
    }
    let (inner, outer) = d.negative_faces(1e-12);
    let counted = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    let negative: Vec<String> = [
        (inner, counted(inner, "interior edge"), "not Delaunay"),
        (
            outer,
            counted(outer, "boundary edge"),
            "opposite an obtuse angle",
        ),
    ]
    .into_iter()
    .filter(|x| x.0 > 0)
    .map(|(_, n, why)| format!("{n} {why}"))
    .collect();
    if !negative.is_empty() {
        eprintln!(
            "note: negative faces, where a two-point flux is not monotone: {}",
            negative.join(", ")
        );
    }
    Ok(())
}

/// `cvtmesh regions`.
#[derive(Args)]
pub struct RegionsArgs {
    /// A region (file or built-in name): list its loops and boundary pieces, numbered as
    /// `--size-toward loop:I` and `piece:J` name them [default: list the built-in regions].
    region: Option<String>,
    /// As for `mesh`: keep only corners turning more than this (degrees); pieces between
    /// corners are merged, so the numbering follows it [default: as `mesh` does].
    #[arg(long, requires = "region", allow_negative_numbers = true)]
    corner_angle: Option<f64>,
}

/// `cvtmesh regions`: the built-in regions, or one region's loops and pieces.
pub fn regions(a: RegionsArgs) -> Result<()> {
    let Some(name) = a.region else {
        return builtin_regions();
    };
    let raw = inputs::region(&name, None)?;
    let (region, _) = inputs::with_corners(raw, a.corner_angle)?;
    let counted = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    outln!(
        "region {}: area {:.6}, {}, {}, {}",
        region.name(),
        region.area(),
        counted(region.loops().len(), "loop"),
        counted(region.pieces().len(), "piece"),
        counted(region.corners().len(), "corner")
    );
    for (i, l) in region.loops().iter().enumerate() {
        let role = if l.role == cvtmesh::geometry::LoopRole::Outer {
            "outer"
        } else {
            "hole"
        };
        outln!("loop {i} ({role}), length {:.6}:", l.length);
        for &j in &l.pieces {
            let p = &region.pieces()[j];
            let kind = p.kind();
            let (s, e) = (p.start(), p.end());
            let marker =
                region
                    .piece_markers()
                    .map_or(String::new(), |m| match region.marker_name(m[j]) {
                        Some(name) => format!(", marker {} ({name})", m[j]),
                        None => format!(", marker {}", m[j]),
                    });
            outln!(
                "  piece {j:<4} {kind:<13} from ({}, {}) to ({}, {}), length {:.6}{marker}",
                s.x,
                s.y,
                e.x,
                e.y,
                p.length()
            );
        }
    }
    for &(p, m) in region.vertex_markers() {
        let name = region
            .marker_name(m)
            .map_or(String::new(), |n| format!(" ({n})"));
        outln!(
            "vertex ({}, {}): marker {m}{name}, a corner of its own",
            p.x,
            p.y
        );
    }
    for &(p, m) in region.embedded_points() {
        let marker = match (m, region.marker_name(m)) {
            (0, _) => String::new(),
            (m, Some(n)) => format!(", marker {m} ({n})"),
            (m, None) => format!(", marker {m}"),
        };
        outln!(
            "point ({}, {}) inside{marker}, a vertex of every mesh",
            p.x,
            p.y
        );
    }
    for (i, line) in region.embedded_lines().iter().enumerate() {
        let marker = match (line.marker, region.marker_name(line.marker)) {
            (0, _) => String::new(),
            (m, Some(n)) => format!(", marker {m} ({n})"),
            (m, None) => format!(", marker {m}"),
        };
        let (a, b) = (line.points[0], line.points[line.points.len() - 1]);
        let shape = if line.is_closed() {
            format!("closed through ({}, {})", a.x, a.y)
        } else {
            format!("from ({}, {}) to ({}, {})", a.x, a.y, b.x, b.y)
        };
        outln!(
            "line {i} {shape}, {} vertices, length {:.6}{marker}: edges of every mesh",
            line.points.len(),
            line.length()
        );
    }
    for &(p, id) in region.subdomain_points() {
        let name = region
            .subdomain_name(id)
            .map_or(String::new(), |n| format!(" ({n})"));
        outln!(
            "subdomain {id}{name} holds ({}, {}): the number of its triangles in the files",
            p.x,
            p.y
        );
    }
    Ok(())
}

fn builtin_regions() -> Result<()> {
    outln!(
        "{:<16} {:>14} {:>6} {:>8}  title",
        "name",
        "area",
        "holes",
        "corners"
    );
    for name in Region::builtin_names() {
        let r = Region::builtin(name)?;
        outln!(
            "{:<16} {:>14.6} {:>6} {:>8}  {}",
            name,
            r.area(),
            r.loops().len() - 1,
            r.corners().len(),
            Region::builtin_title(name).unwrap_or_default()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Mesh {
        #[command(flatten)]
        args: MeshArgs,
    }

    #[test]
    fn mesh_defaults_are_the_librarys() {
        let a = Mesh::try_parse_from(["mesh", "circle", "-n", "50", "-o", "c.msh"])
            .unwrap()
            .args;
        let d = MeshRequest::points(50);
        assert_eq!((a.seed, a.tol, a.max_iter), (d.seed, d.tol, d.max_iter));
        assert_eq!(a.polish, d.polish_below_deg);
        assert_eq!(a.tol, DEFAULT_TOL);
        assert_eq!(a.method.parse::<Method>(), Ok(Method::default()));
        assert!(a.density.is_none() && a.corner_angle.is_none());
    }
}
