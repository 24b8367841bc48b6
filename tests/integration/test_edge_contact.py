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
import tempfile

import harness as h

args = h.parse_args()
MASS = 1000 * 0.3 * 0.1 * 0.1
HALF_DIAG = 0.05 * 2 ** 0.5
H = 0.05
DT, EVERY = 2e-5, 50
Z0 = 0.1514  # A's centre above B's at the start (touching at 2 HALF_DIAG = 0.1414)


def run(edges, mu, steps):
    wd = tempfile.mkdtemp(prefix=f"edge_contact_{edges}_")
    h.make_box_mesh(os.path.join(wd, "a.msh"), (6, 2, 2), (0.3, 0.1, 0.1), (-0.15, -0.05, -0.05))
    h.make_box_mesh(os.path.join(wd, "b.msh"), (2, 6, 2), (0.1, 0.3, 0.1), (-0.05, -0.15, -0.05))
    h.copy_inputs(["in.edge_contact"], wd)
    out = h.run(args.exe, "in.edge_contact", workdir=wd,
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
print("OK")
