"""Distributed against replicated FE bodies: step-loop time and peak memory per rank (issue #13, item 7).

`fracdem_dist_check` (tests/support/distributed_body_check.cpp, built beside the executable) steps
an FE-only steel box of tet4 in two ways, side by side within each repetition:

* replicated: today's `fix fem/body` model: every rank holds the whole body, computes a share of
  the elements, and all-reduces all nodal forces every step;
* distributed: every rank holds one METIS part and sums the forces of shared nodes with its
  neighbouring parts only (NodeExchange).

Reports per variant, body size and rank count the median loop time per step over the
repetitions, the speedup against the same variant at 1 rank, and the largest peak resident memory
of a rank; CSV + PNG.

  python3 bench/distributed_body.py [--exe build/fracdem] [--reps 5] [--cells 26 55] [--np 1 2]

CELLS c gives 12 c^3 tets (26: 2.1e5, 55: 2.0e6). On a machine with more cores, --np 1 2 4 8 16.
Where distributed starts to pay (the default `parallel` by size): --cells 4 6 8 10 13 17 --np 1 2
--name distributed_body_threshold.

  python3 bench/distributed_body.py --memory [--builds before=OLD/fracdem after=build/fracdem]
      [--cells 26] [--np 1 2 4]

measures instead the peak resident memory (VmHWM, as /usr/bin/time reports it) of every rank of
`fix fem/body` itself (tests/integration/inputs/in.distributed, 20 steps, `model elastic`) on a
block of 12 c^3 tets, replicated and distributed, for each build given (files
distributed_body_memory.{csv,png}): set-up (mesh reading, partition, parts) is where a
distributed body's memory goes, which the core loop above does not see.
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))
from harness import mpirun  # noqa: E402  (root and oversubscription flags, as the tests run)


def run(check, np_, cells, steps, mode, model):
    cmd = mpirun(np_) + [check, "tet", str(steps), str(cells), mode, model]
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    m = re.search(r"^dist_time (.*)$", r.stdout, re.M)
    if r.returncode != 0 or not m:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{r.stdout[-2000:]}")
    return dict(kv.split("=", 1) for kv in m.group(1).split())


def peak_memory(exe, np_, wd, parallel):
    """Peak resident memory (MB) of each rank of one fix fem/body run, in rank order."""
    for f in os.listdir(wd):
        if f.startswith("mem."):
            os.remove(os.path.join(wd, f))
    # Each rank under /usr/bin/time, its report in mem.RANK (Open MPI's rank variable).
    wrap = ['sh', '-c', '/usr/bin/time -f %M -o mem.${OMPI_COMM_WORLD_RANK:-0} "$@"', 'sh']
    cmd = mpirun(np_) + wrap + [exe, "-echo", "none", "-in", "in.distributed"]
    variables = dict(dt=1e-7, model="elastic", every=20, thermo=20, steps=20, parallel=parallel)
    for k, v in variables.items():
        cmd += ["-var", k, str(v)]
    r = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1"))
    if r.returncode != 0 or "ERROR" in r.stdout:
        raise SystemExit(f"{' '.join(cmd)} failed in {wd}:\n{r.stdout[-2000:]}")
    return [int(open(os.path.join(wd, f"mem.{k}")).read().split()[-1]) / 1024.0
            for k in range(np_)]


def memory(a):
    import shutil
    import tempfile
    sys.path.insert(0, os.path.join(ROOT, "python"))
    from fracdem import meshgen
    builds = [b.split("=", 1) for b in (a.builds or [f"this={a.exe}"])]
    rows = []
    for cells in a.cells:
        wd = tempfile.mkdtemp(prefix="distributed_memory_")
        for name in ("in.distributed", "in.fe_common"):
            shutil.copy(os.path.join(ROOT, "tests", "integration", "inputs", name), wd)
        X, E, G = meshgen.box_tet_mesh(2 * cells, cells, cells, 0.4, 0.2, 0.2)
        meshgen.write_gmsh22(os.path.join(wd, "block.msh"), X, E, G)
        del X, E, G
        for build, exe in builds:
            for parallel in ("replicated", "distributed"):
                for np_ in a.np:
                    mb = peak_memory(os.path.abspath(exe), np_, wd, parallel)
                    rows.append({"build": build, "variant": parallel,
                                 "elements": 12 * cells ** 3, "np": np_,
                                 "peak_rss_mb_rank0": f"{mb[0]:.1f}",
                                 "peak_rss_mb_other_max": f"{max(mb[1:]):.1f}" if np_ > 1 else "",
                                 "peak_rss_mb_per_rank": " ".join(f"{m:.1f}" for m in mb)})
                    print(rows[-1], flush=True)
        shutil.rmtree(wd, ignore_errors=True)
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, "distributed_body_memory.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {path}")
    plot_memory(rows, os.path.join(a.out, "distributed_body_memory.png"))


def plot_memory(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for build in dict.fromkeys(r["build"] for r in rows):
        for variant, style in (("replicated", ":"), ("distributed", "-")):
            sel = [r for r in rows if r["build"] == build and r["variant"] == variant]
            ax.plot([r["np"] for r in sel], [float(r["peak_rss_mb_rank0"]) for r in sel],
                    "o" + style, label=f"{build}, {variant}, rank 0")
            other = [r for r in sel if r["peak_rss_mb_other_max"]]
            if variant == "distributed" and other:
                ax.plot([r["np"] for r in other], [float(r["peak_rss_mb_other_max"]) for r in other],
                        "s" + style, label=f"{build}, {variant}, other ranks (largest)")
    ax.set(xlabel="ranks", ylabel="peak resident memory of a rank (MB)",
           title=f"fix fem/body, {int(rows[0]['elements']):,} tets")
    ax.set_xticks(sorted({r["np"] for r in rows}))
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--cells", type=int, nargs="+", default=[26, 55])
    p.add_argument("--np", type=int, nargs="+", default=[1, 2])
    p.add_argument("--model", default="elastic", choices=["elastic", "corotational"])
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--name", default="distributed_body", help="stem of the CSV and PNG files")
    p.add_argument("--memory", action="store_true", help="peak memory per rank of fix fem/body")
    p.add_argument("--builds", nargs="+", help="--memory: LABEL=EXE for each build compared")
    a = p.parse_args()
    if a.memory:
        return memory(a)
    check = os.path.join(os.path.dirname(os.path.abspath(a.exe)), "fracdem_dist_check")
    rows = []
    for cells in a.cells:
        # About 2 s of loop per run at 1 rank on the development VM.
        steps = max(10, int(2e7 / (12 * cells**3)))
        samples = {}
        for _ in range(a.reps):  # variants and rank counts in turn: drift hits all alike
            for np_ in a.np:
                for mode in ("time_replicated", "time"):
                    got = run(check, np_, cells, steps, mode, a.model)
                    samples.setdefault((got["mode"], np_), []).append(got)
        for (mode, np_), runs in sorted(samples.items()):
            ms = statistics.median(float(r["ms_per_step"]) for r in runs)
            base = statistics.median(float(r["ms_per_step"]) for r in samples[(mode, a.np[0])])
            rows.append({"variant": mode, "elements": runs[0]["elements"], "np": np_,
                         "steps": steps, "ms_per_step_median": f"{ms:.3f}",
                         "speedup": f"{base / ms * a.np[0]:.3f}",
                         "peak_rss_mb_max": max(float(r["peak_rss_mb_max"]) for r in runs)})
            print(rows[-1])
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, a.name + ".csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {path}")
    plot(rows, os.path.join(a.out, a.name + ".png"))


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(15, 4))
    for variant in ("replicated", "distributed"):
        for elements in sorted({r["elements"] for r in rows}, key=int):
            sel = [r for r in rows if r["variant"] == variant and r["elements"] == elements]
            label = f"{variant}, {int(elements):.1e} tets"
            ax1.plot([r["np"] for r in sel], [float(r["speedup"]) for r in sel], "o-", label=label)
            ax2.plot([r["np"] for r in sel], [r["peak_rss_mb_max"] for r in sel], "o-", label=label)
    nps = sorted({r["np"] for r in rows})
    ax1.plot(nps, nps, "k:", label="ideal")
    ax1.set(xlabel="ranks", ylabel="speedup of the step loop", title="FE-only body")
    ax2.set(xlabel="ranks", ylabel="peak memory of a rank (MB)", title="memory")
    ax1.legend(fontsize=7)
    ax2.legend(fontsize=7)
    # Where distributed pays: replicated / distributed step time at the largest rank count.
    top = max(nps)
    ratio = {}
    for r in rows:
        if r["np"] == top:
            ratio.setdefault(int(r["elements"]), {})[r["variant"]] = float(r["ms_per_step_median"])
    sizes = sorted(e for e, v in ratio.items() if len(v) == 2)
    ax3.semilogx(sizes, [ratio[e]["replicated"] / ratio[e]["distributed"] for e in sizes], "o-")
    ax3.axhline(1.0, color="k", ls=":")
    ax3.set(xlabel="elements", ylabel=f"replicated / distributed step time at {top} ranks",
            title="where distributed pays")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
