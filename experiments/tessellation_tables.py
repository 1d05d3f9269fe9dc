#!/usr/bin/env python3
"""Tessellation experiments of Balazs, Guthe and Klein 2004, OpenCASCADE beside ours.

Every figure comes from the CLI (`nurbsgl tessellate --json`, `nurbsgl deviation --json`, the stable
contract) and the OCCT peer (`peer_occt_mesh`, BRepMesh_IncrementalMesh) in the same run on the same
machine. Per model, at eps = EPS x model size (default 1e-3):

  table2   trim curves (paper Table 2): conversion and approximation time, trim edges before and after
           the simplification (5), midpoint vs arbitrary split.
  table3   subdivision (Table 3): kd-tree vs quadtree x conservative (guaranteed) vs approximate error:
           triangles and times; the paper's four rows also with direct evaluation (`--evaluation
           direct`), for its two time columns (direct, and coherent as every other run).
  table4   quadtree baseline [Kah02] vs ours (Table 4): time, triangles, trim edges (both guaranteed).
  presets  the CLI's presets side by side, measured by --check: `paper` (`tessellate --paper`: the kd-tree
           with the control-net bound, midpoint split, simplified loops, loop polylines on every
           boundary, no watertight step) and `default` (no switch); also a row in Table 2.
  occt     OpenCASCADE at equal MEASURED deviation: our mesh's deviation D comes from `tessellate
           --check`; the deflection of BRepMesh is bisected until its mesh, measured by `nurbsgl
           deviation` the same way, lies within --match of D (the last mesh not above D is kept).

Writes table2.csv, table3.csv, table4.csv, presets.csv, occt.csv, a PNG per table and summary.txt (also on stdout),
with a verdict per model on the targets: >= 2x fewer triangles than the quadtree, no more
triangles than OCCT at equal measured deviation, the bearing (occt_bearing.iges) under 1 s.
Benchmarks, not tests: nothing fails on a slow figure; a command that fails is reported and skipped.
"""
import argparse
import csv
import glob
import json
import math
import os
import shlex
import shutil
import subprocess
import sys
import tempfile

import report

plt = report.pyplot()  # None without matplotlib: the plots are skipped

GENERATED = ["sphere", "torus", "cylinder", "paper-100x105-trimmed"]
VARIANTS = [  # key, --method, --mode, --split, --cell-bound (guaranteed mode: filip, or the paper's net)
    ("kd_g", "kdtree", "guaranteed", "midpoint", "filip"),
    ("kd_a", "kdtree", "approximate", "midpoint", "filip"),
    ("quad_g", "quadtree", "guaranteed", "midpoint", "filip"),
    ("quad_a", "quadtree", "approximate", "midpoint", "filip"),
    ("kd_g_net", "kdtree", "guaranteed", "midpoint", "net"),
    ("quad_g_net", "quadtree", "guaranteed", "midpoint", "net"),
    ("kd_g_arb", "kdtree", "guaranteed", "arbitrary", "filip"),
]
TABLE3 = ("kd_g", "kd_a", "quad_g", "quad_a", "kd_g_net", "quad_g_net")
# Table 3's two time columns: the paper's four rows run again with `--evaluation direct` (every vertex
# evaluated on its own); the runs above evaluate coherently (the column marked 3 in the paper).
DIRECT = ("kd_g_net", "kd_a", "quad_g_net", "quad_a")
# The presets compared: key, the options it adds. kd_g (above) is the default run; this is `--paper`.
PAPER = ("paper", ["--paper"])


def log(msg):
    print(msg, file=sys.stderr, flush=True)


class Failed(RuntimeError):
    pass


def run_json(cmd, timeout, ok=(0,)):
    """stdout of cmd as JSON; exit codes in `ok` are accepted when stdout holds the JSON (a failed check
    still prints its figures)."""
    log("  $ " + " ".join(cmd))
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise Failed(f"{os.path.basename(cmd[0])} {cmd[1] if len(cmd) > 1 else ''}: timed out after {timeout} s")
    try:
        j = json.loads(p.stdout) if p.returncode in ok else None
    except json.JSONDecodeError:
        j = None
    if j is None:
        raise Failed(f"{os.path.basename(cmd[0])} exited {p.returncode}: {p.stderr.strip()[-500:]}")
    return j


def write_csv(path, rows):
    if not rows:
        return
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    log(f"  wrote {path}")


def fmt(x, spec=".3g"):
    return "n/a" if x is None or x == "" else format(x, spec)


