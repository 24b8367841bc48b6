"""Stock LIGGGHTS scripts run unchanged: fracdem and liggghts give identical thermo at 1 and 2 ranks."""
import shutil
import sys
import tempfile

import harness as h

args = h.parse_args()
liggghts = shutil.which("liggghts")
h.check(liggghts is not None, "stock liggghts executable is installed")

for np_ in (1, 2):
    outs = {}
    for name, exe in (("liggghts", liggghts), ("fracdem", args.exe)):
        wd = tempfile.mkdtemp(prefix=f"stock_{name}_{np_}_")
        h.copy_inputs(["in.packing"], wd)
        outs[name] = h.thermo_blocks(h.run(exe, "in.packing", np_=np_, workdir=wd))
    a, b = outs["liggghts"], outs["fracdem"]
    h.check(len(a) == len(b) == 3, f"np={np_}: both produced 3 thermo blocks")
    h.check(all(len(ra[1]) > 0 for ra in a), f"np={np_}: thermo blocks are non-empty")
    h.check(a == b, f"np={np_}: thermo output of fracdem is identical to stock liggghts "
                    f"({sum(len(r[1]) for r in a)} rows, final atoms {a[-1][1][-1][1]:.0f})")
