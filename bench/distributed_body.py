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


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--cells", type=int, nargs="+", default=[26, 55])
    p.add_argument("--np", type=int, nargs="+", default=[1, 2])
    p.add_argument("--model", default="elastic", choices=["elastic", "corotational"])
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    a = p.parse_args()
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
    path = os.path.join(a.out, "distributed_body.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {path}")
    plot(rows, os.path.join(a.out, "distributed_body.png"))


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
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
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
