"""A distributed breaking body gathers itself on rank 0 only when a fracture check can change it
(issue #13: no whole-body gather at every check once the body has cracked).

Scene (inputs/in.distributed_fracture, as test_distributed_fracture): the free Rankine tet4 bar,
1536 tets, its halves thrown apart at 5 m/s, `fracture nodal every 5`, `parallel distributed`.
Its crack is made at steps 50, 160 and 165 (splits and the two fragments); from then on about 190
elements stay failed, so every check step finds a failed element. Two runs of 300 and 600 steps
under the PMPI counter (libfracdem_mpicount.so); their difference is exactly the traffic of steps
301..600, all after the last topology change. Asserted at np 2, 3 and 4, on every rank:

* the last split / fragment line of the log comes before step 300 (the window follows the last
  change), and the 600-step run logs the same lines as the replicated np 1 run;
* the body's fracture check takes exactly one integer max-reduction per check step (60 in the
  window) and no other collective;
* the window holds no gather of the whole body (MPI_Gatherv): 0. Before this change (main
  880e97a) every one of the 60 check steps gathered the body and took a second reduction: 60
  MPI_Gatherv (with 60 MPI_Gather of the sizes) and 120 check reductions per rank (measured with
  this branch's build whose forecast says "may change" everywhere, which is main's path; over the
  whole 600-step run 111 gathers of the 120 check steps; now 3 at np 2 and 3, the three
  changes, and 24 at np 4, where the checks between the changes gather too).
"""
import os
import re
import sys
import tempfile

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "tests", "support"))
sys.path.insert(0, os.path.join(h.ROOT, "python"))
import counted_runs  # noqa: E402
import distributed_scenes as ds  # noqa: E402
from fracdem import fem, meshgen  # noqa: E402

args = h.parse_args()
LIB = os.path.join(os.path.dirname(os.path.abspath(args.exe)), "libfracdem_mpicount.so")
h.check(os.path.isfile(LIB), f"PMPI counter {LIB} built")
SHORT, LONG, EVERY = 300, 600, 5
VARS = dict(frac=f"every {EVERY}", parallel="distributed", dt=2e-7, speed=5.0)


def event_lines(wd):
    with open(os.path.join(wd, "log.liggghts")) as f:
        return [ln for ln in f.read().splitlines() if re.search(ds.EVENTS, ln)]


# The replicated run's last frame: its failed elements (damage 1: no tension left) stay failed, so
# every check step of the window finds some, and before this change gathered the body.
ref = ds.run_bar(args.exe, 1, "replicated", f"every {EVERY}", LONG, vtk=LONG)
damage = fem.read_vtu(os.path.join(ref["wd"], f"bar_{LONG:010d}.vtu"))["cell_data"]["damage"]
failed = int((damage >= 1.0).sum())
h.check(failed > 0, f"np 1: {failed} failed elements at step {LONG}")
for np_ in (2, 3, 4):
    wd = tempfile.mkdtemp(prefix=f"distributed_fracture_gathers_{np_}_")
    meshgen.write_gmsh22(os.path.join(wd, "bar3d.msh"), *meshgen.sheared_tet_bar())
    h.copy_inputs(["in.distributed_fracture"], wd)
    win = counted_runs.window(args.exe, LIB, os.path.join(wd, "in.distributed_fracture"), np_,
                              (SHORT, LONG), VARS, workdir=wd)
    events = event_lines(wd)  # the 600-step run's log (the last one written)
    last = max(int(re.search(r"step (\d+):", ln).group(1)) for ln in events)
    h.check(events == ref["events"] and last < SHORT,
            f"np {np_}: the same {len(events)} split / fragment lines as np 1 replicated, the "
            f"last at step {last} < {SHORT}")
    for d in win.diffs:
        reductions, gathers, other = 0, 0, []
        for (module, caller, func, cat), (count, nbytes) in d["sites"].items():
            if not count or cat != "coll":
                continue
            if "distributed_fracture" in caller and func == "MPI_Allreduce":
                reductions += count
            elif func == "MPI_Gatherv":  # each gather: MPI_Gather of the sizes, then this
                gathers += count
            elif "distributed_fracture" in caller or func == "MPI_Gather":
                other.append(f"{count} x {func} in {caller[:60]}")
        checks = (LONG - SHORT) // EVERY
        h.check(reductions == checks and gathers == 0 and not other,
                f"np {np_} rank {d['rank']}: steps {SHORT + 1}..{LONG} ({checks} check steps, "
                f"failed elements in the body): {reductions} check reductions, {gathers} "
                f"gathers (before this change: {checks} gathers, {2 * checks} reductions), other "
                f"collectives: "
                f"{'; '.join(other) or 'none'}")
print("OK")
