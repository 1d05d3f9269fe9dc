#!/usr/bin/env python3
"""nurbsgl against the mesh pipeline practitioners run for bulk queries (OCCT's BRepMesh at the same
absolute deflection as our tolerance, then CGAL's AABB tree for points, Embree for rays and
thickness, FCL for clearance: experiments/peer_mesh_pipeline.cpp), in the same run on the same
queries, with OpenCASCADE's exact clearance (experiments/peer_occt_distance.cpp) beside them.

Per model, tolerance T (relative to the model size) and query count: the whole process of each side
(median of --repeat runs, nurbsgl with a cold cache; each side writes one file of answers: ours with
--csv, the peer with --out) and the queries alone (nurbsgl: the answering of the points, the cast,
the clearance's preparation and query; the peer: the tree or scene queries, FCL's distance), the
ratio (mesh time / ours), and the mesh answers' error against ours:
  - points: the largest |d_mesh - d| over the deflection, and the share of points whose mesh
    distance lies farther from ours than deflection + our bound (ours is certified within its
    bound; the mesh pipeline's is not);
  - rays: the largest |t_mesh - t| over the deflection, and the share of rays one side hits and the
    other misses;
  - thickness (as many samples on each side, ours on the faces, the peer's on its mesh, each ray
    inward): both sides' thinnest and median wall, and the share of the peer's samples thinner than
    half our thinnest (walls the mesh makes up at its own creases);
  - with --floor (experiments/bench_ray_floor.cpp), beside each rays row: one Embree traversal of
    our certified mesh per ray, plain and of the slab scene the mesh method casts into, the least
    our certified hits cost before any Newton step, against the mesh pipeline's whole query;
  - clearance (the model against a copy moved along x by its box width plus its size): |d_mesh -
    d| over the deflection, and OpenCASCADE's BRepExtrema_DistShapeShape, its time and its distance.

  PYTHONPATH= python3 experiments/mesh_pipeline.py --cli build/cli/nurbsgl \\
      --peer build-bench/experiments/peer_mesh_pipeline [--occt build-bench/experiments/peer_occt_distance] \\
      [--floor build-bench/experiments/bench_ray_floor] --out DIR [--points 20000 ...] [--rays 100000 ...]
      [--thickness 100000 ...]
      [--tol 1e-4 1e-5] [--repeat 3] [--models NAME ...]
Writes DIR/mesh_pipeline.csv, prints the table, and (unless --no-docs) puts the table in
docs/benchmarks.md and the README's headline rows for points and rays against the mesh pipeline (the
model with the most faces, the most queries, the finest tolerance). Benchmarks, not tests.
"""
import argparse
import csv
import json
import os
import pathlib
import random
import statistics
import subprocess
import sys
import time

import report

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "models"
MODELS = {
    "Ventilator": "step/pythonocc_Ventilator.stp",
    "component8": "step/gmsh_component8.step",
    "motor": "generated/occt_Motor-c.step",
    "bearing": "iges/occt_bearing.iges",
}


def run(cmd, env=None):
    t = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if not p.stdout.strip():
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}, no output; {p.stderr.strip()[-400:]}")
    return p, time.perf_counter() - t


def info(cli, model):
    j = json.loads(run([cli, "info", model, "--json"])[0].stdout)
    return j["bbox"]["min"], j["bbox"]["max"], j["size"]


def write_points(path, lo, hi, n, seed):
    rnd = random.Random(seed)
    pad = [0.1 * (h - l) for l, h in zip(lo, hi)]
    with open(path, "w") as f:
        for _ in range(n):
            f.write(" ".join(f"{rnd.uniform(l - p, h + p):.9f}" for l, h, p in zip(lo, hi, pad)) + "\n")


def write_rays(path, lo, hi, n, seed):
    """Rays from above the box's top, down through it with a small tilt."""
    rnd = random.Random(seed)
    top = hi[2] + 0.2 * (hi[2] - lo[2]) + 1.0
    with open(path, "w") as f:
        for _ in range(n):
            x, y = rnd.uniform(lo[0], hi[0]), rnd.uniform(lo[1], hi[1])
            f.write(f"{x:.9f} {y:.9f} {top:.9f} {rnd.uniform(-.1, .1):.6f} {rnd.uniform(-.1, .1):.6f} -1\n")


