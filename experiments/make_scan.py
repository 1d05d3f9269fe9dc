#!/usr/bin/env python3
"""A synthetic scan of a model, as a scanner delivers one: points sampled evenly over the model's
faces (its guaranteed tessellation, area-weighted), Gaussian noise along each point's normal, a share
of outliers (fixture points up to a tenth of the model size off), all moved by a known rigid motion
(the scanner's frame). Writes a binary little-endian PLY (float64 x y z) and the motion that places
the scan back on the model (scan into model coordinates, the matrix `inspect --transform` reads).

    experiments/make_scan.py MODEL OUT.ply --points 1000000 --noise 0.02 --angle 0.5 --shift 0.3 \
        --outliers 0.01 --seed 1 [--truth OUT.json]
"""
import argparse
import json
import pathlib
import sys

import numpy as np


def rotation(axis, degrees):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    a = np.radians(degrees)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("model")
    p.add_argument("out")
    p.add_argument("--points", type=int, default=1000000)
    p.add_argument("--noise", type=float, default=0.02, help="sigma along the normal, model units")
    p.add_argument("--angle", type=float, default=0.5, help="degrees of the misplacement's rotation")
    p.add_argument("--shift", type=float, default=0.3, help="length of its translation, model units")
    p.add_argument("--outliers", type=float, default=0.01, help="share of points off the part")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--truth", help="write the placement back (scan into model) as JSON here")
    p.add_argument("--build", default=str(pathlib.Path(__file__).resolve().parent.parent / "build"),
                   help="the build folder holding python/nurbsgl (default: build/ beside experiments/)")
    a = p.parse_args(argv)
    sys.path.insert(0, a.build + "/python")
    import nurbsgl

    rng = np.random.default_rng(a.seed)
    model = nurbsgl.load(a.model)
    mesh = model.tessellate(eps=1e-4, relative=True)
    v, t = mesh.vertices, mesh.triangles
    e1, e2 = v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]
    cross = np.cross(e1, e2)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    n_out = int(round(a.outliers * a.points))
    n_in = a.points - n_out
    tri = rng.choice(len(t), size=n_in, p=area / area.sum())
    r1, r2 = rng.random(n_in), rng.random(n_in)
    flip = r1 + r2 > 1
    r1[flip], r2[flip] = 1 - r1[flip], 1 - r2[flip]
    pts = v[t[tri, 0]] + r1[:, None] * e1[tri] + r2[:, None] * e2[tri]
    normal = cross[tri] / np.maximum(np.linalg.norm(cross[tri], axis=1), 1e-300)[:, None]
    pts += rng.normal(0.0, a.noise, n_in)[:, None] * normal
    lo, hi = v.min(0), v.max(0)
    size = np.linalg.norm(hi - lo)
    # Outliers: points of a fixture or the table, off the part by up to a tenth of its size.
    base = v[t[rng.choice(len(t), size=n_out, p=area / area.sum()), 0]]
    direction = rng.normal(size=(n_out, 3))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    outliers = base + direction * rng.uniform(0.02 * size, 0.1 * size, (n_out, 1))
    pts = np.vstack([pts, outliers])
    rng.shuffle(pts)
    # The misplacement (model into scan): a rotation about the model's centre, then a shift.
    centre = 0.5 * (lo + hi)
    R = rotation(rng.normal(size=3), a.angle)
    shift = rng.normal(size=3)
    shift *= a.shift / np.linalg.norm(shift)
    scan = (pts - centre) @ R.T + centre + shift
    # Its inverse: scan into model coordinates.
    Ri = R.T
    back = np.eye(4)
    back[:3, :3] = Ri
    back[:3, 3] = centre - Ri @ (centre + shift)
    header = ("ply\nformat binary_little_endian 1.0\ncomment synthetic scan of %s\nelement vertex %d\n"
              "property double x\nproperty double y\nproperty double z\nend_header\n" % (a.model, len(scan)))
    with open(a.out, "wb") as f:
        f.write(header.encode())
        f.write(np.ascontiguousarray(scan, dtype="<f8").tobytes())
    if a.truth:
        with open(a.truth, "w") as f:
            json.dump({"matrix": back.tolist(), "points": len(scan), "outliers": n_out, "noise": a.noise,
                       "model_size": float(size)}, f, indent=1)
    print(f"{a.out}: {len(scan)} points ({n_out} outliers), noise {a.noise}, {a.angle} deg and {a.shift} off")


if __name__ == "__main__":
    main()
