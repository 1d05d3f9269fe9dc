#!/usr/bin/env python3
"""Every STEP and IGES file of a folder through the built CLI: what it reads, distance, tessellation.

For each file under FOLDER (.stp, .step, .igs, .iges, any case; recursively), in name order:
- read: `nurbsgl info --json`: faces, bodies, the wall time, the faces the file holds (faces_in_file),
  the faces the reader dropped counted by reason, the trim problems and the read warnings (the
  top-level fields, or the older "reader": {"trim_problems", "faces_dropped"} block), the exit code
  and the error text of a file it rejects;
- distance, on a file read with at least one face: N random points (fixed seed per file name) in the
  model's box grown by 10% (5% of its extent on each side), `nurbsgl distance MODEL --points F
  --tol T --json` (T: --tol, default 1e-4): exit code, not_found, over_tolerance, limited_by_file,
  uncertified, wall time;
- with OpenCASCADE's peer (BUILD/experiments/peer_occt_distance, built with -DNURBSGL_PEER_BENCH=ON;
  `points --trimmed`: BRepExtrema_DistShapeShape from each point to the trimmed faces as OCCT reads
  them): OCCT's face count, the largest |ours - occ| over our bound, and WRONG, the answers found (but
  those marked uncertified) off OCCT's distance by more than bound + 1e-9 x model size (a certified
  wrong answer, the worst failure), unless OCCT's own mesh of the faces (BRepMesh, deflection 2e-5 of
  the size) agrees with ours within the bound and twice the deflection: then OCCT's exact routine
  misclassified the faces, counted in occ_disputed; OCCT reads in millimetres, so the points go to
  it scaled by the file's unit; a file the peer cannot read leaves its error in occ_error;
- tessellation: `nurbsgl tessellate MODEL --eps 1e-3 --relative --watertight --check --json`: exit
  code, open edges, failed faces, faces over eps in the check, wall time.
Each child runs under a wall-clock limit (--timeout) and an address-space cap (--memory, RLIMIT_AS);
a child past them is recorded as "timeout" or "oom". The writing system of a file is its STEP
FILE_NAME originating_system and preprocessor_version, or its IGES global section's native system id
and preprocessor version (the column writer names the CAD system where the string does; a folder's
INDEX.tsv with columns path and writer is used where present). Prints a table, the read and failure
summary and the distinct failure messages (numbers masked) with an example file each; with --out,
writes corpus.csv, corpus.json and failures.csv there, rewritten after every file so a long run can
be read while it goes. A survey, not a test: nothing here fails.

Usage: experiments/corpus.py FOLDER [--build BUILD] [--out OUT] [--points N] [--tol T] [--timeout S]
       [--memory GB] [--jobs N] [--peer PEER]
"""
import argparse
import collections
import concurrent.futures
import csv
import json
import os
import random
import re
import resource
import signal
import subprocess
import sys
import tempfile
import threading
import time
import zlib

EXTENSIONS = (".stp", ".step", ".igs", ".iges")
# OCCT's mesh, the second opinion on a distance its exact routine and ours disagree on: deflection
# as a share of the model size.
MESH_DEFLECTION = 2e-5
# Points of each guaranteed mesh measured against OCCT's faces.
MESH_SAMPLES = 200
# Substrings of a writer's system string (lower case) and the CAD system they name, first match wins.
SYSTEMS = [("solidworks", "SolidWorks"), ("swstep", "SolidWorks"), ("catia", "CATIA"), ("3dexperience", "CATIA"),
           ("unigraphics", "NX"), ("siemens plm software nx", "NX"), ("siemens nx", "NX"),
           ("pro/engineer", "Creo"), ("creo", "Creo"), ("cocreate", "CoCreate"), ("inventor", "Inventor"),
           ("autodesk translation framework", "Autodesk ATF (Fusion 360/Inventor)"), ("fusion", "Fusion 360"),
           ("rhino", "Rhino"), ("onshape", "Onshape"), ("solid edge", "Solid Edge"), ("kicad stepup", "KiCad StepUp"),
           ("kicad", "KiCad"), ("freecad", "FreeCAD"), ("cadquery", "CadQuery"), ("open cascade", "OpenCASCADE"),
           ("analysis situs", "OpenCASCADE"), ("euclid", "Euclid"), ("theorem", "Theorem"), ("spatial", "ACIS"),
           ("acis", "ACIS"), ("hoops", "HOOPS"), ("cadfix", "CADfix"), ("parasolid", "Parasolid"),
           ("gmsh", "Gmsh"), ("spaceclaim", "SpaceClaim"), ("zw3d", "ZW3D"), ("ironcad", "IronCAD")]
