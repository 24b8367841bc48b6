"""Supports of a three-point bend: a pin + roller with a load point free in x (`prescribed_velocity
load NULL -v NULL`) carries the beam's bending load; a load point held in x as well makes an arch.

Beam: Petersson's (1981) concrete (E 30 GPa, nu 0.2, f_t 3.33 MPa, G_f 124 N/m) and section
(D 200 mm, t 50 mm, zero-width notch a = 100 mm) on a span of 4 D, as in
test_fracture_validation.py, on its coarsest grid (h = 20 mm, meshgen.notched_beam); load point
pulled down at 15 mm/s ramped over 3 ms, run to 0.3 mm (past the peak at ~0.15 mm).
Three arrangements:
  rollers:   both supports held in y, load point prescribed in x too (vx = 0): what
             in.notched_beam does; horizontally determinate (the load point takes no thrust by
             symmetry).
  pin, NULL: left support held in x and y, right in y, load point free in x: the textbook
             arrangement, also determinate.
  pin, 0:    the same pin with the load point held in x: the beam between pin and load point
             cannot lengthen at the bottom fibre, so it pushes as an arch.
Asserted: the pin + NULL peak is within 5 % of the rollers' peak; its load point reports 0 as x
reaction in every row; up to the peak the pin's horizontal reaction stays below 5 % of the peak
(a determinate support carries no thrust: what it shows is the ringing of the ramp); with the
load point held in x the load at the rollers' peak deflection is more than 1.5 times their peak
and the pin's thrust exceeds the load there. The pin + NULL run closes the energy balance of
docs/fix_fem_body.md to 1e-3 of the boundary work through the cracking.
"""
import os
import sys
import tempfile

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import meshgen  # noqa: E402

args = h.parse_args()
DT, STEPS = 2.4e-6, 9000  # 0.78 of the mesh's stable step 3.1 us; 21.6 ms


def run(name, supports, vx):
    wd = tempfile.mkdtemp(prefix=f"bend_supports_{name}_")
    X, E_, G = meshgen.notched_beam(0.8, 0.2, 0.1, 0.02, notch_width=0, span=0.8)
    del G["ligament"]
    meshgen.write_gmsh22(os.path.join(wd, "beam.msh"), X, E_, G)
    h.copy_inputs(["in.bend_supports", "in.fe_common_2d"], wd)
    h.run(args.exe, "in.bend_supports", workdir=wd,
          variables={"supports": supports, "vx": vx, "dt": DT, "steps": STEPS})
    return h.read_csv(os.path.join(wd, "energy.csv"))


def col(e, name):
    return [float(x) for x in e[name]]


rollers = run("rollers", "fixed support_left y fixed support_right y", "0")
pin_free = run("pin_null", "fixed support_left x y fixed support_right y", "NULL")
pin_held = run("pin_held", "fixed support_left x y fixed support_right y", "0")


def peak(e):
    """(peak load, its row) of the load point's downward reaction."""
    load = [-p for p in col(e, "reaction_load_y")]
    k = max(range(len(load)), key=load.__getitem__)
    return load[k], k


p_rollers, k_rollers = peak(rollers)
p_free, k_free = peak(pin_free)
h.check(abs(p_free / p_rollers - 1) < 0.05,
        f"pin + roller, load point NULL in x: peak {p_free:.0f} N within 5 % of the rollers' "
        f"{p_rollers:.0f} N ({p_free / p_rollers - 1:+.1%})")
h.check(all(r == 0 for r in col(pin_free, "reaction_load_x")),
        "load point NULL in x: its x reaction reads 0 in every row")
thrust = max(abs(r) for r in col(pin_free, "reaction_support_left_x")[:k_free + 1])
h.check(thrust < 0.05 * p_free,
        f"pin + roller: the pin's horizontal reaction up to the peak {thrust:.0f} N < 5 % of it")
load_arch = -col(pin_held, "reaction_load_y")[k_rollers]
thrust_arch = abs(col(pin_held, "reaction_support_left_x")[k_rollers])
h.check(load_arch > 1.5 * p_rollers and thrust_arch > load_arch,
        f"load point held in x: an arch: {load_arch:.0f} N at the rollers' peak deflection "
        f"({load_arch / p_rollers:.1f} x their peak), pin thrust {thrust_arch:.0f} N")
lhs = [a + b + c + d for a, b, c, d in zip(col(pin_free, "kinetic"), col(pin_free, "strain"),
                                           col(pin_free, "fracture_energy"),
                                           col(pin_free, "eroded_energy"))]
rhs = [a + b + c for a, b, c in zip(col(pin_free, "boundary_work"), col(pin_free, "external_work"),
                                    col(pin_free, "contact_work"))]
scale = max(abs(r) for r in rhs)
worst = max(abs(a - b) for a, b in zip(lhs, rhs)) / scale
splits = col(pin_free, "split_nodes")[-1]
h.check(worst < 1e-3 and splits > 0,
        f"pin + roller, NULL: energy balance within 1e-3 of the boundary work through "
        f"{splits:.0f} splits (worst {worst:.1e})")
print(f"OK: peaks {p_rollers:.0f} / {p_free:.0f} N, arch {load_arch:.0f} N")
