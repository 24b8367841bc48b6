"""fix balance/graph across write_restart / read_restart: partitions and costs survive.

The settling bed (inputs/in.balance_bed, restart file at step 100) run straight for 200 steps
and continued from the file for 100 (inputs/in.balance_bed_continue), at 3 ranks
(oversubscribed), repartitioned at every check (thresh 1.0, every 20):
1. The continued run's balance.csv rows equal the straight run's rows after step 100, every
   column but the timing ones (partition and migration seconds, measured CPU work), for
   cells + METIS and `cost calibrated` (the calibrated costs are timed at start-up, so equal rows
   need the costs from the file), particles + METIS (`cells 0`), zoltan-rcb and zoltan-hsfc:
   the owners (cells or particles), the costs, the schedule and the fix's outputs are restored,
   and no start-up check runs at the continued run's first step.
2. A continuation on another rank count (2) cannot use the file's owners: it says so, starts
   from the host's bricks (a start-up check at its first step), and keeps every particle.
"""
import os
import tempfile

import harness as h

args = h.parse_args()
TIMING = ("partition_seconds", "migration_seconds_total", "measured_imbalance", "cpu_work_max",
          "cpu_work_avg")
SETTINGS = dict(every=20, thresh=1.0)


def compared(csv):
    keys = [k for k in csv if k not in TIMING and not k.startswith("cpu_rank")]
    return keys, [tuple(csv[k][r] for k in keys) for r in range(len(csv["step"]))]


def straight_and_continued(cost, cover, np_cont=3):
    wd = tempfile.mkdtemp(prefix="balance_restart_")
    h.copy_inputs(["in.balance_bed", "in.balance_bed_continue"], wd)
    v = dict(SETTINGS, cost=cost, cover=cover)
    h.run(args.exe, "in.balance_bed", 3, wd, dict(v, steps=200, restart_every=100))
    straight = h.read_csv(os.path.join(wd, "balance.csv"))
    text = h.run(args.exe, "in.balance_bed_continue", np_cont, wd, dict(v, steps=100))
    return straight, h.read_csv(os.path.join(wd, "balance.csv")), text


for cost, cover in (("calibrated", ""), ("counts", "partitioner metis cells 0"),
                    ("counts", "partitioner zoltan-rcb"), ("calibrated", "partitioner zoltan-hsfc")):
    label = f"cost {cost} {cover or 'cells (METIS)'}"
    straight, cont, text = straight_and_continued(cost, cover)
    keys, rows_s = compared(straight)
    _, rows_c = compared(cont)
    after = [r for r in rows_s if r[0] > 100]
    h.check(cont["step"][0] == 120,
            f"{label}: the continued run's first check is the regular one at step 120 (got "
            f"{cont['step'][0]:.0f}): the owners came from the file, no start-up check")
    reps = sum(1 for r in straight["repartitioned"] if r)
    h.check(reps >= 5, f"{label}: the straight run repartitioned {reps} times")
    same = rows_c == after
    diff = "" if same else "\n" + "\n".join(f"  straight {a}\n  continued {b}"
                                            for a, b in zip(after, rows_c) if a != b)
    h.check(same, f"{label}: the continued run's {len(rows_c)} rows equal the straight run's "
                  f"after step 100 in {', '.join(keys)}{diff}")
    nrep = h.column(h.thermo_blocks(text), "nrep")[-1]
    h.check(nrep == reps, f"{label}: the repartition count carries on ({nrep:.0f} = {reps})")

straight, cont, text = straight_and_continued("counts", "partitioner zoltan-rcb", np_cont=2)
h.check("do not fit this run" in text and cont["step"][0] == 101,
        "a continuation on 2 ranks of a 3-rank file warns and starts from the host's bricks "
        f"(a start-up check at step {cont['step'][0]:.0f})")
blocks = h.thermo_blocks(text)
n, s1 = h.column(blocks, "Atoms"), h.column(blocks, "sumid")
h.check(all(a == n[0] and s == n[0] * (n[0] + 1) / 2 for a, s in zip(n, s1)),
        f"the 2-rank continuation keeps every particle once ({n[0]:.0f} at every output)")
