"""Particle contact under LAMMPS with a given stiffness (pair granular 'hooke K_N DAMP' and 'hertz
K_N DAMP'): a sphere hits a clamped FE block (every node fixed: a rigid flat surface) obliquely,
with friction, and the same scene runs against LAMMPS's own fix wall/gran given the same words on
the plane of the block's top face.

1. Normal part: for hooke with the damping models velocity, mass_velocity, viscoelastic,
   coeff_restitution and tsuji, and hertz K_N with coeff_restitution, the normal force history
   and the normal rebound velocity agree with fix wall/gran to 1e-12 of each column's scale (the
   same law: round-off only).
2. hooke with coeff_restitution: the normal rebound over the impact speed is the given e within
   1e-3 (a linear spring-dashpot restores e exactly; only the time step's error remains).
3. Tangential part (linear_history K_T, mindlin K_T, linear_nohistory with friction): with a given
   stiffness the core follows LAMMPS's tangential models (history turned into the tangent plane,
   spring plus damping capped by Coulomb, the contact point at r from the centre), so the
   tangential force, velocity and spin agree with fix wall/gran to 1e-12 of their scale too.
4. Refusals by name: a K_T of NULL with a given K_N, damping mdr, K_T = 0, K_N < 0.
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

R, RHO, V, VX = 0.005, 7800.0, 0.3, 0.1
m = RHO * 4.0 / 3.0 * math.pi * R ** 3
KN = 2e4  # hooke: half period pi sqrt(m/k) = 1.4 ms, overlap ~ 2.7 % of R at 0.3 m/s
KN_HERTZ = 4.0 / 3.0 * 1e7 / (2 * (1 - 0.3 ** 2))  # 4/3 E* of test_contact_hertz's material
t_hooke = math.pi * math.sqrt(m / KN)
print(f"sphere mass {m:.6g} kg; hooke K_N {KN:g}: contact {t_hooke:.4g} s")

wd = tempfile.mkdtemp(prefix="lmp_contact_hooke_")
shutil.copy(os.path.join(lh.INPUTS, "in.given_k_clamped_lammps"), wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 8, 4), (0.04, 0.04, 0.02), (-0.02, -0.02, -0.02))

base = dict(x0=0.0013, y0=0.0007, z0=R + 1e-5, diam=2 * R, v0x=VX, v0z=-V, dt=1e-6, every=10,
            steps=4000, g=0)


def run(surface, normal, damping, tangential, expect_fail=False):
    out = lmp.run("in.given_k_clamped_lammps", workdir=wd, expect_fail=expect_fail,
                  variables=dict(base, surface=surface, normal=normal, damping=damping,
                                 tangential=tangential))
    return out if expect_fail else h.thermo_blocks(out)[-1]


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


# Damping coefficients of about a fifth of critical (2 sqrt(m K_N) = 18 N s/m) for each model's
# own scaling: eta = c, c m, c m a (a ~ sqrt(R delta_max) ~ 8e-4 m).
a_typ = math.sqrt(R * V * math.sqrt(m / KN))
cases = [
    (f"hooke {KN:g} 3", "velocity", "linear_history 1e4 0.5 0.3"),
    (f"hooke {KN:g} {3 / m:.8g}", "mass_velocity", "linear_history 1e4 0.5 0.3"),
    (f"hooke {KN:g} {3 / (m * a_typ):.8g}", "viscoelastic", "mindlin 1e7 0.5 0.3"),
    (f"hooke {KN:g} 0.5", "coeff_restitution", "linear_history 1e4 0.5 0.3"),
    (f"hooke {KN:g} 0.5", "tsuji", "linear_nohistory 0.5 0.3"),
    (f"hertz {KN_HERTZ:.8g} 0.5", "coeff_restitution", "mindlin 1.6e7 0.5 0.3"),
]
for normal, damping, tangential in cases:
    what = f"{normal.split()[0]} damping {damping}, tangential {tangential.split()[0]}"
    fem = run("fem", normal, damping, tangential)
    wall = run("wall", normal, damping, tangential)
    head, rows = fem
    c = head.index("v_contacts")
    h.check(max(r[c] for r in rows) == 1 and rows[-1][c] == 0, f"{what}: one contact, then free")
    agree(f"{what}: fem/body vs fix wall/gran, normal", fem, wall, ["v_fz", "v_vz"])
    e = rows[-1][head.index("v_vz")] / V
    if damping == "coeff_restitution" and normal.startswith("hooke"):
        h.check(abs(e - 0.5) < 1e-3, f"{what}: restitution {e:.6f} (given 0.5)")
    else:
        h.check(0 < e < 1, f"{what}: the sphere rebounds, restitution {e:.4f}")
    k = head.index("v_fx")
    h.check(max(abs(r[k]) for r in rows) > 0.05 * max(abs(r[head.index("v_fz")]) for r in rows),
            f"{what}: friction acts (tangential force up to {max(abs(r[k]) for r in rows):.4g} N)")
    agree(f"{what}: fem/body vs fix wall/gran, tangential", fem, wall, ["v_fx", "v_vx", "v_wy"])

# ---- refusals by name ----
out = run("fem", f"hooke {KN:g} 3", "velocity", "mindlin NULL 0.5 0.3", expect_fail=True)
h.check("tangential mindlin K_T = NULL takes the stiffness from the material" in out,
        "mindlin NULL with a given K_N is refused by name")
out = run("fem", f"hooke {KN:g} 3", "mdr", "linear_history 1e4 0.5 0.3", expect_fail=True)
h.check("damping model 'mdr' is not supported" in out, "damping mdr is refused by name")
out = run("fem", f"hooke {KN:g} 3", "velocity", "linear_history 0 0.5 0.3", expect_fail=True)
h.check("tangential linear_history K_T must be > 0" in out, "K_T = 0 is refused")
out = run("fem", "hooke -1 3", "velocity", "linear_history 1e4 0.5 0.3", expect_fail=True)
h.check("hooke K_N must be > 0" in out, "a negative K_N is refused")
print("test_contact_hooke: all checks passed")
