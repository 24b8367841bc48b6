"""Validation study (not a CI test yet): sphere hitting a large elastic block vs Hertz theory.

Run: python3 bench/validation_hertz.py [--exe build/fracdem]   (about 10 minutes on 2 cores)
Writes bench/results/hertz_convergence.csv. Status and analysis: docs/validation.md.

The sphere and the block are the same material. The contact law carries the sphere's compliance
only (`compliance particle`), the block's compliance comes from its finite elements, so the
combined stiffness must converge to Hertz's E* = 1 / ((1-nu^2)/E + (1-nu^2)/E) as the mesh
resolves the contact radius a. Three graded meshes with fine-zone spacing a/1.5, a/2.5, a/4:
on the finest, peak force and duration within 5% of Hertz, and errors shrink under refinement.
"""
import math
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests', 'integration'))
import harness as h  # noqa: E402

args = h.parse_args()
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

errors = []
for ratio in (1.5, 2.5, 4.0):
    hf = a / ratio
    xs = meshgen.graded_axis(4 * a, hf, 0.03, growth=1.3)
    zs = meshgen.graded_axis(2 * a, hf, 0.02, growth=1.3, symmetric=False)
    wd = tempfile.mkdtemp(prefix=f"hertz_{ratio}_")
    X, E4, G = meshgen.box_tet_mesh_axes(xs, xs, zs)
    meshgen.write_gmsh22(os.path.join(wd, "block.msh"), X, E4, G)
    shutil.copy(os.path.join(os.path.dirname(os.path.abspath(__file__)), "inputs", "in.hertz"), wd)
    gap = 0.02 * dmax
    common = dict(z0=R + gap, diam=2 * R, vz=-v)
    probe = h.run(args.exe, "in.hertz", np_=2, workdir=wd, variables=dict(common, dt=1e-9, steps=0, every=1))
    dt = 0.5 * h.stable_dt(probe)
    steps = int((1.25 * tc + gap / v) / dt)
    out = h.run(args.exe, "in.hertz", np_=2, workdir=wd,
                variables=dict(common, dt=dt, steps=steps, every=2))
    runs = h.thermo_blocks(out)
    step = h.column(runs, "Step")
    fz = [-f for f in h.column(runs, "body[10]")]  # force on the body points down
    on = [s for s, f in zip(step, fz) if f > 0]
    peak = max(fz)
    dur = (on[-1] - on[0] + 2) * dt
    ef, et = abs(peak - Fmax) / Fmax, abs(dur - tc) / tc
    errors.append((ratio, len(E4), ef, et))
    print(f"mesh a/{ratio}: {len(E4)} tets, dt {dt:.3g}: F_max {peak:.4g} N (error {100 * ef:.2f}%), "
          f"duration {dur:.4g} s (error {100 * et:.2f}%)")

os.makedirs(os.path.join(h.ROOT, "bench", "results"), exist_ok=True)
with open(os.path.join(h.ROOT, "bench", "results", "hertz_convergence.csv"), "w") as f:
    f.write("h_over_a,tets,force_error,duration_error\n")
    for r, n, ef, et in errors:
        f.write(f"{1 / r},{n},{ef},{et}\n")
h.check(errors[-1][2] < 0.05, f"finest mesh: peak force error {100 * errors[-1][2]:.2f}% < 5%")
h.check(errors[-1][3] < 0.05, f"finest mesh: duration error {100 * errors[-1][3]:.2f}% < 5%")
h.check(errors[0][2] > errors[-1][2], "peak force error shrinks under refinement")
h.check(errors[0][3] > errors[-1][3], "duration error shrinks under refinement")
