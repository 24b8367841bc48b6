"""fix fem/body ... parallel distributed: the same body as replicated, and per step only its
interface on the wire (issue #13, items 1, 3 and 6 for FE-only elastic bodies).

Scene (inputs/in.distributed): a steel block of 768 tet4, clamped at xmin, set swinging and
twisting by initial velocities, corotational; no particles. Asserted:

* np 2, 3, 4 `parallel distributed` against np 1 (replicated): every thermo column (energy,
  kinetic, strain, node and element counts, stable step, momentum, the clamp's reaction) and every
  energy-file column within 1e-9 of the column's scale over 2000 steps (the issue asks 1e-10 for
  energies of elastic runs: the energies here agree within that; reactions and momenta are
  differences of large nodal forces and are held to 1e-9 of their largest value);
* np 2 distributed against np 2 replicated: the same within the same tolerance (a replicated body
  at 2 ranks shares element ranges and all-reduces all forces: another summation order);
* with the PMPI counter at 4 ranks (difference of a 200- and a 600-step run, thermo and energy
  rows only at the end): the body's exchange (calls made by NodeExchange) sends exactly 24 bytes
  per (shared node, neighbouring part) pair and step, the number fix fem/body prints at set-up,
  in one message per neighbouring part; the project's code (FixFemBody, BodyDriver, NodeExchange)
  issues no collective between thermo steps but the re-estimate of the sub-cycling (substeps
  auto: one min-reduction of the parts' stable steps every 100 steps, BodyDriver::check_squeezed;
  this test asserted none before the distributed body followed its stable step);
* refusals: `parallel distributed` with `rigid yes` stops naming the keyword (particle
  contact: test_distributed_contact.py; erosion, `erosion_mass remove` included:
  test_distributed_erosion.py; the pieces' contact: test_distributed_self_contact.py).
"""
import glob
import os
import re
import shutil
import sys
import tempfile

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "tests", "support"))
import mpicount  # noqa: E402

args = h.parse_args()
BASE = dict(dt=1e-7, model="corotational", every=100, thermo=500, steps=2000)


def scene(np_, parallel, **overrides):
    wd = tempfile.mkdtemp(prefix=f"distributed_{parallel}_{np_}_")
    h.copy_inputs(["in.distributed", "in.fe_common"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 4, 4), (0.4, 0.2, 0.2))
    variables = dict(BASE, parallel=parallel, **overrides)
    text = h.run(args.exe, "in.distributed", np_=np_, workdir=wd, variables=variables)
    return wd, text


def thermo(text):
    return h.thermo_blocks(text)


def columns(runs):
    header, _ = runs[-1]
    return {n: h.column(runs, n) for n in header if n != "Step"}


ref_wd, ref_text = scene(1, "replicated")
ref = columns(thermo(ref_text))
ref_energy = h.read_csv(os.path.join(ref_wd, "energy.csv"))
rep2_wd, rep2_text = scene(2, "replicated")
for np_ in (2, 3, 4):
    wd, text = scene(np_, "distributed")
    h.check(f"distributed over {np_} ranks" in text, f"np {np_}: the body is distributed")
    got = columns(thermo(text))
    w, where = h.worst_scaled(ref, got)
    h.check(w < 1e-9, f"np {np_} distributed vs np 1 replicated: thermo within {w:.1e} of the "
                      f"column scale (worst: {where}) < 1e-9")
    energy = h.read_csv(os.path.join(wd, "energy.csv"))
    w, where = h.worst_scaled(ref_energy, energy)
    h.check(w < 1e-9, f"np {np_}: energy file within {w:.1e} of the column scale ({where})")
    e_ref = [k + s for k, s in zip(ref_energy["kinetic"], ref_energy["strain"])]
    e_got = [k + s for k, s in zip(energy["kinetic"], energy["strain"])]
    worst_e = max(abs(x - y) / abs(x) for x, y in zip(e_ref, e_got))
    h.check(worst_e < 1e-10, f"np {np_}: body energy within {worst_e:.1e} relative < 1e-10")
    if np_ == 2:
        w, where = h.worst_scaled(columns(thermo(rep2_text)), got)
        h.check(w < 1e-9, f"np 2 distributed vs np 2 replicated: {w:.1e} ({where})")


# ParaView output of a distributed body: one piece per rank and a .pvtu per frame in the .pvd.
wd = tempfile.mkdtemp(prefix="distributed_vtk_")
h.copy_inputs(["in.distributed", "in.fe_common"], wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 4, 4), (0.4, 0.2, 0.2))
with open(os.path.join(wd, "in.distributed")) as f:
    script = f.read().replace("thermo_style", "fix vtk all fem/vtk 500 frame body body\nthermo_style", 1)
with open(os.path.join(wd, "in.vtk"), "w") as f:
    f.write(script)
h.run(args.exe, "in.vtk", np_=3, workdir=wd, variables=dict(BASE, parallel="distributed"))
frames = sorted(glob.glob(os.path.join(wd, "frame_*.pvtu")))
pvd = open(os.path.join(wd, "frame.pvd")).read()
h.check(len(frames) == 5 and all(os.path.basename(p) in pvd for p in frames),
        f"{len(frames)} .pvtu frames, all in frame.pvd")
