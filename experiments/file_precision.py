#!/usr/bin/env python3
"""Answers over the tolerance by the file's edge gaps, per model, as a user runs them.

For each model: N random points (seeded by the file name) in its box grown by 10 % (5 % of its
extent on each side, experiments/corpus.py's write_points), `nurbsgl distance MODEL --points F
--json --csv ROWS` at the default tolerance. Counted from the JSON and the rows: the answers over the
tolerance (found, certified, bound over T), those limited only by the file's precision
(limited_by_file), those short of T with no reason on the answer, the uncertified ones, the exit
code and the wall time. Several builds (--build, repeatable, each LABEL=DIR) run on the same points
in the same run, so a rule is compared with another on equal terms. Writes file_precision.csv under
--out when given. A survey, not a test: nothing here fails.

Usage: experiments/file_precision.py MODEL... [--build LABEL=DIR ...] [--points N] [--out DIR]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from corpus import parse_json, write_points  # noqa: E402


def count_rows(path):
    """(short of T, short of T without a reason, limited by the file) from a --csv file: the reason
    column is "reason" (or the older "uncertified")."""
    short = silent = limited = 0
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["meets_tolerance"] == "true":
                continue
            short += 1
            reason = row.get("reason", row.get("uncertified", ""))
            silent += not reason
            limited += row.get("limited_by_file") == "true"
    return short, silent, limited


def survey(cli, model, points, tmp):
    rows = os.path.join(tmp, "rows.csv")
    t0 = time.monotonic()
    p = subprocess.run([cli, "distance", model, "--points", points, "--json", "--csv", rows], capture_output=True,
                       text=True)
    wall = time.monotonic() - t0
    j = parse_json(p.stdout)
    out = {"exit": p.returncode, "seconds": round(wall, 2), "over_tolerance": j.get("over_tolerance"),
           "uncertified": j.get("uncertified"), "not_found": j.get("not_found"),
           "limited_by_file": j.get("limited_by_file")}
    if os.path.exists(rows):
        short, silent, limited = count_rows(rows)
        out.update(short=short, without_reason=silent)
        os.remove(rows)
    else:
        out["error"] = (p.stderr.strip().splitlines() or [""])[-1]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("models", nargs="+")
    ap.add_argument("--build", action="append", default=[], help="LABEL=DIR of a build (repeatable); default build")
    ap.add_argument("--points", type=int, default=20000)
    ap.add_argument("--out")
    a = ap.parse_args()
    builds = [b.split("=", 1) if "=" in b else [b, b] for b in a.build] or [["build", "build"]]
    table = []
    with tempfile.TemporaryDirectory() as tmp:
        for model in a.models:
            cli0 = os.path.join(builds[0][1], "cli", "nurbsgl")
            info = parse_json(subprocess.run([cli0, "info", model, "--json"], capture_output=True, text=True).stdout)
            if "bbox" not in info:
                print(f"{model}: not read", file=sys.stderr)
                continue
            points = os.path.join(tmp, "points.txt")
            write_points(info, a.points, zlib.crc32(os.path.basename(model).encode()), points)
            for label, build in builds:
                row = {"model": os.path.basename(model), "faces": info.get("faces"), "build": label}
                row.update(survey(os.path.join(build, "cli", "nurbsgl"), model, points, tmp))
                table.append(row)
                print(json.dumps(row), flush=True)
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        keys = sorted({k for r in table for k in r}, key=lambda k: list(table[0]).index(k) if k in table[0] else 99)
        with open(os.path.join(a.out, "file_precision.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            w.writerows(table)


if __name__ == "__main__":
    main()
