"""Fixtures of the Python module's tests: generated models written by the nurbsgl command line
(NURBSGL_CLI, set by ctest), the shared CAD models when present (NURBSGL_SHARED_DIR)."""
import os
import pathlib
import subprocess

import pytest

SPHERE_RADIUS = 10.0  # `nurbsgl generate sphere`: radius 10 at the origin, one rational face


def _cli():
    cli = os.environ.get("NURBSGL_CLI")
    if not cli or not os.path.exists(cli):
        pytest.skip("NURBSGL_CLI (the nurbsgl program) not set: run through ctest")
    return cli


@pytest.fixture(scope="module")
def cli():
    return _cli()


@pytest.fixture(scope="module")
def sphere_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("models") / "sphere.igs"
    subprocess.run([_cli(), "generate", "sphere", "-o", str(path)], check=True, capture_output=True)
    return path


@pytest.fixture(scope="module")
def sphere(sphere_path):
    import nurbsgl
    return nurbsgl.load(sphere_path)


@pytest.fixture(scope="module")
def shared_models():
    root = pathlib.Path(os.environ.get("NURBSGL_SHARED_DIR", "../shared")) / "models"
    if not root.is_dir():
        pytest.skip(f"the shared CAD models are absent ({root})")
    return root