COLUMNS = ["file", "writer", "size_kb", "status", "faces", "bodies", "info_s", "faces_in_file", "dropped",
           "trim_problems", "read_warnings", "dist_exit", "not_found", "over_tol", "limited_by_file", "uncertified", "dist_s",
           "occ_faces", "occ_worst_per_bound", "wrong", "occ_disputed", "tess_exit", "open_edges", "failed_faces", "over_eps",
           "tess_s", "occ_mesh_dev", "tess_bound", "tess_wrong"]


def system_string(path):
    """The writing system a file names in its header: 'originating_system | preprocessor_version' of a
    STEP FILE_NAME, or 'native system id | preprocessor version' of an IGES global section; '' when none."""
    with open(path, "rb") as f:
        head = f.read(65536).decode("latin-1")
    if "ISO-10303-21" in head[:4096]:
        head = re.sub(r"/\*.*?\*/", "", head, flags=re.S)
        m = re.search(r"FILE_NAME\s*\((.*?)\)\s*;", head, re.S)
        # FILE_NAME(name, time_stamp, (author), (organization), preprocessor_version, originating_system, ...)
        args = re.findall(r"\((?:[^()']|'(?:[^']|'')*')*\)|'(?:[^']|'')*'", m.group(1)) if m else []
        text = [" ".join(re.findall(r"'((?:[^']|'')*)'", a)).strip() for a in args]
        return " | ".join(t for t in (text[5:6] + text[4:5]) if t)
    # IGES global section: columns 1-72 of the lines marked G; parameters 5 and 6 are Hollerith strings.
    g = "".join(line[:72] for line in head.splitlines() if len(line) >= 73 and line[72] == "G")
    if not g:
        return ""
    params, i = [], 0
    while i < len(g) and len(params) < 7:
        m = re.match(r"\s*(\d+)H", g[i:])
        if m:
            start = i + m.end()
            params.append(g[start:start + int(m.group(1))])
            i = start + int(m.group(1))
        else:
            j = i
            while j < len(g) and g[j] not in ",;":
                j += 1
            params.append(g[i:j].strip())
            i = j
        i += 1  # the delimiter (IGES files here use the default ',' and ';')
    return " | ".join(p.strip() for p in params[4:6] if p.strip())


def writer_name(system):
    text = system.lower()
    return next((name for key, name in SYSTEMS if key in text), "unknown")


def index_writers(folder):
    """path (relative to folder) -> writer from folder/INDEX.tsv, when it has such columns."""
    path = os.path.join(folder, "INDEX.tsv")
    if not os.path.exists(path):
        return {}
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    return {r["path"]: r["writer"] for r in rows if r.get("path") and r.get("writer")}


