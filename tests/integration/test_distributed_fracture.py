"""fix fem/body ... parallel distributed with fracture nodal: a body that breaks gives the same
run at 1, 2, 3 and 4 ranks (issue #13 item 3).

Scene (inputs/in.distributed_fracture): the free Rankine tet4 bar of in.fracture_cut_3d (1536
tets, concrete-like f_t 3 MPa, G_f 100 N/m: CEB-FIP Model Code 1990 ranges), its halves thrown
apart at 5 m/s each, contact_bodies no. Replicated at np 1 against `parallel distributed`:

* boundary cracks (`fracture nodal every 5`) at np 2, 3, 4: the same log lines of every split,
  cut and fragment count (same steps, nodes, copies, normals to 3 decimals), the same node and
  fragment counts, every energy-file column within 1e-10 of its scale (largest |value| of the
  column; the issue's figure), every thermo column within 1e-10 of its scale (momenta: of the
  bar's m v);
* item 4: at np 3 with `rebalance 1.2 every 20` the damage gathering in the middle part (damaged
  elements modelled at twice the cost) logs a repartition (max/mean above 1.2, predicted below,
  elements moved) and the run stays the np 1 run (same lines, 1e-10);
* cracks through tets (`min_size 0.2`) at np 3: the same; its restart file, written at step 500
  (after the first cuts and splits, before the last), continued at np 2 distributed and at np 1
  replicated: the log lines after step 500, thermo and energy-file rows as the uninterrupted
  run's, within 1e-10 of each column's scale; continued at np 3 distributed (each rank takes its
  part of the record back as it was): thermo and energy-file rows from step 500 on as the
  uninterrupted np 3 run's, byte for byte; its last fem/vtk frame's pieces carry the
  replicated frame's split, fragment and mesh_element fields (by global number);
* three steel spheres hitting the bar across its crack (facet ghosts of the changed parts) at
  np 2 against np 1: thermo (particle kinetic energy, body energies, contact count, momenta)
  within 1e-10 of each column's scale;
* the bar parted by erosion (`erosion damage 0.999`) at np 2 and 3: the same (1e-10), and the
  energy file's fragment count row by row as np 1's.
"""
import glob
import os
import re
import sys

import numpy as np

import distributed_scenes as ds
import harness as h

args = h.parse_args()
sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import fem  # noqa: E402

MASS, SPEED = 2400 * 0.16 * 0.04 * 0.04, 5.0
RESTART_AT = 500  # after the first cuts, before the last (the min_size run's)


def run(np_, parallel, frac, steps, balls=0, restart_at=0, vtk=0):
    return ds.run_bar(args.exe, np_, parallel, frac, steps, balls=balls, restart_at=restart_at,
                      vtk=vtk)


def resume(wd, np_, parallel, frac, rest):
    return ds.resume_bar(args.exe, wd, np_, parallel, frac, rest)


def compare(label, ref, other, after=-1):
    """after: a continued run's first step (its events from there on); momenta scaled by the
    bar's m v."""
    ds.compare(label, ref, other, MASS * SPEED, after=after, need_events=True)


# Boundary cracks: np 2, 3, 4 against np 1.
ref = run(1, "replicated", "every 5", 600)
e = ref["energy"]
h.check(e["fragments"][-1] >= 2 and e["split_nodes"][-1] > 0,
        f"the bar breaks: {int(e['split_nodes'][-1])} split nodes, "
        f"{int(e['fragments'][-1])} fragments")
for np_ in (2, 3, 4):
    compare(f"every 5, np {np_} distributed", ref, run(np_, "distributed", "every 5", 600))

# Item 4: the damage gathers in the middle part of np 3's slabs; its modelled work (damaged
# elements cost twice) passes 1.2 times the mean, the body is repartitioned, the run unchanged.
reb = run(3, "distributed rebalance 1.2 every 20", "every 5", 600)
lines = re.findall(r"step (\d+): parts max/mean ([0-9.]+) > 1.2, repartitioned \(predicted "
                   r"([0-9.]+), (\d+) elements moved\)", "\n".join(
                       open(os.path.join(reb["wd"], "log.liggghts")).read().splitlines()))
h.check(len(lines) > 0 and all(float(m) > 1.2 and float(p) < 1.2 and int(n) > 0
                               for _, m, p, n in lines),
        f"rebalance 1.2 every 20 at np 3: {len(lines)} repartition(s) logged "
        f"({'; '.join(f'step {s}: {m} -> predicted {p}, {n} moved' for s, m, p, n in lines)})")
