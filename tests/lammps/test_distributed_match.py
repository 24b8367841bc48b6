"""parallel distributed under LAMMPS (issue #13 on the second host): the clamped, swinging steel block
of tests/integration/test_distributed_body.py, distributed over 3 LAMMPS ranks, against the
replicated body of the LIGGGHTS build at 1 rank: every thermo column within 1e-9 of its scale
(energies within 1e-10 relative), as between the LIGGGHTS runs; fix fem/vtk writes a .pvtu per
frame whose pieces hold every element.
"""
import glob
import os
import re
import shutil

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)


def scene_dir(tag):
    wd = lh.tempfile.mkdtemp(prefix=f"distributed_{tag}_")
    for name in ("in.distributed_host", "in.lammps_preamble", "in.liggghts_preamble"):
        shutil.copy(os.path.join(lh.INPUTS, name), wd)
    h.copy_inputs(["in.fe_common"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 4, 4), (0.4, 0.2, 0.2))
    return wd


def columns(text):
    """Thermo columns by position (LIGGGHTS names f_body[i] 'body[i]', LAMMPS 'f_body[i]')."""
    runs = h.thermo_blocks(text)
    header, _ = runs[-1]
    return {k: h.column(runs, n) for k, n in enumerate(header) if n != "Step"}


ref_wd = scene_dir("liggghts")
ref = columns(h.run(args.exe, "in.distributed_host", np_=1, workdir=ref_wd,
                    variables=dict(host="liggghts", parallel="replicated")))
wd = scene_dir("lammps")
text = lmp.run("in.distributed_host", np_=3, workdir=wd,
               variables=dict(host="lammps", parallel="distributed"))
h.check("distributed over 3 ranks" in text, "LAMMPS np 3: the body is distributed")
got = columns(text)
worst, where = h.worst_scaled(ref, got)
h.check(worst < 1e-9, f"LAMMPS np 3 distributed vs LIGGGHTS np 1 replicated: thermo within "
                      f"{worst:.1e} of the column scale (worst: column {where}) < 1e-9")
energy = max(abs(x - y) / abs(x) for x, y in zip(ref[1], got[1]))  # column 1: f_body
h.check(energy < 1e-10, f"body energy within {energy:.1e} relative < 1e-10")
frames = sorted(glob.glob(os.path.join(wd, "frame_*.pvtu")))
pieces = re.findall(r'Piece Source="([^"]+)"', open(frames[-1]).read())
cells = sum(int(re.search(r'NumberOfCells="(\d+)"',
                          open(os.path.join(wd, p), "rb").read(4000).decode("latin-1")).group(1))
            for p in pieces)
h.check(len(frames) == 5 and len(pieces) == 3 and cells == 768,
        f"{len(frames)} .pvtu frames; the last has {len(pieces)} pieces with {cells} of 768 "
        f"elements")
