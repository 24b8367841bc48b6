"""fix fem/body ... parallel distributed contact_bodies yes: the contact of a distributed body's own
pieces (node to facet, edge to edge) gives the same run at 1, 2, 3 and 4 ranks (issue #13).

* Two pieces of one mesh: two elastic tet4 blocks (384 tets each, 40 mm, concrete-like E 30 GPa,
  nu 0.2, 2400 kg/m^3: in.fracture_cut_3d's material) in one mesh file, 0.2 mm apart and offset
  across, thrown at each other at 5 m/s each (inputs/in.distributed_self_contact). Replicated at
  np 1 against `parallel distributed` at np 2, 3 and 4: every energy-file column (contact work
  included) and thermo column within 1e-10 of its scale (the issue's figure for elastic runs);
  the blocks do collide (contact work beyond 1 % of their kinetic energy, the kinetic energy
  falls below half and comes back above half: with contact_bodies no they pass through each
  other and keep it). The same in 2D (two tri3 squares, node to edge) at np 2 against np 1, and at
  np 3 against the replicated run at np 3 (which departs from np 1 by itself: below).
* A body that breaks and whose fragments touch: test_distributed_fracture's torn Rankine tet4 bar
  (inputs/in.distributed_fracture, 1536 tets, halves thrown apart at 5 m/s) with
  `contact_bodies yes`: the same split / fragment log lines, energy file and thermo within 1e-10
  of each column's scale at np 2, 3, 4 distributed as at np 1 replicated; the crack faces'
  contact does work (the contact work column is not zero). Its restart file written at np 3 while
  the pieces touch (step 240), continued at np 2 distributed and np 1 replicated: the
  uninterrupted run's later lines and rows (the pieces' contact state is in the record). With
  cracks through tets (`min_size 0.2`) at np 3: the same; with three steel spheres hitting the
  bar across its crack (test_distributed_fracture's) at np 2: the same.
* A body that erodes (test_distributed_erosion's scene) with `contact_bodies yes` at np 3: the
  same erosion lines and energy file as at np 1 (the surface renewed after each erosion, a free
  node among the contacting nodes after the last batch).
* Cost, with the PMPI counter at np 3 (difference of two run lengths, blocks in contact): the
  pieces' contact takes exactly two all-reductions per host step (BodyDriver::
  distributed_body_contacts: the surface's positions and velocities, then its contact forces)
  and the contact scene's balance check one every 10 steps (its `contact_balance` default).
* A distributed body in contact with another `contact_bodies yes` body is refused by name.
"""
import os
import re
import shutil
import sys
import tempfile

import numpy as np

import harness as h

args = h.parse_args()
sys.path.insert(0, os.path.join(h.ROOT, "python"))
sys.path.insert(0, os.path.join(h.ROOT, "tests", "support"))
from fracdem import meshgen  # noqa: E402
import mpicount  # noqa: E402

TOL = 1e-10
SPEED = 5.0
BLOCKS_MV = 2 * 2400 * 0.04**3 * SPEED  # the blocks' m v (their momenta cancel)
BAR_MV = 2400 * 0.16 * 0.04 * 0.04 * SPEED  # the bar's (its halves' cancel)
BLOCK_STEPS = 400
BAR_STEPS = 600
RESTART_AT = 240  # the crack faces in contact (their contact work changes until ~290)


def blocks_2d(path):
    """The same in 2D: two 8 x 8-cell tri3 squares of 40 mm (plane strain), groups of every
    triangle's edges."""
    X, E, _ = meshgen.rect_mesh(8, 8, 0.04, 0.04)
    X = np.array(X, dtype=float)
    E = np.array(E)
    nodes = np.vstack([X, X + np.array([0.0402, 0.006, 0.0])])

    def edges(T):
        return np.array([e for t in T for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))])
    meshgen.write_gmsh22(path, nodes, np.vstack([E, E + len(X)]),
                         {"a": edges(E), "b": edges(E + len(X))})


