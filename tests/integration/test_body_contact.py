"""Body-body contact between two fix fem/body bodies: an elastic block (A, tri3) hits a resting
one (B, quad4, offset so that friction acts too). Asserted: total momentum of the pair is
conserved (internal forces, 1e-9 relative), the bodies interact (B ends faster than A, both
moving +x) and separate (no contact left), kinetic + strain energy after the impact is within
3 % of the initial 12.5 J (penalty contact is elastic; friction and waves take a little), and
np 1 and np 2 agree on the final momenta to 1e-4 (see below).
"""
import os
import subprocess
import sys
import tempfile

import harness as h

args = h.parse_args()
finals = {}
for np_ in (1, 2):
    wd = tempfile.mkdtemp(prefix=f"body_contact_{np_}_")
    env = dict(os.environ, PYTHONPATH=os.path.join(h.ROOT, "python"))
    for name, el in (("a.msh", "tri3"), ("b.msh", "quad4")):
        subprocess.run([sys.executable, "-m", "fracdem.meshgen", "rect", "8", "8", "0.1", "0.1", "-o",
                        os.path.join(wd, name), "--element", el], check=True, env=env,
                       stdout=subprocess.DEVNULL)
    h.copy_inputs(["in.body_contact"], wd)
    runs = h.thermo_blocks(h.run(args.exe, "in.body_contact", np_=np_, workdir=wd,
                                 variables={"steps": 8000}))
    px = h.column(runs, "px")
    energy = h.column(runs, "e")
    pa, pb = h.column(runs, "a[13]"), h.column(runs, "b[13]")
    fa = h.column(runs, "a[8]")
    h.check(max(abs(p - px[0]) for p in px) < 1e-9 * abs(px[0]),
            f"np={np_}: momentum of the pair conserved (5 kg m/s)")
    h.check(max(abs(f) for f in fa) > 0, f"np={np_}: the bodies touched")
    h.check(pb[-1] > pa[-1] > 0, f"np={np_}: B ends faster than A, both moving +x ({pa[-1]:.3f}, {pb[-1]:.3f})")
    h.check(fa[-1] == 0, f"np={np_}: the bodies separated")
    h.check(abs(energy[-1] / energy[0] - 1) < 0.03,
            f"np={np_}: energy after the impact {energy[-1]:.4f} J within 3 % of {energy[0]:.4f} J")
    finals[np_] = (pa[-1], pb[-1])
# At np 2 the elastic element work is shared and summed in another order; the contact's on/off
# switching amplifies those round-off differences to ~1e-5 over the impact (a replicated-work
# material gives identical numbers at np 1 and 2), hence the tolerance.
for k in (0, 1):
    rel = abs(finals[1][k] - finals[2][k]) / abs(finals[1][k])
    h.check(rel < 1e-4, f"np 1 and np 2 agree on the final momenta (rel. diff {rel:.1e})")
print("OK")
