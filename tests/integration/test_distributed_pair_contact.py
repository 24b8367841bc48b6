"""fix fem/body ... parallel distributed contact_bodies yes in contact with another fix fem/body that
has contact_bodies yes and is replicated (issue #13): the same run at 2 and 3 ranks as both bodies
replicated at 1 rank.

* Two elastic tet4 blocks, two bodies (384 tets each, 40 mm, E 30 GPa, nu 0.2, 2400 kg/m^3:
  test_distributed_self_contact's blocks, one mesh file each), 0.2 mm apart and offset across,
  thrown at each other at 5 m/s each with contact_edges yes (inputs/in.distributed_pair_contact).
  Body a distributed, b replicated, at np 2 and 3, with a's fix first (the distributed body's
  call evaluates the pair) and with b's first (the replicated body's call evaluates it) against
  both replicated at np 1 in the same order: both energy files and every thermo column within
  1e-10 of its scale (the issue's figure for elastic runs); the blocks collide (contact work
  beyond 1 % of the kinetic energy, which falls below half and comes back above half).
* The run split while the blocks touch, at np 2 and 3 against np 1, and its restart file written
  at np 3 continued at np 2 distributed and at np 1 replicated (the pairs' contacts go on, from
  the distributed body's restart records into the replicated scene too); split without a restart
  file (the held contact forces replayed) at np 3 against np 1, either fix first.
* The same with contact_edges no, and in 2D (two tri3 squares in plane strain, node to edge) up
  to the step where the scene starts to amplify round-off (the replicated run at np 3 departs
  from np 1 by itself there), and over the whole run within 10 times that departure.
* A breaking distributed body (test_distributed_fracture's torn bar) hit by a replicated elastic
  block that cracks it: the same split lines and runs at np 2 and 3 as at np 1.
* An eroding distributed body (J2, erosion plastic_strain 0.3) in contact with a replicated
  block at 150 m/s: the same erosion lines and runs at np 2 and 3 as at np 1.
* Cost, with the PMPI counter at np 3: the pair adds no collective.
* Two distributed bodies with contact_bodies yes: refused by name.
"""
import os
import re
import shutil
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
STEPS = 400


def result(wd, out):
    blocks = h.thermo_blocks(out)
    return dict(wd=wd, out=out, thermo=(blocks[-1][0], [r for _, rs in blocks for r in rs]),
                events=[ln for ln in out.splitlines() if re.search(r"eroded \d+ elements", ln)],
                energy={b: h.read_csv(os.path.join(wd, f"energy_{b}.csv")) for b in "ab"})


def run(np_, pa, pb, first=1, dim=3, edges="yes", steps=STEPS, restart_at=0, write=1, speed=SPEED,
        akw="", expect_fail=False):
    wd = tempfile.mkdtemp(prefix=f"distributed_pair_contact_{np_}_")
    ds.write_pair_blocks(wd, dim)
    h.copy_inputs(["in.distributed_pair_contact"], wd)
    out = h.run(args.exe, "in.distributed_pair_contact", np_=np_, workdir=wd,
                variables=dict(pa=pa, pb=pb, first=first, dim=dim, edges=edges, steps=steps,
                               dt=2e-7, speed=speed, restart_at=restart_at, write=write,
                               akw=akw),
                expect_fail=expect_fail)
    return out if expect_fail else result(wd, out)


def resume(wd, np_, pa, pb, rest):
    """in.distributed_pair_contact_continue from the restart file of the run in wd."""
    wd2 = tempfile.mkdtemp(prefix=f"distributed_pair_contact_continue_{np_}_")
    for f in ("pair.restart", "a.msh", "b.msh"):
        shutil.copy(os.path.join(wd, f), wd2)
    h.copy_inputs(["in.distributed_pair_contact_continue"], wd2)
    out = h.run(args.exe, "in.distributed_pair_contact_continue", np_=np_, workdir=wd2,
                variables=dict(pa=pa, pb=pb, rest=rest, dt=2e-7, speed=SPEED))
    return result(wd2, out)


def check_collide(label, ref):
    for b in "ab":
        e = ref["energy"][b]
        ke = np.array(e["kinetic"])
        work = np.max(np.abs(e["contact_work"]))
        h.check(work > 0.01 * ke[0] and np.min(ke) < 0.5 * ke[0] and ke[-1] > 0.5 * ke[0],
                f"{label}: the blocks collide and part (body {b}: contact work up to {work:.3g} J,"
                f" kinetic energy {ke[0]:.3g} -> {np.min(ke):.3g} -> {ke[-1]:.3g} J)")


def compare(label, ref, got):
    for b in "ab":
        w, col = h.worst_energy_by_step(ref["energy"][b], got["energy"][b])
        h.check(w < TOL, f"{label}: body {b}'s energy file within {w:.1e} of each column's scale "
                         f"(worst: {col}; tolerance {TOL:g})")
    w, col = ds.worst_thermo(ref["thermo"], got["thermo"], 1.0)
    h.check(w < TOL, f"{label}: thermo within {w:.1e} of each column's scale (worst: {col})")


