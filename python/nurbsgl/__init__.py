"""Certified geometric queries on trimmed NURBS models (IGES, STEP).

    import numpy as np, nurbsgl
    model = nurbsgl.load("part.step")
    r = model.distance(np.array([[10.0, 20.0, 30.0]]), tol=1e-4)
    r.distance, r.bound, r.point, r.face, r.uv, r.meets_tolerance

Every answer carries its bound: |distance - true distance| <= bound, and meets_tolerance says the
answer is certified within the tolerance (relative to the model size, as the command line's
--tol). A model the reader changed (faces dropped, trims repaired) says so in `model.changes`;
answers it makes uncertain say why in `reasons`. Queries release the GIL; GL work runs on one
thread of the module's own. Errors: ReadError (a file that cannot be read, naming file and line or
entity), RequestError (a request refused before the work, as the command line's exit 2), NoGLError
(no OpenGL), ValueError (bad arguments).
"""

from ._nurbsgl import NoGLError, ReadError, RequestError, gl_info
from . import _nurbsgl
from . import histogram

__all__ = ["load", "read_points", "clearance", "clash", "histogram", "Model", "Result", "ReadError", "RequestError",
           "NoGLError", "gl_info"]


class Result:
    """A query's answers: numpy arrays (one row per point or ray) and figures, as attributes and as
    keys (result.distance, result["distance"])."""

    def __init__(self, fields):
        self.__dict__.update(fields)

    def __getitem__(self, key):
        return self.__dict__[key]

    def __contains__(self, key):
        return key in self.__dict__

    def keys(self):
        return self.__dict__.keys()

    def __repr__(self):
        def show(v):
            shape = getattr(v, "shape", None)
            return f"array{shape}" if shape is not None else repr(v)
        return "Result(" + ", ".join(f"{k}={show(v)}" for k, v in self.__dict__.items()) + ")"


class Model:
    """A model read from a file: its bodies, faces, size and unit, and what the reader changed."""

    def __init__(self, binding):
        self._m = binding
        info = binding.info()
        self.path = info["path"]
        self.bodies = info["bodies"]          # list of dicts: name, instance, faces, closed
        self.faces = info["faces"]            # faces read (answers' `face` index them)
        self.faces_in_file = info["faces_in_file"]
        self.size = info["size"]              # the diagonal of the model's box: tolerances scale with it
        self.unit = info["unit"]              # the file's length unit ("mm", "in", ...)
        self.unit_scale_to_mm = info["unit_scale_to_mm"]
        self.dropped = info["dropped"]        # faces of the file the reader left out, each with its reason
        self.changed = info["changed"]        # anything differs from the letter of the file
        self.changes = info["changes"]        # what differs, one line each

    def __repr__(self):
        return (f"nurbsgl.Model({self.path!r}: {len(self.bodies)} bodies, {self.faces} faces, "
                f"size {self.size:.6g} {self.unit}{', changed by the reader' if self.changed else ''})")

    def distance(self, points, tol=1e-5, engine="auto", per_point=False, accept_partial=False, cache=True,
                 signed=False, strict=False):
        """Minimum distance from every point of an (N, 3) float64 array (model units, the model's frame)
        to the model (Krishnamurthy et al.), each answer within `tol` x the model size.

        Returns a Result with, per point: distance, bound, point_bound, point (N, 3), normal (N, 3: the
        face's outward unit normal at the closest point), face, uv (N, 2),
        meets_tolerance (bool), reasons (why an answer falls short of the tolerance: not certified, not
        found, or over it, "" where it meets it), limited_by_file (bool: over the tolerance only because
        the file's edges lie off their faces near it, certified to the file's precision), file_gap and
        gap_face (the gapped face that widened the bound, 0 and -1 where none); and tolerance (model
        units), engine, path ("mesh", "batched" or "per-point"), batched, seconds, prepare_seconds,
        file_precision (the limited answers by face, for people), failure (why the answers are not all
        certified, "" when they are; answers limited by the file count only with strict=True). The
        model is prepared once per set of options; later calls reuse it.
        engine: "auto" (the certified mesh: the faces tessellated within the tolerance, every
        point's closest triangle from Embree's BVH, each bound the mesh's proven distance to the
        faces; the grids' pyramid where the mesh cannot be made), or the grids' pyramid descended
        on "cpu" (its twin in double) or "gpu" (the fragment-shader pass).
        per_point: the paper's one query at a time instead of the batched projection.
        signed: also signed_distance, negative inside the model's solids (RequestError for a model
        whose bodies are not stated closed); nurbsgl.histogram.plot draws its histogram."""
        return Result(self._m.distance(points, tol, engine, per_point, accept_partial, cache, signed, strict))

    def inspect(self, scan, within=(), max_distance=float("inf"), tol=0.0, transform=None, align=False,
                align_faces=(), align_sample=20000, engine="auto", accept_partial=False):
        """A scan against the model, as `nurbsgl inspect`: `scan` an (N, 3) array or a file read by
        read_points; `within` the inspection bands (model units, ascending); points farther than
        `max_distance` are outliers; `tol` the certification tolerance in model units (0: the smallest
        band / 10); `transform` a 4 x 4 placement applied first; `align` best-fits the scan (on
        `align_faces` only when given). Returns a Result with points (in the model's frame), deviation
        (signed where the solids are closed), bound, closest, normal (outward, at the closest point),
        face, outlier, verdicts ((N, bands) int8: 0 within, 1 outside, 2 undecided, 3 outlier,
        4 not found), reasons, alignment, bands, statistics, undecided_points and failure ("" when
        every inlier's verdicts are certain)."""
        if isinstance(scan, (str, bytes)) or hasattr(scan, "__fspath__"):
            scan = read_points(scan).points
        return Result(self._m.inspect(scan, list(within), float(max_distance), float(tol), transform, bool(align),
                                      list(align_faces), int(align_sample), engine, bool(accept_partial)))

    def tessellate(self, eps=1e-3, relative=True, watertight=False, guaranteed=True, check=False,
                   accept_partial=False):
        """The model as one triangle mesh within eps of its faces (Balazs, Guthe, Klein): eps relative to
        the model size unless relative=False. Returns a Result with vertices (V, 3), triangles (T, 3),
        triangle_face (T), normals, eps and bound (model units), failure ("" when the mesh is certified
        within bound) and, with check=True, the measured deviation."""
        return Result(self._m.tessellate(eps, relative, watertight, guaranteed, check, accept_partial))

    def raycast(self, origins, directions, t_min=0.0, engine="cpu", tol=1e-5, mesh_tol=1e-4,
                accept_partial=False):
        """Nearest hits (t > t_min) of rays from (N, 3) origins along (N, 3) directions (Lemasson et al.):
        hit (bool), t (NaN where none), point, face, uv per ray; method, mesh_triangles, hit_residual
        (how far a hit point may lie from the file's faces), seconds, and failure ("" when the hits
        are certified: the mesh method on the CPU, on a model read whole with valid trims). engine
        "cpu" (double, the certified mesh method) or "gpu" (the paper's BVH pass: its nearest hits
        are not certified, as failure says). tol: the bicubic tolerance, mesh_tol: on the CPU, the
        eps of the mesh whose slab finds the crossings (both relative to the model size; the hits are
        the exact faces' whatever they are): finer for millions of rays."""
        return Result(self._m.raycast(origins, directions, t_min, engine, tol, mesh_tol, accept_partial))

    def thickness(self, samples=20000, engine="cpu", ball=False, min_wall=0.0, accept_partial=False):
        """Wall thickness from about `samples` samples over the faces, a ray from each along the inward
        normal: per ray origin, direction, face, thickness (-1: no hit) and with ball=True the rolling
        ball's; min, median, mean, max, hits, below_min_wall, failure."""
        return Result(self._m.thickness(samples, engine, ball, min_wall, accept_partial))


