"""nurbsgl.dask on a LocalCluster of two worker processes: the answers of one process, bit for bit,
also when a worker is killed in the middle; one clear error for a model the workers cannot read."""
import os
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

import nurbsgl
from conftest import SPHERE_RADIUS as R

distributed = pytest.importorskip("distributed")
import nurbsgl.dask  # noqa: E402  (after the skip: it needs numpy alone, its tests need distributed)

TOL = 1e-3  # the answers' bound; the comparison is bit for bit whatever it is
N = 1_000_000


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                       silence_logs=40)
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


@pytest.fixture(scope="module")
def points():
    rng = np.random.default_rng(11)
    return rng.uniform(-2 * R, 2 * R, size=(N, 3))


@pytest.fixture(scope="module")
def one_process(sphere, points):
    return sphere.distance(points, tol=TOL)


def assert_equal(a, b):
    for name in ("distance", "bound", "point", "face", "uv", "meets_tolerance"):
        assert np.array_equal(a[name], b[name], equal_nan=name != "meets_tolerance" and name != "face"), name


def test_answers_equal_one_process(client, sphere_path, points, one_process):
    r = nurbsgl.dask.distance(client, sphere_path, points, tol=TOL)
    assert r.chunks >= 2
    assert r.failure == "" and r.engine == one_process.engine
    assert_equal(r, one_process)


def test_a_worker_killed_in_the_middle_is_replaced(client, sphere_path, points, one_process):
    pids = client.run(os.getpid)
    victim = sorted(pids.values())[0]
    killed = threading.Event()

    def kill_once_running():
        # As soon as the workers hold tasks of this run, one of them dies.
        while not killed.is_set():
            processing = client.processing()
            if any(processing.values()):
                os.kill(victim, signal.SIGKILL)
                killed.set()
            killed.wait(0.05)

    killer = threading.Thread(target=kill_once_running, daemon=True)
    killer.start()
    r = nurbsgl.dask.distance(client, sphere_path, points, tol=TOL, chunk=N // 16)
    killed.set()
    killer.join()
    assert victim not in client.run(os.getpid).values()  # the nanny started a new process
    assert_equal(r, one_process)


def test_a_missing_model_is_one_clear_error(client, tmp_path):
    missing = tmp_path / "missing.step"
    with pytest.raises(nurbsgl.ReadError, match="missing.step"):
        nurbsgl.dask.distance(client, missing, np.zeros((10, 3)))


def test_the_command_line(sphere_path, tmp_path, points):
    pts = tmp_path / "points.npy"
    np.save(pts, points[:5000])
    out = tmp_path / "out.npy"
    env = dict(os.environ)
    run = subprocess.run([sys.executable, "-m", "nurbsgl.dask", "distance", str(sphere_path), str(pts), "-o", str(out),
                          "--workers", "2", "--tol", str(TOL)], capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, run.stderr
    records = np.load(out)
    exact = np.abs(np.linalg.norm(points[:5000], axis=1) - R)
    assert (np.abs(records["distance"] - exact) <= records["bound"]).all()
    assert records["meets_tolerance"].all()
    bad = subprocess.run([sys.executable, "-m", "nurbsgl.dask", "distance", str(tmp_path / "none.igs"), str(pts), "-o",
                          str(out), "--workers", "1"], capture_output=True, text=True, env=env, timeout=300)
    assert bad.returncode == 2 and "none.igs" in bad.stderr