# 3D, edge to edge on: the distributed body's call evaluates the pair (its fix first), then the
# replicated body's (its fix first).
for first, order in ((1, "a's fix first"), (0, "b's fix first")):
    ref = run(1, "replicated", "replicated", first=first)
    check_collide(f"3D, {order}, np 1 replicated", ref)
    for np_ in (2, 3):
        compare(f"3D, {order}, np {np_}, a distributed", ref,
                run(np_, "distributed", "replicated", first=first))
    compare(f"3D, {order}, np 3, b distributed", ref,
            run(3, "replicated", "distributed", first=first))

# A run split while the blocks touch (step 200), its restart file written at np 3 with a
# distributed: the pairs between two bodies go on at a new run and at a restart
# (docs/fix_fem_body.md), at every rank count alike. The split runs at np 2 and 3 against the
# split run at np 1; the restart continued at np 2 distributed and at np 1 replicated (the
# distributed body's pair records read by the replicated scene).
SPLIT = 200
ref = run(1, "replicated", "replicated", restart_at=SPLIT)
for np_ in (2, 3):
    got = run(np_, "distributed", "replicated", restart_at=SPLIT)
    compare(f"3D, run split at step {SPLIT}, np {np_}, a distributed", ref, got)
for np_, pa in ((2, "distributed"), (1, "replicated")):
    compare(f"3D, restart of np 3 at step {SPLIT} continued at np {np_}, a {pa}", ref,
            resume(got["wd"], np_, pa, "replicated", STEPS - SPLIT))

# Split without write_restart: the
# set-up of the second run replays the held contact forces of both bodies, at every rank count
# alike, with either fix first.
for first in (1, 0):
    ref = run(1, "replicated", "replicated", first=first, restart_at=SPLIT, write=0)
    compare(f"3D, run split at step {SPLIT} (no restart file), fix {'ab'[1 - first]} first, np 3,"
            " a distributed", ref,
            run(3, "distributed", "replicated", first=first, restart_at=SPLIT, write=0))

# Node to facet alone.
ref = run(1, "replicated", "replicated", edges="no")
check_collide("3D, contact_edges no, np 1 replicated", ref)
compare("3D, contact_edges no, np 3, a distributed", ref,
        run(3, "distributed", "replicated", edges="no"))

# 2D: node to edge. As in test_distributed_self_contact this scene amplifies round-off: the
# replicated run at np 3 departs from np 1 by itself (2e-4 of the contact work's scale over the
# run, beyond 1e-11 from step 180 on), so the distributed runs are compared with np 1 within 1e-10
# up to step AMPLIFIED, and over the whole run within 10 times the replicated np 3 run's own
# departure.
AMPLIFIED = 170


def until(r, last):
    keep = [i for i, step in enumerate(r["energy"]["a"]["step"]) if step <= last]
    energy = {b: {c: [v[i] for i in keep] for c, v in e.items()} for b, e in r["energy"].items()}
    hdr, rows = r["thermo"]
    return dict(r, energy=energy, thermo=(hdr, [x for x in rows if x[0] <= last]))


def worst_energy(ref, got):
    return max(h.worst_energy_by_step(ref["energy"][b], got["energy"][b])[0] for b in "ab")


ref = run(1, "replicated", "replicated", dim=2)
check_collide("2D, np 1 replicated", ref)
w_rep = worst_energy(ref, run(3, "replicated", "replicated", dim=2))
for np_ in (2, 3):
    got = run(np_, "distributed", "replicated", dim=2)
    compare(f"2D, np {np_}, a distributed, to step {AMPLIFIED}", ref, until(got, AMPLIFIED))
    w = worst_energy(ref, got)
    h.check(w < 10 * w_rep, f"2D, np {np_}, a distributed: energy files within {w:.1e} of each "
                            f"column's scale over {STEPS} steps; the replicated run at np 3: "
                            f"{w_rep:.1e}")

# A breaking distributed body hit by a replicated one: test_distributed_fracture's torn Rankine
# bar (in.distributed_fracture, 1536 tets, contact_bodies yes) and an elastic 20 mm tet block
# falling on its top across its crack at 10 m/s (block 1: fix hit, after the bar's). The impact
# cracks the bar (its surface, parts and free nodes change while the block touches it): the same
# split / fragment lines at np 2 and 3 distributed as at np 1 replicated, both energy files and
# the thermo within 1e-10 of each column's scale.
def run_bar(np_, parallel):
    wd = tempfile.mkdtemp(prefix=f"distributed_pair_contact_bar_{np_}_")
    meshgen.write_gmsh22(os.path.join(wd, "bar3d.msh"), *meshgen.sheared_tet_bar())
    X, E, _ = meshgen.box_tet_mesh(2, 2, 2, 0.02, 0.02, 0.02)
    X = np.array(X, dtype=float) + np.array([0.09, 0.0402, 0.01])
    sides = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))
    meshgen.write_gmsh22(os.path.join(wd, "block.msh"), X, np.array(E),
                         {"all": np.array([[t[i] for i in s] for t in E for s in sides])})
    h.copy_inputs(["in.distributed_fracture"], wd)
    out = h.run(args.exe, "in.distributed_fracture", np_=np_, workdir=wd,
                variables=dict(frac="every 5", parallel=parallel, dt=2e-7, steps=600, speed=5.0,
                               pieces="yes", block=1))
    r = ds.result(wd, out)
    r["hit"] = h.read_csv(os.path.join(wd, "energy_hit.csv"))
    return r


