#!/usr/bin/env python3
"""STEP input on the shared STEP files, OpenCASCADE's STEP reader and the IGES twins beside it.

For every STEP file under ../shared/models (step/, assembly/, generated/*.step):
- read: faces, bodies and trim problems (`nurbsgl info --json`), the in-process read time (bench_read,
  the fastest of --repeat reads) and OpenCASCADE's read + transfer (`peer_occt_step read`, the fastest
  of as many), their ratio, OpenCASCADE's face count and total face area;
- tessellation: `nurbsgl tessellate --eps 1e-3 --relative --watertight` of the STEP file and of its
  IGES twin (the same model written by OpenCASCADE's IGES writer), the meshes' areas beside
  OpenCASCADE's exact area, and the open edges of the STEP mesh; beside it the paper preset
  (`tessellate --paper`: each face on its own, no watertight step): its area and open edges;
- distance: --points random points in the box grown by a fifth (fixed seed), `nurbsgl distance
  --points --json` on the STEP file and on its twin: the largest difference of the two answers over
  the sum of their bounds (<= 1 when they agree within their bounds); the same with the paper preset
  (`distance --paper`: one faithful query per point) on the first --paper-points points;
- for the assembly: `nurbsgl clearance` between two of its parts (--pairs, by body name) and
  OpenCASCADE's BRepExtrema_DistShapeShape between the solids at our closest points, the difference
  over our bound; each pair with the default and with the paper preset (`clearance --paper`), a row each.
Without OpenCASCADE's peer (--peer not given and not built) its columns are left empty, and the
script says so. Writes step_models.csv in OUT and prints a table. A benchmark, not a test.

Usage: experiments/step_models.py --build BUILD --out OUT [--peer PEER] [--points N] [--repeat N]
"""
import argparse
import csv
import glob
import json
import os
import random
import subprocess
import sys
import tempfile

from real_models import write_points  # the same random points in the box grown by a fifth

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "models")
TWINS = {"step/gmsh_component8.step": "generated/gmsh_component8_brep.igs",
         "step/pythonocc_Ventilator.stp": "generated/pythonocc_Ventilator_brep.igs",
         "generated/vase_shell_t2.step": "generated/vase_shell_t2_brep.igs",
         "generated/teapot_bezier32.step": "generated/teapot_bezier32_brep.igs"}
ASSEMBLY_PAIRS = {"assembly/gmsh_as1-tu-203.stp": [("plate", "rod"), ("nut", "bolt"), ("l-bracket", "plate")]}


def output(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}: {p.stderr.strip()[-400:]}")
    return p.stdout


def mesh_area(path):
    """Area of an OBJ triangle mesh."""
    verts, area = [], 0.0
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                a, b, c = (verts[int(x.split("/")[0]) - 1] for x in line.split()[1:4])
                u = [b[k] - a[k] for k in range(3)]
                v = [c[k] - a[k] for k in range(3)]
                n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
                area += 0.5 * (n[0] ** 2 + n[1] ** 2 + n[2] ** 2) ** 0.5
    return area


def tessellate(cli, model, tmp, options=("--watertight",)):
    mesh = os.path.join(tmp, "mesh.obj")
    j = json.loads(output([cli, "tessellate", model, "--eps", "1e-3", "--relative", *options, "-o", mesh, "--json"]))
    return mesh_area(mesh), j.get("open_edges")


def distances(cli, model, points, options=()):
    j = json.loads(output([cli, "distance", model, "--points", points, "--tol", "1e-5", *options, "--json"]))
    return [(r["distance"], r["bound"]) for r in j["results"]]


