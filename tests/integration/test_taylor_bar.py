"""Taylor bar (issue #10, deliverable 7): a copper rod hits a rigid frictionless wall at 227 m/s.

Problem and published results (python/fracdem/taylor.py, docs/validation.md "Taylor bar"): Ansys
Technology Demonstration Guide ch. 17 "Metal Bar Impacting a Rigid Wall" after Kamoulakos (1990,
NAFEMS Benchmark): L0 32.4 mm, R0 3.2 mm, v0 227 m/s, E 117 GPa, nu 0.35, rho 8930 kg/m^3, yield
400 MPa, linear hardening 100 MPa, 80 us; final length 21.4-21.5 mm, foot radius 7.0-7.1 mm.
Model: `plane axisymmetric` quad4 (x = r, y = axis), `material j2`, default bulk viscosity,
`model corotational`; the wall is the impact face held in y (r free), the axis held in r.

Asserted (time step 0.1 of the set-up stable step: the cells at the wall flatten 5-10 times):
1. Impact phase (the first 10 us, 4 x 40 quad4 of 0.8 mm): kinetic + strain + plastic work +
   viscous work = initial kinetic energy within 0.5 % at every row, with plastic work > 10 % of
   it (the bar does yield); np 1 and np 2 give the same energy file (plastic bodies do their
   element work on every rank).
2. The benchmark (80 us) on 4 x 40 and 5 x 51 cells: final length and foot radius within 5 % of
   the published midpoints 21.45 mm and 7.05 mm (5 % is the issue's criterion; the published
   spread is 0.5 % in length and 1.4 % in radius, and on these coarse meshes the foot radius is
   one node's position); the energy balance of 1. within 0.5 %; the two meshes agree on length
   and radius within 2 %.
3. At 0.9 of the set-up stable step (the squeezed foot's stable step falls below it): with
   `substeps off` the run warns; with `substeps auto` (default) the body sub-cycles (logged, the
   energy file's `substeps` column above 1), without the warning, and the balance of 1. holds.

The plastic laws under `model corotational` see the logarithmic strain ln U of the corotated
stretch and return the rotated Kirchhoff stress (src/core/fem/fe_space.cpp), so the plastic foot
keeps its volume; with the small-strain measure U - I the first row of cells at the wall lost
its volume and inverted at 6-12 us (docs/validation.md, Taylor bar). An inverted element now
fails the test like any other error.
"""
import os
import re
import sys
import tempfile

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import taylor  # noqa: E402

args = h.parse_args()
EXE = os.path.abspath(args.exe)
DT_FRACTION = 0.1  # of the set-up stable step: the cells at the wall flatten 5-10x
EARLY = 10e-6
ROWS = 100
TOL_SHAPE, TOL_ENERGY_EARLY, TOL_ENERGY, TOL_MESHES = 0.05, 0.005, 0.005, 0.02
MESHES = (4, 5)


def scene(nr, extra=""):
    """Work directory with the mesh of nr radial cells and in.taylor (the body command with
    `extra` keywords); returns (wd, stable dt)."""
    wd = tempfile.mkdtemp(prefix=f"taylor_{nr}_")
    h.copy_inputs(["in.fe_common_2d"], wd)
    taylor.bar_mesh(os.path.join(wd, "bar.msh"), nr)
    with open(os.path.join(wd, "in.taylor"), "w") as f:
        f.write("include in.fe_common_2d\ntimestep ${dt}\n"
                + taylor.body_command("bar.msh", "energy.csv", "${every}", extra) + "\n"
                "thermo_style custom step f_bar[1] f_bar[2] f_bar[16]\nthermo ${every}\nrun ${steps}\n")
    out = h.run(EXE, "in.taylor", workdir=wd, variables=dict(dt=1e-12, every=1, steps=0))
    return wd, h.stable_dt(out)


SQUEEZED = "its elements have been squeezed"


