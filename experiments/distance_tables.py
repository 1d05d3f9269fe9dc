#!/usr/bin/env python3
"""Distance experiments of Krishnamurthy et al. ("Experiments"), OpenCASCADE beside each.

Every experiment drives the CLI (`nurbsgl clearance` / `nurbsgl distance`, the stable contract) and the
OCCT peer (`peer_occt_distance`, BRepExtrema_DistShapeShape and GeomAPI_ProjectPointOnSurf) in the same
run on the same machine, then writes NAME.csv, NAME.png and a short summary on stdout:

  tables   Tables 1 and 3: the 199x33 surface against the 100x105 one (Table 1) and the trimmed 100x105
           (Table 3) at four positions of B: time per query, prepare time, distance, bound / model
           size, paper preset vs faithful vs default, OCCT distance and time; also Fig. 12 (pairs per
           level).
  table2   Table 2: the per-pass breakdown of one query (`clearance --timings`).
  fig16    Fig. 16: a scripted motion of B over 100 frames (`clearance --motion`), time and bound per frame.
  table5   Table 5: object pairs from ../shared/models (teapot near the vase wall; a model against itself
           moved); skipped with a note when the shared models are absent.
  points   Point distance: `distance --points` on random points near the 100x105 surface vs OCCT's
           GeomAPI_ProjectPointOnSurf initialised once, distances compared.
  all      everything above.

Each experiment runs the CLI's presets side by side, a row (or series) each: `paper` (`--paper`: every
switch at the paper's algorithm: faithful grids, every face, the voxel first stage, 2 x 2 reductions,
the 4-texel stream reduction, every level on the GPU, box upper bounds; one query per point),
`faithful` (`--search faithful` on the default's other switches) and `default` (no switch: the
coarse-to-fine search). The paper preset runs fewer queries (--paper-reps, --paper-frames): its voxel
stage costs seconds per query on a software renderer.

OCCT's answer is checked against ours: |d_occt - d| <= bound + OCCT's shape tolerance, else the CSV
column `within` says `NO`. Benchmarks, not tests: nothing here fails on a slow figure.
"""
import argparse
import csv
import json
import math
import os
import random
import re
import shlex
import statistics
import subprocess
import sys

import report

plt = report.pyplot()  # None without matplotlib: the plots are skipped

# The runs of each experiment, by name: the options each adds to `clearance`.
METHODS = {"paper": ["--paper"], "faithful": ["--search", "faithful"], "default": []}
VOXELS = "default + voxels"  # Table 5 only: --first-stage voxels (§5.4) on the default

# Positions of B (rotated by DEG degrees about the axis through the origin, then moved), chosen so that
# the closest points lie in different places. A: x in [0, 200], y in [0, 40], z in +-5; B: [0, 100]^2,
# z in [16, 24]. Format of a `clearance --motion` line: DX DY DZ AX AY AZ DEG.
POSITIONS = [
    ("above", (0, 0, 0, 0, 0, 1, 0), "B over A: B's edge y=0 above A's crest"),
    ("beside", (50, 45, -20, 0, 0, 1, 5), "B beside A, turned 5 deg: edge against edge"),
    ("wall", (150, -30, 8, 0, 1, 0, -90), "B upright on A: B's lower edge over A's crest"),
    ("below", (60, 60, 8, 1, 0, 0, 180), "B flipped under A: interior against interior"),
]


# Krishnamurthy et al.'s reported figures (GPU time, ACIS time, in seconds), for REPRODUCTION.md.
PAPER_TABLE1 = [(0.218, 64.4), (0.109, 65.4), (0.093, 66.9), (0.171, 66.2)]  # Table 1, positions 1-4
PAPER_TABLE3 = [(0.234, 55.9), (0.125, 57.7), (0.109, 59.1), (0.187, 58.5)]  # Table 3, positions 1-4
PAPER_TABLE2_TOTAL = 0.221  # Table 2, "Total computation time" (s)
PAPER_TABLE5_GPU = (0.382, 1.501)  # Table 5, the fastest and slowest GPU time of its five pairs (s)

# Columns of each CSV that docs/benchmarks.md shows (the CSVs keep them all).
SHOWN = {
    "table1": ["position", "method", "distance", "bound_over_size", "prepare_s", "first_query_s", "query_s",
               "occt_distance", "occt_s", "occt_over_ours", "within"],
    "table2": ["method", "pass", "calls", "gpu_ms", "cpu_ms"],
    "table5": ["pair", "method", "distance", "bound", "prepare_s", "first_query_s", "query_s", "occt_distance",
               "occt_s", "occt_over_ours", "within"],
    "points_summary": ["method", "points", "prepare_s", "query_s", "ms_per_point", "points_per_s"],
}
SHOWN["table3"] = SHOWN["table1"]


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def run_json(cmd, stderr_to=None):
    """Runs cmd, returns its stdout parsed as JSON (and stderr text when stderr_to is a list)."""
    log("  $ " + " ".join(cmd))
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{cmd[0]} exited {p.returncode}: {p.stderr.strip()[-2000:]}")
    if stderr_to is not None:
        stderr_to.append(p.stderr)
    return json.loads(p.stdout)


def motion_line(pos):
    return " ".join(f"{x:g}" for x in pos)


def write_lines(path, lines):
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(report.no_blank(rows))
    log(f"  wrote {path}")


def within(d, bound, d_occt, tol_occt, gaps=None, occt_gaps=None):
    """'yes' when OCCT's distance lies within our bound (plus OCCT's tolerance). Otherwise 'NO', and
    with our witness points' distances to OCCT's faces (gaps) the reason: 'NO: OCCT missed the minimum'
    when OCCT is larger though both our points lie on its faces (within the bound), 'NO: our points
    off OCCT's faces' when they do not (the trims disagree); without gaps 'NO: OCCT larger' (a point
    projection finds only orthogonal feet: a local one). When OCCT is smaller, occt_gaps (OCCT's points
    to our models) tell 'we missed the minimum' from 'its points off our faces' (the trims disagree)."""
    if d_occt is None or d is None:
        return "n/a"
    if abs(d_occt - d) <= bound + tol_occt:
        return "yes"
    if d_occt < d:
        if occt_gaps is None:
            return "NO: OCCT smaller"
        if max(occt_gaps) <= bound + tol_occt:
            return "NO: OCCT smaller (its points on our faces: we missed the minimum)"
        return f"NO: OCCT smaller (its points {max(occt_gaps):.3g} off our faces: the trims disagree)"
    if gaps and max(gaps) <= bound + tol_occt:
        return "NO: OCCT missed the minimum (our points on its faces)"
    return "NO: our points off OCCT's faces" if gaps else "NO: OCCT larger"