def run_child(cmd, timeout, memory_bytes):
    """Runs cmd in its own process group under RLIMIT_AS = memory_bytes; kills the group after timeout
    seconds. Returns (status, exit code or None, stdout, stderr, wall seconds); status is 'ok', 'timeout',
    'oom' (killed or failing for memory) or 'signal N'."""
    def limit():
        os.setsid()  # its own process group, killed whole on a timeout
        resource.setrlimit(resource.RLIMIT_AS, (memory_bytes, memory_bytes))
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace",
                         preexec_fn=limit)
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        return "timeout", None, out, err, time.monotonic() - t0
    wall = time.monotonic() - t0
    memory = re.search(r"out of memory|bad_alloc|cannot allocate|std::length_error", err, re.I)
    if p.returncode < 0:
        # Under RLIMIT_AS a failed allocation that nobody catches ends in SIGABRT or SIGSEGV.
        status = "oom" if memory or -p.returncode in (signal.SIGKILL, signal.SIGABRT) else f"signal {-p.returncode}"
        return status, p.returncode, out, err, wall
    return ("oom" if memory else "ok"), p.returncode, out, err, wall


def parse_json(text):
    """The first JSON object of text, or {} (a child killed mid-way prints a part)."""
    start = text.find("{")
    if start < 0:
        return {}
    try:
        return json.JSONDecoder().raw_decode(text[start:])[0]
    except ValueError:
        return {}


def error_text(j, err, code):
    """The error a failed child gives: its JSON "error", else the last non-empty stderr line, else its
    exit code."""
    if j.get("error"):
        return str(j["error"])
    lines = [line for line in err.splitlines() if line.strip()]
    return lines[-1] if lines else f"exit {code}, no message"


def mask(message, path):
    """message with the file's path and numbers masked, so that files failing alike count as one."""
    message = message.replace(path, "FILE").replace(os.path.basename(path), "FILE")
    message = re.sub(r"\b([#D])\d+\b", r"\1N", message)  # STEP instances #12, IGES directory entries D12
    return re.sub(r"(?<![A-Za-z_\d.])[-+]?\d+(\.\d+)?([eE][-+]?\d+)?", "N", message)[:300]


def read_fields(j):
    """faces_in_file, dropped reasons, trim problems and read warnings from `info --json`, newer
    top-level fields first, else the "reader" block."""
    reader = j.get("reader", {})
    dropped = j.get("faces_dropped")
    if dropped is None:
        dropped = reader.get("faces_dropped", [])
    reasons = [d.get("reason", "") if isinstance(d, dict) else str(d) for d in dropped]
    trims = reader.get("trim_problems")
    if trims is None:
        trims = j.get("invalid_trims", [])
    return j.get("faces_in_file"), reasons, trims, j.get("read_warnings", [])


def write_points(info, n, seed, path):
    """n points in the box of `info --json` grown by 5% of its extent on each side (a flat side by 5% of
    the diagonal), seeded; returns the model size (box diagonal)."""
    lo, hi = info["bbox"]["min"], info["bbox"]["max"]
    ext = [hi[k] - lo[k] for k in range(3)]
    size = sum(e * e for e in ext) ** 0.5
    grow = [0.05 * max(e, 0.05 * size) for e in ext]
    rng = random.Random(seed)
    with open(path, "w") as f:
        for _ in range(n):
            point = (lo[k] - grow[k] + rng.random() * (ext[k] + 2 * grow[k]) for k in range(3))
            f.write(" ".join(f"{x:.12g}" for x in point) + "\n")
    return info.get("size", size)