def blocks(path):
    """Two 4 x 4 x 4-cell tet blocks of 40 mm, the second 0.2 mm further along x and offset by
    6 mm / 4 mm across; groups a and b: every tet's faces of each (so every node)."""
    X, E, _ = meshgen.box_tet_mesh(4, 4, 4, 0.04, 0.04, 0.04)
    X = np.array(X, dtype=float)
    E = np.array(E)
    Y = X + np.array([0.0402, 0.006, 0.004])
    nodes = np.vstack([X, Y])
    tets = np.vstack([E, E + len(X)])

    def faces(T):
        return np.array([f for t in T for f in ((t[0], t[1], t[2]), (t[0], t[1], t[3]),
                                                  (t[0], t[2], t[3]), (t[1], t[2], t[3]))])
    meshgen.write_gmsh22(path, nodes, tets, {"a": faces(E), "b": faces(E + len(X))})


def result(wd, out, energy="energy.csv"):
    with open(os.path.join(wd, "log.liggghts")) as f:
        log = f.read()
    events = [ln for ln in log.splitlines()
              if re.search(r"crack at node|crack through element|fragments, masses|eroded", ln)]
    blocks_ = h.thermo_blocks(out)
    rows = [r for _, rs in blocks_ for r in rs]
    return dict(wd=wd, out=out, log=log, events=events,
                energy=h.read_csv(os.path.join(wd, energy)), thermo=(blocks_[-1][0], rows))


def run_blocks(np_, parallel, steps=BLOCK_STEPS, other=0, expect_fail=False, dim=3):
    wd = tempfile.mkdtemp(prefix=f"distributed_self_contact_{np_}_")
    (blocks if dim == 3 else blocks_2d)(os.path.join(wd, "blocks.msh"))
    h.copy_inputs(["in.distributed_self_contact"], wd)
    out = h.run(args.exe, "in.distributed_self_contact", np_=np_, workdir=wd,
                variables={"parallel": parallel, "dt": 2e-7, "steps": steps, "speed": SPEED,
                           "other": other, "dim": dim},
                expect_fail=expect_fail)
    return out if expect_fail else result(wd, out)


def run_bar(np_, parallel, restart_at=RESTART_AT, frac="every 5", balls=0):
    """restart_at: the run is split there (run, write_restart, run) in every run compared, since
    a split while the pieces touch changes the contact work by 1.2e-6 of its scale at np 1
    replicated too (measured; not traced here)."""
    wd = tempfile.mkdtemp(prefix=f"distributed_self_contact_bar_{np_}_")
    meshgen.write_gmsh22(os.path.join(wd, "bar3d.msh"), *meshgen.sheared_tet_bar())
    h.copy_inputs(["in.distributed_fracture", "in.distributed_fracture_continue"], wd)
    out = h.run(args.exe, "in.distributed_fracture", np_=np_, workdir=wd,
                variables={"frac": frac, "parallel": parallel, "dt": 2e-7,
                           "steps": BAR_STEPS, "speed": SPEED, "pieces": "yes",
                           "restart_at": restart_at, "balls": balls})
    return result(wd, out)


def resume_bar(wd, np_, parallel):
    wd2 = tempfile.mkdtemp(prefix=f"distributed_self_contact_continue_{np_}_")
    for f in ("bar.restart", "bar3d.msh", "in.distributed_fracture_continue"):
        shutil.copy(os.path.join(wd, f), wd2)
    out = h.run(args.exe, "in.distributed_fracture_continue", np_=np_, workdir=wd2,
                variables={"frac": "every 5", "parallel": parallel, "dt": 2e-7,
                           "rest": BAR_STEPS - RESTART_AT, "speed": SPEED, "pieces": "yes"})
    return result(wd2, out, "energy_continued.csv")


def worst_thermo(a, b, momentum):
    """Rows of b matched to a's by step; each column scaled by its largest |value| in a, the
    momenta (which cancel) by `momentum` (the pieces' m v)."""
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


