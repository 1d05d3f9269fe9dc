#!/usr/bin/env python3
"""nurbsgl against the mesh pipeline practitioners run for bulk queries (OCCT's BRepMesh at the same
absolute deflection as our tolerance, then CGAL's AABB tree for points and Embree for rays, both on
every core: experiments/peer_mesh_pipeline.cpp), in the same run on the same points and rays.

Per model, tolerance T (relative to the model size) and query count: the whole process of each side
(median of --repeat runs, nurbsgl with a cold cache; each side writes one file of answers: ours with
--csv, the peer with --out) and the queries alone (nurbsgl: the answering
of the points or the cast; the peer: the tree or scene queries), the ratio (mesh time / ours), and
the mesh answers' error against ours: the largest |d_mesh - d| over the deflection, and the share
of points whose mesh distance lies farther from ours than deflection + our bound (ours is certified
within its bound; the mesh pipeline's is not).

  PYTHONPATH= python3 experiments/mesh_pipeline.py --cli build/cli/nurbsgl \\
      --peer build-peer/experiments/peer_mesh_pipeline --out DIR [--points 20000 ...] [--rays 100000 ...]
      [--tol 1e-4 1e-5] [--repeat 3] [--models NAME ...]
Writes DIR/mesh_pipeline.csv and prints the table. Benchmarks, not tests.
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


def timed(args, ours_cmd, peer_cmd, env):
    """Median whole-process and query seconds of each side over args.repeat runs (ours with a cold
    cache per run), and the last runs' JSON."""
    ours, ours_q, theirs, theirs_q = [], [], [], []
    for rep in range(args.repeat):
        e = dict(env, XDG_CACHE_HOME=str(pathlib.Path(args.out) / f"cache_{time.monotonic_ns()}"))
        r, t = run(ours_cmd, e)
        j = json.loads(r.stdout)
        ours.append(t), ours_q.append(j["seconds"])
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


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cli", required=True)
    p.add_argument("--peer", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--points", type=int, nargs="+", default=[20000])
    p.add_argument("--rays", type=int, nargs="+", default=[100000])
    p.add_argument("--tol", type=float, nargs="+", default=[1e-4, 1e-5])
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--models", nargs="+", default=list(MODELS))
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for name in args.models:
        model = str(SHARED / MODELS[name])
        if not os.path.exists(model):
            print(f"{name}: {model} absent, skipped")
            continue
        lo, hi, size = info(args.cli, model)
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
            rows.append({"model": name, "query": "rays", "count": count, "tol": args.tol[0],
                         "mesh_triangles": pj["triangles"], **figures, "ours_path": j.get("method", ""),
                         "mesh_max_error_over_deflection": max(err) / deflection if err else 0.0,
                         "mesh_share_beyond": disagree / count, "ours_meet_tolerance": ""})
    with open(out / "mesh_pipeline.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]) if rows else ["model"])
        w.writeheader()
        w.writerows(rows)
    print(f"{'model':11} {'query':6} {'count':>7} {'tol':>6} {'tris':>7} {'mesh s':>8} {'ours s':>8} "
          f"{'mesh q s':>9} {'ours q s':>9} {'whole x':>8} {'query x':>8} {'max err/defl':>12} {'beyond':>7}")
    for r in rows:
        print(f"{r['model']:11} {r['query']:6} {r['count']:>7} {r['tol']:>6g} {r['mesh_triangles']:>7} "
              f"{r['mesh_whole_s']:8.2f} {r['ours_whole_s']:8.2f} {r['mesh_queries_s']:9.3f} {r['ours_queries_s']:9.3f} "
              f"{r['ratio_whole']:8.2f} {r['ratio_queries']:8.2f} {r['mesh_max_error_over_deflection']:12.1f} "
              f"{100 * r['mesh_share_beyond']:6.1f}%")
    return 0


if __name__ == "__main__":
    sys.exit(main())
