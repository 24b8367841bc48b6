"""write_restart/read_restart of a body whose pieces touch: the glass strip of
examples/plate_shatter_2d with `contact_bodies yes`, restart written after it cracked (crack
faces and pieces in contact). The continued run matches the uninterrupted one to the last digit
of the thermo (%.17g) at np 1 and 2. Failed before the restart held the pieces' contact state
(SurfaceContact offsets): every continuing contact restarted as new, a resting one lost its force.
"""
import os
import re
import shutil
import tempfile

import harness as h

args = h.parse_args()
src = os.path.join(h.ROOT, "examples", "plate_shatter_2d")
original = open(os.path.join(src, "in.plate_shatter_2d")).read()
h.check("contact_bodies no" in original and "fracture nodal every 10" in original,
        "example input as expected")
FIRST, SECOND = 6000, 3000
base = original.replace("contact_bodies no", "contact_bodies yes")
base = re.sub(r"^(shell|dump|fix vtk|variable|run).*\n", "", base, flags=re.M)
base = base.replace("thermo          1000", "thermo          500\nthermo_modify   format float %.17g")
straight = base + f"run {FIRST}\nwrite_restart state.restart\nrun {SECOND}\n"
# The continuation: the settings and fixes again, the box, atoms and body state from the file.
cont = re.sub(r"^(dimension|atom_style|atom_modify|boundary|units|region|create_box|lattice|"
              r"create_atoms|set|velocity).*\n", "", base, flags=re.M)
cont = "read_restart state.restart\n" + cont + f"run {SECOND}\n"

for np_ in (1, 2):
    wd = tempfile.mkdtemp(prefix=f"restart_contact_{np_}_")
    shutil.copy(os.path.join(src, "plate.msh"), wd)
    open(os.path.join(wd, "in.a"), "w").write(straight)
    open(os.path.join(wd, "in.b"), "w").write(cont)
    a = h.thermo_blocks(h.run(args.exe, "in.a", np_=np_, workdir=wd))
    b = h.thermo_blocks(h.run(args.exe, "in.b", np_=np_, workdir=wd))
    ha, ra = a[-1]
    hb, rb = b[-1]
    h.check(ha == hb and len(ra) == len(rb) and ra[0][0] == FIRST,
            f"np={np_}: same thermo layout after restart")
    splits = h.column(a, "plate[17", run_index=0)
    h.check(splits[-1] > 0, f"np={np_}: the strip cracked before the restart "
                            f"({int(splits[-1])} split nodes)")
    worst = 0.0
    for row_a, row_b in zip(ra, rb):
        for x, y in zip(row_a, row_b):
            worst = max(worst, abs(x - y) / max(abs(x), abs(y), 1e-30))
    h.check(worst == 0.0, f"np={np_}: continued run matches the uninterrupted one "
                          f"(worst rel. diff {worst:.1e})")
print("OK")
