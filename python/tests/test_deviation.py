"""The scan deviation report from Python and from the command line, on the closed solid cylinder of
tests/data (radius 1, height 3 about z): signed distances against the exact ones, the histogram
PNG (matplotlib), the coloured PLY."""
import json
import math
import pathlib
import subprocess

import numpy as np
import pytest

import nurbsgl

CYLINDER = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "closed_cylinder_solid.stp"


def exact_signed(p):
    r = np.hypot(p[:, 0], p[:, 1]) - 1.0
    z = np.maximum(-p[:, 2], p[:, 2] - 3.0)
    inside = (r <= 0) & (z <= 0)
    return np.where(inside, np.maximum(r, z), np.hypot(np.maximum(r, 0), np.maximum(z, 0)))


@pytest.fixture(scope="module")
def scan():
    rng = np.random.default_rng(21)
    return rng.uniform([-2, -2, -1], [2, 2, 4], size=(3000, 3))


def test_signed_distances_are_within_their_bounds(scan):
    model = nurbsgl.load(CYLINDER)
    r = model.distance(scan, tol=1e-5, signed=True)
    assert r.failure == ""
    exact = exact_signed(scan)
    assert (np.abs(r.signed_distance - exact) <= r.bound).all()
    assert (r.signed_distance < 0).sum() > 300
    assert "signed_distance" not in model.distance(scan[:10], tol=1e-5)


def test_signed_distances_need_a_closed_solid(sphere):
    with pytest.raises(nurbsgl.RequestError, match="closed"):
        sphere.distance(np.zeros((1, 3)), signed=True)


def test_histogram_png(scan, tmp_path):
    model = nurbsgl.load(CYLINDER)
    r = model.distance(scan, tol=1e-5, signed=True)
    png = tmp_path / "deviation.png"
    shares = nurbsgl.histogram.plot(r.signed_distance, png, within=[0.5, 0.1], unit=model.unit)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    d = np.abs(r.signed_distance)
    assert shares == [np.count_nonzero(d <= 0.1) / len(d), np.count_nonzero(d <= 0.5) / len(d)]


def test_the_command_line_writes_the_report(cli, scan, tmp_path):
    points = tmp_path / "scan.txt"
    np.savetxt(points, scan[:500], fmt="%.17g")
    ply, png = tmp_path / "scan.ply", tmp_path / "scan.png"
    out = subprocess.run([cli, "distance", str(CYLINDER), "--points", str(points), "--signed", "--within", "0.1,0.5",
                          "--ply", str(ply), "--histogram", str(png), "--json"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    j = json.loads(out.stdout)
    signed = np.array([x["signed_distance"] for x in j["results"]])
    bands = j["deviation"]["within"]
    assert [b["distance"] for b in bands] == [0.1, 0.5]
    assert bands[0]["points"] == np.count_nonzero(np.abs(signed) <= 0.1)
    assert j["deviation"]["sides"]["unsure"] == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    header = ply.read_bytes().split(b"end_header\n")[0].decode()
    assert "element vertex 500" in header and "property float deviation" in header and "element face 0" in header
