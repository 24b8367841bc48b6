"""Graph against geometric partitioners in fix balance/graph, side by side on one scene: METIS on
cells and on particles (gathered), PT-Scotch and Zoltan's graph / hypergraph (distributed), the
gathered compact `rcb` on cells, and Zoltan's RCB / RIB / HSFC on the particles (distributed),
with the stock slabs as the floor. All weigh the same a posteriori costs (`cost counts`, so the
work figures are exact).

Per method and rank count:
* wall clock: the loop time of `--reps` repetitions, run interleaved (repetition k of every
  method before repetition k + 1 of any), and the median over repetitions of the ratio of the
  method's loop time to the reference's (`metis cells`) in the same repetition: machine noise
  that lasts a repetition cancels. Meaningful only where ranks <= cores, and on a shared
  machine only as a ratio;
* the work balance from the fix's CSV (model B: max/avg of the cost model, step-weighted mean
  over the checks; repartitions; particles migrated; share of the loop spent partitioning and
  migrating);
* exact counts over a window of steps (PMPI counter, two runs of different lengths, repartitioned
  at every check: thresh 1.0): messages,
  bytes and partners per rank and step, and the bytes per rank and repartition that fracdem's
  balance code and the partitioning library hand to gathering collectives (gather, allgather,
  broadcast, scatter): the whole graph for the gathered partitioners, metadata for the others.

    python3 bench/partitioner_compare.py [--scene settle|hopper|dragline] [--ranks 2]
        [--reps 3] [--steps N] [--window N1 N2] [--methods NAME ...]

Writes bench/results/partitioners_<scene>.csv (one row per method and rank count) and .png.
"""
import argparse
import csv
import os
import shutil
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))
sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
sys.path.insert(0, HERE)

import balance_compare  # noqa: E402
import counted_runs  # noqa: E402
import harness  # noqa: E402
import mpicount  # noqa: E402
from fracdem import balance  # noqa: E402

REFERENCE = "metis cells"
METHODS = {  # name -> (partitioner words, kind)
    "stock slabs": ("metis", "none"),
    "metis cells": ("metis", "graph, gathered"),
    "metis particles": ("metis cells 0", "graph, gathered"),
    "ptscotch": ("ptscotch", "graph, distributed"),
    "zoltan-graph": ("zoltan-graph", "graph, distributed"),
    "zoltan-phg": ("zoltan-phg", "hypergraph, distributed"),
    "rcb cells": ("rcb", "geometric, gathered"),
    "zoltan-rcb": ("zoltan-rcb", "geometric, distributed"),
    "zoltan-rib": ("zoltan-rib", "geometric, distributed"),
    "zoltan-hsfc": ("zoltan-hsfc", "geometric, distributed"),
}
SCENES = {  # scene -> (input, mesh writer, steps, check every, counted window)
    "settle": ("in.settle_fracdem", None, 1000, 100, (200, 500)),
    "hopper": ("in.hopper_fracdem", "hopper", 3000, 250, (1000, 2000)),
    "dragline": ("in.balance_dragline", "bucket", 3000, 200, (1000, 2000)),
}
GATHERING = ("MPI_Gather", "MPI_Gatherv", "MPI_Allgather", "MPI_Allgatherv", "MPI_Bcast",
             "MPI_Scatter", "MPI_Scatterv")
ENGINES = ("zoltan", "scotch", "metis")


def variables(name, steps, every):
    words, _ = METHODS[name]
    v = dict(steps=steps, every=every, thresh=1.05, model="aposteriori", cost="counts",
             partitioner=words, balance=1)
    if name == "stock slabs":
        v["thresh"] = "1e30"
    return v


def timed_run(exe, script, mesh, np_, v):
    wd = tempfile.mkdtemp(prefix="bench_partitioners_")
    shutil.copy(balance_compare.input_path(script), wd)
    if mesh:
        balance_compare.write_mesh(mesh, wd)
    text = harness.run(exe, script, np_=np_, workdir=wd, variables=v, timeout=1800)
    stats = balance.run_stats(text)
    df = balance.read_balance_csv(os.path.join(wd, "balance.csv"))
    s = balance.summarize_balance(df, np_, stats["loop_s"])
    shutil.rmtree(wd, ignore_errors=True)
    return stats["loop_s"], s


def gathering_bytes(diff):
    """Bytes one rank hands to gathering collectives (sent and received) from fracdem's balance
    code and the partitioning libraries."""
    exe = os.path.basename(diff["exe"])
    total = 0
    for (module, caller, func, cat), (_count, nbytes) in diff["sites"].items():
        own = module == exe and mpicount.owner_class(caller) == "FixBalanceGraph"
        engine = any(e in module for e in ENGINES)
        if (own or engine) and func in GATHERING and cat in ("coll", "crecv"):
            total += nbytes
    return total


