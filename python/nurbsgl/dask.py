"""Scale-out on Dask distributed: a scan's points, or an assembly's body pairs, spread over the
workers of a Dask cluster (a real scheduler and workers: `dask-scheduler`, `dask-worker`, or a
LocalCluster on this machine).

    from distributed import Client
    import nurbsgl.dask
    client = Client("tcp://scheduler:8786")
    r = nurbsgl.dask.distance(client, "/shared/part.step", points, tol=1e-4)

Each worker process loads the model once and keeps it with its prepared query (the disk cache makes
the preparation of a second worker on the same machine a read), and one GL context (a worker may be
given its GPU by NURBSGL_EGL_DEVICE in its environment). The model's path must name the same file
on every worker. Answers equal those of one process bit for bit: every point's answer depends on
that point alone, and the engine ("auto") is resolved the same on like workers.

The clash report of an assembly shards its body pairs the same way (nurbsgl.dask.clash).

Command line:
    python3 -m nurbsgl.dask distance [--scheduler ADDRESS] MODEL POINTS.npy -o OUT.npy [--tol T]
Without --scheduler it starts a LocalCluster on this machine.
"""

import math
import os
import warnings

import numpy as np

# Per worker process: the models read so far, by path (each keeps its prepared queries).
_models = {}

# The per-point fields of a distance answer, in the order of the structured array the command
# line writes.
POINT_FIELDS = (("distance", "f8", ()), ("bound", "f8", ()), ("point_bound", "f8", ()), ("point", "f8", (3,)),
                ("face", "i4", ()), ("uv", "f8", (2,)), ("meets_tolerance", "?", ()), ("limited_by_file", "?", ()),
                ("file_gap", "f8", ()), ("gap_face", "i4", ()))


def _model(path):
    import nurbsgl
    m = _models.get(path)
    if m is None:
        m = _models[path] = nurbsgl.load(path)
    return m


def _distance_chunk(path, points, tol, engine, accept_partial):
    r = _model(path).distance(points, tol=tol, engine=engine, accept_partial=accept_partial)
    out = {name: r[name] for name, _, _ in POINT_FIELDS}
    out["reasons"] = r.reasons
    out["tolerance"] = r.tolerance
    out["engine"] = r.engine
    return out


def _chunk_size(client, n):
    workers = max(1, len(client.scheduler_info().get("workers", {})))
    # A few chunks per worker (a slow or lost worker holds back little), each a pass of at least
    # 65536 points (the batched query's pass, below which llvmpipe's tiles go idle) and at most
    # 2^20 (24 MB of points: each task carries its own, see distance).
    return min(max(65536, math.ceil(n / (4 * workers))), 1 << 20)


