#!/usr/bin/env python3
"""Batched point distance on the shared multi-face B-rep models, OpenCASCADE beside it.

For each model (../shared/models: the Ventilator B-rep, component8, the bearing, every other multi-face
IGES file there) and each relative tolerance (1e-4, 1e-5): N random points in the model's box grown by
a fifth (fixed seed), `nurbsgl distance --points --json` as one process (points per second of the
whole process, preparation included), its CPU share (the JSON `cpu` block: walks cut short, winning
cells without material), its peak resident memory; then OpenCASCADE's projection
(`peer_occt_distance points`: GeomAPI_ProjectPointOnSurf per face, trims ignored) on the first
`--occt-points` of the same points, its rate, and the ratio; then our answers for the first
`--check-points` against OpenCASCADE's exact distance to the trimmed faces (BRepExtrema_DistShapeShape
from a vertex): how many differ by more than our bound plus the shape's tolerance. Each tolerance also
runs the paper preset (`distance --paper`: one faithful query per point) on the first --paper-points
points, a row of its own (column preset). Writes real_models.csv in OUT and prints a table. Then
clearance of each model against a copy of itself moved along x by its box width plus --gap times its
size (separated copies): `nurbsgl clearance --json` as one process (wall, and prepare + query) by
default (the default preset: the engine it chose), on the GPU, on the GPU without the face cull, and
with the paper preset (`--paper`), beside OpenCASCADE's BRepExtrema_DistShapeShape
(`peer_occt_distance shapes`: its first query, reading excluded, and its whole process);
real_models_clearance.csv. A benchmark, not a test: nothing fails on a slow figure.

Usage: experiments/real_models.py --build BUILD --out OUT [--points N] [--occt-points M] [--models ...]
       [--peer PEER]
"""
import argparse
import csv
import json
import os
import random
import subprocess
import sys

import report

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "models")
DEFAULT_MODELS = ["generated/pythonocc_Ventilator_brep.igs", "generated/gmsh_component8_brep.igs",
                  "iges/occt_bearing.iges", "iges/pythonocc_example_45_faces.iges"]


def run(cmd):
    """Runs cmd; returns (stdout, wall seconds, peak resident MB of that child, from os.wait4)."""
    code, out, err, wall, peak = report.run_measured(cmd)
    if code != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {code}: {err.strip()[-400:]}")
    return out, wall, peak


