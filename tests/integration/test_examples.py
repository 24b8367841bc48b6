"""Every example runs (shortened) at 2 ranks: no error, no particle lost, ParaView output written,
nothing but out/ created (LIGGGHTS' `shell mkdir` takes no options: `mkdir -p out` makes `-p`).
LAMMPS versions of examples (`in.*.lammps`) run in tests/lammps."""
import glob
import os
import re
import shutil
import tempfile

import harness as h

args = h.parse_args()
examples = sorted(p for p in glob.glob(os.path.join(h.ROOT, "examples", "*", "in.*"))
                  if not p.endswith(".lammps"))
h.check(len(examples) >= 2, f"found {len(examples)} examples")

# Every input script of the package: `shell mkdir` makes each of its words a directory.
scripts = examples + glob.glob(os.path.join(h.ROOT, "bench", "inputs", "in.*")) + \
    glob.glob(os.path.join(h.INPUTS, "in.*"))
with_options = [s for s in scripts
                if re.search(r"^\s*shell\s+mkdir\b.*\s-", open(s).read(), re.M)]
h.check(not with_options, f"no input passes options to 'shell mkdir' ({with_options or 'none'})")


def script_vtk_fixes(script):
    return len(re.findall(r"^\s*fix\s+\S+\s+\S+\s+fem/vtk\b", open(script).read(), re.M))


for script in examples:
    name = os.path.basename(script)[3:]
    wd = tempfile.mkdtemp(prefix=f"example_{name}_")
    for f in os.listdir(os.path.dirname(script)):
        src = os.path.join(os.path.dirname(script), f)
        if os.path.isfile(src):
            shutil.copy(src, wd)
    # Shortened to 4000 steps, or to what a heavy example asks in its header ("# smoke test: N steps").
    smoke = re.search(r"^# smoke test: (\d+) steps", open(script).read(), re.M)
    steps = int(smoke.group(1)) if smoke else 4000
    out = h.run(args.exe, os.path.basename(script), np_=2, workdir=wd, variables=dict(steps=steps))
    runs = h.thermo_blocks(out)
    atoms = h.column(runs, "Atoms")
    inserted = [a for a in atoms if a > 0]
    if not re.search(r"^\s*(create_atoms|read_data|fix\s+\S+\s+\S+\s+insert/)",
                     open(script).read(), re.M):
        # An FE-only example (taylor_bar): no particle ever, and the body runs every step.
        h.check(max(atoms) == 0 and h.column(runs, "Step")[-1] == steps,
                f"{name}: FE-only example ran {steps} steps")
    else:
        h.check(len(inserted) > 0 and min(inserted) == max(inserted),
                f"{name}: particle count constant once inserted ({int(max(atoms))})")
    # One ParaView series per `fix fem/vtk` (an example with several bodies writes several).
    pvds = glob.glob(os.path.join(wd, "out", "*.pvd"))
    vtus = glob.glob(os.path.join(wd, "out", "*.vtu"))
    frames = steps // 1000 + 1
    h.check(len(pvds) == script_vtk_fixes(script) and len(vtus) == frames * len(pvds),
            f"{name}: {len(vtus)} body frames + {len(pvds)} .pvd written")
    for pvd in pvds:
        with open(pvd) as f:
            h.check(f.read().count("<DataSet") == frames,
                    f"{name}: {os.path.basename(pvd)} indexes every frame")
    made = sorted(d for d in os.listdir(wd) if os.path.isdir(os.path.join(wd, d)))
    h.check(made == ["out"], f"{name}: the run made only the directory out/ ({made})")
