"""Mesh the same regions at the same K with Triangle, Gmsh and DistMesh, and with cvtmesh;
score every mesh with `cvtmesh measure --csv`; write results/compare/compare.{csv,md}.

Each external tool is timed around its mesher call only. K is matched by a short search on
the tool's size parameter (area bound, characteristic length, h0). With --repeat N, Triangle's
and Gmsh's calls at the parameter found and cvtmesh's whole command are timed N times and the
fastest is kept: one call of a tenth of a second moves by half from run to run on a shared
machine, and the least of several is the time the tool needs when nothing else runs.
"""
import argparse, functools, json, math, os, queue, statistics, subprocess, sys, time, multiprocessing as mp
import numpy as np

MEASURES = "K,Ktilde,lambda,gamma,h,mu,chi,nu,tau,d,alpha,beta,q,p".split(",")


def _resample(dense, h):
    """Points along the open polyline `dense` at arc-length spacing ~h, both ends kept."""
    dense = np.asarray(dense, float)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))])
    n = max(1, int(round(s[-1] / h)))
    t = np.linspace(0.0, s[-1], n + 1)
    return np.column_stack([np.interp(t, s, dense[:, 0]), np.interp(t, s, dense[:, 1])])


def segment_points(seg, h):
    """A curved segment (arc, superellipse, parametric) sampled at arc-length spacing ~h,
    from its start to its end; a closed curve (superellipse) repeats its first point last.
    A superellipse runs counter-clockwise; its loop's orientation decides the direction."""
    k = seg["kind"]
    if k == "arc":
        c, r = seg["center"], seg["radius"]
        t = np.radians(np.linspace(seg["from_deg"], seg["to_deg"], 4097))
        dense = np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t)])
    elif k == "superellipse":
        c, a, b, n = seg["center"], seg["a"], seg["b"], seg["exponent"]
        t = np.linspace(0, 2 * math.pi, 16385)
        ct, st = np.cos(t), np.sin(t)
        dense = np.column_stack([c[0] + a * np.sign(ct) * np.abs(ct) ** (2 / n),
                                 c[1] + b * np.sign(st) * np.abs(st) ** (2 / n)])
        dense[-1] = dense[0]
    elif k == "parametric":
        dense = np.asarray(seg["points"], float)
    else:
        raise SystemExit(f"compare_tools: segment kind {k} not supported here")
    return _resample(dense, h)


def _same(a, b, d):
    """Whether two boundary points coincide: a computed arc end and the corner stored in the
    next piece differ by rounding only, and a near-duplicate vertex can crash Triangle."""
    return np.allclose(a, b, rtol=0, atol=1e-9 * max(1.0, max(abs(v) for v in d["bbox"])))


def loops_of(domain_file, h, split_lines=False):
    """Boundary loops as (N,2) arrays, curves sampled at spacing ~h, outer first; straight
    edges whole, or with split_lines also split at spacing ~h."""
    d = json.load(open(domain_file))
    loops = []
    for lp in d["loops"]:
        pts = []
        for seg in lp["segments"]:
            k = seg["kind"]
            if k == "circle":
                c, r = seg["center"], seg["radius"]
                n = max(8, int(round(2 * math.pi * r / h)))
                t = np.linspace(0, 2 * math.pi, n, endpoint=False)
                if lp["orientation"] == "cw":
                    t = -t
                pts += list(zip(c[0] + r * np.cos(t), c[1] + r * np.sin(t)))
            elif k == "polyline":
                p = seg["points"]
                if p[0] == p[-1]:
                    p = p[:-1]
                if split_lines:
                    p = [tuple(q) for a, b in zip(seg["points"], seg["points"][1:])
                         for q in _resample([a, b], h)[:-1]] + [tuple(seg["points"][-1])]
                    p = p[:-1] if _same(p[0], p[-1], d) else p
                pts += [tuple(q) for q in (p if not pts or not _same(p[0], pts[-1], d) else p[1:])]
            else:
                p = segment_points(seg, h)
                if k == "superellipse":
                    p = p[:-1] if lp["orientation"] != "cw" else p[::-1][:-1]
                pts += [tuple(q) for q in (p if not pts or not _same(p[0], pts[-1], d) else p[1:])]
        if len(pts) > 1 and np.allclose(pts[0], pts[-1]):
            pts = pts[:-1]
        loops.append(np.array(pts, float))
    return d, loops


