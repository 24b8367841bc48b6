"""Set-ups shared by the distributed-body tests (test_distributed_fracture,
test_distributed_self_contact): the torn Rankine tet4 bar of inputs/in.distributed_fracture (a run,
and a run continued from its restart file), a run's results (log events, energy file, thermo),
and the comparison of two runs column by column against each column's scale."""
import os
import re
import shutil
import sys
import tempfile

import numpy as np

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import meshgen  # noqa: E402

TOL = 1e-10  # the figure for elastic runs (issue #13)
EVENTS = r"crack at node|crack through element|fragments, masses|eroded"


def result(wd, out, energy="energy.csv"):
    """The run in wd: its log, split / cut / fragment / erosion lines, energy file and thermo
    (last block's header, every block's rows)."""
    with open(os.path.join(wd, "log.liggghts")) as f:
        log = f.read()
    events = [ln for ln in log.splitlines() if re.search(EVENTS, ln)]
    blocks = h.thermo_blocks(out)
    rows = [r for _, rs in blocks for r in rs]
    return dict(wd=wd, out=out, log=log, events=events,
                energy=h.read_csv(os.path.join(wd, energy)), thermo=(blocks[-1][0], rows))


def run_bar(exe, np_, parallel, frac, steps, prefix="distributed_fracture", **variables):
    """inputs/in.distributed_fracture in a new directory: the bar (in.fracture_cut_3d's,
    meshgen.sheared_tet_bar), its halves thrown apart at 5 m/s, dt 2e-7; variables: the input's
    others (balls, pieces, restart_at, vtk)."""
    wd = tempfile.mkdtemp(prefix=f"{prefix}_{np_}_")
    meshgen.write_gmsh22(os.path.join(wd, "bar3d.msh"), *meshgen.sheared_tet_bar())
    h.copy_inputs(["in.distributed_fracture", "in.distributed_fracture_continue"], wd)
    out = h.run(exe, "in.distributed_fracture", np_=np_, workdir=wd,
                variables=dict({"frac": frac, "parallel": parallel, "dt": 2e-7, "steps": steps,
                                "speed": 5.0}, **variables))
    return result(wd, out)


def resume_bar(exe, wd, np_, parallel, frac, rest, prefix="distributed_fracture_continue",
               **variables):
    """in.distributed_fracture_continue in a copy of wd (its restart file and mesh)."""
    wd2 = tempfile.mkdtemp(prefix=f"{prefix}_{np_}_")
    for f in ("bar.restart", "bar3d.msh", "in.distributed_fracture_continue"):
        shutil.copy(os.path.join(wd, f), wd2)
    out = h.run(exe, "in.distributed_fracture_continue", np_=np_, workdir=wd2,
                variables=dict({"frac": frac, "parallel": parallel, "dt": 2e-7, "rest": rest,
                                "speed": 5.0}, **variables))
    return result(wd2, out, "energy_continued.csv")


def worst_thermo(a, b, momentum):
    """Rows of b matched to a's by step (b may be a continued run's); each column scaled by its
    largest |value| in a, the momenta f_ID[13..15] (which cancel) by `momentum`."""
    (ha, ra), (hb, rb) = a, b
    by_step = {r[0]: r for r in ra}
    if ha != hb or not rb or any(r[0] not in by_step for r in rb):
        return float("inf"), "shape"
    ra, rb = np.array([by_step[r[0]] for r in rb]), np.array(rb)
    worst, name = 0.0, ""
    for j, col in enumerate(ha):
        scale = momentum if re.search(r"body\[1[345]\]", col) else \
            max(np.max(np.abs(ra[:, j])), 1e-300)
        w = float(np.max(np.abs(ra[:, j] - rb[:, j]))) / scale
        if w > worst:
            worst, name = w, col
    return worst, name


def compare(label, ref, other, momentum, after=-1, need_events=False, tol=TOL):
    """The same log events (after step `after`: a continued run's), energy file and thermo within
    tol of each column's scale. need_events: ref must have some."""
    events = [ln for ln in ref["events"] if int(re.search(r"step (\d+):", ln).group(1)) > after]
    h.check((events or not need_events) and other["events"] == events,
            f"{label}: the same {len(events)} split / cut / fragment lines")
    w, col = h.worst_energy_by_step(ref["energy"], other["energy"])
    h.check(w < tol, f"{label}: energy file within {w:.1e} of each column's scale "
                     f"(worst: {col}; tolerance {tol:g})")
    w, col = worst_thermo(ref["thermo"], other["thermo"], momentum)
    h.check(w < tol, f"{label}: thermo within {w:.1e} of each column's scale (worst: {col})")


def write_pair_blocks(wd, dim, gap=0.0002):
    """a.msh and b.msh: block b is block a moved gap further along x and across; group "all"
    (every element's faces / edges: every node)."""
    if dim == 3:
        X, E, _ = meshgen.box_tet_mesh(4, 4, 4, 0.04, 0.04, 0.04)
        shift = np.array([0.04 + gap, 0.006, 0.004])
        sides = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))
    else:
        X, E, _ = meshgen.rect_mesh(8, 8, 0.04, 0.04)
        shift = np.array([0.04 + gap, 0.006, 0.0])
        sides = ((0, 1), (1, 2), (2, 0))
    X, E = np.array(X, dtype=float), np.array(E)
    group = {"all": np.array([[t[i] for i in s] for t in E for s in sides])}
    meshgen.write_gmsh22(os.path.join(wd, "a.msh"), X, E, group)
    meshgen.write_gmsh22(os.path.join(wd, "b.msh"), X + shift, E, group)


def body_collectives(d, replicated_pattern=None):
    """One rank's PMPI sites of a counted difference (tests/support/mpicount.py) sorted into the
    body's own costs: sparse_exchange sends and bytes, the stable-step re-estimate, the travel
    flag's one-integer reductions, the output's sums, the collectives of callers matching
    replicated_pattern (a replicated body's), and any other collective (listed)."""
    c = dict(restep=0, travel=0, output=0, sends=0, nbytes=0, replicated=0, other=[])
    for (module, caller, func, cat), (count, nb) in d["sites"].items():
        if not count or "fracdem::" not in caller:
            continue  # the host's own (its neighbour check, thermo)
        if cat == "send" and "sparse_exchange" in caller:
            c["sends"] += count
            c["nbytes"] += nb
        if cat != "coll":
            continue
        if "energy_row" in caller or "vector_entry" in caller:
            c["output"] += count  # the energy file's and the thermo's sums over the parts
        elif "check_squeezed" in caller and func == "MPI_Allreduce":
            c["restep"] += count
        elif "distributed_forces" in caller and func == "MPI_Allreduce" and nb <= 4 * count:
            c["travel"] += count  # the pieces' travel flag: one integer per host step
        elif replicated_pattern and re.search(replicated_pattern, caller):
            c["replicated"] += count
        else:
            c["other"].append(f"{count} x {func} in {caller}")
    return c
