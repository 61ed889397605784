//! Triangular meshes of planar regions by **constrained centroidal Voronoi tessellation**
//! (CCVT), the mesh generators it is compared against, and the 12 quality measures of
//! Nguyen, Burkardt, Gunzburger, Ju & Saka, *Constrained CVT meshes and a comparison of
//! triangular mesh generators* (Computational Geometry 42, 2009).
//!
//! This is the crate a Rust user depends on. It re-exports the types of the workspace's
//! crates and offers one call, [`mesh`](fn@mesh), for the common case:
//!
//! ```
//! use cvtmesh::Region;
//!
//! // The paper's lake with an island, meshed with 500 vertices by the default method.
//! let region = Region::builtin("lake")?;
//! let result = cvtmesh::mesh(&region, 500)?;
//! assert_eq!(result.mesh.num_vertices(), 500);
//! assert!(result.converged);
//! // The triangles tile the region: their areas add up to its area (up to the chords
//! // that replace curved boundary pieces).
//! assert!((result.mesh.area() - region.area()).abs() < 1e-2 * region.area());
//! # Ok::<(), cvtmesh::MeshError>(())
//! ```
//!
//! Everything else goes through a [`Method`] and a [`MeshRequest`]:
//!
//! ```
//! use cvtmesh::{Method, MeshRequest, Region};
//!
//! let region = Region::builtin("square_hole")?;
//! let request = MeshRequest::points(300).seed(7).tol(1e-3);
//! let result = "distmesh".parse::<Method>()?.run(&region, &request)?;
//! let measures = cvtmesh::measures(&result.mesh, &region)?;
//! assert!(measures.beta < 1.0); // the smallest angle is more than 30°
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! | module | what |
//! |---|---|
//! | [`geometry`] | regions, boundary pieces, corners, projection, signed distance, region files |
//! | [`tessellation`] | Delaunay triangulation and Voronoi cells clipped to a region |
//! | [`metrics`] | the 12 quality measures of Section 3 |
//! | [`io`] | mesh files: Triangle, Gmsh, VTK, OBJ |
//! | [`ccvt`], [`refine`], [`distmesh`], [`meshgen`], [`vtm`] | the methods |
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod method;

pub use method::{Method, UnknownMethod};

pub use ccvt;
pub use distmesh;
pub use geometry;
pub use meshgen;
pub use metrics;
pub use refine;
pub use tessellation;
pub use vtm;

pub use ::mesh::io;

pub use ::mesh::{
    boundary_points_needed, check_conforming, chord_allowance, has_subdomains, line_edges,
    looks_graded, measurable, memory_estimate, min_angle_and_slivers, polish, polish_restored,
    polish_restored_holding, polish_within, refuse_embedded, short_coverage, sliver_advice,
    slivers, slivers_in_region, split_at_spacing, subdomain_points_of, subdomains, thin_feature,
    total_memory, triangle_min_angle_deg, BoundaryEdge, ConformityError, Dual, Mesh, MeshError,
    MeshRequest, MeshResult, Mesher, PolishReport, Polished, Progress, Quadratic, ShortCoverage,
    Size, Slivers, ThinFeature, VertexMarker, BYTES_PER_VERTEX, CHORD_ALLOWANCE,
    CONFORMITY_CHECK_LIMIT, EDGE_ALLOWANCE, GRADATION_NOTE, GRADED_SPREAD, MAX_POINTS,
    MIN_COVERAGE, POLISH_BELOW_DEG, SIMPLIFY_SPACINGS, SLIVER_ANGLE_DEG,
};
pub use ccvt::Ccvt;
pub use distmesh::DistMesh;
pub use geometry::{
    DVec2, Density, EmbeddedLine, GeometryError, Region, Simplified, SizeField, SizeFieldError,
};
pub use meshgen::Meshgen;
pub use metrics::{measures, sampled_measures, Measures, MetricsError};
pub use refine::Refine;
pub use vtm::{Vtm, VtmBoundary};

