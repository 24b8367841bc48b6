"""Contact between the pieces of a breaking body with erode_cracked: the glass strip of
examples/plate_shatter_2d (parameters and their sources in its header) shot by 50 steel disks at
20 m/s, with `contact_bodies yes` and `fracture nodal ... erode_cracked yes`. Without
erode_cracked this scene gains energy without bound (docs/fracture.md, restrictions); with it:
asserted at np 2 that no energy is created (particle + body kinetic + strain + dissipated energy
never exceeds the disks' initial kinetic energy by more than 1 %, as nothing else does work), the
dissipation account never goes negative, the strip breaks (>= 2 fragments) and every erosion is
logged.
"""
import os
import re
import shutil
import tempfile

import harness as h

args = h.parse_args()
src = os.path.join(h.ROOT, "examples", "plate_shatter_2d")
wd = tempfile.mkdtemp(prefix="fracture_contact_")
for f in os.listdir(src):
    shutil.copy(os.path.join(src, f), wd)
path = os.path.join(wd, "in.plate_shatter_2d")
text = open(path).read()
h.check("contact_bodies no" in text and "fracture nodal every 10" in text, "example input as expected")
text = text.replace("contact_bodies no", "contact_bodies yes").replace(
    "fracture nodal every 10", "fracture nodal every 10 erode_cracked yes")
open(path, "w").write(text)
out = h.run(args.exe, "in.plate_shatter_2d", np_=2, workdir=wd, variables={"steps": 15000})
runs = h.thermo_blocks(out)
ke_p, ke_b, se_b = h.column(runs, "KinEng"), h.column(runs, "plate[1]"), h.column(runs, "plate[2]")
diss, frags, elems = h.column(runs, "plate[16"), h.column(runs, "plate[18"), h.column(runs, "plate[6]")
e0 = ke_p[0]
worst = max((p + k + s + d) / e0 for p, k, s, d in zip(ke_p, ke_b, se_b, diss))
h.check(worst < 1.01, f"no energy created: max (particles + body + dissipated) / initial = {worst:.4f}")
h.check(min(diss) >= 0, f"dissipation never negative (min {min(diss):.3e} J)")
h.check(frags[-1] >= 2, f"the strip breaks: {int(frags[-1])} fragments")
eroded = len(re.findall(r"failed element \d+ carries no more tension, eroded", open(os.path.join(wd, "log.liggghts")).read()))
h.check(eroded == elems[0] - elems[-1] and eroded > 0,
        f"every erosion logged: {eroded} lines == {int(elems[0] - elems[-1])} elements lost")
print("OK")