def write_node_ele(base, p, t):
    with open(base + ".node", "w") as f:
        f.write(f"{len(p)} 2 0 0\n")
        for i, (x, y) in enumerate(p):
            f.write(f"{i+1} {float(x)!r} {float(y)!r}\n")
    with open(base + ".ele", "w") as f:
        f.write(f"{len(t)} 3 0\n")
        for i, (a, b, c) in enumerate(t):
            f.write(f"{i+1} {a+1} {b+1} {c+1}\n")


def compact(p, t):
    used = np.unique(t)
    remap = -np.ones(len(p), int)
    remap[used] = np.arange(len(used))
    return p[used], remap[t]


def triangle_input(domain_file, h, split_lines=False):
    """Triangle's input for a region: its loops (curves sampled at spacing ~h) as vertices and
    closed segment chains, and its hole points."""
    d, loops = loops_of(domain_file, h, split_lines)
    verts, segs, off = [], [], 0
    for lp in loops:
        n = len(lp)
        verts += lp.tolist()
        segs += [[off + j, off + (j + 1) % n] for j in range(n)]
        off += n
    geom = {"vertices": verts, "segments": segs}
    if d.get("hole_points"):
        geom["holes"] = d["hole_points"]
    return geom


def run_triangle(domain_file, k, area, min_angle=30, split_boundary=False, info=None, tries=8,
                 split_lines=False, repeat=1):
    """Triangle -pq<min_angle>a<A> with A searched to K. Without split_boundary, -Y keeps the
    boundary as sampled (curves at spacing h, straight edges whole); with it Triangle splits
    encroached boundary segments as its default does. `info` (a dict) receives the switches;
    `tries` caps the search on A; split_lines samples straight edges at spacing h too; the
    call at the A found is timed `repeat` times in all and the fastest kept."""
    import triangle
    h = math.sqrt(2 * area / (math.sqrt(3) * k))
    geom = triangle_input(domain_file, h, split_lines)
    a = math.sqrt(3) / 4 * h * h
    best, bracket = None, [None, None]
    for _ in range(tries):
        t0 = time.perf_counter()
        # Triangle's switches take no exponent: "a5.4e-05" would be read as a5.4.
        switches = f"pq{min_angle:g}a{a:.20f}" + ("" if split_boundary else "Y")
        m = triangle.triangulate(geom, switches)
        sec = time.perf_counter() - t0
        kk = len(m["vertices"])
        if best is None or abs(kk - k) < abs(best[2] - k):
            best = (m["vertices"], m["triangles"], kk, sec, switches)
            if info is not None:
                info["switches"] = switches
        if abs(kk - k) <= 0.005 * k:
            break
        a = next_size(a, kk, k, kk / k, bracket)
    sec = best[3]
    for _ in range(repeat - 1):
        t0 = time.perf_counter()
        triangle.triangulate(geom, best[4])
        sec = min(sec, time.perf_counter() - t0)
    return best[0], best[1], sec


def _gmsh_curved_loop(gmsh, d, lp, h):
    """A curve loop of lines (polyline pieces) and splines through points ~h/8 apart (curved
    pieces): a chain of lines would make every sample point a mesh vertex."""
    occ = gmsh.model.occ
    tol = 1e-9 * max(1.0, max(abs(v) for v in d["bbox"]))
    made = []  # (tag, xy): pieces share their end points, and the loop closes on its first

    def point(xy):
        for tag, q in made[-1:] + made[:1]:
            if np.allclose(xy, q, rtol=0, atol=tol):
                return tag
        made.append((occ.addPoint(float(xy[0]), float(xy[1]), 0), np.asarray(xy, float)))
        return made[-1][0]

    curves = []
    for seg in lp["segments"]:
        if seg["kind"] == "polyline":
            ids = [point(q) for q in seg["points"]]
            curves += [occ.addLine(a, b) for a, b in zip(ids, ids[1:]) if a != b]
            continue
        chain = segment_points(seg, h / 8)
        if seg["kind"] == "superellipse" and lp["orientation"] == "cw":
            chain = chain[::-1]
        # A closed piece ends on its first point, which Gmsh makes a periodic spline.
        curves.append(occ.addSpline([point(q) for q in chain]))
    return occ.addCurveLoop(curves)


def gmsh_generate(gmsh):
    """Mesh the current Gmsh model in 2D, timed around `generate` alone; finalizes Gmsh and
    returns the used vertices and the triangles (renumbered) and the seconds."""
    t0 = time.perf_counter()
    gmsh.model.mesh.generate(2)
    sec = time.perf_counter() - t0
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    _, _, enodes = gmsh.model.mesh.getElements(2)
    gmsh.finalize()
    p = xyz.reshape(-1, 3)[:, :2]
    index = {int(tg): i for i, tg in enumerate(tags)}
    tri = np.array([index[int(n)] for n in enodes[0]]).reshape(-1, 3)
    p, tri = compact(p, tri)
    return p, tri, sec


