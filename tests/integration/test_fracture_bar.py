"""A Rankine bar in ramped tension breaks as the crack-band theory says, the same way on 1, 2
and 3 ranks, with its energy balanced, and a restart taken after cracking continues exactly.

Parameters (in.fracture_bar): concrete-like, f_t = 3 MPa, G_f = 100 N/m, section 50 x 50 mm.
Expected: peak tensile force f_t A = 7.5 kN (Rankine criterion, uniaxial stress); dissipated
energy G_f A = 0.25 J (crack band: G_f per unit crack area on any mesh), tolerances below; the
same with the bilinear softening law.
"""
import os
import re
import subprocess
import sys
import tempfile

import harness as h

args = h.parse_args()
FT, GF, AREA = 3e6, 100.0, 0.05 * 0.05
STEPS, RESTART_AT = 1500, 1300


def run_bar(np_, workdir, law="linear", steps=STEPS):
    subprocess.run([sys.executable, "-m", "fracdem.meshgen", "rect", "40", "10", "0.2", "0.05",
                    "-o", os.path.join(workdir, "bar.msh"), "--element", "tri3"],
                   check=True, stdout=subprocess.DEVNULL, env=dict(os.environ, PYTHONPATH=os.path.join(h.ROOT, "python")))
    h.copy_inputs(["in.fracture_bar", "in.fracture_bar_continue"], workdir)
    out = h.run(args.exe, "in.fracture_bar", np_=np_, workdir=workdir,
                variables={"restart_at": RESTART_AT, "rest": steps - RESTART_AT, "law": law})
    splits = re.findall(r"step (\d+): crack at node (\d+) -> new node (\d+)", out)
    import pandas as pd
    energy = pd.read_csv(os.path.join(workdir, "energy.csv"))
    return out, splits, energy


results = {}
for np_ in (1, 2, 3):
    wd = tempfile.mkdtemp(prefix=f"fracture_bar_{np_}_")
    results[np_] = (wd,) + run_bar(np_, wd)

wd, out, splits, e = results[1]
peak = e["reaction_xmax_x"].max()
h.check(abs(peak / (FT * AREA) - 1) < 0.05,
        f"peak force {peak:.1f} N within 5 % of f_t A = {FT * AREA:.1f} N")
dissipated = e["fracture_energy"].iloc[-1]
h.check(abs(dissipated / (GF * AREA) - 1) < 0.15,
        f"dissipated {dissipated:.4f} J within 15 % of G_f A = {GF * AREA:.4f} J")
h.check(e["fragments"].iloc[-1] == 2, f"two fragments at the end (got {e['fragments'].iloc[-1]})")
h.check(e["split_nodes"].iloc[-1] == 11,
        f"one crack across the bar: 11 split nodes (one per node of a mesh column), got {e['split_nodes'].iloc[-1]}")
# Energy balance: kinetic + strain + dissipated = work of the prescribed velocity (+ others).
lhs = e["kinetic"] + e["strain"] + e["fracture_energy"]
rhs = e["boundary_work"] + e["external_work"] + e["contact_work"]
worst = ((lhs - rhs).abs() / rhs.abs().max()).max()
h.check(worst < 0.02, f"energy balance closes within 2 % of the input work (worst {worst:.2e})")

for np_ in (2, 3):
    h.check(results[np_][2] == splits, f"np={np_}: the same splits at the same steps as np=1")
    e2 = results[np_][3]
    rel = abs(e2["fracture_energy"].iloc[-1] / dissipated - 1)
    h.check(rel < 1e-9, f"np={np_}: dissipated energy equals np=1 (rel. diff {rel:.1e})")

# Petersson's bilinear softening (the same G_f): the same peak and dissipation bounds, one crack.
# Its tail (below f_t / 3 out to 3.6 G_f / f_t) is longer than the linear law's 2 G_f / f_t, so
# the run goes on to 2500 steps.
_, _, eb = run_bar(1, tempfile.mkdtemp(prefix="fracture_bar_bilinear_"), "bilinear", 2500)
peak_b, diss_b = eb["reaction_xmax_x"].max(), eb["fracture_energy"].iloc[-1]
h.check(abs(peak_b / (FT * AREA) - 1) < 0.05,
        f"bilinear: peak force {peak_b:.1f} N within 5 % of f_t A = {FT * AREA:.1f} N")
h.check(abs(diss_b / (GF * AREA) - 1) < 0.15,
        f"bilinear: dissipated {diss_b:.4f} J within 15 % of G_f A = {GF * AREA:.4f} J")
h.check(eb["fragments"].iloc[-1] == 2 and eb["split_nodes"].iloc[-1] == 11,
        f"bilinear: two fragments from 11 splits (got {eb['fragments'].iloc[-1]}, "
        f"{eb['split_nodes'].iloc[-1]})")
lhs_b = eb["kinetic"] + eb["strain"] + eb["fracture_energy"]
rhs_b = eb["boundary_work"] + eb["external_work"] + eb["contact_work"]
worst_b = ((lhs_b - rhs_b).abs() / rhs_b.abs().max()).max()
h.check(worst_b < 0.02, f"bilinear: energy balance closes within 2 % (worst {worst_b:.2e})")

# Restart after cracking: the continued run reproduces the uninterrupted one.
for np_ in (1, 2):
    wd = results[np_][0]
    out_c = h.run(args.exe, "in.fracture_bar_continue", np_=np_, workdir=wd,
                  variables={"rest": STEPS - RESTART_AT})
    a = h.thermo_blocks(results[np_][1])[-1][1]
    b = h.thermo_blocks(out_c)[-1][1]
    h.check(len(a) == len(b) and len(a) > 0, f"np={np_}: continued thermo has {len(b)} rows")
    worst = max(abs(x - y) / max(abs(x), abs(y), 1e-30) for ra, rb in zip(a, b) for x, y in zip(ra, rb))
    h.check(worst < 1e-10, f"np={np_}: restart of a cracked bar continues exactly (worst rel. diff {worst:.1e})")
# The same in 3D (tet4): peak f_t A, dissipation G_f A, one crack through the 5 x 5 nodes of a
# cross-section.
wd = tempfile.mkdtemp(prefix="fracture_bar_3d_")
h.make_box_mesh(os.path.join(wd, "bar.msh"), (20, 4, 4), (0.2, 0.04, 0.04))
h.copy_inputs(["in.fracture_bar_3d"], wd)
h.run(args.exe, "in.fracture_bar_3d", np_=2, workdir=wd)
import pandas as pd
e3 = pd.read_csv(os.path.join(wd, "energy.csv"))
a3 = 0.04 * 0.04
peak3 = e3["reaction_xmax_x"].max()
h.check(abs(peak3 / (FT * a3) - 1) < 0.05, f"3D: peak force {peak3:.1f} N within 5 % of f_t A = {FT * a3:.1f} N")
d3 = e3["fracture_energy"].iloc[-1]
h.check(abs(d3 / (GF * a3) - 1) < 0.15, f"3D: dissipated {d3:.4f} J within 15 % of G_f A = {GF * a3:.4f} J")
h.check(e3["fragments"].iloc[-1] == 2 and e3["split_nodes"].iloc[-1] == 25,
        f"3D: two fragments from 25 splits (got {e3['fragments'].iloc[-1]}, {e3['split_nodes'].iloc[-1]})")
print(f"OK: peak {peak:.1f} N, dissipated {dissipated:.4f} J, {len(splits)} splits")