bar = run_bar(1, "replicated")
work = np.max(np.abs(bar["hit"]["contact_work"]))
h.check(any("crack at node" in ln for ln in bar["events"]) and
        work > 0.1 * bar["hit"]["kinetic"][0],
        f"the block hits the bar ({len(bar['events'])} split / fragment lines, the block's "
        f"contact work up to {work:.3g} J of its {bar['hit']['kinetic'][0]:.3g} J)")
for np_ in (2, 3):
    got = run_bar(np_, "distributed")
    ds.compare(f"breaking bar hit by a block, np {np_} distributed", bar, got,
               2400 * 0.16 * 0.04 * 0.04 * SPEED)
    w, col = h.worst_energy_by_step(bar["hit"], got["hit"])
    h.check(w < TOL, f"breaking bar hit by a block, np {np_} distributed: the block's energy "
                     f"file within {w:.1e} of each column's scale (worst: {col})")

# An eroding distributed body: block a of J2 steel-like yield (1e8 Pa, hardening 1e9) that
# erodes its elements at plastic strain 0.3, the blocks thrown together at 150 m/s each: the
# contact goes on over the eroded surface (its facets renewed after each erosion, free nodes
# among its surface nodes). The same erosion lines at np 2 and 3 distributed as at np 1
# replicated, both energy files and the thermo within 1e-10 of each column's scale.
J2 = "material j2 yield 1e8 hardening 1e9 erosion plastic_strain 0.3"
ref = run(1, "replicated", "replicated", speed=150.0, akw=J2)
eroded = int(re.search(r"(\d+) eroded in all", ref["events"][-1]).group(1)) if ref["events"] else 0
h.check(eroded > 10 and np.max(np.abs(ref["energy"]["a"]["contact_work"])) > 0,
        f"eroding block: {len(ref['events'])} erosion lines, {eroded} elements eroded while the "
        f"blocks touch")
for np_ in (2, 3):
    got = run(np_, "distributed", "replicated", speed=150.0, akw=J2)
    h.check(got["events"] == ref["events"],
            f"eroding block, np {np_} distributed: the same {len(ref['events'])} erosion lines")
    compare(f"eroding block, np {np_} distributed", ref, got)

# Cost, with the PMPI counter at np 3 (difference of a 200- and a 100-step run, blocks in
# contact, FE only: no re-neighbouring in between): the pair adds no collective (the bodies'
# code takes the distributed body's travel flag of its pieces, one integer per host step, its
# stable-step re-estimate and the output's sums, as test_distributed_self_contact counts, and
# the replicated body its own all-reductions of every step, BodyDriver::compute_forces, and its
# scene's balance checks), only neighbour messages (sparse_exchange: the pieces' 2 per partner
# and step, the pair's 1 to rank 0 and 1 back).
LIB = os.path.join(os.path.dirname(os.path.abspath(args.exe)), "libfracdem_mpicount.so")
h.check(os.path.isfile(LIB), f"PMPI counter {LIB} built")
wd = tempfile.mkdtemp(prefix="distributed_pair_contact_counts_")
ds.write_pair_blocks(wd, 3)
h.copy_inputs(["in.distributed_pair_contact"], wd)


def counted(steps):
    variables = dict(pa="distributed", pb="replicated", first=1, dim=3, edges="yes",
                     steps=steps, dt=2e-7, speed=SPEED, restart_at=0)
    return mpicount.run(args.exe, "in.distributed_pair_contact", 3, wd, LIB, f"c{steps}",
                        variables)


_, short = counted(100)
_, long_ = counted(200)
for d in mpicount.difference(long_, short):
    c = ds.body_collectives(d, r"BodyDriver::compute_forces|ContactScene::check_balance")
    restep, travel, output, sends, nbytes, other, replicated = (
        c[k] for k in ("restep", "travel", "output", "sends", "nbytes", "other", "replicated"))
    h.check(restep == 1 and travel == 100 and not other,
            f"rank {d['rank']}: in 100 steps no collective of the pair contact (other "
            f"collectives: {'; '.join(other) or 'none'}; the travel flag's {travel} one-integer "
            f"reductions, {restep} stable-step re-estimate, {output} output sums, {replicated} "
            f"of the replicated body); {sends} messages, {nbytes / 100:.0f} bytes per step")

# Two distributed bodies in contact: refused by name.
out = run(2, "distributed", "distributed", steps=1, expect_fail=True)
h.check("fix fem/body a: 'parallel distributed' with 'contact_bodies yes': fix fem/body b is "
        "'parallel distributed' with 'contact_bodies yes' too, and the contact between two "
        "distributed bodies is not done; give one of them 'parallel replicated'" in out,
        "two distributed bodies with contact_bodies yes: refused by name")
print("OK")
