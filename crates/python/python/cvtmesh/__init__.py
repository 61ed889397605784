"""Triangular meshes of planar regions by constrained centroidal Voronoi tessellation.

    >>> import cvtmesh
    >>> m = cvtmesh.mesh("lake", n=500)
    >>> m.points.shape, m.triangles.shape[1]
    ((500, 2), 3)

A region is a built-in name (``cvtmesh.regions()``), the path of a region file (JSON, Triangle
``.poly``, GeoJSON, plain loop list) or of a mesh (``.msh``, ``.node``, ``.vtu``, ``.obj``: the region its
triangles cover), a :class:`Region`, or an ``(k, 2)`` array of the outer loop with
``holes=[(m, 2), ...]``. The mesh's arrays are numpy arrays: ``points`` (N, 2)
float64, ``triangles`` (M, 3) int64, 0-based and counter-clockwise.
"""

from __future__ import annotations

import functools
import os
from typing import Any, Callable, Optional, Sequence, Tuple, Union

import numpy as np

from ._cvtmesh import Mesh, MeshError, Region, __version__
from ._cvtmesh import measures as _measures
from ._cvtmesh import size_conformity as _size_conformity
from ._cvtmesh import mesh as _mesh
from ._cvtmesh import methods, regions

__all__ = [
    "Mesh",
    "MeshError",
    "Region",
    "mesh",
    "measures",
    "methods",
    "size_conformity",
    "regions",
    "__version__",
]

RegionLike = Union[str, "os.PathLike[str]", Region, Any]


def _region(region: RegionLike, holes: Optional[Sequence[Any]], corner_angle: Optional[float]) -> Region:
    # len(), not truth: holes may be a numpy array, whose truth value numpy refuses.
    has_holes = holes is not None and len(holes) > 0
    if isinstance(region, Region):
        if has_holes:
            raise MeshError("holes= goes with an outer loop given as an array, not with a Region")
        r = region
    elif isinstance(region, (str, os.PathLike)):
        if has_holes:
            raise MeshError("holes= goes with an outer loop given as an array, not with a file or name")
        r = Region.load(region)
    elif region is None:
        raise TypeError("region must be a built-in name, a file path, a Region or a (k, 2) array, not None")
    else:
        outer = np.ascontiguousarray(region, dtype=np.float64)
        if outer.ndim != 2 or outer.shape[1] != 2:
            raise MeshError(f"region must be an array of shape (k, 2), got {outer.shape}")
        # Region.from_loops checks each hole, and names hole points given for loops.
        r = Region.from_loops(outer, holes if holes is not None else [])
    if corner_angle is not None:
        r = r.with_corner_angle(float(corner_angle))
    else:
        r = r.with_default_corners()
    return r


