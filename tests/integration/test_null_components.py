"""`prescribed_velocity ... NULL` leaves a component free and `velocity ... NULL` leaves it as it
was (LAMMPS convention).

A plane-stress elastic square (L = W = t = 0.05 m, E 30 GPa, nu 0.4, tri3) is held at xmin in x
and along ymin in y, and pulled at xmax with `prescribed_velocity xmax 0.1 NULL NULL ramp 1e-4`:
nothing holds its lateral contraction, so it is in uniaxial stress and the axial reaction is
E W t / L times the mean xmax displacement. The slope of reaction against displacement over the
constant-velocity part (some 40 wave transits, which averages the ringing of the ramp) must be
E W t / L within 2 %. The same bar with `0.1 0 0` (lateral held at the pulled end: the full
prescription) must be stiffer by more than 2 % and by less than the bound of a bar whose lateral
strain is held everywhere (uniaxial strain in plane stress, E / (1 - nu^2): +19 %).
The NULL run reports 0 as the prescribed group's lateral reaction in every row, the held run a
lateral reaction. Both close the energy balance of docs/fix_fem_body.md (kinetic + strain =
boundary work) to 1e-3 of the boundary work, which a work counted on the free component would
break (the residual is the boundary work's lead of half a step, R v dt / 2, which shrinks
relative to the work as the pull goes on).
A free block given `velocity all 1 0 0` then `velocity all NULL 2 NULL` moves at (1, 2): its
kinetic energy is 0.5 M (1 + 4), not 0.5 M 4 (the second would set vx = 0 without NULL).
The square in Rankine concrete pulled apart with NULL lateral components: a restart written
during the ramp continues bit for bit at 1 and 2 ranks, which agree with each other.
"""
import os
import tempfile

import numpy as np
import pandas as pd

import harness as h

args = h.parse_args()
E, NU, L, W, T, RHO = 30e9, 0.4, 0.05, 0.05, 0.05, 2400.0
STEPS = 1600  # 8e-4 s: ramp 1e-4 s, then constant velocity


def run(lat):
    wd = tempfile.mkdtemp(prefix=f"null_components_{lat}_")
    h.make_rect_mesh(os.path.join(wd, "bar.msh"), (10, 10), (L, W))
    h.make_rect_mesh(os.path.join(wd, "block.msh"), (4, 4), (0.05, 0.05), origin=(0.1, 0.12))
    h.copy_inputs(["in.null_components"], wd)
    h.run(args.exe, "in.null_components", workdir=wd, variables={"vy": lat, "vz": lat, "steps": STEPS})
    return pd.read_csv(os.path.join(wd, "energy.csv")), pd.read_csv(os.path.join(wd, "block.csv"))


def stiffness(e):
    """Slope of the xmax reaction against the xmax displacement after the ramp (least squares)."""
    late = e[e["time"] > 2e-4]
    return np.polyfit(late["displacement_xmax_x"], late["reaction_xmax_x"], 1)[0]


def balance(e):
    """Worst |kinetic + strain - input work| over the rows, scaled by the largest input work;
    and the row where it is."""
    lhs = e["kinetic"] + e["strain"]
    rhs = e["boundary_work"] + e["external_work"] + e["contact_work"]
    err = (lhs - rhs).abs() / rhs.abs().max()
    return err.max(), e["step"][err.idxmax()]


k_axial = E * W * T / L
free, block = run("NULL")
held, _ = run("0")
k_free, k_held = stiffness(free), stiffness(held)
h.check(abs(k_free / k_axial - 1) < 0.02,
        f"NULL lateral: stiffness {k_free:.4e} N/m within 2 % of E W t / L = {k_axial:.4e} N/m "
        f"({k_free / k_axial - 1:+.2%})")
bound = 1 / (1 - NU ** 2) - 1
h.check(0.02 < k_held / k_free - 1 < bound,
        f"lateral held at the pulled end: stiffer by {k_held / k_free - 1:.2%} (> 2 %, below the "
        f"uniaxial-strain bound {bound:.1%})")
h.check((free["reaction_xmax_y"] == 0).all(),
        "NULL lateral: the prescribed group reports no lateral reaction (0 in every row)")
h.check(held["reaction_xmax_y"].abs().max() > 1e-3 * held["reaction_xmax_x"].abs().max(),
        "lateral held: the prescribed group reports a lateral reaction")
for name, e in (("NULL", free), ("held", held)):
    worst, step = balance(e)
    h.check(worst < 1e-3, f"{name}: energy balance closes within 1e-3 of the boundary work "
                          f"(worst {worst:.1e} at step {step})")
mass = RHO * 0.05 * 0.05 * T
ke0 = block["kinetic"].iloc[0]
h.check(abs(ke0 / (0.5 * mass * 5) - 1) < 1e-9,
        f"velocity NULL keeps vx: initial kinetic energy {ke0:.6g} J = 0.5 M (1 + 4) = "
        f"{0.5 * mass * 5:.6g} J")
# The same square in Rankine concrete pulled apart with the lateral component NULL: a restart
# written during the ramp continues bit for bit through the crack, at 1 and 2 ranks, and the
# two rank counts agree (the Partial nodes' prescribed velocity and ramp are in the record).
runs = {}
for np_ in (1, 2):
    wd = tempfile.mkdtemp(prefix=f"null_fracture_{np_}_")
    h.make_rect_mesh(os.path.join(wd, "bar.msh"), (10, 10), (L, W))
    h.copy_inputs(["in.null_fracture", "in.null_fracture_continue"], wd)
    h.run(args.exe, "in.null_fracture", np_=np_, workdir=wd, variables={"first": 100, "rest": 1900})
    h.run(args.exe, "in.null_fracture_continue", np_=np_, workdir=wd, variables={"rest": 1900})
    a = pd.read_csv(os.path.join(wd, "energy.csv"))
    b = pd.read_csv(os.path.join(wd, "energy_b.csv"))
    a = a[a["step"] > 100].reset_index(drop=True)
    b = b[b["step"] > 100].reset_index(drop=True)
    h.check(len(a) == len(b) > 0 and (a[b.columns] == b).all().all(),
            f"np={np_}: restart during the ramp continues bit for bit ({len(b)} rows)")
    runs[np_] = a
h.check(runs[1]["fragments"].iloc[-1] == 2, "the square parts in two")
h.check((runs[1] == runs[2]).all().all(), "np=2 energy rows equal np=1's")
print(f"OK: stiffness NULL {k_free / k_axial - 1:+.2%} of E W t / L, held +{k_held / k_free - 1:.2%}")
