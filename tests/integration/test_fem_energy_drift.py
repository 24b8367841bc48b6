"""Free vibration at half the stable time step: total energy drift below 0.1% over 10^4 steps.

Drift is the change of the mean total energy (kinetic + strain) between the first and the last
1000 steps; central differences make the instantaneous value oscillate (O(dt^2), no trend),
so the windowed mean is what measures a secular drift.
"""
import os
import tempfile

import harness as h

args = h.parse_args()
for model in ("elastic", "corotational"):
    wd = tempfile.mkdtemp(prefix=f"drift_{model}_")
    h.make_box_mesh(os.path.join(wd, "block.msh"), (4, 3, 2), (0.2, 0.1, 0.05))
    h.copy_inputs(["in.vibration", "in.fe_common"], wd)
    probe = h.run(args.exe, "in.vibration", workdir=wd,
                  variables=dict(dt=1e-9, model=model, steps=0, every=1, thermo=1))
    dt = 0.5 * h.stable_dt(probe)
    h.run(args.exe, "in.vibration", workdir=wd,
          variables=dict(dt=dt, model=model, steps=10000, every=10, thermo=1000))
    e = h.read_csv(os.path.join(wd, "energy.csv"))
    tot = e["total"]
    e0 = tot[0]
    first, last = tot[1:101], tot[-100:]
    drift = abs(sum(last) / len(last) - sum(first) / len(first)) / e0
    h.check(len(tot) == 1001, f"{model}: energy history has 1001 rows")
    h.check(max(e["strain"]) > 0.2 * e0, f"{model}: the block really vibrates (strain energy reaches "
                                         f"{max(e['strain']) / e0:.2f} of the total)")
    h.check(drift < 1e-3, f"{model}: energy drift {drift:.2e} < 1e-3 over 10^4 steps at dt = 0.5 dt_crit")
