"""Smoke test of the flagship example in LAMMPS syntax, examples/block_impact/in.block_impact.lammps
(spheres raining on a clamped elastic slab), run as it is at 2 ranks for the first 4500 steps,
the spheres' first landing, with a few thermo quantities added before its `run`:

* the spheres' vertical momentum: P_z(t) - P_z(0) = -M g t + J, J the impulse of the slab's contact
  force (minus fix fem/body's f_slab[10], summed over every step by fix ave/time with the
  velocity-Verlet trapezoid ends), to 1e-9 of M g t, while no sphere reaches a wall (checked from
  the spheres' extent at each thermo row) and pair forces cancel: the slab's reaction is the force
  the spheres feel, and it does hold them up (J > 0, contacts seen);
* the slab's energy: kinetic + strain = gravity work + contact work (elastic, clamped ends do no
  work) within 1 % of the contact work at every row;
* the output: out/body.pvd lists the frames of fix fem/vtk, out/particles_*.csv holds the spheres.
"""
import os
import shutil
import sys
import tempfile

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)
sys.path.insert(0, os.path.join(lh.ROOT, "python"))
from fracdem.fem import read_pvd  # noqa: E402

EX = os.path.join(lh.ROOT, "examples", "block_impact")
STEPS, EVERY, DT, G, RADIUS = 4500, 50, 1e-5, 9.81, 0.004
wd = tempfile.mkdtemp(prefix="lmp_block_impact_")
for name in ("in.block_impact.lammps", "slab.msh"):
    shutil.copy(os.path.join(EX, name), wd)
with open(os.path.join(wd, "in.block_impact.lammps")) as f:
    text = f.read()
CHECKS = f"""variable        pzatom atom mass*vz
compute         pz all reduce sum v_pzatom
variable        mtot equal mass(all)
compute         lo all reduce min x y z
compute         hi all reduce max x y z
fix             fz all ave/time 1 {EVERY} {EVERY} f_slab[10]
thermo_style    custom step c_pz f_slab[10] f_slab[7] f_slab[1] f_slab[2] f_slab[3] f_slab[4] &
                c_lo[1] c_lo[2] c_lo[3] c_hi[1] c_hi[2] f_fz v_mtot
thermo          {EVERY}
thermo_modify   format float %.17g
"""
RUN = "run             ${steps}"
h.check(text.count(RUN) == 1, "the example ends with 'run ${steps}'")
with open(os.path.join(wd, "in.check"), "w") as f:
    f.write(text.replace(RUN, CHECKS + RUN))
out = lmp.run("in.check", np_=2, workdir=wd, variables=dict(steps=STEPS))
header, rows = h.thermo_blocks(out)[-1]
h.check(len(rows) == STEPS // EVERY + 1, f"{len(rows)} thermo rows")
col = {name: k for k, name in enumerate(header)}


def c(row, name):
    return row[col[name]]


# No sphere within reach of a wall (x = +-0.16, y = +-0.04, floor z = -0.03), with room for the
# travel between two rows (50 steps at < 2 m/s).
margin = RADIUS + EVERY * DT * 2.0
lo = [min(c(r, f"c_lo[{k}]") for r in rows) for k in (1, 2, 3)]
hi = [max(c(r, f"c_hi[{k}]") for r in rows) for k in (1, 2)]
h.check(lo[0] > -0.16 + margin and hi[0] < 0.16 - margin and lo[1] > -0.04 + margin and
        hi[1] < 0.04 - margin and lo[2] > -0.03 + margin,
        f"no sphere reaches a wall: x {lo[0]:.4f} .. {hi[0]:.4f}, y {lo[1]:.4f} .. {hi[1]:.4f}, "
        f"z >= {lo[2]:.4f}")

first, last = rows[0], rows[-1]
M, t = c(last, "v_mtot"), STEPS * DT
force_sum = EVERY * sum(c(r, "f_fz") for r in rows[1:])  # steps 1 .. N
J = -DT * (force_sum - 0.5 * c(last, "f_slab[10]") + 0.5 * c(first, "f_slab[10]"))
dP = c(last, "c_pz") - c(first, "c_pz")
resid = dP - (-M * G * t + J)
contacts = max(c(r, "f_slab[7]") for r in rows)
h.check(J > 0 and contacts > 0,
        f"the spheres landed on the slab: up to {contacts:.0f} contacts, the slab's impulse on "
        f"them {J:.5g} N s up ({100 * J / (M * G * t):.0f} % of their weight's {M * G * t:.5g} N s)")
h.check(abs(resid) <= 1e-9 * M * G * t,
        f"spheres' vertical momentum: P_z(t) - P_z(0) = {dP:.10g} = -M g t + J = "
        f"{-M * G * t + J:.10g} N s (difference {abs(resid) / (M * G * t):.1e} of M g t <= 1e-9)")

work = max(abs(c(r, "f_slab[4]")) for r in rows)
worst = max(abs(c(r, "f_slab[1]") + c(r, "f_slab[2]") - c(r, "f_slab[3]") - c(r, "f_slab[4]"))
            for r in rows)
h.check(work > 0 and worst <= 0.01 * work,
        f"slab: kinetic + strain = gravity work + contact work to {worst:.3g} J at every row "
        f"(<= 1 % of the contact work {work:.4g} J)")

frames = read_pvd(os.path.join(wd, "out", "body.pvd"))
want = [f"body_{s:010d}.vtu" for s in range(0, STEPS + 1, 1000)]
h.check([os.path.basename(p) for _, p in frames] == want and all(os.path.exists(p) for _, p in frames),
        f"out/body.pvd lists the fix fem/vtk frames {want[0]} .. {want[-1]}")
with open(os.path.join(wd, "out", "particles_4000.csv")) as f:
    lines = [ln.split(",") for ln in f.read().splitlines() if ln.strip()]
h.check(len(lines) == 300 and all(len(w) == 9 for w in lines),
        f"out/particles_4000.csv: {len(lines)} spheres, 9 comma-separated columns")
