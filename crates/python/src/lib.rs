//! The compiled half of the `cvtmesh` Python package: regions, meshing and measures over the
//! Rust crates, with numpy arrays in and out. `python/cvtmesh/__init__.py` is the public
//! layer (keyword-only options, region coercion, meshio interop); this module does the work.
//!
//! Arrays cross the boundary whole: inputs are read from numpy buffers into owned vectors
//! before the interpreter is released, outputs are moved into numpy without a copy, and a
//! user's size or density function is called on whole background grids.
#![forbid(unsafe_code)]

use cvtmesh::geometry::{LoopRole, SizeField, SizeFieldError, Threshold, Toward};
use cvtmesh::{DVec2, Density, Mesh, MeshRequest, Method, Progress, Region};
use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

mod pickle;

/// This process's own thread pool, which every call's parallel work runs on: rayon's global
/// pool would not survive `os.fork` (the default start method of `multiprocessing` on Linux),
/// whose child has the parent's pool but none of its threads, so a call there would wait for
/// them forever. A child forked from a process that had one builds its own.
fn pool() -> Arc<rayon::ThreadPool> {
    static POOL: std::sync::Mutex<Option<(u32, Arc<rayon::ThreadPool>)>> =
        std::sync::Mutex::new(None);
    let pid = std::process::id();
    let mut slot = POOL.lock().unwrap_or_else(|e| e.into_inner());
    match &*slot {
        Some((owner, pool)) if *owner == pid => pool.clone(),
        _ => {
            // A parent's pool is forgotten, not dropped: none of its threads are in this
            // process, and dropping it would signal them.
            if let Some(parent) = slot.take() {
                std::mem::forget(parent);
            }
            let pool = Arc::new(
                rayon::ThreadPoolBuilder::new()
                    .thread_name(|i| format!("cvtmesh-{i}"))
                    .build()
                    .expect("threads for the pool"),
            );
            *slot = Some((pid, pool.clone()));
            pool
        }
    }
}

/// [`Python::detach`] with the work on [`pool`]: the interpreter released while it runs, as
/// it must be even for work that needs no Python, since the pool's threads may be busy with
/// another thread's mesh whose progress reports need the interpreter.
trait Detached {
    fn detached<T: Send>(self, f: impl FnOnce() -> T + Send) -> T;
}

impl Detached for Python<'_> {
    fn detached<T: Send>(self, f: impl FnOnce() -> T + Send) -> T {
        self.detach(|| pool().install(f))
    }
}

create_exception!(
    _cvtmesh,
    MeshError,
    PyValueError,
    "A region, request or file that cvtmesh cannot use; the message names the problem."
);

/// Nodes per side of the background grid on which a density function is sampled.
const DENSITY_GRID: usize = 256;

fn err(e: impl std::fmt::Display) -> PyErr {
    MeshError::new_err(e.to_string())
}

/// `a` as an int64 array, refused (naming `what`) where a value is not a whole number: numpy
/// would truncate 2.5 to vertex 2 without a word (an index array read with `loadtxt` is
/// floats, and whole floats are taken).
fn whole_numbers<'py>(a: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyAny>> {
    let np = a.py().import("numpy")?;
    let a = np.call_method1("asarray", (a,))?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    if kind == "f" || kind == "c" {
        let whole: bool = np
            .call_method1("array_equal", (&a, np.call_method1("trunc", (&a,))?))?
            .extract()?;
        if !whole {
            return Err(err(format!(
                "{what} must hold whole numbers (vertex indices, markers), got a value with a fraction, NaN or infinity"
            )));
        }
    }
    np.call_method1("asarray", (a, "int64"))
}

/// Refuses to measure `mesh` against a region it is no mesh of (covering an area more than
/// half off the region's: its α would be below 0, its ν inf), and warns where it only nearly
/// conforms (a file's rounded coordinates, a polygon inscribed in a curve), as `cvtmesh
/// measure` does. Its boundary vertices are placed on the region first: a mesh read from a
/// file knows no loops of the region's.
fn fit_to_measure(py: Python<'_>, mesh: &Mesh, region: &Region) -> PyResult<()> {
    let mut placed = mesh.clone();
    let fit = py
        .detached(|| {
            cvtmesh::io::restore_markers(&mut placed, region);
            cvtmesh::measurable(&placed, region)
        })
        .map_err(err)?;
    if let Some(e) = fit {
        let warnings = py.import("warnings")?;
        let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
        let note = format!(
            "the mesh does not conform to region '{}': {e}",
            region.name()
        );
        warnings.call_method1("warn", (note, category))?;
    }
    Ok(())
}

/// What a mesh checked against a region it does not mesh is told.
fn not_conforming(region: &Region, e: cvtmesh::ConformityError) -> String {
    format!(
        "the mesh does not conform to region '{}' ({e})",
        region.name()
    )
}

/// Triangles of an (m, 3) integer array of 0-based vertex numbers below `n`.
fn triangles_of(triangles: &PyReadonlyArray2<'_, i64>, n: usize) -> PyResult<Vec<[u32; 3]>> {
    if triangles.shape()[1] != 3 {
        return Err(err(format!(
            "triangles must be an array of shape (m, 3), got {:?}",
            triangles.shape()
        )));
    }
    let t = triangles.as_array();
    let mut tris = Vec::with_capacity(t.nrows());
    for (j, row) in t.rows().into_iter().enumerate() {
        let mut tri = [0u32; 3];
        for (k, &v) in row.iter().enumerate() {
            if v < 0 || v as usize >= n {
                return Err(err(format!(
                    "triangle {j} refers to vertex {v}, but there are {n} points"
                )));
            }
            tri[k] = v as u32;
        }
        tris.push(tri);
    }
    Ok(tris)
}

/// A mesh of any array-likes of points and 0-based triangles ([`mesh_arrays`]), its vertices'
/// markers read from its triangles.
fn any_mesh(points: &Bound<'_, PyAny>, triangles: &Bound<'_, PyAny>, what: &str) -> PyResult<Mesh> {
    let (points, triangles) = mesh_arrays(points, triangles, what)?;
    Ok(Mesh {
        markers: cvtmesh::io::markers_from_topology(&points, &triangles),
        points,
        triangles,
    })
}

/// The points and triangles of a mesh given as any array-likes (lists, int32 triangles as
/// scipy's Delaunay gives, ...): converted to float64 and int64 by numpy, then checked as
/// [`points_of`] and [`triangles_of`] check them; `what` heads the errors.
fn mesh_arrays(
    points: &Bound<'_, PyAny>,
    triangles: &Bound<'_, PyAny>,
    what: &str,
) -> PyResult<(Vec<DVec2>, Vec<[u32; 3]>)> {
    let np = points.py().import("numpy")?;
    let points = np.call_method1("asarray", (points, "float64"))?;
    let points: PyReadonlyArray2<'_, f64> = points
        .extract()
        .map_err(|_| err(format!("{what}: the mesh's points must be an (n, 2) array")))?;
    let triangles = whole_numbers(triangles, "triangles")?;
    let triangles: PyReadonlyArray2<'_, i64> = triangles.extract().map_err(|_| {
        err(format!(
            "{what}: the mesh's triangles must be an (m, 3) array"
        ))
    })?;
    let pts = points_of(&points, "points")?;
    let tris = triangles_of(&triangles, pts.len())?;
    Ok((pts, tris))
}

/// `walls=(edges, markers)`: boundary edges (e, 2) of vertex indices below `n` and a marker
/// for each (e,), any integer types.
fn walls_of(
    edges: &Bound<'_, PyAny>,
    markers: &Bound<'_, PyAny>,
    n: usize,
) -> PyResult<Vec<([u32; 2], i64)>> {
    let bad = || err("walls must be (edges, markers): an (e, 2) integer array and e integers");
    let edges: PyReadonlyArray2<'_, i64> = whole_numbers(edges, "walls")?
        .extract()
        .map_err(|_| bad())?;
    let markers: PyReadonlyArray1<'_, i64> = whole_numbers(markers, "walls")?
        .call_method0("ravel")?
        .extract()
        .map_err(|_| bad())?;
    let (e, m) = (edges.as_array(), markers.as_array());
    if e.ncols() != 2 || e.nrows() != m.len() {
        return Err(err(format!(
            "walls: {} edges of {} vertices and {} markers; need (e, 2) edges and e markers",
            e.nrows(),
            e.ncols(),
            m.len()
        )));
    }
    e.rows()
        .into_iter()
        .zip(m.iter())
        .map(|(r, &marker)| {
            let v = |k: i64| {
                u32::try_from(k)
                    .ok()
                    .filter(|&k| (k as usize) < n)
                    .ok_or_else(|| err(format!("walls: vertex {k} is not one of the {n} points")))
            };
            Ok(([v(r[0])?, v(r[1])?], marker))
        })
        .collect()
}

