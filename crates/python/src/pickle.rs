//! Python's `pickle` (and so `multiprocessing`, `concurrent.futures`, joblib and dask) for
//! `Region` and `Mesh`: each reduces to a function of this module and its saved state, every
//! number kept to the bit (a region by [`Region::to_state`], a mesh's arrays as numpy arrays).
use super::{err, PyMesh, PyRegion};
use cvtmesh::io::Walls;
use cvtmesh::{DVec2, Mesh, Region, VertexMarker};
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;

/// Bumped whenever a mesh's state below changes: an old state is refused, not misread.
const MESH_STATE: u32 = 1;

/// The module the state functions are found in by name when unpickled.
const MODULE: &str = "cvtmesh._cvtmesh";

/// A file's walls (`cvtmesh::io::Walls`), field by field.
type WallsState = (
    Vec<(u32, u32, i64)>,
    Vec<(u32, i64)>,
    BTreeMap<i64, String>,
    Vec<(u32, u32)>,
    Vec<i64>,
    Vec<i64>,
    BTreeMap<i64, String>,
    Option<(i64, String)>,
    Vec<String>,
);

/// A mesh's markers as four arrays: the kind (0 inside, 1 on a piece, 2 at a corner), the
/// loop, the piece or corner, and the position along the loop.
type MarkersState<'py> = (
    Bound<'py, PyArray1<u8>>,
    Bound<'py, PyArray1<u64>>,
    Bound<'py, PyArray1<u64>>,
    Bound<'py, PyArray1<f64>>,
);

/// Everything a `Mesh` holds: the state's layout, the points and triangles, the markers, the
/// region's state, the held vertices, the file it was read from with its walls, converged,
/// iterations, notes and the energies; the arrays as written (`P`, `T`, `M`, `E`) or read.
type MeshStateOf<P, T, M, E> = (
    u32,
    P,
    T,
    M,
    Option<String>,
    Vec<u32>,
    Option<(PathBuf, WallsState)>,
    bool,
    usize,
    Vec<String>,
    E,
);

/// A mesh's markers as read back ([`MarkersState`]).
type MarkersRead<'py> = (
    PyReadonlyArray1<'py, u8>,
    PyReadonlyArray1<'py, u64>,
    PyReadonlyArray1<'py, u64>,
    PyReadonlyArray1<'py, f64>,
);

/// A mesh's state as read back.
type MeshStateRead<'py> = MeshStateOf<
    PyReadonlyArray2<'py, f64>,
    PyReadonlyArray2<'py, i64>,
    MarkersRead<'py>,
    PyReadonlyArray1<'py, f64>,
>;

/// A mesh's state as written.
pub(crate) type MeshState<'py> = MeshStateOf<Py<PyAny>, Py<PyAny>, MarkersState<'py>, Py<PyAny>>;

/// The `Region` a pickle saved ([`Region::to_state`]).
#[pyfunction]
pub(crate) fn _region_from_state(state: &str) -> PyResult<PyRegion> {
    Ok(PyRegion {
        inner: Arc::new(Region::from_state(state).map_err(err)?),
    })
}

/// `Region.__reduce__`.
pub(crate) fn reduce_region<'py>(
    py: Python<'py>,
    region: &PyRegion,
) -> PyResult<(Bound<'py, PyAny>, (String,))> {
    let f = py.import(MODULE)?.getattr("_region_from_state")?;
    Ok((f, (region.inner.to_state(),)))
}

fn walls_state(w: &Walls) -> WallsState {
    (
        w.edges.iter().map(|&([a, b], m)| (a, b, m)).collect(),
        w.points.clone(),
        w.names.clone(),
        w.inner.iter().map(|&[a, b]| (a, b)).collect(),
        w.inner_markers.clone(),
        w.subdomains.clone(),
        w.subdomain_names.clone(),
        w.surface_group.clone(),
        w.notes.clone(),
    )
}

fn walls(s: WallsState) -> Walls {
    let (edges, points, names, inner, inner_markers, subdomains, subdomain_names, group, notes) = s;
    Walls {
        edges: edges.into_iter().map(|(a, b, m)| ([a, b], m)).collect(),
        points,
        names,
        inner: inner.into_iter().map(|(a, b)| [a, b]).collect(),
        inner_markers,
        subdomains,
        subdomain_names,
        surface_group: group,
        notes,
    }
}