compare("rebalanced np 3", ref, reb)

# Cracks through tets.
ref_cut = run(1, "replicated", "every 5 min_size 0.2", 1000, vtk=1000)
h.check(any("crack through element" in ln for ln in ref_cut["events"]),
        "min_size 0.2: elements are cut")
cut3 = run(3, "distributed", "every 5 min_size 0.2", 1000, restart_at=RESTART_AT, vtk=1000)
compare("min_size 0.2, np 3 distributed", ref_cut, cut3)

# The last frame's pieces carry the whole body's crack fields: every global node's 'split' and
# every global element's 'fragment' and 'mesh_element' as in the replicated frame.
whole = fem.read_vtu(os.path.join(ref_cut["wd"], "bar_0000001000.vtu"))
pieces = sorted(glob.glob(os.path.join(cut3["wd"], "bar_0000001000_p*.vtu")))
same, seen = True, set()
for piece in pieces:
    d = fem.read_vtu(piece)
    gn = d["point_data"]["global_node"].astype(int)
    ge = d["cell_data"]["global_element"].astype(int)
    seen.update(ge.tolist())
    same &= np.array_equal(d["point_data"]["split"], whole["point_data"]["split"][gn])
    for f in ("fragment", "mesh_element"):
        same &= np.array_equal(d["cell_data"][f], whole["cell_data"][f][ge])
h.check(len(pieces) == 3 and same and len(seen) == len(whole["cell_data"]["fragment"]),
        f"np 3 frame: {len(pieces)} pieces hold every element once with the replicated frame's "
        f"split, fragment and mesh_element fields")

# The cracked distributed body written at np 3 goes on at np 2 distributed and at np 1
# replicated (the record is the whole body's) as the uninterrupted run.
for np_, parallel in ((2, "distributed"), (1, "replicated")):
    compare(f"restart at step {RESTART_AT} of np 3, continued at np {np_} {parallel}", ref_cut,
            resume(cut3["wd"], np_, parallel, "every 5 min_size 0.2", 1000 - RESTART_AT),
            after=RESTART_AT)

# At the rank count that wrote it each rank takes its part back as it was (the stored partition,
# its own nodes and accounts): the continued run is the uninterrupted np 3 run byte for byte.
same = resume(cut3["wd"], 3, "distributed", "every 5 min_size 0.2", 1000 - RESTART_AT)
compare(f"restart at step {RESTART_AT} of np 3, continued at np 3 distributed", cut3, same,
        after=RESTART_AT)
h.check_rows_as_uninterrupted(
    "restart of the broken body at np 3, continued at np 3 (against the uninterrupted np 3 run)",
    RESTART_AT, cut3["out"], same["out"], os.path.join(cut3["wd"], "energy.csv"),
    os.path.join(same["wd"], "energy_continued.csv"))

# Spheres hitting the breaking body: facet ghosts of the parts after each change.
ref_b = run(1, "replicated", "every 5", 600, balls=1)
hdr, rows = ref_b["thermo"]
dist_b = run(2, "distributed", "every 5", 600, balls=1)
compare("spheres on the breaking bar, np 2 distributed", ref_b, dist_b)
ke = [r[hdr.index("KinEng")] for r in rows]
h.check(min(ke) < 0.5 * ke[0], f"the spheres hit the bar (their kinetic energy "
                               f"{ke[0]:.3g} -> {min(ke):.3g} J)")

# A bar that parts by erosion (`erosion damage 0.999`: its failing elements leave before a crack
# opens): the energy file's fragment count follows the erosions at np 2 as at np 1 (before: the
# distributed body counted fragments at cracks only and wrote 1 to the end).
ERODE = "every 5 erosion damage 0.999"
ref_e = run(1, "replicated", ERODE, 600)
frag_e = np.array(ref_e["energy"]["fragments"]).astype(int)
h.check(frag_e[-1] >= 2, f"erosion parts the bar ({frag_e[-1]} fragments at the end)")
for np_ in (2, 3):
    got_e = run(np_, "distributed", ERODE, 600)
    ds.compare(f"eroding bar, np {np_} distributed", ref_e, got_e, MASS * SPEED)
    h.check(list(np.array(got_e["energy"]["fragments"]).astype(int)) == list(frag_e),
            f"eroding bar, np {np_} distributed: the fragment count of every energy row as np 1's")
print("OK")