/// The `(vertices, markers)` of `Region.from_triangles(pinned=...)`: k vertex indices below
/// `n` and k markers.
fn pinned_of(
    vertices: &Bound<'_, PyAny>,
    markers: &Bound<'_, PyAny>,
    n: usize,
) -> PyResult<Vec<(u32, i64)>> {
    let bad = || err("pinned must be (vertices, markers): k vertex indices and k integers");
    let as_ints = |a: &Bound<'_, PyAny>| -> PyResult<Vec<i64>> {
        let a: PyReadonlyArray1<'_, i64> = whole_numbers(a, "pinned")?
            .call_method0("ravel")?
            .extract()
            .map_err(|_| bad())?;
        Ok(a.as_array().to_vec())
    };
    let (v, m) = (as_ints(vertices)?, as_ints(markers)?);
    if v.len() != m.len() {
        return Err(err(format!(
            "pinned: {} vertices and {} markers; need one marker per vertex",
            v.len(),
            m.len()
        )));
    }
    v.iter()
        .zip(&m)
        .map(|(&k, &marker)| {
            let k = u32::try_from(k)
                .ok()
                .filter(|&k| (k as usize) < n)
                .ok_or_else(|| err(format!("pinned: vertex {k} is not one of the {n} points")))?;
            Ok((k, marker))
        })
        .collect()
}

/// The error for a region that numbers no walls, asked for markers; `hint` ends it.
fn no_walls(region: &Region, hint: &str) -> PyErr {
    err(format!(
        "region {} numbers no walls (a .poly's segment markers or a Gmsh mesh's physical \
         curves do){hint}",
        region.name()
    ))
}

/// Marked points as Python sees them: `[((x, y), marker), ...]`.
fn marked_points(points: &[(DVec2, i64)]) -> Vec<((f64, f64), i64)> {
    points.iter().map(|&(p, m)| ((p.x, p.y), m)).collect()
}

/// The points of `points` (any array of shape (k, 2)), each with its number of `numbers`
/// (k integers; 0 each where None), named `what` in the error for a count that differs.
fn numbered_points(
    points: &Bound<'_, PyAny>,
    numbers: Option<Vec<i64>>,
    what: &str,
) -> PyResult<Vec<(DVec2, i64)>> {
    let np = points.py().import("numpy")?;
    let points: PyReadonlyArray2<'_, f64> = np
        .call_method1("asarray", (points, "float64"))?
        .call_method1("reshape", (-1, 2))?
        .extract()
        .map_err(|_| err("points must be an array of shape (k, 2)"))?;
    let pts = points_of(&points, "points")?;
    let numbers = numbers.unwrap_or_else(|| vec![0; pts.len()]);
    if numbers.len() != pts.len() {
        return Err(err(format!(
            "{} points and {} {what}s; give one {what} per point",
            pts.len(),
            numbers.len()
        )));
    }
    Ok(pts.into_iter().zip(numbers).collect())
}

/// Points of an (n, 2) float array, refusing other shapes and non-finite values.
fn points_of(a: &PyReadonlyArray2<'_, f64>, what: &str) -> PyResult<Vec<DVec2>> {
    let shape = a.shape();
    if shape[1] != 2 {
        return Err(err(format!(
            "{what} must be an array of shape (n, 2), got {shape:?}"
        )));
    }
    let v = a.as_array();
    let pts: Vec<DVec2> = v
        .rows()
        .into_iter()
        .map(|r| DVec2::new(r[0], r[1]))
        .collect();
    if let Some((i, p)) = pts.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(err(format!(
            "{what} has a non-finite point ({}, {}) at row {i}",
            p.x, p.y
        )));
    }
    Ok(pts)
}

