"""The histogram of a scan's deviation from its model (PNG, matplotlib), with the share of points
within each given tolerance, as inspection software draws it. Used by `nurbsgl distance
--histogram` (which runs this file with python3) and from Python:

    r = model.distance(points, tol=1e-5, signed=True)
    nurbsgl.histogram.plot(r.signed_distance, "deviation.png", within=[0.05, 0.1], unit=model.unit)
"""

import os
import sys


def plot(deviation, path, within=(), unit="mm", signed=True, title="Deviation from the model"):
    """Writes the histogram of `deviation` (NaN where no answer: left out) to `path` (PNG, written
    to a temporary file and renamed). `within`: tolerances drawn as bands, each with its share of
    points. Returns the shares, one per tolerance."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    d = np.asarray(deviation, dtype=np.float64)
    d = d[np.isfinite(d)]
    within = sorted(float(w) for w in within)
    shares = [float(np.count_nonzero(np.abs(d) <= w)) / max(len(d), 1) for w in within]
    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=120)
    bins = min(200, max(10, int(np.sqrt(max(len(d), 1)))))
    ax.hist(d, bins=bins, color="#4a6fa5", edgecolor="none")
    colours = ["#2ca02c", "#ff7f0e", "#d62728", "#9467bd"]
    for k, (w, share) in enumerate(zip(within, shares)):
        lo = -w if signed else 0.0
        ax.axvspan(lo, w, color=colours[k % len(colours)], alpha=0.12)
        ax.axvline(w, color=colours[k % len(colours)], lw=1)
        if signed:
            ax.axvline(-w, color=colours[k % len(colours)], lw=1)
        ax.plot([], [], color=colours[k % len(colours)], label=f"within {w:g} {unit}: {100 * share:.2f} %")
    ax.set_xlabel(f"{'signed ' if signed else ''}deviation ({unit}){', negative inside' if signed else ''}")
    ax.set_ylabel("points")
    stats = (f"{len(d)} points; min {d.min():.4g}, max {d.max():.4g}, mean {d.mean():.4g}, "
             f"rms {np.sqrt(np.mean(d * d)):.4g} {unit}") if len(d) else "no points"
    ax.set_title(f"{title}\n{stats}", fontsize=10)
    if within:
        ax.legend(loc="upper right", fontsize=9)
    fig.tight_layout()
    path = str(path)
    tmp = path + ".tmp.png"
    fig.savefig(tmp)
    plt.close(fig)
    os.replace(tmp, path)
    return shares


def main(argv):
    """python3 histogram.py DEVIATIONS.f64 OUT.png UNIT SIGNED(0|1) [W,W...]: the deviations as raw
    little-endian float64 (what `nurbsgl distance --histogram` hands over)."""
    import numpy as np
    data, out, unit, signed = argv[0], argv[1], argv[2], argv[3] == "1"
    within = [float(w) for w in argv[4].split(",")] if len(argv) > 4 and argv[4] else []
    plot(np.fromfile(data, dtype="<f8"), out, within=within, unit=unit, signed=signed)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except ImportError as e:
        sys.stderr.write(f"{e}: the histogram needs matplotlib and numpy (apt install python3-matplotlib)\n")
        sys.exit(3)
