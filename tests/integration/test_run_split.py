"""A run split in two (`run N`, then `run M`) goes on as one `run N+M`, while the pieces of a body
touch (contact_bodies yes), with friction.

Between the two runs the host calls the fixes' init() and setup() again; its set-up evaluation
of the forces comes at the positions of step N but with the full-step velocities, where the step
took the mid-step ones. The friction of the pieces' contact depends on them: that evaluation took
it anew and changed the contact work by 1.2e-6 of its scale (docs/distributed_bodies.md). It now
takes the contact forces of the last counted evaluation (BodyDriver, "held contact forces"; the
restart record carries them), as the bulk viscosity does.

Scene: test_distributed_self_contact's torn Rankine bar (inputs/in.distributed_fracture, 1536
tets, halves thrown apart at 5 m/s, nodal fracture every 5 steps, contact_bodies yes, friction
0.3): its crack faces touch from about step 200 and do contact work until about step 290; split
at step 240 (a restart file is written between the two runs), 600 steps. Asserted:

* replicated at np 1: every thermo row and the energy file of the split run as the unsplit run's,
  byte for byte, and the thermo row of step 240 that the second run's set-up prints as the one
  the first run ends with; the crack faces do contact work at the split (the contact work
  changes between steps 240 and 250). Before the held forces: the thermo differed from step 300
  on (the build before fails here);
* the restart file of step 240 continued at np 1 (inputs/in.distributed_fracture_continue): the
  rows after step 240 as the unsplit run's, byte for byte;
* `parallel distributed` at np 2: the same (split against unsplit, byte for byte).

Two bodies in contact at the split (test_distributed_pair_contact's blocks, 400 steps, split at
step 240 while they touch): split with and without `write_restart` between, at np 1 replicated
and at np 3 with body a distributed, and the restart files continued as written: the unsplit
run's thermo and energy files byte for byte (the pairs' contacts carried into the next run and
stored in the restart record; before, they started afresh and the contact work departed by 0.92
of its scale).

Particles are left out: the host evaluates its own pairs and walls anew at set-up with the
full-step velocities (a particle-only LIGGGHTS scene does not continue a split run bit for bit
either), and the particles' contact with the body with them.
"""
import os
import shutil
import sys
import tempfile

import distributed_scenes as ds
import harness as h

args = h.parse_args()
sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import meshgen  # noqa: E402

STEPS, SPLIT = 600, 240
VARIABLES = {"frac": "every 5", "dt": 2e-7, "steps": STEPS, "speed": 5.0, "pieces": "yes",
             "balls": 0}


def bar(np_, parallel, restart_at):
    """in.distributed_fracture with its pieces' contact; restart_at > 0: split there."""
    wd = tempfile.mkdtemp(prefix=f"run_split_{np_}_{restart_at}_")
    meshgen.write_gmsh22(os.path.join(wd, "bar3d.msh"), *meshgen.sheared_tet_bar())
    h.copy_inputs(["in.distributed_fracture", "in.distributed_fracture_continue"], wd)
    out = h.run(args.exe, "in.distributed_fracture", np_=np_, workdir=wd,
                variables=dict(VARIABLES, parallel=parallel, restart_at=restart_at))
    return dict(wd=wd, out=out)


def continued(wd, np_, parallel):
    wd2 = tempfile.mkdtemp(prefix=f"run_split_continued_{np_}_")
    for f in ("bar.restart", "bar3d.msh", "in.distributed_fracture_continue"):
        shutil.copy(os.path.join(wd, f), wd2)
    out = h.run(args.exe, "in.distributed_fracture_continue", np_=np_, workdir=wd2,
                variables=dict(VARIABLES, parallel=parallel, rest=STEPS - SPLIT))
    return dict(wd=wd2, out=out)


def energy_lines(run, name="energy.csv"):
    with open(os.path.join(run["wd"], name)) as f:
        return f.read().splitlines()


def check_split(label, whole, split, files=("energy.csv",)):
    """The split run's thermo rows (both runs') and energy files as the unsplit run's; the rows of
    step N that the first run ends with and the second run's set-up prints, the same."""
    ref = h.thermo_text_rows(whole["out"])
    first, second = (h.thermo_text_rows(split["out"], block=k) for k in (0, 1))
    got = {s: ln for rows in (first, second) for s, ln in rows.items() if s in ref}
    differs = [s for s in sorted(ref) if got.get(s) != ref[s]]
    h.check(not differs and first.get(SPLIT) == second.get(SPLIT) is not None,
            f"{label}: {len(got)} thermo rows as the unsplit run's, byte for byte, and the row of "
            f"step {SPLIT} of the second run's set-up as the first run's last"
            + ("" if not differs else
               f" (step {differs[0]}:\n  {ref[differs[0]]}\n  {got.get(differs[0])})"))
    for name in files:
        a, b = energy_lines(whole, name), energy_lines(split, name)  # no row written twice
        line = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), None)
        h.check(b == a, f"{label}: {name}'s {len(a) - 1} rows as the unsplit run's, byte for byte"
                + ("" if line is None else f" (line {line}:\n  {a[line]}\n  {b[line]})"))