/// Points of any array-like numpy converts to an (n, 2) float64 array: lists, integer and
/// float32 arrays as well as float64 ones.
fn xy_of(a: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<DVec2>> {
    let np = a.py().import("numpy")?;
    let arr = np
        .call_method1("asarray", (a, "float64"))
        .map_err(|e| err(format!("{what} must be an (n, 2) array of numbers ({e})")))?;
    let ndim: usize = arr.getattr("ndim")?.extract()?;
    let shape = arr.getattr("shape")?;
    if ndim != 2 || shape.get_item(1)?.extract::<usize>()? != 2 {
        return Err(err(format!(
            "{what} must be an array of shape (n, 2), got {}",
            shape.repr()?
        )));
    }
    let arr: PyReadonlyArray2<'_, f64> = arr.extract()?;
    points_of(&arr, what)
}

/// The hole loops of `holes`, a list of (m, 2) array-likes (or one (h, m, 2) array); `what`
/// prefixes each hole's name in errors. Hole points, as Triangle takes them (one (h, 2) array
/// or a list of (x, y) pairs), are refused by name: here a hole is its boundary loop.
fn hole_loops(holes: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec<DVec2>>> {
    let np = holes.py().import("numpy")?;
    let as_points = |got: String| {
        err(format!(
            "holes must be a list of (m, 2) arrays, one boundary loop per hole, got {got}; a \
             hole is given by its boundary loop, not by a point inside it as Triangle's holes are"
        ))
    };
    let is_array = holes.is_instance(&np.getattr("ndarray")?)?;
    if is_array && holes.getattr("ndim")?.extract::<usize>()? != 3 {
        let shape = holes.getattr("shape")?.repr()?;
        return Err(as_points(format!("one array of shape {shape}")));
    }
    let list: Vec<Bound<'_, PyAny>> = holes
        .extract()
        .map_err(|_| err("holes must be a list of (m, 2) arrays, one boundary loop per hole"))?;
    let points = list
        .iter()
        .map(|h| np.call_method1("ndim", (h,))?.extract::<usize>())
        .collect::<PyResult<Vec<_>>>();
    if !list.is_empty() && points.is_ok_and(|d| d.iter().all(|&d| d == 1)) {
        return Err(as_points(format!("{} points", list.len())));
    }
    list.iter()
        .enumerate()
        .map(|(i, h)| xy_of(h, &format!("{what}hole {i}")))
        .collect()
}

fn xy_array<'py>(py: Python<'py>, pts: &[DVec2]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
    PyArray1::from_vec(py, flat).reshape([pts.len(), 2])
}

fn read_only<T>(a: &Bound<'_, T>) -> PyResult<()> {
    a.as_any().getattr("flags")?.setattr("writeable", false)
}

/// A planar region: one or more disjoint parts, each an outer boundary loop and holes, made of
/// boundary pieces joined at corners.
#[pyclass(name = "Region", module = "cvtmesh", frozen)]
struct PyRegion {
    inner: Arc<Region>,
}

#[pymethods]
impl PyRegion {
    /// Read a region file (JSON, Triangle .poly, GeoJSON, or a plain loop list).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<PyRegion> {
        Ok(PyRegion {
            inner: Arc::new(Region::from_file(&path).map_err(err)?),
        })
    }

    /// One of the paper's ten regions, by name (see `cvtmesh.regions()`).
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<PyRegion> {
        Ok(PyRegion {
            inner: Arc::new(Region::builtin(name).map_err(err)?),
        })
    }

    /// A file path (a str or `os.PathLike`: a region file, or a mesh file: .node/.ele, .msh,
    /// .obj, whose region is what its triangles cover), or a built-in name when no such file
    /// exists.
    /// What the file held that the region does not use (a `.poly`'s regional attributes and
    /// area constraints) is said in a `RuntimeWarning`.
    #[staticmethod]
    fn load(py: Python<'_>, spec: PathBuf) -> PyResult<PyRegion> {
        let text = spec
            .to_str()
            .ok_or_else(|| err(format!("{}: the path is not valid UTF-8", spec.display())))?;
        let region = cvtmesh::load_region(text).map_err(err)?;
        if !region.notes().is_empty() {
            let warnings = py.import("warnings")?;
            let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
            for note in region.notes() {
                warnings.call_method1("warn", (note, &category))?;
            }
        }
        Ok(PyRegion {
            inner: Arc::new(region),
        })
    }

    /// A polygon with polygonal holes: `outer` is (k, 2), each hole (m, 2). Every vertex is a
    /// corner of this region; `cvtmesh.mesh` keeps those turning by more than its
    /// `corner_angle` (30° by default), as `with_corner_angle` does.
    /// Any array-likes of numbers are taken (lists, integer arrays).
    /// `markers=[outer_markers, hole_markers, ...]` numbers the walls for boundary conditions,
    /// as a `.poly`'s segment markers do: one integer per edge of each loop (edge i from point
    /// i to the next), outer loop first. They become `piece_markers`, a vertex where the
    /// marker changes is a corner (so a mesh has a vertex there and no edge lies on two
    /// walls), and the meshes' `.msh` files carry them as physical curves; `names={11:
    /// "inlet"}` names them.
    #[staticmethod]
    #[pyo3(signature = (outer, holes = None, name = "region", markers = None, names = None))]
    fn from_loops(
        outer: &Bound<'_, PyAny>,
        holes: Option<&Bound<'_, PyAny>>,
        name: &str,
        markers: Option<Vec<Bound<'_, PyAny>>>,
        names: Option<std::collections::BTreeMap<i64, String>>,
    ) -> PyResult<PyRegion> {
        let mut loops = vec![(LoopRole::Outer, xy_of(outer, "outer")?)];
        if let Some(holes) = holes {
            loops.extend(
                hole_loops(holes, "")?
                    .into_iter()
                    .map(|h| (LoopRole::Hole, h)),
            );
        }
        let region = match markers {
            None => Region::from_loops(name, loops),
            Some(markers) => {
                if markers.len() != loops.len() {
                    return Err(err(format!(
                        "markers: {} arrays for {} loops; need one per loop, outer loop first",
                        markers.len(),
                        loops.len()
                    )));
                }
                let mut marked = Vec::with_capacity(loops.len());
                for (l, ((role, pts), m)) in loops.into_iter().zip(&markers).enumerate() {
                    let m: PyReadonlyArray1<'_, i64> = whole_numbers(m, "markers")?
                        .call_method0("ravel")?
                        .extract()
                        .map_err(|_| {
                            err(format!(
                                "markers[{l}] must be integers, one per edge of loop {l}"
                            ))
                        })?;
                    marked.push((role, pts, m.as_array().to_vec()));
                }
                Region::from_loops_marked(name, marked)
            }
        }
        .map_err(err)?;
        Ok(PyRegion {
            inner: Arc::new(region.with_marker_names(names.unwrap_or_default())),
        })
    }

    /// The region the triangles of a mesh cover: `points` (n, 2), `triangles` (m, 3) 0-based,
    /// in either orientation. Its loops are the chains of edges of exactly one triangle (holes
    /// where the triangles lie outside them); every vertex where the boundary turns is a
    /// corner. Overlapping triangles, an edge of more than two triangles, or loops that touch
    /// raise `MeshError`. `walls=(edges, markers)` numbers its walls as a solver's mesh does
    /// (meshio's `line` cells and their `gmsh:physical` data): each boundary edge (e, 2) gets
    /// its marker (e,), the region's pieces take them (`piece_markers`), and a vertex where the
    /// marker changes is a corner, so a mesh of the region keeps the boundary conditions.
    /// `pinned=(vertices, markers)` marks boundary vertices on their own (meshio's `vertex`
    /// cells of a Gmsh file's physical points): each whose marker differs from the walls' on
    /// both sides becomes a corner with that marker (`vertex_markers`). `names={11: "inlet"}`
    /// names markers (meshio's `field_data`), as the physical groups of the `.msh` files
    /// written for the region's meshes then are.
    #[staticmethod]
    #[pyo3(signature = (points, triangles, name = "mesh", walls = None, pinned = None, names = None))]
    #[allow(clippy::too_many_arguments)]
    fn from_triangles(
        py: Python<'_>,
        points: Bound<'_, PyAny>,
        triangles: Bound<'_, PyAny>,
        name: &str,
        walls: Option<(Bound<'_, PyAny>, Bound<'_, PyAny>)>,
        pinned: Option<(Bound<'_, PyAny>, Bound<'_, PyAny>)>,
        names: Option<std::collections::BTreeMap<i64, String>>,
    ) -> PyResult<PyRegion> {
        let (pts, tris) = mesh_arrays(&points, &triangles, "from_triangles")?;
        let walls = match walls {
            None => Vec::new(),
            Some((edges, markers)) => walls_of(&edges, &markers, pts.len())?,
        };
        let pinned = match pinned {
            None => Vec::new(),
            Some((vertices, markers)) => pinned_of(&vertices, &markers, pts.len())?,
        };
        let region = py
            .detached(|| Region::from_triangles_pinned(name, &pts, &tris, &walls, &pinned))
            .map_err(err)?
            .with_marker_names(names.unwrap_or_default());
        Ok(PyRegion {
            inner: Arc::new(region),
        })
    }

    /// A region of several disjoint parts, each an outer loop (k, 2) with its holes: `parts`
    /// is a list of `(outer, [hole, ...])`. Loops are numbered part by part, outer loop first.
    #[staticmethod]
    #[pyo3(signature = (parts, name = "region"))]
    fn from_parts(parts: Vec<Bound<'_, PyAny>>, name: &str) -> PyResult<PyRegion> {
        if parts.is_empty() {
            return Err(err("from_parts needs at least one (outer, holes) part"));
        }
        let mut loops = Vec::new();
        for (p, part) in parts.iter().enumerate() {
            let pair: Vec<Bound<'_, PyAny>> = part.extract().unwrap_or_default();
            let [outer, holes] = pair.as_slice() else {
                return Err(err(format!("part {p} must be a pair (outer, [hole, ...])")));
            };
            loops.push((LoopRole::Outer, xy_of(outer, &format!("part {p} outer"))?));
            loops.extend(
                hole_loops(holes, &format!("part {p} "))?
                    .into_iter()
                    .map(|h| (LoopRole::Hole, h)),
            );
        }
        Ok(PyRegion {
            inner: Arc::new(Region::from_loops(name, loops).map_err(err)?),
        })
    }

    /// The same region with only the corners where the boundary turns by more than
    /// `degrees` (digitized outlines have far fewer real corners than vertices).
    fn with_corner_angle(&self, degrees: f64) -> PyResult<PyRegion> {
        if !(0.0..180.0).contains(&degrees) {
            return Err(err(format!(
                "corner_angle must be in [0, 180) degrees, got {degrees}"
            )));
        }
        Ok(PyRegion {
            inner: Arc::new(self.inner.with_corner_angle(degrees)),
        })
    }

    /// The same region with every straight-edged loop and every embedded line simplified
    /// (Douglas–Peucker) so that each dropped vertex lies within `tolerance` of the result (a
    /// line keeps its ends, its junctions with other lines and its points on the boundary);
    /// returns the region and the largest distance between the given boundary or lines and
    /// the simplified ones. The corner angle
    /// applied to this region applies to the result.
    fn simplified(&self, tolerance: f64) -> PyResult<(PyRegion, f64)> {
        let s = self.inner.simplified(tolerance).map_err(err)?;
        Ok((
            PyRegion {
                inner: Arc::new(s.region.with_default_corners()),
            },
            s.deviation,
        ))
    }

    /// The same region with the default corners: where its corners were computed (polygon
    /// files, arrays), only those turning by more than 30°; listed corners are kept.
    fn with_default_corners(&self) -> PyRegion {
        PyRegion {
            inner: Arc::new(self.inner.with_default_corners()),
        }
    }

    /// Number of disjoint parts (outer loops); `cvtmesh.mesh` meshes every one.
    #[getter]
    fn num_parts(&self) -> usize {
        self.inner.num_parts()
    }

    /// Name (file stem or built-in name).
    #[getter]
    fn name(&self) -> String {
        self.inner.name().to_string()
    }

    /// Exact area.
    #[getter]
    fn area(&self) -> f64 {
        self.inner.area()
    }

    /// Corner positions, (c, 2).
    #[getter]
    fn corners<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let c: Vec<DVec2> = self.inner.corners().iter().map(|c| c.pos).collect();
        xy_array(py, &c)
    }

    /// The boundary pieces, numbered as `size_toward=["piece:J"]` names them in
    /// `cvtmesh.mesh(region)` (on this region with its default corners; with
    /// `corner_angle=`, use `with_corner_angle(...).pieces`): a list of dicts with `piece`,
    /// `loop` (0 the outer loop, then the holes), `kind` (`line`, `arc`, `circle`,
    /// `super-ellipse`, `chain`), `start`, `end` and `length`; and `marker` where the region
    /// file numbers its walls (a Triangle `.poly`'s segment markers, a Gmsh mesh's physical
    /// curves, see `piece_markers`), with the wall's `name` where the file names it.
    #[getter]
    fn pieces<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let region = self.inner.with_default_corners();
        let mut out = Vec::new();
        for (i, l) in region.loops().iter().enumerate() {
            for &j in &l.pieces {
                let p = &region.pieces()[j];
                let d = PyDict::new(py);
                d.set_item("piece", j)?;
                d.set_item("loop", i)?;
                d.set_item("kind", p.kind())?;
                d.set_item("start", (p.start().x, p.start().y))?;
                d.set_item("end", (p.end().x, p.end().y))?;
                d.set_item("length", p.length())?;
                if let Some(m) = region.piece_markers() {
                    d.set_item("marker", m[j])?;
                    if let Some(name) = region.marker_name(m[j]) {
                        d.set_item("name", name)?;
                    }
                }
                out.push(d);
            }
        }
        Ok(out)
    }

    /// Each piece's marker, numbered as `pieces`, where the region file numbers its walls (a
    /// Triangle `.poly`'s segment markers: Triangle users' names for boundary conditions);
    /// `None` where it does not. Where the marker changes there is a corner, so no mesh edge
    /// lies on two walls.
    #[getter]
    fn piece_markers(&self) -> Option<Vec<i64>> {
        self.inner
            .with_default_corners()
            .piece_markers()
            .map(<[i64]>::to_vec)
    }

    /// Points inside the region that every mesh of it has as vertices, as
    /// `[((x, y), marker), ...]` (marker 0 for none): a `.poly`'s vertices on no segment, or
    /// those given to `with_embedded_points`.
    #[getter]
    fn embedded_points(&self) -> Vec<((f64, f64), i64)> {
        marked_points(self.inner.embedded_points())
    }

    /// The same region with `points` (k, 2) embedded: every mesh of it has a vertex at each
    /// (a source, a probe), with `markers` (k integers, default 0) in `Mesh.vertex_markers()`
    /// and the files. A point outside the region or on its boundary raises `MeshError`. The
    /// methods ccvt, refine and distmesh keep them; meshgen and vtm refuse such a region.
    #[pyo3(signature = (points, markers = None))]
    fn with_embedded_points(
        &self,
        points: Bound<'_, PyAny>,
        markers: Option<Vec<i64>>,
    ) -> PyResult<PyRegion> {
        let pts = numbered_points(&points, markers, "marker")?;
        let region = (*self.inner).clone();
        Ok(PyRegion {
            inner: Arc::new(region.with_embedded_points(pts).map_err(err)?),
        })
    }

    /// Polylines inside the region that every mesh of it follows with its edges, as
    /// `[(points, marker), ...]` with `points` a (k, 2) array (closed when its last row is its
    /// first): a `.poly`'s segments with the region on both sides, a JSON region's `lines`, or
    /// those given to `with_embedded_lines`.
    #[getter]
    fn embedded_lines<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Vec<(Bound<'py, PyArray2<f64>>, i64)>> {
        self.inner
            .embedded_lines()
            .iter()
            .map(|l| Ok((xy_array(py, &l.points)?, l.marker)))
            .collect()
    }

    /// The same region with `lines` embedded: each a (k, 2) array of a polyline inside the
    /// region (a material interface, a crack; closed when its last point is its first, an
    /// inclusion's outline), with `markers` (one integer per line, default 0). Every mesh of
    /// it has each line's vertices, more vertices along it at the local spacing, and edges
    /// running along it (`Mesh.line_edges()`; in the files, `.poly` segments and Gmsh physical
    /// curves of their markers). A line may end on a polygonal wall, an arc or a circle; lines may meet
    /// at shared vertices, and where two cross both get a vertex there (as Triangle splits
    /// crossing segments), which `embedded_lines` lists (a line crossing itself, twice). A
    /// line leaving the region or running along another raises `MeshError` naming the place,
    /// unless `clip=True`: then each line is cut where it crosses the boundary and only its
    /// parts inside are kept, as Triangle keeps a `.poly` segment's (fractures generated in a
    /// larger box). The methods ccvt, refine and distmesh keep them; meshgen and vtm refuse
    /// such a region.
    #[pyo3(signature = (lines, markers = None, clip = false))]
    fn with_embedded_lines(
        &self,
        lines: Vec<Bound<'_, PyAny>>,
        markers: Option<Vec<i64>>,
        clip: bool,
    ) -> PyResult<PyRegion> {
        let markers = markers.unwrap_or_else(|| vec![0; lines.len()]);
        if markers.len() != lines.len() {
            return Err(err(format!(
                "{} lines and {} markers; give one marker per line",
                lines.len(),
                markers.len()
            )));
        }
        let lines = lines
            .iter()
            .zip(markers)
            .enumerate()
            .map(|(i, (l, marker))| {
                Ok(cvtmesh::EmbeddedLine {
                    points: xy_of(l, &format!("lines[{i}]"))?,
                    marker,
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
        let region = (*self.inner).clone();
        let lines = if clip {
            region.lines_inside(lines)
        } else {
            lines
        };
        Ok(PyRegion {
            inner: Arc::new(region.with_embedded_lines(lines).map_err(err)?),
        })
    }

    /// The points that number the region's subdomains (the parts its embedded lines cut it
    /// into), as `[((x, y), id), ...]`: a `.poly`'s regional attributes, a JSON region's
    /// `subdomains`, or those given to `with_subdomain_points`.
    #[getter]
    fn subdomain_points(&self) -> Vec<((f64, f64), i64)> {
        marked_points(self.inner.subdomain_points())
    }

    /// The same region with `points` (k, 2) numbering its subdomains by `ids` (k integers):
    /// every triangle of a mesh that no embedded line, wall or hole parts from a point gets
    /// its id (`Mesh.subdomains()`; in the files, the `.ele` attribute, a Gmsh physical surface
    /// per id, a VTK cell array), as Triangle's `-A` spreads regional attributes; a part
    /// without a point gets 0, and where two points share a part the later one's id holds. A
    /// point outside the region, on its boundary or on a line raises `MeshError`.
    ///
    /// `names={3: "steel"}` names ids (`subdomain_names`): the `.msh` files' physical
    /// surfaces and `Mesh.to_meshio()`'s groups take the names.
    #[pyo3(signature = (points, ids, names = None))]
    fn with_subdomain_points(
        &self,
        points: Bound<'_, PyAny>,
        ids: Vec<i64>,
        names: Option<BTreeMap<i64, String>>,
    ) -> PyResult<PyRegion> {
        let pts = numbered_points(&points, Some(ids), "id")?;
        let region = (*self.inner).clone();
        Ok(PyRegion {
            inner: Arc::new(
                region
                    .with_subdomain_points(pts)
                    .map_err(err)?
                    .with_subdomain_names(names.unwrap_or_default()),
            ),
        })
    }

    /// The names of subdomain ids, `{id: name}`: a JSON region's subdomain `"name"`s, a Gmsh
    /// file's physical-surface names, or those given to `with_subdomain_points`.
    #[getter]
    fn subdomain_names(&self) -> BTreeMap<i64, String> {
        self.inner.subdomain_names().clone()
    }

    /// The names of wall markers, `{marker: name}`: a Gmsh file's physical-curve names, or
    /// those given as `names` to `from_loops` or `from_triangles`.
    #[getter]
    fn marker_names(&self) -> BTreeMap<i64, String> {
        self.inner.marker_names().clone()
    }

    /// The boundary vertices with a marker of their own, as `[((x, y), marker), ...]`: a
    /// `.poly` vertex whose nonzero marker differs from both its segments' (a point where a
    /// solver pins a value). Each is a corner, so every mesh has a vertex there, and
    /// `Mesh.vertex_markers()` gives it that marker.
    #[getter]
    fn vertex_markers(&self) -> Vec<((f64, f64), i64)> {
        marked_points(self.inner.vertex_markers())
    }

    /// ((xmin, ymin), (xmax, ymax)).
    #[getter]
    fn bbox(&self) -> ((f64, f64), (f64, f64)) {
        let (lo, hi) = self.inner.bbox();
        ((lo.x, lo.y), (hi.x, hi.y))
    }

    /// The boundary as polygons with chord error at most `tol`: a list of (k, 2) arrays, part by
    /// part, each outer loop (counter-clockwise) followed by its holes (clockwise).
    fn polygonize<'py>(
        &self,
        py: Python<'py>,
        tol: f64,
    ) -> PyResult<Vec<Bound<'py, PyArray2<f64>>>> {
        if !(tol.is_finite() && tol > 0.0) {
            return Err(err(format!("tol must be positive and finite, got {tol}")));
        }
        let poly = self.inner.polygonize(tol);
        poly.rings.iter().map(|r| xy_array(py, &r.points)).collect()
    }

    /// True for each of the (n, 2) points (any array-like of numbers) that lies inside the
    /// region.
    fn contains<'py>(
        &self,
        py: Python<'py>,
        xy: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let pts = xy_of(xy, "xy")?;
        let inside: Vec<bool> =
            py.detached(|| pts.iter().map(|&p| self.inner.contains(p)).collect());
        Ok(PyArray1::from_vec(py, inside))
    }

    /// Signed distance to the boundary of each of the (n, 2) points (any array-like of
    /// numbers; negative inside).
    fn signed_distance<'py>(
        &self,
        py: Python<'py>,
        xy: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let pts = xy_of(xy, "xy")?;
        let d: Vec<f64> =
            py.detached(|| pts.iter().map(|&p| self.inner.signed_distance(p)).collect());
        Ok(PyArray1::from_vec(py, d))
    }

    /// Pickling (`multiprocessing`, joblib, dask): the region saved whole, to the bit.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        pickle::reduce_region(py, self)
    }

    fn __repr__(&self) -> String {
        format!(
            "Region('{}', area={}, parts={}, loops={}, corners={})",
            self.inner.name(),
            self.inner.area(),
            self.inner.num_parts(),
            self.inner.loops().len(),
            self.inner.corners().len()
        )
    }
}