pieces = re.findall(r'Piece Source="([^"]+)"', open(frames[-1]).read())
cells = 0
for piece in pieces:
    head = open(os.path.join(wd, piece), "rb").read(4000).decode("latin-1")
    cells += int(re.search(r'NumberOfCells="(\d+)"', head).group(1))
h.check(len(pieces) == 3 and cells == 768,
        f"the last frame has {len(pieces)} pieces holding {cells} of 768 elements")
shutil.rmtree(wd, ignore_errors=True)

# Counts at 4 ranks.
LIB = os.path.join(os.path.dirname(os.path.abspath(args.exe)), "libfracdem_mpicount.so")
h.check(os.path.isfile(LIB), f"PMPI counter {LIB} built")


def counted(wd, steps):
    variables = dict(BASE, parallel="distributed", steps=steps, thermo=steps, every=steps)
    return mpicount.run(args.exe, "in.distributed", 4, wd, LIB, f"d{steps}", variables)


wd = tempfile.mkdtemp(prefix="distributed_counts_")
h.copy_inputs(["in.distributed", "in.fe_common"], wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 4, 4), (0.4, 0.2, 0.2))
text, short = counted(wd, 200)
_, long_ = counted(wd, 600)
steps = 400
pairs = int(re.search(r"(\d+) \(shared node, neighbour\) pairs in all", text).group(1))
diffs = mpicount.difference(long_, short)
# The body's code: the adapter, the driver, the exchange and the MPI services they use. Its
# collectives at set-up and thermo steps are seen in the whole run (so the pattern does match).
BODY_CODE = r"FixFemBody|BodyDriver|NodeExchange|add_mpi_services"
seen = sum(c for d in mpicount.as_diff(long_) for (m, caller, f, cat), (c, _) in d["sites"].items()
           if cat == "coll" and re.search(BODY_CODE, caller))
h.check(seen > 0, f"the body's collectives are recognised in the whole run ({seen} calls at "
                  f"set-up and thermo steps)")
exchange_bytes = exchange_msgs = 0
for d in diffs:
    rank_msgs, own_coll, restep = 0, [], 0
    for (module, caller, func, cat), (count, nbytes) in d["sites"].items():
        if cat == "send" and "NodeExchange" in caller:
            exchange_bytes += nbytes
            rank_msgs += count
        if cat == "coll" and count and re.search(BODY_CODE, caller):
            if func == "MPI_Allreduce" and "check_squeezed" in caller:
                restep += count
            else:
                own_coll.append(f"{count} x {func} in {caller}")
    h.check(not own_coll, f"rank {d['rank']}: no collective of the body's code between thermo "
                          f"steps but the sub-cycling check ({'; '.join(own_coll) or 'none'})")
    h.check(restep == steps // 100,
            f"rank {d['rank']}: {restep} min-reductions of the stable step in {steps} steps "
            f"(substeps auto: one every 100 steps)")
    partners = sum(1 for r, x in enumerate(d["dest"]) if x[0] > 0 and r != d["rank"])
    h.check(abs(rank_msgs / steps - partners) < 1e-9,
            f"rank {d['rank']}: {rank_msgs / steps:.2f} exchange messages per step to "
            f"{partners} neighbouring parts")
    exchange_msgs += rank_msgs
h.check(exchange_bytes / steps == 24 * pairs,
        f"exchange sends {exchange_bytes / steps:.0f} bytes per step = 24 x {pairs} interface "
        f"pairs")
coll = [d["totals"]["coll"][0] / steps for d in diffs]
print(f"note: all collectives per rank and step (the host's neighbour checks included): "
      f"{', '.join(f'{c:.2f}' for c in coll)}")
shutil.rmtree(wd, ignore_errors=True)

# Refusals: what a distributed body does not do yet stops the run naming the keyword (particle
# contact it does: tests/integration/test_distributed_contact.py).
BODY = ("fix body all fem/body file block.msh type 2 density 2400 youngs 3e10 poisson 0.2 "
        "parallel distributed")
REFUSALS = {
    # (breaking distributed bodies and their pieces' contact: test_distributed_fracture.py,
    # test_distributed_self_contact.py)
    "rigid yes": ("", " rigid yes", "does not work with 'rigid yes'"),
}
for name, (before, extra, expect) in REFUSALS.items():
    wd = tempfile.mkdtemp(prefix="distributed_refuse_")
    h.copy_inputs(["in.fe_common"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (2, 2, 2), (0.1, 0.1, 0.1))
    with open(os.path.join(wd, "in.refuse"), "w") as f:
        f.write(f"include in.fe_common\n{before}timestep 1e-7\n{BODY}{extra}\nrun 1\n")
    out = h.run(args.exe, "in.refuse", np_=2, workdir=wd, expect_fail=True)
    h.check(expect in out and "parallel distributed" in out,
            f"parallel distributed with {name}: refused naming the keyword")