def counted(exe, script, mesh, np_, v, window):
    lib = os.path.join(os.path.dirname(os.path.abspath(exe)), "libfracdem_mpicount.so")
    wd = tempfile.mkdtemp(prefix="bench_partitioners_counted_")
    if mesh:
        balance_compare.write_mesh(mesh, wd)
    w = counted_runs.window(exe, lib, balance_compare.input_path(script), np_, window, v, wd)
    rows = list(csv.DictReader(open(os.path.join(wd, "balance.csv"))))
    reps = sum(int(r["repartitioned"]) for r in rows if window[0] < int(r["step"]) <= window[1])
    s = w.summary
    out = dict(msgs_rank_step=s["msgs_avg"], msgs_rank_step_max=s["msgs_max"],
               bytes_rank_step=s["bytes_avg"], bytes_rank_step_max=s["bytes_max"],
               partners=s["partners_avg"], partners_max=s["partners_max"],
               step_partners=s["step_partners_avg"], step_partners_max=s["step_partners_max"],
               window_repartitions=reps)
    if reps:
        out["gather_bytes_per_repartition_max"] = max(gathering_bytes(d) for d in w.diffs) / reps
    shutil.rmtree(wd, ignore_errors=True)
    return out


def plot(rows, path, title):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [("wall_ratio", f"loop time / {REFERENCE}'s (median of reps)"),
              ("model_B", "model B (step-weighted mean over checks)"),
              ("bytes_rank_step", "bytes / rank / step (exact)"),
              ("gather_bytes_per_repartition_max", "gathering-collective bytes / repartition, "
                                                   "worst rank (exact)")]
    fig, axes = plt.subplots(1, len(panels), figsize=(18, 4.8))
    names = [r["method"] for r in rows]
    colours = ["tab:gray" if "none" in r["kind"] else "tab:blue" if "graph" in r["kind"]
               else "tab:orange" for r in rows]
    for ax, (key, label) in zip(axes, panels):
        ys = [r.get(key) or 0.0 for r in rows]
        ax.bar(range(len(rows)), ys, color=colours)
        ax.set_xticks(range(len(rows)))
        ax.set_xticklabels(names, rotation=60, ha="right", fontsize=7)
        ax.set_title(label, fontsize=9)
        if key == "gather_bytes_per_repartition_max":
            ax.set_yscale("symlog", linthresh=100)
        if key in ("wall_ratio", "model_B"):
            ax.axhline(1.0, color="k", lw=0.6)
    fig.suptitle(title + " (blue: graph, orange: geometric, grey: stock slabs)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    ap.add_argument("--scene", choices=sorted(SCENES), default="settle")
    ap.add_argument("--ranks", type=int, nargs="+", default=[2])
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--steps", type=int, default=None)
    ap.add_argument("--window", type=int, nargs=2, default=None)
    ap.add_argument("--methods", nargs="+", default=list(METHODS), choices=list(METHODS))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    script, mesh, steps, every, window = SCENES[a.scene]
    steps, window = a.steps or steps, tuple(a.window or window)
    methods = [m for m in METHODS if m in a.methods]
    if REFERENCE not in methods:
        methods.insert(0, REFERENCE)
    cores = os.cpu_count() or 1
    rows = []
    for np_ in a.ranks:
        loops = {m: [] for m in methods}
        balance_of = {}
        for _ in range(a.reps):
            for m in methods:
                loop, s = timed_run(a.exe, script, mesh, np_, variables(m, steps, every))
                loops[m].append(loop)
                balance_of[m] = s
        for m in methods:
            ratios = [x / r for x, r in zip(loops[m], loops[REFERENCE])]
            s = balance_of[m]
            row = dict(scene=a.scene, method=m, kind=METHODS[m][1], ranks=np_, reps=a.reps,
                       steps=steps, loop_s=statistics.median(loops[m]),
                       wall_ratio=statistics.median(ratios), wall_ratio_min=min(ratios),
                       wall_ratio_max=max(ratios), model_B=s["model_B"],
                       speedup=s["speedup"], repartitions=s["repartitions"],
                       migrated=s["migrated"], partition_share=s.get("partition_share"),
                       ghosts_per_rank=s["ghosts_per_rank"],
                       wall_clock_valid=np_ <= cores)
            # Counted repartitioning at every check (thresh 1.0; the stock slabs never): the
            # traffic of a repartition is in every check of the window.
            cv = dict(variables(m, window[1], every), thresh="1e30" if m == "stock slabs" else 1.0)
            row.update(counted(a.exe, script, mesh, np_, cv, window))
            rows.append(row)
            print({k: (round(v, 4) if isinstance(v, float) else v) for k, v in row.items()},
                  flush=True)
    os.makedirs(a.out, exist_ok=True)
    base = os.path.join(a.out, f"partitioners_{a.scene}")
    cols = list(dict.fromkeys(k for r in rows for k in r))
    with open(base + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        w.writerows(rows)
    last = [r for r in rows if r["ranks"] == a.ranks[-1]]
    plot(last, base + ".png", f"{a.scene}, {a.ranks[-1]} ranks, {steps} steps, "
                              f"counts over steps {window[0]}-{window[1]}")
    print(balance.markdown_table(rows, ["method", "kind", "ranks", "wall_ratio", "wall_ratio_min",
                                        "wall_ratio_max", "loop_s",
                                        "model_B", "repartitions", "migrated", "partition_share",
                                        "ghosts_per_rank", "msgs_rank_step", "bytes_rank_step",
                                        "step_partners",
                                        "gather_bytes_per_repartition_max"]))


if __name__ == "__main__":
    main()