/// A triangle mesh and how it was made. Arrays are read-only views of the result.
#[pyclass(name = "Mesh", module = "cvtmesh", frozen)]
struct PyMesh {
    mesh: Mesh,
    region: Option<Arc<Region>>,
    /// Vertices `polished` holds where they are: the ends of the edges the file it was read
    /// from keeps inside it (a material interface).
    held: Vec<u32>,
    /// For a mesh read from a file: the file and the walls it numbers, which make the region
    /// its triangles cover (what `polished` keeps the boundary on, as `cvtmesh polish` does).
    read_from: Option<(PathBuf, cvtmesh::io::Walls)>,
    /// The vertices, (N, 2) float64.
    #[pyo3(get)]
    points: Py<PyArray2<f64>>,
    /// The triangles, (M, 3) int64: 0-based vertex indices, counter-clockwise.
    #[pyo3(get)]
    triangles: Py<PyArray2<i64>>,
    /// The edges of exactly one triangle, (B, 2) int64, each running with the mesh on its
    /// left: grouped by loop, and in order along it (each edge starts where the last ended).
    #[pyo3(get)]
    boundary_edges: Py<PyArray2<i64>>,
    /// The loop of each row of `boundary_edges`, (B,) int64: 0 the outer loop, then its holes,
    /// then the next part's outer loop and holes.
    #[pyo3(get)]
    boundary_loop: Py<PyArray1<i64>>,
    /// Whether the run met its tolerance (False when stopped by `max_iter` or `time_limit`).
    #[pyo3(get)]
    converged: bool,
    /// Iterations the run took (for `refine`, search steps on the area bound).
    #[pyo3(get)]
    iterations: usize,
    /// What the run reports beyond the arrays: the vertex count reached, polishing, ...
    #[pyo3(get)]
    notes: Vec<String>,
    /// The CVT energy after each iteration, (iterations,) float64 (empty for methods that
    /// minimise none). A run of Algorithm 2 (whose notes give an ε) ends on Ω_ε: its energies
    /// are over the cells clipped to Ω_ε, so compare methods by `measures()`, not by them.
    #[pyo3(get)]
    energy_history: Py<PyArray1<f64>>,
}