def mesh(
    region: RegionLike,
    *,
    holes: Optional[Sequence[Any]] = None,
    n: Optional[int] = None,
    size: Union[None, float, str, Tuple[Any, Any, Any], Callable[[np.ndarray], Any]] = None,
    method: str = "ccvt",
    seed: int = 1,
    tol: float = 1e-4,
    max_iter: int = 10000,
    density: Union[None, str, Callable[[np.ndarray], Any]] = None,
    corner_angle: Optional[float] = None,
    progress: Optional[Callable[[int, float, float], Any]] = None,
    size_min: Optional[float] = None,
    size_max: Optional[float] = None,
    gradation: Optional[float] = 0.3,
    size_toward: Union[str, Sequence[str]] = (),
    size_threshold: Optional[Tuple[float, float, float, float]] = None,
    simplify: Union[None, float, str] = None,
    time_limit: Optional[float] = None,
    polish: float = 40.0,
) -> Mesh:
    """Mesh a planar region.

    Parameters
    ----------
    region
        A built-in name, a region file's path, a mesh file's path (the region its triangles
        cover, to mesh again), a :class:`Region`, or the outer loop as a ``(k, 2)`` array
        (then ``holes`` lists ``(m, 2)`` arrays, each a hole's boundary loop, not a point
        inside it as Triangle takes holes). A region of several parts
        (a GeoJSON MultiPolygon, a loop list of disjoint loops) has every part meshed, with
        the vertices shared by area.
    n
        The number of vertices. With ``size`` as well, the size field's shape is kept and
        scaled so that the mesh has exactly ``n`` vertices. For ``method="refine"`` it is a
        target: Delaunay refinement has no direct control of the count, so the area bound is
        searched and the mesh has the reachable count nearest ``n`` (``notes[1]`` says which).
        Where every triangle refines at the same bound, as on a square, that count jumps (81
        or 145 vertices about 100 on the unit square) and can be far from ``n``.
    size
        The target edge length h: a number, an expression in ``x`` and ``y``
        (``"0.01 + 0.1*sqrt(x^2+y^2)"``), a vectorized callable ``f(xy) -> h`` that
        receives an ``(n, 2)`` array and returns ``n`` values (called on the nodes inside the
        region of a 256×256 background grid, and once more on one of 4 nodes per its smallest
        h where that is finer), or sizes at the vertices of a mesh, linear on its
        triangles (an adaptive solver's sizes on its last mesh): ``(points, triangles, h)``
        arrays, or a Triangle ``.node`` file whose first attribute is h (with its ``.ele``) or
        a Gmsh ``.msh`` file with a ``$NodeData`` view. Without ``n`` the vertex count is
        (2/√3)∫h⁻² over the region.
    method
        One of :func:`methods` (default ``"ccvt"``: Algorithm 2 with Newton's method).
    seed
        Seed of every random choice: the same seed gives the same arrays.
    tol
        Stop when the largest vertex move is below ``tol`` times the mean spacing (for
        ``ccvt`` with a size field, the local spacing the field asks for).
    max_iter
        Iteration cap of each phase (``ccvt``'s Algorithm 2 runs several: its ε-phases, then
        the constrained one; ``iterations`` is their sum); a capped run returns its mesh with
        ``converged = False``.
    density
        A CVT density ρ instead of ``size`` (spacing ∝ ρ^(-1/4)); needs ``n``.
    corner_angle
        Keep only corners where the boundary turns by more than this many degrees; 0 keeps
        every vertex where it turns. Default: 30 where the corners were computed (polygon
        files, arrays), the region's own where it lists them (built-in regions).
    progress
        Called as ``progress(iteration, energy, largest_move)`` during the run.
    size_min, size_max
        Bounds on the edge length ``size`` asks for.
    gradation
        The largest gradient of ``size``: sizes grow by at most this much per unit of
        distance, h(x) = min_y h(y) + g|x - y| (default 0.3; ``None`` leaves the field as
        given).
    size_toward, size_threshold
        Refine toward boundary loops, pieces or points, as Gmsh's Distance + Threshold fields
        do: ``size_toward=["loop:1", "piece:0", "point:0.5,0.5"]`` (loop 0 is the outer
        boundary, then the holes; pieces are numbered as ``cvtmesh regions REGION`` lists
        them; ``"marker:4"`` is every wall a ``.poly`` marks 4, ``"line:0"`` the first embedded line; one target may be a bare string) and ``size_threshold=(h_min, h_max, d_min, d_max)``: edge length ``h_min`` up
        to distance ``d_min``, ``h_max`` from ``d_max`` on, linear between. With ``size`` as
        well, the smaller of the two is used.
    simplify
        Simplify a digitized boundary first (Douglas–Peucker): drop the vertices within this
        distance of the simplified boundary, so that a coastline with more corners than the
        mesh has vertices can be meshed coarsely; ``"auto"`` is a quarter of the spacing. The
        mesh is of the simplified region; its first note says how far that is from the given
        boundary. Default: the boundary as given.
    time_limit
        Stop iterating after this many seconds and return the mesh reached, with
        ``converged = False`` and a note (every method; CCVT ends each phase with one more
        step, so the mesh conforms). Default: none.
    polish
        Move the vertices of triangles with an angle below this many degrees to raise the
        smallest angle around them (boundary vertices along the boundary, corners fixed),
        keeping the triangles and the Delaunay property; ``0`` keeps every vertex where the
        method put it. Default: 40.

    Raises
    ------
    MeshError
        For every bad input (a ``ValueError``), with a message naming the problem.
    KeyboardInterrupt
        On Ctrl-C; the run stops at its next iteration.

    Warns
    -----
    RuntimeWarning
        Where the region is narrower than half the spacing (naming the place and the ``n``
        that resolves it), where the mesh leaves out a tenth of the region, and where it has
        triangles with an angle under 1° that the boundary does not force (counted, the
        flattest located).
    """
    r = _region(region, holes, corner_angle)
    return _mesh(
        r,
        n=n,
        size=size,
        method=method,
        seed=seed,
        tol=tol,
        max_iter=max_iter,
        density=density,
        progress=progress,
        size_min=size_min,
        size_max=size_max,
        # One target may be given as a bare string, which list() would split into letters.
        size_toward=[size_toward] if isinstance(size_toward, str) else list(size_toward),
        size_threshold=size_threshold,
        gradation=gradation,
        simplify=simplify,
        time_limit=time_limit,
        polish=polish,
    )