class Runner:
    def __init__(self, a):
        self.a = a
        self.tmp = tempfile.mkdtemp(prefix="tess_exp_")

    def tessellate(self, model, method, mode, split, bound, check=False, output=None, more=()):
        options = ["--method", method, "--mode", mode, "--split", split, "--cell-bound", bound, *more]
        return self.tessellate_with(model, options, check, output)

    def tessellate_with(self, model, options, check=False, output=None):
        cmd = [self.a.nurbsgl, "tessellate", model, "--eps", str(self.a.eps), "--relative", *options, "--json"]
        if self.a.loop_share is not None:
            cmd += ["--loop-share", str(self.a.loop_share)]
        if check:
            cmd += ["--check", "--check-samples", str(self.a.check_samples)]
        if output:
            cmd += ["-o", output]
        return run_json(cmd, self.a.timeout, ok=(0, 1))

    def deviation(self, model, mesh, eps_abs):
        cmd = [self.a.nurbsgl, "deviation", model, mesh, "--eps", repr(eps_abs), "--samples",
               str(self.a.check_samples), "--json"]
        return run_json(cmd, self.a.timeout, ok=(0, 1))

    def occt(self, model, deflection, output):
        cmd = [self.a.peer, model, "--deflection", repr(deflection), "--angular", str(self.a.angular), "-o", output]
        if self.a.occt_parallel:
            cmd.append("--parallel")
        return run_json(cmd, self.a.timeout)

    def match_occt(self, model, target, eps_abs, tries=None):
        """Bisects BRepMesh's linear deflection (geometrically) for a mesh whose measured deviation is
        `target`; returns the last tried mesh not above the target (else the finest) and all tries
        (`tries`: earlier ones of the same model, reused where a deflection comes again)."""
        mesh = os.path.join(self.tmp, "occt.ply")
        known = {t["deflection"]: t for t in (tries or [])}
        tries = []

        def attempt(d):
            if d in known:
                tries.append(known[d])
                return known[d]
            o = self.occt(model, d, mesh)
            dev = self.deviation(model, mesh, eps_abs)
            t = {"deflection": d, "triangles": o["triangles"], "seconds": o["seconds"],
                 "deviation": dev["max_deviation"], "bare_faces": o["faces_without_triangulation"]}
            tries.append(t)
            log(f"    OCCT deflection {d:.4g}: deviation {t['deviation']:.4g} (target {target:.4g}), "
                f"{t['triangles']} triangles")
            return t

        lo, hi = None, None  # deflections with deviation <= target, > target
        d = eps_abs  # first OCCT's nominal setting: deflection = our eps
        for _ in range(self.a.bisect_steps):
            t = attempt(d)
            if abs(t["deviation"] - target) <= self.a.match * target:
                break
            coarser = [u for u in tries[:-1] if u["deflection"] >= 2 * d]
            if coarser and t["deviation"] > 0.9 * min(u["deviation"] for u in coarser) and t["deviation"] > target:
                t["floor"] = True  # a finer mesh is hardly closer: the faces disagree (trims, gaps), stop
                log(f"    OCCT's deviation stays near {t['deviation']:.4g} however fine: no match")
                break
            if t["deviation"] <= target:
                lo = d if lo is None else max(lo, d)
            else:
                hi = d if hi is None else min(hi, d)
            # Bracketed: geometric bisection; else a secant step assuming deviation ~ deflection, within 8x.
            d = math.sqrt(lo * hi) if lo and hi else d * min(8.0, max(0.125, target / max(t["deviation"], 1e-300)))
        below = [t for t in tries if t["deviation"] <= target * (1 + self.a.match)]
        best = max(below, key=lambda t: t["deflection"]) if below else min(tries, key=lambda t: t["deviation"])
        best = dict(best, matched=bool(below), nominal=tries[0])
        return best, tries

    def model(self, path):
        name = os.path.splitext(os.path.basename(path))[0]
        log(f"== {name}")
        runs, errors = {}, []
        for key, method, mode, split, bound in VARIANTS:
            try:
                check = key in ("kd_g", "kd_g_net")
                out = os.path.join(self.tmp, "ours.ply") if key == "kd_g" else None
                runs[key] = self.tessellate(path, method, mode, split, bound, check=check, output=out)
                if key in DIRECT:
                    runs[key + "_direct"] = self.tessellate(path, method, mode, split, bound,
                                                            more=("--evaluation", "direct"))
            except Failed as e:
                errors.append(f"{key}: {e}")
                log(f"  {key}: {e}")
        try:
            runs[PAPER[0]] = self.tessellate_with(path, PAPER[1], check=True)
        except Failed as e:
            errors.append(f"{PAPER[0]}: {e}")
            log(f"  {PAPER[0]}: {e}")
        result = {"name": name, "path": path, "runs": runs, "errors": errors, "occt": None}
        ours = runs.get("kd_g")
        if ours and "check" in ours:  # our mesh through its file, measured as OCCT's will be (no (u, v))
            try:
                j = self.deviation(path, os.path.join(self.tmp, "ours.ply"), ours["eps"])
                result["ours_file_deviation"] = j["max_deviation"]
            except Failed as e:
                errors.append(f"deviation of our mesh file: {e}")
        if ours and "check" in ours and self.a.peer:
            try:
                best, tries = self.match_occt(path, ours["check"]["max_deviation"], ours["eps"])
                result["occt"], result["occt_tries"] = best, tries
                same = result.get("ours_file_deviation")
                # Same instrument: our mesh measured through its file as OCCT's is, when that differs.
                if same and abs(same - ours["check"]["max_deviation"]) > 0.2 * ours["check"]["max_deviation"]:
                    log(f"  our file measures {same:.4g}, not {ours['check']['max_deviation']:.4g}: matching that too")
                    result["occt_same"], more = self.match_occt(path, same, ours["eps"], tries)
                    result["occt_tries"] += [t for t in more if t not in tries]
            except Failed as e:
                errors.append(f"occt: {e}")
                log(f"  occt: {e}")
        return result