/// Edges (E, 2) and a marker per edge (E,) as numpy arrays.
type EdgesAndMarkers<'py> = (Bound<'py, PyArray2<i64>>, Bound<'py, PyArray1<i64>>);

/// Points (n, 2) and six-node triangles (m, 6) as numpy arrays.
type QuadraticArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>);

impl PyMesh {
    /// `label(piece)` for each row of `boundary_edges`, as a read-only array.
    fn by_boundary_edge<'py>(
        &self,
        py: Python<'py>,
        region: &Region,
        label: impl Fn(usize) -> i64,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let pieces = py.detached(|| self.mesh.boundary_pieces(region));
        let a = PyArray1::from_vec(py, pieces.into_iter().map(label).collect());
        read_only(&a)?;
        Ok(a)
    }

    /// The six-node mesh, its boundary nodes on `region` if given, else on the region the
    /// mesh was made for, else (a mesh read from a file) at its boundary edges' midpoints.
    fn quadratic_mesh(
        &self,
        py: Python<'_>,
        region: Option<&PyRegion>,
    ) -> PyResult<cvtmesh::Quadratic> {
        let region = match (region, &self.region) {
            (None, None) => None,
            _ => Some(self.conforming_region_or(py, region, "quadratic")?),
        };
        Ok(py.detached(|| cvtmesh::Quadratic::new(&self.mesh, region.as_deref())))
    }

    /// Each triangle's subdomain of `region`, as a read-only array.
    fn subdomains_on<'py>(
        &self,
        py: Python<'py>,
        region: &Region,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let ids = py
            .detached(|| cvtmesh::subdomains(&self.mesh, region))
            .map_err(err)?;
        let ids = PyArray1::from_vec(py, ids);
        read_only(&ids)?;
        Ok(ids)
    }

    /// `region` if given, else the region the mesh was made for; a mesh read from a file
    /// has none, and `call` (the method asking) names what to pass.
    fn region_or(&self, region: Option<&PyRegion>, call: &str) -> PyResult<Arc<Region>> {
        match (region, &self.region) {
            (Some(r), _) => Ok(r.inner.clone()),
            (None, Some(r)) => Ok(r.clone()),
            (None, None) => Err(err(format!(
                "this mesh was read from a file: pass the region, mesh.{call}(region)"
            ))),
        }
    }

    /// [`PyMesh::region_or`], but for a mesh read from a file the region its triangles cover,
    /// with the walls the file numbers, as the command line's `polish` and `measure` take it.
    fn region_or_covered(
        &self,
        py: Python<'_>,
        region: Option<&PyRegion>,
        call: &str,
    ) -> PyResult<Arc<Region>> {
        match (region, &self.region, &self.read_from) {
            (None, None, Some((path, walls))) => py
                .detached(|| cvtmesh::region_of_mesh(&self.mesh, walls, path))
                .map(Arc::new)
                .map_err(|e| {
                    err(format!(
                        "the mesh is no region ({e}): pass one, mesh.{call}(region)"
                    ))
                }),
            _ => self.region_or(region, call),
        }
    }

    /// [`PyMesh::region_or`], a `region` passed in checked against the mesh first: boundary
    /// pieces, markers or six-node boundary nodes read off a region the mesh does not mesh
    /// would be numbers without meaning.
    fn conforming_region_or(
        &self,
        py: Python<'_>,
        region: Option<&PyRegion>,
        call: &str,
    ) -> PyResult<Arc<Region>> {
        Ok(self.conforming_mesh_or(py, region, call)?.0)
    }

    /// [`PyMesh::conforming_region_or`] with the mesh its boundary vertices are read from:
    /// against a `region` passed in, a copy whose markers were projected onto it for the
    /// check (a mesh read from a file knows no pieces); else none, the mesh's own markers
    /// being the region's.
    fn conforming_mesh_or(
        &self,
        py: Python<'_>,
        region: Option<&PyRegion>,
        call: &str,
    ) -> PyResult<(Arc<Region>, Option<Mesh>)> {
        let checked = self.region_or(region, call)?;
        if region.is_none() {
            return Ok((checked, None));
        }
        let mut mesh = self.mesh.clone();
        py.detached(|| {
            cvtmesh::io::restore_markers(&mut mesh, &checked);
            cvtmesh::check_conforming(&mesh, &checked)
        })
        .map_err(|e| err(not_conforming(&checked, e)))?;
        Ok((checked, Some(mesh)))
    }

    fn new(
        py: Python<'_>,
        mesh: Mesh,
        region: Option<Arc<Region>>,
        converged: bool,
        iterations: usize,
        notes: Vec<String>,
        energy_history: Vec<f64>,
    ) -> PyResult<PyMesh> {
        let points = xy_array(py, &mesh.points)?;
        let tri: Vec<i64> = mesh
            .triangles
            .iter()
            .flat_map(|t| t.map(i64::from))
            .collect();
        let triangles = PyArray1::from_vec(py, tri).reshape([mesh.triangles.len(), 3])?;
        let edges = py.detached(|| mesh.boundary_edges());
        let flat: Vec<i64> = edges
            .iter()
            .flat_map(|e| [i64::from(e.a), i64::from(e.b)])
            .collect();
        let boundary_edges = PyArray1::from_vec(py, flat).reshape([edges.len(), 2])?;
        let ids: Vec<i64> = edges.iter().map(|e| e.loop_index as i64).collect();
        let boundary_loop = PyArray1::from_vec(py, ids);
        let energy_history = PyArray1::from_vec(py, energy_history);
        read_only(&points)?;
        read_only(&triangles)?;
        read_only(&boundary_edges)?;
        read_only(&boundary_loop)?;
        read_only(&energy_history)?;
        Ok(PyMesh {
            mesh,
            region,
            held: Vec::new(),
            read_from: None,
            points: points.unbind(),
            triangles: triangles.unbind(),
            boundary_edges: boundary_edges.unbind(),
            boundary_loop: boundary_loop.unbind(),
            converged,
            iterations,
            notes,
            energy_history: energy_history.unbind(),
        })
    }
}