def measures(points: Any, triangles: Any, region: RegionLike) -> dict:
    """The 12 quality measures of the paper's Section 3 for any triangle mesh of ``region``.

    ``points`` is ``(N, 2)``, ``triangles`` ``(M, 3)`` 0-based vertex indices; the result maps
    ``lambda, gamma, h, mu, chi, nu, tau, d, alpha, beta, q, p`` to floats (lower is better, 0
    on an ideal hexagonal lattice), and the counts ``K`` and ``Ktilde`` to ints.
    """
    return _measures(points, triangles, _region(region, None, None))


def size_conformity(
    points: Any,
    triangles: Any,
    region: RegionLike,
    size: Any,
    size_min: Optional[float] = None,
    size_max: Optional[float] = None,
    gradation: Optional[float] = 0.3,
) -> dict:
    """How well the edges of any triangle mesh of ``region`` follow a size field.

    ``size`` takes every form :func:`mesh` takes (a number, an expression in ``x`` and ``y``, a
    vectorized callable, ``(points, triangles, h)`` arrays or a ``.node``/``.msh`` file of sizes
    at a mesh's vertices), bounded as :func:`mesh` bounds it (``size_min``, ``size_max``, and
    ``gradation``, 0.3 by default as there; ``None`` measures against the field as given), so
    that the same arguments measure the field a mesh was made for. The result maps ``edges``, ``unit_share`` (the share of edges whose
    length over h at their midpoint lies in [1/√2, √2]), ``efficiency`` (exp of the mean of
    l − 1 for l < 1 and 1/l − 1 otherwise; 1 is ideal), ``mean_length`` (of l),
    ``min_angle_deg``, ``min_angle_p1_deg`` (the 1st percentile of the triangles' smallest
    angles), ``vertices`` and ``predicted_vertices`` ((2/√3)∫h⁻²) to floats.

        >>> import cvtmesh
        >>> m = cvtmesh.mesh("circle", size="0.05 + 0.1*sqrt(x^2+y^2)", tol=1e-3)
        >>> cvtmesh.size_conformity(m.points, m.triangles, "circle", "0.05 + 0.1*sqrt(x^2+y^2)")["unit_share"] > 0.95
        True
    """
    return _size_conformity(
        points, triangles, _region(region, None, None), size, size_min, size_max, gradation
    )


