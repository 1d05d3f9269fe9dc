#!/usr/bin/env python3
"""Rays through known points of the faces: a check of the nearest hits with an oracle.

A ray through a material point p of a face meets the model at p, so its nearest hit lies at p or
before it: an answer beyond p, or a miss, is wrong. Per model: the points `nurbsgl thickness --csv`
samples on the faces; from each, a ray along the chord to the next sample of the same face, tilted
by 0.003, 0.01, 0.03 or 0.1 (radians, random direction) so that it crosses the face there at a
shallow angle (grazing rays, where Newton's steps and float BVHs lose hits), starting 0.3 model
sizes before p. `nurbsgl raycast --method M --csv` answers them; the table counts the rays missed
and the rays answered beyond p (by more than 1e-7 of the size), per method and tilt, and of those
the ones whose p lies on its face's trim edge (`nurbsgl distance --per-point`'s on_trim_edge, by
the exact trims): the sampler puts points on the edges, where a ray may pass between two faces that
do not quite meet.

  PYTHONPATH= python3 experiments/ray_oracle.py --cli build/cli/nurbsgl --out DIR [--samples 20000]
      [--methods mesh bvh] [--models FILE ...]
Writes DIR/ray_oracle.csv and prints the table. A check, not a test: it asserts nothing.
"""
import argparse
import csv
import json
import math
import pathlib
import random
import subprocess
import sys

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "models"
MODELS = ["step/gmsh_component8.step", "generated/occt_Motor-c.step", "iges/occt_bearing.iges",
          "step/pythonocc_Ventilator.stp"]
TILTS = (0.003, 0.01, 0.03, 0.1)


def cli(args, *cmd):
    p = subprocess.run([args.cli, *cmd], capture_output=True, text=True)
    if p.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}: {p.stderr.strip()[-400:]}")
    return p.stdout


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def make_rays(samples_csv, rays_path, size):
    """Rays through the samples (ox oy oz dx dy dz per line) and each one's tilt."""
    rnd = random.Random(4)
    faces = {}
    for r in csv.DictReader(open(samples_csv)):
        faces.setdefault(r["face"], []).append([float(r[k]) for k in "xyz"])
    reach, tilts = 0.3 * size, []
    with open(rays_path, "w") as f:
        for points in faces.values():
            for p, q in zip(points, points[1:]):
                chord = [b - a for a, b in zip(p, q)]
                length = math.sqrt(sum(x * x for x in chord))
                if length == 0.0 or length > 0.05 * size:
                    continue
                tilt = rnd.choice(TILTS)
                d = unit([x / length + tilt * rnd.gauss(0, 1) for x in chord])
                if rnd.random() < 0.5:
                    d = [-x for x in d]
                o = [a - reach * b for a, b in zip(p, d)]
                f.write(" ".join(repr(x) for x in o + d) + "\n")
                tilts.append(tilt)
    return tilts


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cli", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--samples", type=int, default=20000)
    ap.add_argument("--methods", nargs="+", default=["mesh", "bvh"])
    ap.add_argument("--models", nargs="+", default=[str(SHARED / m) for m in MODELS])
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for model in args.models:
        if not pathlib.Path(model).exists():
            print(f"{model}: absent, skipped")
            continue
        name = pathlib.Path(model).name
        size = json.loads(cli(args, "info", model, "--json"))["size"]
        samples, rays = out / f"{name}.samples.csv", out / f"{name}.rays"
        cli(args, "thickness", model, "--samples", str(args.samples), "--csv", str(samples))
        tilts = make_rays(samples, rays, size)
        reach = 0.3 * size
        for method in args.methods:
            answers = out / f"{name}.{method}.csv"
            cli(args, "raycast", model, "--rays", str(rays), "--method", method, "--csv", str(answers))
            rays_in = [[float(x) for x in line.split()] for line in open(rays)]
            with open(answers) as f:
                answered = list(csv.DictReader(f))
            wrong = []  # (ray index, its point p)
            for k, r in enumerate(answered):
                if r["hit"] != "true" or float(r["t"]) > reach + 1e-7 * size:
                    o = rays_in[k]
                    wrong.append((k, [o[i] + reach * o[i + 3] for i in range(3)]))
            at_edge = set()
            if wrong:
                points = out / f"{name}.{method}.wrong.txt"
                points.write_text("".join(" ".join(repr(x) for x in p) + "\n" for _, p in wrong))
                results = json.loads(cli(args, "distance", model, "--points", str(points), "--per-point",
                                              "--json"))["results"]
                at_edge = {k for (k, _), r in zip(wrong, results) if r["on_trim_edge"]}
            for tilt in TILTS:
                missed = beyond = count = edge = 0
                for k, (r, t) in enumerate(zip(answered, tilts)):
                    if t != tilt:
                        continue
                    count += 1
                    missed += r["hit"] != "true"
                    beyond += r["hit"] == "true" and float(r["t"]) > reach + 1e-7 * size
                    edge += k in at_edge
                rows.append({"model": name, "method": method, "tilt": tilt, "rays": count, "missed": missed,
                             "beyond": beyond, "at_trim_edge": edge})
    with open(out / "ray_oracle.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["model", "method", "tilt", "rays", "missed", "beyond", "at_trim_edge"])
        w.writeheader()
        w.writerows(rows)
    print(f"{'model':28} {'method':6} {'tilt':>6} {'rays':>6} {'missed':>7} {'beyond':>7} {'at edge':>8}")
    for r in rows:
        print(f"{r['model']:28} {r['method']:6} {r['tilt']:>6} {r['rays']:>6} {r['missed']:>7} {r['beyond']:>7}"
              f" {r['at_trim_edge']:>8}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
