"""An FE-only body gives the same energy history under LAMMPS (plugin) as under LIGGGHTS (build/fracdem).

Both hosts drive the same core code (fracdem::Body) with the same velocity-Verlet split: half kick
+ drift in initial_integrate, forces in post_force, half kick in final_integrate, and both
evaluate the forces once more in setup(). Built with the same compiler and flags, the two
histories agree to the last bit; the tolerance below (1e-12 relative to the largest value of the
column) leaves room only for a different compiler or reduction order, never for a different
integration scheme (a shifted half step would differ at O(dt), ~1e-2 here).

Scenes: the free vibrating block of test_fem_energy_drift (elastic, corotational) and a bar driven
at one end under gravity with a partial support (prescribed velocity, fixed components, reactions,
external and boundary work), at 1 and 2 MPI ranks of each host.
"""
import os
import shutil
import tempfile

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)
TOL = 1e-12


def scene_dir(scene):
    wd = tempfile.mkdtemp(prefix=f"lmp_match_{scene}_")
    for name in ("in.lammps_preamble", "in.liggghts_preamble", f"in.{scene}"):
        shutil.copy(os.path.join(lh.INPUTS, name), wd)
    h.copy_inputs(["in.fe_common"], wd)
    if scene == "vibration":
        h.make_box_mesh(os.path.join(wd, "block.msh"), (4, 3, 2), (0.2, 0.1, 0.05))
    else:
        h.make_box_mesh(os.path.join(wd, "bar.msh"), (20, 2, 2), (0.4, 0.04, 0.04), (0, -0.02, -0.02))
    return wd


def history(text):
    header, rows = h.thermo_blocks(text)[-1]
    return header, rows


def compare(scene, model, np_, dt, steps, thermo):
    wd = scene_dir(scene)
    var = dict(model=model, dt=dt, steps=steps, thermo=thermo)
    ref = h.run(args.exe, f"in.{scene}", np_=np_, workdir=wd, variables=dict(var, host="liggghts"))
    out = lmp.run(f"in.{scene}", np_=np_, workdir=wd, variables=dict(var, host="lammps"))
    h_ref, rows_ref = history(ref)
    h_out, rows_out = history(out)
    what = f"{scene} {model} np {np_}"
    h.check(len(rows_ref) == len(rows_out) == steps // thermo + 1,
            f"{what}: {len(rows_out)} thermo rows under LAMMPS, {len(rows_ref)} under LIGGGHTS")
    worst = 0.0
    for k in range(1, len(h_ref)):
        scale = max(max(abs(r[k]) for r in rows_ref), 1e-300)
        for a, b in zip(rows_ref, rows_out):
            worst = max(worst, abs(a[k] - b[k]) / scale)
    kinetic = [r[1] for r in rows_out]
    h.check(max(kinetic) > 0, f"{what}: the body moves (kinetic energy up to {max(kinetic):.4g} J)")
    if scene == "bar":  # column 3: external work, done by gravity through LAMMPS's fix gravity
        work = max(abs(r[3]) for r in rows_out)
        h.check(work > 0, f"{what}: fix gravity acts on the body (external work {work:.3g} J)")
    h.check(worst <= TOL, f"{what}: {len(h_ref) - 1} columns x {len(rows_ref)} rows agree, "
                          f"largest difference {worst:.2e} of the column scale (<= {TOL:g})")
    return worst


# The block's stable step is about 2.2e-6 s; the bar's about 2.1e-6 s.
for np_ in (1, 2):
    for model in ("elastic", "corotational"):
        compare("vibration", model, np_, dt=1e-6, steps=1000, thermo=25)
    compare("bar", "corotational", np_, dt=1e-6, steps=400, thermo=20)
