#!/usr/bin/env python3
"""Ray casting and thickness experiments of Lemasson et al., OpenCASCADE beside ours.

Every figure comes from the CLI (`nurbsgl raycast --json`, `nurbsgl thickness --json`, the stable
contract) and the OCCT peer (`peer_occt_distance rays`: IntCurvesFace_ShapeIntersector, PerformNearest)
in the same run on the same machine. Per model:

  rays      N random rays (origins on a sphere around the model, aimed at random points of its box):
            rays per second of the certified mesh method (the default preset, the run without
            switches), the BVH and DACRT methods on the CPU, of the BVH on the GPU (the float pass and
            the double finishing timed apart) and of the paper preset (`--paper`: the BVH built and
            traversed on the GPU), box and patch tests per ray (paper Fig. 7), memory of the BVH,
            patches and trims (Fig. 11). The BVH and DACRT exit 1, their nearest hits not certified:
            their figures are taken from the JSON that says so.
  peer      the first M of those rays through OCCT: rays per second, the hit/miss agreement, and
            |t - t_occt| on the rays both hit (OCCT is the independent reference).
  accuracy  Fig. 13: |t_bicubic - t| (the hit on the bicubic patches, what the paper reports, against
            the hit moved onto the exact NURBS face in double) and |t - t_occt|; the fraction of
            samples within 1e-3 mm (the goal: 99 %; the paper reached 55 %).
  thickness `nurbsgl thickness --samples S`, the default and `--paper`: rays per second, min / median
            thickness.
  dacrt     Figs. 8-9: DACRT's rays per second and tests per ray over its two brute-force thresholds
            (patch set, ray set) on the first model.
  scaling   Figs. 10-12 on the first model: for growing ray counts (--scaling), the whole process's time
            (reading, preparation and tracing, as Fig. 10 counts pre-processing) and peak memory (Fig.
            12) of the BVH on one CPU thread, on every core, DACRT, the GPU pass and the paper preset;
            the ratio of the one-thread time to each (Fig. 10's CPU / GPU ratio), and the structures'
            bytes (Fig. 11).

Writes rays.csv, accuracy.csv, thickness.csv, dacrt.csv, scaling.csv, accuracy.png (histograms),
dacrt.png, scaling.png and summary.txt (also on
stdout). Benchmarks, not tests: nothing fails on a slow figure; a command that fails is reported.
"""
import argparse
import csv
import json
import math
import os
import random
import shlex
import subprocess
import sys

import report

plt = report.pyplot()  # None without matplotlib: the plots are skipped

MODELS = [
    "generated/vase_shell_t2.igs",
    "iges/occt_bearing.iges",
    "generated/pythonocc_Ventilator_nurbs.igs",
    "generated/teapot_bezier32.igs",
    "iges/pythonocc_example_45_faces.iges",
]


def answered(code, out):
    """The JSON of a run that answered: exit 0, or exit 1 where the answer carries why it is not
    certified (the BVH and DACRT: nearest hits not certified), else None."""
    if code not in (0, 1):
        return None
    try:
        j = json.loads(out)
    except ValueError:
        return None
    return j if code == 0 or j.get("uncertified") else None


