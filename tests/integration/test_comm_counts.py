"""Communication counts of graph ownership, exact and machine-independent (issue #11, item 5).

The settling bed runs with the PMPI counter (libfracdem_mpicount.so beside the executable,
LD_PRELOADed) under the stock z-slabs and under graph ownership, each twice (N1 and N2 steps): the
difference of the two runs is exactly the traffic of steps N1..N2, set-up excluded. Asserted per
rank and step:

* one message per partner and communication: the messages per step from a rank to one
  destination (worst rank and destination) at most 1.1 x the stock slabs' figure. Why this and
  not "messages per rank at most the stock slabs'": a z-slab has two neighbours by construction,
  a graph part touches more ranks (how many is issue #11's item 3, compact sub-domains); what the
  communicator owes is the stock cost per neighbour: one message per forward communication (the
  swap-by-swap loop sent one per periodic image, 3-9 per partner and step). The 10 % covers the
  graph run's reneighbour messages (cover cells and atoms, two per partner and reneighbour,
  against the stock count Sendrecv plus atoms per swap) and the repartitions' migration;
* against LAMMPS rcb measured the same way when Debian's `lmp` is installed (not installed here:
  the test says so and skips that part);
* collectives issued by the project's own code outside the balance checks (the communicator:
  one per exchange) at most 0.2 per step; the fix's own collectives (at checks only) are reported;
* the graph run's thermo equals the stock run's over the short run (1e-8 relative), and no
  particle is lost;
* at 8 ranks, `partitioner rcb` (compact parts, issue #11 item 3) has no more forward-comm
  partners (average and maximum) and no more partners of any message than the METIS partition it
  replaces, on cells one cutoff wide, with every repartition's predicted B and the mean B of the
  cost model at the later checks within the threshold.
"""
import os
import shutil
import sys
import tempfile
import time

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "tests", "support"))
import mpicount  # noqa: E402

args = h.parse_args()
LIB = os.path.join(os.path.dirname(os.path.abspath(args.exe)), "libfracdem_mpicount.so")
if not os.path.isfile(LIB):
    h.check(False, f"the PMPI counter {LIB} exists (built with the fracdem target's CMake tree)")
SHORT, LONG = 100, 400
BED = dict(every=100, thresh=1.05, cost="counts", model="aposteriori")


def counted(np_, tag, steps, balance, extra=""):
    wd = tempfile.mkdtemp(prefix=f"comm_counts_{tag}_{np_}_")
    h.copy_inputs(["in.balance_bed"], wd)
    text, ranks = mpicount.run(args.exe, "in.balance_bed", np_, wd, LIB, f"{tag}{steps}",
                               dict(BED, balance=balance, steps=steps, cover=extra))
    return h.thermo_blocks(text), ranks, wd


def measure(np_, tag, balance, extra=""):
    short_thermo, short, _ = counted(np_, tag, SHORT, balance, extra)
    long_thermo, long_, wd = counted(np_, tag, LONG, balance, extra)
    diffs = mpicount.difference(long_, short)
    s = mpicount.summarise(diffs, LONG - SHORT)
    s["csv"] = h.read_csv(os.path.join(wd, "balance.csv")) if balance else None
    return short_thermo, long_thermo, s, diffs


def fix_collectives_per_check(diffs):
    """Collectives of fix balance/graph per check in the window (every rank issues the same)."""
    exe = os.path.basename(diffs[0]["exe"])
    n = sum(c for (m, caller, _, cat), (c, _) in diffs[0]["sites"].items()
            if cat == "coll" and m == exe and mpicount.owner_class(caller) == "FixBalanceGraph")
    return n / ((LONG - SHORT) / BED["every"])


