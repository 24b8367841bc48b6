"""Load-balance analysis: fix balance/graph CSV, end-of-run statistics of LIGGGHTS/LAMMPS logs,
run summaries, tables in the form of the paper's Tables 1-3 and per-rank work plots (its Fig. 4)."""
import re

import numpy as np
import pandas as pd

from . import plots

_STAT = re.compile(r"^(Nlocal|Nghost|Neighs):\s+(\S+)\s+ave\s+(\S+)\s+max\s+(\S+)\s+min")
_BREAKDOWN = re.compile(r"^(Pair|Neigh|Comm|Modify|Output|Other)\s*\|\s*(\S+)\s*\|\s*(\S+)\s*\|\s*(\S+)\s*\|")
_LOOP = re.compile(r"^Loop time of\s+(\S+)\s+on\s+(\d+)\s+procs")


def read_balance_csv(path):
    """The `out` file of fix balance/graph as a DataFrame (one row per check)."""
    return pd.read_csv(path)


def rank_columns(df):
    """Names of the per-rank CPU work columns, in rank order."""
    cols = [c for c in df.columns if c.startswith("cpu_rank")]
    return sorted(cols, key=lambda c: int(c[len("cpu_rank"):]))


def run_stats(text):
    """End-of-run statistics of the last run in a LIGGGHTS or LAMMPS log/stdout text.

    Returns a dict with loop_s, nprocs, and for each of Nlocal/Nghost/Neighs the ave/max/min,
    plus (LAMMPS only) the min/avg/max time of each section of the MPI task timing breakdown.
    """
    out = {}
    for line in text.splitlines():
        m = _LOOP.match(line)
        if m:
            out = {"loop_s": float(m.group(1)), "nprocs": int(m.group(2))}  # last run wins
            continue
        m = _STAT.match(line.strip())
        if m:
            name = m.group(1).lower()
            out[f"{name}_ave"], out[f"{name}_max"], out[f"{name}_min"] = map(float, m.group(2, 3, 4))
            continue
        m = _BREAKDOWN.match(line.strip())
        if m and m.group(2) != "":
            try:
                vals = [float(v) for v in m.group(2, 3, 4)]
            except ValueError:
                continue
            name = m.group(1).lower()
            out[f"{name}_min_s"], out[f"{name}_avg_s"], out[f"{name}_max_s"] = vals
    return out


def summarize_balance(df, nprocs, loop_s=None):
    """Run summary from a fix balance/graph CSV.

    measured_B: time average of max/avg per-rank CPU work, each row (one check interval)
    weighted by its number of steps (the run is taken to start at step 0);
    speedup: work-model speedup sum(W)/max(W) over the whole run, sum over intervals of
    (avg * nprocs) / sum of max; partition_share: partition + migration time over loop time.
    """
    d = {}
    rows = df[df["cpu_work_avg"] > 0]
    steps = df["step"].diff().fillna(df["step"].iloc[0] if len(df) else 0).clip(lower=1)
    w = steps[rows.index]
    d["measured_B"] = (float((rows["measured_imbalance"] * w).sum() / w.sum())
                       if len(rows) else 1.0)
    d["model_B"] = float((df["imbalance"] * steps).sum() / steps.sum())
    tot_max = float(rows["cpu_work_max"].sum())
    d["speedup"] = float(rows["cpu_work_avg"].sum() * nprocs / tot_max) if tot_max > 0 else 1.0
    d["repartitions"] = int(df["repartitioned"].sum())
    d["migrated"] = float(df["migrated"].sum())
    d["ghosts_per_rank"] = float((df["ghosts_total"] / nprocs).mean())
    d["ghost_max_over_avg"] = float(df["ghost_max_over_avg"].mean())
    seconds = float(df["partition_seconds"].sum()) + float(df["migration_seconds_total"].iloc[-1])
    d["partition_seconds"] = seconds
    if loop_s:
        d["partition_share"] = seconds / loop_s
    cols = rank_columns(df)
    if cols:
        d["work_per_rank"] = [float(df[c].sum()) for c in cols]
    return d


def markdown_table(rows, columns, floatfmt="{:.3g}"):
    """A list of dicts as a Markdown table with the given columns (missing values left empty)."""
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for r in rows:
        cells = []
        for c in columns:
            v = r.get(c, "")
            cells.append(floatfmt.format(v) if isinstance(v, float) else str(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot_rank_work(runs, out=None, title="Per-rank work"):
    """Fig. 4-style grouped bars: total CPU work of each rank for each method.

    runs: dict method -> list of per-rank work values (seconds)."""
    _, fig, ax = plots.new_figure(True, figsize=(7, 4))
    methods = list(runs)
    nranks = max(len(v) for v in runs.values())
    width = 0.8 / max(len(methods), 1)
    for k, m in enumerate(methods):
        w = np.asarray(runs[m], dtype=float)
        ax.bar(np.arange(len(w)) + k * width, w, width, label=m)
    ax.set_xticks(np.arange(nranks) + 0.4 - width / 2)
    ax.set_xticklabels([str(r) for r in range(nranks)])
    ax.set_xlabel("rank")
    ax.set_ylabel("CPU time of particle work (s)")
    return plots.finish_figure(fig, ax, out, title=title, close=True)


def plot_imbalance_history(series, out=None, title="Imbalance over the run"):
    """B over time: series is dict method -> (steps, B values)."""
    _, fig, ax = plots.new_figure(True, figsize=(7, 4))
    for m, (steps, b) in series.items():
        ax.plot(steps, b, marker=".", label=m)
    ax.set_xlabel("step")
    ax.set_ylabel("max/avg per-rank CPU work")
    ax.axhline(1.0, color="k", lw=0.5)
    return plots.finish_figure(fig, ax, out, title=title, close=True)