def preset_row(model, preset, j):
    """A row of the presets table: the preset's triangles, edges, time and measured deviation."""
    c = j.get("check", {})
    return {"model": model, "preset": preset, "eps": j["eps"], "triangles": j["triangles"],
            "trim_edges": j["trim_edges"], "open_edges": j["open_edges"], "cells": j["cells"],
            "rectangle_faces": j["trim"]["rectangle_faces"], "total_s": j["seconds"]["total"],
            "max_deviation": c.get("max_deviation", ""), "within_eps": c.get("within_eps", ""),
            "settings": json.dumps(j.get("preset", {}).get("settings", {}), sort_keys=True)}


def rows_of(results):
    t2, t3, t4, oc, pr = [], [], [], [], []
    for r in results:
        runs, n = r["runs"], r["name"]
        for key, name in (("kd_g", "default"), (PAPER[0], "paper")):
            if runs.get(key):
                pr.append(preset_row(n, name, runs[key]))
        for key, split, run in (("kd_g", "midpoint", "default"), ("kd_g_arb", "arbitrary", "arbitrary split"),
                                (PAPER[0], "midpoint", "paper")):
            j = runs.get(key)
            if j:
                tr = j["trim"]
                t2.append({"model": n, "faces": j["faces"], "run": run, "split": split,
                           "curve_pieces": tr["curve_pieces"],
                           "conversion_s": j["seconds"]["conversion"],
                           "approximation_s": j["seconds"]["trim_approximation"],
                           "edges_before": tr["edges_before_simplification"],
                           "edges_after": tr["edges_after_simplification"],
                           "reduction": tr["edges_before_simplification"] / max(1, tr["edges_after_simplification"])})
        for key, method, mode, split, bound in (v for v in VARIANTS if v[0] in TABLE3):
            j = runs.get(key)
            if j:
                s = j["seconds"]
                error = ("conservative" if bound == "filip" else "conservative-net") if mode == "guaranteed" else mode
                d = runs.get(key + "_direct")
                t3.append({"model": n, "method": method, "error": error,
                           "max_deviation": j["check"]["max_deviation"] if "check" in j else "",
                           "triangles": j["triangles"], "vertices": j["vertices"], "cells": j["cells"],
                           "failed_faces": j["failed_faces"], "total_s": s["total"],
                           "direct_total_s": d["seconds"]["total"] if d else "",
                           "surface_s": s["surface_approximation"], "trimming_s": s["trimming"],
                           "triangulation_s": s["triangulation"], "evaluation_s": s["evaluation"],
                           "direct_evaluation_s": d["seconds"]["evaluation"] if d else ""})
        q, k = runs.get("quad_g"), runs.get("kd_g")
        qn, kn = runs.get("quad_g_net"), runs.get("kd_g_net")
        if q and k:
            t4.append({"model": n, "quadtree_s": q["seconds"]["total"], "ours_s": k["seconds"]["total"],
                       "quadtree_triangles": q["triangles"], "ours_triangles": k["triangles"],
                       "triangle_ratio": q["triangles"] / max(1, k["triangles"]),
                       "net_quadtree_triangles": qn["triangles"] if qn else "",
                       "net_ours_triangles": kn["triangles"] if kn else "",
                       "net_triangle_ratio": qn["triangles"] / max(1, kn["triangles"]) if qn and kn else "",
                       "paper_quadtree_over_ours": qn["triangles"] / max(1, k["triangles"]) if qn else "",
                       "quadtree_trim_edges": q["trim_edges"], "ours_trim_edges": k["trim_edges"]})
        o = r["occt"]
        if k and o:
            c = k["check"]
            oc.append({"model": n, "faces": k["faces"], "eps": k["eps"], "ours_deviation": c["max_deviation"],
                       "ours_within_eps": c["within_eps"], "ours_triangles": k["triangles"],
                       "ours_file_deviation": r.get("ours_file_deviation", ""),
                       "ours_s": k["seconds"]["total"], "occt_deflection": o["deflection"],
                       "occt_deviation": o["deviation"], "occt_triangles": o["triangles"], "occt_s": o["seconds"],
                       "occt_matched": o["matched"], "occt_nominal_deviation": o["nominal"]["deviation"],
                       "occt_nominal_triangles": o["nominal"]["triangles"], "occt_nominal_s": o["nominal"]["seconds"],
                       "occt_bare_faces": o["bare_faces"], "occt_tries": len(r["occt_tries"]),
                       "occt_over_ours_triangles": o["triangles"] / max(1, k["triangles"])})
            same = r.get("occt_same")
            oc[-1].update({"same_instrument_target": r.get("ours_file_deviation", ""),
                           "same_occt_deviation": same["deviation"] if same else "",
                           "same_occt_triangles": same["triangles"] if same else "",
                           "same_occt_s": same["seconds"] if same else "",
                           "same_matched": same["matched"] if same else ""})
    return t2, t3, t4, oc, pr


