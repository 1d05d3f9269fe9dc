"""Optional plotting and the generated Markdown of the experiments: docs/benchmarks.md (a section per
experiment script, a table per experiment with the machine, date and command of the run that wrote
it) and REPRODUCTION.md (the papers' reported figures beside ours and the command, a row per figure).
A run replaces only the tables and rows it measured. Shared by distance_tables.py,
tessellation_tables.py and raycast_tables.py."""
import csv
import datetime
import math
import os
import platform
import re
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HEADER = ("_Written by the experiment scripts (scripts/experiments.sh, scripts/tessellation_experiments.sh, "
          "scripts/raycast_experiments.sh, experiments/real_models.py): each run replaces the tables and rows it "
          "measured; do not edit by hand._\n\n")
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


def run_measured(cmd):
    """Runs cmd; returns (exit code, stdout, stderr, wall seconds, peak resident MB from os.wait4). The
    output goes through files and the child is reaped by os.wait4, whose ru_maxrss is the child's
    (kB on Linux); it also counts the caller's resident memory, which the child's start copies."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t0 = time.monotonic()
        p = subprocess.Popen(cmd, stdout=out, stderr=err, text=True)
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.monotonic() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0), err.seek(0)
        return p.returncode, out.read(), err.read(), wall, usage.ru_maxrss / 1024.0


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


def _split(text, level):
    """(head, [(title, body)]) of text cut at its headings of the given level ('## ', '### ')."""
    parts = re.split(rf"(?m)^(?={re.escape(level)})", text)
    head, rest = (parts[0], parts[1:]) if parts and not parts[0].startswith(level) else ("", parts)
    return head, [(p.split("\n", 1)[0][len(level):], p.split("\n", 1)[1] if "\n" in p else "") for p in rest]


def _replace_section(path, title, body):
    """Writes path with the section '## title' replaced by body (appended when new), header first."""
    text = open(path).read() if os.path.exists(path) else ""
    if text.startswith("_Written by the experiment scripts"):  # this header, or an earlier wording of it
        text = text.split("\n\n", 1)[1] if "\n\n" in text else ""
    head, sections = _split(text, "## ")
    sections = [(t, b) for t, b in sections if t != title] + [(title, f"\n{body.strip()}\n\n")]
    with open(path, "w") as f:
        f.write(HEADER + (head or f"# {TITLES[os.path.basename(path)]}\n\n") +
                "".join(f"## {t}\n{b}" for t, b in sections))


def _section(path, title):
    """The body of '## title' in path, or ''."""
    text = open(path).read() if os.path.exists(path) else ""
    return next((b for t, b in _split(text, "## ")[1] if t == title), "")


def write_benchmarks(title, command, info, tables, left_out, root=ROOT):
    """Writes the tables ((caption, markdown)) of this run into the section `title` of
    docs/benchmarks.md, each under its caption with the machine (CPU model, cores, the GL renderer of
    `nurbsgl gpu-info --json` in info), date, command and what was left out. Tables of earlier runs
    whose captions this run did not write stay, so a run of one experiment, or on fewer models, does
    not erase the others (each table names the run that wrote it)."""
    path = os.path.join(root, "docs", "benchmarks.md")
    command = command.strip()
    run = [f"- machine: {cpu_model()}, {os.cpu_count()} cores; GL: {info.get('renderer', '?')} "
           f"({info.get('backend', '?')})",
           f"- date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC",
           f"- command: `{command}`"]
    if left_out:
        run.append(f"- left out: {left_out}")
    new = {caption.rstrip(":"): "\n".join(run + ["", table]) for caption, table in tables}
    _, old = _split(_section(path, title), "### ")
    kept = [(t, b.strip()) for t, b in old if t not in new]
    body = "\n\n".join(f"### {t}\n\n{b}" for t, b in kept + list(new.items()))
    _replace_section(path, title, body)


def write_reproduction(title, rows, command, root=ROOT):
    """Writes the rows ((what, the paper's figure with its table or figure number, ours)) of this run
    into the section `title` of REPRODUCTION.md, each with its command; rows of earlier runs for
    figures this run did not measure stay."""
    path = os.path.join(root, "REPRODUCTION.md")
    old = []
    for line in _section(path, title).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        if line.startswith("| ") and len(cells) == 4 and cells[0] not in ("figure", "---"):
            old.append(tuple(cells))
    new = [(what, paper, ours, f"`{command.strip()}`") for what, paper, ours in rows]
    measured = {r[0] for r in new}
    body = ["| figure | paper | ours | command |", "|---|---|---|---|"]
    body += [f"| {' | '.join(r)} |" for r in [r for r in old if r[0] not in measured] + new]
    _replace_section(path, title, "\n".join(body))


HEADLINE_BEGIN = "<!-- headline figures: written by the experiment scripts (experiments/report.py) -->"
HEADLINE_END = "<!-- end of headline figures -->"
HEADLINE_COLUMNS = ["query", "model (faces)", "nurbsgl", "peer, same run", "ratio",
                    "command"]


def write_headline(query, model, ours, peer, ratio, command, root=ROOT):
    """Sets the row `query` of the README's table of headline figures (between HEADLINE_BEGIN and
    HEADLINE_END): one current figure per query against its peer (OpenCASCADE, the mesh pipeline),
    from the same run, with the command that measured it; the other rows stay."""
    path = os.path.join(root, "README.md")
    text = open(path).read()
    if HEADLINE_BEGIN not in text or HEADLINE_END not in text:
        return
    head, rest = text.split(HEADLINE_BEGIN, 1)
    block, tail = rest.split(HEADLINE_END, 1)
    rows = []
    for line in block.strip().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        if line.startswith("| ") and len(cells) == len(HEADLINE_COLUMNS) and cells[0] not in ("query", "---"):
            rows.append(cells)
    new = [query, model, ours, peer or "not run", ratio or "", f"`{command.strip()}`"]
    rows = [new if r[0] == query else r for r in rows] if any(r[0] == query for r in rows) else rows + [new]
    table = ["| " + " | ".join(HEADLINE_COLUMNS) + " |", "|" + "---|" * len(HEADLINE_COLUMNS)]
    table += ["| " + " | ".join(r) + " |" for r in rows]
    with open(path, "w") as f:
        f.write(head + HEADLINE_BEGIN + "\n" + "\n".join(table) + "\n" + HEADLINE_END + tail)