def write_points(cli, model, n, path):
    info = json.loads(subprocess.run([cli, "info", model, "--json"], capture_output=True, text=True,
                                     check=True).stdout)
    lo, hi = info["bbox"]["min"], info["bbox"]["max"]
    rng = random.Random(7)
    with open(path, "w") as f:
        for _ in range(n):
            f.write(" ".join(f"{lo[k] - 0.1 * (hi[k] - lo[k]) + rng.random() * 1.2 * (hi[k] - lo[k]):.9g}"
                             for k in range(3)) + "\n")
    return info["faces"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--points", type=int, default=20000)
    ap.add_argument("--paper-points", type=int, default=20, help="points of the paper preset (one query each)")
    ap.add_argument("--occt-points", type=int, default=500)
    ap.add_argument("--check-points", type=int, default=100,
                    help="our answers checked against OpenCASCADE's exact distance to the trimmed faces")
    ap.add_argument("--tolerances", default="1e-4,1e-5")
    ap.add_argument("--models", nargs="*", default=DEFAULT_MODELS)
    ap.add_argument("--gap", type=float, default=1.0, help="clearance: the copies' gap, times the model size")
    ap.add_argument("--clearance-tol", default="1e-5")
    ap.add_argument("--peer", help="peer_occt_distance (default: BUILD/experiments/peer_occt_distance)")
    ap.add_argument("--no-docs", action="store_true", help="leave docs/benchmarks.md and the README alone")
    a = ap.parse_args()
    cli = os.path.join(a.build, "cli", "nurbsgl")
    peer = a.peer or os.path.join(a.build, "experiments", "peer_occt_distance")
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for rel in a.models:
        model = os.path.join(ROOT, rel)
        if not os.path.exists(model):
            print(f"{rel}: absent, skipped")
            continue
        pts = os.path.join(a.out, os.path.basename(rel) + ".points.txt")
        faces = write_points(cli, model, a.points, pts)
        occt_rate, occt_trimmed = None, None
        if os.path.exists(peer):
            sub = pts + f".first{a.occt_points}"
            with open(pts) as f, open(sub, "w") as g:
                g.writelines(f.readlines()[: a.occt_points])
            out, _, _ = run([peer, "points", model, "--points", sub, "--repeat", "1", "--trimmed",
                             str(a.check_points)])
            d = json.loads(out)
            occt_rate = d["points"] / d["seconds"]
            occt_trimmed = d["trimmed"]
        paper_pts = pts + f".first{a.paper_points}"
        with open(pts) as f, open(paper_pts, "w") as g:
            g.writelines(f.readlines()[: a.paper_points])
        for tol, preset in ((t, p) for t in a.tolerances.split(",") for p in ("default", "paper")):
            paper = preset == "paper"
            options = ["--points", paper_pts, "--paper"] if paper else ["--points", pts]
            n = a.paper_points if paper else a.points
            try:
                out, wall, peak = run([cli, "distance", model, *options, "--tol", tol, "--json"])
            except RuntimeError as e:  # a failed run is a result too (the paper preset's grids may not fit)
                print(f"{rel} tol {tol} {preset}: {e}", flush=True)
                continue
            d = json.loads(out)
            cpu = d.get("cpu", {})
            rate = n / wall
            row = {"model": rel, "faces": faces, "tol": tol, "preset": d["preset"]["name"], "points": n,
                   "wall_s": round(wall, 2),
                   "prepare_s": round(d["prepare_seconds"], 2), "points_per_s": round(rate, 1),
                   "cpu_share": round(cpu.get("share", float("nan")), 4),
                   "walk_cut_short": cpu.get("walk_cut_short"), "searched_again": cpu.get("no_material_in_winning_cell"),
                   "peak_mb": round(peak), "occt_points_per_s": round(occt_rate, 1) if occt_rate else "",
                   "ratio": round(rate / occt_rate, 1) if occt_rate else "",
                   "engine": d.get("engine", {}).get("used", "")}
            if occt_trimmed:
                # Our answers against OpenCASCADE's exact distance to the trimmed faces: outside when
                # they differ by more than our bound plus the shape's tolerance.
                checked, outside, worst = 0, 0, 0.0
                for r, ref in zip(d["results"], occt_trimmed["distances"]):
                    if ref is None or not r.get("found"):
                        continue
                    checked += 1
                    err = abs(r["distance"] - ref)
                    outside += err > r["bound"] + occt_trimmed["tolerance"]
                    worst = max(worst, err / r["bound"])
                row.update({"occt_checked": checked, "outside_bound": outside,
                            "worst_error_per_bound": round(worst, 3),
                            "occt_trimmed_points_per_s": round(occt_trimmed["points"] / occt_trimmed["seconds"], 1)})
            rows.append(row)
            print("  ".join(f"{k}={v}" for k, v in row.items()), flush=True)
    write_csv(os.path.join(a.out, "real_models.csv"), rows)
    crows = []
    for rel in a.models:
        model = os.path.join(ROOT, rel)
        if not os.path.exists(model):
            continue
        info = json.loads(subprocess.run([cli, "info", model, "--json"], capture_output=True, text=True,
                                         check=True).stdout)
        lo, hi = info["bbox"]["min"], info["bbox"]["max"]
        size = sum((hi[k] - lo[k]) ** 2 for k in range(3)) ** 0.5
        move = f"{hi[0] - lo[0] + a.gap * size:.9g},0,0"
        row = {"model": rel, "faces": info["faces"], "tol": a.clearance_tol, "move_x": move.split(",")[0]}
        # The default preset (the CPU alone for small models, else the GPU), the GPU descent with the face
        # cull, without it (the paper's preparation of every face), and the paper preset.
        for name, extra in (("default", []), ("gpu", ["--engine", "gpu"]),
                            ("gpu_all_faces", ["--engine", "gpu", "--face-cull", "off"]), ("paper", ["--paper"])):
            out, wall, peak = run([cli, "clearance", model, model, "--move-b", move, "--tol", a.clearance_tol,
                                   "--json"] + extra)
            d = json.loads(out)
            row[f"distance_{name}"] = d["distance"]
            row[f"engine_{name}"] = d["engine"]["used"]
            row[f"wall_s_{name}"] = round(wall, 3)
            row[f"prepare_query_s_{name}"] = round(d["prepare_seconds"] + d["seconds"], 3)
            if name == "default":
                row["faces_kept"] = f"{d['face_cull']['faces_a']}+{d['face_cull']['faces_b']}"
        if os.path.exists(peer):
            out, wall, _ = run([peer, "shapes", model, model, "--move-b", move, "--repeat", "1"])
            d = json.loads(out)
            row["occt_distance"] = d["distance"]
            row["occt_query_s"] = round(d["first_seconds"], 3)
            row["occt_wall_s"] = round(wall, 3)
            row["ratio_query"] = round(d["first_seconds"] / row["prepare_query_s_default"], 2)
            row["ratio_wall"] = round(wall / row["wall_s_default"], 2)
        crows.append(row)
        print("  ".join(f"{k}={v}" for k, v in row.items()), flush=True)
    write_csv(os.path.join(a.out, "real_models_clearance.csv"), crows)
    if not a.no_docs and (rows or crows):
        publish(a, cli, rows, crows)
    return 0


def publish(a, cli, rows, crows):
    """docs/benchmarks.md (both tables) and the README's headline rows for distance and clearance: the
    model with the most faces that OpenCASCADE ran on, at the finest tolerance."""
    command = "experiments/real_models.py " + " ".join(sys.argv[1:])
    info = json.loads(subprocess.run([cli, "gpu-info", "--json"], capture_output=True, text=True).stdout or "{}")
    peer = any(r.get("occt_points_per_s") for r in rows)
    report.write_benchmarks("Distance and clearance on multi-face B-rep models", command, info,
                            [(f"`{n}`", report.markdown_table(t)) for n, t in
                             (("real_models.csv", rows), ("real_models_clearance.csv", crows)) if t],
                            "" if peer else "the OpenCASCADE columns")
    finest = min((float(r["tol"]) for r in rows), default=None)
    shown = [r for r in rows if r["preset"] == "default" and float(r["tol"]) == finest and r["occt_points_per_s"]]
    if shown:
        r = max(shown, key=lambda r: r["faces"])
        report.write_headline("distance from points (batched)", f"{os.path.basename(r['model'])} ({r['faces']})",
                              f"{r['points_per_s']:,.0f} points/s within {r['tol']} of the size, whole process",
                              f"{r['occt_points_per_s']:,.1f} points/s (GeomAPI_ProjectPointOnSurf)",
                              f"{r['ratio']}x faster", command)
    shown = [r for r in crows if r.get("occt_wall_s")]
    if shown:
        r = max(shown, key=lambda r: r["faces"])
        report.write_headline("clearance of two parts", f"{os.path.basename(r['model'])} ({r['faces']}) and a copy",
                              f"{r['wall_s_default']} s whole process, distance {r['distance_default']:.9g}",
                              f"{r['occt_wall_s']} s (BRepExtrema_DistShapeShape), {r['occt_distance']:.9g}",
                              f"{r['ratio_wall']}x faster", command)


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        if rows:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    sys.exit(main())