def survey(path, rel, writer, a, cli, peer, tmp):
    """One file's row and its failure messages [(step, message)]."""
    row = {"file": rel, "writer": writer, "size_kb": round(os.path.getsize(path) / 1024)}
    failures = []
    limit = int(a.memory * 2 ** 30)
    status, code, out, err, wall = run_child([cli, "info", path, "--json"], a.timeout, limit)
    j = parse_json(out)
    row["info_exit"], row["info_s"] = code, round(wall, 3)
    if status != "ok" or code != 0:
        row["status"] = status if status != "ok" else "rejected"
        row["error"] = error_text(j, err, code) if status == "ok" else status
        failures.append(("info", mask(row["error"], path)))
        return row, failures
    in_file, reasons, trims, warnings = read_fields(j)
    row.update({"faces": j.get("faces"), "bodies": j.get("bodies"),
                "read_s": round(j.get("reader", {}).get("seconds", 0), 3), "faces_in_file": in_file,
                "dropped": len(reasons), "trim_problems": len(trims),
                "read_warnings": len(warnings)})
    row["dropped_reasons"] = dict(collections.Counter(mask(r, path) for r in reasons))
    row["status"] = "read_dropped" if reasons else "read"
    failures += [("dropped", m) for m in row["dropped_reasons"]]
    failures += [("trim", mask(str(t), path)) for t in trims[:3]]
    failures += [("warning", mask(str(w), path)) for w in warnings[:3]]
    if not j.get("faces"):
        return row, failures

    points = os.path.join(tmp, f"{zlib.crc32(rel.encode())}.points.txt")
    size = write_points(j, a.points, zlib.crc32(rel.encode()), points)
    status, code, out, err, wall = run_child([cli, "distance", path, "--points", points, "--tol", repr(a.tol),
                                              "--json"], a.timeout, limit)
    d = parse_json(out)
    row["dist_exit"] = code if status == "ok" else status
    row["dist_s"] = round(wall, 2)
    if status == "ok" and d.get("results") is not None:
        row.update({"not_found": d.get("not_found"), "over_tol": d.get("over_tolerance"),
                    "limited_by_file": d.get("limited_by_file"), "uncertified": d.get("uncertified")})
    if status != "ok" or code != 0:
        row["dist_error"] = error_text(d, err, code) if status == "ok" else status
        failures.append(("distance", mask(row["dist_error"], path)))
    if peer and d.get("results"):
        unit = j.get("unit_scale_to_mm") or 1.0
        compare_with_occt(row, d["results"], peer, path, points, size, unit, a, limit, failures)

    mesh = os.path.join(tmp, f"{zlib.crc32(rel.encode())}.mesh.obj")
    status, code, out, err, wall = run_child([cli, "tessellate", path, "--eps", "1e-3", "--relative", "--watertight",
                                              "--check", "--json", "-o", mesh], a.timeout, limit)
    t = parse_json(out)
    if peer and status == "ok" and code == 0 and os.path.exists(mesh):
        unit = j.get("unit_scale_to_mm") or 1.0
        check_mesh_with_occt(row, t, mesh, peer, path, size, unit, a, limit, failures)
    row["tess_exit"] = code if status == "ok" else status
    row["tess_s"] = round(wall, 2)
    if "open_edges" in t:
        row.update({"open_edges": t["open_edges"], "failed_faces": t.get("failed_faces"),
                    "over_eps": len(t.get("trim_check", {}).get("faces_over_eps", [])) +
                                len(t.get("surface_check", {}).get("faces_over_eps", [])),
                    "max_deviation": t.get("check", {}).get("max_deviation")})
    if status != "ok" or code != 0:
        row["tess_error"] = error_text(t, err, code) if status == "ok" else status
        failures.append(("tessellate", mask(row["tess_error"], path)))
    for f in t.get("failures", [])[:3]:
        failures.append(("tessellate face", mask(str(f.get("reason", "")), path)))
    return row, failures


def occt_trimmed(peer, path, xyz, points, size, unit, a, limit):
    """OCCT's exact distances from the points `xyz` (the file's unit) to the trimmed faces, and to
    its own mesh of them (deflection MESH_DEFLECTION x size): ({faces, distances, mesh, tolerance,
    deflection}, None), all in the file's unit, or (None, the error). OCCT's readers convert to
    millimetres, ours keep the file's unit (`unit` mm each): the peer gets the points scaled by it
    (written to the file `points`) and its figures come back divided by it."""
    with open(points, "w") as f:
        for x in xyz:
            f.write(" ".join(repr(v * unit) for v in x) + "\n")
    status, code, out, err, wall = run_child([peer, "points", path, "--points", points, "--repeat", "0", "--trimmed",
                                              str(len(xyz)), "--mesh-deflection", repr(MESH_DEFLECTION * size * unit)],
                                             a.timeout, limit)
    o = parse_json(out)
    if status != "ok" or code != 0 or "trimmed" not in o:
        return None, (error_text(o, err, code) if status == "ok" else status)[:200]
    back = lambda values: [None if v is None else v / unit for v in values]
    return {"faces": o.get("faces"), "distances": back(o["trimmed"]["distances"]),
            "mesh": back(o["trimmed"].get("mesh", {}).get("distances", [])),
            "tolerance": o["trimmed"].get("tolerance", 0.0) / unit, "deflection": MESH_DEFLECTION * size}, None