def bars(path, title, models, series, ylabel, log_scale=True):
    """Grouped bars: series = [(label, [value per model or None])]."""
    if not models or plt is None:
        return
    fig, ax = plt.subplots(figsize=(max(6, 1.1 * len(models) + 2), 4.5))
    width = 0.8 / len(series)
    for i, (label, values) in enumerate(series):
        xs = [m + (i - (len(series) - 1) / 2) * width for m in range(len(models))]
        ax.bar(xs, [v if v is not None else 0 for v in values], width, label=label)
    ax.set_xticks(range(len(models)))
    ax.set_xticklabels(models, rotation=30, ha="right", fontsize=8)
    if log_scale:
        ax.set_yscale("log")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    log(f"  wrote {path}")


def plots(out, t2, t3, t4, oc, pr):
    mid = [r for r in t2 if r["run"] == "default"]
    bars(os.path.join(out, "table2.png"), "Trim edges before / after simplification (midpoint split)",
         [r["model"] for r in mid], [("before", [r["edges_before"] for r in mid]),
                                     ("after", [r["edges_after"] for r in mid])], "trim edges")
    models = sorted({r["model"] for r in t3}, key=[r["model"] for r in t3].index)
    series = []
    for method in ("kdtree", "quadtree"):
        for error in ("conservative-net", "conservative", "approximate"):
            vals = {r["model"]: r["triangles"] for r in t3 if r["method"] == method and r["error"] == error}
            series.append((f"{method}, {error}", [vals.get(m) for m in models]))
    bars(os.path.join(out, "table3.png"), "Triangles per subdivision and error estimate", models, series, "triangles")
    bars(os.path.join(out, "table4.png"), "Quadtree [Kah02] vs ours (kd-tree), guaranteed error",
         [r["model"] for r in t4], [("quadtree", [r["quadtree_triangles"] for r in t4]),
                                    ("ours", [r["ours_triangles"] for r in t4])], "triangles")
    models = sorted({r["model"] for r in pr}, key=[r["model"] for r in pr].index)
    bars(os.path.join(out, "presets.png"), "Triangles per preset (guaranteed error)", models,
         [(p, [next((r["triangles"] for r in pr if r["model"] == m and r["preset"] == p), None) for m in models])
          for p in ("default", "paper")], "triangles")
    bars(os.path.join(out, "occt.png"), "Triangles at equal measured deviation", [r["model"] for r in oc],
         [("ours", [r["ours_triangles"] for r in oc]), ("OCCT BRepMesh", [r["occt_triangles"] for r in oc])],
         "triangles")