def distance(client, model_path, points, tol=1e-5, engine="auto", accept_partial=False, chunk=None, strict=False):
    """nurbsgl.Model.distance of `points` ((N, 3) float64) on the cluster of `client`, in chunks of
    `chunk` points (default: four chunks per worker, from 65536 to 2^20 points each). Returns a
    nurbsgl.Result with the arrays of Model.distance (distance, bound, point_bound, point, face, uv,
    meets_tolerance, limited_by_file, file_gap, gap_face, reasons) in input order, tolerance, engine,
    and failure ("" when every answer is certified: meets the tolerance, or, unless strict, is over it
    only by the file's precision). A worker lost in the middle is replaced and its chunks run again; an
    error of a chunk (an unreadable model: nurbsgl.ReadError) is raised here, the other chunks
    cancelled."""
    import nurbsgl
    points = np.ascontiguousarray(points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points: an (N, 3) array is wanted, not shape {points.shape}")
    path = os.path.abspath(str(model_path))
    n = len(points)
    size = chunk or _chunk_size(client, n)
    starts = list(range(0, n, size)) or [0]
    # Each task carries its points (not scattered ahead): a worker lost in the middle takes no
    # input with it, and its tasks run again elsewhere.
    with warnings.catch_warnings():  # a chunk of more than a megabyte in the graph is meant so
        warnings.filterwarnings("ignore", message="Large object of size")
        futures = [client.submit(_distance_chunk, path, points[s:s + size], tol, engine, accept_partial,
                                 pure=False) for s in starts]
    try:
        results = client.gather(futures)
    except BaseException:
        client.cancel(futures)
        raise
    fields = {name: np.concatenate([r[name] for r in results]) for name, _, _ in POINT_FIELDS}
    fields["reasons"] = [reason for r in results for reason in r["reasons"]]
    fields["tolerance"] = results[0]["tolerance"]
    fields["engine"] = results[0]["engine"]
    certified = fields["meets_tolerance"] | (fields["limited_by_file"] & (not strict))
    failing = int(np.count_nonzero(~certified))
    fields["failure"] = "" if failing == 0 else f"{failing} of {n} answers do not meet the tolerance"
    fields["chunks"] = len(starts)
    return nurbsgl.Result(fields)


def _body_count(path):
    return len(_model(path).bodies)


def _clash_shard(path, pairs, min_clearance, tol, engine, accept_partial):
    import nurbsgl
    r = nurbsgl.clash(_model(path), min_clearance, tol, engine, accept_partial, pairs)
    return [dict(row.__dict__) for row in r.rows]


def _row_key(row):
    """The clash report's order (queries/distance/clash.cpp): intersecting pairs first, then by
    clearance, then the pairs left out by box distance; ties by body indices."""
    computed = row["computed"]
    return (not computed, computed and not row["intersecting"],
            row["distance"] if computed else row["box_distance"], row["body_a"], row["body_b"])


def clash(client, model_path, min_clearance=None, tol=1e-5, engine="auto", accept_partial=False, shards=None):
    """nurbsgl.clash of the model's bodies with the pairs sharded over the cluster (default: four
    shards per worker); the rows merged in the report's order, the counts and failure as
    nurbsgl.clash gives them. Each worker loads the model once."""
    import nurbsgl
    path = os.path.abspath(str(model_path))
    bodies = client.submit(_body_count, path, pure=False).result()
    pairs = [(i, j) for i in range(bodies) for j in range(i + 1, bodies)]
    if bodies < 2:  # the library's refusal, with its message
        return nurbsgl.clash(nurbsgl.load(path), min_clearance, tol, engine, accept_partial)
    workers = max(1, len(client.scheduler_info().get("workers", {})))
    count = max(1, min(len(pairs), shards or 4 * workers))
    parts = [pairs[k::count] for k in range(count)]
    futures = [client.submit(_clash_shard, path, part, min_clearance, tol, engine, accept_partial, pure=False)
               for part in parts]
    try:
        rows = [row for shard in client.gather(futures) for row in shard]
    except BaseException:
        client.cancel(futures)
        raise
    rows.sort(key=_row_key)
    computed = [r for r in rows if r["computed"]]
    failing = [r for r in computed if not r["meets_tolerance"] and not r["limited_by_file"]]
    lines = "".join(f"\n  bodies {r['body_a']} ({r['name_a']}) and {r['body_b']} ({r['name_b']}): {r['failure']}"
                    for r in failing)
    return nurbsgl.Result({
        "rows": [nurbsgl.Result(r) for r in rows], "bodies": bodies, "pairs": len(rows),
        "pairs_computed": len(computed), "pairs_beyond": len(rows) - len(computed),
        "pairs_beyond_computed": sum(1 for r in computed if r["beyond_min_clearance"]),
        "pairs_intersecting": sum(1 for r in computed if r["intersecting"]),
        "pairs_uncertified": len(failing), "shards": count,
        "pairs_limited_by_file": sum(1 for r in computed if r["limited_by_file"]),
        "failure": f"{len(failing)} of {len(computed)} computed pairs not certified:{lines}" if failing else ""})


def as_records(result):
    """The per-point arrays of a distance Result as one structured array (the command line's .npy)."""
    out = np.empty(len(result.distance), dtype=[(name, kind, shape) for name, kind, shape in POINT_FIELDS])
    for name, _, _ in POINT_FIELDS:
        out[name] = result[name]
    return out


def _read_points(path):
    if str(path).endswith(".npy"):
        return np.load(path, allow_pickle=False)
    return np.loadtxt(path, dtype=np.float64, delimiter=None, comments="#", ndmin=2)


def main(argv=None):
    """The command line (see the module's doc). Exit codes as nurbsgl's: 0 every answer meets the
    tolerance, 1 one does not, 2 bad command line or input."""
    import argparse
    import sys

    import nurbsgl
    from distributed import Client, LocalCluster

    parser = argparse.ArgumentParser(prog="python3 -m nurbsgl.dask",
                                     description="nurbsgl queries spread over a Dask cluster")
    sub = parser.add_subparsers(dest="command", required=True)
    d = sub.add_parser("distance", help="minimum distance from many points to a model")
    d.add_argument("model", help="IGES or STEP file (the same path on every worker)")
    d.add_argument("points", help="(N, 3) float64 .npy, or a text file of x y z rows")
    d.add_argument("-o", "--output", required=True, help="the answers as a structured .npy (fields: "
                   + ", ".join(name for name, _, _ in POINT_FIELDS) + ")")
    d.add_argument("--scheduler", help="address of a running scheduler (tcp://host:8786); default: a "
                   "LocalCluster on this machine")
    d.add_argument("--workers", type=int, default=0, help="LocalCluster: worker processes (default: one per core)")
    d.add_argument("--tol", type=float, default=1e-5, help="bound of every answer, relative to the model size")
    d.add_argument("--engine", choices=("auto", "cpu", "gpu"), default="auto")
    d.add_argument("--accept-partial", action="store_true",
                   help="answers on a model whose reader dropped faces may be certified")
    d.add_argument("--chunk", type=int, default=0, help="points per task (default: four tasks per worker)")
    args = parser.parse_args(argv)
    if not (0.0 < args.tol < 1.0):
        parser.error(f"--tol {args.tol}: between 0 and 1 (relative to the model size)")
    try:
        points = _read_points(args.points)
    except (OSError, ValueError) as e:
        print(f"nurbsgl.dask: {args.points}: {e}", file=sys.stderr)
        return 2
    cluster = None
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers or None, threads_per_worker=1, processes=True)
        client = Client(cluster)
    try:
        r = distance(client, args.model, points, tol=args.tol, engine=args.engine,
                     accept_partial=args.accept_partial, chunk=args.chunk or None)
    except (nurbsgl.ReadError, nurbsgl.RequestError, ValueError) as e:
        print(f"nurbsgl.dask: {e}", file=sys.stderr)
        return 2
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    out = str(args.output)
    tmp = out + ".tmp.npy"
    np.save(tmp, as_records(r))
    os.replace(tmp, out)
    met = int(np.count_nonzero(r.meets_tolerance))
    print(f"{len(points)} points in {r.chunks} chunks on the cluster: {met} meet the tolerance "
          f"{r.tolerance:.6g}; answers in {out}", file=sys.stderr)
    if r.failure:
        print(f"nurbsgl.dask: not certified: {r.failure}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    import sys

    # Run as nurbsgl.dask, not as __main__: the tasks must name their functions by the package's
    # module (a function of __main__ travels to the workers by value, with a copy of _models each time).
    from nurbsgl.dask import main as package_main

    sys.exit(package_main())
