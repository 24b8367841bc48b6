"""fix fem/body ... parallel distributed contact_bodies yes: the contact of a distributed body's own
pieces (node to facet, edge to edge) gives the same run at 1, 2, 3 and 4 ranks (issue #13).

* Two pieces of one mesh: two elastic tet4 blocks (384 tets each, 40 mm, concrete-like E 30 GPa,
  nu 0.2, 2400 kg/m^3: in.fracture_cut_3d's material) in one mesh file, 0.2 mm apart and offset
  across, thrown at each other at 5 m/s each (inputs/in.distributed_self_contact). Replicated at
  np 1 against `parallel distributed` at np 2, 3 and 4: every energy-file column (contact work
  included) and thermo column within 1e-10 of its scale (the issue's figure for elastic runs);
  the blocks do collide (contact work beyond 1 % of their kinetic energy, the kinetic energy
  falls below half and comes back above half: with contact_bodies no they pass through each
  other and keep it). The same in 2D (two tri3 squares, node to edge) at np 2 and 3 against np 1,
  up to the step where the scene starts to amplify round-off (the replicated run at np 3 departs
  from np 1 by itself there: below), and over the whole run within 10 times that departure.
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
* Cost, with the PMPI counter at np 3 (difference of two run lengths, blocks in contact, FE only:
  no re-neighbouring in between): no collective from the pieces' contact (BodyDriver::
  distributed_body_contacts: neighbour messages, body/piece_ghosts.h) but one integer reduction
  per host step (the travel flag), two messages per partner and step, at most 9 doubles per
  surface node plus one per message. Blocks 12 mm apart (out of each other's reach at set-up,
  buffer 1e-5) collide at np 2 distributed as at np 1: the travel flag renews the parts' boxes.
* A distributed body in contact with another distributed `contact_bodies yes` body is refused by
  name (with a replicated one: test_distributed_pair_contact).
"""
import os
import re
import sys
import tempfile

import numpy as np

import distributed_scenes as ds
import harness as h

args = h.parse_args()
sys.path.insert(0, os.path.join(h.ROOT, "python"))
sys.path.insert(0, os.path.join(h.ROOT, "tests", "support"))
from fracdem import meshgen  # noqa: E402
import mpicount  # noqa: E402

TOL = ds.TOL
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


def blocks(path, gap=0.0002):
    """Two 4 x 4 x 4-cell tet blocks of 40 mm, the second `gap` (0.2 mm) further along x and
    offset by 6 mm / 4 mm across; groups a and b: every tet's faces of each (so every node)."""
    X, E, _ = meshgen.box_tet_mesh(4, 4, 4, 0.04, 0.04, 0.04)
    X = np.array(X, dtype=float)
    E = np.array(E)
    Y = X + np.array([0.04 + gap, 0.006, 0.004])
    nodes = np.vstack([X, Y])
    tets = np.vstack([E, E + len(X)])

    def faces(T):
        return np.array([f for t in T for f in ((t[0], t[1], t[2]), (t[0], t[1], t[3]),
                                                  (t[0], t[2], t[3]), (t[1], t[2], t[3]))])
    meshgen.write_gmsh22(path, nodes, tets, {"a": faces(E), "b": faces(E + len(X))})


def run_blocks(np_, parallel, steps=BLOCK_STEPS, other=0, expect_fail=False, dim=3, gap=0.0002,
               speed=SPEED, **more):
    wd = tempfile.mkdtemp(prefix=f"distributed_self_contact_{np_}_")
    if dim == 3:
        blocks(os.path.join(wd, "blocks.msh"), gap)
    else:
        blocks_2d(os.path.join(wd, "blocks.msh"))
    h.copy_inputs(["in.distributed_self_contact"], wd)
    out = h.run(args.exe, "in.distributed_self_contact", np_=np_, workdir=wd,
                variables=dict({"parallel": parallel, "dt": 2e-7, "steps": steps,
                                "speed": speed, "other": other, "dim": dim}, **more),
                expect_fail=expect_fail)
    return out if expect_fail else ds.result(wd, out)


def run_bar(np_, parallel, restart_at=RESTART_AT, frac="every 5", balls=0):
    """restart_at: the run is split there (run, write_restart, run) in every run compared, so
    that the restart record of that step can be continued at other rank counts (a split run now
    continues as the unsplit one: test_run_split)."""
    return ds.run_bar(args.exe, np_, parallel, frac, BAR_STEPS,
                      prefix="distributed_self_contact_bar", pieces="yes",
                      restart_at=restart_at, balls=balls)


def resume_bar(wd, np_, parallel):
    return ds.resume_bar(args.exe, wd, np_, parallel, "every 5", BAR_STEPS - RESTART_AT,
                         prefix="distributed_self_contact_continue", pieces="yes")


compare = ds.compare


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

# 2D (node to edge). This contact amplifies round-off: the replicated run at 3 ranks departs from
# np 1 by itself (its contact forces summed over 3 ranks differ by 4e-12 of the strain energy at
# step 170, 2e-8 at step 190, 8e-5 by step 400; in the builds before the neighbour exchange
# too), and so does any other order of the sums (the neighbour exchange adds each part's forces
# on a node, then the partners' returned ones). So the distributed runs (np 2: the squares are
# the two parts; np 3) are compared with np 1 within 1e-10 up to step AMPLIFIED, and over the
# whole run within 10 times the replicated np 3 run's own departure from np 1.
AMPLIFIED = 170


