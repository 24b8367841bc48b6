"""Bulk viscosity and the plastic state in a high-velocity impact (issue #10): the sphere of
test_fast_impact (20 mm, rho 2500) hits the clamped steel block (10 x 10 x 5 cells of tets), here J2
plastic (yield 5e8, hardening 2e9), at dt 1e-8.

Asserted:
* the body's energy balance kinetic + strain + plastic work + viscous work = contact work closes
  within 1 % of the impact energy at every row of the energy file, with the bulk viscosity on (the
  default for a plastic body) and off, at 600 and 1500 m/s; the viscosity takes work (> 0);
* with the viscosity the impact is no less stable: at 3000 m/s both runs go through and the balance
  is no worse with it; the stable step at set-up is reduced by sqrt(1 + Q1^2) - Q1;
* energy file and fix fem/vtk carry the plastic columns / cell fields for the plastic body, not for
  an elastic one; an elastic run is bit for bit the same with 'bulk_viscosity off' as by default;
* a restart of the plastic body (viscosity on) continues bit for bit as the straight run;
* a 1D shock (uniaxial-strain bar, 80 cells, hit by a piston at 100 m/s): the particle velocity at
  mid-bar overshoots its final value less with the viscosity than without.
About a minute.
"""
import math
import os
import re
import sys
import tempfile

import harness as h

args = h.parse_args()
wd = tempfile.mkdtemp(prefix="bulk_viscosity_")
h.copy_inputs(["in.fast_impact", "in.fe_common"], wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (10, 10, 5), (0.1, 0.1, 0.05))
R, RHO = 0.01, 2500.0
MASS = RHO * 4.0 / 3.0 * math.pi * R ** 3
J2 = "fixed zmin material j2 yield 5e8 hardening 2e9"


def impact(v, body, name, steps=2500, expect_fail=False):
    kw = f"{body} energy_file {name}.csv 10"
    out = h.run(args.exe, "in.fast_impact", workdir=wd, expect_fail=expect_fail,
                variables=dict(v=v, dt=1e-8, x0=0.05, y0=0.05, bodykw=kw, steps=steps, every=250))
    return out, (None if expect_fail else h.read_csv(os.path.join(wd, f"{name}.csv")))


def worst_balance(e, v):
    """Largest |kinetic + strain + plastic + viscous - contact work| over the rows / impact energy."""
    visc = e.get("viscous_work", [0.0] * len(e["step"]))
    worst = 0.0
    for k in range(len(e["step"])):
        lhs = e["kinetic"][k] + e["strain"][k] + e["plastic_work"][k] + visc[k]
        worst = max(worst, abs(lhs - e["contact_work"][k] - e["external_work"][k]))
    return worst / (0.5 * MASS * v * v)


for v in (600, 1500):
    out_on, on = impact(v, J2, f"on_{v}")
    out_off, off = impact(v, J2 + " bulk_viscosity off", f"off_{v}")
    b_on, b_off = worst_balance(on, v), worst_balance(off, v)
    wv, wp = on["viscous_work"][-1], on["plastic_work"][-1]
    E0 = 0.5 * MASS * v * v
    h.check("bulk viscosity 0.06 1.2" in out_on and "bulk viscosity" not in out_off,
            f"{v} m/s: the plastic body has bulk viscosity 0.06 1.2 by default, 'off' turns it off")
    h.check(b_on < 0.01 and b_off < 0.01,
            f"{v} m/s: kinetic + strain + plastic + viscous work = contact work within 1 % of the "
            f"impact energy (worst {100 * b_on:.3f} % with viscosity, {100 * b_off:.3f} % without)")
    h.check(wv > 0 and "viscous_work" not in off,
            f"{v} m/s: viscous work {wv:.4g} J ({100 * wv / E0:.2f} % of the impact energy; plastic "
            f"work {100 * wp / E0:.1f} %), no viscous column without viscosity")

# 3000 m/s: both run through (the J2 block does not collapse even without viscosity); with the
# viscosity the balance is no worse and the stable step at set-up is the undamped one times
# sqrt(1 + Q1^2) - Q1 (no compression yet: only the linear part damps).
out_off, off = impact(3000, J2 + " bulk_viscosity off", "off_3000")
out_on, on = impact(3000, J2, "on_3000")
b_on, b_off = worst_balance(on, 3000), worst_balance(off, 3000)
h.check(b_on < 0.01 and b_on <= b_off + 5e-4,
        f"3000 m/s: runs through with and without viscosity, balance within 1 % and no worse with "
        f"it ({100 * b_on:.3f} % vs {100 * b_off:.3f} %)")
dt_on, dt_off = h.stable_dt(out_on), h.stable_dt(out_off)
factor = math.sqrt(1 + 0.06 ** 2) - 0.06
h.check(abs(dt_on / dt_off - factor) < 1e-5,
        f"stable FE step with viscosity {dt_on:.6g} = {dt_off:.6g} x (sqrt(1 + Q1^2) - Q1) = "
        f"{dt_off * factor:.6g}")

# Elastic bodies: viscosity off by default, results bit for bit as with 'bulk_viscosity off'.
out_def, el = impact(600, "fixed zmin", "elastic_default", steps=600)
out_off, el_off = impact(600, "fixed zmin bulk_viscosity off", "elastic_off", steps=600)
h.check(h.thermo_blocks(out_def) == h.thermo_blocks(out_off) and el == el_off and "fracture_energy" in el
        and "plastic_work" not in el and "viscous_work" not in el,
        "elastic: no viscosity by default (thermo and energy file identical to 'bulk_viscosity off'; "
        "columns fracture_energy, no plastic_work / viscous_work)")

# fix fem/vtk: plastic fields for the plastic body only.
sys.path.insert(0, os.path.join(h.ROOT, "python"))
try:
    import vtk  # noqa: F401
    have_vtk = True