/// `Mesh.__reduce__`.
pub(crate) fn reduce_mesh<'py>(
    py: Python<'py>,
    m: &PyMesh,
) -> PyResult<(Bound<'py, PyAny>, (MeshState<'py>,))> {
    let f = py.import(MODULE)?.getattr("_mesh_from_state")?;
    let n = m.mesh.markers.len();
    let (mut kind, mut a, mut b, mut t) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for marker in &m.mesh.markers {
        let (k, x, y, s) = match *marker {
            VertexMarker::Interior => (0, 0, 0, 0.0),
            VertexMarker::Boundary {
                loop_index,
                piece,
                loop_param,
            } => (1, loop_index, piece, loop_param),
            VertexMarker::Corner {
                loop_index,
                corner,
                loop_param,
            } => (2, loop_index, corner, loop_param),
        };
        kind.push(k);
        a.push(x as u64);
        b.push(y as u64);
        t.push(s);
    }
    let markers = (
        PyArray1::from_vec(py, kind),
        PyArray1::from_vec(py, a),
        PyArray1::from_vec(py, b),
        PyArray1::from_vec(py, t),
    );
    let state = (
        MESH_STATE,
        m.points.clone_ref(py).into_any(),
        m.triangles.clone_ref(py).into_any(),
        markers,
        m.region.as_ref().map(|r| r.to_state()),
        m.held.clone(),
        m.read_from
            .as_ref()
            .map(|(path, w)| (path.clone(), walls_state(w))),
        m.converged,
        m.iterations,
        m.notes.clone(),
        m.energy_history.clone_ref(py).into_any(),
    );
    Ok((f, (state,)))
}

/// The `Mesh` a pickle saved.
#[pyfunction]
pub(crate) fn _mesh_from_state(py: Python<'_>, state: MeshStateRead<'_>) -> PyResult<PyMesh> {
    let (
        version,
        points,
        triangles,
        markers,
        region,
        held,
        read_from,
        converged,
        iterations,
        notes,
        energies,
    ) = state;
    if version != MESH_STATE {
        return Err(err(format!(
            "a mesh's saved state of layout {version} (this build reads layout {MESH_STATE})"
        )));
    }
    let points = points.as_array();
    let triangles = triangles.as_array();
    let (kind, a, b, t) = (
        markers.0.as_array(),
        markers.1.as_array(),
        markers.2.as_array(),
        markers.3.as_array(),
    );
    let n = points.nrows();
    if points.ncols() != 2
        || triangles.ncols() != 3
        || [kind.len(), a.len(), b.len(), t.len()]
            .iter()
            .any(|&k| k != n)
    {
        return Err(err("not a mesh's saved state: its arrays do not match"));
    }
    let vertex = |v: i64| u32::try_from(v).ok().filter(|&v| (v as usize) < n);
    let triangles: Option<Vec<[u32; 3]>> = triangles
        .rows()
        .into_iter()
        .map(|r| Some([vertex(r[0])?, vertex(r[1])?, vertex(r[2])?]))
        .collect();
    let Some(triangles) = triangles else {
        return Err(err("not a mesh's saved state: a triangle names no vertex"));
    };
    let markers = (0..n)
        .map(|i| match kind[i] {
            0 => Ok(VertexMarker::Interior),
            1 => Ok(VertexMarker::Boundary {
                loop_index: a[i] as usize,
                piece: b[i] as usize,
                loop_param: t[i],
            }),
            2 => Ok(VertexMarker::Corner {
                loop_index: a[i] as usize,
                corner: b[i] as usize,
                loop_param: t[i],
            }),
            _ => Err(err("not a mesh's saved state: a marker of no kind")),
        })
        .collect::<PyResult<Vec<_>>>()?;
    let mesh = Mesh {
        points: points
            .rows()
            .into_iter()
            .map(|r| DVec2::new(r[0], r[1]))
            .collect(),
        triangles,
        markers,
    };
    let region = region
        .map(|s| Region::from_state(&s).map(Arc::new))
        .transpose()
        .map_err(err)?;
    let mut m = PyMesh::new(
        py,
        mesh,
        region,
        converged,
        iterations,
        notes,
        energies.as_array().to_vec(),
    )?;
    m.held = held;
    m.read_from = read_from.map(|(path, w)| (path, walls(w)));
    Ok(m)
}