/// Mesh `region` with `n` vertices by the default method ([`Method::Ccvt`]: Algorithm 2 with
/// Newton's method) and the default request ([`MeshRequest::points`]: seed 1, tolerance 1e-4
/// of the mean spacing). This is what `cvtmesh mesh REGION --points N` runs, except that for a
/// region read from a polygon file, whose every turning vertex is a corner, the command first
/// keeps those turning by more than 30° ([`Region::with_default_corners`]): do so too before
/// meshing a digitized boundary here, or a coastline's thousand corners ask for more points
/// than it needs.
///
/// ```
/// let region = cvtmesh::Region::builtin("circle")?;
/// let result = cvtmesh::mesh(&region, 88)?;
/// assert_eq!(result.mesh.num_vertices(), 88);
/// cvtmesh::check_conforming(&result.mesh, &region)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn mesh(region: &Region, n: usize) -> Result<MeshResult, MeshError> {
    Method::default().run(region, &MeshRequest::points(n))
}

/// The region the triangles of `mesh`, read from `path`, cover ([`Region::from_triangles`]),
/// named after the file, with the walls the file numbers (`walls`, from
/// [`io::read_mesh_with_walls`]: Gmsh physical curves, a Triangle `.poly`'s segment markers),
/// so that a mesh of it carries the same boundary conditions
/// ([`Region::from_triangles_marked`], [`Region::with_marker_names`]), and the lines it keeps
/// inside the mesh ([`io::Walls::inner`], with [`io::Walls::inner_markers`]) as embedded lines
/// ([`Region::embedded_lines`]), so that a new or polished mesh keeps them; its errors name
/// the file.
///
/// ```
/// use cvtmesh::{io::{markers_from_topology, Walls}, DVec2, Mesh};
/// let points = vec![DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
/// let triangles = vec![[0, 1, 2], [0, 2, 3]];
/// let mesh = Mesh { markers: markers_from_topology(&points, &triangles), points, triangles };
/// let path = std::path::Path::new("runs/square.msh");
/// let r = cvtmesh::region_of_mesh(&mesh, &Walls::default(), path)?;
/// assert_eq!((r.name(), r.area()), ("square", 1.0));
/// // Its bottom edge numbered 3, named "heated", and its corner (1, 1) a point marked 8.
/// let walls = Walls {
///     edges: vec![([0, 1], 3)],
///     points: vec![(2, 8)],
///     names: [(3, "heated".to_string())].into(),
///     ..Default::default()
/// };
/// let r = cvtmesh::region_of_mesh(&mesh, &walls, path)?.with_default_corners();
/// assert_eq!(r.piece_markers().map(|m| m.contains(&3)), Some(true));
/// assert_eq!(r.marker_name(3), Some("heated"));
/// assert_eq!(r.vertex_markers(), &[(DVec2::ONE, 8)]);
/// // Its diagonal kept inside as an interface, marked 5: a line of the region.
/// let walls = Walls { inner: vec![[0, 2]], inner_markers: vec![5], ..Default::default() };
/// let r = cvtmesh::region_of_mesh(&mesh, &walls, path)?;
/// assert_eq!(r.embedded_lines()[0].marker, 5);
/// # Ok::<(), cvtmesh::GeometryError>(())
/// ```
pub fn region_of_mesh(
    mesh: &Mesh,
    walls: &io::Walls,
    path: &std::path::Path,
) -> Result<Region, GeometryError> {
    let name = path
        .file_stem()
        .map_or_else(|| "mesh".into(), |s| s.to_string_lossy());
    let region = Region::from_triangles_pinned(
        &name,
        &mesh.points,
        &mesh.triangles,
        &walls.edges,
        &walls.points,
    );
    region
        .map(|r| {
            let r = r
                .with_marker_names(walls.names.clone())
                .with_notes(walls.notes.iter().cloned());
            let r = match &walls.surface_group {
                Some((tag, name)) => r.with_surface_group(*tag, name),
                None => r,
            };
            with_subdomains(with_inner_lines(r, mesh, walls), mesh, walls)
        })
        .map_err(|e| match e {
            GeometryError::Invalid { message, .. } => GeometryError::Invalid {
                region: path.display().to_string(),
                message: format!("the region its triangles cover: {message}"),
            },
            e => e,
        })
}