except ImportError:
    have_vtk = False
for name, body in (("plastic", J2), ("elastic", "fixed zmin")):
    with open(os.path.join(wd, "in.fast_impact")) as f:
        text = f.read().replace("run ", f"fix vtk all fem/vtk 300 vtk_{name} body body\nrun ", 1)
    with open(os.path.join(wd, f"in.vtk_{name}"), "w") as f:
        f.write(text)
    h.run(args.exe, f"in.vtk_{name}", workdir=wd,
          variables=dict(v=600, dt=1e-8, x0=0.05, y0=0.05, bodykw=body, steps=600, every=300))
    frame = os.path.join(wd, f"vtk_{name}_0000000600.vtu")
    with open(frame, "rb") as f:
        head = f.read(20000).decode("latin-1")
    names = set(re.findall(r'Name="([a-z_]+)"', head))
    wanted = {"plastic_strain", "temperature_rise", "plastic_work"}
    h.check(wanted <= names if name == "plastic" else not (wanted & names),
            f"fem/vtk {name}: cell fields {sorted(wanted & names) or 'without plastic fields'}")
    if have_vtk and name == "plastic":
        from fracdem import fem

        d = fem.read_vtu(frame)["cell_data"]
        h.check(max(d["plastic_strain"]) > 0.01 and max(d["temperature_rise"]) == 0
                and max(d["plastic_work"]) > 0,
                f"fem/vtk plastic: max plastic strain {max(d['plastic_strain']):.3f}, plastic work "
                f"density {max(d['plastic_work']):.3g} J/m^3, no heating without cp")

# Restart of the plastic body (viscosity on): continued run = straight run, bit for bit.
PRE = """atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
hard_particles yes
region box block -0.05 0.15 -0.05 0.15 -0.01 0.2 units box
create_box 2 box
"""
MAT = """neighbor 0.002 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 2e11 2e11
fix m2 all property/global poissonsRatio peratomtype 0.3 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 2 1.0 1.0 1.0 1.0
fix m4 all property/global coefficientFriction peratomtypepair 2 0.0 0.0 0.0 0.0
pair_style gran model hertz tangential history
pair_coeff * *
timestep 1e-8
fix body all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 """ + J2 + """
"""
OUT = """fix integr all nve/sphere
compute ke all ke
thermo_style custom step c_ke f_body[1] f_body[2] f_body[4] f_body[16] f_body[11]
thermo_modify format float %.17g
thermo 100
"""
with open(os.path.join(wd, "in.restart_a"), "w") as f:
    f.write(PRE + MAT + "create_atoms 1 single 0.05 0.05 0.0605 units box\n"
            "set atom 1 diameter 0.02 density 2500\nvelocity all set 0 0 -600 units box\n"
            + OUT + "run 700\nwrite_restart plastic.restart\nrun 700\n")
with open(os.path.join(wd, "in.restart_b"), "w") as f:
    f.write("read_restart plastic.restart\nnewton off\ncommunicate single vel yes\n"
            "hard_particles yes\n" + MAT + OUT
            + "run 700\n")
a = h.run(args.exe, "in.restart_a", workdir=wd)
b = h.run(args.exe, "in.restart_b", workdir=wd)
rows = lambda text: [l.split() for l in text.split("Step")[-1].splitlines()[1:]
                     if l.split() and l.split()[0].isdigit()]
ra, rb = rows(a), rows(b)
h.check(len(ra) == len(rb) == 8 and ra == rb and float(ra[-1][5]) > 0,
        f"plastic restart: the continued run equals the straight one bit for bit ({len(rb)} rows, "
        f"dissipated {float(rb[-1][5]):.6g} J at step {rb[-1][0]})")

# 1D shock: uniaxial-strain bar (80 x 1 x 1 cells, lateral components held), piston at xmin.
sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import meshgen  # noqa: E402

NX, L, A, VP, DT = 80, 0.2, 0.0025, 100.0, 2.5e-8
X, E, G = meshgen.box_tet_mesh(NX, 1, 1, L, A, A, origin=(0.0, 0.0, 0.0))
i_mid = NX // 2
G["mid"] = [[n for n in range(len(X)) if abs(X[n][0] - i_mid * L / NX) < 1e-9][:4]]
G["mid"] = [[G["mid"][0][k] for k in (0, 1, 3, 2)]]
meshgen.write_gmsh22(os.path.join(wd, "bar.msh"), X, E, G)


def shock(extra, name):
    with open(os.path.join(wd, f"in.{name}"), "w") as f:
        f.write("include in.fe_common\ntimestep %g\n" % DT
                + "fix bar all fem/body file bar.msh type 2 density 7800 youngs 2e11 poisson 0.3 "
                  "material j2 yield 5e8 hardening 2e9 prescribed_velocity xmin %g 0 0 " % VP
                + "fixed ymin y fixed ymax y fixed zmin z fixed zmax z fixed mid y z "
                + f"{extra} energy_file {name}.csv 4\nrun 1800\n")
    h.run(args.exe, f"in.{name}", workdir=wd)
    e = h.read_csv(os.path.join(wd, f"{name}.csv"))
    u, t = e["displacement_mid_x"], e["time"]
    vel = [(u[k + 1] - u[k]) / (t[k + 1] - t[k]) for k in range(len(u) - 1)]
    return max(vel) / VP - 1


over_on, over_off = shock("", "shock_on"), shock("bulk_viscosity off", "shock_off")
h.check(over_on < 0.75 * over_off,
        f"1D shock: the particle velocity at mid-bar overshoots its final {VP:g} m/s by "
        f"{100 * over_on:.1f} % with the viscosity, {100 * over_off:.1f} % without")