def summary(a, results, t2, t3, t4, oc, pr):
    eps_of = {r["name"]: j["eps"] for r in results for j in [r["runs"].get("kd_g") or r["runs"].get("kd_g_net")] if j}
    L = [f"Tessellation experiments: eps = {a.eps:g} x model size, check {a.check_samples}^2 samples "
         f"per face, OCCT angular deflection {a.angular:g} rad{', parallel' if a.occt_parallel else ''}; "
         f"{os.cpu_count()} CPU cores (shared: times are indicative)", ""]
    L.append("Table 2 (trim curves; default and arbitrary split: the default's other switches; paper: --paper, "
             "whose loops also run along rectangle-bounded faces' boundaries)")
    L.append(f"  {'model':<28}{'run':<16}{'pieces':>8}{'conv s':>9}{'approx s':>10}{'edges before':>14}"
             f"{'after':>8}{'ratio':>7}")
    for r in t2:
        L.append(f"  {r['model']:<28}{r['run']:<16}{r['curve_pieces']:>8}{r['conversion_s']:>9.3f}"
                 f"{r['approximation_s']:>10.3f}{r['edges_before']:>14}{r['edges_after']:>8}{r['reduction']:>7.2f}")
    L += ["", "Table 3 (subdivision x error estimate)"]
    L.append("  (conservative: the cells' bound with Filip's (default); conservative-net: the paper's control-net "
             "test alone; dev / eps: measured by --check, kd-tree guaranteed only)")
    L.append("  (total s, eval s: vertices evaluated coherently, the paper's column 3; direct: `--evaluation direct`, "
             "the paper's first time column, on its four rows; eval: CPU seconds summed over faces)")
    L.append(f"  {'model':<28}{'method':<10}{'error':<18}{'triangles':>10}{'dev/eps':>8}{'total s':>9}{'direct s':>9}"
             f"{'surface s':>10}{'trim s':>8}{'tri s':>8}{'eval s':>8}{'direct eval s':>14}")
    for r in t3:
        dev = "" if r["max_deviation"] == "" else f"{r['max_deviation'] / eps_of[r['model']]:.2f}"
        L.append(f"  {r['model']:<28}{r['method']:<10}{r['error']:<18}{r['triangles']:>10}{dev:>8}{r['total_s']:>9.3f}"
                 f"{fmt(r['direct_total_s'], '.3f'):>9}{r['surface_s']:>10.3f}{r['trimming_s']:>8.3f}"
                 f"{r['triangulation_s']:>8.3f}{r['evaluation_s']:>8.3f}{fmt(r['direct_evaluation_s'], '.3f'):>14}")
    L += ["", "Table 4 (quadtree [Kah02] vs ours, guaranteed; ratio = quadtree / kd-tree triangles with the same "
          "cell bound: Filip's, then the paper's net; 'paper quad / ours' = the quadtree with the paper's bound "
          "against our default)"]
    L.append(f"  {'model':<28}{'quad s':>9}{'ours s':>9}{'quad tris':>11}{'ours tris':>11}{'ratio':>7}"
             f"{'net ratio':>10}{'paper quad / ours':>19}{'quad edges':>12}{'ours edges':>12}")
    for r in t4:
        L.append(f"  {r['model']:<28}{r['quadtree_s']:>9.3f}{r['ours_s']:>9.3f}{r['quadtree_triangles']:>11}"
                 f"{r['ours_triangles']:>11}{r['triangle_ratio']:>7.2f}{fmt(r['net_triangle_ratio']):>10}"
                 f"{fmt(r['paper_quadtree_over_ours']):>19}{r['quadtree_trim_edges']:>12}{r['ours_trim_edges']:>12}")
    L += ["", "Presets (paper: tessellate --paper; default: no switch; dev / eps measured by --check)"]
    L.append(f"  {'model':<28}{'preset':<9}{'triangles':>10}{'trim edges':>11}{'open edges':>11}{'rect faces':>11}"
             f"{'dev/eps':>8}{'total s':>9}")
    for r in pr:
        dev = "" if r["max_deviation"] == "" else f"{r['max_deviation'] / r['eps']:.2f}"
        L.append(f"  {r['model']:<28}{r['preset']:<9}{r['triangles']:>10}{r['trim_edges']:>11}{r['open_edges']:>11}"
                 f"{r['rectangle_faces']:>11}{dev:>8}{r['total_s']:>9.3f}")
    L += ["", "OpenCASCADE BRepMesh at equal measured deviation"]
    L.append(f"  {'model':<28}{'eps':>10}{'ours dev':>10}{'ours tris':>10}{'ours s':>8}{'deflection':>11}"
             f"{'OCCT dev':>10}{'OCCT tris':>10}{'OCCT s':>8}{'OCCT/ours':>10}")
    for r in oc:
        L.append(f"  {r['model']:<28}{r['eps']:>10.3g}{r['ours_deviation']:>10.3g}{r['ours_triangles']:>10}"
                 f"{r['ours_s']:>8.3f}{r['occt_deflection']:>11.3g}{r['occt_deviation']:>10.3g}"
                 f"{r['occt_triangles']:>10}{r['occt_s']:>8.3f}{r['occt_over_ours_triangles']:>10.2f}"
                 f"{'' if r['occt_matched'] else '  NO MATCH: OCCT never got down to our deviation'}")
    L.append("  OCCT at its nominal setting (deflection = eps): "
             + "; ".join(f"{r['model']} {r['occt_nominal_triangles']} triangles, deviation "
                         f"{r['occt_nominal_deviation']:.3g}, {r['occt_nominal_s']:.3f} s" for r in oc))
    L.append("  (ours dev: `tessellate --check`; the same mesh read back from its PLY by `nurbsgl deviation`, as "
             "OCCT's is: " + ", ".join(f"{r['model']} {fmt(r['ours_file_deviation'])}" for r in oc) + ")")
    for r in oc:
        if r["same_occt_triangles"] != "":
            L.append(f"  same instrument, {r['model']}: ours {r['same_instrument_target']:.3g} through its file; OCCT "
                     f"{r['same_occt_deviation']:.3g} with {r['same_occt_triangles']} triangles "
                     f"({r['same_occt_triangles'] / max(1, r['ours_triangles']):.2f}x ours), {r['same_occt_s']:.3f} s"
                     f"{'' if r['same_matched'] else ', NO MATCH'}")
    L += ["", "Targets (yes / NO / n/a)"]
    L.append(f"  {'model':<28}{'>=2x fewer than quadtree':>25}{'<= OCCT triangles':>28}{'within eps':>12}"
             f"{'bearing < 1 s':>15}")
    t4m, ocm = {r["model"]: r for r in t4}, {r["model"]: r for r in oc}
    for res in results:
        n = res["name"]
        quad = "n/a" if n not in t4m else ("yes" if t4m[n]["triangle_ratio"] >= 2 else "NO") + \
            f" ({t4m[n]['triangle_ratio']:.2f}x; paper's {fmt(t4m[n]['paper_quadtree_over_ours'])}x)"
        occ = "n/a" if n not in ocm else ("yes" if ocm[n]["ours_triangles"] <= ocm[n]["occt_triangles"] else "NO") + \
            f" ({ocm[n]['occt_over_ours_triangles']:.2f}x)"
        if n in ocm and not ocm[n]["occt_matched"]:
            o = ocm[n]
            occ = "n/a (no match)"
            if o["same_matched"]:  # shown, but it decides nothing: near the instrument's floor
                ratio = o["same_occt_triangles"] / max(1, o["ours_triangles"])
                occ = f"n/a (same instr. {ratio:.2f}x)"
        k = res["runs"].get("kd_g")
        eps_ok = "n/a" if not k or "check" not in k else ("yes" if k["check"]["within_eps"] else "NO")
        bearing = ""
        if "bearing" in n and k:
            bearing = ("yes" if k["seconds"]["total"] < 1 else "NO") + f" ({k['seconds']['total']:.2f} s)"
        L.append(f"  {n:<28}{quad:>25}{occ:>28}{eps_ok:>12}{bearing:>15}")
    errs = [(r["name"], e) for r in results for e in r["errors"]]
    if errs:
        L += ["", "Failures"] + [f"  {n}: {e}" for n, e in errs]
    failed = [(r["name"], j["failed_faces"]) for r in results for k, j in r["runs"].items() if j["failed_faces"]]
    if failed:
        L += ["", "Faces that could not be tessellated (runs still counted)"]
        L += [f"  {n}: {f} faces in one of its runs" for n, f in sorted(set(failed))]
    return "\n".join(L) + "\n"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(root, "build-bench"), help="build dir with cli/ and experiments/")
    p.add_argument("--nurbsgl", help="nurbsgl binary (default BUILD/cli/nurbsgl)")
    p.add_argument("--peer", help="peer_occt_mesh binary (default BUILD/experiments/peer_occt_mesh; '' = no OCCT)")
    p.add_argument("--out", help="output dir (default BUILD/experiments/tessellation)")
    p.add_argument("--shared", default=os.path.join(root, "..", "shared"), help="the shared folder (models/ in it)")
    p.add_argument("--eps", type=float, default=1e-3, help="tolerance relative to the model size")
    p.add_argument("--loop-share", type=float, help="tessellate --loop-share (default: the CLI's)")
    p.add_argument("--check-samples", type=int, default=24, help="N x N samples per face of every measurement")
    p.add_argument("--angular", type=float, default=0.5, help="OCCT angular deflection, radians")
    p.add_argument("--occt-serial", dest="occt_parallel", action="store_false",
                   help="mesh OCCT's faces on one thread (default: parallel, as ours uses every core)")
    p.add_argument("--match", type=float, default=0.05, help="OCCT deviation within this fraction of ours")
    p.add_argument("--bisect-steps", type=int, default=10, help="OCCT meshes tried per model at most")
    p.add_argument("--timeout", type=int, default=600, help="seconds per command")
    p.add_argument("--models", nargs="*", help="only models whose file name contains one of these")
    p.add_argument("--command", help="the command line to name in docs/benchmarks.md and REPRODUCTION.md")
    p.add_argument("--no-docs", action="store_true", help="leave docs/benchmarks.md and REPRODUCTION.md alone")
    a = p.parse_args()
    a.nurbsgl = a.nurbsgl or os.path.join(a.build, "cli", "nurbsgl")
    a.peer = os.path.join(a.build, "experiments", "peer_occt_mesh") if a.peer is None else a.peer
    if a.peer and not os.path.exists(a.peer):
        log(f"no OCCT peer at {a.peer}: the OCCT comparison is skipped")
        a.peer = ""
    a.out = a.out or os.path.join(a.build, "experiments", "tessellation")
    os.makedirs(a.out, exist_ok=True)
    models = [os.path.join(a.build, "models", f"{g}.igs") for g in GENERATED]
    shared = os.path.join(a.shared, "models")
    if os.path.isdir(shared):
        models += sorted(glob.glob(os.path.join(shared, "iges", "*.ig*")))
        models += sorted(glob.glob(os.path.join(shared, "generated", "*.igs")))
    if a.models:
        models = [m for m in models if any(s in os.path.basename(m) for s in a.models)]
    r = Runner(a)
    results = []
    for m in models:
        if not os.path.exists(m):
            log(f"missing {m}")
            continue
        results.append(r.model(m))
        write_outputs(a, results, final=m == models[-1])  # after every model: a long run leaves tables behind
    shutil.rmtree(r.tmp, ignore_errors=True)  # the last mesh files
    print(open(os.path.join(a.out, "summary.txt")).read(), end="")
    if not a.no_docs and results:
        publish(a, rows_of(results))
    print(f"\nCSV{'' if plt is None else ', PNG'} and summary.txt in {a.out}")


