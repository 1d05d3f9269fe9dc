#!/usr/bin/env python3
"""Scan inspection against its peers, in one run on the same files: `nurbsgl inspect --align` (best
fit, certified signed deviations), CloudCompare (Debian `cloudcompare`, headless: ICP with 95 %
overlap on a BRepMesh mesh at the smallest band / 10, then cloud-to-mesh distances) and Open3D
(Debian `python3-open3d`: point-to-plane ICP on the same mesh's vertices, then RaycastingScene
signed distances). Scans come from experiments/make_scan.py: sampled on the model, noise along the
normal, 1 % outliers, misplaced by 0.5 degrees and a shift; all lengths relative to the model size S
as a 100 mm part's are to it: noise 2e-4 S (0.02 mm), shift 3e-3 S (0.3 mm), bands 5e-4 S and 1e-3 S,
outliers beyond 1e-2 S, the peers' mesh at the smallest band / 10. Per tool and scan: the whole
process's wall time and peak memory (GNU time), its stages where it reports them, and the fit's
error: the largest distance, over the model's box corners, between the fitted and the true placement.

    experiments/inspect_bench.py --build build --out results/inspect [--points 1000000 ...] [--models ...]

Writes OUT/inspect_bench.json and the table into docs/benchmarks.md ("Scan inspection").
"""
import argparse
import itertools
import json
import os
import pathlib
import re
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "models"
MODELS = {  # IGES B-reps: BRepMesh (peer_occt_mesh) reads IGES
    "Ventilator": SHARED / "generated" / "pythonocc_Ventilator_brep.igs",
    "Motor": SHARED / "generated" / "occt_Motor-c_brep.igs",
    "bearing": SHARED / "iges" / "occt_bearing.iges",
}
BANDS = (5e-4, 1e-3)  # times the model size
NOISE, SHIFT, MAX_DISTANCE = 2e-4, 3e-3, 1e-2


def timed(cmd, env=None):
    """Runs cmd under GNU time: (stdout, stderr, wall seconds, peak MB)."""
    t0 = time.time()
    p = subprocess.run(["/usr/bin/time", "-f", "TIME %e %M"] + [str(c) for c in cmd], capture_output=True, text=True,
                       env=env)
    wall = time.time() - t0
    m = re.findall(r"TIME ([0-9.]+) ([0-9]+)", p.stderr)
    peak = float(m[-1][1]) / 1024 if m else float("nan")
    return p.stdout, p.stderr, wall, peak, p.returncode


def placement_error(fit, truth, corners):
    """Largest distance over the corners between truth^-1 applied then fit applied, and the corners."""
    scan = (corners - truth[:3, 3]) @ np.linalg.inv(truth[:3, :3]).T
    return float(np.abs(scan @ fit[:3, :3].T + fit[:3, 3] - corners).max())


def cloudcompare(scan, mesh):
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    out, err, wall, peak, rc = timed(["CloudCompare", "-SILENT", "-NO_TIMESTAMP", "-AUTO_SAVE", "OFF", "-O", scan, "-O",
                                      mesh, "-ICP", "-OVERLAP", "95", "-C2M_DIST"], env)
    text = out + err
    distances = sum(float(x) for x in re.findall(r"\[ComputeDistances\] Time: ([0-9.]+) s", text))
    rms = re.findall(r"RMS: ([0-9.e-]+)", text)
    return {"seconds": wall, "peak_mb": peak, "distance_seconds": distances, "rms": float(rms[-1]) if rms else None,
            "ok": rc == 0 and bool(rms)}


OPEN3D = r"""
import sys, time, json, numpy as np, open3d as o3d
scan_path, mesh_path, reach = sys.argv[1], sys.argv[2], float(sys.argv[3])
t0 = time.time()
scan = o3d.io.read_point_cloud(scan_path)
mesh = o3d.io.read_triangle_mesh(mesh_path)
mesh.compute_vertex_normals()
target = o3d.geometry.PointCloud(mesh.vertices)
target.normals = mesh.vertex_normals
pts = np.asarray(scan.points)
sample = scan.select_by_index(np.linspace(0, len(pts) - 1, 20000).astype(int))
t1 = time.time()
reg = o3d.pipelines.registration.registration_icp(sample, target, reach, np.eye(4),
    o3d.pipelines.registration.TransformationEstimationPointToPlane(),
    o3d.pipelines.registration.ICPConvergenceCriteria(max_iteration=60))
t2 = time.time()
scene = o3d.t.geometry.RaycastingScene()
scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(mesh))
moved = pts @ reg.transformation[:3, :3].T + reg.transformation[:3, 3]
d = scene.compute_signed_distance(o3d.core.Tensor(moved.astype(np.float32))).numpy()
t3 = time.time()
print(json.dumps({"matrix": reg.transformation.tolist(), "rms": reg.inlier_rmse, "read_seconds": t1 - t0,
                  "fit_seconds": t2 - t1, "distance_seconds": t3 - t2}))
"""


