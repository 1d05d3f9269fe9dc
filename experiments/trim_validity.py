#!/usr/bin/env python3
"""Which trims nurbsgl reads as invalid where OpenCASCADE's BRepCheck_Analyzer holds the face valid.

For each STEP or IGES file under FOLDER (recursively, name order): `nurbsgl info --json` (its
invalid_trims) beside BUILD/experiments/peer_occt_check (built with -DNURBSGL_PEER_BENCH=ON: every
face OCCT's readers and BRepCheck_Analyzer find invalid). DISPUTED counts, per file, the faces
invalid here beyond the number OCCT finds invalid (faces are not matched one to one: a lower bound
of the faces invalid here and valid there). Prints one line per file with
invalid trims on either side, then the totals; with --out, writes trim_validity.csv. A survey, not a
test: nothing here fails.

Usage: experiments/trim_validity.py FOLDER [--build BUILD] [--out DIR] [--timeout S]
"""
import argparse
import csv
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from corpus import EXTENSIONS, parse_json  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folder")
    ap.add_argument("--build", default="build")
    ap.add_argument("--out")
    ap.add_argument("--timeout", type=float, default=120)
    a = ap.parse_args()
    cli = os.path.join(a.build, "cli", "nurbsgl")
    peer = os.path.join(a.build, "experiments", "peer_occt_check")
    if not os.path.exists(peer):
        sys.exit(f"{peer} is not built (-DNURBSGL_PEER_BENCH=ON with OpenCASCADE's packages)")
    files = sorted(os.path.join(d, f) for d, _, fs in os.walk(a.folder) for f in fs if f.lower().endswith(EXTENSIONS))
    rows = []
    for path in files:
        try:
            ours = parse_json(subprocess.run([cli, "info", path, "--json"], capture_output=True, text=True,
                                             timeout=a.timeout).stdout)
            theirs = parse_json(subprocess.run([peer, path], capture_output=True, text=True, timeout=a.timeout).stdout)
        except subprocess.TimeoutExpired:
            rows.append({"file": path, "error": "timeout"})
            continue
        invalid = ours.get("invalid_trims", [])
        occt = theirs.get("invalid_faces", [])
        disputed = invalid[len(occt):]
        row = {"file": path, "faces": ours.get("faces"), "occt_faces": theirs.get("faces"), "ours_invalid": len(invalid),
               "occt_invalid": len(occt), "disputed": len(disputed),
               "problems": " | ".join(t["problem"] for t in disputed), "error": theirs.get("error", "")}
        rows.append(row)
        if invalid or occt:
            print(json.dumps(row), flush=True)
    total = {k: sum(r.get(k) or 0 for r in rows) for k in ("ours_invalid", "occt_invalid", "disputed")}
    print(f"{len(rows)} files: {total['ours_invalid']} faces with invalid trims here, {total['occt_invalid']} faces "
          f"BRepCheck finds invalid, {total['disputed']} invalid here and valid there")
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        keys = ["file", "faces", "occt_faces", "ours_invalid", "occt_invalid", "disputed", "problems", "error"]
        with open(os.path.join(a.out, "trim_validity.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
