"""Particles hit a distributed body (issue #13 item 2): `parallel distributed` at np 2, 3, 4
against the replicated body at np 1.

Scene (inputs/in.distributed_contact): six steel spheres (d 10 mm, particle modulus 1e5 Pa, pair
gran between them) shot obliquely (0.3-0.5 m/s down, 1.5-3 m/s along) onto the top of a free,
soft corotational block (0.2 x 0.1 x 0.05 m, 12 x 6 x 3 cells of 6 tet4, E 1e8 Pa) centred on
the host's rank boundary x = 0.5; no gravity, no walls. The spheres stay in contact ~10 ms while they slide 10-30 mm
across the top: over element boundaries, the METIS parts' boundaries and (np 2, 4) the host's
rank boundary, so particles change host rank and facets change part during contact. Asserted:

* every thermo column (particle translational and rotational kinetic energy, body energy, kinetic
  and strain energy, contact work, particle momentum, positions of four spheres) of every np
  within 1e-9 of the column's scale of the replicated run (the body's kinetic and strain energy:
  of the body's energy; the strain energy is a small part of it, and the replicated body at np 2
  already differs from np 1 by 1.1e-9 of the strain column's own scale, 9.7e-12 of the body's
  energy), and the contact count equal at every thermo step (the facets, their order and the
  history keys of the distributed surface are the replicated body's, so only the summation order
  of nodal forces differs);
* the same at np 3 with the particles owned by `fix balance/graph` (graph partition, not the
  host's slabs: the particle boxes come from each rank's particles);
* total momentum (particles + body) conserved to round-off: its largest change over the run
  within 1e-10 of the largest change of the particles' momentum (the impulse the body exchanged);
* the spheres touched the body (contacts at the peak >= 4) and were slowed by it;
* with the PMPI counter at 4 ranks (difference of a 400- and a 1200-step run, thermo only at the
  ends): the contact's only collective is the boxes' MPI_Allgather, once per host
  re-neighbouring ("Neighbor list builds"), and the body's code issues no other collective between
  thermo steps but the sub-cycling's min-reduction of the parts' stable steps, one every 100
  steps (added with it; none before); the facet ghosts do travel (point-to-point messages of the contact exchange).
"""
import os
import re
import sys
import tempfile

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "tests", "support"))
import mpicount  # noqa: E402

args = h.parse_args()
STEPS, THERMO = 2400, 100


def scene(np_, parallel, balance=0):
    wd = tempfile.mkdtemp(prefix=f"distributed_contact_{parallel}_{np_}_")
    h.copy_inputs(["in.distributed_contact"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (12, 6, 3), (0.2, 0.1, 0.05),
                    origin=(0.4, -0.05, -0.05))
    text = h.run(args.exe, "in.distributed_contact", np_=np_, workdir=wd,
                 variables=dict(parallel=parallel, steps=STEPS, thermo=THERMO, balance=balance))
    runs = h.thermo_blocks(text)
    header, _ = runs[-1]
    return text, {n: h.column(runs, n) for n in header if n != "Step"}


def worst_scaled(a, b):
    """h.worst_scaled, the body's kinetic and strain energies scaled by the body's energy (the
    strain energy is a small part of it and already differs by 1.1e-9 of its own scale between
    np 1 and np 2 replicated)."""
    return h.worst_scaled(a, b, lambda name: "body" if name in ("body[1]", "body[2]") else name)


def momentum_balance(cols):
    worst = 0.0
    for d in "xyz":
        q, p = cols[f"q{d}"], cols[f"p{d}"]
        impulse = max(abs(x - q[0]) for x in q)
        worst = max(worst, max(abs(x - p[0]) for x in p) / impulse)
    return worst


_, ref = scene(1, "replicated")
h.check(max(ref["body[7]"]) >= 4, f"the spheres touched the body ({max(ref['body[7]']):.0f} "
                                    f"contacts at the peak)")
h.check(ref["KinEng"][-1] < 0.9 * ref["KinEng"][0],
        f"the contacts slowed the spheres (KE {ref['KinEng'][0]:.4g} -> {ref['KinEng'][-1]:.4g} J)")
w = momentum_balance(ref)
h.check(w < 1e-10, f"np 1 replicated: total momentum change {w:.1e} of the impulse < 1e-10")
for np_, balance in ((2, 0), (3, 0), (4, 0), (3, 1)):
    text, got = scene(np_, "distributed", balance)
    h.check(f"distributed over {np_} ranks" in text, f"np {np_}: the body is distributed")
    if balance:
        h.check("repartitioned" in text, f"np {np_}: fix balance/graph owns the particles")
        np_ = f"{np_} (balance/graph)"
    h.check(got["body[7]"] == ref["body[7]"],
            f"np {np_}: contact count equal at every thermo step (peak {max(got['body[7]']):.0f})")
    w, where = worst_scaled(ref, got)
    h.check(w < 1e-9, f"np {np_} distributed vs np 1 replicated: thermo within {w:.1e} of the "
                      f"column scale (worst: {where}) < 1e-9")
    w = momentum_balance(got)
    h.check(w < 1e-10, f"np {np_}: total momentum change {w:.1e} of the impulse < 1e-10")

# Counts at 4 ranks.
LIB = os.path.join(os.path.dirname(os.path.abspath(args.exe)), "libfracdem_mpicount.so")
h.check(os.path.isfile(LIB), f"PMPI counter {LIB} built")
wd = tempfile.mkdtemp(prefix="distributed_contact_counts_")
h.copy_inputs(["in.distributed_contact"], wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (12, 6, 3), (0.2, 0.1, 0.05),
                origin=(0.4, -0.05, -0.05))


def counted(steps):
    variables = dict(parallel="distributed", steps=steps, thermo=steps, balance=0)
    return mpicount.run(args.exe, "in.distributed_contact", 4, wd, LIB, f"c{steps}", variables)


def builds(text):
    return int(re.search(r"Neighbor list builds\s*=\s*(\d+)", text).group(1))


short_text, short = counted(400)
long_text, long_ = counted(1200)
regroupings = builds(long_text) - builds(short_text)
BODY_CODE = r"FixFemBody|BodyDriver|NodeExchange|add_mpi_services|all_gather|sparse_exchange"
ghost_msgs = 0
for d in mpicount.difference(long_, short):
    gathers, restep, other = 0, 0, []
    for (module, caller, func, cat), (count, nbytes) in d["sites"].items():
        if cat == "send" and "sparse_exchange" in caller:
            ghost_msgs += count
        if cat != "coll" or not count or not re.search(BODY_CODE, caller):
            continue
        if "all_gather" in caller:
            gathers += count
        elif func == "MPI_Allreduce" and "check_squeezed" in caller:
            restep += count  # substeps auto: the parts' stable steps, every 100 steps
        else:
            other.append(f"{count} x {func} in {caller}")
    h.check(not other, f"rank {d['rank']}: no other collective of the body's code between thermo "
                       f"steps ({'; '.join(other) or 'none'})")
    h.check(restep == 800 // 100, f"rank {d['rank']}: {restep} min-reductions of the stable "
                                  f"step in 800 steps (one every 100)")
    h.check(gathers == regroupings and regroupings > 0,
            f"rank {d['rank']}: {gathers} box all-gathers in 800 steps = {regroupings} host "
            f"re-neighbourings")
h.check(ghost_msgs > 0, f"the facet ghosts travel: {ghost_msgs} contact messages in 800 steps")