def _to_meshio(self: Mesh, order: int = 1, region: Optional[RegionLike] = None) -> Any:
    """The mesh as a ``meshio.Mesh``: a ``triangle`` block, ``line`` blocks of boundary
    edges, one cell set per boundary loop (``boundary_0`` is the outer loop) and, for a mesh
    made here, one per piece (``piece_3``: a wall, numbered as ``Region.pieces``) and, where
    the region file numbers its walls (a ``.poly``'s segment markers, a Gmsh mesh's physical
    curves), one per number (``marker_4``), cell data ``marker`` (the wall's number on each
    line, 0 on the triangles, which XDMF and VTU files keep) and point data ``marker``
    (:meth:`Mesh.vertex_markers`), which finite-element libraries
    reading meshio see as named boundaries. ``order=2`` gives
    ``triangle6`` and ``line3`` blocks instead (:meth:`Mesh.quadratic`: the boundary nodes on
    the region's exact boundary). A mesh read from a file knows no region: pass ``region`` for
    its pieces, markers and exact boundary.

    The lines, concatenated (``cells_dict["line"]``), are the rows of ``boundary_edges``;
    there is one block per run of them along one piece (one loop where the pieces are not
    known), so that ``write(path, file_format="gmsh")`` writes each block as a Gmsh curve:
    cell data ``gmsh:geometrical`` numbers the curves, ``gmsh:physical`` gives each line its
    wall's marker (its loop + 1 where the region numbers no walls) and the triangles 1, point
    data ``gmsh:dim_tags`` puts each node on its curve or the surface, and ``field_data``
    names the physical groups as the cell sets (``marker_4`` or ``boundary_0``, and
    ``domain``), which meshio reads back as cell sets. The edges along the region's embedded
    lines (:meth:`Mesh.line_edges`: an interface, a crack) follow as one ``line`` block per
    marker, in the cell set ``marker_7`` of their marker and its physical group. Where the
    region has lines or subdomain points, each triangle's subdomain (:meth:`Mesh.subdomains`)
    is cell data ``subdomain`` (0 on the lines) and a cell set ``subdomain_3`` per number, and
    the triangles' ``gmsh:physical`` tags are those numbers (Gmsh's physical surfaces); with
    several numbers the triangles come in a block per number, in increasing order (each a
    Gmsh surface, the triangles of each in the mesh's order), as Gmsh files and meshio's Gmsh
    writer, which gives a block one physical tag, need them. A
    marker or subdomain the region names (``Region.marker_names``, ``Region.subdomain_names``:
    a Gmsh file's physical names, a JSON subdomain's ``"name"``) has a cell set by its name
    beside the numbered one, and its physical group in ``field_data`` takes the name, as a
    Gmsh file names it."""
    import meshio

    if region is not None and not isinstance(region, Region):
        region = _region(region, None, None)
    loops = np.asarray(self.boundary_loop)
    try:
        pieces = np.asarray(self.boundary_pieces(region))
    except MeshError:  # read from a file: its pieces need the region
        pieces = np.empty(0, dtype=np.int64)
    try:
        markers = np.asarray(self.boundary_markers(region))
    except MeshError:  # no region, or one that numbers no walls
        markers = np.empty(0, dtype=np.int64)
    if order == 1:
        points, tris = np.array(self.points), np.array(self.triangles)
        lines = np.array(self.boundary_edges)
        kinds = ("triangle", "line")
    elif order == 2:
        points, tri6 = self.quadratic(region)
        # Each edge's node, by the edge's sorted ends: the triangles hold every edge.
        ends = np.concatenate([tri6[:, [0, 1]], tri6[:, [1, 2]], tri6[:, [2, 0]]])
        nodes = np.concatenate([tri6[:, 3], tri6[:, 4], tri6[:, 5]])
        node_of = dict(zip(map(tuple, np.sort(ends, axis=1).tolist()), nodes.tolist()))
        edges = np.array(self.boundary_edges)
        mids = [node_of[tuple(e)] for e in np.sort(edges, axis=1).tolist()]
        lines = np.column_stack([edges, np.array(mids, dtype=np.int64).reshape(-1)])
        points, tris = np.array(points), np.array(tri6)
        kinds = ("triangle6", "line3")
    else:
        raise MeshError(f"order must be 1 or 2, got {order}")

    # Gmsh curves: runs of consecutive lines on one loop and piece. Gmsh (and meshio's
    # writer) give a curve one physical tag, so a curve must not straddle two walls.
    keys = np.column_stack([loops, pieces]) if len(pieces) else loops[:, None]
    cuts = np.flatnonzero(np.any(keys[1:] != keys[:-1], axis=1)) + 1
    bounds = np.concatenate([[0], cuts, [len(lines)]]).astype(np.int64)
    runs = list(zip(bounds[:-1].tolist(), bounds[1:].tolist()))
    group = markers if len(markers) else loops + 1

    cells = [(kinds[0], tris)] + [(kinds[1], lines[a:b]) for a, b in runs]

    def per_block(rows: np.ndarray) -> list:
        """Line rows (indices into boundary_edges) as meshio's per-block lists."""
        return [np.empty(0, dtype=np.int64)] + [rows[(rows >= a) & (rows < b)] - a for a, b in runs]

    cell_sets = {f"boundary_{k}": per_block(np.flatnonzero(loops == k)) for k in np.unique(loops)}
    cell_sets["domain"] = [np.arange(len(tris))] + [np.empty(0, dtype=np.int64) for _ in runs]
    for j in np.unique(pieces):
        cell_sets[f"piece_{j}"] = per_block(np.flatnonzero(pieces == j))
    for m in np.unique(markers):
        cell_sets[f"marker_{m}"] = per_block(np.flatnonzero(markers == m))

    cell_data = {
        "gmsh:physical": [np.ones(len(tris), dtype=np.int64)]
        + [np.full(b - a, group[a], dtype=np.int64) for a, b in runs],
        "gmsh:geometrical": [np.ones(len(tris), dtype=np.int64)]
        + [np.full(b - a, r + 1, dtype=np.int64) for r, (a, b) in enumerate(runs)],
    }
    names = "marker_{}" if len(markers) else "boundary_{}"
    field_data = {"domain": np.array([1, 2])}
    for g in np.unique(group):
        field_data[names.format(g if len(markers) else g - 1)] = np.array([g, 1])
    # Every node on the surface but the lines' own: each line's first node (and its edge
    # node) on its curve, so each curve holds a node, as Gmsh's entities list them.
    dim_tags = np.tile(np.array([2, 1], dtype=np.int64), (len(points), 1))
    for r, (a, b) in enumerate(runs):
        dim_tags[lines[a:b, [0] + list(range(2, lines.shape[1]))].ravel()] = [1, r + 1]
    point_data = {"gmsh:dim_tags": dim_tags}
    # The edges along the region's embedded lines (an interface, a crack): a line block per
    # marker after the boundary's, in the cell set and physical group of that marker.
    try:
        inner, inner_markers = self.line_edges(region)
    except MeshError:  # no region, or no lines the mesh follows
        inner, inner_markers = np.empty((0, 2), dtype=np.int64), np.empty(0, dtype=np.int64)
    inner = np.array(inner)
    if order == 2 and len(inner):
        mids = [node_of[tuple(e)] for e in np.sort(inner, axis=1).tolist()]
        inner = np.column_stack([inner, np.array(mids, dtype=np.int64)])
    spare = int(max(group.max(initial=0), inner_markers.max(initial=0))) + 1
    for i, m in enumerate(np.unique(inner_markers).tolist()):
        rows = inner[inner_markers == m]
        cells.append((kinds[1], rows))
        for blocks in cell_sets.values():
            blocks.append(np.empty(0, dtype=np.int64))
        name = f"marker_{m}"
        if name not in cell_sets:
            cell_sets[name] = [np.empty(0, dtype=np.int64) for _ in cells]
        cell_sets[name][-1] = np.arange(len(rows))
        tag = m if m > 0 else spare + i
        cell_data["gmsh:physical"].append(np.full(len(rows), tag, dtype=np.int64))
        cell_data["gmsh:geometrical"].append(np.full(len(rows), len(runs) + 1 + i, dtype=np.int64))
        field_data[name] = np.array([tag, 1])
    # Each triangle's subdomain, where the region's lines part it or its points number it: a
    # physical surface per number (a number 0 or below takes a tag past the others).
    try:
        parts, marker_names, subdomain_names = self._groups(region)
    except MeshError:  # no region, or one whose lines the mesh does not follow
        parts, marker_names, subdomain_names = None, {}, {}
    if parts is not None:
        parts = np.asarray(parts)
        cell_data["subdomain"] = [parts] + [np.zeros(len(c[1]), dtype=np.int64) for c in cells[1:]]
        numbers = np.unique(parts).tolist()
        top = max([0] + [n for n in numbers if n > 0])
        tags = {n: (n if n > 0 else top + 1 + k) for k, n in enumerate(numbers)}
        cell_data["gmsh:physical"][0] = np.array([tags[n] for n in parts.tolist()], dtype=np.int64)
        del field_data["domain"]
        for n in numbers:
            cell_sets[f"subdomain_{n}"] = [np.flatnonzero(parts == n)] + [
                np.empty(0, dtype=np.int64) for _ in cells[1:]]
            field_data[f"subdomain_{n}"] = np.array([tags[n], 2])
    # A group the region names (a Gmsh physical name, a JSON subdomain's "name") is a cell
    # set by that name as well, and the name of its physical group: what Gmsh users read.
    for kind, names in (("marker", marker_names), ("subdomain", subdomain_names)):
        for n, name in names.items():
            numbered = f"{kind}_{n}"
            if numbered in cell_sets and name not in cell_sets:
                cell_sets[name] = list(cell_sets[numbered])
                if numbered in field_data:
                    field_data[name] = field_data.pop(numbered)
    if len(markers):
        # The walls' numbers as cell data too (0 on the triangles): XDMF and VTU, which
        # finite-element codes read facet tags from, keep cell data, not cell sets.
        cell_data["marker"] = (
            [np.zeros(len(tris), dtype=np.int64)]
            + [markers[a:b] for a, b in runs]
            + [np.full(len(c[1]), m, dtype=np.int64) for c, m in zip(cells[1 + len(runs):], np.unique(inner_markers).tolist())]
        )
        # Each vertex's as a Triangle .node gives it (a point the region marks on its own
        # keeps its marker); the edge nodes of order 2 take 0.
        marks = np.zeros(len(points), dtype=np.int64)
        own = np.asarray(self.vertex_markers(region))
        marks[: len(own)] = own
        point_data["marker"] = marks
    # Gmsh gives an entity one physical tag, and meshio's Gmsh writer takes each block's first:
    # each line block along an embedded line gets a node on its curve (one inside the line,
    # on no other curve), and triangles of several subdomains become a block (a surface) per
    # subdomain, so that a file meshio writes names every curve and surface it lists.
    on_curves = np.zeros(len(points), dtype=bool)
    on_curves[lines.ravel()] = True
    for i in range(len(cells) - 1 - len(runs)):
        rows = cells[1 + len(runs) + i][1]
        if rows.shape[1] > 2:  # order 2: the first edge's own node
            node = rows[0, 2]
        else:  # a node two of the block's edges share, on no boundary curve
            nodes, counts = np.unique(rows, return_counts=True)
            inside = nodes[(counts == 2) & ~on_curves[nodes]]
            node = inside[0] if len(inside) else rows[0, 0]
        dim_tags[node] = [1, len(runs) + 1 + i]
        on_curves[rows.ravel()] = True
    if parts is not None and len(np.unique(parts)) > 1:
        cells, cell_sets, cell_data = _surface_per_subdomain(
            parts, kinds[0], cells, cell_sets, cell_data, dim_tags, on_curves
        )
    return meshio.Mesh(
        points,
        cells,
        cell_sets=cell_sets,
        cell_data=cell_data,
        point_data=point_data,
        field_data=field_data,
    )