# Balazs, Guthe and Klein's reported figures, for REPRODUCTION.md.
PAPER_TABLE2_EDGES = (170484, 151234)  # Table 2 (Golf): 3d Bezier, midpoint, eps_line edges, then + simpl.
PAPER_TABLE3_KD_APPROX = (101.3, 464354)  # Table 3 (Golf): kd-tree, eps_approx: time (s), triangles
PAPER_TABLE3_TIMES = {"kd-tree, conservative": (100.1, 96.9), "kd-tree, approx.": (101.3, 97.3),  # Table 3:
                      "quadtree, conservative": (183.6, 175.2), "quadtree, approx.": (191.7, 184.6)}  # direct, coherent
PAPER_TABLE4_TRIANGLES = {"Golf": (2058739, 464354), "vent. con.": (562949, 29113),  # Table 4: quadtree,
                          "Beetle": (3153954, 593652)}  # ours (triangles)


def largest(rows):
    """'T ms, N triangles on MODEL' of the row with the most triangles, or 'not run'."""
    if not rows:
        return "not run"
    r = max(rows, key=lambda r: r["triangles"])
    return f"{1e3 * r['total_s']:.0f} ms, {r['triangles']:,} triangles ({r['model']}, the most of {len(rows)} models)"


def sum_ratio(rows, num, den):
    """'1.23x': the sum of column num over the sum of column den, or 'not run'."""
    d = sum(r[den] for r in rows)
    return f"{sum(r[num] for r in rows) / d:.2f}x" if rows and d > 0 else "not run"


