"""Particle contact under LAMMPS: a sphere hits a clamped FE block (every node fixed, so a rigid
flat surface of the sphere's material, `compliance combined`).

1. Hertz: elastic impact (restitution 1) at 0.3 m/s, the material of
   tests/integration/test_hertz_impact.py (E 1e7, nu 0.3, R 5 mm, rho 7800): peak force and
   contact duration against Hertz's theory (Johnson, Contact Mechanics, sec. 11.4: t_c =
   2.868 (m^2 / (R E*^2 v))^(1/5)) within 1 %. That test allows 5 % for a deformable block whose
   compliance the mesh must resolve; here the surface is rigid and flat, only the time step
   discretises the impact. The LIGGGHTS run of the same scene (same mesh, dt, material) agrees
   with the LAMMPS run to 1e-12 of each column's scale: both hosts call the same core law, and
   LAMMPS's and LIGGGHTS's fix nve/sphere do the same arithmetic (v += dt/2 f/m, x += dt v,
   omega += dt/2 torque/(0.4 m r^2)).
2. The mapping of the law onto LAMMPS's own: the same oblique impact (restitution 0.5, friction
   0.3) against LAMMPS's fix wall/gran with the same 'granular hertz/material ...' words on the
   plane of the block's top face, for damping coeff_restitution and tsuji. Normal force and
   velocity agree to 1e-12; the tangential force, velocity and spin are the core's (LIGGGHTS's)
   and differ from fix wall/gran's by a few percent (printed; the rebound's tangential velocity
   and spin are bounded here at 6 %).
3. History migrates with the atom: a sphere slides and rolls across the boundary between two
   ranks (processors 2 1 1); its trajectory at 2 ranks equals the one at 1 rank to 1e-12.
"""
import math
import os
import shutil
import tempfile

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)
TOL = 1e-12

E, NU, R, RHO, V = 1e7, 0.3, 0.005, 7800.0, 0.3
m = RHO * 4.0 / 3.0 * math.pi * R ** 3
Estar = E / (2 * (1 - NU ** 2))  # sphere on a rigid surface of the same material
dmax = (15 * m * V ** 2 / (16 * Estar * math.sqrt(R))) ** 0.4
Fmax = 4.0 / 3.0 * Estar * math.sqrt(R) * dmax ** 1.5
tc = 2.868 * (m ** 2 / (R * Estar ** 2 * V)) ** 0.2
# The core's tangential damping ratio, 2 sqrt(G*/E*) (the same for both moduli mixed).
XT = 2 * math.sqrt((1 - NU) / (2 * (2 - NU)))
print(f"Hertz: F_max {Fmax:.6g} N, t_c {tc:.6g} s, delta_max {dmax:.4g} m; XT {XT:.6f}")

wd = tempfile.mkdtemp(prefix="lmp_contact_hertz_")
for name in ("in.hertz_clamped_lammps", "in.hertz_clamped_liggghts"):
    shutil.copy(os.path.join(lh.INPUTS, name), wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 8, 4), (0.04, 0.04, 0.02), (-0.02, -0.02, -0.02))


def lammps(surface, np_=1, damping="coeff_restitution", tangential="linear_nohistory 0 0", **var):
    out = lmp.run("in.hertz_clamped_lammps", np_=np_, workdir=wd,
                  variables=dict(var, surface=surface, damping=damping, tangential=tangential))
    return h.thermo_blocks(out)[-1]


def liggghts(**var):
    return h.thermo_blocks(h.run(args.exe, "in.hertz_clamped_liggghts", workdir=wd, variables=var))[-1]


def agree(what, a, b, columns, tol=TOL):
    """Largest difference of the named columns relative to each column's scale."""
    (ha, ra), (hb, rb) = a, b
    h.check(len(ra) == len(rb), f"{what}: {len(ra)} and {len(rb)} rows")
    worst = 0.0
    for name in columns:
        ka, kb = ha.index(name), hb.index(name)
        scale = max(max(abs(r[ka]) for r in ra), 1e-300)
        worst = max(worst, max(abs(x[ka] - y[kb]) for x, y in zip(ra, rb)) / scale)
    h.check(worst <= tol, f"{what}: {', '.join(columns)} agree to {worst:.2e} of the column "
                          f"scale (<= {tol:g})")
    return worst