def until(run, last):
    """The run's energy rows and thermo rows up to step `last` (compared with the reference's
    rows of the same steps)."""
    keep = [i for i, step in enumerate(run["energy"]["step"]) if step <= last]
    energy = {c: [v[i] for i in keep] for c, v in run["energy"].items()}
    hdr, rows = run["thermo"]
    return dict(run, energy=energy, thermo=(hdr, [r for r in rows if r[0] <= last]))


ref2 = run_blocks(1, "replicated", dim=2)
e = ref2["energy"]
h.check(np.max(np.abs(e["contact_work"])) > 0.01 * e["kinetic"][0] and
        np.min(e["kinetic"]) < 0.5 * e["kinetic"][0],
        f"2D: the squares collide (contact work up to {np.max(np.abs(e['contact_work'])):.3g} J)")
w_rep, _ = h.worst_energy_by_step(ref2["energy"], run_blocks(3, "replicated", dim=2)["energy"])
for np_ in (2, 3):
    d = run_blocks(np_, "distributed", dim=2)
    compare(f"2D squares, np {np_} distributed, to step {AMPLIFIED}", ref2, until(d, AMPLIFIED),
            BLOCKS_MV)
    w, col = h.worst_energy_by_step(ref2["energy"], d["energy"])
    h.check(w < 10 * w_rep, f"2D squares, np {np_} distributed: energy file within {w:.1e} of "
                            f"each column's scale over {BLOCK_STEPS} steps (worst: {col}); the "
                            f"replicated run at np 3: {w_rep:.1e}")

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

# Cost, with the PMPI counter at np 3 (difference of a 200- and a 100-step run, blocks in contact;
# FE only, so the host never re-neighbours and no box exchange falls in between): no collective
# of the body's code but the output's sums and the stable-step re-estimate (every 100 steps);
# the pieces' messages (sparse_exchange: positions and velocities out, forces back) one per
# partner and round, so 2 k per step for k partners, 1 <= k <= 2, and at most 9 doubles per
# surface node of the whole body (S) plus 1 per message (6 |S_p| + 1 out, 3 |S_q| back, S_p the
# surface nodes of a part).
LIB = os.path.join(os.path.dirname(os.path.abspath(args.exe)), "libfracdem_mpicount.so")
h.check(os.path.isfile(LIB), f"PMPI counter {LIB} built")
wd = tempfile.mkdtemp(prefix="distributed_self_contact_counts_")
blocks(os.path.join(wd, "blocks.msh"))
h.copy_inputs(["in.distributed_self_contact"], wd)
# Surface nodes of the two 4 x 4 x 4-cell blocks (no shared node): (5^3 - 3^3) each.
S = 2 * (5**3 - 3**3)


def counted(steps):
    variables = dict(parallel="distributed", dt=2e-7, steps=steps, speed=SPEED, other=0)
    return mpicount.run(args.exe, "in.distributed_self_contact", 3, wd, LIB, f"c{steps}",
                        variables)


short_text, short = counted(100)
long_text, long_ = counted(200)
for d in mpicount.difference(long_, short):
    c = ds.body_collectives(d)
    restep, travel, output, sends, nbytes, other = (
        c[k] for k in ("restep", "travel", "output", "sends", "nbytes", "other"))
    k = sends / 200
    h.check(restep == 1 and travel == 100 and not other and k in (1, 2)
            and nbytes / 100 <= 8 * k * (9 * S + 1),
            f"rank {d['rank']}: in 100 steps no collective of the pieces' contact but the travel "
            f"flag's {travel} one-integer reductions (other "
            f"collectives: {'; '.join(other) or 'none'}; {restep} stable-step re-estimate, "
            f"{output} output sums), {sends} messages ({k:g} partners, 2 per step each), "
            f"{nbytes / 100:.0f} bytes per step (bound 8 k (9 S + 1) = {8 * k * (9 * S + 1):.0f}, "
            f"S = {S})")

# Parts out of each other's reach at set-up: the blocks 12 mm apart (their boxes, grown by the
# buffer 1e-5 and the facets' reach of at most 5 mm, half a tet's altitude, do not meet), closing at 50 m/s in an
# FE-only run (the host never re-neighbours). At np 2 the blocks are the two parts. Once a part's
# surface leaves its box the travel flag (one integer reduction per host step) renews the boxes,
# the parts become partners before they touch, and the collision is the replicated run's.
FAR = dict(gap=0.012, speed=25.0, steps=1400, buffer=1e-5)
far_ref = run_blocks(1, "replicated", **FAR)
far_work = np.max(np.abs(far_ref["energy"]["contact_work"]))
h.check(far_work > 0.01 * far_ref["energy"]["kinetic"][0],
        f"blocks 12 mm apart collide within the run (contact work {far_work:.3g} J)")
compare("blocks 12 mm apart, np 2 distributed, buffer 1e-5", far_ref,
        run_blocks(2, "distributed", **FAR), 2 * 2400 * 0.04**3 * FAR["speed"])

# Contact with a replicated contact_bodies body: test_distributed_pair_contact. With another
# distributed one: refused by name.
out = run_blocks(2, "distributed", steps=1, other=1, otherpar="distributed", expect_fail=True)
h.check("fix fem/body body: 'parallel distributed' with 'contact_bodies yes': fix fem/body other "
        "is 'parallel distributed' with 'contact_bodies yes' too" in out,
        "a distributed body with another distributed contact_bodies body: refused by name")
print("OK")
