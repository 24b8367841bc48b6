"""Elastic bar: a velocity step travels at the bar speed sqrt(E/rho) (within 2%).

A free steel bar (L = 1 m, 0.04 x 0.04 section) has its xmin face driven at v0 = 0.01 m/s.
When the front reaches the free end, that end's velocity jumps to 2 v0; the time at which the
mean end velocity crosses v0 (half the jump) is the arrival time L / c_bar. Read from the VTK
time series written by fix fem/vtk (also checks that output).
"""
import glob
import math
import os
import tempfile

import harness as h

args = h.parse_args()
E, rho, L, v0 = 2e11, 7800.0, 1.0, 0.01
c_bar = math.sqrt(E / rho)

import vtk  # noqa: E402
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402


def read_vtu(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    return vtk_to_numpy(g.GetPoints().GetData()), vtk_to_numpy(g.GetPointData().GetArray("velocity"))


for model in ("elastic", "corotational"):
    wd = tempfile.mkdtemp(prefix=f"wave_{model}_")
    X, _ = h.make_box_mesh(os.path.join(wd, "bar.msh"), (50, 2, 2), (L, 0.04, 0.04), (0, -0.02, -0.02))
    h.copy_inputs(["in.bar_wave", "in.fe_common"], wd)
    dt = 1e-6
    steps = int(1.6 * L / c_bar / dt)
    out = h.run(args.exe, "in.bar_wave", np_=1, workdir=wd,
                variables=dict(dt=dt, nu=0.25, model=model, steps=steps))
    files = sorted(glob.glob(os.path.join(wd, "bar_*.vtu")))
    h.check(len(files) == steps // 5 + 1, f"{model}: one VTU file per output step ({len(files)})")
    h.check(os.path.exists(os.path.join(wd, "bar.pvd")), f"{model}: .pvd series index written")
    end = X[:, 0] > L - 1e-9
    t_prev, v_prev, t_arrive = None, None, None
    for f in files:
        step = int(os.path.basename(f)[4:-4])
        _, vel = read_vtu(f)
        vend = vel[end, 0].mean()
        t = step * dt
        if v_prev is not None and v_prev < v0 <= vend:
            t_arrive = t_prev + (v0 - v_prev) / (vend - v_prev) * (t - t_prev)
            break
        t_prev, v_prev = t, vend
    h.check(t_arrive is not None, f"{model}: wave front reached the free end")
    c_meas = L / t_arrive
    err = abs(c_meas - c_bar) / c_bar
    h.check(err < 0.02, f"{model}: measured wave speed {c_meas:.1f} m/s vs sqrt(E/rho) = {c_bar:.1f} m/s "
                        f"(error {100 * err:.2f}% < 2%)")