Mesh.to_meshio = _to_meshio  # type: ignore[attr-defined]


def _surface_per_subdomain(parts, kind, cells, cell_sets, cell_data, dim_tags, on_curves):
    """The first (triangle) block of ``to_meshio``'s lists split into one block per subdomain
    number, in increasing order, each its own Gmsh surface holding a node of its own."""
    numbers = np.unique(parts)
    where = [np.flatnonzero(parts == n) for n in numbers]
    tris = cells[0][1]
    new_cells = [(kind, tris[w]) for w in where] + cells[1:]
    sets = {
        name: [np.flatnonzero(np.isin(w, blocks[0])) for w in where] + blocks[1:]
        for name, blocks in cell_sets.items()
    }
    data = {name: [blocks[0][w] for w in where] + blocks[1:] for name, blocks in cell_data.items()}
    data["gmsh:geometrical"][: len(where)] = [
        np.full(len(w), s + 1, dtype=np.int64) for s, w in enumerate(where)
    ]
    for s, w in enumerate(where):
        nodes = np.unique(tris[w][:, :3])
        free = nodes[~on_curves[nodes]]
        if len(free):
            dim_tags[free[0]] = [2, s + 1]
    return new_cells, sets, data


def _taking_region_names(name: str) -> None:
    """Mesh.<name>(region=None, ...) taking a region as ``mesh`` does: a built-in name, a
    file path (a mesh's too) or an outer loop's array as well as a Region."""
    method = getattr(Mesh, name)

    # The method's own name, documentation and signature (help() and inspect show them).
    @functools.wraps(method)
    def call(self: Mesh, region: Optional[RegionLike] = None, *args: Any, **kwargs: Any) -> Any:
        if region is not None and not isinstance(region, Region):
            region = _region(region, None, None)
        return method(self, region, *args, **kwargs)

    setattr(Mesh, name, call)


for _name in (
    "quadratic",
    "boundary_pieces",
    "boundary_markers",
    "line_edges",
    "subdomains",
    "vertex_markers",
    "measures",
    "polished",
):
    _taking_region_names(_name)