def not_met(row):
    """A note when the CLI says the answer's grids did not meet the tolerance (meets_tolerance false)."""
    return " [tolerance not met]" if row.get("meets_tolerance") is False else ""


def verdicts(values):
    """'none' or the count of each 'NO: ...' verdict, numbers inside the verdicts dropped."""
    counts = {}
    for v in values:
        if v.startswith("NO"):
            key = re.sub(r" [0-9.e+-]+ off", " off", v)
            counts[key] = counts.get(key, 0) + 1
    return "; ".join(f"{n} x {k}" for k, n in counts.items()) or "none"


def num(x, spec, unit=""):
    """x formatted by spec (then unit), or '-' in its width when x is empty or NaN (a peer column
    without the peer)."""
    if isinstance(x, (int, float)) and not (isinstance(x, float) and math.isnan(x)):
        return format(x, spec) + unit
    return format("-", re.match(r"[<>^]?\d*", spec).group()) + " " * len(unit)


def peer_ratio(occt, ours, spec):
    """', OCCT/ours 12.3x' (spec formats the ratio), or '' without the peer."""
    return f", OCCT/ours {occt / ours:{spec}}x" if occt == occt and ours > 0 else ""


def fmt_xyz(p):
    return " ".join(f"{x:.9g}" for x in p)


def undo_motion(p, m):
    """The point of B before the motion m = (DX DY DZ AX AY AZ DEG): rotation about the axis through the
    origin, then the move; undone as the move back, then the rotation by -DEG (Rodrigues)."""
    v = [p[i] - m[i] for i in range(3)]
    n = math.sqrt(sum(x * x for x in m[3:6]))
    if m[6] == 0 or n == 0:
        return v
    k = [x / n for x in m[3:6]]
    c, s = math.cos(math.radians(-m[6])), math.sin(math.radians(-m[6]))
    kxv = [k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]]
    kv = sum(k[i] * v[i] for i in range(3))
    return [v[i] * c + kxv[i] * s + k[i] * kv * (1 - c) for i in range(3)]