def blocks(np_, pa, restart_at, write):
    """Two bodies in contact (test_distributed_pair_contact's blocks, body a `pa`, b replicated);
    restart_at > 0: split there, write 1: write_restart between the two runs."""
    wd = tempfile.mkdtemp(prefix=f"run_split_pair_{np_}_{restart_at}_")
    ds.write_pair_blocks(wd, 3)
    h.copy_inputs(["in.distributed_pair_contact"], wd)
    out = h.run(args.exe, "in.distributed_pair_contact", np_=np_, workdir=wd,
                variables=dict(pa=pa, pb="replicated", first=1, dim=3, edges="yes", steps=400,
                               dt=2e-7, speed=5.0, restart_at=restart_at, write=write, akw=""))
    return dict(wd=wd, out=out)


whole = bar(1, "replicated", 0)
e = h.read_csv(os.path.join(whole["wd"], "energy.csv"))
k = e["step"].index(SPLIT)
h.check(e["fragments"][-1] >= 2 and e["contact_work"][k + 1] != e["contact_work"][k],
        f"the bar breaks ({int(e['fragments'][-1])} fragments) and its crack faces do contact "
        f"work across step {SPLIT} ({e['contact_work'][k]:.6g} -> {e['contact_work'][k + 1]:.6g} "
        f"J by step {int(e['step'][k + 1])})")
split = bar(1, "replicated", SPLIT)
check_split(f"np 1 replicated, split at step {SPLIT}", whole, split)
resumed = continued(split["wd"], 1, "replicated")
h.check_rows_as_uninterrupted(
    f"np 1 replicated, restart of step {SPLIT} continued at np 1 (against the unsplit run)",
    SPLIT + 1, whole["out"], resumed["out"], os.path.join(whole["wd"], "energy.csv"),
    os.path.join(resumed["wd"], "energy_continued.csv"))
check_split(f"np 2 distributed, split at step {SPLIT}", bar(2, "distributed", 0),
            bar(2, "distributed", SPLIT))
# Two bodies in contact at the split: their pairs' contacts go on in the second run (the scene's
# pair state carried, and the held forces replayed). Before: the second run took them as new
# contacts and the contact work departed by 0.92 of its scale.
pair_whole = blocks(1, "replicated", 0, 0)
e = h.read_csv(os.path.join(pair_whole["wd"], "energy_a.csv"))
k = e["step"].index(SPLIT)
h.check(e["contact_work"][k] != 0 and e["contact_work"][k + 1] != e["contact_work"][k],
        f"the blocks touch across step {SPLIT} (contact work {e['contact_work'][k]:.6g} -> "
        f"{e['contact_work'][k + 1]:.6g} J)")
pair_files = ("energy_a.csv", "energy_b.csv")
pair_whole_dist = blocks(3, "distributed", 0, 0)
for write in (0, 1):
    how = "with write_restart between" if write else "no restart file"
    pair_split = blocks(1, "replicated", SPLIT, write)
    check_split(f"two bodies in contact, np 1 replicated, split at step {SPLIT} ({how})",
                pair_whole, pair_split, pair_files)
    pair_split_dist = blocks(3, "distributed", SPLIT, write)
    check_split(f"two bodies in contact, np 3 distributed + replicated, split ({how})",
                pair_whole_dist, pair_split_dist, pair_files)
# Their restart file (the pairs' contacts in it, as the held forces), continued as it was
# written: the rows after the split as the unsplit run's, byte for byte (np 1 replicated; np 3
# with body a distributed, whose pairs it held). Before: 0.91 of the contact work's scale. The
# file continued in the other form: test_distributed_pair_contact (1e-10).
for np_, pa, split_run, whole_run in ((1, "replicated", pair_split, pair_whole),
                                      (3, "distributed", pair_split_dist, pair_whole_dist)):
    wd2 = tempfile.mkdtemp(prefix="run_split_pair_continued_")
    for f in ("pair.restart", "a.msh", "b.msh"):
        shutil.copy(os.path.join(split_run["wd"], f), wd2)
    h.copy_inputs(["in.distributed_pair_contact_continue"], wd2)
    out = h.run(args.exe, "in.distributed_pair_contact_continue", np_=np_, workdir=wd2,
                variables=dict(pa=pa, pb="replicated", rest=400 - SPLIT, dt=2e-7, speed=5.0))
    for b in "ab":
        h.check_rows_as_uninterrupted(
            f"two bodies in contact, np {np_} a {pa}: restart continued (body {b})", SPLIT + 1,
            whole_run["out"], out, os.path.join(whole_run["wd"], f"energy_{b}.csv"),
            os.path.join(wd2, f"energy_{b}.csv"))
print("OK")