#[pymethods]
impl PyMesh {
    /// Write the mesh; the format follows the extension: .node/.ele (Triangle), .msh (Gmsh
    /// 4.1), .vtu, .obj, or a .png/.svg picture (on the region's exact boundary when the mesh
    /// was made here, else outlined by its own boundary edges). `order=2` writes six-node
    /// triangles (see `quadratic`) to .msh, .vtu or .node.
    #[pyo3(signature = (path, order = 1))]
    fn write(&self, py: Python<'_>, path: PathBuf, order: u8) -> PyResult<()> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if order == 2 {
            let q = self.quadratic_mesh(py, None)?;
            return py
                .detached(|| cvtmesh::io::write_quadratic(&q, &path))
                .map_err(err);
        }
        if order != 1 {
            return Err(err(format!("order must be 1 or 2, got {order}")));
        }
        py.detached(|| match ext.as_deref() {
            Some(kind @ ("png" | "svg")) => {
                let title = path
                    .file_stem()
                    .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
                let panel = match &self.region {
                    Some(r) => render::Panel::new(&title, r).with_mesh(&self.mesh),
                    None => render::Panel::for_mesh(&title, &self.mesh),
                };
                let layout = render::Layout::new(1).panel_px(1200);
                if kind == "png" {
                    render::render_png(&[panel], &layout, &path).map_err(err)
                } else {
                    render::render_svg(&[panel], &layout, &path).map_err(err)
                }
            }
            _ => match &self.region {
                Some(r) => cvtmesh::io::write_mesh_on(&self.mesh, r, &path),
                None => cvtmesh::io::write_mesh(&self.mesh, &path),
            }
            .map_err(|e| match e.to_string() {
                // The mesh formats' list, with the pictures this method writes too.
                s if s.contains("supported: ") => err(format!("{s}, .png, .svg")),
                _ => err(e),
            }),
        })
    }

    /// Six-node (quadratic, P2) triangles: `(points, triangles)` with `points` (N + E, 2), the
    /// mesh's N vertices first and then one node per edge, and `triangles` (M, 6): corners
    /// counter-clockwise, then the nodes of edges (0, 1), (1, 2), (2, 0), the order of Gmsh,
    /// VTK and meshio's "triangle6". Boundary edges' nodes lie on the exact boundary of
    /// `region`, or of the region the mesh was made for (arcs of a circle, not its chords); a
    /// mesh read from a file without `region` keeps them at the edges' midpoints.
    #[pyo3(signature = (region = None))]
    fn quadratic<'py>(
        &self,
        py: Python<'py>,
        region: Option<&PyRegion>,
    ) -> PyResult<QuadraticArrays<'py>> {
        let q = self.quadratic_mesh(py, region)?;
        let points = xy_array(py, &q.points)?;
        let flat: Vec<i64> = q.triangles.iter().flatten().map(|&v| v as i64).collect();
        let triangles = PyArray1::from_vec(py, flat).reshape([q.triangles.len(), 6])?;
        read_only(&points)?;
        read_only(&triangles)?;
        Ok((points, triangles))
    }

    /// The piece (wall) of the region each row of `boundary_edges` lies on, as
    /// `Region.pieces` numbers them: the region the mesh was made for, or `region` (needed for
    /// a mesh read from a file). Boundary conditions per wall select edges by it.
    #[pyo3(signature = (region = None))]
    fn boundary_pieces<'py>(
        &self,
        py: Python<'py>,
        region: Option<&PyRegion>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let region = self.conforming_region_or(py, region, "boundary_pieces")?;
        self.by_boundary_edge(py, &region, |p| p as i64)
    }

    /// The edges along the region's embedded lines (`Region.embedded_lines`), line by line
    /// and in order along each: `(edges, markers)`, an (E, 2) int64 array of vertex indices
    /// and the (E,) markers of their lines: where an interface condition or a flux across a
    /// crack is set. Against the region the mesh was made for, or `region`; for a mesh read
    /// from a file, the lines the file keeps inside it (a `.poly`'s internal segments, an
    /// `.ele`'s materials, Gmsh's physical surfaces). A `MeshError` where the mesh does not
    /// follow a line.
    #[pyo3(signature = (region = None))]
    fn line_edges<'py>(
        &self,
        py: Python<'py>,
        region: Option<&PyRegion>,
    ) -> PyResult<EdgesAndMarkers<'py>> {
        let region = self.region_or_covered(py, region, "line_edges")?;
        let edges = py
            .detached(|| cvtmesh::line_edges(&self.mesh, &region))
            .map_err(err)?;
        let flat: Vec<i64> = edges.iter().flat_map(|(e, _)| e.map(i64::from)).collect();
        let pairs = PyArray1::from_vec(py, flat).reshape([edges.len(), 2])?;
        let markers = PyArray1::from_vec(py, edges.iter().map(|&(_, m)| m).collect());
        read_only(&pairs)?;
        read_only(&markers)?;
        Ok((pairs, markers))
    }

    /// Each triangle's subdomain, an (T,) int64 array: the parts the region's embedded lines
    /// cut it into, numbered by its subdomain points (`Region.subdomain_points`; 0 for a part
    /// without one) or, where it has none, 1, 2, ... from the left. For a mesh read from a
    /// file, the region its triangles cover, numbered as the file numbers them (a `.ele`'s
    /// attribute, Gmsh's physical surfaces). A `MeshError` where the mesh does not follow a
    /// line of the region.
    #[pyo3(signature = (region = None))]
    fn subdomains<'py>(
        &self,
        py: Python<'py>,
        region: Option<&PyRegion>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let region = self.region_or_covered(py, region, "subdomains")?;
        self.subdomains_on(py, &region)
    }

    /// What `to_meshio` groups the triangles and edges by, from one region: `subdomains(region)`
    /// where the region has lines or subdomain points (what the files number), else None;
    /// the region's marker names and subdomain names.
    #[pyo3(signature = (region = None))]
    #[allow(clippy::type_complexity)]
    fn _groups<'py>(
        &self,
        py: Python<'py>,
        region: Option<&PyRegion>,
    ) -> PyResult<(
        Option<Bound<'py, PyArray1<i64>>>,
        BTreeMap<i64, String>,
        BTreeMap<i64, String>,
    )> {
        // A mesh read from a file: the region its triangles cover, made once.
        let covered = self.region_or_covered(py, region, "subdomains")?;
        let names = (
            covered.marker_names().clone(),
            covered.subdomain_names().clone(),
        );
        if !cvtmesh::has_subdomains(&covered) {
            return Ok((None, names.0, names.1));
        }
        let parts = self.subdomains_on(py, &covered)?;
        Ok((Some(parts), names.0, names.1))
    }

    /// The marker of the wall each row of `boundary_edges` lies on, where the region file
    /// numbers its walls (`Region.piece_markers`, a Triangle `.poly`'s segment markers): the
    /// region the mesh was made for, or `region`. A `MeshError` where the region has none.
    #[pyo3(signature = (region = None))]
    fn boundary_markers<'py>(
        &self,
        py: Python<'py>,
        region: Option<&PyRegion>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let region = self.conforming_region_or(py, region, "boundary_markers")?;
        let Some(markers) = region.piece_markers() else {
            return Err(no_walls(
                &region,
                "; boundary_pieces() names the walls by piece",
            ));
        };
        self.by_boundary_edge(py, &region, |p| markers[p])
    }

    /// Each vertex's marker, as a Triangle `.node` (and Triangle's `vertex_markers`) gives
    /// it, where the region numbers its walls: a boundary vertex the marker of the wall
    /// leaving it (counter-clockwise along an outer loop), a vertex of the region's own
    /// (`Region.vertex_markers`) that marker, an interior vertex 0. Against the region the
    /// mesh was made for, or `region`; a `MeshError` where the region numbers no walls.
    #[pyo3(signature = (region = None))]
    fn vertex_markers<'py>(
        &self,
        py: Python<'py>,
        region: Option<&PyRegion>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let (region, restored) = self.conforming_mesh_or(py, region, "vertex_markers")?;
        let mesh = restored.as_ref().unwrap_or(&self.mesh);
        let markers = py.detached(|| cvtmesh::io::vertex_markers(mesh, &region));
        let Some(markers) = markers else {
            return Err(no_walls(&region, ""));
        };
        let a = PyArray1::from_vec(py, markers);
        read_only(&a)?;
        Ok(a)
    }

    /// The Voronoi dual restricted to the mesh, for vertex-centred finite volumes (two-point
    /// flux): a dict of read-only arrays, `volumes` (N,) each vertex's control volume, `edges`
    /// (E, 2) every edge once (lower vertex first, sorted), `lengths` (E,), `faces` (E,) the
    /// dual face between the two ends' cells (from the edge's midpoint to its triangle's
    /// circumcentre on the boundary), `on_boundary` (E,) bool, and `circumcentres` (M, 2).
    /// Flux across edge e ≈ faces[e] / lengths[e] × the difference of its ends' values.
    /// Faces are signed: negative on an edge whose opposite angles sum to more than π (not
    /// Delaunay) or a boundary edge of a triangle obtuse there; the volumes always sum to the
    /// mesh's area.
    fn dual<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = py
            .detached(|| cvtmesh::Dual::new(&self.mesh))
            .map_err(err)?;
        let out = PyDict::new(py);
        let edges: Vec<i64> = d.edges.iter().flatten().map(|&v| v as i64).collect();
        let centres: Vec<f64> = d.circumcentres.iter().flat_map(|c| [c.x, c.y]).collect();
        let ne = d.edges.len();
        let nt = d.circumcentres.len();
        let arrays: [(&str, Bound<'py, PyAny>); 6] = [
            ("volumes", PyArray1::from_vec(py, d.volumes).into_any()),
            (
                "edges",
                PyArray1::from_vec(py, edges).reshape([ne, 2])?.into_any(),
            ),
            ("lengths", PyArray1::from_vec(py, d.lengths).into_any()),
            ("faces", PyArray1::from_vec(py, d.faces).into_any()),
            (
                "on_boundary",
                PyArray1::from_vec(py, d.on_boundary).into_any(),
            ),
            (
                "circumcentres",
                PyArray1::from_vec(py, centres).reshape([nt, 2])?.into_any(),
            ),
        ];
        for (name, a) in arrays {
            a.getattr("flags")?.setattr("writeable", false)?;
            out.set_item(name, a)?;
        }
        Ok(out)
    }

    /// The 12 quality measures of the paper's Section 3 (and K, K̃), against `region` if
    /// given, else the region the mesh was made for, else (a mesh read from a file) the region
    /// its triangles cover, as `cvtmesh measure` takes it: a `MeshError` where the mesh covers
    /// an area more than half off the region's, a `RuntimeWarning` where it only nearly
    /// conforms.
    #[pyo3(signature = (region = None))]
    fn measures<'py>(
        &self,
        py: Python<'py>,
        region: Option<&PyRegion>,
    ) -> PyResult<Bound<'py, PyDict>> {
        if let Some(r) = region {
            fit_to_measure(py, &self.mesh, &r.inner)?;
        }
        let region = self.region_or_covered(py, region, "measures")?;
        let m = py
            .detached(|| cvtmesh::measures(&self.mesh, &region))
            .map_err(err)?;
        measures_dict(py, &m)
    }

    /// A polished copy: the vertices of triangles with an angle below `below` degrees move to
    /// raise the smallest angle around them (boundary vertices along the region's boundary,
    /// corners fixed, the triangles kept, no triangle or cell taken past the mesh's extremes),
    /// against `region`, else the region the mesh was made for, else (a mesh read from a file)
    /// the region its triangles cover, with the walls the file numbers, as `cvtmesh polish`
    /// takes it: every vertex of its boundary is a corner of that region and stays where it is
    /// (pass the region to let them slide along it). The vertices on the lines the file keeps
    /// inside the mesh (an interface) stay on them, sliding along their straight runs. Its
    /// notes say how many moved.
    #[pyo3(signature = (region = None, below = cvtmesh::POLISH_BELOW_DEG),
        text_signature = "(self, region=None, below=40.0)")]
    fn polished(&self, py: Python<'_>, region: Option<&PyRegion>, below: f64) -> PyResult<PyMesh> {
        let region = self.region_or_covered(py, region, "polished")?;
        if !(0.0..=60.0).contains(&below) {
            return Err(err(format!(
                "below must be an angle from 0 to 60 degrees, got {below}"
            )));
        }
        let mut mesh = self.mesh.clone();
        let note = py.detached(|| {
            cvtmesh::polish_restored_holding(&mut mesh, &region, below, &self.held)
                .map(|report| report.to_string())
                .map_err(|e| not_conforming(&region, e))
        });
        let note = note.map_err(err)?;
        let mut notes = self.notes.clone();
        notes.push(note);
        let history = self.energy_history.bind(py).to_vec()?;
        let mut polished = PyMesh::new(
            py,
            mesh,
            Some(region),
            self.converged,
            self.iterations,
            notes,
            history,
        )?;
        polished.held = self.held.clone();
        Ok(polished)
    }

    /// Read a mesh file (.node/.ele, .msh, .vtu, .obj). Higher-order triangles come back as the
    /// three-node mesh of their corners, with a warning.
    #[staticmethod]
    fn read(py: Python<'_>, path: PathBuf) -> PyResult<PyMesh> {
        let file = py
            .detached(|| cvtmesh::io::read_mesh_file(&path))
            .map_err(err)?;
        if file.triangle_nodes > 3 {
            let warnings = py.import("warnings")?;
            let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
            let note = format!(
                "{}: {}-node triangles read as the three-node mesh of their corners \
                 (Mesh.quadratic gives six-node ones again)",
                path.display(),
                file.triangle_nodes
            );
            warnings.call_method1("warn", (note, category))?;
        }
        let held = file.walls.inner_vertices();
        let mut mesh = PyMesh::new(py, file.mesh, None, true, 0, Vec::new(), Vec::new())?;
        mesh.held = held;
        mesh.read_from = Some((path, file.walls));
        Ok(mesh)
    }

    /// Pickling (`multiprocessing`, joblib, dask): the mesh saved whole, its region and the
    /// file it was read from with it, every number to the bit.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (pickle::MeshState<'py>,))> {
        pickle::reduce_mesh(py, self)
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh(points={}, triangles={}, converged={}, iterations={})",
            self.mesh.num_vertices(),
            self.mesh.num_triangles(),
            if self.converged { "True" } else { "False" },
            self.iterations
        )
    }
}

