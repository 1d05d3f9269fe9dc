#!/usr/bin/env python3
"""Points per second through the Python module and through Dask, the command line beside them, and the
clash report of an assembly against a loop of `clearance` runs; one run, one machine, figures
written to OUT/python_scale.csv and printed.

  points   N random points in a model's box: `nurbsgl distance --points` (whole process, and its
           own query time), nurbsgl.load + Model.distance in this process (first call with its
           preparation, second call prepared), nurbsgl.dask.distance on a LocalCluster of W worker
           processes (cluster started beforehand; the call's wall time, which includes each worker's
           load and preparation). The answers of Python and Dask are compared with the CLI's, bit for
           bit.
  clash    `nurbsgl clash ASSEMBLY`, nurbsgl.clash, nurbsgl.dask.clash on W workers, and a shell-style
           loop of `nurbsgl clearance --body-a I --body-b J` over the pairs (one process each).

Run with the build tree's package on the path:
  PYTHONPATH=build/python python3 experiments/python_scale.py --cli build/cli/nurbsgl --out OUT \\
      [--model M] [--points N] [--assembly A] [--workers W]
Benchmarks, not tests: nothing here fails on a slow figure.
"""
import argparse
import csv
import json
import os
import pathlib
import subprocess
import sys
import time

import numpy as np


def timed(f):
    t = time.perf_counter()
    r = f()
    return r, time.perf_counter() - t


def model_box(cli, model):
    info = json.loads(subprocess.run([cli, "info", model, "--json"], check=True, capture_output=True,
                                     text=True).stdout)
    return np.array(info["bbox"]["min"]), np.array(info["bbox"]["max"])


def points_rows(args, client, rows):
    import nurbsgl
    import nurbsgl.dask
    lo, hi = model_box(args.cli, args.model)
    pad = 0.1 * (hi - lo)
    pts = np.random.default_rng(1).uniform(lo - pad, hi + pad, size=(args.points, 3))
    path = pathlib.Path(args.out) / "points.txt"
    np.savetxt(path, pts, fmt="%.17g")
    env = dict(os.environ, XDG_CACHE_HOME=str(pathlib.Path(args.out) / "cache"))
    out, t_cli = timed(lambda: subprocess.run([args.cli, "distance", args.model, "--points", str(path), "--tol",
                                               str(args.tol), "--json"], capture_output=True, text=True, env=env))
    j = json.loads(out.stdout)
    ref = np.array([r["distance"] if r["found"] else np.nan for r in j["results"]])
    n = args.points
    rows.append(("points", "cli distance --points (whole process)", n, t_cli, n / t_cli, ""))
    rows.append(("points", "cli distance --points (queries)", n, j["seconds"], n / j["seconds"], ""))
    model, t_load = timed(lambda: nurbsgl.load(args.model))
    first, t_first = timed(lambda: model.distance(pts, tol=args.tol))
    second, t_second = timed(lambda: model.distance(pts, tol=args.tol))
    same = np.array_equal(first.distance, ref, equal_nan=True)
    rows.append(("points", "python load + first distance (prepares)", n, t_load + t_first, n / (t_load + t_first),
                 f"equal to cli: {same}"))
    rows.append(("points", "python distance, prepared", n, t_second, n / t_second, ""))
    r, t_dask = timed(lambda: nurbsgl.dask.distance(client, args.model, pts, tol=args.tol))
    rows.append(("points", f"dask distance, {args.workers} workers (loads and prepares on each)", n, t_dask,
                 n / t_dask, f"equal to cli: {np.array_equal(r.distance, ref, equal_nan=True)}, {r.chunks} chunks"))
    r, t_dask2 = timed(lambda: nurbsgl.dask.distance(client, args.model, pts, tol=args.tol))
    rows.append(("points", f"dask distance, {args.workers} workers, prepared", n, t_dask2, n / t_dask2, ""))


def clash_rows(args, client, rows):
    import nurbsgl
    import nurbsgl.dask
    out, t_cli = timed(lambda: subprocess.run([args.cli, "clash", args.assembly, "--tol", str(args.tol), "--json"],
                                              capture_output=True, text=True))
    j = json.loads(out.stdout)
    pairs = j["pairs"]
    rows.append(("clash", "cli clash (whole process)", pairs, t_cli, pairs / t_cli, f"exit {out.returncode}"))
    model = nurbsgl.load(args.assembly)
    r, t_py = timed(lambda: nurbsgl.clash(model, tol=args.tol))
    rows.append(("clash", "python clash", pairs, t_py, pairs / t_py, ""))
    r, t_dask = timed(lambda: nurbsgl.dask.clash(client, args.assembly, tol=args.tol))
    rows.append(("clash", f"dask clash, {args.workers} workers", pairs, t_dask, pairs / t_dask, f"{r.shards} shards"))
    # A loop of one clearance process per pair, as a shell script would run them (a sample of pairs,
    # scaled to all).
    sample = [(x["body_a"], x["body_b"]) for x in j["results"]][:args.loop_pairs]
    t0 = time.perf_counter()
    for a, b in sample:
        subprocess.run([args.cli, "clearance", args.assembly, args.assembly, "--body-a", str(a), "--body-b", str(b),
                        "--tol", str(args.tol)], capture_output=True)
    t_loop = (time.perf_counter() - t0) * pairs / max(len(sample), 1)
    rows.append(("clash", f"loop of clearance processes ({len(sample)} run, scaled)", pairs, t_loop,
                 pairs / t_loop, ""))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cli", required=True)
    p.add_argument("--out", required=True)
    shared = pathlib.Path(__file__).resolve().parents[2] / "shared" / "models"
    p.add_argument("--model", default=str(shared / "step" / "pythonocc_Ventilator.stp"))
    p.add_argument("--assembly", default=str(shared / "assembly" / "gmsh_as1-tu-203.stp"))
    p.add_argument("--points", type=int, default=200_000)
    p.add_argument("--tol", type=float, default=1e-4)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--loop-pairs", type=int, default=20)
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    import distributed
    rows = []
    with distributed.LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                                  dashboard_address=None, silence_logs=40) as cluster, distributed.Client(cluster) as client:
        if os.path.exists(args.model):
            points_rows(args, client, rows)
        if os.path.exists(args.assembly):
            clash_rows(args, client, rows)
    with open(pathlib.Path(args.out) / "python_scale.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["job", "how", "items", "seconds", "items_per_second", "note"])
        w.writerows(rows)
    for job, how, n, s, rate, note in rows:
        print(f"{job:6} {how:62} {n:>9} {s:9.3f} s {rate:12.0f}/s  {note}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
