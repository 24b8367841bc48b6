"""Particles hit a distributed body under LAMMPS (issue #13 item 2 on the second host): the
oblique sphere impact on a free elastic block of tests/lammps/test_contact_momentum.py (friction,
damping, no gravity, no walls), `parallel distributed` over 2 LAMMPS ranks against the replicated
body at 1 LAMMPS rank (the sphere starts 0.2 mm above the block, 4500 steps: rebound included): every thermo column within 1e-9 of its scale, the contact count equal at
every thermo step, and total momentum (particle + body) conserved to 1e-12 of its size.
"""
import os
import shutil
import tempfile

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)

wd = tempfile.mkdtemp(prefix="lmp_distributed_contact_")
for name in ("in.momentum", "in.lammps_preamble", "in.lammps_law"):
    shutil.copy(os.path.join(lh.INPUTS, name), wd)
with open(os.path.join(wd, "in.momentum")) as f:
    script = f.read().replace("${law}\n", "${law} parallel ${parallel}\n", 1)
# The sphere starts 0.2 mm above the block (not 1 mm): the same impact in fewer steps.
script = script.replace("single 0.1 0.05 0.056 ", "single 0.1 0.05 0.0552 ", 1)
with open(os.path.join(wd, "in.distributed_momentum"), "w") as f:
    f.write(script)
h.make_box_mesh(os.path.join(wd, "block.msh"), (6, 6, 3), (0.2, 0.1, 0.05))

runs = {}
for np_, parallel in ((1, "replicated"), (2, "distributed")):
    out = lmp.run("in.distributed_momentum", np_=np_, workdir=wd,
                  variables=dict(host="lammps", model="corotational", steps=4500, every=100,
                                 parallel=parallel))
    if parallel == "distributed":
        h.check("distributed over 2 ranks" in out, "LAMMPS np 2: the body is distributed")
    header, rows = h.thermo_blocks(out)[-1]
    runs[np_] = {n: [r[k] for r in rows] for k, n in enumerate(header) if n != "Step"}
ref, got = runs[1], runs[2]
h.check(max(ref["f_body[7]"]) >= 1, "the sphere touched the body")
h.check(got["f_body[7]"] == ref["f_body[7]"], "contact count equal at every thermo step")
worst, where = h.worst_scaled(ref, got)
h.check(worst < 1e-9, f"LAMMPS np 2 distributed vs np 1 replicated: thermo within {worst:.1e} "
                      f"of the column scale (worst: {where}) < 1e-9")
for comp in ("v_px", "v_py", "v_pz"):
    p = got[comp]
    change = max(abs(x - p[0]) for x in p) / max(abs(x) for x in p)
    h.check(change < 1e-12, f"np 2 distributed: total {comp[3]}-momentum conserved, largest "
                            f"relative change {change:.1e}")