fn measures_dict<'py>(py: Python<'py>, m: &cvtmesh::Measures) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("K", m.k)?;
    d.set_item("Ktilde", m.k_tilde)?;
    // The 12 measures follow K and K̃ in the paper's order.
    for (name, value) in cvtmesh::Measures::NAMES.iter().zip(m.values()).skip(2) {
        d.set_item(*name, value)?;
    }
    Ok(d)
}

/// Gmsh's Distance + Threshold: sizes from `threshold` = (h_min, h_max, d_min, d_max) by the
/// distance to the loops, pieces, lines and points of `toward` (`"loop:I"`, `"line:L"`, `"point:X,Y"`); `None` without
/// targets.
fn distance_field(
    py: Python<'_>,
    region: &Region,
    toward: &[String],
    threshold: Option<(f64, f64, f64, f64)>,
) -> PyResult<Option<SizeField>> {
    if toward.is_empty() {
        return match threshold {
            Some(_) => Err(err(
                "size_threshold needs size_toward (the loops or points)",
            )),
            None => Ok(None),
        };
    }
    let targets = toward
        .iter()
        .map(|t| {
            t.parse::<Toward>()
                .map_err(|e| err(format!("size_toward {e}")))
        })
        .collect::<PyResult<Vec<_>>>()?;
    let (size_min, size_max, dist_min, dist_max) = threshold
        .ok_or_else(|| err("size_toward needs size_threshold=(h_min, h_max, d_min, d_max)"))?;
    let t = Threshold {
        size_min,
        size_max,
        dist_min,
        dist_max,
    };
    py.detached(|| SizeField::threshold(region, &targets, t))
        .map(Some)
        .map_err(|e| err(format!("size_toward: {e}")))
}

/// A field given as a number, an expression in x and y, or a vectorized callable.
fn scalar_field(
    py: Python<'_>,
    region: &Region,
    spec: &Bound<'_, PyAny>,
    what: &str,
) -> PyResult<SizeField> {
    if spec.is_instance_of::<PyString>() {
        let text: String = spec.extract()?;
        if cvtmesh::io::names_sizes(std::path::Path::new(&text)) {
            let file = cvtmesh::io::read_sizes(std::path::Path::new(&text)).map_err(err)?;
            if let Some(view) = &file.view {
                let warnings = py.import("warnings")?;
                let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
                warnings.call_method1("warn", (view, category))?;
            }
            let (mesh, sizes) = (file.mesh, file.sizes);
            return py
                .detached(|| SizeField::from_mesh(region, &mesh.points, &mesh.triangles, &sizes))
                .map_err(|e| err(format!("{what} {text}: {e}")));
        }
        return SizeField::from_expr(&text).map_err(|e| err(format!("{what}: {e}")));
    }
    // (points, triangles, values): values at the vertices of a mesh, linear on its triangles.
    if let Ok((points, triangles, values)) =
        spec.extract::<(Bound<'_, PyAny>, Bound<'_, PyAny>, Bound<'_, PyAny>)>()
    {
        let (pts, tris) = mesh_arrays(&points, &triangles, what)?;
        let np = py.import("numpy")?;
        let values = np.call_method1("asarray", (values, "float64"))?;
        let values = np.call_method1("ravel", (values,))?;
        let values: PyReadonlyArray1<'_, f64> = values.extract()?;
        let values = values.as_array().to_vec();
        return py
            .detached(|| SizeField::from_mesh(region, &pts, &tris, &values))
            .map_err(|e| err(format!("{what}: {e}")));
    }
    if spec.is_callable() {
        let np = py.import("numpy")?;
        let call = |nodes: &[DVec2]| -> PyResult<Vec<f64>> {
            let xy = xy_array(py, nodes)?;
            let out = spec.call1((xy,))?;
            let arr = np.call_method1("asarray", (out, "float64"))?;
            let arr = np.call_method1("ravel", (arr,))?;
            let values: PyReadonlyArray1<'_, f64> = arr.extract()?;
            Ok(values.as_array().to_vec())
        };
        // A size's smallest value sets how fine its grid must be; a density's values are no
        // lengths, so it keeps one grid.
        let sampled = match what {
            "density" => SizeField::from_samples(region, DENSITY_GRID, call),
            _ => SizeField::from_sampler(region, call),
        }
        .map_err(|e: SizeFieldError| err(format!("{what}: {e}")))?;
        return sampled;
    }
    let not_a_field = |tail: &str| {
        err(format!(
            "{what} must be a number, an expression string in x and y, a mesh file (.node, .msh), (points, triangles, values) arrays, or a callable taking an (n, 2) array{tail}"
        ))
    };
    // True is an int to Python, and would be a size of 1.
    if spec.is_instance_of::<pyo3::types::PyBool>() {
        return Err(not_a_field(", not a bool"));
    }
    let h: f64 = spec.extract().map_err(|_| not_a_field(""))?;
    // Checked here, as given: bounding the field clamps a constant below at 0, so a later
    // check would report 0, not the number given.
    if what == "size" && !(h.is_finite() && h > 0.0) {
        return Err(err(format!(
            "{what} is {h}: an edge length must be positive and finite"
        )));
    }
    Ok(SizeField::constant(h))
}

/// Run a mesher with the interpreter released, reporting progress to `progress` (if any)
/// and stopping at Ctrl-C.
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (region, *, n = None, size = None, method = "ccvt", seed = None, tol = 1e-4,
    max_iter = None, density = None, progress = None, size_min = None, size_max = None,
    gradation = 0.3, size_toward = Vec::new(), size_threshold = None, simplify = None,
    time_limit = None, polish = cvtmesh::POLISH_BELOW_DEG))]
