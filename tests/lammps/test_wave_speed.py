"""The validation case "wave speed" under LAMMPS: an elastic bar's velocity step travels at the bar
speed sqrt(E/rho) within 2 % (the tolerance of tests/integration/test_fem_wave_speed.py), and the
LAMMPS run agrees with the LIGGGHTS run of that test's own input.

A free steel bar (L = 1 m, 0.04 x 0.04 section, 50 x 2 x 2 cells) has its xmin face driven at
v0 = 0.01 m/s; the time at which the mean velocity of the free end crosses v0 (half its jump to
2 v0) is the arrival time L / c_bar. Read from the fix fem/vtk series of each host (every 5
steps). Both hosts run the same core integration: the arrival times must agree to 1e-9 relative
and the end velocities of every frame to 1e-12 of v0.
"""
import glob
import math
import os
import shutil
import sys
import tempfile

import numpy as np

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)
sys.path.insert(0, os.path.join(lh.ROOT, "python"))
from fracdem.fem import read_vtu  # noqa: E402

E, rho, L, v0 = 2e11, 7800.0, 1.0, 0.01
c_bar = math.sqrt(E / rho)
DT = 1e-6
STEPS = int(1.6 * L / c_bar / DT)


def end_velocities(wd, X):
    """(time, mean x-velocity of the free end) per frame of bar_*.vtu."""
    end = X[:, 0] > L - 1e-9
    out = []
    for f in sorted(glob.glob(os.path.join(wd, "bar_*.vtu"))):
        step = int(os.path.basename(f)[4:-4])
        out.append((step * DT, float(read_vtu(f)["point_data"]["velocity"][end, 0].mean())))
    return out


def arrival(series):
    for (t0, v_a), (t1, v_b) in zip(series, series[1:]):
        if v_a < v0 <= v_b:
            return t0 + (v0 - v_a) / (v_b - v_a) * (t1 - t0)
    return None


def run(host, model):
    wd = tempfile.mkdtemp(prefix=f"lmp_wave_{host}_{model}_")
    X, _ = h.make_box_mesh(os.path.join(wd, "bar.msh"), (50, 2, 2), (L, 0.04, 0.04),
                           (0, -0.02, -0.02))
    var = dict(dt=DT, nu=0.25, model=model, steps=STEPS)
    if host == "liggghts":  # the integration test's own input
        h.copy_inputs(["in.bar_wave", "in.fe_common"], wd)
        h.run(args.exe, "in.bar_wave", np_=1, workdir=wd, variables=var)
    else:
        for name in ("in.lammps_preamble", "in.bar_wave_lammps"):
            shutil.copy(os.path.join(lh.INPUTS, name), wd)
        lmp.run("in.bar_wave_lammps", np_=1, workdir=wd, variables=var)
    series = end_velocities(wd, X)
    h.check(len(series) == STEPS // 5 + 1 and os.path.exists(os.path.join(wd, "bar.pvd")),
            f"{host} {model}: {len(series)} VTU frames (one per 5 steps) and bar.pvd")
    return series


for model in ("elastic", "corotational"):
    ref, out = run("liggghts", model), run("lammps", model)
    t_ref, t_out = arrival(ref), arrival(out)
    h.check(t_out is not None and t_ref is not None, f"{model}: the front reached the free end")
    c_meas = L / t_out
    err = abs(c_meas - c_bar) / c_bar
    h.check(err < 0.02, f"{model}: LAMMPS wave speed {c_meas:.1f} m/s vs sqrt(E/rho) = "
                        f"{c_bar:.1f} m/s (error {100 * err:.2f}% < 2%)")
    h.check(abs(t_out - t_ref) <= 1e-9 * t_ref,
            f"{model}: arrival time {t_out:.9e} s under LAMMPS, {t_ref:.9e} s under LIGGGHTS")
    dv = max(abs(a[1] - b[1]) for a, b in zip(ref, out))
    h.check(len(ref) == len(out) and dv <= 1e-12 * v0,
            f"{model}: end velocity of all {len(out)} frames agrees, largest difference "
            f"{dv:.2e} m/s (<= {1e-12 * v0:g})")
