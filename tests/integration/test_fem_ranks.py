"""FE-only runs agree across 1, 2 and 3 MPI ranks to 1e-10 relative (replicated body, split element work)."""
import os
import tempfile

import harness as h

args = h.parse_args()
results = {}
for model in ("elastic", "corotational"):
    for np_ in (1, 2, 3):
        wd = tempfile.mkdtemp(prefix=f"ranks_{model}_{np_}_")
        h.make_box_mesh(os.path.join(wd, "bar.msh"), (12, 2, 2), (0.6, 0.05, 0.05), (0, -0.025, -0.025))
        h.copy_inputs(["in.cantilever", "in.fe_common"], wd)
        h.run(args.exe, "in.cantilever", np_=np_, workdir=wd, variables=dict(dt=2e-6, model=model, steps=2000))
        results[(model, np_)] = h.read_csv(os.path.join(wd, "energy.csv"))
    ref = results[(model, 1)]
    h.check(max(ref["strain"]) > 0, f"{model}: the cantilever deforms under gravity")
    for np_ in (2, 3):
        other = results[(model, np_)]
        worst = max(h.rel_diff(a, b) for k in ("kinetic", "strain", "external_work")
                    for a, b in zip(ref[k][1:], other[k][1:]))
        h.check(worst < 1e-10, f"{model}: np={np_} agrees with np=1, worst relative difference {worst:.1e}")