def worst_per_bounds(a, b):
    """The largest difference of two runs' answers over the sum of their bounds."""
    return round(max(abs(x[0] - y[0]) / max(x[1] + y[1], 1e-300) for x, y in zip(a, b)), 3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--peer", help="peer_occt_step (default: BUILD/experiments/peer_occt_step if built)")
    ap.add_argument("--points", type=int, default=200)
    ap.add_argument("--paper-points", type=int, default=20, help="points of the paper preset (one query each)")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    cli = os.path.join(args.build, "cli", "nurbsgl")
    bench = os.path.join(args.build, "experiments", "bench_read")
    peer = args.peer or os.path.join(args.build, "experiments", "peer_occt_step")
    if not os.path.exists(peer):
        print(f"note: no OpenCASCADE peer at {peer}: its columns are left empty "
              "(build it with -DNURBSGL_PEER_BENCH=ON)", file=sys.stderr)
        peer = None
    os.makedirs(args.out, exist_ok=True)
    files = sorted(glob.glob(os.path.join(ROOT, "step", "*.st*p")) + glob.glob(os.path.join(ROOT, "assembly", "*.stp")) +
                   glob.glob(os.path.join(ROOT, "generated", "*.step")))
    if not files:
        sys.exit(f"no STEP file under {ROOT}")
    rows, clearances = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for path in files:
            name = os.path.relpath(path, ROOT)
            print(f"{name} ...", file=sys.stderr)
            info = json.loads(output([cli, "info", path, "--json"]))
            ours = json.loads(output([bench, "--repeat", str(args.repeat), path]).splitlines()[0])
            row = {"model": name, "faces": info["faces"], "bodies": info["bodies"],
                   "trim_problems": len(info["reader"]["trim_problems"]),
                   "faces_dropped": len(info["reader"]["faces_dropped"]),
                   "read_s": round(ours["read_seconds"], 4), "parse_s": round(ours.get("parse_seconds", 0.0), 4)}
            if peer:
                occt = json.loads(output([peer, "read", path, "--repeat", str(args.repeat)]))
                row.update({"occt_faces": occt["faces"], "occt_read_s": round(occt["read_seconds"], 4),
                            "read_ratio": round(occt["read_seconds"] / ours["read_seconds"], 2),
                            "occt_area": round(occt["area"], 3)})
            area, open_edges = tessellate(cli, path, tmp)
            row.update({"mesh_area": round(area, 3), "open_edges": open_edges})
            area, open_edges = tessellate(cli, path, tmp, ("--paper",))
            row.update({"paper_mesh_area": round(area, 3), "paper_open_edges": open_edges})
            twin = TWINS.get(name)
            if twin and os.path.exists(os.path.join(ROOT, twin)):
                twin_path = os.path.join(ROOT, twin)
                row["twin"] = twin
                row["twin_mesh_area"] = round(tessellate(cli, twin_path, tmp)[0], 3)
                points = os.path.join(tmp, "points.txt")
                write_points(cli, path, args.points, points)
                a, b = distances(cli, path, points), distances(cli, twin_path, points)
                row.update({"distance_points": len(a), "worst_difference_per_bounds": worst_per_bounds(a, b)})
                first = os.path.join(tmp, "paper_points.txt")
                with open(points) as f, open(first, "w") as g:
                    g.writelines(f.readlines()[: args.paper_points])
                a, b = distances(cli, path, first, ["--paper"]), distances(cli, twin_path, first, ["--paper"])
                row.update({"paper_distance_points": len(a),
                            "paper_worst_difference_per_bounds": worst_per_bounds(a, b)})
            rows.append(row)
            pairs = [(pair, preset) for pair in ASSEMBLY_PAIRS.get(name, []) for preset in ("default", "paper")]
            for (body_a, body_b), preset in pairs:
                item = {"model": name, "a": body_a, "b": body_b, "preset": preset}
                try:
                    c = json.loads(output([cli, "clearance", path, path, "--body-a", body_a, "--body-b", body_b,
                                           *(["--paper"] if preset == "paper" else []), "--json"]))
                except RuntimeError as e:  # an unproven answer (exit 1) is a result of the run too
                    item["error"] = str(e).split(": ")[-1]
                    clearances.append(item)
                    continue
                item.update({"clearance": c["distance"], "bound": c["bound"]})
                if peer:
                    pa = ",".join(f"{x:.12g}" for x in c["point_a"])
                    pb = ",".join(f"{x:.12g}" for x in c["point_b"])
                    occt = json.loads(output([peer, "clearance", path, "--a", pa, "--b", pb]))
                    item.update({"occt_distance": occt["distance"],
                                 "difference_per_bound": round(abs(occt["distance"] - c["distance"]) / c["bound"], 3)})
                clearances.append(item)
    for rows_, file in ((rows, "step_models.csv"), (clearances, "step_models_clearance.csv")):
        if not rows_:
            continue
        keys = []
        for r in rows_:
            keys += [k for k in r if k not in keys]
        with open(os.path.join(args.out, file), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            w.writerows(rows_)
        print(f"\n{file}")
        print(" | ".join(keys))
        for r in rows_:
            print(" | ".join(str(r.get(k, "")) for k in keys))


if __name__ == "__main__":
    main()
