"""Body-body contact at scale: twelve plane-strain tri3 blocks (3 rows of 4, 8 mm apart, farther
than the search reaches) thrown down at 3, 5 and 7 m/s (row by row, so that the rows catch each
other) onto a fixed quad4 floor,
all with contact_bodies yes: one contact scene, one search over all surfaces, its work split
among the ranks by the graph partitioner (contact_balance, docs/fix_fem_body.md).
Asserted, for np 2 and 3 (a posteriori model, thresh 1.01, checks every 20 steps) against np 1:
  * every body's kinetic energy, contact work, momentum and contact force agree within 1e-10 of
    the column's scale (harness.worst_scaled);
  * every candidate pair is evaluated exactly once over all ranks: the per-rank facet tests and
    contacts of the contact_balance file sum, check by check, to the np 1 counts;
  * the work is shared (no rank has less than half the busiest one's), the run repartitions by
    the recorded work (logged), and each repartition's predicted imbalance is below the trigger;
  * np 1 with 'contact_balance ... parts 3' (the work model of bench/contact_partition.py) books
    exactly the per-part work and repartitions of np 3.
np 3 with the a priori model (partitioned after every search) agrees with np 1 as well.
The bodies carry bulk viscosity so that their element work is replicated (not split among the
ranks, whose summation order would differ by round-off that the contacts' on/off switching
amplifies, see test_body_contact): the ranks then differ only in how the contact forces are
summed.
The run stops at step 340, about 100 steps after the first contacts: a pile of colliding blocks
is chaotic (node-to-facet penalty contacts switch facets at corners), so any difference grows
without bound: in the same pile with the blocks 1 mm apart, changing one block's initial speed
by 1e-12 relative at np 1 gave contact-force differences of 1e-4 of their scale 140 steps after
the first contacts and O(1) 20 steps later; the ranks' different summation order of the contact
forces (round-off) starts the same growth (here from step ~360).
"""
import os
import sys
import tempfile

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import scenes  # noqa: E402

args = h.parse_args()

ROWS, COLS, SIZE, GAP = 3, 4, 0.04, 0.008
SPEEDS = (3.0, 5.0, 7.0)  # per row, bottom up: each row catches the one below
STEPS, THERMO = 340, 20


def write_case(wd, balance):
    lines, names = scenes.block_pile(wd, ROWS, COLS, lambda r: SPEEDS[r], floor_cells=20,
                                     box_top=0.3, size=SIZE, gap=GAP, floor_balance=balance,
                                     extra=" bulk_viscosity 0.06 1.2")
    cols = []
    for n in names:
        cols += [f"f_{n}[1]", f"f_{n}[4]", f"f_{n}[8]", f"f_{n}[9]", f"f_{n}[13]", f"f_{n}[14]"]
    lines += ["thermo_style custom step " + " ".join(cols), "thermo_modify format float %.15g",
              f"thermo {THERMO}", f"run {STEPS}"]
    with open(os.path.join(wd, "in.pile"), "w") as f:
        f.write("\n".join(lines) + "\n")


def run(np_, balance):
    wd = tempfile.mkdtemp(prefix=f"contact_partition_{np_}_")
    write_case(wd, balance)
    out = h.run(args.exe, "in.pile", np_=np_, workdir=wd)
    runs = h.thermo_blocks(out)
    cols = {name: h.column(runs, name) for name in runs[-1][0] if name != "Step"}
    h.check(len(cols) == 6 * (1 + ROWS * COLS), f"np {np_}: thermo of every body")
    logs = [os.path.join(wd, f) for f in os.listdir(wd) if f.startswith("log.")]
    log = "".join(open(p).read() for p in logs)  # the repartition lines go to the log file only
    return cols, h.read_csv(os.path.join(wd, "balance.csv")), log


def per_part(csv, what):
    """Per check: the sum over the parts of the column group `what` (tests, contacts)."""
    keys = [k for k in csv if k.startswith(what + "_")]
    return [sum(csv[k][i] for k in keys) for i in range(len(csv["step"]))]


posteriori = "a_posteriori thresh 1.01 every 20"
ref, ref_rows, _ = run(1, posteriori)
h.check(max(per_part(ref_rows, "contacts")) > 100, "np 1: the blocks pile up (contacts counted)")
h.check(all(abs(b - 1) < 1e-12 for b in ref_rows["imbalance"]), "np 1: one part, B = 1")
model_parts = {}
for np_, balance in ((2, posteriori), (3, posteriori), (4, posteriori), (3, "a_priori thresh 1.01 every 20")):
    cols, rows, out = run(np_, balance)
    worst, where = h.worst_scaled(ref, cols)
    h.check(worst < 1e-10, f"np {np_} ({balance.split()[0]}): every body's columns within 1e-10 "
                           f"of np 1 ({worst:.1e}, {where})")
    for what in ("tests", "contacts"):
        a, b = per_part(ref_rows, what), per_part(rows, what)
        h.check(a == b, f"np {np_}: the ranks' {what} add up to np 1's at every check "
                        f"({int(sum(b))} in all)")
    busy = [int(sum(rows[f"work_{p}"])) for p in range(np_)]
    h.check(min(busy) > 0.5 * max(busy), f"np {np_}: the ranks share the work ({busy})")
    reps = int(rows["repartitions"][-1])
    h.check(reps >= 1, f"np {np_}: {reps} repartitions")
    preds = sorted(set(rows["predicted_imbalance"]) - {0.0})
    h.check(preds and max(preds) < 1.01, f"np {np_}: predicted imbalance after each repartition "
                                         f"below the trigger 1.01 (worst {max(preds):.3f})")
    if balance.startswith("a_posteriori"):
        h.check("repartitioned (a posteriori" in out, f"np {np_}: repartitions in the log file")
        model_parts[np_] = rows
# bench/contact_partition.py measures K ranks by 'parts K' at one rank: the same partitions, the
# same per-part work at every check as K real ranks.
for k in (3,):
    _, rows, _ = run(1, posteriori + f" parts {k}")
    same = all(rows[c] == model_parts[k][c] for c in rows if c.split("_")[0] in ("work", "tests",
                                                                                 "contacts"))
    h.check(same and rows["repartitions"] == model_parts[k]["repartitions"],
            f"np 1 'parts {k}': the per-part work and repartitions of np {k} at every check")
print("OK")
