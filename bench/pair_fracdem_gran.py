"""pair_style fracdem/gran against the host's pair gran on the stock packing scene
(bench/inputs/in.stock_packing: 6 876 spheres of 2.5 mm radius inserted at 0.5 m/s into a box,
falling and settling), one rank. Variants, run in turn within each repetition:

  gran     pair_style gran model hertz tangential history (the stock script)
  fracdem  pair_style fracdem/gran model hertz tangential history (no bridge)
  bridge   the same plus 'bridge willett' (water: 0.072 N/m, 0.35 rad, 1 % of a particle's
           volume per bridge, wet yes)

  python3 bench/pair_fracdem_gran.py [--reps 5] [--steps 10000] [--out bench/results]

Figures: medians over repetitions of LIGGGHTS' "Loop time" and "Pair time", the per-repetition
ratio fracdem / gran of both (goal: within 5 %), and the bridge pass's cost: the extra pair time
of 'bridge' over 'fracdem' per step and per pair closer than S_c at the end of the run (a count
from the final positions; pairs that never touched are bridged too, by wet yes). The wet run's
physics differ (clumps), so its extra time also holds the change in contacts.
Writes pair_fracdem_gran.csv (one row per run), pair_fracdem_gran.md and pair_fracdem_gran.png.
"""
import argparse
import csv
import os
import re
import shutil
import statistics
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))

import harness  # noqa: E402

GRAN = "pair_style      gran model hertz tangential history"
VOLUME = 0.01 * 4 / 3 * np.pi * 0.0025 ** 3
THETA = 0.35
RUPTURE = (1 + THETA / 2) * VOLUME ** (1 / 3)
VARIANTS = {
    "gran": GRAN,
    "fracdem": "pair_style      fracdem/gran model hertz tangential history",
    "bridge": "pair_style      fracdem/gran model hertz tangential history bridge willett "
              f"surface_tension 0.072 contact_angle {THETA} volume {VOLUME:.6g}",
}


def close_pairs(path):
    """Pairs with surface gap below S_c in a 'dump custom ... x y z radius' file (last frame)."""
    with open(path) as f:
        lines = f.read().splitlines()
    start = max(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    a = np.array([[float(w) for w in l.split()] for l in lines[start:]])
    x, r = a[:, :3], a[:, 3]
    count = 0
    for i in range(len(a) - 1):
        gap = np.linalg.norm(x[i + 1:] - x[i], axis=1) - r[i + 1:] - r[i]
        count += int(np.count_nonzero(gap < RUPTURE))
    return count


def run_variant(exe, name, steps):
    wd = tempfile.mkdtemp(prefix=f"bench_pair_{name}_")
    with open(os.path.join(HERE, "inputs", "in.stock_packing")) as f:
        text = f.read()
    assert GRAN in text
    text = text.replace(GRAN, VARIANTS[name])
    text += f"write_dump all custom final.dump x y z radius\n"
    with open(os.path.join(wd, "in.scene"), "w") as f:
        f.write(text)
    out = harness.run(exe, "in.scene", workdir=wd, variables=dict(steps=steps))
    loop = float(re.search(r"^Loop time of (\S+)", out, re.M).group(1))
    pair = float(re.search(r"^Pair\s+time \(%\) = (\S+)", out, re.M).group(1))
    pairs = close_pairs(os.path.join(wd, "final.dump")) if name == "bridge" else 0
    shutil.rmtree(wd, ignore_errors=True)
    return loop, pair, pairs


def summary(rows, steps):
    def med(name, key):
        return statistics.median(r[key] for r in rows if r["variant"] == name)

    def ratio(key):
        by = {}
        for r in rows:
            by.setdefault(r["repetition"], {})[r["variant"]] = r[key]
        return statistics.median(v["fracdem"] / v["gran"] for v in by.values())

    extra = med("bridge", "pair_s") - med("fracdem", "pair_s")
    bridges = med("bridge", "close_pairs")
    lines = ["| variant | loop time (s, median) | pair time (s, median) |", "|---|---|---|"]
    lines += [f"| {n} | {med(n, 'loop_s'):.3f} | {med(n, 'pair_s'):.3f} |" for n in VARIANTS]
    lines += ["", f"fracdem / gran: loop time {ratio('loop_s'):.4f}, pair time "
                  f"{ratio('pair_s'):.4f} (median of per-repetition ratios; goal <= 1.05).",
              f"bridge - fracdem pair time: {extra:.3f} s over {steps} steps, {bridges:.0f} pairs "
              f"closer than S_c = {RUPTURE:.3g} m at the end: "
              f"{1e9 * extra / (steps * max(bridges, 1)):.0f} ns per bridged pair and step."]
    return "\n".join(lines) + "\n"


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for k, key in enumerate(("loop_s", "pair_s")):
        vals = [statistics.median(r[key] for r in rows if r["variant"] == n) for n in VARIANTS]
        ax.bar(np.arange(len(VARIANTS)) + 0.4 * k, vals, 0.4, label=key.replace("_s", " time"))
    ax.set_xticks(np.arange(len(VARIANTS)) + 0.2, list(VARIANTS))
    ax.set_ylabel("s (median)")
    ax.set_title("stock packing scene, 1 rank")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    p = harness.parser()
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--steps", type=int, default=10000)
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    args = harness.parse_args(p)
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for rep in range(args.reps):
        for name in VARIANTS:
            loop, pair, pairs = run_variant(args.exe, name, args.steps)
            rows.append(dict(variant=name, repetition=rep, loop_s=loop, pair_s=pair,
                             close_pairs=pairs))
            print(f"  {name:8s} rep {rep}: loop {loop:.3f} s, pair {pair:.3f} s")
    with open(os.path.join(args.out, "pair_fracdem_gran.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    text = summary(rows, args.steps)
    with open(os.path.join(args.out, "pair_fracdem_gran.md"), "w") as f:
        f.write(text)
    plot(rows, os.path.join(args.out, "pair_fracdem_gran.png"))
    print(text)


if __name__ == "__main__":
    main()
