"""A sphere hits a large elastic block of the same material at low speed: peak force and contact
duration against Hertz theory on three graded meshes (contact radius a resolved by a/1.5, a/2.5,
a/4), within 5 % on the finest, the peak force error shrinking from the coarsest to the finest
and the duration error not growing beyond the sampling resolution.

The contact law carries the sphere's compliance (`compliance particle`); the block's comes from
its finite elements, loaded by the contact's Hertz pressure spread over the contact disc, and the
law's contact radius follows the total approach a^2 = R (delta_sphere + delta_block). Hertz's
theory is quasi-static: the peak is taken from the force history averaged over a window of
t_c / 50, which removes the elastic waves ringing in the block's surface nodes (the raw peak is
printed as well). About 2.5 minutes on 2 cores. `--csv FILE` writes the convergence table.
"""
import math
import os
import shutil
import sys
import tempfile

import harness as h

p = h.parser()
p.add_argument("--csv", default=None)
args = h.parse_args(p)
sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import meshgen  # noqa: E402

E, nu, R, rho_s, v = 1e7, 0.3, 0.005, 7800.0, 0.3
m = rho_s * 4.0 / 3.0 * math.pi * R ** 3
Estar = 1.0 / (2 * (1 - nu ** 2) / E)
dmax = (15 * m * v ** 2 / (16 * Estar * math.sqrt(R))) ** 0.4
Fmax = 4.0 / 3.0 * Estar * math.sqrt(R) * dmax ** 1.5
tc = 2.868 * (m ** 2 / (R * Estar ** 2 * v)) ** 0.2
a = math.sqrt(R * dmax)
print(f"Hertz: delta_max {dmax:.4g} m, contact radius {a:.4g} m, F_max {Fmax:.4g} N, duration {tc:.4g} s")

HALF, DEPTH = 0.06, 0.05  # block half-width and depth: 55a and 46a, a half-space to ~1 %
rows = []
for ratio in (1.5, 2.5, 4.0):
    hf = a / ratio
    xs = meshgen.graded_axis(4 * a, hf, HALF, growth=1.3)
    zs = meshgen.graded_axis(2 * a, hf, DEPTH, growth=1.3, symmetric=False)
    wd = tempfile.mkdtemp(prefix=f"hertz_{ratio}_")
    X, E4, G = meshgen.box_tet_mesh_axes(xs, xs, zs)
    meshgen.write_gmsh22(os.path.join(wd, "block.msh"), X, E4, G)
    h.copy_inputs(["in.hertz"], wd)
    gap = 0.02 * dmax
    common = dict(z0=R + gap, diam=2 * R, vz=-v)
    probe = h.run(args.exe, "in.hertz", np_=2, workdir=wd, variables=dict(common, dt=1e-9, steps=0, every=1))
    dt = 0.5 * h.stable_dt(probe)
    every = 2
    steps = int((1.25 * tc + gap / v) / dt)
    out = h.run(args.exe, "in.hertz", np_=2, workdir=wd, variables=dict(common, dt=dt, steps=steps, every=every))
    runs = h.thermo_blocks(out)
    step = h.column(runs, "Step")
    fz = [-f for f in h.column(runs, "body[10]")]  # force on the body points down
    on = [i for i, f in enumerate(fz) if f > 0]
    dur = (step[on[-1]] - step[on[0]] + every) * dt
    window = max(1, int(round(tc / 50 / (every * dt))))
    smooth = [sum(fz[i:i + window]) / window for i in range(len(fz) - window + 1)]
    peak, raw = max(smooth), max(fz)
    ef, et = abs(peak - Fmax) / Fmax, abs(dur - tc) / tc
    rows.append((ratio, len(E4), ef, et, abs(raw - Fmax) / Fmax))
    # the duration is read from sampled forces: each end is known to one sample (every * dt)
    resolution = 2 * every * dt / tc
    print(f"mesh a/{ratio}: {len(E4)} tets, dt {dt:.3g}: F_max {peak:.4g} N (error {100 * ef:.2f}%; "
          f"raw peak {raw:.4g} N, {100 * rows[-1][4]:.2f}%), duration {dur:.4g} s (error {100 * et:.2f}%)")

if args.csv:
    with open(args.csv, "w") as f:
        f.write("h_over_a,tets,force_error,duration_error,raw_peak_force_error\n")
        for r, n, ef, et, er in rows:
            f.write(f"{1 / r:.4f},{n},{ef:.4f},{et:.4f},{er:.4f}\n")
h.check(rows[-1][2] < 0.05, f"finest mesh: peak force error {100 * rows[-1][2]:.2f}% < 5%")
h.check(rows[-1][3] < 0.05, f"finest mesh: contact duration error {100 * rows[-1][3]:.2f}% < 5%")
h.check(rows[-1][2] < rows[0][2], f"peak force error shrinks under refinement "
                                  f"({100 * rows[0][2]:.2f}% -> {100 * rows[-1][2]:.2f}%)")
h.check(rows[-1][3] <= rows[0][3] + resolution,
        f"duration error does not grow under refinement beyond the sampling resolution "
        f"{100 * resolution:.2f}% ({100 * rows[0][3]:.2f}% -> {100 * rows[-1][3]:.2f}%)")