def open3d(scan, mesh, reach):
    out, err, wall, peak, rc = timed([sys.executable, "-c", OPEN3D, scan, mesh, reach])
    try:
        r = json.loads(out.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return {"ok": False, "error": err[-400:]}
    r.update(seconds=wall, peak_mb=peak, ok=rc == 0)
    return r


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=str(ROOT / "build"))
    p.add_argument("--out", default=str(ROOT / "results" / "inspect"))
    p.add_argument("--points", type=int, nargs="+", default=[1000000])
    p.add_argument("--models", nargs="+", default=list(MODELS))
    p.add_argument("--work", default="/tmp/nurbsgl_inspect_bench", help="scans and meshes (large files)")
    a = p.parse_args(argv)
    out, work = pathlib.Path(a.out), pathlib.Path(a.work)
    out.mkdir(parents=True, exist_ok=True)
    work.mkdir(parents=True, exist_ok=True)
    build = pathlib.Path(a.build)
    nurbsgl = build / "cli" / "nurbsgl"
    mesher = build / "experiments" / "peer_occt_mesh"
    sys.path.insert(0, str(build / "python"))
    import nurbsgl as module
    rows = []
    for name in a.models:
        model = MODELS[name]
        if not model.exists():
            print(f"{name}: {model} missing, skipped", file=sys.stderr)
            continue
        loaded = module.load(model)
        v = loaded.tessellate(eps=1e-3).vertices
        lo, hi = v.min(0), v.max(0)
        corners = np.array(list(itertools.product(*zip(lo, hi))))
        size = float(np.linalg.norm(hi - lo))
        bands = [b * size for b in BANDS]
        mesh = work / f"{name}_brepmesh.ply"
        if mesher.exists():
            m_out, m_err, m_wall, _, _ = timed([mesher, model, "--deflection", min(bands) / 10, "-o", mesh])
            mesh_json = json.loads(m_out) if m_out.strip().startswith("{") else {}
        else:
            mesh_json = {}
        for n in a.points:
            scan, truth_file = work / f"{name}_{n}.ply", work / f"{name}_{n}_truth.json"
            if not scan.exists():
                subprocess.run([sys.executable, ROOT / "experiments" / "make_scan.py", model, scan, "--points", str(n),
                                "--noise", str(NOISE * size), "--shift", str(SHIFT * size), "--truth", truth_file,
                                "--build", build], check=True)
            truth = np.array(json.load(open(truth_file))["matrix"])
            row = {"model": name, "faces": loaded.faces, "points": n, "size": size, "bands": bands,
                   "mesh_triangles": mesh_json.get("triangles"),
                   "mesh_seconds": mesh_json.get("seconds")}
            o_out, o_err, wall, peak, rc = timed([nurbsgl, "inspect", model, scan, "--within",
                                                  ",".join(f"{b:.6g}" for b in bands), "--max-distance",
                                                  f"{MAX_DISTANCE * size:.6g}", "--align", "--json"])
            j = json.loads(o_out)
            row["nurbsgl"] = {"seconds": wall, "peak_mb": peak, "stages": j["seconds"], "rc": rc,
                              "rms": j["alignment"]["rms"], "undecided": j["undecided_points"],
                              "fit_error": placement_error(np.array(j["alignment"]["matrix"]), truth, corners)}
            if mesh.exists():
                row["cloudcompare"] = cloudcompare(scan, mesh)
                o3 = open3d(scan, mesh, MAX_DISTANCE * size)
                if o3.get("ok"):
                    o3["fit_error"] = placement_error(np.array(o3["matrix"]), truth, corners)
                    del o3["matrix"]
                row["open3d"] = o3
            rows.append(row)
            print(json.dumps(row), flush=True)
    (out / "inspect_bench.json").write_text(json.dumps(rows, indent=1))
    lines = ["| model (faces, size) | points | nurbsgl whole s | its stages (prepare / fit / deviations) | peak MB "
             "| fit error | CloudCompare whole s (C2M s) | peak MB | Open3D whole s (fit / distances) | fit error |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        o, c, d = r["nurbsgl"], r.get("cloudcompare", {}), r.get("open3d", {})
        st = o["stages"]
        lines.append(f"| {r['model']} ({r['faces']}, {r['size']:.3g}) | {r['points']:,} | {o['seconds']:.2f} | "
                     f"{st['prepare']:.2f} / {st['fit']:.2f} / {st['deviations']:.2f} | {o['peak_mb']:.0f} | "
                     f"{o['fit_error']:.2g} | {c.get('seconds', float('nan')):.2f} ({c.get('distance_seconds', 0):.2f})"
                     f" | {c.get('peak_mb', float('nan')):.0f} | {d.get('seconds', float('nan')):.2f} "
                     f"({d.get('fit_seconds', float('nan')):.2f} / {d.get('distance_seconds', float('nan')):.2f}) | "
                     f"{d.get('fit_error', float('nan')):.2g} |")
    print("\n".join(lines))
    sys.path.insert(0, str(ROOT / "experiments"))
    import report
    gl = json.loads(subprocess.run([nurbsgl, "gpu-info", "--json"], capture_output=True, text=True).stdout or "{}")
    command = "experiments/inspect_bench.py " + " ".join(
        "DIR" if sys.argv[i - 1] in ("--out", "--work") else w for i, w in enumerate(sys.argv[1:], 1))
    report.write_benchmarks("Scan inspection", command, gl,
                            [(f"`inspect_bench.json`: {', '.join(f'{n:,}' for n in a.points)} points, bands "
                              f"{BANDS[0]:g} and {BANDS[1]:g} of the model size, fit error over the model's box",
                              "\n".join(lines))], "" if mesher.exists() else "the peers (no peer_occt_mesh)")


if __name__ == "__main__":
    main()
