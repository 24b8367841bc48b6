"""Counted windows of steps, for fracdem and for Debian's LAMMPS (`lmp`) alike: one scene run
twice under the PMPI counter (N1 and N2 steps), the difference being exactly the traffic of steps
N1..N2. Shared by tests/integration/test_comm_counts.py and bench/comm_counts.py, so that the
test's comparison with LAMMPS rcb measures what the bench's tables do.
"""
import os
import shutil
import tempfile

import mpicount

# The `balance` variable of the LAMMPS inputs (bench/inputs/in.settle_lammps,
# tests/integration/inputs/in.balance_bed_lammps) for `comm_style tiled` + `fix balance rcb
# weight neigh`: the reference of issue #11.
LAMMPS_RCB = "rcb_neigh"


def lmp():
    """Debian's LAMMPS executable (package `lammps`), or None where it is not installed."""
    return shutil.which("lmp")


class Window:
    """The counts of one scene over steps N1..N2: summary (mpicount.summarise, per rank and
    step), diffs (per rank and call site), texts (stdout of both runs), workdir."""

    def __init__(self, summary, diffs, texts, workdir):
        self.summary, self.diffs, self.texts, self.workdir = summary, diffs, texts, workdir


def window(exe, lib, script, np_, steps, variables=None, workdir=None, tag="s"):
    """Run the input file `script` (a path, copied into workdir unless it is there) with exe at
    np_ ranks for steps[0] and steps[1] steps (the `steps` variable), counted by lib."""
    wd = workdir or tempfile.mkdtemp(prefix="counted_")
    name = os.path.basename(script)
    if os.path.abspath(os.path.dirname(script)) != os.path.abspath(wd):
        shutil.copy(script, wd)
    texts, runs = [], []
    for n in steps:
        text, ranks = mpicount.run(exe, name, np_, wd, lib, f"{tag}{n}",
                                   dict(variables or {}, steps=n))
        texts.append(text)
        runs.append(ranks)
    diffs = mpicount.difference(runs[1], runs[0])
    return Window(mpicount.summarise(diffs, steps[1] - steps[0]), diffs, texts, wd)


def lammps_rcb(lib, script, np_, steps, variables=None, workdir=None):
    """The LAMMPS input `script` balanced by rcb (weight neigh), counted like window(); None
    where `lmp` is not installed."""
    exe = lmp()
    if exe is None:
        return None
    return window(exe, lib, script, np_, steps, dict(variables or {}, balance=LAMMPS_RCB),
                  workdir, tag="lmp")
