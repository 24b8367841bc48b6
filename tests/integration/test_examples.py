"""Every example runs (shortened) at 2 ranks: no error, no particle lost, ParaView output written."""
import glob
import os
import shutil
import tempfile

import harness as h

args = h.parse_args()
examples = sorted(glob.glob(os.path.join(h.ROOT, "examples", "*", "in.*")))
h.check(len(examples) >= 2, f"found {len(examples)} examples")
for script in examples:
    name = os.path.basename(os.path.dirname(script))
    wd = tempfile.mkdtemp(prefix=f"example_{name}_")
    for f in os.listdir(os.path.dirname(script)):
        src = os.path.join(os.path.dirname(script), f)
        if os.path.isfile(src):
            shutil.copy(src, wd)
    steps = 4000
    out = h.run(args.exe, os.path.basename(script), np_=2, workdir=wd, variables=dict(steps=steps))
    runs = h.thermo_blocks(out)
    atoms = h.column(runs, "Atoms")
    inserted = [a for a in atoms if a > 0]
    h.check(len(inserted) > 0 and min(inserted) == max(inserted),
            f"{name}: particle count constant once inserted ({int(max(atoms))})")
    pvd = glob.glob(os.path.join(wd, "out", "*.pvd"))
    vtus = glob.glob(os.path.join(wd, "out", "*.vtu"))
    h.check(len(pvd) == 1 and len(vtus) == steps // 1000 + 1, f"{name}: {len(vtus)} body frames + .pvd written")
    with open(pvd[0]) as f:
        h.check(f.read().count("<DataSet") == len(vtus), f"{name}: .pvd indexes every frame")
