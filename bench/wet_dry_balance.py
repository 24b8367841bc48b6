"""Balancing a box whose left half is wet (liquid bridges of pair_style fracdem/gran) and right
half dry (tests/integration/inputs/in.wet_dry_box, yz 29.4 mm: about 4 000 spheres), 2 ranks,
fix balance/graph with the contacts and bridges the pair counts ('counts pair') against its own
recount over the neighbour list ('counts recount', which sees no bridges), --reps times each.

  python3 bench/wet_dry_balance.py [--reps 3] [--cost calibrated] [--out bench/results]

The measure is the imbalance of measured particle work (max/avg over the ranks of the CPU time of
neighbour build, pair and post-force work between checks: the 'measured_imbalance' column of the
fix's report) after the first repartition, median over the checks and then over the
repetitions; goal: below the fix's threshold (1.05) with the pair's counts, higher with the
recount. Writes wet_dry_balance_COST.csv (one row per check) and wet_dry_balance_COST.md.
"""
import csv
import os
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))

import harness  # noqa: E402

THRESH = 1.05


def run(exe, counts, cost, steps, every):
    wd = tempfile.mkdtemp(prefix=f"bench_wet_dry_{counts}_")
    harness.copy_inputs(["in.wet_dry_box"], wd)
    harness.run(exe, "in.wet_dry_box", np_=2, workdir=wd,
                variables=dict(counts=counts, cost=cost, thresh=THRESH, every=every, steps=steps,
                               yz=0.0294))
    return harness.read_csv(os.path.join(wd, "balance.csv"))


def main():
    p = harness.parser()
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--cost", default="calibrated")
    p.add_argument("--steps", type=int, default=3000)
    p.add_argument("--every", type=int, default=250)
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    args = harness.parse_args(p)
    os.makedirs(args.out, exist_ok=True)
    rows, summary = [], {}
    for rep in range(args.reps):
        for counts in ("pair", "recount"):
            c = run(args.exe, counts, args.cost, args.steps, args.every)
            for k in range(len(c["step"])):
                rows.append(dict(counts=counts, repetition=rep, step=int(c["step"][k]),
                                 modelled_imbalance=c["imbalance"][k],
                                 repartitioned=int(c["repartitioned"][k]),
                                 measured_imbalance=c["measured_imbalance"][k]))
            # The start check has no measured time; the first interval runs on the stock split.
            after = c["measured_imbalance"][2:]
            summary.setdefault(counts, []).append(statistics.median(after))
            print(f"  {counts:8s} rep {rep}: measured imbalance after balancing "
                  f"{summary[counts][-1]:.3f} (median over {len(after)} checks), "
                  f"{int(sum(c['repartitioned']))} repartitions", flush=True)
    with open(os.path.join(args.out, f"wet_dry_balance_{args.cost}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    lines = [f"2 ranks, cost {args.cost}, thresh {THRESH}, {args.steps} steps, checks every "
             f"{args.every}; measured imbalance (max/avg CPU time of particle work) after the "
             "first repartition, median over checks, per repetition:", "",
             "| counts | repetitions | median |", "|---|---|---|"]
    for counts, vals in summary.items():
        lines.append(f"| {counts} | {', '.join(f'{v:.3f}' for v in vals)} | "
                     f"{statistics.median(vals):.3f} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, f"wet_dry_balance_{args.cost}.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
