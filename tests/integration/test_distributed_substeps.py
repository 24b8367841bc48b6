"""Sub-cycling of a distributed body that is squeezed during the run (issue #13; `substeps auto`).

Scene (inputs/in.distributed_squeeze): the steel block of test_distributed_body (768 tet4, 0.4 x
0.2 x 0.2 m), clamped at xmin, its xmax face pushed towards it at 30 m/s (ramped over 0.5 ms),
corotational, 1000 host steps of 0.993 x the set-up stable step. The shortened elements bring the
stable step below the host step (by about 0.7 % near step 600), so `substeps auto` must go from 1
to 2 FE steps per host step during the run. The step is re-estimated every 100 steps; a
distributed body takes the smallest of its parts' steps (one min-reduction), so every rank
sub-cycles alike. Asserted:

* the replicated body at np 1 does go from 1 to 2 substeps during the run (energy file column
  `substeps`), and logs the change;
* np 2 and 3 `parallel distributed`: the same `substeps` column, value for value, the same change
  logged at the same step (once), and every energy-file column within 1e-10 of the column's
  largest value (the brief's tolerance; differences are summation order only).
"""
import os
import re
import tempfile

import harness as h

args = h.parse_args()
BASE = dict(v=-30, ramp=5e-4, every=50, thermo=100, steps=1000)


def scene(np_, parallel, dt):
    wd = tempfile.mkdtemp(prefix=f"distributed_substeps_{parallel}_{np_}_")
    h.copy_inputs(["in.distributed_squeeze", "in.fe_common"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 4, 4), (0.4, 0.2, 0.2))
    variables = dict(BASE, parallel=parallel, dt=repr(dt))
    if dt < 1e-9:
        variables["steps"] = 0
    text = h.run(args.exe, "in.distributed_squeeze", np_=np_, workdir=wd, variables=variables)
    return wd, text


CHANGE = r"fix fem/body body: step (\d+): stable FE time step \S+ < host time step \S+: (\d+) FE"
_, probe = scene(1, "replicated", 1e-12)
dt = 0.993 * h.stable_dt(probe)
ref_wd, ref_text = scene(1, "replicated", dt)
ref = h.read_csv(os.path.join(ref_wd, "energy.csv"))
ref_changes = re.findall(CHANGE, ref_text)
h.check(ref["substeps"][0] == 1 and max(ref["substeps"]) == 2 and len(ref_changes) == 1,
        f"np 1 replicated: from 1 to 2 substeps per host step during the run (change logged at "
        f"step {ref_changes[0][0] if ref_changes else '?'})")
for np_ in (2, 3):
    wd, text = scene(np_, "distributed", dt)
    h.check(f"distributed over {np_} ranks" in text, f"np {np_}: the body is distributed")
    got = h.read_csv(os.path.join(wd, "energy.csv"))
    h.check(got["substeps"] == ref["substeps"],
            f"np {np_}: the substeps column equals the replicated run's, row for row")
    changes = re.findall(CHANGE, text)
    h.check(changes == ref_changes, f"np {np_}: the change logged once, at the same step "
                                    f"({changes})")
    w, where = h.worst_scaled(ref, got)
    h.check(w < 1e-10, f"np {np_} distributed vs np 1 replicated: energy file within {w:.1e} of "
                       f"the column scale (worst: {where}) < 1e-10")