def run_to(wd, dt0, t_end, np_=1, fraction=None):
    """Run to t_end at DT_FRACTION x dt0; returns the energy file as {column: list}."""
    dt = (fraction or DT_FRACTION) * dt0
    every = max(1, int(round(t_end / dt)) // ROWS)
    steps = every * int(round(t_end / dt / every))
    out = h.run(EXE, "in.taylor", np_=np_, workdir=wd,
                variables=dict(dt=dt, every=every, steps=steps))
    if SQUEEZED in out:  # the bound is conservative: the run may still be stable
        print(f"note: dt {dt:.3g}: " + next(l for l in out.splitlines() if SQUEEZED in l))
    run_to.text = out
    return h.read_csv(os.path.join(wd, "energy.csv"))


# 1. Impact phase.
wd, dt0 = scene(4)
early = {np_: run_to(wd, dt0, EARLY, np_) for np_ in (1, 2)}
e = early[1]
err = taylor.energy_balance_error(e)
h.check(err < TOL_ENERGY_EARLY and e["plastic_work"][-1] > 0.1 * e["kinetic"][0],
        f"first {EARLY * 1e6:g} us: kinetic + strain + plastic + viscous work = E(0) = "
        f"{e['kinetic'][0]:.2f} J within {100 * err:.3f} % (plastic work {e['plastic_work'][-1]:.1f} J, "
        f"viscous {e['viscous_work'][-1]:.2f} J)")
h.check(early[1] == early[2], "np 1 and np 2: the same energy file")

# 2. The benchmark.
shapes = {}
for nr in MESHES:
    wd, dt0 = scene(nr) if nr != MESHES[0] else (wd, dt0)
    e = run_to(wd, dt0, taylor.T_END)
    length, radius = (v[-1] for v in taylor.final_shape(e))
    dl, dr = length / taylor.REF_LENGTH - 1, radius / taylor.REF_RADIUS - 1
    shapes[nr] = (length, radius)
    h.check(abs(dl) < TOL_SHAPE and abs(dr) < TOL_SHAPE,
            f"{nr} x {taylor.cells_along(nr)} cells: final length {length * 1e3:.2f} mm ({100 * dl:+.1f} %), "
            f"foot radius {radius * 1e3:.2f} mm ({100 * dr:+.1f} %) against "
            f"{taylor.REF_LENGTH * 1e3:.2f} / {taylor.REF_RADIUS * 1e3:.2f} mm")
    err = taylor.energy_balance_error(e)
    h.check(err < TOL_ENERGY, f"{nr} x {taylor.cells_along(nr)} cells: energy balance within {100 * err:.3f} %")
(la, ra), (lb, rb) = (shapes[nr] for nr in MESHES)
d = max(abs(la / lb - 1), abs(ra / rb - 1))
h.check(d < TOL_MESHES, f"the two meshes agree: length and foot radius within {100 * d:.2f} %")

# 3. A time step that set-up accepts (0.9 of the stable step of the undeformed bar) but that the
# squeezed foot cannot follow: without sub-cycling the run warns, with the figures, before it
# loses stability; with 'substeps auto' (the default) the body sub-cycles from the periodic check
# on (logged) and the energy balance of 1. holds.
wd, dt0 = scene(MESHES[0], "substeps off")
run_to(wd, dt0, EARLY, fraction=0.9)
h.check(SQUEEZED in run_to.text, "'substeps off': at 0.9 of the set-up stable step the run warns "
                                 "that the squeezed elements' stable step fell below the host step")
wd, dt0 = scene(MESHES[0])
e = run_to(wd, dt0, EARLY, fraction=0.9)
changes = re.findall(r"step \d+: stable FE time step \S+ < host time step \S+: (\d+) FE substeps",
                     run_to.text)
err = taylor.energy_balance_error(e)
h.check(SQUEEZED not in run_to.text and changes and max(e["substeps"]) > 1
        and err < TOL_ENERGY_EARLY,
        f"'substeps auto': the squeezed foot is sub-cycled (n up to {max(e['substeps']):g}, "
        f"{len(changes)} changes logged), no warning, energy balance within {100 * err:.3f} %")
