"""Work-model speedup of the partitioned body-body contact (the paper's Table 3: a priori vs a
posteriori graph model at 2, 4 and 6 ranks) on a pile of tri3 blocks.

Scene: 40 plane-strain tri3 blocks (8 rows of 5, 4 x 4 elements of 10 mm, 8 mm apart: farther
than the search reaches, so the candidates grow where the blocks meet) thrown down at 2 + 0.5 r
m/s (row r, bottom up, so that each row catches the one below: a pile grows from the floor while
the upper rows still fly) onto a fixed quad4 floor, time step 10 us; all contact_bodies yes, one
contact scene. Every run is at one rank with `contact_balance MODEL parts K every 1`:
the partition of K parts is made exactly as K ranks make it (the ctest
tests/integration/test_contact_partition.py shows that np 3 and 'parts 3' at np 1 give the same
per-part work), every node is still evaluated on the rank, and its work (facet tests + contacts,
counted) is booked to its part. Per step the parallel work is that of the busiest part, so

    work-model speedup = sum over steps of the total work / sum over steps of the largest part's

(counts: the same on any machine; repartitioning and communication are not in it, the paper's
measured speedups include them).

    python3 bench/contact_partition.py [--exe build/fracdem] [--steps 3000]
        [--csv bench/results/contact_partition.csv] [--png bench/results/contact_partition.png]

`--scene ceramic` runs the paper's own Example 3 instead: examples/ceramic_target/in.ceramic_target
(six axisymmetric bodies, the rod at 1325 m/s, its cracking tiles and eroding metals; the input as
shipped, with `contact_balance MODEL thresh B every 1 parts K file balance.csv` added to the rod,
the first contact body) for --steps steps (default 8000, the example's run), written to
bench/results/contact_partition_ceramic.{csv,png}.
"""
import argparse
import csv
import glob
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))
from fracdem import scenes  # noqa: E402

# Table 3 of the paper (Example 3, the layered ceramic target): speedup at 2, 4, 6 processors.
PAPER = {"a_priori": {2: 1.82, 4: 3.52, 6: 4.60}, "a_posteriori": {2: 1.86, 4: 3.63, 6: 5.33}}
ROWS, COLS, SIZE, GAP = 8, 5, 0.04, 0.008


def write_case(wd, model, parts, steps, thresh):
    lines, _ = scenes.block_pile(
        wd, ROWS, COLS, lambda r: 2.0 + 0.5 * r, floor_cells=24, box_top=0.45, size=SIZE, gap=GAP,
        floor_balance=f"{model} thresh {thresh} every 1 parts {parts}", name="b{r}_{c}")
    lines += ["thermo 500", f"run {steps}"]
    with open(os.path.join(wd, "in.pile"), "w") as f:
        f.write("\n".join(lines) + "\n")


def write_ceramic(wd, model, parts, steps, thresh):
    """The example as shipped, its rod (the first contact body) holding the scene's balance."""
    src = os.path.join(ROOT, "examples", "ceramic_target")
    for f in glob.glob(os.path.join(src, "*.msh")) + [os.path.join(src, "in.ceramic_target")]:
        shutil.copy(f, wd)
    path = os.path.join(wd, "in.ceramic_target")
    text = open(path).read()
    head = "fix rod all fem/body file rod.msh"
    if text.count(head) != 1:
        sys.exit(f"{path}: expected one '{head}' line")
    text = text.replace(head, f"{head} contact_balance {model} thresh {thresh} every 1 "
                        f"parts {parts} file balance.csv")
    open(path, "w").write(text)
    return ["-var", "steps", str(steps), "-var", "v", "1325"]


def speedup(path, parts):
    rows = list(csv.DictReader(open(path)))
    total = sum(sum(float(r[f"work_{p}"]) for p in range(parts)) for r in rows)
    busiest = sum(max(float(r[f"work_{p}"]) for p in range(parts)) for r in rows)
    b = [float(r["imbalance"]) for r in rows if sum(float(r[f"work_{p}"]) for p in range(parts))]
    contacts = sum(sum(float(r[f"contacts_{p}"]) for p in range(parts)) for r in rows)
    return {"speedup": total / busiest, "mean_B": sum(b) / len(b), "max_B": max(b),
            "repartitions": int(rows[-1]["repartitions"]), "searches": int(rows[-1]["searches"]),
            "work": int(total), "contacts": int(contacts)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    ap.add_argument("--scene", choices=("pile", "ceramic"), default="pile")
    ap.add_argument("--steps", type=int, default=None)
    ap.add_argument("--thresh", type=float, default=1.05)
    ap.add_argument("--csv", default=None)
    ap.add_argument("--png", default=None)
    a = ap.parse_args()
    ceramic = a.scene == "ceramic"
    a.steps = a.steps or (8000 if ceramic else 3000)
    name = "contact_partition" + ("_ceramic" if ceramic else "")
    a.csv = a.csv or os.path.join(HERE, "results", name + ".csv")
    a.png = a.png or os.path.join(HERE, "results", name + ".png")
    results = []
    for model in ("a_priori", "a_posteriori"):
        for parts in (2, 4, 6):
            wd = tempfile.mkdtemp(prefix=f"contact_partition_{model}_{parts}_")
            if ceramic:
                extra, script = write_ceramic(wd, model, parts, a.steps, a.thresh), "in.ceramic_target"
            else:
                write_case(wd, model, parts, a.steps, a.thresh)
                extra, script = [], "in.pile"
            r = subprocess.run([a.exe, "-echo", "none", "-in", script] + extra, cwd=wd, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
            if r.returncode != 0 or "ERROR" in r.stdout:
                sys.exit(f"{model} parts {parts} failed in {wd}:\n{r.stdout[-3000:]}")
            row = {"model": model, "parts": parts, **speedup(os.path.join(wd, "balance.csv"),
                                                            parts),
                   "paper": PAPER[model][parts]}
            print(row, flush=True)
            results.append(row)
    os.makedirs(os.path.dirname(a.csv), exist_ok=True)
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(results[0]))
        w.writeheader()
        for row in results:
            w.writerow({k: (f"{v:.4f}" if isinstance(v, float) else v) for k, v in row.items()})
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    ranks = [2, 4, 6]
    ax.plot(ranks, ranks, "k:", label="ideal")
    for model, colour in (("a_priori", "tab:blue"), ("a_posteriori", "tab:red")):
        ours = [r["speedup"] for r in results if r["model"] == model]
        ax.plot(ranks, ours, "o-", color=colour, label=f"{model} (work model, this scene)")
        ax.plot(ranks, [PAPER[model][k] for k in ranks], "s--", color=colour, alpha=0.6,
                label=f"{model} (paper Table 3, measured)")
    ax.set_xlabel("ranks (parts)")
    ax.set_ylabel("speedup of the contact work")
    ax.set_title("ceramic target (Example 3), 1325 m/s, " if ceramic else
                 f"{ROWS * COLS} tri3 blocks piling up, ", fontsize=9, loc="left")
    ax.set_title(f"{a.steps} steps", fontsize=9, loc="right")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)
    print("wrote", a.csv, a.png)


if __name__ == "__main__":
    main()
