"""Particle-body collisions without walls or gravity conserve linear momentum to round-off."""
import os
import tempfile

import harness as h

args = h.parse_args()
for model in ("elastic", "corotational"):
    wd = tempfile.mkdtemp(prefix=f"momentum_{model}_")
    h.make_box_mesh(os.path.join(wd, "block.msh"), (6, 6, 3), (0.2, 0.1, 0.05))
    h.copy_inputs(["in.momentum", "in.fe_common"], wd)
    runs = h.thermo_blocks(h.run(args.exe, "in.momentum", workdir=wd, variables=dict(model=model, steps=20000)))
    contacts = h.column(runs, "body[7]")
    fz = h.column(runs, "body[10]")
    h.check(max(contacts) >= 1, f"{model}: the sphere touched the body ({int(max(contacts))} contacts at peak)")
    h.check(min(h.column(runs, "Atoms")) == 1, f"{model}: no particle lost")
    for comp in ("px", "py", "pz"):
        p = h.column(runs, comp)
        scale = max(abs(x) for x in p)
        worst = max(abs(x - p[0]) for x in p) / scale
        h.check(worst < 1e-9, f"{model}: total {comp[1]}-momentum conserved, max relative change {worst:.1e}")
    pz = h.column(runs, "pz")
    h.check(max(abs(f) for f in fz) > 0, f"{model}: non-zero contact force recorded (peak {max(abs(f) for f in fz):.3g} N)")