def compare(label, ref, other, momentum, after=-1):
    events = [ln for ln in ref["events"] if int(re.search(r"step (\d+):", ln).group(1)) > after]
    h.check(other["events"] == events, f"{label}: the same {len(events)} split / fragment lines")
    w, col = h.worst_energy_by_step(ref["energy"], other["energy"])
    h.check(w < TOL, f"{label}: energy file within {w:.1e} of each column's scale "
                     f"(worst: {col}; tolerance {TOL:g})")
    w, col = worst_thermo(ref["thermo"], other["thermo"], momentum)
    h.check(w < TOL, f"{label}: thermo within {w:.1e} of each column's scale (worst: {col})")


# Two pieces of one mesh thrown at each other.
ref = run_blocks(1, "replicated")
e = ref["energy"]
ke0, work = e["kinetic"][0], np.array(e["contact_work"])
ke = np.array(e["kinetic"])
h.check(np.max(np.abs(work)) > 0.01 * ke0 and np.min(ke) < 0.5 * ke0 and ke[-1] > 0.5 * ke0,
        f"the blocks collide and part: contact work up to {np.max(np.abs(work)):.3g} J, kinetic "
        f"energy {ke0:.3g} -> {np.min(ke):.3g} -> {ke[-1]:.3g} J")
for np_ in (2, 3, 4):
    compare(f"blocks, np {np_} distributed", ref, run_blocks(np_, "distributed"), BLOCKS_MV)

# 2D (node to edge). At np 2 the two squares are the two parts; at 3 ranks the replicated run
# itself departs from np 1 (the scene's contact forces summed over 3 ranks differ by round-off
# at step 170, 1e-11, which this contact amplifies to 8e-5 by step 400, in the build before this
# change too), so np 3 is compared with the replicated run at 3 ranks (the same partition of
# the contact work).
ref2 = run_blocks(1, "replicated", dim=2)
e = ref2["energy"]
h.check(np.max(np.abs(e["contact_work"])) > 0.01 * e["kinetic"][0] and
        np.min(e["kinetic"]) < 0.5 * e["kinetic"][0],
        f"2D: the squares collide (contact work up to {np.max(np.abs(e['contact_work'])):.3g} J)")
compare("2D squares, np 2 distributed", ref2, run_blocks(2, "distributed", dim=2), BLOCKS_MV)
compare("2D squares, np 3 distributed against np 3 replicated", run_blocks(3, "replicated", dim=2),
        run_blocks(3, "distributed", dim=2), BLOCKS_MV)

# A breaking body whose crack faces touch.
bar = run_bar(1, "replicated")
first = None
e = bar["energy"]
h.check(e["fragments"][-1] >= 2 and np.max(np.abs(e["contact_work"])) > 0,
        f"the bar breaks ({int(e['split_nodes'][-1])} split nodes, {int(e['fragments'][-1])} "
        f"fragments) and its pieces touch: contact work up to "
        f"{np.max(np.abs(e['contact_work'])):.3g} J")
for np_ in (2, 3, 4):
    d = run_bar(np_, "distributed")
    compare(f"breaking bar, np {np_} distributed", bar, d, BAR_MV)
    first = d if np_ == 3 else first
for np_, parallel in ((2, "distributed"), (1, "replicated")):
    compare(f"restart at step {RESTART_AT} of np 3, continued at np {np_} {parallel}", bar,
            resume_bar(first["wd"], np_, parallel), BAR_MV, after=RESTART_AT)
# Cracks through tets (min_size 0.2): cut elements' facets and nodes in the pieces' contact.
cut = run_bar(1, "replicated", frac="every 5 min_size 0.2")
h.check(any("crack through element" in ln for ln in cut["events"]) and
        np.max(np.abs(cut["energy"]["contact_work"])) > 0,
        "min_size 0.2: elements are cut and the pieces touch")
compare("min_size 0.2, np 3 distributed", cut,
        run_bar(3, "distributed", frac="every 5 min_size 0.2"), BAR_MV)

# Three steel spheres hitting the breaking bar across its crack as well (facet ghosts; the
# contact forces of pieces and particles summed once at shared nodes).
balls = run_bar(1, "replicated", balls=1)
hdr, rows = balls["thermo"]
ke = [r[hdr.index("KinEng")] for r in rows]
h.check(min(ke) < 0.5 * ke[0], f"the spheres hit the bar ({ke[0]:.3g} -> {min(ke):.3g} J)")
compare("spheres and pieces, np 2 distributed", balls, run_bar(2, "distributed", balls=1), BAR_MV)