def run_gmsh(domain_file, k, area, algo, info=None, tries=5, size_from_boundary=True, repeat=1):
    """Gmsh algorithm `algo` at a uniform size searched to K; `info` (a dict) receives the size.
    Gmsh extends the sizes of the boundary's 1-D mesh inward, below Mesh.MeshSizeMin: a short
    edge split in two then halves the spacing around it (square_two_hex: K jumps from 145 to
    277 between sizes 0.100 and 0.099). size_from_boundary=False turns that off. The size
    found is meshed `repeat` times in all and the fastest `generate` kept."""
    import gmsh
    h0 = math.sqrt(2 * area / (math.sqrt(3) * k))
    d, loops = loops_of(domain_file, h0 / 4)
    best, h, bracket = None, h0, [None, None]

    def build(h):
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("m")
        curve_loops = []
        for i, lp in enumerate(loops):
            seg = d["loops"][i]["segments"]
            if len(seg) == 1 and seg[0]["kind"] == "circle":
                c, r = seg[0]["center"], seg[0]["radius"]
                cl = gmsh.model.occ.addCurveLoop([gmsh.model.occ.addCircle(c[0], c[1], 0, r)])
            elif any(s["kind"] not in ("polyline", "circle") for s in seg):
                cl = _gmsh_curved_loop(gmsh, d, d["loops"][i], h0)
            else:
                pts = [gmsh.model.occ.addPoint(x, y, 0) for x, y in lp]
                lines = [gmsh.model.occ.addLine(pts[j], pts[(j + 1) % len(pts)]) for j in range(len(pts))]
                cl = gmsh.model.occ.addCurveLoop(lines)
            curve_loops.append(cl)
        gmsh.model.occ.addPlaneSurface(curve_loops)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMin", h)
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.option.setNumber("Mesh.Algorithm", algo)
        if not size_from_boundary:
            gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)

    for _ in range(tries):
        build(h)
        p, tri, sec = gmsh_generate(gmsh)
        if best is None or abs(len(p) - k) < abs(len(best[0]) - k):
            best = (p, tri, sec, h)
            if info is not None:
                info["size"] = h
        if abs(len(p) - k) <= 0.01 * k:
            break
        h = next_size(h, len(p), k, math.sqrt(len(p) / k), bracket)
    sec = best[2]
    for _ in range(repeat - 1):
        build(best[3])
        sec = min(sec, gmsh_generate(gmsh)[2])
    return best[0], best[1], sec


def run_distmesh(domain_file, k, area):
    from distmeshpy import distmesh2d
    from distmeshpy.utils import huniform
    h = math.sqrt(2 * area / (math.sqrt(3) * k))
    d, loops = loops_of(domain_file, h / 8)

    def dist(p):
        best = np.full(len(p), np.inf)
        inside = np.zeros(len(p), bool)
        for lp in loops:
            a, b = lp, np.roll(lp, -1, axis=0)
            for j in range(len(a)):
                ab = b[j] - a[j]
                t = np.clip(((p - a[j]) @ ab) / (ab @ ab), 0, 1)
                best = np.minimum(best, np.linalg.norm(p - (a[j] + t[:, None] * ab), axis=1))
                cond = ((a[j][1] > p[:, 1]) != (b[j][1] > p[:, 1])) & (
                    p[:, 0] < a[j][0] + (p[:, 1] - a[j][1]) * ab[0] / (ab[1] if ab[1] != 0 else 1e-300))
                inside ^= cond
        return np.where(inside, -best, best)

    if all(len(lp["segments"]) == 1 and lp["segments"][0]["kind"] == "circle" for lp in d["loops"]):
        def dist(p):  # exact for concentric circles
            r = np.linalg.norm(p - np.array(d["loops"][0]["segments"][0]["center"]), axis=1)
            out = r - d["loops"][0]["segments"][0]["radius"]
            for lp in d["loops"][1:]:
                out = np.maximum(out, lp["segments"][0]["radius"] - r)
            return out

    x0, y0, x1, y1 = d["bbox"]
    fixed = np.array(d["corners"]) if d["corners"] else None
    t0 = time.perf_counter()
    p, t = distmesh2d(dist, huniform, h, ((x0, x1), (y0, y1)), fixed_points=fixed)
    sec = time.perf_counter() - t0
    return np.asarray(p), np.asarray(t), sec


