"""Model.inspect: a scan of a generated surface moved by a known rigid motion is fitted back onto it
(the fit's matrix against the motion's inverse), its verdicts hold against the exact deviations, and
refused options name their field."""
import json
import subprocess

import numpy as np
import pytest

import nurbsgl


@pytest.fixture(scope="module")
def surface(cli, tmp_path_factory):
    path = tmp_path_factory.mktemp("models") / "paper-100x105.igs"
    subprocess.run([cli, "generate", "paper-100x105", "-o", str(path)], check=True, capture_output=True)
    return nurbsgl.load(path)


def motion(degrees, axis, shift, centre):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    a = np.radians(degrees)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    r = np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k
    m = np.eye(4)
    m[:3, :3] = r
    m[:3, 3] = centre - r @ centre + shift
    return m


def apply(m, p):
    return p @ m[:3, :3].T + m[:3, 3]


def scan_of(model, n=4000, seed=5):
    v = model.tessellate(eps=1e-4).vertices  # vertices are surface points at any eps
    return v[np.random.default_rng(seed).choice(len(v), size=n, replace=False)]


def test_the_fit_undoes_a_known_misplacement(surface):
    on = scan_of(surface)
    centre = 0.5 * (on.min(0) + on.max(0))
    moved = motion(0.5, [0.3, -0.2, 1.0], [0.3, -0.1, 0.2], centre)
    r = surface.inspect(apply(moved, on), within=[0.05], align=True)
    assert r.alignment["aligned"] and r.alignment["converged"], r.alignment["problem"]
    # Over the scan's box, the fitted placement lands within a tenth of the tolerance (the query's,
    # whose closest points the fit uses) of the motion's inverse.
    corners = np.array([[x, y, z] for x in on[:, 0].take([on[:, 0].argmin(), on[:, 0].argmax()])
                        for y in (on[:, 1].min(), on[:, 1].max()) for z in (on[:, 2].min(), on[:, 2].max())])
    assert np.abs(apply(r.alignment["matrix"] @ moved, corners) - corners).max() < 0.1 * r.tolerance
    assert (np.abs(r.deviation) <= r.bound).all()
    assert r.failure == "" and r.undecided_points == 0
    assert r.bands[0]["certainly_within"] == len(on)
    # The same placement given as a transform, without the fit: the same points.
    again = surface.inspect(apply(moved, on), within=[0.05], transform=r.alignment["matrix"])
    assert not again.alignment["aligned"]
    assert np.allclose(again.points, r.points, atol=1e-12)


def test_verdicts_follow_the_deviations_and_their_bounds(surface):
    on = scan_of(surface, 200)
    rng = np.random.default_rng(2)
    normal = surface.inspect(on).normal
    off = rng.uniform(-0.3, 0.3, len(on))
    r = surface.inspect(on + off[:, None] * normal, within=[0.1, 0.2], max_distance=0.25)
    assert not r.signed  # an open surface: distances
    assert (np.abs(r.deviation - np.abs(off)) <= r.bound).all()
    a = np.abs(r.deviation)
    outlier = a > 0.25
    assert (r.outlier == outlier).all()
    for b, d in enumerate((0.1, 0.2)):
        v = r.verdicts[:, b]
        assert (v[outlier] == 3).all()
        assert ((v == 0) == (~outlier & (a + r.bound <= d))).all()
        assert ((v == 1) == (~outlier & (a - r.bound > d))).all()
        assert r.bands[b]["certainly_within"] == int((v == 0).sum())
    assert r.statistics["inliers"] == int((~outlier).sum())
    assert r.statistics["max"] == r.deviation[~outlier].max()


def test_refused_options_name_their_field(surface):
    on = scan_of(surface, 10)
    with pytest.raises(nurbsgl.RequestError, match="within: the bands must ascend"):
        surface.inspect(on, within=[0.2, 0.1])
    with pytest.raises(nurbsgl.RequestError, match="transform: not a rigid motion"):
        surface.inspect(on, transform=np.diag([2.0, 1.0, 1.0, 1.0]))


def test_the_command_line_writes_every_output(cli, surface, tmp_path):
    # A scan file of the surface 0.1 off along its normals, inspected by `nurbsgl inspect`: the CSV
    # holds the deviations, normals and verdicts, the PLY its points, the PNG a histogram.
    on = scan_of(surface, 300)
    off = on + 0.1 * surface.inspect(on).normal
    np.save(tmp_path / "scan.npy", off)
    csv, ply, png = tmp_path / "r.csv", tmp_path / "r.ply", tmp_path / "r.png"
    out = subprocess.run([cli, "inspect", surface.path, str(tmp_path / "scan.npy"), "--within", "0.05,0.2",
                          "--csv", str(csv), "--ply", str(ply), "--histogram", str(png), "--json"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    j = json.loads(out.stdout)
    assert j["scan"]["format"] == "npy float64" and j["statistics"]["inliers"] == 300
    assert [b["certainly_outside"] for b in j["bands"]] == [300, 0]
    rows = np.genfromtxt(csv, delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert np.allclose(rows["deviation"], 0.1, atol=j["tolerance"])
    assert (rows["within_005"] == "outside").all() and (rows["within_02"] == "within").all()
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"element vertex 300" in ply.read_bytes().split(b"end_header\n")[0]


def test_a_scan_far_off_starts_from_the_box_centres(surface):
    # Moved by a third of the model size: the sample's median distance is above a tenth of it, so the
    # fit first matches the box centres, then converges onto the surface.
    on = scan_of(surface)
    centre = 0.5 * (on.min(0) + on.max(0))
    far = motion(0.5, [0.3, -0.2, 1.0], [30.0, -25.0, 20.0], centre)
    r = surface.inspect(apply(far, on), within=[0.05], align=True)
    assert r.alignment["coarse_start"] and r.alignment["converged"], r.alignment["problem"]
    assert (np.abs(r.deviation) <= r.bound).all()
    near = surface.inspect(apply(motion(0.5, [0.3, -0.2, 1.0], [0.3, -0.1, 0.2], centre), on), within=[0.05],
                           align=True)
    assert not near.alignment["coarse_start"]


def test_the_fit_on_chosen_faces(surface):
    on = scan_of(surface, 500)
    r = surface.inspect(on + [0.2, 0.0, 0.0], within=[0.05], align=True, align_faces=[0])
    assert r.alignment["converged"] and (np.abs(r.deviation) <= r.bound).all()
    with pytest.raises(nurbsgl.RequestError, match="face 3 is not a face of the model"):
        surface.inspect(on, align=True, align_faces=[3])
