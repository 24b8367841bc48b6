"""write_restart/read_restart continue a body + particle run: the continued run matches the straight one."""
import os
import tempfile

import harness as h

args = h.parse_args()
for np_ in (1, 2):
    wd = tempfile.mkdtemp(prefix=f"restart_{np_}_")
    h.make_box_mesh(os.path.join(wd, "bar.msh"), (12, 2, 2), (0.6, 0.05, 0.05), (0, -0.025, -0.025))
    h.copy_inputs(["in.restart_a", "in.restart_b", "in.fe_common"], wd)
    a = h.thermo_blocks(h.run(args.exe, "in.restart_a", np_=np_, workdir=wd))
    b = h.thermo_blocks(h.run(args.exe, "in.restart_b", np_=np_, workdir=wd))
    ha, ra = a[-1]
    hb, rb = b[-1]
    h.check(ha == hb and len(ra) == len(rb), f"np={np_}: same thermo layout after restart")
    h.check(max(abs(x) for x in h.column(a, "body[4]")) > 0, f"np={np_}: the particle did work on the body")
    worst = 0.0
    for row_a, row_b in zip(ra, rb):
        for x, y in zip(row_a, row_b):
            worst = max(worst, abs(x - y) / max(abs(x), abs(y), 1e-30))
    h.check(worst < 1e-6, f"np={np_}: continued run matches the uninterrupted one (worst rel. diff {worst:.1e})")
