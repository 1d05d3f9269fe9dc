"""nurbsgl.read_points: the files numpy and a scanner's PLY export write, read back exactly, and a
malformed file named in the error."""
import struct

import numpy as np
import pytest

import nurbsgl


def cloud(n=1000, seed=3):
    return np.random.default_rng(seed).uniform(-50.0, 50.0, size=(n, 3))


@pytest.mark.parametrize("dtype", ["<f8", ">f8", "<f4", ">f4"])
def test_npy_written_by_numpy(tmp_path, dtype):
    pts = cloud().astype(dtype)
    np.save(tmp_path / "scan.npy", pts)
    np.save(tmp_path / "scan_f.npy", np.asfortranarray(pts))
    for name in ("scan.npy", "scan_f.npy"):
        r = nurbsgl.read_points(tmp_path / name)
        assert r.points.dtype == np.float64 and r.points.shape == pts.shape
        assert np.array_equal(r.points, pts.astype(np.float64))
        assert r.normals is None and r.colors is None


def test_text_written_by_numpy_with_a_header(tmp_path):
    pts = cloud()
    rgb = np.random.default_rng(4).integers(0, 256, size=(len(pts), 3))
    np.savetxt(tmp_path / "scan.csv", np.c_[np.arange(len(pts)), pts, rgb], delimiter=",",
               header="id,x,y,z,red,green,blue", comments="", fmt=["%d", "%.17g", "%.17g", "%.17g", "%d", "%d", "%d"])
    r = nurbsgl.read_points(tmp_path / "scan.csv")
    assert r.format == "text"
    assert np.array_equal(r.points, pts)
    assert np.array_equal(r.colors, rgb.astype(np.uint8))


def test_binary_ply_with_normals_and_colours(tmp_path):
    pts = cloud(100).astype(np.float32)
    normals = np.tile(np.float32([0, 0, 1]), (len(pts), 1))
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
              "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
              "property uchar green\nproperty uchar blue\nend_header\n" % len(pts)).encode()
    body = b"".join(struct.pack("<6f3B", *p, *n, 1, 2, 3) for p, n in zip(pts, normals))
    (tmp_path / "scan.ply").write_bytes(header + body)
    r = nurbsgl.read_points(tmp_path / "scan.ply")
    assert r.format == "ply binary little endian"
    assert np.array_equal(r.points, pts.astype(np.float64))
    assert np.array_equal(r.normals, normals.astype(np.float64))
    assert (r.colors == [1, 2, 3]).all()


def test_a_truncated_ply_names_the_byte(tmp_path):
    header = b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n" \
             b"property float z\nend_header\n"
    (tmp_path / "cut.ply").write_bytes(header + struct.pack("<4f", 1, 2, 3, 4))
    message = r"cut\.ply: byte %d: vertex 1 of 2: the file ends" % (len(header) + 12)
    with pytest.raises(nurbsgl.ReadError, match=message):
        nurbsgl.read_points(tmp_path / "cut.ply")