/// `region` (the one `mesh`'s triangles cover) with the lines the file keeps inside the mesh
/// ([`io::Walls::inner`]: an interface between materials, a curve in the domain) as embedded
/// lines, straight runs of the mesh's edges joined, so that a new mesh, a polished one and
/// their files keep them; where they make no valid lines, the region without them and a note.
fn with_inner_lines(region: Region, mesh: &Mesh, walls: &io::Walls) -> Region {
    if walls.inner.is_empty() {
        return region;
    }
    let segments: Vec<(usize, usize, i64)> = walls
        .inner
        .iter()
        .enumerate()
        .map(|(k, &[a, b])| {
            let m = walls.inner_markers.get(k).copied().unwrap_or(0);
            (a as usize, b as usize, m)
        })
        .collect();
    let lines =
        geometry::EmbeddedLine::join(&mesh.points, &segments, |v| mesh.markers[v].on_boundary());
    let lines: Vec<_> = lines.iter().map(|l| l.straightened(1e-9)).collect();
    match region.clone().with_embedded_lines(lines) {
        Ok(r) => r,
        Err(e) => region.with_notes([format!(
            "the {} edges the mesh keeps inside it are not lines of the region ({e}): a new \
             mesh does not follow them",
            walls.inner.len()
        )]),
    }
}

/// `region` (the one `mesh`'s triangles cover) with a subdomain point in each part whose
/// triangles the file numbers alike ([`io::Walls::subdomains`]), so that a new mesh and a
/// polished one number their triangles as the file did; where the points are refused, the
/// region without them and a note.
fn with_subdomains(region: Region, mesh: &Mesh, walls: &io::Walls) -> Region {
    let points = subdomain_points_of(mesh, &walls.subdomains);
    if points.is_empty() {
        return region;
    }
    match region.clone().with_subdomain_points(points) {
        Ok(r) => r.with_subdomain_names(walls.subdomain_names.clone()),
        Err(e) => region.with_notes([format!(
            "the file's numbers of its triangles' parts are not kept ({e}): a new mesh numbers \
             its subdomains anew"
        )]),
    }
}

/// A region by what a user types: the path of a region file in any format
/// [`Region::from_file`] reads; the path of a mesh ([`io::read_mesh`]: Triangle `.node`/`.ele`,
/// Gmsh `.msh`, `.obj`), whose region is what its triangles cover
/// ([`Region::from_triangles`]), so a mesh can be meshed again, polished or measured with no
/// region file; the lines the file keeps inside the mesh ([`io::Walls::inner`]: a material
/// interface) are the region's embedded lines ([`Region::embedded_lines`]), so that a new
/// mesh follows them too; or, when the text looks like no path (no `.` or `/`), the name of a built-in
/// region, even where a file of that name lies in the working directory (a file without an
/// extension is in no format; `./lake` names the file). As read: a polygon file's every
/// turning vertex is a corner ([`Region::with_default_corners`] keeps the command line's).
///
/// ```
/// let lake = cvtmesh::load_region("lake")?;
/// assert_eq!(lake.name(), "lake");
/// let e = cvtmesh::load_region("no_such_dir/region.poly").unwrap_err();
/// assert!(e.to_string().contains("no_such_dir/region.poly"), "{e}");
///
/// // A mesh file names the region its triangles cover.
/// let dir = std::env::temp_dir().join(format!("cvtmesh-doc-load-region-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let mesh = cvtmesh::mesh(&cvtmesh::Region::builtin("square_hole")?, 400)?.mesh;
/// cvtmesh::io::write_mesh(&mesh, &dir.join("old.msh"))?;
/// let again = cvtmesh::load_region(dir.join("old.msh").to_str().unwrap())?;
/// assert_eq!((again.name(), again.loops().len()), ("old", 2));
/// assert!((again.area() - mesh.area()).abs() < 1e-12 * mesh.area());
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn load_region(spec: &str) -> Result<Region, GeometryError> {
    let path = std::path::Path::new(spec);
    if io::names_mesh(path) {
        let (mesh, walls) = io::read_mesh_with_walls(path).map_err(|e| GeometryError::Parse {
            path: spec.to_string(),
            message: e.to_string(),
        })?;
        return region_of_mesh(&mesh, &walls, path);
    }
    let plain = !spec.contains('.') && !spec.contains('/');
    if plain && Region::builtin_names().contains(&spec) {
        return Region::builtin(spec);
    }
    if path.exists() || !plain {
        Region::from_file(path).map_err(|e| match e {
            // Here a mesh file is a region too: say so beside the region formats.
            GeometryError::UnknownFormat { ref path, .. } => GeometryError::Parse {
                path: path.clone(),
                message: format!(
                    "{}, or a mesh ({}) for the region its triangles cover",
                    e.to_string()
                        .strip_prefix(&format!("region file {path}: "))
                        .unwrap_or_default(),
                    io::READ_EXTENSIONS
                        .iter()
                        .map(|x| format!(".{x}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            },
            e => e,
        })
    } else {
        Region::builtin(spec)
    }
}