def run_json(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    j = answered(r.returncode, r.stdout)
    if j is None:
        print(f"  failed ({r.returncode}): {' '.join(cmd)}\n  {r.stderr.strip()[-400:]}", file=sys.stderr)
    return j


def make_rays(info, count, seed, path):
    lo, hi = info["bbox"]["min"], info["bbox"]["max"]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = 0.75 * math.dist(lo, hi)
    rng = random.Random(seed)
    with open(path, "w") as f:
        for _ in range(count):
            while True:
                d = [rng.gauss(0, 1) for _ in range(3)]
                n = math.sqrt(sum(x * x for x in d))
                if n > 1e-9:
                    break
            o = [c + radius * x / n for c, x in zip(centre, d)]
            target = [rng.uniform(a, b) for a, b in zip(lo, hi)]
            f.write(" ".join(f"{x:.17g}" for x in o + [t - a for t, a in zip(target, o)]) + "\n")


def run_measured(cmd):
    """(JSON of cmd, wall seconds, peak resident MB) of one process, or (None, ...) when it fails."""
    code, out, err, wall, peak = report.run_measured(cmd)
    j = answered(code, out)
    if j is None:
        print(f"  failed ({code}): {' '.join(cmd)}\n  {err.strip()[-400:]}", file=sys.stderr)
    return j, wall, peak


# The runs of the scaling experiment: key, label, options of `nurbsgl raycast`.
SCALING = [("bvh_1", "BVH, CPU, 1 thread", ["--method", "bvh", "--threads", "1"]),
           ("bvh", "BVH, CPU, every core", ["--method", "bvh"]),
           ("mesh", "mesh (default), CPU, every core", []),
           ("dacrt", "DACRT, CPU, every core", ["--method", "dacrt"]),
           ("gpu", "BVH, GPU pass", ["--engine", "gpu"]),
           ("paper", "paper preset (BVH built on the GPU)", ["--paper"])]


def scaling(nurbsgl, path, name, counts, out):
    """Figs. 10-12: one process per run and ray count; rows with time, memory and the structures' bytes."""
    rows = []
    info = run_json([nurbsgl, "info", path, "--json"])
    if info is None:
        return rows
    for n in counts:
        rays = os.path.join(out, f"{name}_scaling_{n}.txt")
        make_rays(info, n, 11, rays)
        for key, label, options in SCALING:
            print(f"  scaling: {n} rays, {label}", file=sys.stderr)
            j, wall, peak = run_measured([nurbsgl, "raycast", path, "--rays", rays, *options, "--json"])
            if j is None:
                continue
            b = j["memory_bytes"]
            # The process's own peak (VmHWM, taken when the rays are cast): the child's ru_maxrss
            # also holds this script's resident memory, which the child's start copies (vfork).
            own = b.get("process_peak", -1)
            rows.append({"model": name, "rays": n, "run": key, "label": label, "process_s": round(wall, 3),
                         "build_s": round(j["seconds_build"], 3), "cast_s": round(j["seconds_cast"], 3),
                         "work_s": round(j["seconds_build"] + j["seconds_cast"], 3),
                         "rays_per_second": round(j["rays_per_second"]),
                         "peak_mb": round(own / 2**20 if own > 0 else peak, 1), "bvh_mb": round(b["bvh"] / 2**20, 2),
                         "patches_mb": round(b["patches"] / 2**20, 2), "trims_mb": round(b["trims"] / 2**20, 2),
                         "hits": j["hits"]})
        os.remove(rays)
    for r in rows:  # Fig. 10's ratio: the one-thread CPU run over this run, at the same ray count, on the
        # preparation and the tracing (the paper's "with pre-processing"; reading and writing apart)
        one = next((x["work_s"] for x in rows if x["rays"] == r["rays"] and x["run"] == "bvh_1"), None)
        r["one_thread_over_this"] = round(one / r["work_s"], 2) if one and r["work_s"] > 0 else ""
    if rows and plt is not None:
        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4))
        for key, label, _ in SCALING:
            pts = [r for r in rows if r["run"] == key]
            ax0.plot([r["rays"] for r in pts], [r["work_s"] for r in pts], "o-", label=label)
            ax1.plot([r["rays"] for r in pts], [r["peak_mb"] for r in pts], "o-", label=label)
        for ax, yl, title in ((ax0, "seconds, preparation and tracing", "Fig. 10: time with pre-processing"),
                              (ax1, "peak resident MB", "Fig. 12: memory")):
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("rays")
            ax.set_ylabel(yl)
            ax.set_title(f"{title}, {name}", fontsize=9)
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "scaling.png"), dpi=120)
        plt.close(fig)
    return rows


def head(path, count, out):
    with open(path) as f, open(out, "w") as g:
        for k, line in enumerate(f):
            if k >= count:
                break
            g.write(line)


