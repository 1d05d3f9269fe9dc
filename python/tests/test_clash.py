"""The clash report from Python, and sharded on Dask: the rows of `nurbsgl clash --json` on the
shared 18-body assembly (skipped without the shared models), the refusal of a one-body model."""
import json
import subprocess

import numpy as np
import pytest

import nurbsgl

ASSEMBLY = "assembly/gmsh_as1-tu-203.stp"


def rows_of(report):
    return [(r["body_a"], r["body_b"], r["computed"], r["distance"] if r["computed"] else None,
             r["bound"] if r["computed"] else None, r["intersecting"] if r["computed"] else None) for r in report.rows]


def test_one_body_is_refused(sphere):
    with pytest.raises(nurbsgl.RequestError, match="bod"):
        nurbsgl.clash(sphere)


def test_equals_the_command_line(shared_models, cli):
    path = shared_models / ASSEMBLY
    if not path.exists():
        pytest.skip(f"{path} is absent")
    r = nurbsgl.clash(nurbsgl.load(path), min_clearance=20.0, tol=1e-4)
    out = subprocess.run([cli, "clash", str(path), "--min-clearance", "20", "--tol", "1e-4", "--json"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    j = json.loads(out.stdout)
    assert r.pairs == j["pairs"] == 153
    assert r.pairs_computed == j["pairs_computed"] and r.pairs_beyond == j["pairs_beyond"]
    cli_rows = [(x["body_a"], x["body_b"], x["computed"], x.get("distance"), x.get("bound"), x.get("intersecting"))
                for x in j["results"]]
    assert rows_of(r) == cli_rows
    assert r.failure == ""


def test_sharded_on_dask_equals_one_process(shared_models):
    distributed = pytest.importorskip("distributed")
    import nurbsgl.dask
    path = shared_models / ASSEMBLY
    if not path.exists():
        pytest.skip(f"{path} is absent")
    one = nurbsgl.clash(nurbsgl.load(path), tol=1e-4)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=40) as cluster, distributed.Client(cluster) as client:
        sharded = nurbsgl.dask.clash(client, path, tol=1e-4)
    assert sharded.shards >= 2
    assert rows_of(sharded) == rows_of(one)
    assert (sharded.pairs_intersecting, sharded.pairs_uncertified) == (one.pairs_intersecting, one.pairs_uncertified)
    assert sharded.failure == one.failure