def compare_with_occt(row, ours, peer, path, points, size, unit, a, limit, failures):
    """OCCT's face count and exact distances to the trimmed faces of the same points; WRONG counts our
    found answers (but those marked uncertified) off OCCT's by more than our bound plus 1e-9 x size."""
    with open(points) as f:
        xyz = [tuple(float(v) for v in line.split()) for line in f if line.strip()]
    o, error = occt_trimmed(peer, path, xyz, points + ".mm.txt", size, unit, a, limit)
    if error:
        row["occ_error"] = error
        return
    row["occ_faces"] = o["faces"]
    mesh = o["mesh"] + [None] * (len(ours) - len(o["mesh"]))
    deflection = o["deflection"]
    worst, wrong, disputed, beyond_occ_tol = 0.0, 0, 0, 0
    for r, ref, m in zip(ours, o["distances"], mesh):
        if ref is None or not r.get("found") or r.get("distance") is None:
            continue
        diff = abs(r["distance"] - ref)
        worst = max(worst, diff / max(r["bound"], 1e-300))
        # Every answer found claims its bound, within the tolerance or not; an uncertified one claims none.
        if not r.get("uncertified") and diff > r["bound"] + 1e-9 * size:
            # OCCT's mesh of the same faces agrees with ours where its exact distance does not: the
            # exact distance's face classification erred (seen on tori whose loops run along a
            # seam edge that is not the surface's), a disputed answer, not a wrong one.
            if m is not None and abs(r["distance"] - m) <= r["bound"] + 2 * deflection:
                disputed += 1
                continue
            wrong += 1
            beyond_occ_tol += diff > r["bound"] + o["tolerance"]
    row.update({"occ_worst_per_bound": round(worst, 3), "wrong": wrong, "wrong_beyond_occ_tolerance": beyond_occ_tol,
                "occ_disputed": disputed, "occ_tolerance": o["tolerance"]})
    if wrong:
        failures.append(("WRONG", f"{wrong} certified distances off OCCT's by more than the bound"))


def read_obj_triangles(path):
    """The triangles of an OBJ file as [(a, b, c)] of (x, y, z)."""
    vertices, triangles = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append(tuple(float(x) for x in line.split()[1:4]))
            elif line.startswith("f "):
                k = [int(x.split("/")[0]) - 1 for x in line.split()[1:4]]
                triangles.append(tuple(vertices[i] for i in k))
    return triangles


