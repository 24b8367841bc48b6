"""Edge-to-edge contact of two tet4 bodies (issues #9 item 3, #10 item 5).

Two 0.3 x 0.1 x 0.1 m boxes of 6 x 2 x 2 Kuhn-split cells (h = 0.05 m), E = 10 MPa, nu = 0.3,
1000 kg/m^3 (3 kg each; the soft blocks of test_body_contact, in 3D), contact_penalty 0.1 (the
default). A is long in x and turned 45 deg about x, so a ridge along x is its lowest line; B is
long in y and turned 45 deg about y, its ridge along y on top. A falls onto B at 1 m/s; the
ridges cross at right angles half an element from the nearest node of either (offsets of h/2),
so no node meets a facet until the ridges overlap by h/2 (B's flanks fall at 45 deg).

Asserted, from thermo (momenta) and the energy files:
* without edge contact (`contact_edges no`) the bodies pass into each other: A's centre comes
  closer to B's than the touching distance (the two half diagonals, 2 x 0.0707 m) by more than
  h/2, the depth at which node-to-facet contact could first act;
* with it they bounce: the overlap of the centres stays below the contact's reach (half the
  element altitude over a facet, h/2), the relative velocity along z reverses (coefficient of
  restitution > 0), the bodies separate (no contact force at the end);
* the pair's momentum along z is conserved to 1e-10 of the initial momentum (the contact forces
  are equal and opposite; no other force acts);
* kinetic + strain - contact work of both bodies stays within 2 % of the initial kinetic energy
  at every energy-file row (penalty contact is elastic; the contact work is what the contact
  spring holds while the bodies touch);
* the same with friction mu = 0.3 (the ridges are at right angles, so sliding is small: the
  friction path is run, the balance must still close).
Centre positions are integrated from the momenta over the thermo rows (trapezoidal rule; the
rows are 50 steps apart, 1e-3 s, which shifts the distances by ~1e-5 m, far below h/2).
"""
import os
import re
import sys
import tempfile

import numpy as np

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import meshgen  # noqa: E402

args = h.parse_args()
MASS = 1000 * 0.3 * 0.1 * 0.1
HALF_DIAG = 0.05 * 2 ** 0.5
H = 0.05
DT, EVERY = 2e-5, 50
Z0 = 0.1514  # A's centre above B's at the start (touching at 2 HALF_DIAG = 0.1414)


def run(edges, mu, steps, np_=1):
    wd = tempfile.mkdtemp(prefix=f"edge_contact_{edges}_")
    h.make_box_mesh(os.path.join(wd, "a.msh"), (6, 2, 2), (0.3, 0.1, 0.1), (-0.15, -0.05, -0.05))
    h.make_box_mesh(os.path.join(wd, "b.msh"), (2, 6, 2), (0.1, 0.3, 0.1), (-0.05, -0.15, -0.05))
    h.copy_inputs(["in.edge_contact"], wd)
    out = h.run(args.exe, "in.edge_contact", np_=np_, workdir=wd,
                variables={"edges": edges, "mu": mu, "steps": steps})
    runs = h.thermo_blocks(out)
    pa, pb = h.column(runs, "a[15]"), h.column(runs, "b[15]")
    fz = h.column(runs, "a[10]")
    # Centre distance along z, from the momenta.
    dist, gap = [Z0], Z0
    for k in range(1, len(pa)):
        vrel = 0.5 * ((pa[k] + pa[k - 1]) - (pb[k] + pb[k - 1])) / MASS
        gap += vrel * EVERY * DT
        dist.append(gap)
    ea, eb = h.read_csv(os.path.join(wd, "a.csv")), h.read_csv(os.path.join(wd, "b.csv"))
    return pa, pb, fz, dist, ea, eb


touching = 2 * HALF_DIAG
pa, pb, fz, dist, _, _ = run("no", 0.0, 3000)
overlap = touching - min(dist)
h.check(overlap > H / 2, f"without edge contact the boxes pass into each other "
        f"(centres {overlap:.4f} m closer than touching, > h/2 = {H / 2})")

