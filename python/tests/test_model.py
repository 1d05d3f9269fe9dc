"""The Python module's queries on the generated sphere (radius 10 at the origin), against the exact
answers and against the nurbsgl command line on the same inputs."""
import json
import subprocess
import threading
import time

import numpy as np
import pytest

import nurbsgl
from conftest import SPHERE_RADIUS as R


def sphere_points(n, seed=1):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    return d * rng.uniform(0.3 * R, 3.0 * R, size=(n, 1))


def test_load_describes_the_model(sphere):
    assert sphere.faces == 1
    assert len(sphere.bodies) == 1
    assert sphere.unit == "mm"
    # The box of a sphere of radius R: its diagonal 2 R sqrt(3), up to the box's sampling.
    assert sphere.size == pytest.approx(2 * R * np.sqrt(3), rel=1e-6)
    assert not sphere.changed and sphere.dropped == []
    assert "1 faces" in repr(sphere)


def test_a_bad_file_is_a_read_error_naming_it(tmp_path):
    bad = tmp_path / "bad.igs"
    bad.write_text("not an IGES file\n")
    with pytest.raises(nurbsgl.ReadError, match="bad.igs"):
        nurbsgl.load(bad)
    with pytest.raises(nurbsgl.ReadError, match="missing.step"):
        nurbsgl.load(tmp_path / "missing.step")


def test_distance_is_within_its_bound_of_the_exact_one(sphere):
    p = sphere_points(2000)
    r = sphere.distance(p, tol=1e-5)
    exact = np.abs(np.linalg.norm(p, axis=1) - R)
    assert r.distance.shape == (2000,) and r.point.shape == (2000, 3) and r.uv.shape == (2000, 2)
    assert r.meets_tolerance.all() and r.failure == ""
    assert (np.abs(r.distance - exact) <= r.bound).all()
    assert (r.bound <= r.tolerance).all()
    assert r.tolerance == pytest.approx(1e-5 * sphere.size)
    # The closest points lie on the sphere, within the point bound of the exact ones.
    exact_points = p / np.linalg.norm(p, axis=1)[:, None] * R
    assert (np.linalg.norm(r.point - exact_points, axis=1) <= r.point_bound + 1e-12).all()
    assert (r.face == 0).all()


def test_the_mesh_and_the_pyramid_agree_within_their_bounds(sphere):
    p = sphere_points(500, seed=3)
    mesh, pyramid = sphere.distance(p, tol=1e-4), sphere.distance(p, tol=1e-4, engine="cpu")
    assert mesh.path == "mesh" and pyramid.path == "batched"
    assert (np.abs(mesh.distance - pyramid.distance) <= mesh.bound + pyramid.bound).all()


def test_distance_equals_the_command_line(sphere, sphere_path, cli, tmp_path):
    p = sphere_points(300, seed=7)
    points = tmp_path / "points.txt"
    np.savetxt(points, p, fmt="%.17g")
    out = subprocess.run([cli, "distance", str(sphere_path), "--points", str(points), "--tol", "1e-4", "--json"],
                         check=True, capture_output=True, text=True)
    answers = json.loads(out.stdout)["results"]
    r = sphere.distance(p, tol=1e-4)
    assert [a["distance"] for a in answers] == r.distance.tolist()
    assert [a["bound"] for a in answers] == r.bound.tolist()
    assert [a["face"] for a in answers] == r.face.tolist()


def test_bad_points_are_value_errors(sphere):
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        sphere.distance(np.zeros((4, 2)))
    bad = np.zeros((3, 3))
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match="row 2"):
        sphere.distance(bad)
    with pytest.raises(ValueError, match="engine"):
        sphere.distance(np.zeros((1, 3)), engine="quantum")
    with pytest.raises(nurbsgl.RequestError):
        sphere.distance(np.zeros((1, 3)), tol=1e-30)


def test_the_gil_is_released_while_a_query_runs(sphere):
    p = sphere_points(200_000, seed=3)
    ticks = []
    worker = threading.Thread(target=lambda: sphere.distance(p, tol=1e-3, engine="cpu"))
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    # This thread ran on while the query held no GIL: many ticks, not one at the end.
    assert len(ticks) > 20


def test_tessellate_lies_within_its_bound(sphere):
    m = sphere.tessellate(eps=1e-3)
    assert m.failure == ""
    assert m.vertices.shape[1] == 3 and m.triangles.shape[1] == 3 and len(m.triangle_face) == len(m.triangles)
    assert m.triangles.max() < len(m.vertices)
    radial = np.abs(np.linalg.norm(m.vertices, axis=1) - R)
    assert radial.max() <= m.bound