# Lemasson et al.'s reported accuracy (Fig. 13 and its text): the share of hits within 1e-3 mm.
PAPER_FIG13_WITHIN_1UM = {"GPU (32-bit floats)": 55, "CPU method (64-bit floats)": 15}  # percent
# Fig. 10 (Lens): the CPU software's time over the GPU BVH's and GPU DACRT's, at 2.11 M and 7.50 M rays.
PAPER_FIG10_LENS = {2.11e6: (4.52, 3.42), 7.50e6: (19.06, 10.79)}
# Fig. 12 (Lens): memory in MB of the CPU software and of DACRT at 2.11 M and 7.50 M rays; Fig. 11: the
# BVH method's memory, 37.90 MB whatever the number of rays.
PAPER_FIG12_LENS = {2.11e6: (1615.0, 773.1), 7.50e6: (5749.6, 2749.4)}
PAPER_FIG11_LENS_BVH_MB = 37.90


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build-bench")
    ap.add_argument("--out", default=None)
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared", "models"))
    ap.add_argument("--rays", type=int, default=100000, help="rays per model for our methods")
    ap.add_argument("--peer-rays", type=int, default=2000, help="of those, rays through OCCT")
    ap.add_argument("--samples", type=int, default=100000, help="thickness samples per model")
    ap.add_argument("--models", nargs="*", default=None, help="substrings of the model paths to keep")
    ap.add_argument("--peer", help="peer_occt_distance binary (default BUILD/experiments/peer_occt_distance; '' = no OCCT)")
    ap.add_argument("--scaling", type=int, nargs="*", default=[10000, 30000, 100000, 300000],
                    help="ray counts of the scaling experiment (Figs. 10-12) on the first model; none to skip it")
    ap.add_argument("--command", help="the command line to name in docs/benchmarks.md")
    ap.add_argument("--no-docs", action="store_true", help="leave docs/benchmarks.md alone")
    a = ap.parse_args()
    out = a.out or os.path.join(a.build, "experiments", "raycast")
    os.makedirs(out, exist_ok=True)
    nurbsgl = os.path.join(a.build, "cli", "nurbsgl")
    peer = os.path.join(a.build, "experiments", "peer_occt_distance") if a.peer is None else a.peer
    models = [m for m in MODELS if not a.models or any(s in m for s in a.models)]
    rows, acc_rows, th_rows, summary = [], [], [], []
    hist_bicubic, hist_occt, hist_gpu = [], [], []
    for rel in models:
        path = os.path.join(a.shared, rel)
        if not os.path.exists(path):
            print(f"{rel}: missing, skipped", file=sys.stderr)
            continue
        name = os.path.splitext(os.path.basename(rel))[0]
        print(f"{name}:", file=sys.stderr)
        info = run_json([nurbsgl, "info", path, "--json"])
        if info is None:
            continue
        rays = os.path.join(out, f"{name}_rays.txt")
        make_rays(info, a.rays, 7, rays)
        ours = {}
        # key, options: the default preset (the certified mesh method on the cpu), the paper's BVH on the
        # cpu, DACRT, the BVH pass on the GPU, the paper preset.
        for key, options in (("mesh", []), ("bvh", ["--method", "bvh"]), ("dacrt", ["--method", "dacrt"]),
                             ("gpu", ["--engine", "gpu"]), ("paper", ["--paper"])):
            j = run_json([nurbsgl, "raycast", path, "--rays", rays, *options, "--json"])
            if j is None:
                continue
            method, device = j["method"], j["device"]
            preset = j.get("preset", {}).get("name", "")
            # Per-ray fields as lists (-1 for a miss) from the one object per ray.
            j["t"] = [r["t"] if r["hit"] else -1.0 for r in j["results"]]
            j["t_bicubic"] = [r["t_bicubic"] if r["hit"] else -1.0 for r in j["results"]]
            ours[key] = j
            gpu = j.get("gpu") or {}
            rows.append({"model": name, "faces": j["faces"], "preset": preset if key in ("mesh", "paper") else "",
                         "method": method,
                         "device": device, "bvh_build": gpu.get("bvh_build", "cpu"), "rays": j["rays"],
                         "gpu_pass_seconds": round(gpu.get("gpu_seconds", 0), 4),
                         "finish_seconds": round(gpu.get("cpu_seconds", 0), 4), "fallbacks": gpu.get("fallbacks", 0),
                         "hits": j["hits"], "rays_per_second": round(j["rays_per_second"]),
                         "box_tests_per_ray": round(j["tests_per_ray"]["box"], 2),
                         "patch_tests_per_ray": round(j["tests_per_ray"]["patch"], 2),
                         "patches": j["patches"], "bvh_bytes": j["memory_bytes"]["bvh"],
                         "patch_bytes": j["memory_bytes"]["patches"], "trim_bytes": j["memory_bytes"]["trims"],
                         "build_seconds": round(j["seconds_build"], 3)})
        peer_rays = os.path.join(out, f"{name}_peer_rays.txt")
        head(rays, a.peer_rays, peer_rays)
        occt = run_json([peer, "rays", path, "--rays", peer_rays, "--repeat", "1"]) if peer and os.path.exists(peer) else None
        if occt is not None:
            rows.append({"model": name, "faces": info["faces"], "method": "occt", "device": "cpu (1 thread)",
                         "rays": occt["rays"],
                         "hits": sum(1 for t in occt["t"] if t >= 0),
                         "rays_per_second": round(occt["rays_per_second"]), "build_seconds": round(occt["init_seconds"], 3)})
        if "bvh" in ours:
            j = ours["bvh"]
            bic = [abs(tb - t) for t, tb in zip(j["t"], j["t_bicubic"]) if t >= 0 and tb >= 0]
            hist_bicubic += bic
            line = f"{name}: {j['rays']} rays, {j['hits']} hits; bvh {j['rays_per_second']:.0f} rays/s"
            if "mesh" in ours:
                line += f", mesh (default) {ours['mesh']['rays_per_second']:.0f} rays/s, {ours['mesh']['hits']} hits"
            if "dacrt" in ours:
                line += f", dacrt {ours['dacrt']['rays_per_second']:.0f} rays/s"
            if "gpu" in ours:
                g = ours["gpu"]
                line += (f", gpu {g['rays_per_second']:.0f} rays/s (pass {g['gpu']['gpu_seconds']:.3f} s, finishing "
                         f"{g['gpu']['cpu_seconds']:.3f} s, {g['gpu']['fallbacks']} fallbacks)")
                tg = [abs(a - b) for a, b in zip(g["t_bicubic"], j["t"]) if a >= 0 and b >= 0]
                hist_gpu.extend(tg)
                wg = sum(1 for x in tg if x <= 1e-3) / max(1, len(tg))
                line += f"; |t_gpu_float - t| <= 1e-3: {100 * wg:.1f} %"
            if "paper" in ours:
                pj = ours["paper"]
                line += (f", paper preset {pj['rays_per_second']:.0f} rays/s (BVH built on the gpu in "
                         f"{pj['gpu']['bvh_build_gpu_seconds']:.3f} s)")
            line += (f"; {j['tests_per_ray']['box']:.1f} boxes + {j['tests_per_ray']['patch']:.2f} patches per ray;"
                     f" {j['patches']} patches")
            within = sum(1 for x in bic if x <= 1e-3) / max(1, len(bic))
            line += f"; |t_bicubic - t| <= 1e-3: {100 * within:.1f} % (max {max(bic, default=0):.2e})"
            if occt is not None:
                n = len(occt["t"])
                both = [(t, to) for t, to in zip(j["t"][:n], occt["t"]) if t >= 0 and to >= 0]
                agree = sum(1 for t, to in zip(j["t"][:n], occt["t"]) if (t >= 0) == (to >= 0))
                d = [abs(t - to) for t, to in both]
                hist_occt += d
                w = sum(1 for x in d if x <= 1e-3) / max(1, len(d))
                line += (f"\n    OCCT on {n} rays: {occt['rays_per_second']:.0f} rays/s (ratio ours/OCCT "
                         f"{j['rays_per_second'] / max(occt['rays_per_second'], 1e-9):.0f}x); hit/miss agree "
                         f"{agree}/{n}; |t - t_occt| <= 1e-3 on {100 * w:.2f} % of {len(d)} (max {max(d, default=0):.2e})")
                acc_rows.append({"model": name, "rays": n, "agree": agree, "both_hit": len(d),
                                 "within_1e-3_occt": round(w, 5), "max_dt_occt": max(d, default=0),
                                 "within_1e-3_bicubic": round(within, 5), "max_dt_bicubic": max(bic, default=0)})
            summary.append(line)
        for preset, options in (("default", []), ("paper", ["--paper"])):
            th = run_json([nurbsgl, "thickness", path, "--samples", str(a.samples), *options, "--json"])
            if th is None:
                continue
            th_rows.append({"model": name, "preset": preset, "device": th["device"], "rays": th["rays"],
                            "hits": th["hits"],
                            "rays_per_second": round(th["thickness_rays_per_second"]),
                            "min": th["thickness"]["min"], "median": th["thickness"]["median"],
                            "faces_flipped": th["orientation"]["faces_flipped_from_file"],
                            "faces_unsure": th["orientation"]["faces_unsure"]})
            summary.append(f"    thickness ({preset}): {th['rays']} samples, {th['hits']} hits, "
                           f"{th['thickness_rays_per_second']:.0f} rays/s, min {th['thickness']['min']:.4g}, "
                           f"median {th['thickness']['median']:.4g}")
    dacrt_rows = []
    if models and os.path.exists(os.path.join(a.shared, models[0])):
        name = os.path.splitext(os.path.basename(models[0]))[0]
        rays = os.path.join(out, f"{name}_rays.txt")
        print(f"{name}: DACRT thresholds", file=sys.stderr)
        for pl in (2, 8, 32, 128):
            for rl in (2, 8, 32, 128):
                j = run_json([nurbsgl, "raycast", os.path.join(a.shared, models[0]), "--rays", rays, "--method", "dacrt",
                              "--dacrt-patches", str(pl), "--dacrt-rays", str(rl), "--json"])
                if j is not None:
                    dacrt_rows.append({"model": name, "patch_leaf": pl, "ray_leaf": rl,
                                       "rays_per_second": round(j["rays_per_second"]),
                                       "box_tests_per_ray": round(j["tests_per_ray"]["box"], 2),
                                       "patch_tests_per_ray": round(j["tests_per_ray"]["patch"], 2)})
        if dacrt_rows:
            best = max(dacrt_rows, key=lambda r: r["rays_per_second"])
            summary.append(f"DACRT thresholds on {name}: best patch leaf {best['patch_leaf']}, ray leaf "
                           f"{best['ray_leaf']}: {best['rays_per_second']} rays/s")
        if dacrt_rows and plt is not None:
            fig, axes = plt.subplots(1, 2, figsize=(10, 4))
            for rl in (2, 8, 32, 128):
                pts = [r for r in dacrt_rows if r["ray_leaf"] == rl]
                axes[0].plot([r["patch_leaf"] for r in pts], [r["rays_per_second"] for r in pts], "o-",
                             label=f"ray leaf {rl}")
                axes[1].plot([r["patch_leaf"] for r in pts], [r["patch_tests_per_ray"] for r in pts], "o-",
                             label=f"ray leaf {rl}")
            for ax, yl in ((axes[0], "rays per second"), (axes[1], "patch tests per ray")):
                ax.set_xscale("log", base=2)
                ax.set_xlabel("patch leaf threshold")
                ax.set_ylabel(yl)
                ax.legend(fontsize=8)
            fig.suptitle(f"DACRT thresholds, {name} (Lemasson et al. Figs. 8-9)")
            fig.tight_layout()
            fig.savefig(os.path.join(out, "dacrt.png"), dpi=120)
    scaling_rows = []
    if models and a.scaling and os.path.exists(os.path.join(a.shared, models[0])):
        name = os.path.splitext(os.path.basename(models[0]))[0]
        print(f"{name}: scaling (Figs. 10-12)", file=sys.stderr)
        scaling_rows = scaling(nurbsgl, os.path.join(a.shared, models[0]), name, a.scaling, out)
        if scaling_rows:
            summary += ["", f"Figs. 10-12 on {name}: preparation and tracing (work s; the whole process with "
                            "reading the rays and writing the answers: process s), the process's peak memory",
                        f"{'rays':>9}  {'run':<38}{'work s':>8}{'process s':>10}{'1 thread / this':>16}{'peak MB':>9}"
                        f"{'BVH + patches + trims MB':>26}"]
            for r in scaling_rows:
                summary.append(f"{r['rays']:>9}  {r['label']:<38}{r['work_s']:>8.2f}{r['process_s']:>10.2f}"
                               f"{r['one_thread_over_this']:>16}{r['peak_mb']:>9.0f}"
                               f"{r['bvh_mb'] + r['patches_mb'] + r['trims_mb']:>26.1f}")
    for fname, data in (("rays.csv", rows), ("accuracy.csv", acc_rows), ("thickness.csv", th_rows),
                        ("dacrt.csv", dacrt_rows), ("scaling.csv", scaling_rows)):
        if data:
            keys = list(dict.fromkeys(k for r in data for k in r))
            with open(os.path.join(out, fname), "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=keys)
                w.writeheader()
                w.writerows(data)
    if plt is not None:
        fig, ax = plt.subplots(figsize=(7, 4))
        bins = [10.0 ** e for e in range(-16, 1)]
        for data, label in ((hist_bicubic, "|t_bicubic - t| (bicubic hit vs exact NURBS hit)"),
                            (hist_gpu, "|t_gpu - t| (the float GPU pass vs exact NURBS hit)"),
                            (hist_occt, "|t - t_OCCT| (ours vs OpenCASCADE)")):
            if data:
                ax.hist([max(x, 1e-16) for x in data], bins=bins, alpha=0.6, label=label)
        ax.set_xscale("log")
        ax.axvline(1e-3, color="k", linestyle="--", linewidth=1)
        ax.set_xlabel("distance error (model units, mm)")
        ax.set_ylabel("rays")
        ax.set_title("Hit accuracy (Lemasson et al. Fig. 13 style)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "accuracy.png"), dpi=120)
    # Rays per second of every run, the presets named (default: no switch; paper: --paper).
    summary += ["", f"{'model':<28}{'preset':<9}{'method':<7}{'device':<16}{'bvh build':<10}{'rays/s':>10}"
                    f"{'boxes/ray':>10}{'patches/ray':>12}{'build s':>9}"]
    for r in rows:
        summary.append(f"{r['model']:<28}{r.get('preset', ''):<9}{r['method']:<7}{r['device']:<16}"
                       f"{r.get('bvh_build', ''):<10}{r['rays_per_second']:>10}{r.get('box_tests_per_ray', ''):>10}"
                       f"{r.get('patch_tests_per_ray', ''):>12}{r['build_seconds']:>9}")
    text = "\n".join(summary)
    with open(os.path.join(out, "summary.txt"), "w") as f:
        f.write(text + "\n")
    print(text)
    if not a.no_docs and rows:
        info = run_json([nurbsgl, "gpu-info", "--json"]) or {}
        left_out = ", ".join(w for w, gone in (("the OCCT rows", not any(r["method"] == "occt" for r in rows)),
                                               ("the plots", plt is None)) if gone)
        tables = [(f"`{f}`:", report.markdown_table(d)) for f, d in
                  (("rays.csv", rows), ("thickness.csv", th_rows), ("scaling.csv", scaling_rows)) if d]
        command = a.command or shlex.join(["experiments/raycast_tables.py", *sys.argv[1:]])
        report.write_benchmarks("Ray casting and thickness (Lemasson et al.)", command, info, tables, left_out)
        share = lambda d: f"{100 * sum(x <= 1e-3 for x in d) / len(d):.0f} % of {len(d)} hits" if d else "not run"
        figures = [
            ("Fig. 13, hits within 1e-3 mm of the exact NURBS hit",
             ", ".join(f"{k} {v} %" for k, v in PAPER_FIG13_WITHIN_1UM.items()) + " (Fig. 13)",
             f"float GPU pass {share(hist_gpu)}; bicubic {share(hist_bicubic)}")]
        if scaling_rows:
            most = max(r["rays"] for r in scaling_rows)
            at = {r["run"]: r for r in scaling_rows if r["rays"] == most}
            least = {r["run"]: r for r in scaling_rows if r["rays"] == min(x["rays"] for x in scaling_rows)}
            model = scaling_rows[0]["model"]
            ratio = lambda k: f"{at[k]['one_thread_over_this']}x" if k in at else "not run"
            mb = lambda d, k: f"{d[k]['peak_mb']:.0f} MB" if k in d else "not run"
            figures += [
                ("Fig. 10, one-thread CPU time over each method's, with pre-processing (reading and writing apart)",
                 "Lens: CPU / GPU BVH " + ", ".join(f"{v[0]}x at {n / 1e6:.2f} M rays" for n, v in
                                                    PAPER_FIG10_LENS.items()) + "; CPU / GPU DACRT " +
                 ", ".join(f"{v[1]}x" for v in PAPER_FIG10_LENS.values()) + " (Fig. 10)",
                 f"{model}, {most:,} rays: every core {ratio('bvh')}, DACRT {ratio('dacrt')}, GPU pass "
                 f"{ratio('gpu')}, paper preset {ratio('paper')}"),
                ("Fig. 11, memory of the BVH method (structures)",
                 f"Lens {PAPER_FIG11_LENS_BVH_MB} MB, whatever the number of rays (Fig. 11)",
                 f"{model}: BVH + patches + trims "
                 f"{at['bvh']['bvh_mb'] + at['bvh']['patches_mb'] + at['bvh']['trims_mb']:.1f} MB" if "bvh" in at
                 else "not run"),
                ("Fig. 12, memory against the number of rays",
                 "Lens: CPU software " + ", ".join(f"{v[0]:.0f} MB" for v in PAPER_FIG12_LENS.values()) +
                 ", DACRT " + ", ".join(f"{v[1]:.0f} MB" for v in PAPER_FIG12_LENS.values()) + " at " +
                 ", ".join(f"{n / 1e6:.2f} M" for n in PAPER_FIG12_LENS) + " rays (Fig. 12)",
                 f"{model}, the process's peak at {min(least.values(), key=lambda r: r['rays'])['rays']:,} / "
                 f"{most:,} rays: BVH {mb(least, 'bvh')} / {mb(at, 'bvh')}, DACRT {mb(least, 'dacrt')} / "
                 f"{mb(at, 'dacrt')}, GPU pass {mb(least, 'gpu')} / {mb(at, 'gpu')}")]
        report.write_reproduction("Ray casting (Lemasson et al.)", figures, command)
        peer_rows = [r for r in rows if r["method"] == "occt"]
        if peer_rows:  # the README's headline: the model of most faces that OCCT ran on
            o = max(peer_rows, key=lambda r: r["faces"])
            ours = next((r for r in rows if r["model"] == o["model"] and r.get("preset") == "default"), None)
            if ours:
                report.write_headline("ray casting (nearest hit)", f"{o['model']} ({o['faces']})",
                                      f"{ours['rays_per_second']:,} rays/s ({ours['rays']:,} rays, "
                                      f"{ours['device']}, every core)",
                                      f"{o['rays_per_second']:,} rays/s (IntCurvesFace_ShapeIntersector, one core)",
                                      f"{ours['rays_per_second'] / max(o['rays_per_second'], 1):.0f}x faster", command)


if __name__ == "__main__":
    main()