def timed(args, ours_cmd, peer_cmd, env, ours_seconds=lambda j: j["seconds"]):
    """Median whole-process and query seconds of each side over args.repeat runs (ours with a cold
    cache per run; our query seconds read from its JSON by ours_seconds), and the last runs' JSON."""
    ours, ours_q, theirs, theirs_q = [], [], [], []
    for rep in range(args.repeat):
        e = dict(env, XDG_CACHE_HOME=str(pathlib.Path(args.out) / f"cache_{time.monotonic_ns()}"))
        r, t = run(ours_cmd, e)
        j = json.loads(r.stdout)
        ours.append(t), ours_q.append(ours_seconds(j))
        r, t = run(peer_cmd)
        pj = json.loads(r.stdout)
        theirs.append(t), theirs_q.append(pj["query_seconds"])
    m = statistics.median
    return {"mesh_whole_s": m(theirs), "ours_whole_s": m(ours), "mesh_queries_s": m(theirs_q),
            "ours_queries_s": m(ours_q), "ratio_whole": m(theirs) / m(ours),
            "ratio_queries": m(theirs_q) / m(ours_q)}, j, pj


def read_column(path, column):
    with open(path) as f:
        return [float(r[column]) if r[column] != "" else None for r in csv.DictReader(f)]


def publish(args, rows, faces):
    """docs/benchmarks.md's section of this run, and the README's headline rows for points and rays."""
    # The command as a reader runs it: the peers where bench.sh builds them, DIR for the output.
    generic = {"--peer": "build-bench/experiments/peer_mesh_pipeline",
               "--occt": "build-bench/experiments/peer_occt_distance",
               "--floor": "build-bench/experiments/bench_ray_floor", "--out": "DIR"}
    words = sys.argv[1:]
    words = [generic.get(words[i - 1], w) if i > 0 else w for i, w in enumerate(words)]
    command = "experiments/mesh_pipeline.py " + " ".join(words)
    gl = json.loads(subprocess.run([args.cli, "gpu-info", "--json"], capture_output=True, text=True).stdout or "{}")
    shown = [{k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()} for r in rows]
    report.write_benchmarks("Against the mesh pipeline", command, gl,
                            [(f"`mesh_pipeline.csv`: {', '.join(map(str, args.points)) or 'no'} points, "
                              f"{', '.join(map(str, args.rays)) or 'no'} rays, "
                              f"{', '.join(map(str, args.thickness)) or 'no'} thickness samples",
                              report.markdown_table(shown))],
                            "" if args.occt else "OpenCASCADE's clearance")
    for query, what, peer_tool in (("points", "distance from points", "BRepMesh + CGAL AABB tree"),
                                   ("rays", "ray casting", "BRepMesh + Embree")):
        mine = [r for r in rows if r["query"] == query]
        if not mine:
            continue
        finest = min(r["tol"] for r in mine) if query == "points" else mine[0]["tol"]
        r = max((r for r in mine if r["tol"] == finest), key=lambda r: (faces[r["model"]], r["count"]))
        report.write_headline(
            f"{what} (against the mesh pipeline)", f"{r['model']} ({faces[r['model']]})",
            f"{r['count']:,} {query}, " + (f"within {r['tol']:g} of the size" if query == "points" else "exact hits") +
            f" (certified): {r['ours_whole_s']:.2f} s whole, "
            f"{r['ours_queries_s']:.3f} s queries",
            f"{r['mesh_whole_s']:.2f} s whole, {r['mesh_queries_s']:.3f} s queries ({peer_tool}, deflection "
            f"{r['tol']:g} of the size, uncertified)",
            f"{r['ratio_whole']:.2f}x whole, {r['ratio_queries']:.2f}x per query", command)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cli", required=True)
    p.add_argument("--peer", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--points", type=int, nargs="*", default=[20000], help="points (none: no point rows)")
    p.add_argument("--rays", type=int, nargs="*", default=[100000], help="rays (none: no ray rows)")
    p.add_argument("--thickness", type=int, nargs="*", default=[100000], help="samples (none: no thickness rows)")
    p.add_argument("--no-clearance", action="store_true")
    p.add_argument("--occt", help="peer_occt_distance: OpenCASCADE's exact clearance beside the mesh's")
    p.add_argument("--floor", help="bench_ray_floor: one Embree traversal of our certified mesh per ray, beside "
                                   "the rays rows (the least our mesh method spends before its exact hits)")
    p.add_argument("--no-docs", action="store_true", help="leave docs/benchmarks.md and the README alone")
    p.add_argument("--tol", type=float, nargs="+", default=[1e-4, 1e-5])
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--models", nargs="+", default=list(MODELS))
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows, faces = [], {}
    for name in args.models:
        model = str(SHARED / MODELS[name])
        if not os.path.exists(model):
            print(f"{name}: {model} absent, skipped")
            continue
        lo, hi, size = info(args.cli, model)
        faces[name] = json.loads(run([args.cli, "info", model, "--json"])[0].stdout)["faces"]
        for count in args.points:
            pts = out / f"{name}_points_{count}.txt"
            write_points(pts, lo, hi, count, 1)
            for tol in args.tol:
                deflection = tol * size
                ours_csv, mesh_txt = out / "ours_d.csv", out / "mesh_d.txt"
                figures, j, pj = timed(
                    args, [args.cli, "distance", model, "--points", str(pts), "--tol", str(tol), "--json", "--csv",
                           str(ours_csv)],
                    [args.peer, model, "--deflection", str(deflection), "--points", str(pts), "--out", str(mesh_txt)],
                    os.environ)
                d, b = read_column(ours_csv, "distance"), read_column(ours_csv, "bound")
                with open(ours_csv) as f:
                    meets = sum(1 for r in csv.DictReader(f) if r["meets_tolerance"] == "true")
                dm = [float(x) for x in open(mesh_txt)]
                err = [abs(a - c) for a, c in zip(dm, d) if c is not None]
                beyond = sum(1 for a, c, k in zip(dm, d, b) if c is not None and abs(a - c) > deflection + k)
                rows.append({"model": name, "query": "points", "count": count, "tol": tol,
                             "mesh_triangles": pj["triangles"], **figures, "ours_path": j.get("path", ""),
                             "mesh_max_error_over_deflection": max(err) / deflection if err else 0.0,
                             "mesh_share_beyond": beyond / max(len(err), 1), "ours_meet_tolerance": meets / count})
        # Rays: the hits are exact on both sides' terms; the mesh at the first tolerance's deflection.
        deflection = args.tol[0] * size
        for count in args.rays:
            rays = out / f"{name}_rays_{count}.txt"
            write_rays(rays, lo, hi, count, 2)
            ours_csv, mesh_txt = out / "ours_t.csv", out / "mesh_t.txt"
            figures, j, pj = timed(
                args, [args.cli, "raycast", model, "--rays", str(rays), "--json", "--csv", str(ours_csv)],
                [args.peer, model, "--deflection", str(deflection), "--rays", str(rays), "--out", str(mesh_txt)],
                os.environ)
            tm = [float(x) for x in open(mesh_txt)]
            tn = [x if x is not None else -1.0 for x in read_column(ours_csv, "t")]
            both = [(a, c) for a, c in zip(tm, tn) if a >= 0 and c >= 0]
            err = [abs(a - c) for a, c in both]
            disagree = sum(1 for a, c in zip(tm, tn) if (a >= 0) != (c >= 0))
            row = {"model": name, "query": "rays", "count": count, "tol": args.tol[0],
                   "mesh_triangles": pj["triangles"], **figures, "ours_path": j.get("method", ""),
                   "mesh_max_error_over_deflection": max(err) / deflection if err else 0.0,
                   "mesh_share_beyond": disagree / count, "ours_meet_tolerance": ""}
            if args.floor:
                fj = json.loads(run([args.floor, model, "--rays", str(rays), "--repeat", str(args.repeat)])[0].stdout)
                row.update({"ours_one_traversal_s": fj["plain_seconds"], "ours_slab_traversal_s": fj["slab_seconds"],
                            "ours_mesh_triangles": fj["triangles"],
                            "ratio_one_traversal": figures["mesh_queries_s"] / fj["plain_seconds"]})
            rows.append(row)
        for count in args.thickness:
            ours_csv, mesh_txt = out / "ours_w.csv", out / "mesh_w.txt"
            # The peer casts as many rays as our sampling made (--samples is "about").
            j0 = json.loads(run([args.cli, "thickness", model, "--samples", str(count), "--json"])[0].stdout)
            figures, j, pj = timed(
                args, [args.cli, "thickness", model, "--samples", str(count), "--json", "--csv", str(ours_csv)],
                [args.peer, model, "--deflection", str(deflection), "--thickness", str(j0["rays"]), "--out",
                 str(mesh_txt)], os.environ, ours_seconds=lambda j: j["seconds_cast"])
            wm = sorted(float(x) for x in open(mesh_txt) if float(x) >= 0)
            ours_min = j["thickness"]["min"]
            rows.append({"model": name, "query": "thickness", "count": j["rays"], "tol": args.tol[0],
                         "mesh_triangles": pj["triangles"], **figures, "ours_path": j.get("method", ""),
                         "mesh_max_error_over_deflection": "",
                         "mesh_share_beyond": sum(1 for x in wm if x < 0.5 * ours_min) / max(len(wm), 1),
                         "ours_meet_tolerance": "", "ours_min": ours_min, "mesh_min": wm[0] if wm else "",
                         "ours_median": j["thickness"]["median"], "mesh_median": wm[len(wm) // 2] if wm else ""})
        if args.no_clearance:
            continue
        move = f"{hi[0] - lo[0] + size:.9g},0,0"
        for tol in args.tol:
            deflection = tol * size
            figures, j, pj = timed(
                args, [args.cli, "clearance", model, model, "--move-b", move, "--tol", str(tol), "--json"],
                [args.peer, model, "--deflection", str(deflection), "--clearance", move], os.environ,
                ours_seconds=lambda j: j["prepare_seconds"] + j["seconds"])
            row = {"model": name, "query": "clearance", "count": 1, "tol": tol, "mesh_triangles": pj["triangles"],
                   **figures, "ours_path": j["engine"]["used"],
                   "mesh_max_error_over_deflection": abs(pj["distance"] - j["distance"]) / deflection,
                   "mesh_share_beyond": float(abs(pj["distance"] - j["distance"]) > deflection + j["bound"]),
                   "ours_meet_tolerance": float(j["meets_tolerance"]), "ours_distance": j["distance"],
                   "ours_bound": j["bound"], "mesh_distance": pj["distance"]}
            if args.occt and tol == args.tol[0]:
                r, wall = run([args.occt, "shapes", model, model, "--move-b", move, "--repeat", "1"])
                oj = json.loads(r.stdout)
                row.update({"occt_whole_s": wall, "occt_query_s": oj["first_seconds"], "occt_distance": oj["distance"]})
            rows.append(row)
    fields = []
    for r in rows:
        fields += [k for k in r if k not in fields]
    with open(out / "mesh_pipeline.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields or ["model"])
        w.writeheader()
        w.writerows(rows)
    print(f"{'model':11} {'query':9} {'count':>7} {'tol':>6} {'tris':>7} {'mesh s':>8} {'ours s':>8} "
          f"{'mesh q s':>9} {'ours q s':>9} {'whole x':>8} {'query x':>8} {'max err/defl':>12} {'beyond':>7}")
    for r in rows:
        err = r["mesh_max_error_over_deflection"]
        print(f"{r['model']:11} {r['query']:9} {r['count']:>7} {r['tol']:>6g} {r['mesh_triangles']:>7} "
              f"{r['mesh_whole_s']:8.2f} {r['ours_whole_s']:8.2f} {r['mesh_queries_s']:9.4f} {r['ours_queries_s']:9.4f} "
              f"{r['ratio_whole']:8.2f} {r['ratio_queries']:8.2f} {err if err == '' else f'{err:.1f}':>12} "
              f"{100 * r['mesh_share_beyond']:6.1f}%")
        if r["query"] == "thickness":
            print(f"{'':11} thinnest: ours {r['ours_min']:.6g}, mesh {r['mesh_min']:.6g}; median: ours "
                  f"{r['ours_median']:.6g}, mesh {r['mesh_median']:.6g}")
        if "ours_one_traversal_s" in r:
            print(f"{'':11} one traversal of our mesh ({r['ours_mesh_triangles']} triangles): "
                  f"{r['ours_one_traversal_s']:.4f} s plain, {r['ours_slab_traversal_s']:.4f} s of the slabs; "
                  f"mesh query / one plain traversal {r['ratio_one_traversal']:.2f}x")
        if "occt_distance" in r:
            print(f"{'':11} OpenCASCADE: {r['occt_distance']:.12g} in {r['occt_query_s']:.4f} s "
                  f"({r['occt_whole_s']:.2f} s whole); ours {r['ours_distance']:.12g} +- {r['ours_bound']:.3g}, "
                  f"mesh {r['mesh_distance']:.12g}")
    if rows and not args.no_docs:
        publish(args, rows, faces)
    return 0


if __name__ == "__main__":
    sys.exit(main())