def check_mesh_with_occt(row, t, mesh, peer, path, size, unit, a, limit, failures):
    """The mesh against OCCT's faces: at MESH_SAMPLES points of the mesh where it strays most from
    the faces (triangle centroids and edge midpoints of random triangles, seeded), OCCT's exact
    distance to the trimmed faces, with OCCT's own mesh as a second opinion as for the distances.
    occ_mesh_dev is the largest (in the file's unit); TESS_WRONG counts the samples farther than
    the tessellation's bound (eps plus the edge gaps, as its JSON says) from both."""
    triangles = read_obj_triangles(mesh)
    if not triangles:
        return
    rng = random.Random(zlib.crc32(path.encode()))
    samples = []
    for _ in range(MESH_SAMPLES):
        p, q, r = triangles[rng.randrange(len(triangles))]
        pick = rng.randrange(4)
        w = [(1 / 3, 1 / 3, 1 / 3), (0.5, 0.5, 0), (0, 0.5, 0.5), (0.5, 0, 0.5)][pick]
        samples.append(tuple(w[0] * p[k] + w[1] * q[k] + w[2] * r[k] for k in range(3)))
    o, error = occt_trimmed(peer, path, samples, mesh + ".samples.txt", size, unit, a, limit)
    if error:
        row["occ_mesh_error"] = error
        return
    second = o["mesh"] + [None] * (len(o["distances"]) - len(o["mesh"]))
    bound = t.get("bound", t.get("eps", 0.0))
    worst, wrong = 0.0, 0
    for d, m in zip(o["distances"], second):
        if d is None:
            continue
        # OCCT's mesh lies within its deflection of the faces: the farther point is nearer than that.
        dev = d if m is None else min(d, m + o["deflection"])
        worst = max(worst, dev)
        wrong += dev > bound * (1 + 1e-9) + 1e-9 * size
    row.update({"occ_mesh_dev": worst, "tess_bound": bound, "tess_wrong": wrong})
    if wrong:
        failures.append(("TESS_WRONG", f"{wrong} mesh points farther from OCCT's faces than the mesh's bound"))


def cell(v):
    if isinstance(v, float):
        return f"{v:.3g}"
    return "" if v is None else str(v)


def print_table(rows, file=sys.stdout):
    widths = {c: max(len(c), *(len(cell(r.get(c))) for r in rows)) if rows else len(c) for c in COLUMNS}
    widths["file"] = min(widths["file"], 60)
    print("  ".join(c.ljust(widths[c]) for c in COLUMNS), file=file)
    for r in rows:
        print("  ".join(cell(r.get(c))[-widths[c]:].ljust(widths[c]) for c in COLUMNS), file=file)


def summary(rows, failures):
    """Counts of the run and the distinct failure messages, most frequent first: [(step, message, count,
    example file)]."""
    s = collections.Counter(r["status"] for r in rows)
    named = ("read", "read_dropped", "rejected", "timeout", "oom")
    lines = [f"files {len(rows)}: read fully {s['read']}, read with dropped faces {s['read_dropped']}, "
             f"rejected {s['rejected']}, timeout {s['timeout']}, oom {s['oom']}"
             + "".join(f", {k} {v}" for k, v in s.items() if k not in named)]
    for step, key in (("distance", "dist_exit"), ("tessellate", "tess_exit")):
        c = collections.Counter(str(r[key]) for r in rows if key in r)
        lines.append(f"{step} runs {sum(c.values())}: " + ", ".join(f"exit {k} {v}" for k, v in sorted(c.items())))
    compared = [r for r in rows if "occ_faces" in r]
    if compared:
        meshed = [r for r in rows if "tess_wrong" in r]
        lines.append(f"meshes measured against OpenCASCADE's faces on {len(meshed)} files ({MESH_SAMPLES} points "
                     f"each): TESS_WRONG points {sum(r['tess_wrong'] for r in meshed)} in "
                     f"{sum(1 for r in meshed if r['tess_wrong'])} files")
        lines.append(f"OpenCASCADE compared on {len(compared)} files: WRONG answers "
                     f"{sum(r['wrong'] for r in compared)} in {sum(1 for r in compared if r['wrong'])} files; "
                     f"disputed (OCCT's exact distance off, its mesh with ours) "
                     f"{sum(r.get('occ_disputed', 0) for r in compared)} in "
                     f"{sum(1 for r in compared if r.get('occ_disputed'))} files")
    by_writer = collections.defaultdict(collections.Counter)
    for r in rows:
        by_writer[r["writer"]][r["status"]] += 1
    lines.append("by writer: " + "; ".join(f"{w} {sum(c.values())} ({', '.join(f'{k} {v}' for k, v in c.items())})"
                                           for w, c in sorted(by_writer.items(), key=lambda x: -sum(x[1].values()))))
    count, example = collections.Counter(), {}
    for file, step, message in failures:
        count[(step, message)] += 1
        example.setdefault((step, message), file)
    top = [(step, message, n, example[(step, message)]) for (step, message), n in count.most_common()]
    return lines, top


