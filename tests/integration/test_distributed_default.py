"""`fix fem/body` without the `parallel` keyword: replicated or distributed by the body's size
(issue #13 item 1; threshold kDistributedMinElements = 20000 elements, body/body_setup.h, measured
with bench/distributed_body.py, docs/distributed_bodies.md). At np 2, steps 0, asserted:

* a block of 20 736 tet4 (just above the threshold) is distributed, and set-up says why;
* a block of 19 872 tet4 (just below) stays replicated, and set-up says why;
* the larger block with `fracture nodal` (which distributed bodies refuse) stays replicated, and
  set-up names the keyword;
* `parallel replicated` on the larger block is obeyed and logs no choice; at np 1 nothing is logged.
"""
import os
import tempfile

import harness as h

args = h.parse_args()
STEEL = "type 2 density 7800 youngs 2e11 poisson 0.3"
CONCRETE = ("type 2 density 2400 youngs 3e10 poisson 0.2 material rankine strength 3e6 "
            "fracture_energy 100 fracture nodal")


def run(nx, body, np_=2):
    wd = tempfile.mkdtemp(prefix=f"distributed_default_{nx}_")
    h.copy_inputs(["in.fe_common"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (nx, 12, 12), (0.4, 0.2, 0.2))
    with open(os.path.join(wd, "in.default"), "w") as f:
        f.write(f"include in.fe_common\ntimestep 1e-8\n"
                f"fix body all fem/body file block.msh {body} fixed xmin\nrun 0\n")
    return h.run(args.exe, "in.default", np_=np_, workdir=wd)


out = run(24, STEEL)
h.check("fix fem/body body: parallel distributed (by default: 20736 elements > 20000" in out
        and "distributed over 2 ranks" in out,
        "20 736 elements, no 'parallel': distributed, the choice logged")
out = run(23, STEEL)
h.check("fix fem/body body: parallel replicated (by default: 19872 elements <= 20000" in out
        and "distributed over" not in out,
        "19 872 elements, no 'parallel': replicated, the choice logged")
out = run(24, CONCRETE)
h.check("parallel replicated (by default: the body uses 'fracture'" in out
        and "distributed over" not in out,
        "20 736 elements with fracture: replicated, the keyword named")
out = run(24, STEEL + " parallel replicated")
h.check("by default" not in out and "distributed over" not in out,
        "'parallel replicated' obeyed above the threshold, no choice logged")
out = run(24, STEEL, np_=1)
h.check("by default" not in out, "np 1: no choice logged")
