"""Fracture, plasticity and erosion under LAMMPS: the same step (fracdem::BodyDriver) as LIGGGHTS.

Scenes (no particles, so both hosts run nothing but the core's code):
* the rankine bar of tests/integration/test_fracture_bar.py (in.fracture_bar2d, 2D, tri3):
  ramped tension, one crack across (11 split nodes, 2 fragments) at np 1 and 2;
* a J2 steel bar clamped at one end and sheared at the other (in.j2_erosion, tet4) with
  `erosion plastic_strain 0.2`: elements erode from step ~3600 on, at np 1 and 2;
* a LAMMPS write_restart of the bar after cracking (9 split nodes at step 1300), continued with
  read_restart: the continued rows equal the uninterrupted run's.
Contact between bodies and a rigid body: test_body_contact_match.py.

Tolerance: 1e-10 of each energy-file column's largest value. Both hosts build the same core
sources with the same compiler and flags, the element work of a breaking or eroding body is
replicated on every rank (no reduction order enters), and there are no particles, so the
histories agree to the last bit (the test prints whether the files are byte-identical); 1e-10
leaves room only for another compiler's rounding. A difference in the orchestration (a fracture
check or an erosion at another step, a lost half step) changes the peak force and the dissipated
energy at O(1e-3) or more. The split and erosion log lines must be the same text.
"""
import os

import host_match as hm

h, lmp = hm.h, hm.lmp
TOL = hm.TOL
FT, GF, AREA = 3e6, 100.0, 0.05 * 0.05
STEPS, RESTART_AT = 1500, 1300
run_both, compare_hosts, worst_difference = hm.run_both, hm.compare_hosts, hm.worst_difference

# ---- the cracking bar ----
for np_ in (1, 2):
    runs = run_both("fracture_bar2d", np_, dict(restart_at=RESTART_AT, rest=STEPS - RESTART_AT))
    e = compare_hosts("fracture_bar2d", np_, runs)
    peak, dissipated = max(e["reaction_xmax_x"]), e["fracture_energy"][-1]
    peak_g = max(runs["liggghts"][2]["reaction_xmax_x"])
    diss_g = runs["liggghts"][2]["fracture_energy"][-1]
    h.check(abs(peak / peak_g - 1) <= TOL and abs(dissipated / diss_g - 1) <= TOL,
            f"np {np_}: peak force {peak:.6f} N and dissipated energy {dissipated:.8f} J equal "
            f"LIGGGHTS's (rel. diff {abs(peak / peak_g - 1):.1e}, "
            f"{abs(dissipated / diss_g - 1):.1e})")
    h.check(abs(peak / (FT * AREA) - 1) < 0.05 and abs(dissipated / (GF * AREA) - 1) < 0.15
            and e["fragments"][-1] == 2 and e["split_nodes"][-1] == 11,
            f"np {np_}: LAMMPS's bar breaks as test_fracture_bar's: peak within 5 % of f_t A, "
            f"dissipation within 15 % of G_f A, 2 fragments from 11 splits")

    # LAMMPS restart after cracking: the continued run reproduces the uninterrupted one.
    wd = runs["lammps"][0]
    lmp.run("in.fracture_bar2d_continue_lammps", np_=np_, workdir=wd,
            variables=dict(rest=STEPS - RESTART_AT))
    cont = h.read_csv(os.path.join(wd, "energy_continued.csv"))
    h.check(cont["split_nodes"][0] > 0 and cont["fragments"][0] == 1,
            f"np {np_}: the restart was written after cracking "
            f"({int(cont['split_nodes'][0])} split nodes) and before the bar came apart")
    first = e["step"].index(RESTART_AT)
    tail = {k: v[first:] for k, v in e.items()}
    worst = worst_difference(tail, cont, f"restart np {np_}")
    h.check(worst == 0.0, f"np {np_}: write_restart + read_restart of the cracked bar continues "
                          f"identically ({len(cont['step'])} rows, largest difference {worst:.1e})")

# ---- the eroding J2 bar ----
for np_ in (1, 2):
    runs = run_both("j2_erosion", np_, dict(dt=1e-7, steps=4500, v=100, eps=0.2, thermo=500))
    e = compare_hosts("j2_erosion", np_, runs)
    eroded = int(e["eroded_elements"][-1])
    h.check(eroded > 10 and e["plastic_work"][-1] > 0 and e["viscous_work"][-1] > 0,
            f"np {np_}: the J2 bar yields (plastic work {e['plastic_work'][-1]:.4g} J, viscous "
            f"work {e['viscous_work'][-1]:.4g} J) and {eroded} elements erode under LAMMPS")
print("OK")