def check_ranks(np_):
    t0 = time.time()
    stock_short, _, stock, _ = measure(np_, "stock", 0)
    graph_short, graph_long, graph, diffs = measure(np_, "graph", 1)
    print(f"stock slabs: {mpicount.format_summary(stock)}")
    print(f"graph:       {mpicount.format_summary(graph)}")
    for line in mpicount.site_lines(diffs, LONG - SHORT, 12):
        print("    graph site:", line)

    reps = h.column(graph_long, "nrep")[-1]
    h.check(reps >= 1, f"np={np_}: graph ownership is on ({reps:.0f} repartitions)")
    h.check(graph["dest_rate_max"] <= 1.1 * stock["dest_rate_max"],
            f"np={np_}: one message per partner and communication: messages/step to one partner "
            f"(worst rank and partner) {graph['dest_rate_max']:.3f} <= 1.1 x stock slabs' "
            f"{stock['dest_rate_max']:.3f} (graph: messages/rank/step {graph['msgs_avg']:.2f} avg, "
            f"{graph['msgs_max']:.2f} max, per-step partners {graph['step_partners_avg']:.2f} avg, "
            f"{graph['step_partners_max']} max; stock: {stock['msgs_avg']:.2f} avg, "
            f"{stock['msgs_max']:.2f} max, {stock['step_partners_max']} partners)")
    if shutil.which("lmp") is None:
        print(f"note: np={np_}: Debian `lmp` is not installed: the comparison with LAMMPS rcb "
              f"(messages and partners at most rcb's) is skipped; bench/comm_counts.py runs it "
              f"where lmp exists")
    comm_coll = graph["project_coll"].get("CommGraph", 0.0) + graph["project_coll"].get("other", 0)
    h.check(comm_coll <= 0.2,
            f"np={np_}: collectives from the project's code outside balance checks "
            f"{comm_coll:.3f}/step <= 0.2 (fix balance/graph: {fix_collectives_per_check(diffs):.1f}"
            f" per check, every {BED['every']} steps)")

    w = 0.0
    for name in ("KinEng", "rke", "sumid", "Atoms"):
        for x, y in zip(h.column(stock_short, name), h.column(graph_short, name)):
            w = max(w, h.rel_diff(x, y))
    h.check(w < 1e-8, f"np={np_}: graph thermo equals the stock decomposition over {SHORT} steps "
                      f"(worst rel. diff {w:.1e})")
    n = h.column(graph_long, "Atoms")
    h.check(min(n) == max(n), f"np={np_}: no particle lost over {LONG} steps")
    return time.time() - t0


def check_compact(np_):
    """`partitioner rcb` (issue #11, item 3) against the METIS partition it replaces: no more
    forward-comm partners, no more partners of any message, and balance kept: every repartition's
    predicted B within the threshold, and the mean B of the cost model at the checks after the
    first repartition too (a single check may drift above it: that check repartitions)."""
    # Cells one cutoff wide (7 x 7 x 16 on this small bed): with the default two cutoffs there
    # are 72 cells for 8 ranks, too coarse for any partitioner to reach the 5 % threshold.
    _, _, metis, _ = measure(np_, "metis", 1, "cells 1")
    _, rcb_long, rcb, _ = measure(np_, "rcb", 1, "partitioner rcb cells 1")
    print(f"metis: {mpicount.format_summary(metis)}")
    print(f"rcb:   {mpicount.format_summary(rcb)}")
    h.check(h.column(rcb_long, "nrep")[-1] >= 1, f"np={np_}: partitioner rcb repartitioned")
    h.check(rcb["step_partners_avg"] <= metis["step_partners_avg"] + 1e-9 and
            rcb["step_partners_max"] <= metis["step_partners_max"],
            f"np={np_}: partitioner rcb has no more forward-comm partners than metis: avg "
            f"{rcb['step_partners_avg']:.2f} (max {rcb['step_partners_max']}) <= "
            f"{metis['step_partners_avg']:.2f} (max {metis['step_partners_max']})")
    h.check(rcb["partners_avg"] <= metis["partners_avg"] + 1e-9,
            f"np={np_}: partitioner rcb has no more partners of any message than metis: "
            f"{rcb['partners_avg']:.2f} <= {metis['partners_avg']:.2f}")
    for name, s in (("metis", metis), ("rcb", rcb)):
        csv = s["csv"]
        pred = [p for p, r in zip(csv["predicted_imbalance"], csv["repartitioned"]) if r]
        print(f"{name}: B at checks {[round(b, 3) for b in csv['imbalance']]}, predicted "
              f"{[round(p, 3) for p in pred]}")
    csv_r, csv_m = rcb["csv"], metis["csv"]
    pred = [p for p, r in zip(csv_r["predicted_imbalance"], csv_r["repartitioned"]) if r]
    h.check(max(pred) <= BED["thresh"],
            f"np={np_}: partitioner rcb balances the cost model within the threshold at every "
            f"repartition (predicted B max {max(pred):.3f} <= {BED['thresh']})")
    later_r, later_m = csv_r["imbalance"][1:], csv_m["imbalance"][1:]
    mean_r, mean_m = sum(later_r) / len(later_r), sum(later_m) / len(later_m)
    h.check(mean_r <= BED["thresh"],
            f"np={np_}: balance kept: mean B of the cost model at the checks after the first "
            f"repartition {mean_r:.3f} <= {BED['thresh']} (metis {mean_m:.3f}; a check above the "
            f"threshold repartitions)")

elapsed = check_ranks(4)
check_compact(8)
# 16 ranks oversubscribed: only where the 4-rank case shows it fits the time budget (~4x longer).
if elapsed * 4 < 120:
    check_ranks(16)
else:
    print(f"note: 16 ranks skipped: 4 ranks took {elapsed:.0f} s, 16 would exceed 2 minutes here")