def cvtmesh_run(exe, region, k, base, max_iter, timeout, repeat=1):
    """Seconds of the whole command (the fastest of `repeat` runs) and a note: iterations and
    whether it converged."""
    sec = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = subprocess.run([exe, "mesh", region, "--points", str(k), "--quiet", "--max-iter",
                              str(max_iter), "-o", base + ".node"],
                             capture_output=True, text=True, timeout=timeout)
        if out.returncode != 0:
            raise RuntimeError(out.stderr)
        sec = min(sec, time.perf_counter() - t0)
    line = out.stdout.strip().splitlines()[-1]
    its = next((w.split("=")[1] for w in line.split() if w.startswith("iterations=")), "?")
    state = "not converged" if "not converged" in line.lower() else "converged"
    return sec, f"whole command; {its} iterations; {state}"


def paired_ratios(exe, region, k, domain_file, area, base, max_iter, timeout, pairs):
    """cvtmesh's whole command over Triangle's call, timed `pairs` times in alternation (one
    Triangle call, then one cvtmesh command), so that both see the machine in the same state:
    on a shared VM the speed drifts by tens of per cent within a minute, which moves the ratio
    of two separately timed blocks as much. Triangle at the switches its search finds here."""
    import triangle
    info = {}
    run_triangle(domain_file, k, area, info=info)
    h = math.sqrt(2 * area / (math.sqrt(3) * k))
    geom = triangle_input(domain_file, h, False)
    ratios = []
    for _ in range(pairs):
        t0 = time.perf_counter()
        triangle.triangulate(geom, info["switches"])
        tri = time.perf_counter() - t0
        sec, _ = cvtmesh_run(exe, region, k, base, max_iter, timeout)
        ratios.append(sec / tri)
    return ratios


