"""Contact between the pieces of a breaking body: the glass strip of examples/plate_shatter_2d
(parameters and their sources in its header) shot by 50 steel disks at 20 m/s with
`contact_bodies yes`, once with `fracture nodal ... erode_cracked yes` and once without it.
Asserted at np 2 for both: no energy is created (particle + body kinetic + strain + dissipated
energy never exceeds the disks' initial kinetic energy by more than 1 %, as nothing else does
work), the dissipation account never falls (the Rankine law dissipates int psi+ dd >= 0), the
strip breaks (>= 2 fragments); with erode_cracked every erosion is logged.
Both failed before (docs/fracture.md, restrictions): a body-body contact that appeared already
deep (after an erosion) released up to 60 J of penalty energy in one step (4.9x the shot's
energy), and without erode_cracked the non-potential crack law plus that contact took the body
to 5e4 J with the dissipation account at -3e4 J.
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
original = open(path).read()
h.check("contact_bodies no" in original and "fracture nodal every 10" in original,
        "example input as expected")


def shatter(erode):
    extra = " erode_cracked yes" if erode else ""
    open(path, "w").write(original.replace("contact_bodies no", "contact_bodies yes").replace(
        "fracture nodal every 10", "fracture nodal every 10" + extra))
    out = h.run(args.exe, "in.plate_shatter_2d", np_=2, workdir=wd, variables={"steps": 15000})
    runs = h.thermo_blocks(out)
    ke_p, ke_b, se_b = h.column(runs, "KinEng"), h.column(runs, "plate[1]"), h.column(runs, "plate[2]")
    diss, frags = h.column(runs, "plate[16"), h.column(runs, "plate[18")
    elems = h.column(runs, "plate[6]")
    name = "erode_cracked" if erode else "no erosion"
    e0 = ke_p[0]
    worst = max((p + k + s + d) / e0 for p, k, s, d in zip(ke_p, ke_b, se_b, diss))
    h.check(worst < 1.01, f"{name}: no energy created: max (particles + body + dissipated) / "
                          f"initial = {worst:.4f}")
    fall = max([a - b for a, b in zip(diss, diss[1:])] + [0.0])
    h.check(min(diss) >= 0 and fall <= 1e-9 * max(diss),
            f"{name}: dissipation never negative (min {min(diss):.3e} J) and never falls "
            f"(largest fall {fall:.3e} J)")
    h.check(frags[-1] >= 2, f"{name}: the strip breaks: {int(frags[-1])} fragments")
    return elems


elems = shatter(erode=True)
eroded = len(re.findall(r"failed element \d+ carries no more tension, eroded",
                        open(os.path.join(wd, "log.liggghts")).read()))
h.check(eroded == elems[0] - elems[-1] and eroded > 0,
        f"every erosion logged: {eroded} lines == {int(elems[0] - elems[-1])} elements lost")
shatter(erode=False)
print("OK")