# A body that erodes (test_distributed_erosion's scene: the 20 mm sphere at 1500 m/s on the
# clamped J2 block, 3000 tets, erosion plastic_strain 0.3) with contact_bodies yes: the surface
# renewed after each erosion, the free node the last batch leaves (mesh node 665, step 675) among
# the contacting nodes.
def run_erosion(np_, parallel):
    wd = tempfile.mkdtemp(prefix=f"distributed_self_contact_erosion_{np_}_")
    h.copy_inputs(["in.fast_impact"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (10, 10, 5), (0.1, 0.1, 0.05))
    body = ("fixed zmin material j2 yield 5e8 hardening 2e9 erosion plastic_strain 0.3 "
            f"energy_file energy.csv 10 contact_bodies yes parallel {parallel}")
    out = h.run(args.exe, "in.fast_impact", np_=np_, workdir=wd,
                variables=dict(v=1500.0, dt=1e-8, x0=0.05, y0=0.05, steps=700, every=50,
                               bodykw=body))
    lines = [ln for ln in out.splitlines() if re.search(r"eroded \d+ elements", ln)]
    return lines, h.read_csv(os.path.join(wd, "energy.csv"))


lines1, e1 = run_erosion(1, "replicated")
lines3, e3 = run_erosion(3, "distributed")
w, col = h.worst_energy_by_step(e1, e3)
h.check(len(lines1) == 6 and lines3 == lines1 and w < TOL,
        f"eroding block with contact_bodies yes, np 3 distributed: the same {len(lines1)} erosion "
        f"lines, energy file within {w:.1e} of each column's scale (worst: {col})")

# Cost: two all-reductions per host step, and the scene's balance check every 10 steps.
LIB = os.path.join(os.path.dirname(os.path.abspath(args.exe)), "libfracdem_mpicount.so")
h.check(os.path.isfile(LIB), f"PMPI counter {LIB} built")
wd = tempfile.mkdtemp(prefix="distributed_self_contact_counts_")
blocks(os.path.join(wd, "blocks.msh"))
h.copy_inputs(["in.distributed_self_contact"], wd)


def counted(steps):
    variables = dict(parallel="distributed", dt=2e-7, steps=steps, speed=SPEED, other=0)
    return mpicount.run(args.exe, "in.distributed_self_contact", 3, wd, LIB, f"c{steps}",
                        variables)


short_text, short = counted(100)
long_text, long_ = counted(200)
for d in mpicount.difference(long_, short):
    pieces, scene, restep, output, other = 0, 0, 0, 0, []
    for (module, caller, func, cat), (count, nbytes) in d["sites"].items():
        if cat != "coll" or not count or "fracdem::" not in caller:
            continue  # the host's own (its neighbour check, thermo)
        if "energy_row" in caller or "vector_entry" in caller:
            output += count  # output: the energy file's and the thermo's sums over the parts
        elif "distributed_body_contacts" in caller and func == "MPI_Allreduce":
            pieces += count
        elif "ContactScene::check_balance" in caller and func == "MPI_Allreduce":
            scene += count
        elif "check_squeezed" in caller and func == "MPI_Allreduce":
            restep += count
        else:
            other.append(f"{count} x {func} in {caller}")
    h.check(pieces == 200 and scene == 10 and restep == 1 and not other,
            f"rank {d['rank']}: in 100 steps {pieces} all-reductions of the pieces' contact (two "
            f"per host step), {scene} balance checks of the scene (one per 10 steps), {restep} "
            f"stable-step re-estimate, {output} output sums (2 thermo steps, 10 energy rows), "
            f"other collectives: {'; '.join(other) or 'none'}")

out = run_blocks(2, "distributed", steps=1, other=1, expect_fail=True)
h.check("'parallel distributed' with 'contact_bodies yes' takes the contact of its own pieces "
        "only, but fix fem/body other has 'contact_bodies yes' too" in out,
        "a distributed body with another contact_bodies body: refused by name")
print("OK")
