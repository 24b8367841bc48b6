"""Particle contact under LAMMPS conserves momentum: a sphere hits a free elastic block obliquely,
with friction and damping (the scene of tests/integration/test_contact_momentum.py), no gravity,
no walls. Total linear momentum, particle (mass(all) * vcm(all)) plus body (f_body[13..15]),
stays at its initial value to round-off at 1 and 2 ranks, elastic and corotational: the core
adds each contact force to the particle and its reaction to the facet's nodes by the contact
point's barycentric weights, and the ranks sum the nodal reactions.

The same run under LIGGGHTS (property/global materials of in.fe_common; under LAMMPS the same law
after 'contact') gives the same history to 1e-12 of each column's scale: same core, same
integration.
"""
import os
import shutil
import tempfile

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)

wd = tempfile.mkdtemp(prefix="lmp_contact_momentum_")
for name in ("in.momentum", "in.lammps_preamble", "in.liggghts_preamble", "in.lammps_law",
             "in.liggghts_law"):
    shutil.copy(os.path.join(lh.INPUTS, name), wd)
h.copy_inputs(["in.fe_common"], wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (6, 6, 3), (0.2, 0.1, 0.05))

STEPS, EVERY = 20000, 100
runs = {}
for model in ("elastic", "corotational"):
    for np_ in (1, 2):
        out = lmp.run("in.momentum", np_=np_, workdir=wd,
                      variables=dict(host="lammps", model=model, steps=STEPS, every=EVERY))
        header, rows = h.thermo_blocks(out)[-1]
        runs[model, np_] = (header, rows)
        col = lambda name: [r[header.index(name)] for r in rows]  # noqa: E731
        what = f"{model} np {np_}"
        h.check(max(col("f_body[7]")) >= 1, f"{what}: the sphere touched the body")
        h.check(min(col("Atoms")) == 1, f"{what}: no particle lost")
        h.check(col("f_body[1]")[-1] > 0, f"{what}: the body moves after the impact "
                                          f"(kinetic energy {col('f_body[1]')[-1]:.3g} J)")
        vz = col("v_vpz")
        h.check(vz[-1] > 0, f"{what}: the sphere bounced (vz {vz[0]:.3g} -> {vz[-1]:.4g} m/s)")
        for comp in ("v_px", "v_py", "v_pz"):
            p = col(comp)
            worst = max(abs(x - p[0]) for x in p) / max(abs(x) for x in p)
            h.check(worst < 1e-12, f"{what}: total {comp[3]}-momentum conserved, largest relative "
                                   f"change {worst:.1e}")

# np 2 against np 1, and against LIGGGHTS
for model in ("elastic", "corotational"):
    (ha, ra), (hb, rb) = runs[model, 1], runs[model, 2]
    worst = max(abs(x - y) / max(max(abs(r[k]) for r in ra), 1e-300)
                for k in range(1, len(ha)) for x, y in ((a[k], b[k]) for a, b in zip(ra, rb)))
    h.check(worst < 1e-9, f"{model}: np 2 equals np 1 to {worst:.1e} of the column scale")
ref = h.thermo_blocks(h.run(args.exe, "in.momentum", np_=2, workdir=wd,
                            variables=dict(host="liggghts", model="elastic", steps=STEPS,
                                           every=EVERY)))[-1]
header, rows = runs["elastic", 2]
h.check(len(ref[1]) == len(rows), f"LIGGGHTS: {len(ref[1])} rows, LAMMPS: {len(rows)}")
worst = max(abs(x - y) / max(max(abs(r[k]) for r in rows), 1e-300)
            for k in range(1, len(header)) for x, y in ((a[k], b[k]) for a, b in zip(rows, ref[1])))
h.check(worst <= 1e-12, f"elastic np 2: all {len(header) - 1} columns equal the LIGGGHTS run to "
                        f"{worst:.1e} of the column scale (<= 1e-12)")