def test_raycast_hits_the_sphere(sphere):
    rng = np.random.default_rng(5)
    d = rng.normal(size=(500, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    origins = -3 * R * d  # outside, looking through the centre
    r = sphere.raycast(origins, d)
    assert r.method == "mesh" and r.failure == ""
    assert r.hit.all()
    assert np.abs(r.t - 2 * R).max() < 1e-6 * R
    assert np.abs(r.t - 2 * R).max() <= r.hit_residual
    assert np.abs(np.linalg.norm(r.point, axis=1) - R).max() < 1e-6 * R
    # A coarser slab mesh finds the same exact hits.
    coarse = sphere.raycast(origins, d, mesh_tol=1e-3)
    assert 0 < coarse.mesh_triangles < r.mesh_triangles
    assert np.array_equal(coarse.hit, r.hit) and np.abs(coarse.t - r.t).max() < 1e-9 * R
    with pytest.raises(ValueError, match="mesh_tol"):
        sphere.raycast(origins, d, mesh_tol=0.5)
    with pytest.raises(ValueError, match="tol"):
        sphere.raycast(origins, d, tol=0.5)


def test_raycast_on_the_gpu_says_its_hits_are_not_certified(sphere):
    # The paper's BVH pass: the same hits here, but a ray grazing a face within the bicubic
    # tolerance may miss it, so its nearest hits are never certified.
    d = np.tile([0.0, 0.0, 1.0], (3, 1))
    origins = np.array([[0.0, 0.0, -3 * R], [0.5 * R, 0.0, -3 * R], [2 * R, 0.0, -3 * R]])
    r = sphere.raycast(origins, d, engine="gpu")
    assert r.method == "bvh"
    assert r.failure.startswith("the nearest hits are not certified: the bvh method")
    assert list(r.hit) == [True, True, False]
    assert abs(r.t[0] - 2 * R) <= r.hit_residual
    t = sphere.thickness(samples=200, engine="gpu")
    assert t.failure.startswith("the nearest hits are not certified: the bvh method")


def test_thickness_of_a_sphere_is_its_diameter(sphere):
    t = sphere.thickness(samples=500)
    hit = t.thickness >= 0
    assert hit.mean() > 0.99
    assert np.abs(t.thickness[hit] - 2 * R).max() < 1e-6 * R


def test_clearance_of_a_moved_copy(sphere):
    move = np.eye(4)
    move[0, 3] = 3 * R  # centres 3R apart: a gap of R
    c = nurbsgl.clearance(sphere, sphere, motion=move, tol=1e-5)
    assert c.found and c.meets_tolerance and not c.intersecting
    assert abs(c.distance - R) <= c.bound
    several = nurbsgl.clearance(sphere, sphere, motion=np.stack([move, move]), tol=1e-5)
    assert [s.distance for s in several] == [c.distance, c.distance]
    overlap = np.eye(4)
    overlap[0, 3] = R  # the spheres cross
    assert nurbsgl.clearance(sphere, sphere, motion=overlap, tol=1e-5).intersecting


def test_an_answer_limited_by_the_files_edges_says_so(shared_models):
    # The bearing's edges lie up to 6e-6 off its faces: beside face 48's edge (3e-6 off) the answer
    # is over the default tolerance only by that, certified to the file's precision; over a face's
    # middle it meets the tolerance. strict=True makes the first a failure.
    import nurbsgl
    bearing = nurbsgl.load(shared_models / "iges" / "occt_bearing.iges")
    points = np.array([[0.0226551151168, 0.010058773699, -0.000123904306734],
                       [0.0156512499625, 0.0249416595128, 0.0258558387296]])
    r = bearing.distance(points)
    assert list(r.limited_by_file) == [True, False]
    assert list(r.meets_tolerance) == [False, True]
    assert r.gap_face[0] == 48 and 0 < r.file_gap[0] < 1e-5
    assert "only by the file's precision: face 48 (id 1251)" in r.reasons[0]
    assert r.reasons[1] == ""
    assert r.failure == ""
    assert "face 48 (id 1251)" in r.file_precision
    strict = bearing.distance(points, strict=True)
    assert "only by the file's precision (strict)" in strict.failure


def test_every_answer_carries_the_outward_normal_at_its_closest_point(sphere):
    # On the sphere about the origin the outward normal at the closest point is the point's direction.
    pts = sphere_points(200, seed=7)
    r = sphere.distance(pts, tol=1e-6)
    expected = pts / np.linalg.norm(pts, axis=1)[:, None]
    assert np.abs(r.normal - expected).max() < 1e-4


def test_a_tolerance_that_is_not_a_number_is_refused_after_a_good_call(sphere):
    pts = sphere_points(5)
    sphere.distance(pts, tol=1e-5)
    for bad in (float("nan"), float("inf"), 0.0, -1e-5):
        with pytest.raises(nurbsgl.RequestError, match="tolerance: .* is not a finite number from 1e-9 to 1"):
            sphere.distance(pts, tol=bad)