# ---- 1. Hertz's impact, both hosts ----
gap = 0.02 * dmax
dt, every = tc / 2000, 1
steps = int((1.25 * tc + gap / V) / dt)
var = dict(x0=0.0013, y0=0.0007, z0=R + gap, diam=2 * R, v0x=0, v0z=-V, dt=dt, every=every,
           steps=steps, cor=1.0, mu=0.0, g=0)
run_lmp = lammps("fem", **var)
header, rows = run_lmp
fz = [r[header.index("v_fz")] for r in rows]
on = [i for i, f in enumerate(fz) if f > 0]
duration = (rows[on[-1]][0] - rows[on[0]][0] + every) * dt
peak = max(fz)
h.check(abs(rows[0][header.index("v_m")] - m) < 1e-12 * m, f"sphere mass {m:.6g} kg")
h.check(abs(peak - Fmax) < 0.01 * Fmax,
        f"LAMMPS: peak force {peak:.6g} N vs Hertz {Fmax:.6g} N ({100 * (peak / Fmax - 1):+.3f} %)")
h.check(abs(duration - tc) < 0.01 * tc, f"LAMMPS: contact duration {duration:.6g} s vs Hertz "
                                        f"{tc:.6g} s ({100 * (duration / tc - 1):+.3f} %)")
vz_after = rows[-1][header.index("v_vz")]
h.check(abs(vz_after - V) < 1e-3 * V, f"LAMMPS: rebound speed {vz_after:.6g} m/s (elastic: {V})")
run_lig = liggghts(**var)
# same columns in the same order (LIGGGHTS drops the v_ prefixes)
agree("Hertz impact, LAMMPS vs LIGGGHTS", run_lmp, (header, run_lig[1]), ["v_contacts", "v_fz", "v_vz"])

# ---- 2. the law against LAMMPS's fix wall/gran, oblique, with friction ----
var = dict(var, v0x=0.1, cor=0.5, mu=0.3, dt=1e-6, every=10, steps=3000)
tang = f"mindlin NULL {XT:.6f} 0.3"
for damping in ("coeff_restitution", "tsuji"):
    fem = lammps("fem", damping=damping, tangential=tang, **var)
    wall = lammps("wall", damping=damping, tangential=tang, **var)
    k = fem[0].index("v_vz")
    h.check(fem[1][-1][k] > 0, f"{damping}: the sphere rebounds ({fem[1][-1][k]:.6g} m/s)")
    agree(f"{damping}: fem/body vs fix wall/gran, normal", fem, wall, ["v_fz", "v_vz"])
    c = fem[0].index("v_fx")
    dfx = max(abs(a[c] - b[c]) for a, b in zip(fem[1], wall[1])) / max(abs(r[c]) for r in wall[1])
    for name in ("v_vx", "v_wy"):
        c = fem[0].index(name)
        a, b = fem[1][-1][c], wall[1][-1][c]
        h.check(abs(a - b) < 0.06 * abs(b),
                f"{damping}: {name[2:]} after the bounce {a:.6g}, fix wall/gran {b:.6g} "
                f"({100 * (a / b - 1):+.2f} %; the core's tangential law is LIGGGHTS's; "
                f"tangential force history within {100 * dfx:.1f} % of its peak)")
    if damping == "coeff_restitution":  # LIGGGHTS has the restitution law only
        lig = liggghts(**var)
        agree("oblique impact with friction, LAMMPS vs LIGGGHTS", fem, (fem[0], lig[1]),
              ["v_contacts", "v_fz", "v_fx", "v_vz", "v_vx", "v_wy"])

# ---- 3. history migrates between ranks: slide and roll across x = 0 (processors 2 1 1) ----
var = dict(var, x0=-0.004, y0=0.0007, z0=R, v0x=0.2, v0z=0, cor=0.5, g=9.81, dt=2e-6,
           every=500, steps=20000)
one = lammps("fem", 1, tangential=tang, **var)
two = lammps("fem", 2, tangential=tang, **var)
wy = [r[one[0].index("v_wy")] for r in one[1]]
h.check(max(abs(w) for w in wy) > 10, f"the sphere spins up by friction (omega_y up to {max(wy):.4g} 1/s)")
x_end = one[1][-1][one[0].index("v_x")]
h.check(x_end > 0.001, f"it crosses x = 0, the boundary between the two ranks (ends at x = {x_end:.4f} m)")
agree("sliding across ranks, np 2 vs np 1", one, two,
      ["v_contacts", "v_fz", "v_fx", "v_vx", "v_wy", "v_x"])