class Runner:
    def __init__(self, args):
        self.a = args
        self.out = args.out
        os.makedirs(self.out, exist_ok=True)
        self.models = os.path.join(self.out, "models")
        os.makedirs(self.models, exist_ok=True)

    def nurbsgl(self, *args, stderr_to=None):
        gl = ["--gl", self.a.gl] if self.a.gl else []
        return run_json([self.a.nurbsgl, *gl, *args], stderr_to)

    def each_method(self, what, run):
        """{method: run(method)} for the methods whose run succeeds; a failure is reported, not fatal."""
        out = {}
        for m in METHODS:
            try:
                out[m] = run(m)
            except RuntimeError as e:
                print(f"\n{what}: {m} failed: {e}")
        return out

    def clearance(self, a, b, method, *args, stderr_to=None):
        return self.nurbsgl("clearance", a, b, *args, *METHODS[method], "--tol", str(self.a.tol), "--json",
                            stderr_to=stderr_to)

    def reps(self, method):
        """Queries per position of a method: fewer for the paper preset (its voxel stage is slow)."""
        return min(self.a.reps, self.a.paper_reps) if method == "paper" else self.a.reps

    def peer(self, *args):
        """The peer's JSON, or None when the peer was not built (its columns then stay empty)."""
        return run_json([self.a.peer, *args]) if self.a.peer else None

    def occt_shapes(self, name, a, b, frames, witnesses, repeat):
        """BRepExtrema_DistShapeShape per frame (motion lines); witnesses: (frame, point_a, point_b) of
        our answers, whose distances to OCCT's faces come back in that order as (gap_a, gap_b)."""
        motion, wfile = self.path(f"{name}_occt_motion.txt"), self.path(f"{name}_occt_witness.txt")
        write_lines(motion, frames)
        write_lines(wfile, [f"{k} {fmt_xyz(pa)} {fmt_xyz(pb)}" for k, pa, pb in witnesses])
        j = self.peer("shapes", a, b, "--motion", motion, "--witness", wfile, "--repeat", str(repeat))
        if j is None:
            j = {"results": [{"seconds": math.nan, "first_seconds": math.nan} for _ in frames],
                 "tolerance": math.nan, "read_seconds": math.nan,
                 "witnesses": [{"gap_a": "", "gap_b": ""} for _ in witnesses]}
        return j, [(w["gap_a"], w["gap_b"]) for w in j["witnesses"]]

    def our_gaps(self, a, b, occt_result, motion):
        """Distances of OCCT's witness points to our models (`nurbsgl distance --point`, one query each,
        the per-point path), B's point moved back first: (gap_a, gap_b)."""
        pa, pb = occt_result["point_a"], undo_motion(occt_result["point_b"], motion)
        return tuple(self.nurbsgl("distance", m, "--point", ",".join(f"{x:.9g}" for x in p), "--tol", str(self.a.tol),
                                  "--json")["distance"] for m, p in ((a, pa), (b, pb)))

    def gaps_where_occt_smaller(self, a, b, occt_results, motions, answers):
        """our_gaps for the frames k where OCCT is below some answer of ours by more than its bound;
        answers: (k, distance, bound, occt tolerance)."""
        need = sorted({k for k, d, bound, tol in answers
                       if "distance" in occt_results[k] and occt_results[k]["distance"] < d - bound - tol})
        return {k: self.our_gaps(a, b, occt_results[k], motions[k]) for k in need}

    def model(self, name):
        path = os.path.join(self.models, name + ".igs")
        if not os.path.exists(path):
            log(f"  $ nurbsgl generate {name}")
            subprocess.run([self.a.nurbsgl, "generate", name, "-o", path], check=True, capture_output=True)
        return path

    def path(self, name):
        return os.path.join(self.out, name)

    # --- Tables 1 and 3, Fig. 12 -------------------------------------------------------------------
    def pair_table(self, table, a, b, positions):
        """One nurbsgl process per method (one prepare), each position repeated; OCCT per position."""
        reps = {m: self.reps(m) for m in METHODS}

        def run(m):
            motion = self.path(f"{table}_{m}_motion.txt")
            write_lines(motion, [motion_line(p) for _, p, _ in positions for _ in range(reps[m])])
            return self.clearance(a, b, m, "--motion", motion)

        ours = self.each_method(table, run)
        if not ours:
            return
        last = {(k, m): ours[m]["results"][(k + 1) * reps[m] - 1] for k in range(len(positions)) for m in ours}
        occt, gaps = self.occt_shapes(table, a, b, [motion_line(p) for _, p, _ in positions],
                                      [(k, r["point_a"], r["point_b"]) for (k, _), r in last.items()],
                                      max(self.a.reps, 3))
        gaps = dict(zip(last.keys(), gaps))
        back = self.gaps_where_occt_smaller(a, b, occt["results"], [p for _, p, _ in positions],
                                            [(k, r["distance"], r["bound"], occt["tolerance"])
                                             for (k, _), r in last.items()])
        rows, levels = [], []
        for k, (name, pos, where) in enumerate(positions):
            o = occt["results"][k]
            for m in ours:
                j = ours[m]
                frames = j["results"][k * reps[m]:(k + 1) * reps[m]]
                r = frames[-1]
                g = gaps[(k, m)]
                size = j["tolerance"] / self.a.tol
                steady = statistics.median(f["seconds"] for f in frames[1:]) if reps[m] > 1 else r["seconds"]
                d_o = o.get("distance")
                rows.append({
                    "table": table, "position": name, "motion": motion_line(pos), "where": where, "method": m,
                    "preset": j.get("preset", {}).get("name", ""), "queries": reps[m],
                    "distance": r["distance"], "bound": r["bound"], "bound_over_size": r["bound"] / size,
                    "model_size": size, "tolerance": j["tolerance"],
                    "prepare_s": j["prepare_seconds"] if k == 0 else "",
                    "first_query_s": frames[0]["seconds"], "query_s": steady, "levels": len(r["pairs_per_level"]),
                    "leaf_pairs": r["leaf_pairs"], "meets_tolerance": r.get("meets_tolerance", ""),
                    "refine_rounds": r.get("refine", {}).get("rounds", ""),
                    "refine_cells": r.get("refine", {}).get("cells", ""),
                    "refine_s": r.get("refine", {}).get("seconds", ""),
                    "on_trim_edge": r.get("on_trim_edge", ""), "face_a": r["face_a"], "face_b": r["face_b"],
                    "point_a": fmt_xyz(r["point_a"]), "point_b": fmt_xyz(r["point_b"]),
                    "occt_distance": d_o if d_o is not None else "", "occt_s": o["seconds"],
                    "occt_point_a": fmt_xyz(o["point_a"]) if d_o is not None else "",
                    "occt_point_b": fmt_xyz(o["point_b"]) if d_o is not None else "",
                    "occt_first_s": o["first_seconds"], "occt_tolerance": occt["tolerance"],
                    "diff_occt": (d_o - r["distance"]) if d_o is not None else "",
                    "occt_gap_a": g[0], "occt_gap_b": g[1],
                    "ours_gap_a": back.get(k, ("", ""))[0], "ours_gap_b": back.get(k, ("", ""))[1],
                    "within": within(r["distance"], r["bound"], d_o, occt["tolerance"], g, back.get(k)),
                    "occt_over_ours": o["seconds"] / steady,
                })
                for lvl, n in enumerate(r["pairs_per_level"]):
                    levels.append({"table": table, "position": name, "method": m, "level": lvl, "pairs": n})
        write_csv(self.path(f"{table}.csv"), rows)
        write_csv(self.path(f"{table}_fig12_pairs_per_level.csv"), levels)
        self.plot_pair_table(table, rows, positions)
        self.plot_levels(table, levels, positions)
        print(f"\n{table}: {os.path.basename(a)} vs {os.path.basename(b)}, tol {self.a.tol:g} x model size, "
              f"median of the queries after the first ({', '.join(f'{m} {max(reps[m] - 1, 1)}' for m in ours)})")
        print(f"{'position':<8} {'method':<15} {'distance':>12} {'bound/size':>10} {'prep ms':>8} {'1st ms':>8} "
              f"{'query ms':>9} {'OCCT d':>12} {'OCCT ms':>8} {'OCCT/ours':>9} within")
        for r in rows:
            prep = f"{1e3 * r['prepare_s']:.0f}" if r["prepare_s"] != "" else ""
            print(f"{r['position']:<8} {r['method']:<15} {r['distance']:>12.6f} {r['bound_over_size']:>10.2e} "
                  f"{prep:>8} {1e3 * r['first_query_s']:>8.1f} {1e3 * r['query_s']:>9.1f} "
                  f"{num(r['occt_distance'], '>12.6f')} {num(1e3 * r['occt_s'], '>8.1f')} {num(r['occt_over_ours'], '>8.2f', 'x')} "
                  f"{r['within']}{not_met(r)}")
        return rows

    def plot_pair_table(self, table, rows, positions):
        if plt is None:
            return
        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4))
        names = [p[0] for p in positions]
        series = [(m, "query_s", [m]) for m in METHODS] + [("OCCT", "occt_s", list(METHODS))]
        w = 0.8 / len(series)
        for i, (label, key, filt) in enumerate(series):
            ys = [1e3 * next((r[key] for r in rows if r["position"] == n and r["method"] in filt), math.nan)
                  for n in names]
            ax0.bar([x + (i - (len(series) - 1) / 2) * w for x in range(len(names))], ys, w, label=label)
        ax0.set_xticks(range(len(names)), names)
        ax0.set_yscale("log")
        ax0.set_ylim(bottom=1)
        ax0.set_ylabel("time per query (ms)")
        ax0.set_title(f"{table}: time per position")
        ax0.legend()
        for i, m in enumerate(METHODS):
            ys = [next((r["bound_over_size"] for r in rows if r["position"] == n and r["method"] == m), math.nan)
                  for n in names]
            ax1.bar([x + (i - (len(METHODS) - 1) / 2) * w for x in range(len(names))], ys, w, label=m)
        ax1.axhline(2 * self.a.tol, color="k", ls="--", lw=0.8, label="2 x tol (K_a + K_b)")
        ax1.set_xticks(range(len(names)), names)
        ax1.set_ylabel("bound / model size")
        ax1.set_title(f"{table}: bound")
        ax1.legend()
        fig.tight_layout()
        fig.savefig(self.path(f"{table}.png"), dpi=110)
        plt.close(fig)

    def plot_levels(self, table, levels, positions):
        if plt is None:
            return
        fig, ax = plt.subplots(figsize=(6, 4))
        for name, _, _ in positions:
            for m, ls in zip(METHODS, ("-", "--", ":")):
                pts = [(r["level"], r["pairs"]) for r in levels if r["position"] == name and r["method"] == m]
                ax.plot([p[0] for p in pts], [p[1] for p in pts], ls, marker="o", ms=3, label=f"{name} {m}")
        ax.set_yscale("log")
        ax.set_xlabel("level (0 = root pairs)")
        ax.set_ylabel("surviving pairs")
        ax.set_title(f"Fig. 12 ({table}): pairs per level")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(self.path(f"{table}_fig12_pairs_per_level.png"), dpi=110)
        plt.close(fig)

    def tables(self):
        positions = POSITIONS[:1] if self.a.quick else POSITIONS
        a = self.model("paper-199x33")
        self.pair_table("table1", a, self.model("paper-100x105"), positions)
        self.pair_table("table3", a, self.model("paper-100x105-trimmed"), positions)

    # --- Table 2 -----------------------------------------------------------------------------------
    def table2(self):
        a, b = self.model("paper-199x33"), self.model("paper-100x105")
        name, pos, _ = POSITIONS[0]
        rows, errs = [], {}

        def run(m):
            errs[m] = []
            return self.clearance(a, b, m, "--move-b", ",".join(f"{x:g}" for x in pos[:3]), "--rotate-b",
                                  ",".join(f"{x:g}" for x in pos[3:]), "--timings", stderr_to=errs[m])

        for m, j in self.each_method("table2", run).items():
            err = errs[m]
            rows.append({"method": m, "pass": "prepare (grids, wall)", "calls": "", "gpu_ms": "",
                         "cpu_ms": 1e3 * j["prepare_seconds"]})
            for key, v in j.get("prepare", {}).items():  # the CLI's preparation breakdown, where it gives one
                if key.endswith("_seconds"):
                    rows.append({"method": m, "pass": f"  prepare: {key[:-8]}", "calls": "", "gpu_ms": "",
                                 "cpu_ms": 1e3 * v})
            for line in err[0].splitlines():
                f = line.split()
                if len(f) == 4 and re.fullmatch(r"\d+", f[1]):
                    rows.append({"method": m, "pass": f[0], "calls": int(f[1]), "gpu_ms": float(f[2]),
                                 "cpu_ms": float(f[3])})
                elif len(f) == 3 and f[0] == "total":
                    rows.append({"method": m, "pass": "total (passes)", "calls": "", "gpu_ms": float(f[1]),
                                 "cpu_ms": float(f[2])})
            if "refine" in j:
                rows.append({"method": m, "pass": "refine (CPU, double)", "gpu_ms": "",
                             "calls": f"{j['refine'].get('rounds')} rounds, {j['refine'].get('cells')} cells",
                             "cpu_ms": 1e3 * j["refine"].get("seconds", math.nan)})
            rows.append({"method": m, "pass": "query (wall, passes synchronised)", "calls": "", "gpu_ms": "",
                         "cpu_ms": 1e3 * j["seconds"]})
        write_csv(self.path("table2.csv"), rows)
        passes = [r for r in rows if isinstance(r["calls"], int)]
        names = list(dict.fromkeys(r["pass"] for r in passes))
        methods = list(dict.fromkeys(r["method"] for r in rows))
        if plt is not None:
            fig, ax = plt.subplots(figsize=(7, 4))
            bottom = [0.0] * len(methods)
            for n in names:
                ys = [sum(r["gpu_ms"] for r in passes if r["pass"] == n and r["method"] == m) for m in methods]
                ax.bar(methods, ys, 0.5, bottom=bottom, label=n)
                bottom = [b0 + y for b0, y in zip(bottom, ys)]
            ax.set_ylabel("GPU ms (GL_TIME_ELAPSED)")
            ax.set_title(f"Table 2: passes of one query (Table 1, position '{name}')")
            ax.legend(fontsize=7)
            fig.tight_layout()
            fig.savefig(self.path("table2.png"), dpi=110)
            plt.close(fig)
        print(f"\ntable2: passes of one clearance query, Table 1 position '{name}' (ms, synchronised)")
        print(f"{'pass':<36} " + " ".join(f"{m + ' gpu':>20} {m + ' cpu':>20}" for m in methods))
        for n in list(dict.fromkeys(r["pass"] for r in rows)):
            cells = []
            for m in methods:
                r = next((r for r in rows if r["pass"] == n and r["method"] == m), None)
                g = "" if r is None or r["gpu_ms"] == "" else f"{r['gpu_ms']:.1f}"
                c = "" if r is None else f"{r['cpu_ms']:.1f}"
                cells.append(f"{g:>20} {c:>20}")
            print(f"{n:<36} " + " ".join(cells))

    # --- Fig. 16 -----------------------------------------------------------------------------------
    def fig16(self):
        """B glides along A, turning about z and bobbing, always above A's crests (distance 3..11)."""
        a, b = self.model("paper-199x33"), self.model("paper-100x105")
        frames = 20 if self.a.quick else 100
        lines = []
        for k in range(frames):
            t = k / (frames - 1)
            s, c = math.sin(2 * math.pi * t), math.cos(2 * math.pi * t)
            lines.append(f"{100 * t:.6g} {-20 + 10 * s:.6g} {-6 + 2 * c:.6g} 0 0 1 {10 * s:.6g}")
        # The frames each method runs: all, or every few for the paper preset (--paper-frames of them).
        step = max(1, frames // max(1, self.a.paper_frames))
        run_frames = {m: list(range(0, frames, step)) if m == "paper" else list(range(frames)) for m in METHODS}

        def run(m):
            motion = self.path(f"fig16_{m}_motion.txt")
            write_lines(motion, [lines[k] for k in run_frames[m]])
            return self.clearance(a, b, m, "--motion", motion)

        ours = self.each_method("fig16", run)
        if not ours:
            return
        res = {m: dict(zip(run_frames[m], ours[m]["results"])) for m in ours}  # method -> frame -> answer
        order = [(m, k) for m in ours for k in res[m]]
        occt, gaps = self.occt_shapes("fig16", a, b, lines, [(k, res[m][k]["point_a"], res[m][k]["point_b"])
                                                              for m, k in order], 1)
        gaps = dict(zip(order, gaps))
        back = self.gaps_where_occt_smaller(a, b, occt["results"], [[float(x) for x in ln.split()] for ln in lines],
                                            [(k, res[m][k]["distance"], res[m][k]["bound"], occt["tolerance"])
                                             for m, k in order])
        rows = []
        for k in range(frames):
            o = occt["results"][k]
            row = {"frame": k + 1, "motion": lines[k], "occt_distance": o.get("distance", ""), "occt_s": o["seconds"]}
            for m in ours:
                r = res[m].get(k)
                row[f"{m}_s"] = r["seconds"] if r else ""
                row[f"{m}_distance"] = r["distance"] if r else ""
                row[f"{m}_bound"] = r["bound"] if r else ""
                # Fig. 16(b): the distance and position tolerances as fractions of the model size.
                size = ours[m]["tolerance"] / self.a.tol
                row[f"{m}_bound_over_size"] = r["bound"] / size if r else ""
                row[f"{m}_point_bound_over_size"] = r["point_bound"] / size if r else ""
                row[f"{m}_meets_tolerance"] = r.get("meets_tolerance", "") if r else ""
                row[f"{m}_within"] = within(r["distance"], r["bound"], o.get("distance"), occt["tolerance"],
                                            gaps[(m, k)], back.get(k)) if r else ""
            row["ours_gap_a"], row["ours_gap_b"] = back.get(k, ("", ""))
            rows.append(row)
        write_csv(self.path("fig16.csv"), rows)
        if plt is not None:
            fig, (ax0, ax1) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
            x = [r["frame"] for r in rows]
            for m in ours:
                ran = [r for r in rows if r[f"{m}_s"] != ""]
                style = "o-" if len(ran) < len(rows) else "-"
                ax0.plot([r["frame"] for r in ran], [1e3 * r[f"{m}_s"] for r in ran], style, ms=3, label=m)
                ax1.plot([r["frame"] for r in ran], [r[f"{m}_bound_over_size"] for r in ran], style, ms=3,
                         label=f"distance, {m}")
                ax1.plot([r["frame"] for r in ran], [r[f"{m}_point_bound_over_size"] for r in ran], "--", ms=3,
                         label=f"position, {m}")
            ax0.plot(x, [1e3 * r["occt_s"] for r in rows], label="OCCT")
            ax0.set_yscale("log")
            ax0.set_ylabel("ms per frame")
            ax0.set_title("Fig. 16: 199x33 vs 100x105 moving")
            ax0.legend()
            ax1.set_yscale("log")
            ax1.set_ylabel("tolerance / model size")
            ax1.set_xlabel("frame")
            ax1.set_title("Fig. 16(b): distance tolerance K and position tolerance sqrt(4Kd + K^2)", fontsize=9)
            ax1.legend(loc="upper left", fontsize=7, ncol=2)
            fig.tight_layout()
            fig.savefig(self.path("fig16.png"), dpi=110)
            plt.close(fig)
        occt_ms = 1e3 * statistics.median(r["occt_s"] for r in rows)
        print(f"\nfig16: {frames} frames, tol {self.a.tol:g} x model size (median ms per frame; bound min-max)")
        for m in ours:
            ran = [r for r in rows if r[f"{m}_s"] != ""]
            ms = 1e3 * statistics.median(r[f"{m}_s"] for r in ran)
            bounds = [r[f"{m}_bound"] for r in ran]
            position = [r[f"{m}_point_bound_over_size"] for r in ran]
            bad = verdicts(r[f"{m}_within"] for r in ran)
            n_unmet = sum(r[f"{m}_meets_tolerance"] is False for r in ran)
            unmet = f"; tolerance not met on {n_unmet} frames" if n_unmet else ""
            print(f"  {m:<15} {len(ran):>3} frames, prepare {1e3 * ours[m]['prepare_seconds']:.0f} ms, {ms:.1f} "
                  f"ms/frame, bound {min(bounds):.3g}-{max(bounds):.3g}"
                  + (f", OCCT {occt_ms:.1f} ms/frame" if occt_ms == occt_ms else "") + peer_ratio(occt_ms, ms, ".2f")
                  + f", OCCT outside our bound: {bad}{unmet}; position tolerance / size "
                  f"{min(position):.2g}-{max(position):.2g}")

    # --- Table 5 -----------------------------------------------------------------------------------
    def table5(self):
        shared = os.path.join(self.a.shared, "models")
        pairs = [
            ("teapot-vase", "generated/vase_shell_t2.igs", "generated/teapot_bezier32.igs",
             (33.75, 0, 48.65, 0, 0, 1, 0), "teapot at the vase wall, closest point on a vase face's seam (README)"),
            ("teapot-vase-low", "generated/vase_shell_t2.igs", "generated/teapot_bezier32.igs", (44, 0, 36, 0, 0, 1, 0),
             "teapot outside the vase wall, lower"),
            ("45faces-self", "iges/pythonocc_example_45_faces.iges", "iges/pythonocc_example_45_faces.iges",
             (0, 0, 40, 0, 0, 1, 0), "the 45-face part over itself, moved 40 up"),
            ("bearing-self", "iges/occt_bearing.iges", "iges/occt_bearing.iges", (0.01, 0, 0.035, 0, 0, 1, 0),
             "the 213-face bearing over itself, moved up and aside"),
        ]
        if self.a.quick:
            pairs = pairs[:1]
        if not os.path.isdir(shared):
            print(f"\ntable5: skipped, {shared} is absent")
            return
        rows = []
        help_text = subprocess.run([self.a.nurbsgl, "clearance", "--help"], capture_output=True, text=True).stdout
        voxels = "--first-stage" in help_text
        for name, fa, fb, pos, where in pairs:
            a, b = os.path.join(shared, fa), os.path.join(shared, fb)
            if not (os.path.exists(a) and os.path.exists(b)):
                print(f"\ntable5: {name} skipped, {fa} or {fb} is absent")
                continue
            motion = self.path(f"table5_{name}_motion.txt")
            write_lines(motion, [motion_line(pos)] * 2)  # the first query, then one more (the CAD pairs are slow)
            ours = self.each_method(f"table5 {name}", lambda m: self.clearance(a, b, m, "--motion", motion))
            if voxels:  # the paper's §5.4 voxel first stage before the hierarchy, on the default search
                try:
                    ours[VOXELS] = self.clearance(a, b, "default", "--motion", motion, "--first-stage", "voxels")
                except RuntimeError as e:
                    print(f"\ntable5 {name}: {VOXELS} failed: {e}")
            if not ours:
                continue
            occt, gaps = self.occt_shapes(f"table5_{name}", a, b, [motion_line(pos)],
                                          [(0, j["results"][-1]["point_a"], j["results"][-1]["point_b"])
                                           for j in ours.values()], 3)
            o = occt["results"][0]
            back = self.gaps_where_occt_smaller(a, b, [o], [pos], [(0, j["results"][-1]["distance"], j["results"][-1][
                "bound"], occt["tolerance"]) for j in ours.values()]).get(0)
            for (m, j), g in zip(ours.items(), gaps):
                fr = j["results"]
                r = fr[-1]
                steady = statistics.median(f["seconds"] for f in fr[1:]) if len(fr) > 1 else r["seconds"]
                size = j["tolerance"] / self.a.tol
                rows.append({
                    "pair": name, "a": fa, "b": fb, "motion": motion_line(pos), "where": where, "method": m,
                    "preset": j.get("preset", {}).get("name", ""),
                    "distance": r["distance"], "bound": r["bound"], "bound_over_size": r["bound"] / size,
                    "prepare_s": j["prepare_seconds"], "first_query_s": fr[0]["seconds"], "query_s": steady,
                    "first_total_s": j["prepare_seconds"] + fr[0]["seconds"], "leaf_pairs": r["leaf_pairs"],
                    "meets_tolerance": r.get("meets_tolerance", ""), "on_trim_edge": r.get("on_trim_edge", ""),
                    "first_stage_s": r.get("first_stage", {}).get("seconds", ""),
                    "first_stage_face_pairs": r.get("first_stage", {}).get("face_pairs", ""),
                    "face_a": r["face_a"], "face_b": r["face_b"], "point_a": fmt_xyz(r["point_a"]),
                    "point_b": fmt_xyz(r["point_b"]), "occt_distance": o.get("distance", ""), "occt_s": o["seconds"],
                    "occt_point_a": fmt_xyz(o["point_a"]) if "distance" in o else "",
                    "occt_point_b": fmt_xyz(o["point_b"]) if "distance" in o else "",
                    "occt_read_s": occt["read_seconds"], "occt_tolerance": occt["tolerance"],
                    "diff_occt": o["distance"] - r["distance"] if "distance" in o else "",
                    "occt_gap_a": g[0], "occt_gap_b": g[1], "ours_gap_a": back[0] if back else "",
                    "ours_gap_b": back[1] if back else "",
                    "within": within(r["distance"], r["bound"], o.get("distance"), occt["tolerance"], g, back),
                    "occt_over_ours": o["seconds"] / steady, "occt_over_first_total": o["seconds"] / (
                        j["prepare_seconds"] + fr[0]["seconds"]),
                })
        if not rows:
            return
        write_csv(self.path("table5.csv"), rows)
        names = list(dict.fromkeys(r["pair"] for r in rows))
        if plt is not None:
            fig, ax = plt.subplots(figsize=(9, 4))
            series = [(f"{what}, {m}", m, key) for m in METHODS
                      for what, key in (("prepare + 1st", "first_total_s"), ("query", "query_s"))]
            series.append((f"query, {VOXELS}", VOXELS, "query_s"))
            w = 0.8 / (len(series) + 1)
            for i, (label, m, key) in enumerate(series):
                ys = [1e3 * next((r[key] for r in rows if r["pair"] == n and r["method"] == m), math.nan) for n in names]
                ax.bar([x + (i - len(series) / 2) * w for x in range(len(names))], ys, w, label=label)
            ys = [1e3 * next(r["occt_s"] for r in rows if r["pair"] == n) for n in names]
            ax.bar([x + len(series) / 2 * w for x in range(len(names))], ys, w, label="OCCT")
            ax.set_xticks(range(len(names)), names)
            ax.set_yscale("log")
            ax.set_ylim(bottom=1)
            ax.set_ylabel("ms")
            ax.set_title("Table 5: object clearance")
            ax.legend(fontsize=7)
            fig.tight_layout()
            fig.savefig(self.path("table5.png"), dpi=110)
            plt.close(fig)
        print(f"\ntable5: object pairs, tol {self.a.tol:g} x the larger model size")
        print(f"{'pair':<15} {'method':<15} {'distance':>10} {'bound':>9} {'prep ms':>8} {'1st ms':>8} {'query ms':>9} "
              f"{'OCCT d':>10} {'OCCT ms':>8} {'OCCT/query':>10} {'OCCT/(prep+1st)':>15} within")
        for r in rows:
            print(f"{r['pair']:<15} {r['method']:<15} {r['distance']:>10.5f} {r['bound']:>9.2e} "
                  f"{1e3 * r['prepare_s']:>8.0f} {1e3 * r['first_query_s']:>8.1f} {1e3 * r['query_s']:>9.1f} "
                  f"{num(r['occt_distance'], '>10.5f')} {num(1e3 * r['occt_s'], '>8.1f')} "
                  f"{num(r['occt_over_ours'], '>9.2f', 'x')} {num(r['occt_over_first_total'], '>14.2f', 'x')} "
                  f"{r['within']}{not_met(r)}")

    # --- points ------------------------------------------------------------------------------------
    def points(self):
        """`distance --points` by default (the batched projection) on all points, and one query per point
        on the first --per-point-sample points: the paper preset (`--paper`: per point, faithful) and the
        coarse-to-fine search (`--per-point`); against OCCT's projection of every point."""
        model = self.model("paper-100x105")
        n = 200 if self.a.quick else self.a.points
        rnd = random.Random(8)
        pts = [(rnd.uniform(0, 100), rnd.uniform(0, 100), rnd.uniform(11, 29)) for _ in range(n)]
        file = self.path("points_input.txt")
        write_lines(file, [f"{x:.9g} {y:.9g} {z:.9g}" for x, y, z in pts])
        sample = min(n, 20 if self.a.quick else self.a.per_point_sample)
        sample_file = self.path("points_input_sample.txt")
        write_lines(sample_file, [f"{x:.9g} {y:.9g} {z:.9g}" for x, y, z in pts[:sample]])
        tol = ["--tol", str(self.a.tol), "--json"]
        runs = {}
        try:
            runs["points"] = self.nurbsgl("distance", model, "--points", file, *tol)
            runs["points"]["label"] = f"default (--points, {runs['points'].get('path', 'as the CLI gives it')})"
        except RuntimeError as e:
            print(f"\npoints: --points failed: {e}")
        for key, args, label in (("paper", ["--paper"], "paper (--paper, per point)"),
                                 ("coarse-to-fine", ["--per-point"], "per point, coarse-to-fine")):
            try:
                runs[key] = self.nurbsgl("distance", model, "--points", sample_file, *args, *tol)
                runs[key]["label"] = label
            except RuntimeError as e:
                print(f"\npoints: {label} failed: {e}")
        if not runs:
            return
        occt = self.peer("points", model, "--points", file, "--repeat", "3") or {
            "results": [{"distance": None}] * n, "init_seconds": math.nan, "seconds": math.nan}
        big = 2000 if self.a.quick else self.a.batch_points
        if big > n and "points" in runs:  # throughput at scale: the batched path only (OCCT is per point anyway)
            big_file = self.path("points_input_large.txt")
            write_lines(big_file, [f"{rnd.uniform(0, 100):.9g} {rnd.uniform(0, 100):.9g} {rnd.uniform(11, 29):.9g}"
                                   for _ in range(big)])
            try:
                runs["large"] = self.nurbsgl("distance", model, "--points", big_file, *tol)
                path = runs["large"].get("path", "as the CLI gives it")
                runs["large"]["label"] = f"default (--points, {path}, {big} points)"
            except RuntimeError as e:
                print(f"\npoints: --points with {big} points failed: {e}")
        rows = []
        for k, p in enumerate(pts):
            o = occt["results"][k]["distance"]
            row = {"i": k, "x": p[0], "y": p[1], "z": p[2], "occt_distance": "" if o is None else o}
            for key, j in runs.items():
                if key == "large":
                    continue
                r = j["results"][k] if k < len(j["results"]) else None
                row[f"{key}_distance"] = r["distance"] if r else ""
                row[f"{key}_bound"] = r["bound"] if r else ""
                row[f"{key}_diff_occt"] = "" if o is None or r is None else o - r["distance"]
                row[f"{key}_within"] = within(r["distance"], r["bound"], o, 0.0) if r else ""
            rows.append(row)
        write_csv(self.path("points.csv"), rows)
        summary = []
        for key, j in runs.items():
            count = len(j["results"])
            summary.append({"method": j["label"], "key": key, "points": count, "prepare_s": j["prepare_seconds"],
                            "query_s": j["seconds"], "ms_per_point": 1e3 * j["seconds"] / count,
                            "points_per_s": count / j["seconds"]})
        if self.a.peer:
            summary.append({"method": "OCCT GeomAPI_ProjectPointOnSurf", "key": "occt", "points": n,
                            "prepare_s": occt["init_seconds"], "query_s": occt["seconds"],
                            "ms_per_point": 1e3 * occt["seconds"] / n, "points_per_s": n / occt["seconds"]})
        write_csv(self.path("points_summary.csv"), summary)
        if plt is not None:
            fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4))
            labels = [s["method"].replace(" (", "\n(").replace(", ", ",\n").replace("OCCT GeomAPI_", "OCCT\n")
                      for s in summary]
            ax0.bar(labels, [s["ms_per_point"] for s in summary])
            ax0.set_yscale("log")
            ax0.set_ylabel("ms per point")
            ax0.set_title("points near the 100x105 surface")
            for key, j in runs.items():
                if key == "large":
                    continue
                ratios = [r[f"{key}_diff_occt"] / r[f"{key}_bound"] for r in rows if r[f"{key}_diff_occt"] != ""]
                ax1.hist(ratios, bins=40, range=(-3, 3), alpha=0.5, label=j["label"])
            ax1.set_xlabel("(d_OCCT - d) / bound (within the bound: |x| <= 1; beyond +-3 not shown)")
            ax1.set_ylabel("points")
            ax1.legend()
            fig.tight_layout()
            fig.savefig(self.path("points.png"), dpi=110)
            plt.close(fig)
        occt_ms = 1e3 * occt["seconds"] / n
        none = sum(r["occt_distance"] == "" for r in rows)
        print(f"\npoints: {n} random points near the 100x105 surface, tol {self.a.tol:g} x model size")
        for s in summary[:-1] if self.a.peer else summary:
            m = s["key"]
            if m == "large":
                print(f"  {s['method']:<40} prepare {1e3 * s['prepare_s']:.0f} ms, {s['ms_per_point']:.4f} ms/point "
                      f"({s['points_per_s']:.0f} points/s){peer_ratio(occt_ms, s['ms_per_point'], '.1f')}")
                continue
            diffs = [abs(r[f"{m}_diff_occt"]) for r in rows if r[f"{m}_diff_occt"] != ""]
            bad = verdicts(r[f"{m}_within"] for r in rows if r[f"{m}_within"])
            print(f"  {s['method']:<40} {s['points']} points, prepare {1e3 * s['prepare_s']:.0f} ms, "
                  f"{s['ms_per_point']:.3f} ms/point "
                  f"({s['points_per_s']:.0f} points/s){peer_ratio(occt_ms, s['ms_per_point'], '.2f')}"
                  + (f", max |d - d_OCCT| {max(diffs):.2e}, OCCT outside our bound: {bad}" if diffs else ""))
        pairs = [(r["points_distance"] - r["paper_distance"], r["points_bound"] + r["paper_bound"]) for r in rows
                 if "points" in runs and "paper" in runs and r["paper_distance"] != ""]
        if pairs:
            print(f"  default --points vs the paper preset on {len(pairs)} points: max |diff| "
                  f"{max(abs(d) for d, _ in pairs):.2e}, beyond both bounds on {sum(abs(d) > b for d, b in pairs)}")
        if self.a.peer:
            print(f"  {'OCCT':<40} {n} points, init {1e3 * occt['init_seconds']:.2f} ms, {occt_ms:.3f} ms/point, "
                  f"no projection found for {none} points")


