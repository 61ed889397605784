"""End-to-end tests of the Python package: real meshes, checked for real properties."""

import math
import subprocess
import sys
from pathlib import Path
import threading

import numpy as np
import warnings

import pytest

import cvtmesh
from cvtmesh import MeshError, Region

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
HOLE = np.array([[0.4, 0.4], [0.4, 0.6], [0.6, 0.6], [0.6, 0.4]])


def triangle_areas(points, triangles):
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])


def triangle_set(points, triangles):
    """Each triangle as the set of its corners' coordinates (rounded to 1e-12)."""
    return {frozenset(map(tuple, np.round(points[t], 12))) for t in triangles}


def edge_lengths(points, triangles):
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    return e, np.linalg.norm(points[e[:, 0]] - points[e[:, 1]], axis=1)


def test_polygon_with_hole_tiles_the_region_and_keeps_the_hole_empty():
    m = cvtmesh.mesh(SQUARE, holes=[HOLE], n=400)
    assert m.points.shape == (400, 2) and m.points.dtype == np.float64
    assert m.triangles.shape[1] == 3 and m.triangles.dtype == np.int64
    assert m.converged and m.iterations > 0
    areas = triangle_areas(m.points, m.triangles)
    assert (areas > 0).all(), "triangles are counter-clockwise"
    assert areas.sum() == pytest.approx(1.0 - 0.04, rel=1e-12)
    centroids = m.points[m.triangles].mean(axis=1)
    in_hole = (abs(centroids[:, 0] - 0.5) < 0.1) & (abs(centroids[:, 1] - 0.5) < 0.1)
    assert not in_hole.any()
    # Two boundary loops: the square's 4 sides and the hole's, edges on their own loop.
    assert sorted(np.unique(m.boundary_loop)) == [0, 1]
    assert len(m.boundary_edges) == len(m.boundary_loop)
    ends = m.points[m.boundary_edges]
    on_hole = (abs(ends - 0.5) <= 0.1 + 1e-12).all(axis=(1, 2))
    assert (on_hole == (m.boundary_loop == 1)).all()


def test_region_coercions_agree():
    by_name = cvtmesh.mesh("circle", n=88)
    by_region = cvtmesh.mesh(Region.builtin("circle"), n=88)
    np.testing.assert_array_equal(by_name.points, by_region.points)
    assert "circle" in cvtmesh.regions() and cvtmesh.methods()[0] == "ccvt"


def test_same_seed_same_arrays_other_seed_other_arrays():
    a = cvtmesh.mesh("square_hole", n=194, seed=3)
    b = cvtmesh.mesh("square_hole", n=194, seed=3)
    c = cvtmesh.mesh("square_hole", n=194, seed=4)
    assert a.points.tobytes() == b.points.tobytes()
    assert a.triangles.tobytes() == b.triangles.tobytes()
    assert a.points.tobytes() != c.points.tobytes()


def test_arrays_are_read_only():
    m = cvtmesh.mesh("circle", n=19)
    with pytest.raises(ValueError):
        m.points[0, 0] = 5.0


@pytest.mark.parametrize("method", cvtmesh.methods())
def test_every_method_meshes_the_lake(method):
    m = cvtmesh.mesh("lake", n=300, method=method, tol=1e-3)
    region = Region.builtin("lake")
    assert m.points.shape == (300, 2)
    assert triangle_areas(m.points, m.triangles).sum() == pytest.approx(region.area, rel=2e-2)
    assert region.contains(m.points[m.triangles].mean(axis=1)).all()


