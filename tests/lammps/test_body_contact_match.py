"""Contact of fix fem/body under LAMMPS through the core's BodyDriver, against LIGGGHTS.

* two elastic blocks with `contact_bodies yes` (the scene of tests/integration/test_body_contact,
  frictionless), A hitting B: the contact between two fix fem/body of one host, at np 1 and 2,
  and at np 2 with A `parallel distributed` (its pairs with the replicated B evaluated on rank 0);
* a rigid block ('rigid yes motion linear 0 0 0.1') meeting a falling sphere (COR 0.5): the
  thermo histories agree between hosts and the sphere leaves at 0.1 + 0.5 (0.3 + 0.1) m/s.

Tolerance 1e-10 of each column's scale, as in test_fracture_match.py: the same core code on both
hosts, and a sum over two ranks is exact in either order; the files turn out byte-identical.
"""
import os

import host_match as hm

h, lmp, args = hm.h, hm.lmp, hm.args
TOL = hm.TOL
run_both, compare_hosts, worst_difference = hm.run_both, hm.compare_hosts, hm.worst_difference
scene_dir = hm.scene_dir

# ---- contact between two bodies of one host ----
for np_ in (1, 2):
    runs = run_both("body_contact2d", np_, dict(steps=8000), energy="a.csv")
    compare_hosts("body_contact2d", np_, runs, energy="a.csv", events=False)
    wd_g, wd_l = runs["liggghts"][0], runs["lammps"][0]
    b_g, b_l = (h.read_csv(os.path.join(wd, "b.csv")) for wd in (wd_g, wd_l))
    worst = worst_difference(b_g, b_l, f"body_contact2d np {np_} (b.csv)")
    h.check(worst <= TOL, f"body_contact2d np {np_}: body B's history agrees between hosts "
                          f"(largest difference {worst:.2e} of the column scale)")
    rows = h.thermo_blocks(runs["lammps"][1])[-1][1]
    px = [r[3] for r in rows]
    h.check(max(abs(r[5]) for r in rows) > 0 and rows[-1][2] > rows[-1][1] > 0
            and max(abs(p - px[0]) for p in px) < 1e-9 * abs(px[0]),
            f"np {np_}: under LAMMPS the blocks touch, B ends faster than A "
            f"({rows[-1][1]:.4f}, {rows[-1][2]:.4f} kg m/s) and the pair's momentum is conserved")
# ---- a distributed body in contact with a replicated one (A distributed over 2 ranks) ----
runs = run_both("body_contact2d", 2, dict(steps=8000, pa="distributed"), energy="a.csv")
compare_hosts("body_contact2d, A distributed,", 2, runs, energy="a.csv", events=False)
worst = worst_difference(*(h.read_csv(os.path.join(runs[k][0], "b.csv"))
                           for k in ("liggghts", "lammps")), "body_contact2d A distributed (b.csv)")
h.check(worst <= TOL, f"body_contact2d, A distributed at np 2: body B's history agrees between "
                      f"hosts (largest difference {worst:.2e} of the column scale)")
h.check("fix fem/body a: a.msh" in runs["lammps"][1] and "distributed over 2 ranks" in
        runs["lammps"][1] and max(abs(r[5]) for r in h.thermo_blocks(runs["lammps"][1])[-1][1]) > 0,
        "under LAMMPS block A is distributed over 2 ranks and touches the replicated B")
# ---- a rigid body in prescribed motion hit by a particle ----
for np_ in (1, 2):
    rows = {}
    for host in ("liggghts", "lammps"):
        wd = scene_dir("rigid_impact", host, np_)
        if host == "liggghts":
            text = h.run(args.exe, f"in.rigid_impact_{host}", np_=np_, workdir=wd,
                         variables=dict(steps=3000))
        else:
            text = lmp.run(f"in.rigid_impact_{host}", np_=np_, workdir=wd,
                           variables=dict(steps=3000))
        rows[host] = h.thermo_blocks(text)[-1][1]
    a, b = rows["liggghts"], rows["lammps"]
    worst = 0.0
    for k in range(1, len(a[0])):
        scale = max(max(abs(r[k]) for r in a), 1e-300)
        worst = max(worst, max(abs(x[k] - y[k]) for x, y in zip(a, b)) / scale)
    touched = max(r[1] for r in b)
    h.check(len(a) == len(b) == 31 and worst <= TOL and touched == 1,
            f"rigid_impact np {np_}: the moving rigid block's contact history agrees between hosts "
            f"({len(b)} rows, largest difference {worst:.2e} of the column scale)")
    h.check(abs(b[-1][3] / 0.3 - 1) < 1e-3 and b[-1][1] == 0,
            f"rigid_impact np {np_}: the sphere leaves at {b[-1][3]:.6f} m/s "
            f"(0.1 + 0.5 * 0.4 = 0.3)")
print("OK")