def ms(rows, **match):
    """'12.3 ms' of the query_s of the row matching every key, or 'not run'."""
    r = next((r for r in rows if all(r.get(k) == v for k, v in match.items())), None)
    return f"{1e3 * r['query_s']:.1f} ms" if r and r.get("query_s", "") != "" else "not run"


# The CSVs each experiment writes (those docs/benchmarks.md shows).
WRITES = {"tables": ("table1", "table3", "table1_fig12_pairs_per_level"), "table2": ("table2",),
          "fig16": ("fig16",), "table5": ("table5",), "points": ("points_summary",)}


def publish(a, info, left_out, done):
    """docs/benchmarks.md and REPRODUCTION.md: the tables and rows of the experiments run (done), from
    the CSVs in a.out; a --quick run's tables are captioned apart, so they never replace a full run's."""
    command = a.command or shlex.join(["experiments/distance_tables.py", *sys.argv[1:]])
    ran = {name for e in done for name in WRITES[e]}
    csvs = {name: report.read_csv(os.path.join(a.out, name + ".csv")) if name in ran else [] for name in SHOWN}
    fig16 = report.read_csv(os.path.join(a.out, "fig16.csv")) if "fig16" in ran else []
    quick = " (--quick)" if a.quick else ""
    tables = [(f"`{name}.csv`{quick}", report.markdown_table(rows, SHOWN[name])) for name, rows in csvs.items() if rows]
    if fig16:
        per = [{"method": m, "frames": len(ran), "median_ms_per_frame": 1e3 * statistics.median(ran),
                "occt_median_ms": 1e3 * statistics.median(r["occt_s"] for r in fig16) if a.peer else ""}
               for m in METHODS for ran in [[r[f"{m}_s"] for r in fig16 if r.get(f"{m}_s", "") != ""]] if ran]
        tables.append((f"`fig16.csv` (per method){quick}", report.markdown_table(per)))
    report.write_benchmarks("Distance (Krishnamurthy et al.)", command, info, tables, left_out)
    rows = []
    for table, paper in (("table1", PAPER_TABLE1), ("table3", PAPER_TABLE3)):
        for k, (name, _, _) in enumerate(POSITIONS):
            if any(r["position"] == name for r in csvs[table]):
                rows.append((f"Table {table[-1]}, position {k + 1} (ours: '{name}')",
                             f"GPU {paper[k][0]} s, ACIS {paper[k][1]} s (Table {table[-1]})",
                             f"paper preset {ms(csvs[table], position=name, method='paper')}, default "
                             f"{ms(csvs[table], position=name, method='default')}"))
    if csvs["table2"]:
        wall = lambda m: next((f"{r['cpu_ms']:.1f} ms" for r in csvs["table2"]
                               if r["method"] == m and str(r["pass"]).startswith("query")), "not run")
        rows.append(("Table 2, total computation time", f"{PAPER_TABLE2_TOTAL} s (Table 2)",
                     f"paper preset {wall('paper')}, default {wall('default')}"))
    if csvs["table5"]:
        q = [r["query_s"] for r in csvs["table5"] if r["method"] == "default"]
        rows.append(("Table 5, object clearance per pair (other models)",
                     f"GPU {PAPER_TABLE5_GPU[0]}-{PAPER_TABLE5_GPU[1]} s over five pairs (Table 5)",
                     f"default {1e3 * min(q):.1f}-{1e3 * max(q):.1f} ms (pairs: {len(q)})" if q else "not run"))
    if fig16:
        rows.append(("Fig. 16(a), time per frame of the moving pair",
                     "under 0.15 s for most frames, 9.07 frames/s on average (Fig. 16(a))",
                     "; ".join(f"{p['method']} {p['median_ms_per_frame']:.1f} ms" for p in per)))
        tol = lambda m, what: [r[f"{m}_{what}_over_size"] for r in fig16 if r.get(f"{m}_{what}_over_size", "") != ""]
        rows.append(("Fig. 16(b), distance and position tolerances / model size",
                     "position tolerances below 4e-2 of the model size, the tolerance ACIS was run at (Fig. 16(b))",
                     "; ".join(f"{m}: distance {min(d):.2g}-{max(d):.2g}, position {min(q):.2g}-{max(q):.2g}"
                               for m in METHODS for d, q in [(tol(m, "bound"), tol(m, "point_bound"))] if d and q)))
    levels = report.read_csv(os.path.join(a.out, "table1_fig12_pairs_per_level.csv")) if "tables" in done else []
    if levels:
        first = levels[0]["position"]
        per_method = {m: [int(r["pairs"]) for r in levels if r["method"] == m and r["position"] == first]
                      for m in METHODS}
        rows.append(("Fig. 12, box pairs per level from the root (Table 1's pair)",
                     "rising over the first levels, then about constant, a few thousand, after level 3 (Fig. 12)",
                     "; ".join(f"{m} {', '.join(str(n) for n in p)}" for m, p in per_method.items() if p)
                     + f" (position '{first}')"))
    if rows:
        report.write_reproduction("Distance (Krishnamurthy et al.)", rows, command)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("experiments", nargs="*", metavar="EXPERIMENT",
                   help="all (default), tables, table2, fig16, table5, points")
    p.add_argument("--build", default=os.path.join(root, "build-bench"), help="build dir with cli/ and experiments/")
    p.add_argument("--nurbsgl", help="nurbsgl binary (default BUILD/cli/nurbsgl)")
    p.add_argument("--peer", help="peer_occt_distance binary (default BUILD/experiments/peer_occt_distance)")
    p.add_argument("--out", help="output dir (default BUILD/experiments)")
    p.add_argument("--shared", default=os.path.join(root, "..", "shared"), help="the shared folder (models/ in it)")
    p.add_argument("--tol", type=float, default=1e-5, help="tolerance relative to the model size")
    p.add_argument("--reps", type=int, default=4, help="queries per position (the first is reported apart)")
    p.add_argument("--points", type=int, default=1000, help="random points of the points experiment")
    p.add_argument("--batch-points", type=int, default=100000, help="points of the batched throughput run")
    p.add_argument("--per-point-sample", type=int, default=200, help="points of the one-query-per-point runs")
    p.add_argument("--paper-reps", type=int, default=2,
                   help="queries per position of the paper preset in Tables 1 and 3 (its voxel stage is slow)")
    p.add_argument("--paper-frames", type=int, default=10, help="frames of Fig. 16 that the paper preset runs")
    p.add_argument("--gl", help="GL backend passed to nurbsgl")
    p.add_argument("--quick", action="store_true", help="one position, fewer frames and points")
    p.add_argument("--command", help="the command line to name in docs/benchmarks.md and REPRODUCTION.md")
    p.add_argument("--no-docs", action="store_true", help="leave docs/benchmarks.md and REPRODUCTION.md alone")
    a = p.parse_args()
    a.nurbsgl = a.nurbsgl or os.path.join(a.build, "cli", "nurbsgl")
    a.peer = os.path.join(a.build, "experiments", "peer_occt_distance") if a.peer is None else a.peer
    if a.peer and not os.path.exists(a.peer):
        a.peer = ""  # not built: the OCCT columns stay empty
    a.out = a.out or os.path.join(a.build, "experiments")
    r = Runner(a)
    info = r.nurbsgl("gpu-info", "--json")
    commit = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    print(f"nurbsgl {commit.stdout.strip() or '(no git)'} on {info['renderer']} ({info['backend']}), "
          f"{os.cpu_count()} CPU cores; " + ("OCCT on one core" if a.peer else "no OCCT peer"))
    every = ["tables", "table2", "fig16", "table5", "points"]
    todo = every if not a.experiments or "all" in a.experiments else a.experiments
    for name in todo:
        if name not in every:
            p.error(f"unknown experiment '{name}' (all, {', '.join(every)})")
    for name in todo:
        log(f"== {name}")
        getattr(r, name)()
    left_out = ", ".join(w for w, gone in (("the OCCT columns", not a.peer), ("the plots", plt is None)) if gone)
    if not a.no_docs:
        publish(a, info, left_out, todo)
    print(f"\nCSV{'' if plt is None else ' and PNG'} files in {a.out}")


if __name__ == "__main__":
    main()
