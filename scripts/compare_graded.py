"""Graded meshes side by side: cvtmesh against Gmsh Frontal-Delaunay with the same size field
(Gmsh's Distance + Threshold, cvtmesh's --size-toward/--size-threshold) at the same vertex
count, scored by `cvtmesh measure --size-toward ...` (unit share, efficiency, angles).

Gmsh is timed around `gmsh.model.mesh.generate` only, after calibration runs that scale the
sizes to hit K (its count goes as size^-2), so its time includes evaluating its fields;
cvtmesh is timed as the whole command and as the seconds it prints (building the size field
and meshing, without reading the region or writing the file). Run through
scripts/compare_graded.sh.
"""
import argparse, csv, json, math, os, re, shlex, statistics, subprocess, sys, time
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_tools import loops_of, write_node_ele, gmsh_generate  # noqa: E402

# name, region, toward (cvtmesh syntax), size ratio hmax/hmin, (dmin, dmax). Distances are in
# the region's own coordinates, as both Gmsh and cvtmesh read them. The lake is in map units
# (about 530 x 650, area 124 889, its deepest point 106 from any shore), so its band is 0-35,
# about 0.1 sqrt(area): two thirds of the lake lies in the graded band, the rest at hmax.
CASES = {
    "circle-point": ("circle", ["point:0,0"], 11.0, (0.0, 1.0)),
    "l-corner": ("l_shape", ["point:0.5,0.5"], 30.0, (0.0, 0.7)),
    "square_hole-hole": ("square_hole", ["loop:1"], 10.0, (0.02, 0.6)),
    "lake-shores": ("lake", None, 5.0, (0.0, 35.0)),
}
DEFAULT_CASES = "circle-point,l-corner,square_hole-hole,lake-shores"
# cvtmesh mesh limits a size field's gradient to this by default (`--gradation`); Gmsh does not.
CVTMESH_GRADATION = 0.3
CONFORMITY = "edges,unit_share,efficiency,mean_length,min_angle_deg,min_angle_p1_deg,vertices,predicted_vertices".split(",")


def region_file(domains, extra, region):
    for d in (domains, extra):
        for ext in (".json", ".txt"):
            f = os.path.join(d, region + ext)
            if os.path.exists(f):
                return f
    raise SystemExit(f"compare_graded: no file for region {region}")


def loops_from(path, h):
    if path.endswith(".txt"):
        pts = np.loadtxt(path)
        return {"loops": [{"segments": [{"kind": "polyline"}]}]}, [pts]
    return loops_of(path, h)


def region_area(path):
    if path.endswith(".txt"):
        x, y = np.loadtxt(path).T
        return abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))) / 2
    return float(json.load(open(path))["area"])


def toward_all_loops(path):
    if path.endswith(".txt"):
        return ["loop:0"]
    return [f"loop:{i}" for i in range(len(json.load(open(path))["loops"]))]


def gmsh_mesh(path, toward, hmin, ratio, dists):
    import gmsh
    d, loops = loops_from(path, hmin)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("m")
    curve_loops, loop_curves = [], []
    for i, lp in enumerate(loops):
        seg = d["loops"][i]["segments"]
        if len(seg) == 1 and seg[0]["kind"] == "circle":
            c, r = seg[0]["center"], seg[0]["radius"]
            curves = [gmsh.model.occ.addCircle(c[0], c[1], 0, r)]
        else:
            pts = [gmsh.model.occ.addPoint(x, y, 0) for x, y in lp]
            curves = [gmsh.model.occ.addLine(pts[j], pts[(j + 1) % len(pts)]) for j in range(len(pts))]
        curve_loops.append(gmsh.model.occ.addCurveLoop(curves))
        loop_curves.append(curves)
    gmsh.model.occ.addPlaneSurface(curve_loops)
    gmsh.model.occ.synchronize()
    dist = gmsh.model.mesh.field.add("Distance")
    points, curves = [], []
    for t in toward:
        kind, rest = t.split(":")
        if kind == "point":
            x, y = map(float, rest.split(","))
            points.append(gmsh.model.occ.addPoint(x, y, 0))
        else:
            curves += loop_curves[int(rest)]
    gmsh.model.occ.synchronize()
    if points:
        gmsh.model.mesh.field.setNumbers(dist, "PointsList", points)
    if curves:
        gmsh.model.mesh.field.setNumbers(dist, "CurvesList", curves)
        gmsh.model.mesh.field.setNumber(dist, "Sampling", 200)
    th = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(th, "InField", dist)
    gmsh.model.mesh.field.setNumber(th, "SizeMin", hmin)
    gmsh.model.mesh.field.setNumber(th, "SizeMax", ratio * hmin)
    gmsh.model.mesh.field.setNumber(th, "DistMin", dists[0])
    gmsh.model.mesh.field.setNumber(th, "DistMax", dists[1])
    gmsh.model.mesh.field.setAsBackgroundMesh(th)
    for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber("Mesh." + opt, 0)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    return gmsh_generate(gmsh)