def load(path):
    """Reads an IGES, STEP or .bpt file. Raises ReadError naming the file and where in it."""
    return Model(_nurbsgl.load(str(path)))


def read_points(path):
    """Reads a file of points as scanners write them, told apart by content: PLY (ascii or binary,
    either byte order), NumPy .npy (N x 3 or more columns, float32 or float64) or text (x y z per line,
    spaces, tabs, commas or semicolons, an optional header naming the columns). Returns a Result with
    `points` (N x 3 float64), `normals` (N x 3, or None), `colors` (N x 3 uint8, or None) and `format`.
    Raises ReadError naming the file and the line or byte."""
    return Result(_nurbsgl.read_points(str(path)))


def _frames(motion):
    import numpy as np
    if motion is None:
        return [], True
    m = np.asarray(motion, dtype=np.float64)
    if m.shape == (4, 4):
        return [m], True
    if m.ndim == 3 and m.shape[1:] == (4, 4):
        return list(m), False
    raise ValueError(f"motion: a 4 x 4 array or a (K, 4, 4) array is wanted, not shape {m.shape}")


def clearance(a, b=None, motion=None, bodies=(None, None), tol=1e-5, engine="auto", voxel_stage=False,
              accept_partial=False):
    """Minimum distance between two models (or two bodies of one), with the bound K_a + K_b
    (Krishnamurthy et al. §5). b None: A's own file (pick bodies). motion: B's placement, a 4 x 4
    matrix acting on column vectors (model units), or a (K, 4, 4) array of placements (one answer
    each, the preparation shared). bodies: (body of A, body of B) by index or name; None: every body.

    Returns a Result (a list of them for a (K, 4, 4) motion) with found, distance, bound,
    point_bound, point_a, point_b, face_a, face_b, uv_a, uv_b, intersecting (and intersection, a
    common point), meets_tolerance, uncertified, failure, tolerance, seconds."""
    frames, single = _frames(motion)
    body_a, body_b = ("" if x is None else str(x) for x in bodies)
    answers = _nurbsgl.clearance(a._m, None if b is None else b._m, frames, body_a, body_b, tol, engine,
                                 voxel_stage, accept_partial)
    results = [Result(r) for r in answers]
    return results[0] if single else results


def clash(model, min_clearance=None, tol=1e-5, engine="auto", accept_partial=False, pairs=None):
    """The clash report of an assembly (or any model of several bodies): the clearance of every pair
    of bodies, as nurbsgl.clearance(model, bodies=(i, j)) answers it. Pairs whose bodies' boxes lie
    farther apart than min_clearance (model units; None: every pair computed) are left out. pairs: a
    shard, a list of (i, j); None: every pair i < j.

    Returns a Result with rows (one Result per pair, intersecting pairs first, then by clearance, then
    those left out by their boxes: body_a, body_b, name_a, name_b, box_distance, computed,
    beyond_min_clearance and, when computed, the fields of nurbsgl.clearance), bodies, pairs,
    pairs_computed, pairs_beyond, pairs_beyond_computed, pairs_intersecting, pairs_uncertified,
    seconds, failure ("" when every computed pair is certified)."""
    r = _nurbsgl.clash(model._m, float("inf") if min_clearance is None else float(min_clearance), tol, engine,
                       accept_partial, [] if pairs is None else [(int(i), int(j)) for i, j in pairs])
    r["rows"] = [Result(row) for row in r["rows"]]
    return Result(r)
