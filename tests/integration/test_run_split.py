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

Particles are left out: the host evaluates its own pairs and walls anew at set-up with the
full-step velocities (a particle-only LIGGGHTS scene does not continue a split run bit for bit
either), and the particles' contact with the body with them.
"""
import os
import shutil
import sys
import tempfile

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


def check_split(label, whole, split):
    """The split run's thermo rows (both runs') and energy file as the unsplit run's; the rows of
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
    a, b = energy_lines(whole), energy_lines(split)  # the set-up writes no row twice
    line = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), None)
    h.check(b == a, f"{label}: the energy file's {len(a) - 1} rows as the unsplit run's, byte for "
                    f"byte" + ("" if line is None else f" (line {line}:\n  {a[line]}\n  {b[line]})"))


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
print("OK")