def span(values, unit="", scale=1.0):
    """'lo-hi UNIT over N models' of the numbers in values, or 'not run'."""
    v = [scale * x for x in values if isinstance(x, (int, float))]
    return f"{min(v):.3g}-{max(v):.3g}{unit} over {len(v)} runs" if v else "not run"


def publish(a, tables):
    """docs/benchmarks.md and REPRODUCTION.md sections of this run (Balazs et al. Tables 2, 3, 4)."""
    t2, t3, t4, oc, pr = tables
    command = (a.command or shlex.join(["experiments/tessellation_tables.py", *sys.argv[1:]])).strip()
    kd_approx = [r for r in t3 if r["method"] == "kdtree" and r["error"] == "approximate"]
    both = [r for r in t3 if r["direct_total_s"] != ""]
    info = run_json([a.nurbsgl, "gpu-info", "--json"], a.timeout)
    left_out = ", ".join(w for w, gone in (("the OCCT columns", not a.peer), ("the plots", plt is None)) if gone)
    shown = [(f"`{n}.csv`:", report.markdown_table(rows)) for n, rows in
             (("table2", t2), ("table3", t3), ("table4", t4), ("presets", pr), ("occt", oc)) if rows]
    report.write_benchmarks("Tessellation (Balazs, Guthe and Klein)", command, info, shown, left_out)
    report.write_reproduction("Tessellation (Balazs, Guthe and Klein)", [
        ("Table 2, trim edges before / after simplification",
         f"{PAPER_TABLE2_EDGES[0] / PAPER_TABLE2_EDGES[1]:.2f}x ({PAPER_TABLE2_EDGES[0]:,} / {PAPER_TABLE2_EDGES[1]:,}"
         ", Golf, Table 2)",
         span([r["reduction"] for r in t2], "x")),
        ("Table 3, tessellation time (kd-tree, approximate error)",
         f"{PAPER_TABLE3_KD_APPROX[0]} s, {PAPER_TABLE3_KD_APPROX[1]:,} triangles (Golf, Table 3)",
         largest(kd_approx)),
        ("Table 3, time with direct / with coherent evaluation (the column marked 3)",
         ", ".join(f"{k} {d / c:.3f}x" for k, (d, c) in PAPER_TABLE3_TIMES.items()) + " (Golf, Table 3)",
         sum_ratio(both, "direct_total_s", "total_s") + "; the evaluation stage alone "
         + sum_ratio(both, "direct_evaluation_s", "evaluation_s") + f" (sums over {len(both)} runs)"),
        ("Table 4, quadtree triangles / ours",
         ", ".join(f"{m} {q / k:.1f}x" for m, (q, k) in PAPER_TABLE4_TRIANGLES.items()) + " (Table 4)",
         span([r["triangle_ratio"] for r in t4], "x"))], command)
    matched = [r for r in oc if r["occt_matched"]]
    if matched:  # the README's headline: the model of most faces where OCCT reached our deviation
        r = max(matched, key=lambda r: r["faces"])
        report.write_headline("tessellation (guaranteed error)", f"{r['model']} ({r['faces']})",
                              f"{r['ours_triangles']:,} triangles, measured deviation {r['ours_deviation']:.3g} "
                              f"(eps {r['eps']:.3g}), {r['ours_s']:.2f} s",
                              f"{r['occt_triangles']:,} triangles at deviation {r['occt_deviation']:.3g} "
                              f"(BRepMesh), {r['occt_s']:.2f} s",
                              f"{r['occt_over_ours_triangles']:.2f}x fewer triangles, {r['ours_s'] / r['occt_s']:.1f}x "
                              "OpenCASCADE's time" if r["occt_s"] > 0 else "", command)


def write_outputs(a, results, final):
    t2, t3, t4, oc, pr = rows_of(results)
    for name, rows in (("table2", t2), ("table3", t3), ("table4", t4), ("presets", pr), ("occt", oc)):
        write_csv(os.path.join(a.out, f"{name}.csv"), rows)
    tries = [dict(model=res["name"], **t) for res in results for t in res.get("occt_tries", [])]
    write_csv(os.path.join(a.out, "occt_bisection.csv"), tries)
    plots(a.out, t2, t3, t4, oc, pr)
    text = summary(a, results, t2, t3, t4, oc, pr)
    with open(os.path.join(a.out, "summary.txt"), "w") as f:
        f.write(text if final else text + "\n(partial: the run is still going)\n")


if __name__ == "__main__":
    main()
