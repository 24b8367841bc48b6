"""Axis shield of `plane axisymmetric` bodies (issue #10, deliverable 4): a soft ring (r from 2 to
12 mm, 10 mm high, tri3; E 1e7, rho 1000) thrown at the axis at 50 m/s implodes onto it.

Asserted:
* no node ever has r < 0 (every fix fem/vtk frame, when the vtk module is there);
* the shield acts (shield_work < 0 in the energy file, equal to the fix vector's element after the
  eroded ones, f_ID[23] with no fixed group);
* the energy balance kinetic + strain = initial kinetic + shield work closes within 1 % of the
  initial kinetic energy at every row (the figure is printed);
* np 1 and np 2 give the same energy history.
"""
import glob
import math
import os
import sys
import tempfile

import harness as h

args = h.parse_args()
wd = tempfile.mkdtemp(prefix="axis_shield_")
h.copy_inputs(["in.fe_common_2d"], wd)
h.make_rect_mesh(os.path.join(wd, "ring.msh"), (10, 10), (0.01, 0.01), origin=(0.002, 0.0))
with open(os.path.join(wd, "in.ring"), "w") as f:
    f.write("include in.fe_common_2d\ntimestep 2e-7\n"
            "fix ring all fem/body file ring.msh type 2 density 1000 youngs 1e7 poisson 0.3 "
            "plane axisymmetric gravity no velocity all -50 0 0 energy_file ring.csv 20\n"
            "fix vtk all fem/vtk 100 frame body ring\n"
            "thermo_style custom step f_ring[1] f_ring[2] f_ring[23]\n"
            "thermo_modify format float %.12g\nthermo 100\nrun 2000\n")

histories = {}
for np_ in (1, 2):
    out = h.run(args.exe, "in.ring", np_=np_, workdir=wd)
    e = h.read_csv(os.path.join(wd, "ring.csv"))
    histories[np_] = e
    e0 = e["kinetic"][0]
    worst = max(abs(k + s - e0 - w) for k, s, w in zip(e["kinetic"], e["strain"], e["shield_work"]))
    h.check(e["shield_work"][-1] < 0 and worst / e0 < 0.01,
            f"np {np_}: shield work {e['shield_work'][-1]:.4g} J ({100 * e['shield_work'][-1] / e0:.1f} % "
            f"of the initial {e0:.4g} J); kinetic + strain = initial + shield work within "
            f"{100 * worst / e0:.2g} %")
    runs = h.thermo_blocks(out)
    h.check(abs(h.column(runs, "ring[23]")[-1] - e["shield_work"][-1]) <= 1e-9 * abs(e0),
            f"np {np_}: f_ring[23] is the shield work")

h.check(histories[1] == histories[2], "np 1 and np 2: the same energy history")

try:
    sys.path.insert(0, os.path.join(h.ROOT, "python"))
    from fracdem import fem

    import vtk  # noqa: F401
except ImportError:
    print("skip: no vtk module, node positions not checked")
else:
    frames = sorted(glob.glob(os.path.join(wd, "frame_*.vtu")))
    r_min = min(float(fem.read_vtu(p)["points"][:, 0].min()) for p in frames)
    h.check(len(frames) >= 20 and r_min >= 0.0 and r_min < 1e-4,
            f"{len(frames)} frames: the ring reaches the axis and no node crosses it "
            f"(smallest r {r_min:.3g} m)")