def test_measures_are_those_of_the_paper_and_match_the_free_function():
    m = cvtmesh.mesh("circle", n=88)
    own = m.measures()
    free = cvtmesh.measures(m.points, m.triangles, "circle")
    names = ["lambda", "gamma", "h", "mu", "chi", "nu", "tau", "d", "alpha", "beta", "q", "p"]
    for k in names:
        assert own[k] == pytest.approx(free[k], rel=1e-12), k
        assert own[k] >= 0.0
    assert own["K"] == 88
    # β = (π/3)/(smallest angle) − 1: check it against the angles of the triangles.
    p = m.points[m.triangles]
    angles = []
    for i in range(3):
        u, v = p[:, (i + 1) % 3] - p[:, i], p[:, (i + 2) % 3] - p[:, i]
        cos = (u * v).sum(axis=1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        angles.append(np.arccos(np.clip(cos, -1, 1)))
    assert own["beta"] == pytest.approx(math.pi / 3 / np.min(angles) - 1, rel=1e-9)


def test_size_field_grades_the_mesh_and_callable_is_called_on_whole_grids():
    calls = []

    def h(xy):
        calls.append(xy.shape)
        return 0.03 + 0.12 * np.hypot(xy[:, 0], xy[:, 1])

    m = cvtmesh.mesh("circle", size=h, tol=1e-3)
    # The nodes inside the circle of a 256 x 256 grid, then of one with 4 nodes per its
    # smallest h (about 0.03) across the circle's width of 2: never point by point.
    assert [c[1] for c in calls] == [2, 2]
    assert 0.75 * 256**2 < calls[0][0] < 0.8 * 256**2
    assert calls[0][0] < calls[1][0] < 0.8 * 268**2
    # Edges near the centre are shorter than edges near the rim, roughly as h says.
    e, lengths = edge_lengths(m.points, m.triangles)
    mid = 0.5 * (m.points[e[:, 0]] + m.points[e[:, 1]])
    r = np.hypot(mid[:, 0], mid[:, 1])
    inner, outer = lengths[r < 0.25].mean(), lengths[r > 0.75].mean()
    assert outer > 2.5 * inner
    # The vertex count is (2/√3)∫h⁻², within the boundary layer's error.
    exact = 2 / math.sqrt(3) * 2 * math.pi * (1 / 0.12**2) * (
        math.log((0.03 + 0.12) / 0.03) - 0.12 / (0.03 + 0.12)
    )
    assert len(m.points) == pytest.approx(exact, rel=0.02)


def test_sizes_on_a_mesh_grade_as_the_expression_they_sample(tmp_path):
    expr = "0.02 + 0.08*sqrt((x-0.3)^2 + y^2)"
    bg = cvtmesh.mesh("circle", n=1500, tol=1e-3)
    h = 0.02 + 0.08 * np.hypot(bg.points[:, 0] - 0.3, bg.points[:, 1])
    on_mesh = cvtmesh.mesh("circle", size=(bg.points, bg.triangles, h), tol=1e-3)
    by_expr = cvtmesh.mesh("circle", size=expr, tol=1e-3)
    assert len(on_mesh.points) == pytest.approx(len(by_expr.points), rel=0.02)
    # The same sizes from a Triangle file (first attribute) give the same mesh.
    node = tmp_path / "bg.node"
    node.write_text(
        f"{len(bg.points)} 2 1 0\n"
        + "".join(
            f"{i} {float(x)!r} {float(y)!r} {float(v)!r}\n"
            for i, ((x, y), v) in enumerate(zip(bg.points, h))
        )
    )
    (tmp_path / "bg.ele").write_text(
        f"{len(bg.triangles)} 3 0\n"
        + "".join(f"{i} {a} {b} {c}\n" for i, (a, b, c) in enumerate(bg.triangles))
    )
    from_file = cvtmesh.mesh("circle", size=str(node), tol=1e-3)
    assert np.array_equal(from_file.points, on_mesh.points)
    with pytest.raises(cvtmesh.MeshError, match="sizes for a mesh of"):
        cvtmesh.mesh("circle", size=(bg.points, bg.triangles, h[:-1]))
    with pytest.raises(cvtmesh.MeshError, match="refers to vertex"):
        cvtmesh.mesh("circle", size=(bg.points, bg.triangles + len(bg.points), h))


def test_size_conformity_scores_a_graded_mesh_against_any_form_of_its_field():
    expr = "0.03 + 0.12*sqrt(x^2+y^2)"
    m = cvtmesh.mesh("circle", size=expr, tol=1e-3)
    by_expr = cvtmesh.size_conformity(m.points, m.triangles, "circle", expr)
    assert by_expr["unit_share"] >= 0.95 and by_expr["efficiency"] >= 0.9
    assert by_expr["vertices"] == len(m.points)
    assert by_expr["predicted_vertices"] == pytest.approx(len(m.points), rel=0.02)
    # The same field as sizes at the vertices of another mesh, and as a callable.
    bg = cvtmesh.mesh("circle", n=2000, tol=1e-3)
    h = 0.03 + 0.12 * np.hypot(bg.points[:, 0], bg.points[:, 1])
    on_mesh = cvtmesh.size_conformity(m.points, m.triangles, "circle", (bg.points, bg.triangles, h))
    by_call = cvtmesh.size_conformity(
        m.points, m.triangles, "circle", lambda xy: 0.03 + 0.12 * np.hypot(xy[:, 0], xy[:, 1])
    )
    for other in (on_mesh, by_call):
        assert other["unit_share"] == pytest.approx(by_expr["unit_share"], abs=0.01)
        assert other["efficiency"] == pytest.approx(by_expr["efficiency"], abs=0.01)
    # A uniform mesh is far from this field.
    u = cvtmesh.mesh("circle", n=len(m.points), tol=1e-3)
    assert cvtmesh.size_conformity(u.points, u.triangles, "circle", expr)["unit_share"] < 0.8
    with pytest.raises(cvtmesh.MeshError, match="positive"):
        cvtmesh.size_conformity(m.points, m.triangles, "circle", "x")


def test_a_callable_size_that_is_no_size_somewhere_is_refused_with_its_value():
    # Zero on half the square: refused, not filled in from the other half.
    with pytest.raises(MeshError, match=r"size field is 0 at \((0\.[5-9]|1)"):
        cvtmesh.mesh("square_hole", size=lambda xy: np.where(xy[:, 0] > 0.5, 0.0, 0.1), n=300)
    with pytest.raises(MeshError, match="size field is -1 at"):
        cvtmesh.mesh("square_hole", size=lambda xy: -np.ones(len(xy)), n=300)


def test_size_expression_with_n_keeps_the_shape_and_hits_n():
    m = cvtmesh.mesh("circle", size="0.03 + 0.12*sqrt(x^2+y^2)", n=500, tol=1e-3)
    assert len(m.points) == 500


def test_gradation_and_bounds_shape_the_size_field():
    field = "0.01 + 0.5*max(0, sqrt(x^2+y^2)-0.3)"
    limited = cvtmesh.mesh("circle", size=field, tol=1e-2)
    free = cvtmesh.mesh("circle", size=field, tol=1e-2, gradation=None)
    assert len(limited.points) > 1.05 * len(free.points)
    capped = cvtmesh.mesh("circle", size=field, tol=1e-2, size_max=0.05)
    assert len(capped.points) > len(limited.points)
    with pytest.raises(MeshError, match=r"size_min, --size-min\) 0.2 is larger than the largest"):
        cvtmesh.mesh("circle", size=0.1, size_min=0.2, size_max=0.1)


def test_distance_fields_refine_toward_a_hole_and_a_point():
    # Gmsh's Distance + Threshold toward square_hole's hole (loop 1).
    m = cvtmesh.mesh("square_hole", size_toward=["loop:1"], size_threshold=(0.02, 0.2, 0.04, 1.2))
    assert m.converged
    e, lengths = edge_lengths(m.points, m.triangles)
    mid = 0.5 * (m.points[e[:, 0]] + m.points[e[:, 1]])
    d = np.hypot(mid[:, 0], mid[:, 1]) - 0.4
    near, far = lengths[d < 0.04].mean(), lengths[d > 0.5].mean()
    assert near == pytest.approx(0.02, rel=0.2)
    assert far > 4 * near
    # With n the field's shape is kept; with size as well the smaller of the two is used.
    m = cvtmesh.mesh("circle", n=400, size_toward=["point:0,0"], size_threshold=(0.02, 0.2, 0, 1))
    assert len(m.points) == 400
    both = cvtmesh.mesh("circle", size=0.05, size_toward=["point:0,0"], size_threshold=(0.02, 0.2, 0, 1))
    alone = cvtmesh.mesh("circle", size=0.05)
    assert len(both.points) > len(alone.points)
    with pytest.raises(MeshError, match="expected loop:I"):
        cvtmesh.mesh("circle", size_toward=["corner:1"], size_threshold=(0.02, 0.2, 0, 1))
    with pytest.raises(MeshError, match="size_threshold"):
        cvtmesh.mesh("circle", size_toward=["loop:0"])
    with pytest.raises(MeshError, match="no loop 3"):
        cvtmesh.mesh("square_hole", size_toward=["loop:3"], size_threshold=(0.02, 0.2, 0, 1))
    # One piece: square_hole's piece 0 is the side y = -1, a wall with a boundary layer.
    pieces = cvtmesh.Region.builtin("square_hole").pieces
    assert [(p["piece"], p["loop"], p["kind"]) for p in pieces] == [
        (0, 0, "line"), (1, 0, "line"), (2, 0, "line"), (3, 0, "line"), (4, 1, "circle")
    ]
    assert pieces[0]["start"] == (-1.0, -1.0) and pieces[0]["end"] == (1.0, -1.0)
    assert pieces[4]["length"] == pytest.approx(2 * math.pi * 0.4)
    wall = cvtmesh.mesh("square_hole", size_toward=["piece:0"], size_threshold=(0.02, 0.2, 0, 1))
    e, lengths = edge_lengths(wall.points, wall.triangles)
    y = 0.5 * (wall.points[e[:, 0], 1] + wall.points[e[:, 1], 1])
    assert lengths[y > 0.8].mean() > 4 * lengths[y < -0.95].mean()
    with pytest.raises(MeshError, match="no piece 5"):
        cvtmesh.mesh("square_hole", size_toward=["piece:5"], size_threshold=(0.02, 0.2, 0, 1))


def min_angles(points, triangles):
    p = points[triangles]
    angles = []
    for i in range(3):
        u = p[:, (i + 1) % 3] - p[:, i]
        v = p[:, (i + 2) % 3] - p[:, i]
        cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        angles.append(np.degrees(np.arctan2(cross, (u * v).sum(axis=1))))
    return np.min(angles, axis=0)


def test_polish_raises_the_smallest_angle_and_keeps_the_boundary_on_the_boundary():
    kw = dict(size_toward=["loop:1"], size_threshold=(0.02, 0.1, 0.02, 0.6))
    raw = cvtmesh.mesh("square_hole", polish=0, **kw)
    done = cvtmesh.mesh("square_hole", **kw)
    assert not any(n.startswith("polish") for n in raw.notes)
    assert any(n.startswith("polish") for n in done.notes)
    before, after = min_angles(raw.points, raw.triangles), min_angles(done.points, done.triangles)
    assert before.min() < 40 and after.min() > before.min() + 0.5
    np.testing.assert_array_equal(raw.triangles, done.triangles)
    moved = np.any(raw.points != done.points, axis=1)
    assert 0 < moved.sum() < 0.05 * len(moved)
    # Boundary vertices slide along their side of the square or around the hole.
    b = done.points[np.unique(np.asarray(done.boundary_edges).ravel())]
    on_square = np.isclose(np.abs(b).max(axis=1), 1.0, atol=1e-12)
    on_hole = np.isclose(np.hypot(b[:, 0], b[:, 1]), 0.4, atol=1e-12)
    assert (on_square | on_hole).all()


def test_constant_size_gives_the_lattice_count():
    m = cvtmesh.mesh("square_hole", size=0.1, tol=1e-3)
    area = Region.builtin("square_hole").area
    assert len(m.points) == round(2 * area / (math.sqrt(3) * 0.01))


def test_progress_is_called_and_can_stop_the_run():
    seen = []
    cvtmesh.mesh("circle", n=88, progress=lambda it, e, mv: seen.append((it, e, mv)))
    assert len(seen) > 3 and seen[0][0] == 1

    calls = []

    def stop(it, e, mv):
        calls.append(it)
        if it == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        cvtmesh.mesh("circle", n=2000, progress=stop)
    # The run stopped at the call that raised: no iteration was reported after it.
    assert calls[-1] == 3 and calls.count(3) == 1


def test_ctrl_c_stops_a_long_mesh():
    import os
    import signal
    import time

    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signals reach the main thread only")
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            cvtmesh.mesh("lake", n=400_000)
    finally:
        timer.cancel()
    # Stopped at the next report, long before the mesh would be done.
    assert time.monotonic() - start < 10


def test_threads_mesh_in_parallel_with_the_same_results():
    seeds = (1, 2, 1)
    out = {}

    def run(i):
        out[i] = cvtmesh.mesh("annulus", n=303, seed=seeds[i]).points.tobytes()

    threads = [threading.Thread(target=run, args=(i,)) for i in range(len(seeds))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    # Every run, in parallel, gives the bytes of the same seed run alone.
    for i, seed in enumerate(seeds):
        assert out[i] == cvtmesh.mesh("annulus", n=303, seed=seed).points.tobytes(), i
    assert out[0] != out[1]


@pytest.mark.parametrize(
    "kwargs, words",
    [
        (dict(region="nowhere/region.poly", n=100), "nowhere/region.poly"),
        (dict(region="no_such_region", n=100), "unknown region"),
        (dict(region="circle", n=100, method="lloyd"), "unknown method"),
        (dict(region="circle"), "give n"),
        (dict(region="circle", size="x"), "positive and finite"),
        (dict(region="circle", size="0.1 +"), "unexpected end of expression"),
        (dict(region="circle", size=lambda xy: np.full(len(xy), np.nan)), "positive and finite"),
        (dict(region="circle", size=1e-9), "more than cvtmesh meshes"),
        (dict(region="circle", n=100, density="-1"), "non-negative"),
        (dict(region="circle", n=100, size=0.1, density="1"), "not both"),
        (dict(region="square_hole", n=3), "at least 7 vertices"),
        (dict(region=[[0, 0], [1, 1], [1, 0], [0, 1]], n=50), "crosses itself at (0.5, 0.5)"),
        (dict(region=[[0, 0], [1, 0], [float("nan"), 1]], n=50), "non-finite"),
        (dict(region=[0, 1, 2], n=50), "shape"),
        (dict(region="circle", n=100, corner_angle=200), "corner_angle"),
        (dict(region="circle", n=100, simplify="coarse"), 'got "coarse"'),
        (dict(region="circle", n=100, simplify=-1.0), "simplify must be a positive number"),
        (dict(region="circle", n=100, time_limit=-1.0), "time_limit"),
        (dict(region="circle", n=100, time_limit=float("nan")), "time_limit"),
        (dict(region="circle", n=100, polish=75.0), "polish threshold (polish,"),
        (dict(region="circle", n=100, polish=float("nan")), "polish threshold"),
        (dict(region="circle", n=100, tol=0.0), "tolerance (tol,"),
        (dict(region="circle", n=100, max_iter=0), "(max_iter,"),
        (dict(region="circle", n=-5), "n must be a number of vertices, a positive integer"),
        (dict(region="circle", n=-5), "got -5"),
        (dict(region="circle", n=2**70), "got 1180591620717411303424"),
        (dict(region="circle", n=100, seed=-1), "seed must be an integer from 0 to 2**64 - 1"),
        (dict(region="circle", n=100, seed=2**64), "got 18446744073709551616"),
        (dict(region="circle", n=100, seed=-1), "got -1"),
        (dict(region="circle", n=100, max_iter=-1), "max_iter must be an iteration cap, a positive"),
        (dict(region="circle", n=100, max_iter=np.int64(-3)), "got -3"),
        (dict(region="circle", size=-0.1), "size is -0.1"),
        (dict(region="circle", size=True), "not a bool"),
        (
            dict(region=SQUARE, size_toward=["loop:0"], size_threshold=(1e-5, 0.1, 0, 0.5)),
            "vertices along the boundary alone",
        ),
        (dict(region="circle", size="min(0.1)"), "2 or more arguments"),
        (dict(region="circle", n=100, size=-1), "size is -1"),
        (dict(region=SQUARE, n=100, holes=np.array([[0.5, 0.5]])), "not by a point inside it"),
        (dict(region=SQUARE, n=100, holes=[(0.5, 0.5)]), "not by a point inside it"),
        (dict(region=SQUARE, n=100, holes=[np.zeros((3, 3))]), "hole 0 must be an array of shape (n, 2), got (3, 3)"),
        (dict(region="square_hole", n=3), "(corner_angle,"),
    ],
)
@pytest.mark.filterwarnings("ignore:size field.*background grid:RuntimeWarning")
def test_bad_input_raises_mesh_error_naming_the_problem(kwargs, words):
    region = kwargs.pop("region")
    with pytest.raises(MeshError) as e:
        cvtmesh.mesh(region, **kwargs)
    assert words in str(e.value)
    assert isinstance(e.value, ValueError)


def test_write_every_format_and_read_back(tmp_path):
    m = cvtmesh.mesh(SQUARE, holes=[HOLE], n=200)
    for ext in ["node", "msh", "vtu", "obj"]:
        path = tmp_path / f"mesh.{ext}"
        m.write(path)
        assert path.stat().st_size > 0
    back = cvtmesh.Mesh.read(tmp_path / "mesh.msh")
    np.testing.assert_allclose(back.points, m.points, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(back.triangles, m.triangles)
    with pytest.raises(MeshError):
        m.write(tmp_path / "mesh.xyz")
    assert not (tmp_path / "mesh.xyz").exists()


def test_region_api():
    r = Region.from_loops(SQUARE, [HOLE], name="sq")
    assert r.name == "sq" and r.area == pytest.approx(0.96)
    assert r.corners.shape == (8, 2)
    rings = r.polygonize(1e-3)
    assert len(rings) == 2 and rings[0].shape[1] == 2
    d = r.signed_distance(np.array([[0.5, 0.1], [0.5, 0.5], [2.0, 0.5]]))
    assert d[0] == pytest.approx(-0.1) and d[1] > 0 and d[2] == pytest.approx(1.0)
    lake = Region.builtin("lake")
    # Only the vertices where the shore turns by more than 60 degrees stay corners.
    assert len(lake.with_corner_angle(60).corners) < len(lake.corners) / 2
    assert len(lake.with_corner_angle(0).corners) == len(lake.corners)


def test_to_meshio_names_each_boundary_loop_and_piece(tmp_path):
    meshio = pytest.importorskip("meshio")
    m = cvtmesh.mesh(SQUARE, holes=[HOLE], n=200)
    mm = m.to_meshio()
    assert isinstance(mm, meshio.Mesh)
    assert mm.cells_dict["triangle"].shape == m.triangles.shape
    # The line blocks, concatenated, are the boundary edges; cell sets index them so.
    np.testing.assert_array_equal(mm.cells_dict["line"], m.boundary_edges)
    assert set(mm.cell_sets) >= {"boundary_0", "boundary_1", "domain"}
    hole_edges = mm.cell_sets_dict["boundary_1"]["line"]
    assert (m.boundary_loop[hole_edges] == 1).all()
    # And each piece (wall): the square's four sides and the hole's four, each edge on its own.
    pieces = m.boundary_pieces()
    assert pieces.shape == (len(m.boundary_edges),)
    assert set(np.unique(pieces)) == set(range(8))
    sides = {p["piece"]: p for p in Region.from_loops(SQUARE, [HOLE]).pieces}
    for j in range(8):
        edges = mm.cell_sets_dict[f"piece_{j}"]["line"]
        assert (pieces[edges] == j).all() and len(edges) > 0
        a, b = np.array(sides[j]["start"]), np.array(sides[j]["end"])
        ends = m.points[m.boundary_edges[edges].ravel()]
        # Every end on the segment a-b.
        t = np.clip(((ends - a) @ (b - a)) / ((b - a) @ (b - a)), 0.0, 1.0)
        assert np.abs(a + t[:, None] * (b - a) - ends).max() < 1e-9
    # The .msh file names the same walls as physical curves "piece0", ... for any Gmsh reader.
    m.write(tmp_path / "m.msh")
    back = meshio.read(tmp_path / "m.msh")
    line_block = [k for k, c in enumerate(back.cells) if c.type == "line"]
    for j in range(8):
        in_file = sum(len(back.cell_sets[f"piece{j}"][k]) for k in line_block)
        assert in_file == len(mm.cell_sets_dict[f"piece_{j}"]["line"])
    # A mesh read from a file needs the region for its pieces, and to_meshio takes it too.
    read = cvtmesh.Mesh.read(tmp_path / "m.msh")
    with pytest.raises(MeshError, match="pass the region"):
        read.boundary_pieces()
    assert not any(k.startswith("piece_") for k in read.to_meshio().cell_sets)
    again = read.to_meshio(region=Region.from_loops(SQUARE, [HOLE]))
    for j in range(8):
        assert len(again.cell_sets_dict[f"piece_{j}"]["line"]) == len(
            mm.cell_sets_dict[f"piece_{j}"]["line"]
        )
    # Against a region the mesh does not mesh, pieces and boundary nodes would mean nothing.
    for ask in (read.boundary_pieces, m.boundary_pieces, m.quadratic):
        with pytest.raises(MeshError, match="does not conform to region 'lake'"):
            ask(region=Region.builtin("lake"))


MARKED_CHANNEL = (
    "6 2 0 0\n1 0 0\n2 1.5 0\n3 2.5 0\n4 4 0\n5 4 1\n6 0 1\n"
    "6 1\n1 1 2 1\n2 2 3 4\n3 3 4 1\n4 4 5 3\n5 5 6 1\n6 6 1 2\n0\n"
)


def test_a_poly_s_segment_markers_name_the_walls(tmp_path):
    # A 4 x 1 channel: walls 1, inlet 2, outlet 3, a heated strip 4 on the bottom wall.
    path = tmp_path / "channel.poly"
    path.write_text(MARKED_CHANNEL)
    region = Region.load(str(path))
    assert sorted(region.piece_markers) == [1, 1, 1, 2, 3, 4]
    assert {p["marker"] for p in region.pieces if p["start"] == (1.5, 0.0)} == {4}
    m = cvtmesh.mesh(region, n=600)
    markers = m.boundary_markers()
    assert markers.shape == (len(m.boundary_edges),)
    ends = m.points[m.boundary_edges]
    strip = ends[markers == 4]
    assert (strip[:, :, 1] == 0.0).all()
    # The strip's edges cover exactly [1.5, 2.5]: its ends are mesh vertices.
    assert np.abs(strip[:, 1, 0] - strip[:, 0, 0]).sum() == pytest.approx(1.0, abs=1e-12)
    assert (ends[markers == 2][:, :, 0] == 0.0).all()
    assert (ends[markers == 3][:, :, 0] == 4.0).all()
    meshio = pytest.importorskip("meshio")
    mm = m.to_meshio()
    for k in (1, 2, 3, 4):
        assert (markers[mm.cell_sets_dict[f"marker_{k}"]["line"]] == k).all()
    # The same numbers as cell data, which files keep where they drop cell sets (VTU here).
    assert (mm.cell_data_dict["marker"]["line"] == markers).all()
    assert not mm.cell_data_dict["marker"]["triangle"].any()
    mm.write(tmp_path / "m.vtu")
    back = meshio.read(tmp_path / "m.vtu")
    assert (back.cell_data_dict["marker"]["line"] == markers).all()
    # A region that numbers no walls says so.
    with pytest.raises(MeshError, match="numbers no walls"):
        cvtmesh.mesh("circle", n=100).boundary_markers()
    assert Region.builtin("circle").piece_markers is None


def test_a_solver_s_mesh_meshed_again_keeps_its_boundary_conditions(tmp_path):
    # A channel meshed with walls numbered, written, read back by meshio as a solver would
    # hold it: triangles, boundary lines and their physical tags.
    meshio = pytest.importorskip("meshio")
    path = tmp_path / "channel.poly"
    path.write_text(MARKED_CHANNEL)
    old = cvtmesh.mesh(Region.load(str(path)), n=600)
    xy, tri = old.points, old.triangles
    lines, tags = old.boundary_edges, old.boundary_markers()
    region = Region.from_triangles(xy, tri, walls=(lines, tags))
    # The old mesh's boundary is the channel's: six straight pieces, with their markers.
    assert sorted(region.piece_markers) == [1, 1, 1, 2, 3, 4]
    new = cvtmesh.mesh(region, n=1500)
    assert new.converged
    markers = new.boundary_markers()
    strip = new.points[new.boundary_edges[markers == 4]]
    assert np.abs(strip[:, 1, 0] - strip[:, 0, 0]).sum() == pytest.approx(1.0, abs=1e-12)
    # Through a file as well: Region.load of a .msh takes its physical curves.
    old.write(tmp_path / "old.msh")
    assert sorted(Region.load(str(tmp_path / "old.msh")).piece_markers) == [1, 1, 1, 2, 3, 4]
    back = meshio.read(tmp_path / "old.msh")
    assert "marker4" in back.cell_sets
    # meshio's one tag per line is the wall's number, as a Gmsh user's file has it.
    lines = back.cells_dict["line"]
    tags = back.cell_data_dict["gmsh:physical"]["line"]
    assert set(np.unique(tags)) == {1, 2, 3, 4}
    strip = back.points[lines[tags == 4]][:, :, :2]
    assert np.abs(strip[:, 1, 0] - strip[:, 0, 0]).sum() == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(MeshError, match="walls"):
        Region.from_triangles(xy, tri, walls=(lines, tags[:-1]))
    with pytest.raises(MeshError, match="not one of the"):
        Region.from_triangles(xy, tri, walls=(lines + len(xy), tags))


PINNED_CHANNEL = (
    "6 2 0 1\n1 0 0 1\n2 1.5 0 7\n3 2.5 0 1\n4 4 0 1\n5 4 1 1\n6 0 1 1\n"
    "6 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 5 3\n5 5 6 1\n6 6 1 2\n0\n"
)


def test_a_vertex_marked_on_its_own_is_a_vertex_of_every_mesh(tmp_path):
    # The channel's vertex (1.5, 0) marks itself 7 on a wall marked 1: a point where a solver
    # pins a value. Vertex (2.5, 0) is marked as its wall and pins nothing.
    meshio = pytest.importorskip("meshio")
    path = tmp_path / "pinned.poly"
    path.write_text(PINNED_CHANNEL)
    region = Region.load(str(path))
    assert region.vertex_markers == [((1.5, 0.0), 7)]
    m = cvtmesh.mesh(region, n=400)
    marks = m.vertex_markers()
    assert marks.shape == (len(m.points),)
    # The mesh's own markers and the ones projected onto the region handed in agree.
    assert (m.vertex_markers(region) == marks).all()
    assert m.points[marks == 7].tolist() == [[1.5, 0.0]]
    # Boundary vertices carry their wall's number, interior ones 0.
    inside = region.signed_distance(m.points) < -1e-9
    assert not marks[inside].any() and set(np.unique(marks[~inside])) == {1, 2, 3, 7}
    assert (m.to_meshio().point_data["marker"] == marks).all()
    # Through a Gmsh file read by meshio: the physical point is a vertex cell tagged 7, and
    # handing it back as `pinned` keeps the point when the mesh is meshed again.
    m.write(tmp_path / "m.msh")
    back = meshio.read(tmp_path / "m.msh")
    vertex = back.cells_dict["vertex"][:, 0]
    tags = back.cell_data_dict["gmsh:physical"]
    assert back.points[vertex, :2].tolist() == [[1.5, 0.0]] and tags["vertex"].tolist() == [7]
    again = Region.from_triangles(
        back.points[:, :2],
        back.cells_dict["triangle"],
        walls=(back.cells_dict["line"], tags["line"]),
        pinned=(vertex, tags["vertex"]),
        names={3: "outlet", 7: "probe"},
    )
    assert again.vertex_markers == [((1.5, 0.0), 7)]
    assert {p["name"] for p in again.pieces if p["marker"] == 3} == {"outlet"}
    new = cvtmesh.mesh(again, n=250)
    assert new.points[new.vertex_markers() == 7].tolist() == [[1.5, 0.0]]
    # The names reach the file: Gmsh's groups are named as the user named them.
    new.write(tmp_path / "new.msh")
    text = (tmp_path / "new.msh").read_text()
    assert '0 7 "probe"' in text and '1 3 "outlet"' in text
    with pytest.raises(MeshError, match="pinned"):
        Region.from_triangles(back.points[:, :2], back.cells_dict["triangle"], pinned=([0, 1], [7]))
    with pytest.raises(MeshError, match="numbers no walls"):
        cvtmesh.mesh("circle", n=100).vertex_markers()


def test_embedded_points_are_vertices_of_every_mesh(tmp_path):
    # A probe at (0.3, 0.1) marked 5 and a source at (-0.2, 0.4) unmarked, inside the circle.
    region = Region.builtin("circle").with_embedded_points([[0.3, 0.1], [-0.2, 0.4]], [5, 0])
    assert region.embedded_points == [((0.3, 0.1), 5), ((-0.2, 0.4), 0)]
    for method in ("ccvt", "refine", "distmesh"):
        m = cvtmesh.mesh(region, n=300, method=method)
        for (x, y), _ in region.embedded_points:
            assert ((m.points[:, 0] == x) & (m.points[:, 1] == y)).sum() == 1, method
        marks = m.vertex_markers()
        assert m.points[marks == 5].tolist() == [[0.3, 0.1]], method
        assert (m.vertex_markers(region) == marks).all(), method
    with pytest.raises(MeshError, match="embeds 2 points"):
        cvtmesh.mesh(region, n=300, method="meshgen")
    with pytest.raises(MeshError, match="outside the region"):
        region.with_embedded_points([[1.5, 0.0]])
    with pytest.raises(MeshError, match="one marker per point"):
        region.with_embedded_points([[0.0, 0.0]], [1, 2])
    # A .poly's vertices on no segment are embedded points.
    path = tmp_path / "probe.poly"
    path.write_text(PINNED_CHANNEL.replace("6 2 0 1", "7 2 0 1", 1).replace(
        "6 0 1 1\n", "6 0 1 1\n7 1 0.5 9\n", 1))
    assert Region.load(str(path)).embedded_points == [((1.0, 0.5), 9)]


INTERFACE_POLY = """# a unit square of two materials: an interface x = 0.5 from wall to wall, marked 7
6 2 0 1
1 0 0 1
2 1 0 1
3 1 1 1
4 0 1 1
5 0.5 0 0
6 0.5 1 0
7 1
1 1 5 1
2 5 2 1
3 2 3 1
4 3 6 1
5 6 4 1
6 4 1 1
7 5 6 7
0
"""


def test_an_interface_and_an_inclusion_are_followed_by_edges(tmp_path):
    # An interface read from a .poly, as Triangle users write one, and a circular inclusion
    # (a closed polygon) added from arrays.
    path = tmp_path / "two.poly"
    path.write_text(INTERFACE_POLY)
    region = Region.load(str(path))
    ((pts, marker),) = region.embedded_lines
    assert marker == 7 and pts.tolist() == [[0.5, 0.0], [0.5, 1.0]]
    t = np.linspace(0.0, 2.0 * np.pi, 41)
    ring = np.c_[0.75 + 0.1 * np.cos(t), 0.5 + 0.1 * np.sin(t)]
    ring[-1] = ring[0]
    region = region.with_embedded_lines([ring], markers=[8])
    for method in ("ccvt", "refine", "distmesh"):
        m = cvtmesh.mesh(region, n=1500, method=method, seed=2)
        edges, markers = m.line_edges()
        seg = m.points[edges]
        length = np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1)
        assert set(markers.tolist()) == {7, 8}, method
        assert abs(length[markers == 7].sum() - 1.0) < 1e-12, method
        polygon = np.linalg.norm(np.diff(ring, axis=0), axis=1).sum()
        assert abs(length[markers == 8].sum() - polygon) < 1e-12, method
        # No triangle straddles the interface: the left triangles tile half the square.
        tri = m.points[m.triangles]
        c = tri.mean(axis=1)
        u, v = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
        area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        assert abs(area[c[:, 0] < 0.5].sum() - 0.5) < 1e-12, method
        # Triangle's files list the interface as segments with its marker; Gmsh's as lines
        # in the physical curve 7.
        m.write(str(tmp_path / f"{method}.poly"))
        poly = (tmp_path / f"{method}.poly").read_text()
        assert poly.count(" 7\n") >= len(edges[markers == 7]), method
        m.write(str(tmp_path / f"{method}.msh"))
        assert '1 7 "marker7"' in (tmp_path / f"{method}.msh").read_text()
    # meshio gets the lines as a block per marker, in the cell set and physical group of the
    # marker, which a Gmsh file written by meshio carries back.
    m = cvtmesh.mesh(region, n=1500)
    edges, markers = m.line_edges()
    mm = m.to_meshio()
    assert sum(len(b) for b in mm.cell_sets["marker_8"]) == (markers == 8).sum()
    path = tmp_path / "meshio.msh"
    mm.write(str(path), file_format="gmsh22", binary=False)
    back = cvtmesh.Mesh.read(str(path))
    again_edges, again_markers = back.line_edges(region)
    assert sorted(again_markers.tolist()) == sorted(markers.tolist())
    with pytest.raises(MeshError, match="embeds 2 lines"):
        cvtmesh.mesh(region, n=1500, method="vtm")
    with pytest.raises(MeshError, match="leaves the region|outside the region"):
        region.with_embedded_lines([[[0.2, 0.2], [1.5, 0.2]]])
    # Lines that cross, each other, the interface or themselves, are split there, as Triangle
    # splits crossing segments; a line whose vertex touches its own segment is refused.
    crossed = region.with_embedded_lines(
        [[[0.2, 0.2], [0.4, 0.4]], [[0.2, 0.4], [0.4, 0.2]], [[0.4, 0.1], [0.6, 0.1]]]
    )
    lines = [pts.tolist() for pts, _ in crossed.embedded_lines]
    assert lines[0] == [[0.5, 0.0], [0.5, 0.1], [0.5, 1.0]]
    assert lines[2][1] == lines[3][1] and np.allclose(lines[2][1], [0.3, 0.3])
    assert lines[4] == [[0.4, 0.1], [0.5, 0.1], [0.6, 0.1]]
    m = cvtmesh.mesh(crossed, n=1500)
    assert (np.abs(m.points - [0.3, 0.3]).max(axis=1) < 1e-15).sum() == 1
    bow = region.with_embedded_lines([[[0.2, 0.2], [0.4, 0.4], [0.4, 0.2], [0.2, 0.4]]])
    pts = bow.embedded_lines[2][0]
    assert len(pts) == 6 and (pts[1] == pts[4]).all() and np.allclose(pts[1], [0.3, 0.3])
    with pytest.raises(MeshError, match=r"touches or runs along itself at \(0\.3"):
        region.with_embedded_lines([[[0.2, 0.3], [0.4, 0.3], [0.4, 0.4], [0.3, 0.3], [0.3, 0.45]]])
    with pytest.raises(MeshError, match="one marker per line"):
        region.with_embedded_lines([[[0.2, 0.2], [0.3, 0.3]]], markers=[1, 2])


def test_boundary_edges_lie_on_the_boundary_and_close_each_loop():
    region = Region.builtin("annulus")
    m = cvtmesh.mesh(region, n=303)
    ends = m.points[m.boundary_edges.ravel()]
    # Vertices on ∂Ω (to rounding); the chord between two lies within the chord error inside.
    assert np.abs(region.signed_distance(ends)).max() < 1e-9
    # Each edge is a chord of ∂Ω: its midpoint is off ∂Ω by the sagitta, a small fraction of
    # the edge's length on the annulus's circles.
    seg = m.points[m.boundary_edges]
    length = np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1)
    assert (np.abs(region.signed_distance(seg.mean(axis=1))) < 0.1 * length).all()
    for k in np.unique(m.boundary_loop):
        e = m.boundary_edges[m.boundary_loop == k]
        # Every vertex of a loop starts exactly one edge and ends exactly one, and following
        # the edges from one of them visits all before it comes back: one closed chain.
        nxt = dict(zip(e[:, 0].tolist(), e[:, 1].tolist()))
        assert len(nxt) == len(e) and sorted(nxt) == sorted(e[:, 1].tolist())
        start = e[0, 0]
        v, steps = nxt[start], 1
        while v != start:
            v, steps = nxt[v], steps + 1
        assert steps == len(e)


def _cli():
    """The ``cvtmesh`` command the package installed beside this Python."""
    exe = Path(sys.executable).parent / ("cvtmesh.exe" if sys.platform == "win32" else "cvtmesh")
    assert exe.exists(), f"the package installed no cvtmesh command at {exe}"
    return exe


def test_the_installed_command_gives_the_librarys_mesh_for_the_same_seed(tmp_path):
    out = tmp_path / "c.node"
    run = subprocess.run(
        [str(_cli()), "mesh", "circle", "-n", "300", "--seed", "7", "--quiet", "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    back = cvtmesh.Mesh.read(out)
    own = cvtmesh.mesh("circle", n=300, seed=7)
    assert back.points.shape == (300, 2)
    assert triangle_set(back.points, back.triangles) == triangle_set(own.points, own.triangles)
    # python -m cvtmesh is the same command.
    again = tmp_path / "again.node"
    run = subprocess.run(
        [sys.executable, "-m", "cvtmesh", "mesh", "circle", "-n", "300", "--seed", "7", "-q", "-o", str(again)],
        capture_output=True,
    )
    assert run.returncode == 0, run.stderr
    assert again.read_bytes() == out.read_bytes()
    assert again.with_suffix(".ele").read_bytes() == out.with_suffix(".ele").read_bytes()


def test_the_installed_command_names_bad_input_and_exits_non_zero(tmp_path):
    out = tmp_path / "x.msh"
    run = subprocess.run(
        [str(_cli()), "mesh", "no_such_region", "-n", "100", "-o", str(out)], capture_output=True, text=True
    )
    assert run.returncode == 1
    assert "unknown region 'no_such_region'" in run.stderr
    assert not out.exists()
    run = subprocess.run([str(_cli()), "mesh", "circle", "--no-such-option"], capture_output=True, text=True)
    assert run.returncode == 2 and "--no-such-option" in run.stderr
    run = subprocess.run([str(_cli()), "--version"], capture_output=True, text=True)
    assert run.returncode == 0 and run.stdout.split() == ["cvtmesh", cvtmesh.__version__]
    # Its output goes through a pipe like any command's.
    listing = subprocess.run(f"'{_cli()}' regions | head -1", shell=True, capture_output=True, text=True)
    assert listing.returncode == 0 and listing.stderr == "" and listing.stdout.startswith("name")


def test_measures_equal_the_command_lines_on_the_same_mesh(tmp_path):
    exe = _cli()
    m = cvtmesh.mesh("lake", n=1109)
    m.write(tmp_path / "lake.node")
    out = subprocess.run(
        [str(exe), "measure", str(tmp_path / "lake.node"), "--region", "lake", "--csv"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip().splitlines()
    header, values = out[0].split(","), out[1].split(",")
    cli = dict(zip(header, values))
    own = m.measures()
    compared = 0
    for name, value in own.items():
        if name in cli:
            assert float(cli[name]) == pytest.approx(value, rel=1e-9, abs=1e-12), name
            compared += 1
    assert compared >= 12, (header, sorted(own))


def test_meshio_reads_back_what_write_writes(tmp_path):
    meshio = pytest.importorskip("meshio")
    m = cvtmesh.mesh(SQUARE, holes=[HOLE], n=300)
    for ext in ["msh", "vtu"]:
        path = tmp_path / f"m.{ext}"
        m.write(path)
        back = meshio.read(path)
        # The same triangles, whatever order the file lists its nodes in.
        assert triangle_set(back.points[:, :2], back.cells_dict["triangle"]) == triangle_set(
            m.points, m.triangles
        )
    # The meshio object we build round-trips through meshio's own writer too.
    mm = m.to_meshio()
    mm.write(tmp_path / "via_meshio.vtu")
    again = meshio.read(tmp_path / "via_meshio.vtu")
    assert triangle_set(again.points[:, :2], again.cells_dict["triangle"]) == triangle_set(
        m.points, m.triangles
    )


def test_pictures_are_written_with_and_without_the_region(tmp_path):
    m = cvtmesh.mesh("horn", n=138)
    m.write(tmp_path / "horn.png")
    assert (tmp_path / "horn.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    m.write(tmp_path / "horn.svg")
    assert (tmp_path / "horn.svg").read_text().lstrip().startswith("<")
    m.write(tmp_path / "horn.node")
    read = cvtmesh.Mesh.read(tmp_path / "horn.node")
    read.write(tmp_path / "alone.png")
    assert (tmp_path / "alone.png").stat().st_size > 1000
    # Without a region, as `cvtmesh measure` does: the region its triangles cover, whose
    # boundary is the mesh's own.
    own = read.measures()
    assert own["K"] == 138
    horn = read.measures(Region.builtin("horn"))
    assert horn["K"] == 138 and horn["Ktilde"] == own["Ktilde"]


def test_every_part_of_a_multipolygon_is_meshed(tmp_path):
    path = tmp_path / "two.geojson"
    path.write_text(
        '{"type":"MultiPolygon","coordinates":[[[[0,0],[1,0],[1,1],[0,1],[0,0]]],'
        '[[[2,0],[4,0],[4,1],[2,1],[2,0]],[[2.5,0.25],[2.5,0.75],[3,0.75],[3,0.25],[2.5,0.25]]]]}'
    )
    r = Region.from_file(str(path))
    assert r.num_parts == 2
    m = cvtmesh.mesh(str(path), n=1000)
    p, t = m.points, m.triangles
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    areas = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    assert areas.sum() == pytest.approx(2.75, rel=1e-9)
    # Vertices in proportion to area: 1 / 2.75 of them in the unit square.
    assert (p[:, 0] <= 1.0 + 1e-9).sum() == 364
    assert set(np.unique(m.boundary_loop)) == {0, 1, 2}
    assert m.converged


def test_a_coastline_keeps_only_its_real_corners():
    t = np.linspace(0, 2 * np.pi, 3000, endpoint=False)
    r = 1 + 0.05 * np.sin(7 * t) + 0.003 * np.sin(53 * t)
    coast = np.column_stack([r * np.cos(t), r * np.sin(t)])
    assert len(Region.from_loops(coast).corners) == 3000
    assert len(Region.from_loops(coast).with_default_corners().corners) == 0
    m = cvtmesh.mesh(coast, n=300)
    assert len(m.points) == 300
    with pytest.raises(MeshError, match="at least 3000"):
        cvtmesh.mesh(coast, n=300, corner_angle=0)
    # Simplified to the mesh's scale, the vertices left may all be corners.
    m = cvtmesh.mesh(coast, n=300, corner_angle=0, simplify="auto")
    assert len(m.points) == 300
    assert m.notes[0].startswith("boundary: simplified from 3000 to ")
    given = Region.from_loops(coast)
    simple, deviation = given.simplified(0.01)
    assert 0 < deviation <= 0.01
    assert len(simple.corners) == 0  # smooth at this scale: the default corner angle applies
    assert 3 <= len(simple.polygonize(1e-9)[0]) < 300
    m = cvtmesh.mesh(simple, n=300)
    assert (given.signed_distance(m.points) <= deviation * (1 + 1e-9)).all()


def test_a_time_limit_returns_the_mesh_reached_not_converged():
    m = cvtmesh.mesh("lake", n=3000, time_limit=0)
    assert not m.converged and m.iterations <= 2
    assert "stopped at the time limit before converging" in m.notes
    assert len(m.points) == 3000
    # A limit beyond any clock is none.
    assert cvtmesh.mesh("circle", n=100, time_limit=1e308).converged


def test_a_channel_thinner_than_the_spacing_warns_with_the_k_that_resolves_it():
    channel = np.array([[0, 0], [10, 0], [10, 0.001], [0, 0.001]], dtype=float)
    with pytest.warns(RuntimeWarning, match=r"1\.000e-3 wide near .*K ≥ 11\d{3} .*one edge across"):
        cvtmesh.mesh(channel, n=300)


def test_a_size_field_finer_than_its_background_grid_warns_where():
    # A point source asking for 1e-5 on the unit circle: the grid's step is about 2e-3.
    kw = dict(n=500, max_iter=1, polish=0, size_toward=["point:0.3,0.2"])
    with pytest.warns(RuntimeWarning, match=r"near \(0\.30\d*, 0\.20\d*\) it grows from .* over one step"):
        cvtmesh.mesh("circle", size_threshold=(1e-5, 0.1, 0, 1), **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cvtmesh.mesh("circle", size_threshold=(1e-2, 0.1, 0, 1), **kw)


def test_slivers_are_named_in_a_warning():
    # 0.51 spacings wide at n = 300: DistMesh puts every point on one side and fans across.
    strip = np.array([[0, 0], [1000, 0], [1000, 1], [0, 1]], dtype=float)
    with pytest.warns(RuntimeWarning, match=r"triangles have an angle under 1° \(the smallest"):
        cvtmesh.mesh(strip, n=300, method="distmesh")


def test_a_near_miss_of_two_fractures_names_refine_which_leaves_no_sliver():
    # A fracture stopping a ten-thousandth short of another: the CVT's points along both
    # leave slivers there; Delaunay refinement splits the lines and keeps its 20° bound.
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    lines = [np.array([[0.1, 0.5], [0.9, 0.5]]), np.array([[0.5, 0.5001], [0.55, 0.9]])]
    region = cvtmesh.Region.from_loops(square).with_embedded_lines(lines)
    with pytest.warns(RuntimeWarning, match=r"under 1° .* the refine method"):
        cvtmesh.mesh(region, n=1000)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = cvtmesh.mesh(region, n=1000, method="refine")
    edges, _ = m.line_edges()
    assert len(edges) > 0 and min_angles(m.points, m.triangles).min() >= 20.0


def test_fractures_from_a_larger_box_are_clipped_to_the_region():
    # Fractures drawn in [-1, 2]² and clipped to the unit square keep their parts inside,
    # which every mesh follows; without clip a fracture leaving the square is refused.
    rng = np.random.default_rng(3)
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    lines = [rng.uniform(-1, 2, (2, 2)) for _ in range(30)]
    region = cvtmesh.Region.from_loops(square)
    with pytest.raises(cvtmesh.MeshError, match="outside the region"):
        region.with_embedded_lines(lines)
    clipped = region.with_embedded_lines(lines, markers=list(range(1, 31)), clip=True)
    kept = clipped.embedded_lines
    assert 0 < len(kept) and all(((p >= -1e-12) & (p <= 1 + 1e-12)).all() for p, _ in kept)
    m = cvtmesh.mesh(clipped, n=2000, method="refine")
    edges, _ = m.line_edges()
    along = np.linalg.norm(m.points[edges[:, 0]] - m.points[edges[:, 1]], axis=1).sum()
    total = sum(np.linalg.norm(np.diff(p, axis=0), axis=1).sum() for p, _ in kept)
    assert abs(along - total) < 1e-9


def test_regions_of_several_parts_from_arrays_mesh_every_part():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    frame = np.array([[2, 0], [4, 0], [4, 2], [2, 2]], float)
    hole = np.array([[2.5, 0.5], [2.5, 1.5], [3.5, 1.5], [3.5, 0.5]], float)
    r = Region.from_parts([(square, []), (frame, [hole])], name="two")
    assert r.num_parts == 2
    assert r.area == pytest.approx(1 + 4 - 1)
    m = cvtmesh.mesh(r, n=400)
    assert len(m.points) == 400
    # Vertices are shared by area: a quarter in the unit square.
    in_square = np.count_nonzero(m.points[:, 0] <= 1 + 1e-12)
    assert abs(in_square - 100) <= 2
    with pytest.raises(MeshError, match="at least one"):
        Region.from_parts([])


def test_a_mesh_that_leaves_out_part_of_the_region_warns(tmp_path):
    # A ring 0.01 wide: Algorithm 1 at n = 300 keeps too few vertices on the outer circle.
    ring = tmp_path / "ring.json"
    ring.write_text(
        '{"loops": [{"role": "outer", "segments": [{"kind": "circle", "center": [0, 0], "radius": 1.0}]},'
        ' {"role": "hole", "segments": [{"kind": "circle", "center": [0, 0], "radius": 0.99}]}]}'
    )

    def warned(**kw):
        with pytest.warns(RuntimeWarning) as caught:
            m = cvtmesh.mesh(Region.from_file(str(ring)), n=300, method="ccvt1", **kw)
        return m, [str(w.message) for w in caught]

    _, said = warned(polish=0)
    assert any("the mesh covers 82.6 % of the region's area" in w for w in said), said
    # Its chords are slivers too, and both are named.
    assert any("triangles have an angle under 1°" in w for w in said), said
    # The polish does not hide them: the bounds on the mesh's worst triangles and cells refuse
    # sliding the outer circle's vertices apart.
    m, said = warned()
    assert any(n.startswith("polish") for n in m.notes)
    assert any("the mesh covers 83.2 % of the region's area" in w for w in said), said


def test_a_mesh_read_from_a_file_can_be_polished(tmp_path):
    kw = dict(size_toward=["loop:1"], size_threshold=(0.02, 0.1, 0.02, 0.6))
    raw = cvtmesh.mesh("square_hole", polish=0, **kw)
    path = str(tmp_path / "raw.msh")
    raw.write(path)
    read = cvtmesh.Mesh.read(path)
    region = Region.builtin("square_hole")
    # Without a region, as `cvtmesh polish` does: the region its triangles cover, every
    # vertex of its boundary a corner of it, so only inner vertices move.
    own = read.polished()
    assert own.notes[-1].startswith("polish:")
    np.testing.assert_array_equal(own.triangles, read.triangles)
    assert min_angles(own.points, own.triangles).min() > min_angles(read.points, read.triangles).min()
    ends = np.unique(read.boundary_edges)
    np.testing.assert_array_equal(own.points[ends], read.points[ends])
    assert not np.array_equal(own.points, read.points)
    with pytest.raises(MeshError, match="below"):
        read.polished(region, below=90)
    done = read.polished(region)
    before = min_angles(read.points, read.triangles).min()
    after = min_angles(done.points, done.triangles).min()
    # Up to the threshold where the mesh's extreme triangles and cells allow (35.0° → 38.4°).
    assert after > before + 2.0
    np.testing.assert_array_equal(done.triangles, read.triangles)
    assert done.notes[-1].startswith("polish:")
    # Polished while meshing a graded request, the size field's extremes may move: at least as
    # far.
    made = cvtmesh.mesh("square_hole", **kw)
    assert min_angles(made.points, made.triangles).min() >= after - 1e-9


def test_a_mesh_names_the_region_its_triangles_cover(tmp_path):
    old = cvtmesh.mesh("square_hole", n=600, method="distmesh")
    old.write(tmp_path / "old.msh")
    covered = triangle_areas(old.points, old.triangles).sum()
    r = Region.load(str(tmp_path / "old.msh"))
    assert r.name == "old" and len(r.pieces) > 4
    assert r.area == pytest.approx(covered, rel=1e-12)
    # From arrays too, in any integer type and orientation (scipy's Delaunay gives int32).
    flipped = old.triangles[:, ::-1].astype(np.int32)
    same = Region.from_triangles(old.points.tolist(), flipped)
    assert same.area == pytest.approx(covered, rel=1e-12)
    # Meshed again from the file alone: every new vertex lies in the old region, and the new
    # triangles cover it up to the chords between boundary vertices where the old boundary
    # bends less than a corner (the hole's polygon).
    new = cvtmesh.mesh(tmp_path / "old.msh", n=600)
    assert new.points.shape == (600, 2)
    assert (r.signed_distance(new.points) < 1e-9).all()
    assert triangle_areas(new.points, new.triangles).sum() == pytest.approx(covered, rel=5e-3)
    # Triangles that overlap make no region.
    with pytest.raises(MeshError, match="overlap"):
        Region.from_triangles(SQUARE, [[0, 1, 2], [0, 2, 1]])
    with pytest.raises(MeshError, match=r"triangles must be an \(m, 3\) array"):
        Region.from_triangles(SQUARE, [0, 1, 2])
    # Vertex numbers as floats (as loadtxt reads them) are taken when whole, refused when not.
    whole = Region.from_triangles(SQUARE, np.array([[0, 1, 2], [0, 2, 3]], dtype=float))
    assert whole.area == pytest.approx(1.0)
    for frac in ([[0, 1, 2.5], [0, 2, 3]], [[0, 1, np.nan], [0, 2, 3]]):
        with pytest.raises(MeshError, match="whole numbers"):
            Region.from_triangles(SQUARE, np.array(frac))
        with pytest.raises(MeshError, match="whole numbers"):
            cvtmesh.measures(SQUARE, np.array(frac), "circle")


def test_quadratic_triangles_put_boundary_nodes_on_the_exact_boundary(tmp_path):
    m = cvtmesh.mesh("circle", n=300)
    pts, tri = m.quadratic()
    assert tri.shape == (len(m.triangles), 6) and tri.dtype == np.int64
    # The mesh's vertices come first and are the corners.
    assert np.array_equal(pts[:300], m.points) and np.array_equal(tri[:, :3], m.triangles)
    # One node per edge, shared by the triangles on it.
    edges = {tuple(sorted(e)) for t in m.triangles for e in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]}
    assert len(pts) == 300 + len(edges) and len(np.unique(tri[:, 3:])) == len(edges)
    # Boundary edges' nodes on the unit circle, interior ones at their edge's midpoint.
    boundary = {tuple(sorted(e)) for e in m.boundary_edges}
    for t in tri:
        for k, (a, b) in enumerate([(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]):
            node = pts[t[3 + k]]
            if tuple(sorted((a, b))) in boundary:
                assert abs(np.hypot(*node) - 1.0) < 1e-12
            else:
                assert np.allclose(node, 0.5 * (pts[a] + pts[b]), rtol=0, atol=1e-15)
    # Written as .msh and .vtu, meshio reads the same six-node triangles, node for node.
    meshio = pytest.importorskip("meshio")

    def six_node_set(points, triangles):
        return {tuple(map(tuple, np.round(points[t], 12))) for t in triangles}

    for ext in ["msh", "vtu"]:
        m.write(tmp_path / f"c.{ext}", order=2)
        back = meshio.read(tmp_path / f"c.{ext}")
        assert six_node_set(back.points[:, :2], back.cells_dict["triangle6"]) == six_node_set(pts, tri)
    # And as a meshio object: six-node triangles, three-node boundary lines whose middle node
    # is on the circle, the same cell sets.
    mm = m.to_meshio(order=2)
    assert six_node_set(mm.points[:, :2], mm.cells_dict["triangle6"]) == six_node_set(pts, tri)
    line3 = mm.cells_dict["line3"]
    assert len(line3) == len(m.boundary_edges)
    assert np.allclose(np.hypot(*mm.points[line3[:, 2], :2].T), 1.0, rtol=0, atol=1e-12)
    assert set(mm.cell_sets) == set(m.to_meshio().cell_sets)
    with pytest.raises(MeshError, match="six-node"):
        m.write(tmp_path / "c.obj", order=2)
    # Read back, the six-node file is the mesh of its corners, said in a warning.
    with pytest.warns(UserWarning, match="6-node triangles"):
        back = cvtmesh.Mesh.read(tmp_path / "c.msh")
    np.testing.assert_array_equal(back.points, m.points)
    np.testing.assert_array_equal(back.triangles, m.triangles)
    with pytest.raises(MeshError, match="order must be 1 or 2"):
        m.write(tmp_path / "c.msh", order=3)


def assert_chained(m):
    """Each loop's rows of boundary_edges: each edge starts where the last ended, and the last
    ends where the first starts."""
    loops = m.boundary_loop
    assert (np.diff(loops) >= 0).all(), "rows grouped by loop"
    for k in np.unique(loops):
        e = m.boundary_edges[loops == k]
        np.testing.assert_array_equal(e[1:, 0], e[:-1, 1], err_msg=f"loop {k}")
        assert e[-1, 1] == e[0, 0], k


def edge_set(points, edges):
    return {tuple(sorted((tuple(points[a][:2]), tuple(points[b][:2])))) for a, b in edges}


def test_boundary_edges_read_from_any_file_are_in_order_along_each_loop(tmp_path):
    region = Region.from_loops(SQUARE, [HOLE])
    m = cvtmesh.mesh(region, n=200)
    assert_chained(m)
    assert_chained(cvtmesh.mesh("annulus", n=303))
    sides = {p["piece"]: (np.array(p["start"]), np.array(p["end"])) for p in region.pieces}
    for ext in ["msh", "obj", "node"]:
        m.write(tmp_path / f"m.{ext}")
        read = cvtmesh.Mesh.read(tmp_path / f"m.{ext}")
        assert_chained(read)
        assert edge_set(read.points, read.boundary_edges) == edge_set(m.points, m.boundary_edges)
        # The pieces follow the rows: each edge lies on the side its piece names.
        for (a, b), j in zip(read.boundary_edges, read.boundary_pieces(region)):
            s0, s1 = sides[j]
            for v in (read.points[a], read.points[b]):
                (dx, dy), (ex, ey) = s1 - s0, v - s0
                assert abs(dx * ey - dy * ex) < 1e-9, (ext, j)


def test_regions_take_any_array_like_of_numbers():
    want = Region.from_loops(SQUARE, [HOLE])
    for outer, hole in [
        (SQUARE.tolist(), HOLE.tolist()),
        ((SQUARE * 10).astype(np.int32), (HOLE * 10).astype(np.int64)),
        (SQUARE.astype(np.float32), HOLE.astype(np.float32)),
    ]:
        got = Region.from_loops(outer, [hole])
        scale = 10.0 if np.asarray(outer).dtype.kind == "i" else 1.0
        assert got.area == pytest.approx(want.area * scale**2)
        parts = Region.from_parts([[outer, [hole]], (np.asarray(outer) + 3 * scale, [])])
        assert parts.num_parts == 2 and parts.area == pytest.approx(got.area + scale**2)
    # Several holes of one size as one (h, m, 2) array are several loops.
    assert Region.from_loops(SQUARE, np.array([HOLE])).area == pytest.approx(want.area)
    xy = [[-1, 0], [1, 2], [0.5, 0.1]]
    assert want.contains(xy).tolist() == [False, False, True]
    np.testing.assert_allclose(
        want.signed_distance(np.array(xy, dtype=np.int64)[:2]), want.signed_distance(np.array(xy, float)[:2])
    )
    np.testing.assert_allclose(
        want.signed_distance(np.array(xy, dtype=np.float32)), want.signed_distance(xy), atol=1e-7
    )
    for bad, words in [
        ([0.5, 0.5], "xy must be an array of shape (n, 2), got (2,)"),
        ([["a", "b"]], "xy must be an (n, 2) array of numbers"),
    ]:
        with pytest.raises(MeshError) as e:
            want.contains(bad)
        assert words in str(e.value)
    with pytest.raises(MeshError, match="not by a point inside it"):
        Region.from_loops(SQUARE, np.array([[0.5, 0.5]]))
    with pytest.raises(MeshError, match="part 0 must be a pair"):
        Region.from_parts([SQUARE])


def test_counts_that_are_no_integers_are_type_errors():
    for name, kwargs in [("n", dict(n=100.5)), ("seed", dict(n=100, seed="1")), ("max_iter", dict(n=100, max_iter=1e3))]:
        with pytest.raises(TypeError, match=f"{name} must be an integer"):
            cvtmesh.mesh("circle", **kwargs)
    # numpy's integers are integers.
    assert len(cvtmesh.mesh("circle", n=np.int32(50), seed=np.uint8(3)).points) == 50


def test_measures_refuse_a_region_the_mesh_is_no_mesh_of_and_warn_where_it_nearly_is(tmp_path):
    m = cvtmesh.mesh(SQUARE, n=300)
    circle = Region.builtin("circle")
    with pytest.raises(MeshError, match="not a mesh of that region"):
        m.measures(circle)
    with pytest.raises(MeshError, match="region 'circle'"):
        cvtmesh.measures(m.points, m.triangles, "circle")
    m.write(tmp_path / "sq.msh")
    with pytest.raises(MeshError, match="not a mesh of that region"):
        cvtmesh.Mesh.read(tmp_path / "sq.msh").measures(circle)
    # Coordinates a little off, as a foreign file's rounding leaves them: measured, with a
    # warning.
    rounded = np.round(m.points + 1e-6 * (m.points - 0.5), 7)
    with pytest.warns(RuntimeWarning, match="does not conform to region 'square'"):
        near = cvtmesh.measures(rounded, m.triangles, Region.from_loops(SQUARE, name="square"))
    assert near["K"] == 300 and near["alpha"] == pytest.approx(m.measures()["alpha"], abs=1e-3)
    # The mesh's own region raises nothing.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cvtmesh.measures(m.points, m.triangles, SQUARE)
        m.measures(Region.from_loops(SQUARE))


def test_to_meshio_writes_gmsh_files_with_the_boundary_groups(tmp_path):
    meshio = pytest.importorskip("meshio")
    path = tmp_path / "channel.poly"
    path.write_text(MARKED_CHANNEL)
    cases = [
        (cvtmesh.mesh(SQUARE, holes=[HOLE], n=300), "boundary_{}", None),
        (cvtmesh.mesh(Region.load(path), n=600), "marker_{}", None),
    ]
    cases.append((cvtmesh.Mesh.read(_written(cases[0][0], tmp_path / "sq.node")), "boundary_{}", None))
    cases.append((cases[1][0], "marker_{}", 2))
    for m, names, order in cases:
        mm = m.to_meshio() if order is None else m.to_meshio(order=order)
        line = "line" if order is None else "line3"
        groups = m.boundary_markers() if names == "marker_{}" else m.boundary_loop
        # meshio 5.3's Gmsh 2.2 reader fails on files with element data (the markers) and more
        # than two triangles, so that format is read back without them.
        for fmt in ("gmsh", "gmsh22") if names == "boundary_{}" else ("gmsh",):
            out = tmp_path / f"{fmt}.msh"
            mm.write(out, file_format=fmt)
            back = meshio.read(out)
            tri = "triangle" if order is None else "triangle6"
            assert triangle_set(back.points[:, :2], back.cells_dict[tri][:, :3]) == triangle_set(
                m.points, m.triangles
            )
            tags = back.cell_data_dict["gmsh:physical"][line]
            want_tags = groups if names == "marker_{}" else groups + 1
            # Each group's lines, by their ends' coordinates, come back under its tag, which
            # the file names as the cell set, and (meshio reads Gmsh 4.1's names so) in it.
            for g in np.unique(groups):
                edges = m.boundary_edges[groups == g]
                name = names.format(g)
                tag = want_tags[groups == g][0]
                assert back.field_data[name].tolist() == [tag, 1]
                tagged = back.cells_dict[line][tags == tag][:, :2]
                assert edge_set(back.points, tagged) == edge_set(m.points, edges), (fmt, name)
                if fmt == "gmsh":
                    got = back.cells_dict[line][back.cell_sets_dict[name][line]][:, :2]
                    assert edge_set(back.points, got) == edge_set(m.points, edges), name
            assert back.field_data["domain"].tolist() == [1, 2]
            assert (back.cell_data_dict["gmsh:physical"][tri] == 1).all()


def _written(m, path):
    m.write(path)
    return path


def test_refine_says_which_vertex_count_it_reached():
    m = cvtmesh.mesh(SQUARE, n=100, method="refine")
    assert f"K reached {len(m.points)} (requested 100" in m.notes[1]


def test_small_conveniences():
    # One size_toward target as a bare string is that target, not its letters.
    kw = dict(n=150, size_threshold=(0.02, 0.2, 0.05, 0.5))
    one = cvtmesh.mesh("square_hole", size_toward="loop:1", **kw)
    np.testing.assert_array_equal(one.points, cvtmesh.mesh("square_hole", size_toward=["loop:1"], **kw).points)
    # Region.load takes a pathlib.Path as mesh() and from_file do.
    assert Region.load(Path("circle")).name == "circle"
    # help() shows the real defaults, not Ellipsis.
    import inspect

    assert inspect.signature(cvtmesh.Mesh.polished).parameters["below"].default == 40.0
    assert inspect.signature(Region.from_loops).parameters["holes"].default is None
    for name in ["points", "triangles", "boundary_edges", "boundary_loop", "converged", "iterations", "notes", "energy_history"]:
        assert getattr(cvtmesh.Mesh, name).__doc__, name


def test_size_bounds_without_a_size_field_are_refused_not_ignored():
    with pytest.raises(MeshError, match="bound a size field"):
        cvtmesh.mesh("circle", n=200, size_min=0.01)
    with pytest.raises(MeshError, match="bound a size field"):
        cvtmesh.mesh("circle", n=200, size_max=0.5)


def test_size_bounds_with_n_are_refused_as_they_would_not_hold():
    # n scales the field to n vertices: absolute bounds would become relative ones.
    with pytest.raises(MeshError, match=r"size_min \(--size-min\) is an edge length the mesh keeps"):
        cvtmesh.mesh("square_hole", size="0.01 + 0.1*abs(x)", size_min=0.02, n=300)
    # 0 and inf bound nothing, as Gmsh's defaults.
    m = cvtmesh.mesh("square_hole", size="0.04 + 0.1*abs(x)", size_min=0.0, size_max=float("inf"))
    g = cvtmesh.mesh("square_hole", size="0.04 + 0.1*abs(x)")
    assert np.array_equal(m.points, g.points)


def test_a_steep_field_notes_what_the_gradation_limit_added_and_is_measured_as_meshed():
    field = "0.01 + 0.5*abs(x)"
    m = cvtmesh.mesh("square_hole", size=field, tol=1e-3)
    assert any("the gradation limit 0.3" in n for n in m.notes), m.notes
    same = cvtmesh.size_conformity(m.points, m.triangles, "square_hole", field)
    given = cvtmesh.size_conformity(m.points, m.triangles, "square_hole", field, gradation=None)
    assert same["unit_share"] > 0.99 and given["unit_share"] < 0.9, (same, given)


def test_a_poly_s_area_constraints_are_named_as_not_used(tmp_path):
    poly = tmp_path / "sq.poly"
    poly.write_text("4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n1\n1 0.5 0.5 10 0.001\n")
    with pytest.warns(RuntimeWarning, match="1 area constraint is not used"):
        m = cvtmesh.mesh(str(poly), n=100)
    assert len(m.points) == 100


def _two_materials(tmp_path):
    # A 9 x 5 grid over [0, 2] x [0, 1], materials 10 | 20 either side of x = 1, the interior
    # vertices jittered (the interface's along it only).
    rng = np.random.default_rng(1)
    nx, ny = 9, 5
    pts = []
    for j in range(ny):
        for i in range(nx):
            x, y = 2 * i / (nx - 1), j / (ny - 1)
            if 0 < i < nx - 1 and 0 < j < ny - 1:
                if i != nx // 2:
                    x += 0.1 * (rng.random() - 0.5)
                y += 0.1 * (rng.random() - 0.5)
            pts.append((x, y))
    tris = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            v = lambda a, b: (j + b) * nx + i + a + 1
            m = 10 if i < nx // 2 else 20
            tris += [(v(0, 0), v(1, 0), v(1, 1), m), (v(0, 0), v(1, 1), v(0, 1), m)]
    node = tmp_path / "two.node"
    node.write_text(f"{len(pts)} 2 0 0\n" + "".join(f"{k + 1} {x!r} {y!r}\n" for k, (x, y) in enumerate(pts)))
    (tmp_path / "two.ele").write_text(f"{len(tris)} 3 1\n" + "".join(f"{k + 1} {a} {b} {c} {m}\n" for k, (a, b, c, m) in enumerate(tris)))
    return node


def test_an_interface_between_materials_is_held_by_polished_and_kept_by_a_new_mesh(tmp_path):
    node = _two_materials(tmp_path)
    m = cvtmesh.Mesh.read(str(node))
    rectangle = Region.from_loops(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]))
    p = m.polished(rectangle, below=60.0)
    assert not np.array_equal(p.points, m.points)
    assert np.count_nonzero(p.points[:, 0] == 1.0) == np.count_nonzero(m.points[:, 0] == 1.0) == 5
    # Meshed again, the region its triangles cover keeps the interface x = 1 as a line, and
    # the new mesh follows it.
    ((line, marker),) = Region.load(str(node)).embedded_lines
    assert line.tolist() == [[1.0, 0.0], [1.0, 1.0]] or line.tolist() == [[1.0, 1.0], [1.0, 0.0]]
    again = cvtmesh.mesh(str(node), n=300)
    edges, _ = again.line_edges()
    assert (again.points[edges.ravel(), 0] == 1.0).all()
    assert abs(np.abs(np.diff(again.points[edges][:, :, 1], axis=1)).sum() - 1.0) < 1e-12


def test_no_region_is_a_type_error_naming_what_a_region_may_be():
    with pytest.raises(TypeError, match="a Region or a"):
        cvtmesh.mesh(None, n=100)


def test_walls_numbered_on_arrays_reach_the_mesh_and_its_file(tmp_path):
    # A channel: inlet 1 on the left, walls 2, outlet 3 on the right, and a heated stretch 4
    # of the bottom from x = 1 on, where the side does not turn.
    pts = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [0, 1]], float)
    names = {1: "inlet", 3: "outlet", 4: "heated"}
    r = Region.from_loops(pts, markers=[[2, 4, 3, 2, 1]], names=names)
    assert r.piece_markers == [2, 4, 3, 2, 1]
    m = cvtmesh.mesh(r, n=600)
    # (1, 0) is a vertex, so no edge lies on two walls.
    assert np.any(np.all(m.points == [1.0, 0.0], axis=1))
    mid = m.points[m.boundary_edges].mean(axis=1)
    expected = np.select(
        [mid[:, 0] < 1e-12, mid[:, 0] > 2 - 1e-12, (mid[:, 1] < 1e-12) & (mid[:, 0] > 1)],
        [1, 3, 4],
        2,
    )
    np.testing.assert_array_equal(m.boundary_markers(), expected)
    # A hole's walls too, in the same list; the .msh names the groups.
    hole = np.array([[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]])
    r2 = Region.from_loops(pts, holes=[hole], markers=[[2, 4, 3, 2, 1], [7, 7, 7, 7]], names=names)
    assert r2.piece_markers[-1] == 7
    m2 = cvtmesh.mesh(r2, n=600)
    m2.write(tmp_path / "c.msh")
    text = (tmp_path / "c.msh").read_text()
    assert '"heated"' in text and '"inlet"' in text and '"marker7"' in text
    with pytest.raises(MeshError, match="loop 0 has 2 markers for its 5 edges"):
        Region.from_loops(pts, markers=[[1, 2]])
    with pytest.raises(MeshError, match="1 arrays for 2 loops"):
        Region.from_loops(pts, holes=[hole], markers=[[2, 4, 3, 2, 1]])
    with pytest.raises(MeshError, match="whole numbers"):
        Region.from_loops(pts, markers=[[2, 4, 3.5, 2, 1]])


def test_the_dual_gives_finite_volume_cells_that_tile_the_mesh():
    m = cvtmesh.mesh("square_hole", n=1500)
    d = m.dual()
    u = m.points[m.triangles[:, 1]] - m.points[m.triangles[:, 0]]
    v = m.points[m.triangles[:, 2]] - m.points[m.triangles[:, 0]]
    area = 0.5 * (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum()
    assert d["volumes"].shape == (len(m.points),) and (d["volumes"] > 0).all()
    assert abs(d["volumes"].sum() - area) < 1e-12 * area
    # A CCVT mesh is Delaunay and has no triangle obtuse at the boundary: no negative face,
    # so a two-point flux scheme is monotone on it.
    assert (d["faces"] >= -1e-12 * d["lengths"]).all()
    # Every edge once; boundary edges are those of the mesh's boundary.
    assert len(d["edges"]) == len({tuple(e) for e in d["edges"]})
    ends = np.sort(m.boundary_edges, axis=1)
    assert {tuple(e) for e in d["edges"][d["on_boundary"]]} == {tuple(e) for e in ends}
    # Divergence theorem on the dual: for u = x² + y², Δu = 4, the two-point fluxes out of an
    # inner cell sum to 4 × its volume (exactly, on a Delaunay mesh, for a quadratic).
    u = (m.points**2).sum(axis=1)
    i, j = d["edges"][:, 0], d["edges"][:, 1]
    flux = d["faces"] / d["lengths"] * (u[j] - u[i])
    net = np.zeros(len(u))
    np.add.at(net, i, flux)
    np.add.at(net, j, -flux)
    inner = np.ones(len(u), bool)
    inner[np.unique(m.boundary_edges)] = False
    np.testing.assert_allclose(net[inner], 4 * d["volumes"][inner], rtol=1e-9)
    assert not d["faces"].flags.writeable
    assert d["circumcentres"].shape == (len(m.triangles), 2)


def _areas_by(m, ids):
    tri = m.points[m.triangles]
    u, v = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    area = 0.5 * (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    return {int(n): float(area[ids == n].sum()) for n in np.unique(ids)}


def test_subdomain_points_number_the_triangles_the_files_and_meshio(tmp_path):
    path = tmp_path / "two.poly"
    path.write_text(INTERFACE_POLY)
    region = Region.load(str(path)).with_subdomain_points([[0.25, 0.5], [0.75, 0.5]], [3, 4])
    assert region.subdomain_points == [((0.25, 0.5), 3), ((0.75, 0.5), 4)]
    m = cvtmesh.mesh(region, n=400)
    ids = m.subdomains()
    assert ids.dtype == np.int64 and ids.shape == (len(m.triangles),) and not ids.flags.writeable
    areas = _areas_by(m, ids)
    assert set(areas) == {3, 4} and all(abs(a - 0.5) < 1e-12 for a in areas.values()), areas
    # Without points, the two sides are 1 and 2 from the left.
    plain = cvtmesh.mesh(Region.load(str(path)), n=400)
    assert _areas_by(plain, plain.subdomains()).keys() == {1, 2}
    # meshio: a cell array, and a triangle block (a Gmsh surface) and physical surface per
    # number, each block's triangles in the mesh's order.
    mm = m.to_meshio()
    order = np.concatenate([np.flatnonzero(ids == 3), np.flatnonzero(ids == 4)])
    assert (mm.cells_dict["triangle"] == m.triangles[order]).all()
    assert mm.cell_data_dict["subdomain"]["triangle"].tolist() == ids[order].tolist()
    assert mm.cell_data_dict["gmsh:physical"]["triangle"].tolist() == ids[order].tolist()
    assert mm.field_data["subdomain_4"].tolist() == [4, 2]
    assert mm.cell_sets["subdomain_3"][0].tolist() == list(range((ids == 3).sum()))
    assert mm.cell_sets["subdomain_3"][1].size == 0
    # Written by meshio's Gmsh 4.1 writer, each surface keeps its number (one block of several
    # numbers had the first triangle's for all), and the interface its curve.
    meshio = pytest.importorskip("meshio")
    mm.write(str(tmp_path / "meshio.msh"), file_format="gmsh")
    back = meshio.read(str(tmp_path / "meshio.msh"))
    for n in (3, 4):
        got = back.cells_dict["triangle"][back.cell_sets_dict[f"subdomain_{n}"]["triangle"]]
        assert triangle_set(back.points[:, :2], got) == triangle_set(m.points, m.triangles[ids == n])
    edges, _ = m.line_edges()
    got = back.cells_dict["line"][back.cell_sets_dict["marker_7"]["line"]]
    assert edge_set(back.points, got) == edge_set(m.points, edges)
    # A region of one material, or of two parts without lines, keeps its one surface.
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    two_parts = Region.from_parts([(square, []), (square + [2.0, 0.0], [])])
    for plain in (cvtmesh.mesh("circle", n=200), cvtmesh.mesh(two_parts, n=200)):
        assert "subdomain" not in plain.to_meshio().cell_data
    # The files keep them, and a mesh read back numbers its triangles as the file did.
    for name in ("m.msh", "m.node"):
        m.write(str(tmp_path / name))
        back = cvtmesh.Mesh.read(str(tmp_path / name))
        areas = _areas_by(back, back.subdomains())
        assert set(areas) == {3, 4} and all(abs(a - 0.5) < 1e-12 for a in areas.values()), (name, areas)


def test_named_subdomains_and_walls_name_the_meshio_groups(tmp_path):
    meshio = pytest.importorskip("meshio")
    path = tmp_path / "two.poly"
    path.write_text(INTERFACE_POLY)
    named = Region.load(str(path)).with_subdomain_points(
        [[0.25, 0.5], [0.75, 0.5]], [3, 4], names={4: "steel"}
    )
    assert named.subdomain_names == {4: "steel"} and named.marker_names == {}
    m = cvtmesh.mesh(named, n=400)
    mm = m.to_meshio()
    # The named group by its name, in the cell sets beside its number and as the physical
    # group's name; the unnamed one by its number.
    assert mm.field_data["steel"].tolist() == [4, 2] and "subdomain_4" not in mm.field_data
    assert mm.field_data["subdomain_3"].tolist() == [3, 2]
    assert mm.cell_sets["steel"][0].tolist() == mm.cell_sets["subdomain_4"][0].tolist()
    out = tmp_path / "meshio.msh"
    mm.write(str(out), file_format="gmsh")
    back = meshio.read(str(out))
    steel = back.cells_dict["triangle"][back.cell_sets_dict["steel"]["triangle"]]
    assert triangle_set(back.points[:, :2], steel) == triangle_set(
        m.points, m.triangles[m.subdomains() == 4])
    # cvtmesh's own .msh names the surface, and a mesh read back has the names.
    m.write(str(tmp_path / "own.msh"))
    back = cvtmesh.Mesh.read(str(tmp_path / "own.msh"))
    assert back.to_meshio().field_data["steel"].tolist() == [4, 2]
    # Named walls likewise.
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    walls = Region.from_loops(square, markers=[[11, 12, 12, 12]], names={11: "inlet"})
    assert walls.marker_names == {11: "inlet"}
    wm = cvtmesh.mesh(walls, n=200).to_meshio()
    assert wm.field_data["inlet"].tolist() == [11, 1] and wm.field_data["marker_12"].tolist() == [12, 1]
    assert [len(b) for b in wm.cell_sets["inlet"]] == [len(b) for b in wm.cell_sets["marker_11"]]


def test_a_mesh_refined_toward_an_interface(tmp_path):
    path = tmp_path / "two.poly"
    path.write_text(INTERFACE_POLY)
    m = cvtmesh.mesh(str(path), size_toward="line:0", size_threshold=(0.01, 0.08, 0.0, 0.3))
    edges, _ = m.line_edges()
    along = np.linalg.norm(np.diff(m.points[edges], axis=1)[:, 0], axis=1).mean()
    assert 0.01 / np.sqrt(2) < along < 0.01 * np.sqrt(2), along
    with pytest.raises(MeshError, match="no line 1"):
        cvtmesh.mesh(str(path), size_toward="line:1", size_threshold=(0.01, 0.08, 0.0, 0.3))


def test_bad_subdomain_points_raise_mesh_error():
    square = Region.from_loops(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]))
    split = square.with_embedded_lines([np.array([[0.5, 0.0], [0.5, 1.0]])])
    with pytest.raises(MeshError, match="on an embedded line"):
        split.with_subdomain_points([[0.5, 0.5]], [1])
    with pytest.raises(MeshError, match="outside the region"):
        split.with_subdomain_points([[2.0, 0.5]], [1])
    with pytest.raises(MeshError, match="2 points and 1 ids"):
        split.with_subdomain_points([[0.2, 0.5], [0.7, 0.5]], [1])


def test_mesh_methods_take_a_region_by_name_or_path_as_mesh_does(tmp_path):
    m = cvtmesh.Mesh.read(str(_write(cvtmesh.mesh("circle", n=300), tmp_path / "c.msh")))
    by_name, by_object = m.measures("circle"), m.measures(Region.builtin("circle"))
    assert by_name == by_object
    assert m.boundary_pieces("circle").tolist() == m.boundary_pieces(Region.builtin("circle")).tolist()
    assert m.polished(region="circle").points.shape == m.points.shape
    assert len(m.to_meshio(region="circle").cells_dict["triangle"]) == len(m.triangles)
    # A mesh mostly off the region it is measured against is no mesh of it, whatever its area.
    with pytest.raises(MeshError, match="not a mesh of that region"):
        cvtmesh.measures(m.points + [1.5, 0.0], m.triangles, "circle")
    with pytest.raises(MeshError, match="unknown|cannot|no built-in"):
        m.measures("no_such_region")


def _write(m, path):
    m.write(str(path))
    return path


def _cracked_disc():
    crack = np.array([[0.0, 1.0], [0.0, 0.2]])
    return Region.load("circle").with_embedded_lines([crack], markers=[4])


def _mesh_in_another_process(seed):
    return cvtmesh.mesh(_cracked_disc(), n=400, seed=seed)


def test_regions_and_meshes_pickle_to_the_bit_and_cross_processes(tmp_path):
    import multiprocessing
    import pickle
    from concurrent.futures import ProcessPoolExecutor

    region = _cracked_disc()
    back = pickle.loads(pickle.dumps(region))
    assert repr(back) == repr(region)
    assert back.piece_markers == region.piece_markers
    assert back.pieces == region.pieces
    np.testing.assert_array_equal(back.corners, region.corners)
    assert [m for _, m in back.embedded_lines] == [4]
    # The region that comes back meshes to the same bits.
    m = cvtmesh.mesh(region, n=400, seed=3)
    np.testing.assert_array_equal(cvtmesh.mesh(back, n=400, seed=3).points, m.points)
    again = pickle.loads(pickle.dumps(m))
    for name in ["points", "triangles", "boundary_edges", "boundary_loop", "energy_history"]:
        np.testing.assert_array_equal(getattr(again, name), getattr(m, name))
    assert (again.converged, again.iterations, again.notes) == (m.converged, m.iterations, m.notes)
    # What the mesh answers from its region and markers is the same.
    for a, b in zip(again.line_edges(), m.line_edges()):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(again.boundary_pieces(), m.boundary_pieces())
    assert again.measures() == m.measures()
    np.testing.assert_array_equal(again.polished().points, m.polished().points)
    # A mesh read from a file keeps its walls and the interface it holds in the polish.
    m.write(tmp_path / "m.msh")
    read = cvtmesh.Mesh.read(tmp_path / "m.msh")
    read_again = pickle.loads(pickle.dumps(read))
    np.testing.assert_array_equal(read_again.boundary_markers(region), read.boundary_markers(region))
    np.testing.assert_array_equal(read_again.polished().points, read.polished().points)
    # Meshes made in worker processes come back as the same meshes made here.
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        made = list(pool.map(_mesh_in_another_process, [1, 2]))
    for seed, there in zip([1, 2], made):
        here = _mesh_in_another_process(seed)
        np.testing.assert_array_equal(there.points, here.points)
        np.testing.assert_array_equal(there.triangles, here.triangles)
    # A state that is not one is refused as a MeshError.
    with pytest.raises(MeshError, match="not a region's saved state"):
        cvtmesh._cvtmesh._region_from_state("{}")


def _calls_after_a_fork(out):
    """What a worker of a parameter sweep calls, its results sent back through `out`."""
    square = cvtmesh.mesh(SQUARE, holes=[HOLE], n=300, seed=2)
    graded = cvtmesh.mesh("circle", size_toward=["point:0,0"], size_threshold=(0.02, 0.1, 0, 1))
    expr = cvtmesh.mesh("lake", size="3 + 0.02*abs(x)", n=500)
    by_call = cvtmesh.mesh(SQUARE, size=lambda xy: 0.03 + 0.05 * xy[:, 0])
    measured = square.measures()
    polished = square.polished()
    out.send([square.points.tobytes(), len(graded.points), len(expr.points), len(by_call.points),
              measured["lambda"], polished.points.tobytes()])


def test_a_process_forked_after_meshing_meshes_too():
    # multiprocessing's default start method on Linux forks: the child has the parent's memory
    # but none of its threads. Meshing there, after the parent meshed, must not wait for them.
    import multiprocessing

    if "fork" not in multiprocessing.get_all_start_methods():
        pytest.skip("no fork here")
    here_pipe = multiprocessing.Pipe()
    cvtmesh.mesh("circle", n=300)
    _calls_after_a_fork(here_pipe[1])
    here = here_pipe[0].recv()
    ctx = multiprocessing.get_context("fork")
    receive, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_calls_after_a_fork, args=(send,))
    child.start()
    child.join(120)
    if child.is_alive():
        child.kill()
        pytest.fail("the forked process hung")
    assert child.exitcode == 0
    assert receive.recv() == here