fn mesh(
    py: Python<'_>,
    region: &PyRegion,
    n: Option<&Bound<'_, PyAny>>,
    size: Option<&Bound<'_, PyAny>>,
    method: &str,
    seed: Option<&Bound<'_, PyAny>>,
    tol: f64,
    max_iter: Option<&Bound<'_, PyAny>>,
    density: Option<&Bound<'_, PyAny>>,
    progress: Option<Py<PyAny>>,
    size_min: Option<f64>,
    size_max: Option<f64>,
    gradation: Option<f64>,
    size_toward: Vec<String>,
    size_threshold: Option<(f64, f64, f64, f64)>,
    simplify: Option<&Bound<'_, PyAny>>,
    time_limit: Option<f64>,
    polish: f64,
) -> PyResult<PyMesh> {
    let n = n
        .map(|n| whole_count(n, "n", "a number of vertices, a positive integer"))
        .transpose()?;
    let seed = seed.map_or(Ok(1), |s| {
        whole_count(s, "seed", "an integer from 0 to 2**64 - 1")
    })?;
    let max_iter = max_iter.map_or(Ok(10_000), |m| {
        whole_count(m, "max_iter", "an iteration cap, a positive integer")
    })?;
    let method: Method = method.parse().map_err(err)?;
    let region = region.inner.clone();
    if size.is_some() && density.is_some() {
        return Err(err(
            "give size (an edge length) or density (a CVT density), not both",
        ));
    }
    let toward = distance_field(py, &region, &size_toward, size_threshold)?;
    if toward.is_some() && density.is_some() {
        return Err(err(
            "give size_toward (an edge length) or density (a CVT density), not both",
        ));
    }
    let by_size = size
        .map(|s| scalar_field(py, &region, s, "size"))
        .transpose()?;
    let graded = match (by_size, toward) {
        (Some(a), Some(b)) => Some(py.detached(|| a.min(&b, &region)).map_err(err)?),
        (a, b) => a.or(b),
    };
    if graded.is_none() && (size_min.is_some() || size_max.is_some()) {
        return Err(err(
            "size_min and size_max bound a size field: give size or size_toward as well",
        ));
    }
    // What bounding the field changed, for the result's notes.
    let mut field_note = None;
    let request = match (graded, density) {
        (Some(field), _) => {
            let (request, field, note) = py
                .detached(|| {
                    MeshRequest::bounded_size_field(
                        &field, &region, size_min, size_max, gradation, n,
                    )
                })
                .map_err(err)?;
            field_note = note;
            // Sizes that change faster than the field's background grid follows: say where,
            // as the command line does.
            if let Some(u) = py.detached(|| field.unresolved(&region)) {
                let warnings = py.import("warnings")?;
                let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
                warnings.call_method1("warn", (u.for_mesh(), category))?;
            }
            request
        }
        (None, Some(d)) => {
            let field = scalar_field(py, &region, d, "density")?;
            let k = n.ok_or_else(|| err("density needs n, the number of vertices"))?;
            MeshRequest::points(k).density(density_of(field))
        }
        (None, None) => MeshRequest::points(
            n.ok_or_else(|| err("give n (the number of vertices) or size (an edge length)"))?,
        ),
    };
    let (region, simplified) = match simplify {
        None => (region, None),
        Some(s) => {
            let tol = simplify_tolerance(s, &region, &request)?;
            let s = region.simplified(tol).map_err(err)?;
            (
                Arc::new(s.region.with_default_corners()),
                Some(s.to_string()),
            )
        }
    };
    // A region narrower than half the spacing somewhere meshes into slivers there: say where,
    // and what K would resolve it, as the command line does.
    if let Some(thin) = py.detached(|| cvtmesh::thin_feature(&region, &request)) {
        let warnings = py.import("warnings")?;
        let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
        warnings.call_method1("warn", (thin.to_string(), category))?;
    }
    let cancel = Arc::new(AtomicBool::new(false));
    let request = request
        .seed(seed)
        .tol(tol)
        .max_iter(max_iter)
        .polish(polish)
        .cancel_flag(cancel.clone());
    let request = match time_limit {
        None => request,
        Some(s) => request.time_limit_secs(s).map_err(err)?,
    };
    let mut stopped: Option<PyErr> = None;
    let result = {
        let region = region.clone();
        let stopped = &mut stopped;
        py.detach(move || {
            let mut report = |p: Progress| {
                if stopped.is_some() {
                    return;
                }
                let outcome = Python::attach(|py| -> PyResult<()> {
                    if let Some(cb) = &progress {
                        cb.call1(py, (p.iteration, p.energy, p.max_move))?;
                    }
                    py.check_signals()
                });
                if let Err(e) = outcome {
                    *stopped = Some(e);
                    cancel.store(true, Ordering::Relaxed);
                }
            };
            // The mesh is made on the pool, its progress reported here, on the calling thread:
            // the only one where Python sees Ctrl-C.
            let (tx, rx) = std::sync::mpsc::channel();
            let mut made = None;
            pool().in_place_scope(|s| {
                let (made, region, request) = (&mut made, &region, &request);
                s.spawn(move |_| {
                    *made = Some(method.mesher().mesh_parts(region, request, &mut |p| {
                        // The receiver outlives the mesh (it drains until this sender drops).
                        let _ = tx.send(p);
                    }));
                });
                for p in rx {
                    report(p);
                }
            });
            made.expect("the scope waits for the mesh")
        })
    };
    if let Some(e) = stopped {
        return Err(e);
    }
    let mut r = result.map_err(err)?;
    r.notes
        .splice(0..0, simplified.into_iter().chain(field_note));
    // As the command line does: a mesh that leaves out a band along a curved boundary, or
    // has triangles flatter than a degree, is named in a warning.
    let findings = py.detached(|| {
        [
            cvtmesh::short_coverage(&r.mesh, &region).map(|s| s.to_string()),
            cvtmesh::slivers_in_region(&r.mesh, &region).map(|s| {
                let advice = cvtmesh::sliver_advice(&region, method.mesher().as_ref());
                s.to_string() + &advice.map(|a| format!("; {a}")).unwrap_or_default()
            }),
        ]
    });
    for finding in findings.into_iter().flatten() {
        let warnings = py.import("warnings")?;
        let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
        warnings.call_method1("warn", (finding, category))?;
    }
    PyMesh::new(
        py,
        r.mesh,
        Some(region),
        r.converged,
        r.iterations,
        r.notes,
        r.energy_history,
    )
}

/// A count or seed argument `name` as an unsigned integer: Python integers (and numpy's)
/// from 0 on. A negative or too large one is a `MeshError` naming the argument, `what` it
/// must be and its value, which the conversion's `OverflowError` would not.
fn whole_count<T: TryFrom<u64>>(v: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<T> {
    if let Ok(k) = v.extract::<u64>() {
        if let Ok(k) = T::try_from(k) {
            return Ok(k);
        }
    }
    let Ok(int) = v.call_method0("__index__") else {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "{name} must be an integer, got {}",
            v.repr()?
        )));
    };
    Err(err(format!("{name} must be {what}, got {}", int.repr()?)))
}

/// The tolerance `simplify=` asks for: a positive number, or `"auto"` for the request's own.
fn simplify_tolerance(
    s: &Bound<'_, PyAny>,
    region: &Region,
    request: &MeshRequest,
) -> PyResult<f64> {
    if let Ok(word) = s.extract::<String>() {
        if word == "auto" {
            return Ok(request.simplify_tolerance(region));
        }
        return Err(err(format!(
            "simplify must be a positive number or \"auto\", got {word:?}"
        )));
    }
    match s.extract::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(err(format!(
            "simplify must be a positive number or \"auto\", got {}",
            s.repr()?
        ))),
    }
}

/// A density given as a field; the request's validation checks it on the region.
fn density_of(field: SizeField) -> Density {
    Density::Function(Arc::new(move |p| field.at(p)))
}

/// The 12 measures of any mesh of `region`: `points` (N, 2), `triangles` (M, 3), 0-based;
/// refused or warned about where the mesh does not conform to `region` (`Mesh.measures`).
#[pyfunction]
fn measures<'py>(
    py: Python<'py>,
    points: &Bound<'_, PyAny>,
    triangles: &Bound<'_, PyAny>,
    region: &PyRegion,
) -> PyResult<Bound<'py, PyDict>> {
    let mesh = any_mesh(points, triangles, "measures")?;
    let region = region.inner.clone();
    fit_to_measure(py, &mesh, &region)?;
    let m = py
        .detached(|| cvtmesh::measures(&mesh, &region))
        .map_err(err)?;
    measures_dict(py, &m)
}

/// How well the edges of any mesh of `region` follow the size field `size` (any form `mesh`
/// takes): the share of edges with length / h(midpoint) in [1/√2, √2], the efficiency index,
/// the mean of that ratio, the smallest angle and its 1st percentile, the vertex count and
/// the count the field asks for. The field is bounded as `mesh` bounds it (`size_min`,
/// `size_max`, `gradation`), so that the field a mesh was made for is the one measured.
#[pyfunction]
#[pyo3(signature = (points, triangles, region, size, size_min = None, size_max = None, gradation = 0.3))]
#[allow(clippy::too_many_arguments)]
fn size_conformity<'py>(
    py: Python<'py>,
    points: &Bound<'_, PyAny>,
    triangles: &Bound<'_, PyAny>,
    region: &PyRegion,
    size: &Bound<'_, PyAny>,
    size_min: Option<f64>,
    size_max: Option<f64>,
    gradation: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let mesh = any_mesh(points, triangles, "size_conformity")?;
    let region = region.inner.clone();
    let field = scalar_field(py, &region, size, "size")?
        .bounded(&region, size_min, size_max, gradation)
        .map_err(err)?;
    field
        .check(&region)
        .map_err(|e| err(format!("size: {e}")))?;
    let c = py
        .detached(|| cvtmesh::metrics::size_conformity(&mesh, &field, &region))
        .map_err(err)?;
    let d = PyDict::new(py);
    for (name, value) in cvtmesh::metrics::SizeConformity::NAMES
        .iter()
        .zip(c.values())
    {
        d.set_item(*name, value)?;
    }
    Ok(d)
}

/// Names of the built-in regions.
#[pyfunction]
fn regions() -> Vec<&'static str> {
    Region::builtin_names().to_vec()
}

/// Names of the methods, the default first.
#[pyfunction]
fn methods() -> Vec<&'static str> {
    Method::ALL.iter().map(|m| m.name()).collect()
}

/// Runs the `cvtmesh` command line `argv` (the program's name first) and returns its exit
/// code; what the command prints goes to the process's standard output and error. The
/// package's `cvtmesh` entry point and `python -m cvtmesh` call this.
#[pyfunction]
fn cli(py: Python<'_>, argv: Vec<std::ffi::OsString>) -> i32 {
    py.detached(|| cvtmesh_cli::run(argv))
}

#[pymodule]
fn _cvtmesh(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MeshError", m.py().get_type::<MeshError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<PyRegion>()?;
    m.add_class::<PyMesh>()?;
    m.add_function(wrap_pyfunction!(mesh, m)?)?;
    m.add_function(wrap_pyfunction!(measures, m)?)?;
    m.add_function(wrap_pyfunction!(size_conformity, m)?)?;
    m.add_function(wrap_pyfunction!(regions, m)?)?;
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(cli, m)?)?;
    m.add_function(wrap_pyfunction!(pickle::_region_from_state, m)?)?;
    m.add_function(wrap_pyfunction!(pickle::_mesh_from_state, m)?)?;
    Ok(())
}