def write_outputs(out, rows, top):
    os.makedirs(out, exist_ok=True)
    keys = list(dict.fromkeys(COLUMNS + [k for r in rows for k in r]))
    with open(os.path.join(out, "corpus.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows({k: json.dumps(v) if isinstance(v, (dict, list)) else v for k, v in r.items()} for r in rows)
    with open(os.path.join(out, "corpus.json"), "w") as f:
        json.dump(rows, f, indent=1)
    with open(os.path.join(out, "failures.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["step", "message", "files", "example"])
        w.writerows(top)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folder")
    ap.add_argument("--build", default="build")
    ap.add_argument("--out", help="write corpus.csv, corpus.json and failures.csv here")
    ap.add_argument("--points", type=int, default=50, help="random points per file for distance")
    ap.add_argument("--tol", type=float, default=1e-4, help="distance's --tol")
    ap.add_argument("--timeout", type=float, default=120, help="seconds per child run")
    ap.add_argument("--memory", type=float, default=6, help="GB of address space per child run (RLIMIT_AS)")
    ap.add_argument("--jobs", type=int, default=1, help="files surveyed at once")
    ap.add_argument("--peer", help="peer_occt_distance (default: BUILD/experiments/peer_occt_distance if built)")
    a = ap.parse_args()
    cli = os.path.join(a.build, "cli", "nurbsgl")
    if not os.path.exists(cli):
        sys.exit(f"no CLI at {cli} (--build names the build folder)")
    peer = a.peer or os.path.join(a.build, "experiments", "peer_occt_distance")
    if not os.path.exists(peer):
        print(f"note: no OpenCASCADE peer at {peer}: no OCCT columns (build it with -DNURBSGL_PEER_BENCH=ON)",
              file=sys.stderr)
        peer = None
    folder = os.path.abspath(a.folder)
    files = sorted(os.path.join(dp, f) for dp, _, fs in os.walk(folder) for f in fs if f.lower().endswith(EXTENSIONS))
    if not files:
        sys.exit(f"no .stp/.step/.igs/.iges file under {folder}")
    known = index_writers(folder)
    rows, failures, lock = {}, [], threading.Lock()
    with tempfile.TemporaryDirectory() as tmp:
        def one(path):
            rel = os.path.relpath(path, folder)
            writer = known.get(rel) or writer_name(system_string(path))
            try:
                row, fails = survey(path, rel, writer, a, cli, peer, tmp)
            except Exception as e:  # the survey goes on: a file the script cannot handle is a row too
                row, fails = {"file": rel, "writer": writer, "status": "script error", "error": repr(e)}, []
            with lock:
                rows[path] = row
                failures.extend((path, step, message) for step, message in fails)
                print(f"[{len(rows)}/{len(files)}] " +
                      "  ".join(f"{c}={cell(row.get(c))}" for c in COLUMNS if c in row) +
                      "".join(f"  {k}: {row[k]}" for k in ("error", "dist_error", "tess_error") if k in row),
                      file=sys.stderr, flush=True)
                if a.out:
                    ordered = [rows[p] for p in files if p in rows]
                    write_outputs(a.out, ordered, summary(ordered, failures)[1])
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            list(pool.map(one, files))
    ordered = [rows[p] for p in files]
    lines, top = summary(ordered, failures)
    print_table(ordered)
    print()
    print("\n".join(lines))
    print("\nfailure messages (step, files, message, example):")
    for step, message, n, example in top:
        print(f"  {step:16} {n:4}  {message}\n  {'':16} {'':4}  e.g. {example}")
    if a.out:
        write_outputs(a.out, ordered, top)
    return 0


if __name__ == "__main__":
    sys.exit(main())