def measure(exe, base, region):
    out = subprocess.run([exe, "measure", base + ".node", "--region", region, "--csv"], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(out.stderr)
    return dict(zip(MEASURES, map(float, out.stdout.strip().splitlines()[1].split(","))))


def _worker(q, fn, args):
    try:
        p, t, sec = fn(*args)
        q.put((np.asarray(p), np.asarray(t), sec))
    except Exception as e:  # reported as a failed row
        q.put(e)


def next_size(x, kk, k, step, bracket):
    """The next size (area bound or mesh size; a larger one gives fewer vertices) after `x`
    gave kk vertices for k wanted: the proportional step, unless it leaves the bracket the
    runs so far have set, where K(x) jumps and the step cycles; then the bracket's geometric
    middle. `bracket` is [too small, too large], updated here."""
    if kk > k:
        bracket[0] = x if bracket[0] is None else max(bracket[0], x)
    elif kk < k:
        bracket[1] = x if bracket[1] is None else min(bracket[1], x)
    y = x * step
    lo, hi = bracket
    if lo is not None and hi is not None and not lo < y < hi:
        y = math.sqrt(lo * hi)
    return y


def with_timeout(fn, args, timeout):
    """fn(*args) in a child process; None if it takes longer than `timeout` seconds.
    The result is read before joining: a large result blocks the child until it is read."""
    q = mp.Queue()
    pr = mp.Process(target=_worker, args=(q, fn, args))
    pr.start()
    try:
        r = q.get(timeout=timeout)
    except queue.Empty:
        pr.terminate()
        pr.join()
        return None
    pr.join()
    if isinstance(r, Exception):
        raise r
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cvtmesh", required=True)
    ap.add_argument("--domains", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--sizes", default="10000,100000")
    ap.add_argument("--regions", default="circle,lake")
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--update", action="store_true",
                    help="keep the rows of an existing table that this run does not redo")
    ap.add_argument("--name", default="compare", help="stem of the CSV and Markdown tables in --out")
    ap.add_argument("--tools", default="triangle,gmsh-delaunay,gmsh-frontal,distmeshpy,cvtmesh",
                    help="which tools to run (e.g. leave out the slow ones at 10^6)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="time Triangle's and Gmsh's calls and cvtmesh's command this many times "
                         "and keep the fastest (distmeshpy runs once)")
    ap.add_argument("--pairs", type=int, default=0,
                    help="also time Triangle's call and cvtmesh's command this many times in "
                         "alternation and add the median of the pairs' ratios to cvtmesh's note")
    ap.add_argument("--cvtmesh-max-iter", type=int, default=10000,
                    help="cvtmesh's iteration cap per phase (a capped run is reported as not converged)")
    a = ap.parse_args()
    if a.repeat < 1:
        ap.error("--repeat must be at least 1")
    os.makedirs(a.out, exist_ok=True)
    rows = []
    timed = functools.partial
    tools = [("triangle", timed(run_triangle, repeat=a.repeat), ()),
             ("gmsh-delaunay", timed(run_gmsh, repeat=a.repeat), (5,)),
             ("gmsh-frontal", timed(run_gmsh, repeat=a.repeat), (6,)),
             ("distmeshpy", run_distmesh, ())]
    wanted = set(a.tools.split(","))
    tools = [t for t in tools if t[0] in wanted]
    for region in a.regions.split(","):
        dfile = os.path.join(a.domains, region + ".json")
        area = json.load(open(dfile))["area"]
        for k in map(int, a.sizes.split(",")):
            for name, fn, extra in tools:
                base = os.path.join(a.out, f"{region}_{k}_{name}")
                try:
                    r = with_timeout(fn, (dfile, k, area) + extra, a.timeout)
                except Exception as e:
                    print(f"{region} {k} {name}: failed: {e}", file=sys.stderr)
                    continue
                if r is None:
                    print(f"{region} {k} {name}: no result within {a.timeout:.0f} s", file=sys.stderr)
                    rows.append(dict(region=region, K_requested=k, tool=name, seconds=float("nan"), note="timeout"))
                    continue
                p, t, sec = r
                write_node_ele(base, p, t)
                m = measure(a.cvtmesh, base, region)
                rows.append(dict(region=region, K_requested=k, tool=name, seconds=sec, note="", **m))
                print(f"{region} {k} {name}: K={m['K']:.0f} {sec:.2f}s", file=sys.stderr)
            if "cvtmesh" not in wanted:
                continue
            base = os.path.join(a.out, f"{region}_{k}_cvtmesh")
            try:
                sec, note = cvtmesh_run(a.cvtmesh, region, k, base, a.cvtmesh_max_iter, a.timeout,
                                        a.repeat)
            except subprocess.TimeoutExpired:
                print(f"{region} {k} cvtmesh: no result within {a.timeout:.0f} s", file=sys.stderr)
                rows.append(dict(region=region, K_requested=k, tool="cvtmesh", seconds=float("nan"), note="timeout"))
                continue
            m = measure(a.cvtmesh, base, region)
            if a.pairs > 0:
                ratios = sorted(paired_ratios(a.cvtmesh, region, k, dfile, area, base,
                                              a.cvtmesh_max_iter, a.timeout, a.pairs))
                note += (f"; {len(ratios)} alternating pairs with Triangle: median ratio "
                         f"{statistics.median(ratios):.1f}x ({ratios[0]:.1f}-{ratios[-1]:.1f})")
                print(f"{region} {k} cvtmesh / triangle over {len(ratios)} pairs: "
                      + " ".join(f"{r:.1f}" for r in ratios), file=sys.stderr)
            rows.append(dict(region=region, K_requested=k, tool="cvtmesh", seconds=sec, note=note, **m))
            print(f"{region} {k} cvtmesh: K={m['K']:.0f} {sec:.2f}s", file=sys.stderr)
    cols = ["region", "K_requested", "tool", "seconds"] + MEASURES + ["note"]
    old_csv = os.path.join(a.out, a.name + ".csv")
    if a.update and os.path.exists(old_csv):
        import csv
        done = {(r["region"], int(r["K_requested"]), r["tool"]) for r in rows}
        kept = []
        with open(old_csv) as f:
            for r in csv.DictReader(f):
                r["K_requested"] = int(r["K_requested"])
                for c in ["seconds"] + MEASURES:
                    r[c] = float(r[c]) if r.get(c) not in (None, "") else ""
                if (r["region"], r["K_requested"], r["tool"]) not in done:
                    kept.append(r)
        order = {t: i for i, t in enumerate(["triangle", "gmsh-delaunay", "gmsh-frontal", "distmeshpy", "cvtmesh"])}
        rows = sorted(kept + rows, key=lambda r: (r["region"] != "circle", r["region"], r["K_requested"],
                                                  order.get(r["tool"], 99)))
    with open(os.path.join(a.out, a.name + ".csv"), "w") as f:
        f.write(",".join(cols) + "\n")
        for r in rows:
            f.write(",".join(str(r.get(c, "")) for c in cols) + "\n")
    with open(os.path.join(a.out, a.name + ".md"), "w") as f:
        f.write("| " + " | ".join(cols[:-1]) + " |\n|" + "---|" * (len(cols) - 1) + "\n")
        for r in rows:
            cells = [str(r.get(c, "")) if not isinstance(r.get(c), float) else f"{r[c]:.3g}" for c in cols[:-1]]
            f.write("| " + " | ".join(cells) + " |\n")
    print(open(os.path.join(a.out, a.name + ".md")).read())


if __name__ == "__main__":
    main()