def field_args(toward, hmin, ratio, dists):
    args = []
    for t in toward:
        args += ["--size-toward", t]
    return args + ["--size-threshold", f"{hmin!r},{ratio * hmin!r},{dists[0]!r},{dists[1]!r}"]


def mesh_field_args(toward, hmin, ratio, dists):
    # A steeper threshold than cvtmesh's gradation limit would be flattened by the mesher (and
    # not by `measure`), so cvtmesh would mesh another field than Gmsh's: lift the limit then.
    steep = (ratio - 1) * hmin / (dists[1] - dists[0]) > CVTMESH_GRADATION
    return field_args(toward, hmin, ratio, dists) + (["--gradation", "inf"] if steep else [])


def measure(exe, mesh, region, fargs):
    # Against the field as handed to both tools: `measure` limits its gradient as `mesh` does
    # unless told not to.
    out = subprocess.run([exe, "measure", mesh, "--region", region, "--csv", "--gradation", "inf"] + fargs,
                         capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(out.stderr)
    lines = out.stdout.strip().splitlines()
    return dict(zip(lines[-2].split(","), map(float, lines[-1].split(","))))


def write_tables(out, rows):
    with open(os.path.join(out, "graded.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["case", "K", "tool", "seed", "seconds", "mesher_seconds", "iterations", "note"] + CONFORMITY)
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in w.fieldnames})
    with open(os.path.join(out, "graded.md"), "w") as f:
        f.write("| case | K | tool | seed | seconds (mesher) | × Gmsh | iterations | vertices | unit share | efficiency | min angle | 1st pct angle |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        gmsh = {(r["case"], r["K"]): r["mesher_seconds"] for r in rows if r["tool"] == "gmsh-frontal"}
        for r in rows:
            ratio = "" if r["tool"] == "gmsh-frontal" else f"{r['mesher_seconds'] / gmsh[r['case'], r['K']]:.1f}"
            tool = r["tool"] + (" (not converged)" if r.get("note") == "not converged" else "")
            f.write(f"| {r['case']} | {r['K']} | {tool} | {r.get('seed', '')} | {r['seconds']:.2f} ({r['mesher_seconds']:.2f}) | {ratio} | "
                    f"{r.get('iterations', '')} | {r['vertices']:.0f} | "
                    f"{r['unit_share']:.3f} | {r['efficiency']:.3f} | {r['min_angle_deg']:.1f} | {r['min_angle_p1_deg']:.1f} |\n")
        # One CCVT run's length moves with its seed (by 2× and more at 10⁴): the median over
        # the seeds is the ratio to quote.
        f.write("\n| case | K | seeds | median seconds (mesher) | median × Gmsh | iterations |\n|---|---|---|---|---|---|\n")
        keys = dict.fromkeys((r["case"], r["K"]) for r in rows if r["tool"] == "cvtmesh")
        for key in keys:
            runs = [r for r in rows if r["tool"] == "cvtmesh" and (r["case"], r["K"]) == key]
            med = statistics.median(r["mesher_seconds"] for r in runs)
            its = sorted(r["iterations"] for r in runs)
            f.write(f"| {key[0]} | {key[1]} | {len(runs)} | {med:.2f} | {med / gmsh[key]:.1f} | {its[0]}–{its[-1]} |\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cvtmesh", required=True)
    ap.add_argument("--domains", required=True)
    ap.add_argument("--regions-extra", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--sizes", default="10000,100000")
    ap.add_argument("--cases", default=DEFAULT_CASES,
                    help="comma-separated, of " + ",".join(CASES))
    ap.add_argument("--seeds", type=int, default=1,
                    help="run cvtmesh with --seed 1..N (each run a row; the median is summarised)")
    ap.add_argument("--cvtmesh-args", default="",
                    help="more arguments for `cvtmesh mesh`, e.g. '--tol 1e-3'")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for case in a.cases.split(","):
        region, toward, ratio, dists = CASES[case]
        path = region_file(a.domains, a.regions_extra, region)
        toward = toward or toward_all_loops(path)
        # The first guess comes from the region's area, not from a uniform Gmsh mesh at a fixed
        # size: such a mesh of the lake at h = 0.05 would have had some 60 million vertices.
        area = region_area(path)
        for k in map(int, a.sizes.split(",")):
            # A first guess, then corrections (Gmsh's count goes as hmin^-2); the last run is
            # the one timed and kept.
            hmin = math.sqrt(2 * area / (math.sqrt(3) * k)) / math.sqrt(ratio)
            for _ in range(5):
                p, t, sec = gmsh_mesh(path, toward, hmin, ratio, dists)
                if abs(len(p) - k) <= 0.005 * k:
                    break
                hmin *= math.sqrt(len(p) / k)
            base = os.path.join(a.out, f"{case}_{k}_gmsh")
            write_node_ele(base, p, t)
            fargs = field_args(toward, hmin, ratio, dists)
            m = measure(a.cvtmesh, base + ".node", path, fargs)
            rows.append(dict(case=case, K=k, tool="gmsh-frontal", seconds=sec, mesher_seconds=sec, **m))
            print(f"{case} {k} gmsh: {len(p)} vertices {sec:.2f}s", file=sys.stderr)
            margs = mesh_field_args(toward, hmin, ratio, dists)
            for seed in range(1, a.seeds + 1):
                base = os.path.join(a.out, f"{case}_{k}_cvtmesh" + (f"_seed{seed}" if a.seeds > 1 else ""))
                t0 = time.perf_counter()
                out = subprocess.run([a.cvtmesh, "mesh", path, "--points", str(k), "--quiet", "--seed", str(seed), "-o", base + ".node"] + margs
                                     + shlex.split(a.cvtmesh_args),
                                     capture_output=True, text=True)
                whole = time.perf_counter() - t0
                if out.returncode != 0:
                    raise SystemExit(out.stderr)
                line = out.stdout.strip().splitlines()[-1]
                own = float(line.split()[-3].rstrip("s"))
                iterations = int(re.search(r"iterations=(\d+)", line).group(1))
                for w in out.stderr.splitlines():
                    if w.startswith("note:"):
                        print(f"{case} {k} cvtmesh {w}", file=sys.stderr)
                asked = next(float(w.split("(")[1].split()[0]) for w in out.stderr.split("\n") if "asked for by the field" in w)
                # With --points the field is scaled to K: measure against the scaled field.
                scaled = field_args(toward, hmin * math.sqrt(asked / k), ratio, dists)
                m = measure(a.cvtmesh, base + ".node", path, scaled)
                state = "converged" if line.endswith(".node") and "NOT CONVERGED" not in line else "not converged"
                rows.append(dict(case=case, K=k, tool="cvtmesh", seed=seed, seconds=whole, mesher_seconds=own, iterations=iterations,
                                 note=state, **m))
                print(f"{case} {k} cvtmesh seed {seed}: {line}", file=sys.stderr)
            write_tables(a.out, rows)


if __name__ == "__main__":
    main()
