#!/usr/bin/env python3
"""Signed distances against OpenCASCADE's solid classifier, on every STEP and IGES file of folders.

For each file (.stp, .step, .igs, .iges; recursively, in name order):
- `nurbsgl tessellate MODEL --eps 1e-3 --relative --watertight -o mesh.obj`; N points (fixed seed per
  file name) at random places of random triangles (area-weighted), each moved off the mesh along the
  triangle's normal by +-OFFSET x model size (--offset, default 1e-4: 0.03 mm on a 300 mm part),
  half to each side;
- `nurbsgl distance MODEL --points F --signed --tol T --json --csv C`: a file whose bodies the
  command refuses as not closed is skipped (its reason in the table);
- `peer_occt_distance sides` (BUILD/experiments, built with -DNURBSGL_PEER_BENCH=ON): per point
  BRepClass3d_SolidClassifier in every solid of OCCT's reading, inside any solid being inside (the
  part is the union of its solids); OCCT reads in millimetres, so the points go to it scaled by the
  file's unit.
Per file: solids (ours, OCCT's), answers certified (meets_tolerance, no reason) with |signed| over
their bound (a side was stated), WRONG (those whose side is not OCCT's, points OCCT puts on a face
left out), unsure or uncertified answers, and among them those that name another solid (hidden).
A survey, not a test: nothing here fails. Prints a table and the totals; --out writes sides.csv.

Usage: experiments/signed_sides.py FOLDER... [--build BUILD] [--points N] [--offset R] [--tol T]
       [--timeout S] [--out DIR]
"""
import argparse
import csv
import json
import os
import random
import sys
import tempfile
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import corpus  # noqa: E402  (run_child, parse_json, error_text, read_obj_triangles, EXTENSIONS)

COLUMNS = ["file", "faces", "solids", "occ_solids", "points", "stated", "wrong", "uncertified", "hidden", "occ_on",
           "seconds", "status"]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def near_points(triangles, n, offset, seed):
    """n points off random places of the triangles (area-weighted), alternately outward and inward."""
    rng = random.Random(seed)
    frames, weights = [], []
    for a, b, c in triangles:
        e1 = [b[k] - a[k] for k in range(3)]
        e2 = [c[k] - a[k] for k in range(3)]
        nrm = cross(e1, e2)
        area = sum(x * x for x in nrm) ** 0.5
        if area > 0:
            frames.append((a, e1, e2, [x / area for x in nrm]))
            weights.append(area)
    points = []
    for k, (a, e1, e2, nrm) in enumerate(rng.choices(frames, weights=weights, k=n)):
        s, t = rng.random(), rng.random()
        if s + t > 1:
            s, t = 1 - s, 1 - t
        side = offset if k % 2 == 0 else -offset
        points.append([a[i] + s * e1[i] + t * e2[i] + side * nrm[i] for i in range(3)])
    return points