for mu in (0.0, 0.3):
    pa, pb, fz, dist, ea, eb = run("yes", mu, 3000)
    overlap = touching - min(dist)
    h.check(0 < overlap < H / 2, f"mu={mu}: with edge contact the ridges overlap by {overlap:.4f} m "
            f"at most (> 0, < reach h/2 = {H / 2})")
    p0 = pa[0] + pb[0]
    drift = max(abs(a + b - p0) for a, b in zip(pa, pb)) / abs(p0)
    h.check(drift < 1e-10, f"mu={mu}: momentum along z conserved to {drift:.1e} of the initial")
    v_before = (pa[0] - pb[0]) / MASS
    v_after = (pa[-1] - pb[-1]) / MASS
    restitution = -v_after / v_before
    h.check(restitution > 0, f"mu={mu}: the boxes bounce (coefficient of restitution "
            f"{restitution:.3f})")
    h.check(fz[-1] == 0 and dist[-1] > touching, f"mu={mu}: the boxes separated "
            f"(centres {dist[-1]:.4f} m apart, touching at {touching:.4f})")
    e0 = ea["kinetic"][0] + eb["kinetic"][0]
    worst = max(abs(ea["kinetic"][k] + ea["strain"][k] + eb["kinetic"][k] + eb["strain"][k]
                    - ea["contact_work"][k] - eb["contact_work"][k] - e0)
                for k in range(len(ea["kinetic"]))) / e0
    h.check(worst < 0.02, f"mu={mu}: kinetic + strain - contact work within {worst:.2e} of the "
            f"initial energy {e0:.4f} J at every row (< 2 %)")

# Two ranks: the contact scene evaluates the pair's edge contact on every rank and adds its forces
# on one (pair_part), so np 2 must give np 1's energy files to round-off (1e-10 of column scale).
_, _, _, _, ea2, eb2 = run("yes", 0.3, 3000, np_=2)
for name, one, two in (("a", ea, ea2), ("b", eb, eb2)):
    diff, where = h.worst_scaled(one, two)
    h.check(diff < 1e-10, f"np 2 vs np 1, body {name}: energy file within {diff:.1e} of the "
            f"column scale (worst: {where}) < 1e-10")

# Restart while two pieces of one body touch edge on edge: the boxes of 6 x 1 x 1 and 1 x 6 x 1
# cells (every node on the surface, so the upper piece's faces carry its velocity) placed as
# above in one mesh, self contact; write_restart at step 600, 100 steps into the contact (the
# pieces touch only by their ridges then: the overlap stays below h/2). The continued run must
# match the uninterrupted one bit for bit (%.17g): the pieces' edge contact state (the offsets of
# the penetrations, restart head section 2) is restored. Without it, the continuing contact
# would restart as an unexplained penetration and push less.
def rotated(X, axis, shift):
    c = s = 2 ** -0.5
    x, y, z = X[:, 0].copy(), X[:, 1].copy(), X[:, 2].copy()
    if axis == 0:
        y, z = c * y - s * z, s * y + c * z
    else:
        z, x = c * z - s * x, s * z + c * x
    return np.column_stack([x + shift[0], y + shift[1], z + shift[2]])


Xa, Ea, Ga = meshgen.box_tet_mesh(6, 1, 1, 0.3, 0.1, 0.1, origin=(-0.15, -0.05, -0.05))
Xb, Eb, _ = meshgen.box_tet_mesh(1, 6, 1, 0.1, 0.3, 0.1, origin=(-0.05, -0.15, -0.05))
X = np.vstack([rotated(Xa, 0, (0, 0.025, Z0)), rotated(Xb, 1, (0.025, 0, 0))])
E = np.vstack([Ea, Eb + len(Xa)])
wd = tempfile.mkdtemp(prefix="edge_contact_restart_")
meshgen.write_gmsh22(os.path.join(wd, "pieces.msh"), X, E,
                     {"upper": np.vstack([Ga[f] for f in sorted(Ga)])})
head = open(os.path.join(h.INPUTS, "in.edge_contact")).read()
head = head[:head.index("fix a all fem/body")].replace("${mu}", "0.3")
fix = ("fix p all fem/body file pieces.msh type 1 density 1000 youngs 1e7 poisson 0.3 gravity no "
       "velocity upper 0 0 -1 contact_bodies yes contact_edges yes energy_file p.csv 50\n"
       "thermo_style custom step f_p[1] f_p[2] f_p[4] f_p[13] f_p[14] f_p[15]\n"
       "thermo_modify format float %.17g\nthermo 50\n")
setup = re.compile(r"^(dimension|atom_style|atom_modify|boundary|units|region|create_box).*\n", re.M)
open(os.path.join(wd, "in.a"), "w").write(head + fix + "run 600\nwrite_restart p.restart\nrun 400\n")
open(os.path.join(wd, "in.b"), "w").write("read_restart p.restart\n" + setup.sub("", head) + fix
                                          + "run 400\n")
a = h.thermo_blocks(h.run(args.exe, "in.a", workdir=wd))
b = h.thermo_blocks(h.run(args.exe, "in.b", workdir=wd))
work = h.column(a, "p[4]", run_index=0)
h.check(work[-1] != 0, f"pieces in contact at the restart (contact work {work[-1]:.3e} J)")
(ha, ra), (hb, rb) = a[-1], b[-1]
h.check(ha == hb and len(ra) == len(rb) and ra[0][0] == 600, "same thermo layout after restart")
h.check(ra == rb, "the continued run matches the uninterrupted one bit for bit")
print("OK")
