"""Optional plotting and the generated Markdown of the experiments: docs/benchmarks.md (machine, date,
command, tables; a section per experiment script, rewritten by each run) and REPRODUCTION.md (the
papers' reported figures beside ours and the command). Shared by distance_tables.py,
tessellation_tables.py and raycast_tables.py."""
import csv
import datetime
import math
import os
import platform
import re

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HEADER = ("_Written by the experiment scripts (scripts/experiments.sh, scripts/tessellation_experiments.sh, "
          "scripts/raycast_experiments.sh), a section each, on every run; do not edit by hand._\n\n")
TITLES = {"benchmarks.md": "Benchmarks", "REPRODUCTION.md": "Reproduction: the papers' figures beside ours"}


def pyplot():
    """matplotlib.pyplot on the Agg backend, or None when matplotlib is not installed (plots skipped)."""
    try:
        import matplotlib
    except ImportError:
        return None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def no_blank(rows):
    """rows with NaN floats written as '' (a column the peer did not fill stays empty)."""
    return [{k: "" if isinstance(v, float) and math.isnan(v) else v for k, v in r.items()} for r in rows]


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def markdown_table(rows, columns=None):
    """A Markdown table of rows (dicts), the given columns (default all), columns empty (or 'n/a': a peer's
    verdict without the peer) on every row left out; floats to 6 significant digits."""
    columns = [c for c in (columns or list(dict.fromkeys(k for r in rows for k in r)))
               if any(r.get(c, "") not in ("", "n/a") for r in rows)]
    cell = lambda v: (f"{v:.0f}" if abs(v) >= 1e6 else f"{v:.6g}") if isinstance(v, float) else str(v).replace("|", "/")
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(cell(r.get(c, "")) for c in columns) + " |" for r in rows]
    return "\n".join(lines)


def read_csv(path):
    """Rows of a CSV written by an experiment, numbers as floats; [] when the file is absent."""
    if not os.path.exists(path):
        return []
    def num(v):
        try:
            return float(v)
        except ValueError:
            return v
    with open(path, newline="") as f:
        return [{k: num(v) for k, v in r.items()} for r in csv.DictReader(f)]


def _replace_section(path, title, body):
    """Writes path with the section '## title' replaced by body (appended when new), header first."""
    text = open(path).read() if os.path.exists(path) else ""
    sections = re.split(r"(?m)^(?=## )", text[len(HEADER):] if text.startswith(HEADER) else text)
    head, rest = (sections[0], sections[1:]) if sections and not sections[0].startswith("## ") else ("", sections)
    rest = [s for s in rest if not s.startswith(f"## {title}\n")] + [f"## {title}\n\n{body.strip()}\n\n"]
    with open(path, "w") as f:
        f.write(HEADER + (head or f"# {TITLES[os.path.basename(path)]}\n\n") + "".join(rest))


def write_benchmarks(title, command, info, tables, left_out, root=ROOT):
    """Rewrites the section `title` of docs/benchmarks.md: machine (CPU model, cores, the GL renderer of
    `nurbsgl gpu-info --json` in info), date, command, what was left out, and tables ((caption, markdown))."""
    body = [f"- machine: {cpu_model()}, {os.cpu_count()} cores; GL: {info.get('renderer', '?')} "
            f"({info.get('backend', '?')})",
            f"- date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC",
            f"- command: `{command}`"]
    if left_out:
        body.append(f"- left out: {left_out}")
    for caption, table in tables:
        body += ["", f"{caption}", "", table]
    _replace_section(os.path.join(root, "docs", "benchmarks.md"), title, "\n".join(body))


def write_reproduction(title, rows, command, root=ROOT):
    """Rewrites the section `title` of REPRODUCTION.md; rows: (what, paper's figure with its table or
    figure number, ours)."""
    body = [f"Command: `{command}`", "", "| figure | paper | ours |", "|---|---|---|"]
    body += [f"| {what} | {paper} | {ours} |" for what, paper, ours in rows]
    _replace_section(os.path.join(root, "REPRODUCTION.md"), title, "\n".join(body))