def survey(path, rel, a, cli, peer, tmp):
    row = {"file": rel}
    base = os.path.join(tmp, str(zlib.crc32(rel.encode())))
    mesh, pts, out_csv = base + ".obj", base + ".xyz", base + ".csv"
    status, code, out, err, _ = corpus.run_child(
        [cli, "tessellate", path, "--eps", "1e-3", "--relative", "--watertight", "-o", mesh, "--json"], a.timeout,
        int(a.memory * 2**30))
    j = corpus.parse_json(out)
    if status != "ok" or not os.path.exists(mesh):
        row["status"] = f"tessellate: {status} {code}: {corpus.error_text(j, err, code)}"[:160]
        return row
    triangles = corpus.read_obj_triangles(mesh)
    status, code, out, err, _ = corpus.run_child([cli, "info", path, "--json"], a.timeout, int(a.memory * 2**30))
    info = corpus.parse_json(out)
    size, unit = info.get("size", 0.0), info.get("unit_scale_to_mm", 1.0)
    row["faces"], row["solids"] = info.get("faces"), info.get("bodies")
    points = near_points(triangles, a.points, a.offset * size, zlib.crc32(rel.encode()))
    with open(pts, "w") as f:
        f.writelines(" ".join(f"{x:.12g}" for x in p) + "\n" for p in points)
    status, code, out, err, wall = corpus.run_child(
        [cli, "distance", path, "--points", pts, "--signed", "--tol", str(a.tol), "--json", "--csv", out_csv],
        a.timeout, int(a.memory * 2**30))
    if status != "ok" or code not in (0, 1):
        row["status"] = f"distance: {status} {code}: {corpus.error_text(corpus.parse_json(out), err, code)}"[:160]
        return row
    row["seconds"] = round(wall, 2)
    with open(out_csv, newline="") as f:
        ours = list(csv.DictReader(f))
    with open(pts + ".mm", "w") as f:
        f.writelines(" ".join(f"{x * unit:.12g}" for x in p) + "\n" for p in points)
    status, code, out, err, _ = corpus.run_child([peer, "sides", path, "--points", pts + ".mm"], a.timeout * 5,
                                                 int(a.memory * 2**30))
    occ = corpus.parse_json(out)
    if status != "ok" or code != 0 or len(occ.get("results", [])) != len(ours):
        row["status"] = f"occt: {status} {code}: {corpus.error_text(occ, err, code)}"[:160]
        return row
    row["occ_solids"], row["points"] = occ["solids"], len(ours)
    stated = wrong = uncertified = hidden = on = 0
    for r, o in zip(ours, occ["results"]):
        if r.get("reason"):
            uncertified += 1
            hidden += "lies inside or on body" in r["reason"]
            continue
        if r["found"] != "true" or r["meets_tolerance"] != "true":
            continue
        s, b = float(r["signed_distance"]), float(r["bound"])
        if abs(s) <= b:
            continue
        if o == "on":
            on += 1
            continue
        stated += 1
        wrong += (s < 0) != (o == "in")
    row.update(stated=stated, wrong=wrong, uncertified=uncertified, hidden=hidden, occ_on=on, status="ok")
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--build", default="build")
    ap.add_argument("--points", type=int, default=400)
    ap.add_argument("--offset", type=float, default=1e-4, help="points' distance off the mesh, relative to the size")
    ap.add_argument("--tol", type=float, default=1e-5)
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--memory", type=float, default=8, help="GB of address space per child run")
    ap.add_argument("--out", help="write sides.csv here")
    a = ap.parse_args()
    cli = os.path.join(a.build, "cli", "nurbsgl")
    peer = os.path.join(a.build, "experiments", "peer_occt_distance")
    for tool in (cli, peer):
        if not os.path.exists(tool):
            sys.exit(f"no {tool} (the peer needs -DNURBSGL_PEER_BENCH=ON)")
    files = []
    for folder in a.folders:
        folder = os.path.abspath(folder)
        files += sorted((os.path.join(dp, f), os.path.relpath(os.path.join(dp, f), os.path.dirname(folder)))
                        for dp, _, fs in os.walk(folder) for f in fs if f.lower().endswith(corpus.EXTENSIONS))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, (path, rel) in enumerate(files):
            try:
                row = survey(path, rel, a, cli, peer, tmp)
            except Exception as e:  # the survey goes on
                row = {"file": rel, "status": f"script error {e!r}"}
            rows.append(row)
            print(f"[{k + 1}/{len(files)}] " + "  ".join(f"{c}={row.get(c, '')}" for c in COLUMNS), file=sys.stderr,
                  flush=True)
    print("\t".join(COLUMNS))
    for row in rows:
        print("\t".join(str(row.get(c, "")) for c in COLUMNS))
    done = [r for r in rows if r.get("status") == "ok"]
    total = {c: sum(r.get(c, 0) for r in done) for c in ("points", "stated", "wrong", "uncertified", "hidden", "occ_on")}
    print(f"\n{len(done)} of {len(rows)} files compared: {json.dumps(total)}")
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        with open(os.path.join(a.out, "sides.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
