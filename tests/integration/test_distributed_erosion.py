"""fix fem/body ... parallel distributed with erosion: a body that erodes gives the same run at 1,
2, 3 and 4 ranks (issue #13 item 3: "erosion ... give the same body at 1, 2, 3 and 4 ranks").

Scene (inputs/in.fast_impact, test_erosion's): the 20 mm sphere hits the clamped J2 steel block
(yield 5e8, hardening 2e9) at 1500 m/s with `erosion plastic_strain 0.3` (erosion_mass keep, the
default; 10 x 10 x 5 cells of tets, 3000 elements), 700 steps of 1e-8 s (elements erode from
step 525 on, in 6 batches). Replicated at np 1 against `parallel distributed` at np 2, 3 and 4,
and with `substeps 2` (erosions in the first FE step of a host step wait for the follow-up at
the second) at np 3:

* the same erosion log lines (step, count, cause, elements, the totals);
* every energy-file column within 1e-10 of its scale (largest |value| of the column; the issue's
  figure), and the thermo (contacts, particle + body energy) within 1e-10 of its scale: the sphere
  meets, in the host step of an erosion, the surface without the eroded elements on every rank
  (the parts' facet ghosts are renewed before the contact).
* item 4: with `rebalance 1.05 every 50` at np 3 the yielded and eroded elements' modelled work
  triggers repartitions (logged), and the run is the np 1 run (1e-10);
* restart: written at step 560 by np 3 distributed (after 3 batches), continued at np 2
  distributed and at np 1 replicated (the parts' records merged), and written and continued at
  np 1: the later lines, energy rows and thermo rows as those of the uninterrupted np 1 run,
  within 1e-10 of each column's scale; continued at np 3 distributed (each rank takes its part
  back as it was): thermo and energy rows from step 560 on as the uninterrupted np 3 run's, byte
  for byte.
* cost, with the PMPI counter at np 3 (difference of a 200- and a 300-step run, before the first
  erosion): the body's code takes exactly one integer reduction per host step for the erosion
  (BodyDriver::distributed_erosion), and no other collective but the stable step's re-estimate
  every 100 steps, the boxes' all-gather per host re-neighbouring and the energy file's sums;
  the same with `erosion_mass remove`.
`erosion_mass remove` (each eroded element's lumped mass leaves with it; a node that no part
holds an element of anymore keeps neither mass nor velocity): replicated at np 1 against
distributed at np 2, 3 and 4, and a restart written by np 3 after 3 batches continued at np 2:
* the same erosion log lines, energy file and thermo within 1e-10 of each column's scale (the
  thermo with the eroded mass f_body[24] and the body's mass f_body[28]);
* mass was removed (eroded_mass > 0), and the body's mass plus the eroded mass is the initial
  mass at every thermo row to round-off (1e-13 relative) at every rank count;
* `fix fem/vtk` at np 3 (issue #13 item 5): a .pvtu of 3 pieces per frame in the .pvd, the
  pieces holding every element at step 0 and, at the last step, the elements of np 1's frame
  (the eroded ones left out);
* with the PMPI counter (as above, before the first erosion): the same collectives as with
  `keep`, and the shared-node sums send exactly 16 bytes more per (shared node, neighbour) pair
  and step (5 doubles in the force sum instead of 3).
"""
import os
import re
import shutil
import sys
import tempfile

import numpy as np

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "tests", "support"))
import mpicount  # noqa: E402

args = h.parse_args()
TOL = 1e-10
BODY = ("fixed zmin material j2 yield 5e8 hardening 2e9 erosion plastic_strain 0.3 "
        "energy_file energy.csv 10")
STEPS = 700
RESTART_AT = 560
# in.fast_impact continued from its restart file (the sphere's state is in it).
CONTINUE = """hard_particles  yes
read_restart    erosion.restart
newton          off
neighbor        0.002 bin
neigh_modify    delay 0
communicate     single vel yes
fix m1 all property/global youngsModulus peratomtype 2e11 2e11
fix m2 all property/global poissonsRatio peratomtype 0.3 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 2 1.0 1.0 1.0 1.0
fix m4 all property/global coefficientFriction peratomtypepair 2 0.0 0.0 0.0 0.0
pair_style      gran model hertz tangential history
pair_coeff      * *
fix body all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 ${bodykw}
fix integr all nve/sphere
timestep        1e-8
compute ke all ke
variable tot equal c_ke+f_body+f_body[16]
thermo_style    custom step f_body[7] v_tot
thermo_modify   format float %.10g
thermo          50
run             ${steps}
"""


THERMO = "thermo_style    custom step f_body[7] v_tot\nthermo_modify   format float %.10g\n"
# erosion_mass remove: also the eroded mass (21 + 3G) and the body's mass (25 + 3G; G = 1 group),
# with every digit.
MASS_THERMO = ("thermo_style    custom step f_body[7] v_tot f_body[24] f_body[28]\n"
               "thermo_modify   format float %.17g\n")


def run(np_, parallel, steps=STEPS, body=BODY, expect_fail=False, write=False, resume=None,
        then=0, thermo=THERMO, vtk=False):
    """parallel: the keyword's value and what follows it (e.g. 'distributed substeps 2'); write:
    a restart file at the end (then: and `then` steps more after it); resume: the directory of a
    run that wrote one (continued); vtk: fem/vtk frames at the first and the last step."""
    if vtk:
        thermo += f"fix vtk all fem/vtk {steps} frame body body\n"
    wd = tempfile.mkdtemp(prefix=f"distributed_erosion_{np_}_")
    h.copy_inputs(["in.fast_impact"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (10, 10, 5), (0.1, 0.1, 0.05))
    script = "in.fast_impact"
    path = os.path.join(wd, script)
    with open(path) as f:
        text = f.read()
    assert THERMO in text and THERMO in CONTINUE
    with open(path, "w") as f:
        f.write(text.replace(THERMO, thermo))
    if write:
        with open(os.path.join(wd, script), "a") as f:
            f.write("write_restart   erosion.restart\n")
            if then:
                f.write(f"run             {then}\n")
    if resume:
        shutil.copy(os.path.join(resume, "erosion.restart"), wd)
        script = "in.continue"
        with open(os.path.join(wd, script), "w") as f:
            f.write(CONTINUE.replace(THERMO, thermo))
    out = h.run(args.exe, script, np_=np_, workdir=wd, expect_fail=expect_fail,
                variables=dict(v=1500.0, dt=1e-8, x0=0.05, y0=0.05, steps=steps, every=50,
                               bodykw=f"{body} parallel {parallel}"))
    if expect_fail:
        return out
    with open(os.path.join(wd, "log.liggghts")) as f:
        log = f.read()
    lines = [ln for ln in log.splitlines() if re.search(r"eroded|substep", ln)]
    blocks = h.thermo_blocks(out)
    return dict(lines=lines, energy=h.read_csv(os.path.join(wd, "energy.csv")), thermo=blocks[-1],
                wd=wd, out=out)


def worst_thermo(a, b):
    """Rows of b matched to a's by step (b may be a continued run's, whose set-up row at the
    restart step falls between a's rows: rows a does not have are left out)."""
    (ha, ra), (hb, rb) = a, b
    by_step = {r[0]: r for r in ra}
    rb = [r for r in rb if r[0] in by_step]
    if ha != hb or len(rb) < 2:
        return float("inf"), "shape"
    ra, rb = np.array([by_step[r[0]] for r in rb]), np.array(rb)
    worst, name = 0.0, ""
    for j, col in enumerate(ha):
        w = float(np.max(np.abs(ra[:, j] - rb[:, j]))) / max(np.max(np.abs(ra[:, j])), 1e-300)
        if w > worst:
            worst, name = w, col
    return worst, name


def compare(label, ref, d, after=-1):
    """after: a continued run's first step (its lines from there on)."""
    lines = [ln for ln in ref["lines"] if int(re.search(r"step (\d+):", ln).group(1)) > after]
    h.check(len(lines) > 0 and d["lines"] == lines,
            f"{label}: the same {len(lines)} erosion / substep log lines"
            + ("" if d["lines"] == lines else f"\n  np 1: {lines[:3]}\n  "
               f"{label}: {d['lines'][:3]}"))
    w, col = h.worst_energy_by_step(ref["energy"], d["energy"])
    h.check(w < TOL, f"{label}: energy file within {w:.1e} of each column's scale "
                     f"(worst: {col}; tolerance {TOL:g})")
    w, col = worst_thermo(ref["thermo"], d["thermo"])
    h.check(w < TOL, f"{label}: thermo within {w:.1e} of each column's scale "
                     f"(worst: {col})")


ref = run(1, "replicated")
eroded = int(ref["energy"]["eroded_elements"][-1])
batches = [ln for ln in ref["lines"] if "eroded" in ln]
h.check(eroded > 0 and len(batches) > 1,
        f"np 1: {eroded} elements erode in {len(batches)} logged batches")
for np_ in (2, 3, 4):
    compare(f"np {np_} distributed", ref, run(np_, "distributed"))
# Two FE steps per host step: the parts' erosions in the first substep wait for the follow-up at
# the second (the lines and the stable step in the order of the evaluations).
ref2 = run(1, "replicated substeps 2")
compare("substeps 2, np 3 distributed", ref2, run(3, "distributed substeps 2"))
# Item 4: a yielding, eroding body's modelled work drifts (a yielded element at twice the cost of
# an elastic one, an eroded one at none); with `rebalance 1.05 every 50` at np 3 the parts are
# repartitioned (logged) and the run stays the np 1 run. Before, only breaking bodies were checked.
reb = run(3, "distributed rebalance 1.05 every 50")
with open(os.path.join(reb["wd"], "log.liggghts")) as f:
    repartitions = [ln for ln in f.read().splitlines() if "repartitioned" in ln]
h.check(len(repartitions) > 0, f"rebalance 1.05 every 50, np 3: {len(repartitions)} repartitions "
                               f"logged ({repartitions[0].strip() if repartitions else '-'})")
compare("rebalance 1.05 every 50, np 3 distributed", ref, reb)

# Restart of the eroded distributed body (the parts' records, merged), continued at
# np 2 distributed and np 1 replicated, and the replicated restart (written and continued at
# np 1): each against the uninterrupted np 1 run. The set-up evaluation of a continued run repeats
# the last step's bulk-viscosity forces (those of its mid-step velocities, in the record); taken
# from the full-step velocities they put the clamp's reaction 1.3e-4 of its scale off on the
# set-up row and the energies 1e-7 after (before that fix).
rest = STEPS - RESTART_AT
compare(f"restart at step {RESTART_AT} of np 1, continued at np 1", ref,
        run(1, "replicated", steps=rest,
            resume=run(1, "replicated", steps=RESTART_AT, write=True)["wd"]), after=RESTART_AT)
first = run(3, "distributed", steps=RESTART_AT, write=True, then=rest)  # and goes on to STEPS
for np_, parallel in ((2, "distributed"), (1, "replicated")):
    compare(f"restart at step {RESTART_AT} of np 3, continued at np {np_} {parallel}", ref,
            run(np_, parallel, steps=rest, resume=first["wd"]), after=RESTART_AT)
# At the rank count that wrote it each rank takes its part back as it was: the continued run is
# the uninterrupted np 3 run byte for byte.
same = run(3, "distributed", steps=rest, resume=first["wd"])
h.check_rows_as_uninterrupted(
    "restart of the eroded body at np 3, continued at np 3 (against the uninterrupted np 3 run)",
    RESTART_AT, first["out"], same["out"], os.path.join(first["wd"], "energy.csv"),
    os.path.join(same["wd"], "energy.csv"))

# Cost while nothing erodes: one integer reduction per host step (counted at np 3).
LIB = os.path.join(os.path.dirname(os.path.abspath(args.exe)), "libfracdem_mpicount.so")
h.check(os.path.isfile(LIB), f"PMPI counter {LIB} built")
wd = tempfile.mkdtemp(prefix="distributed_erosion_counts_")
h.copy_inputs(["in.fast_impact"], wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (10, 10, 5), (0.1, 0.1, 0.05))


def counted(steps, body):
    variables = dict(v=1500.0, dt=1e-8, x0=0.05, y0=0.05, steps=steps, every=steps,
                     bodykw=f"{body} parallel distributed")
    return mpicount.run(args.exe, "in.fast_impact", 3, wd, LIB, f"c{steps}", variables)


def builds(text):
    return int(re.search(r"Neighbor list builds\s*=\s*(\d+)", text).group(1))


def check_counts(label, body):
    short_text, short = counted(200, body)
    long_text, long_ = counted(300, body)
    regroupings = builds(long_text) - builds(short_text)
    pairs = int(re.search(r"(\d+) \(shared node, neighbour\) pairs in all", long_text).group(1))
    sent = 0  # bytes of the shared-node sums (NodeExchange) of all ranks in the 100 steps
    for d in mpicount.difference(long_, short):
        erosion, restep, gathers, other = 0, 0, 0, []
        for (module, caller, func, cat), (count, nbytes) in d["sites"].items():
            if cat == "send" and "NodeExchange" in caller:
                sent += nbytes
            if cat != "coll" or not count or not re.search(r"FixFemBody|BodyDriver|all_gather",
                                                            caller):
                continue
            if "energy_row" in caller:
                continue  # output (energy_file every 10 steps): sums over the parts
            if "distributed_erosion" in caller and func == "MPI_Allreduce":
                erosion += count
            elif "check_squeezed" in caller and func == "MPI_Allreduce":
                restep += count
            elif "all_gather" in caller:
                gathers += count
            else:
                other.append(f"{count} x {func} in {caller}")
        h.check(erosion == 100 and restep == 1 and gathers == regroupings and not other,
                f"{label}rank {d['rank']}: in 100 steps without erosion {erosion} erosion "
                f"reductions (one per host step), {restep} stable-step re-estimates, {gathers} box "
                f"all-gathers ({regroupings} host re-neighbourings), other collectives: "
                f"{'; '.join(other) or 'none'}")
    return sent, pairs


keep_sent, pairs = check_counts("", BODY)
# erosion_mass remove: the shared nodes' mass travels with the force sum, no collective is added;
# the force sum carries 5 doubles per (shared node, neighbour) pair instead of 3 (the contact
# forces' sum, the same in both runs before the first erosion, stays at 3).
remove_sent, _ = check_counts("erosion_mass remove, ", BODY + " erosion_mass remove")
h.check(remove_sent - keep_sent == 16 * pairs * 100,
        f"erosion_mass remove: the shared-node sums send {(remove_sent - keep_sent) / 100:.0f} "
        f"bytes per step more than with keep = 16 x {pairs} (shared node, neighbour) pairs")

# erosion_mass remove: the mass of shared nodes leaves on every sharer (with the force sum).
REMOVE = BODY + " erosion_mass remove"


def check_mass(label, d, m0):
    """The body's mass plus the eroded mass against the initial mass m0, at every thermo row."""
    head, rows = d["thermo"]
    im, ie = head.index("body[28]"), head.index("body[24]")
    worst = max(abs(r[im] + r[ie] - m0) for r in rows) / m0
    removed = d["energy"]["eroded_mass"][-1]
    h.check(removed > 0 and rows[-1][ie] > 0 and worst < 1e-13,
            f"{label}: {removed:.6g} kg removed (eroded_mass), body mass + eroded mass = initial "
            f"{m0:.6g} kg within {worst:.1e} relative at all {len(rows)} thermo rows")


def frame_cells(d, step):
    """Cells of the fem/vtk frame of `step` (the pieces' sum for a .pvtu) and whether the .pvd
    lists it."""
    name = f"frame_{step:010d}"
    stem = os.path.join(d["wd"], name)
    pvd = open(os.path.join(d["wd"], "frame.pvd")).read()
    if os.path.isfile(stem + ".vtu"):
        paths, listed = [stem + ".vtu"], name + ".vtu" in pvd
    else:
        pieces = re.findall(r'Piece Source="([^"]+)"', open(stem + ".pvtu").read())
        paths = [os.path.join(d["wd"], p) for p in pieces]
        listed = name + ".pvtu" in pvd
    cells = 0
    for path in paths:
        head = open(path, "rb").read(4000).decode("latin-1")
        cells += int(re.search(r'NumberOfCells="(\d+)"', head).group(1))
    return cells, len(paths), listed


ref_r = run(1, "replicated", body=REMOVE, thermo=MASS_THERMO, vtk=True)
m0 = ref_r["thermo"][1][0][ref_r["thermo"][0].index("body[28]")]
h.check(abs(m0 - 7800 * 0.1 * 0.1 * 0.05) < 1e-12 * m0 and ref_r["thermo"][1][0][0] == 0,
        f"remove, np 1: initial mass {m0:.12g} kg = density x volume (3.9 kg)")
check_mass("remove, np 1 replicated", ref_r, m0)
for np_ in (2, 3, 4):
    d = run(np_, "distributed", body=REMOVE, thermo=MASS_THERMO, vtk=np_ == 3)
    compare(f"remove, np {np_} distributed", ref_r, d)
    check_mass(f"remove, np {np_} distributed", d, m0)
    if np_ != 3:
        continue
    # fem/vtk of the eroded distributed body: one piece per rank per frame, the .pvtu in the .pvd,
    # the pieces together holding the replicated frame's active elements.
    lost = int(ref_r["energy"]["eroded_elements"][-1])
    first_cells, last_cells = frame_cells(d, 0), frame_cells(d, STEPS)
    ref_cells = frame_cells(ref_r, STEPS)[0]
    h.check(first_cells == (3000, 3, True) and last_cells == (3000 - lost, 3, True) and
            ref_cells == 3000 - lost,
            f"remove, np 3: fem/vtk frames of 3 pieces in the .pvd, {first_cells[0]} cells at step "
            f"0 and {last_cells[0]} at step {STEPS} (np 1's frame: {ref_cells}; {lost} eroded)")
first = run(3, "distributed", steps=RESTART_AT, body=REMOVE, thermo=MASS_THERMO, write=True)
d = run(2, "distributed", steps=rest, body=REMOVE, thermo=MASS_THERMO, resume=first["wd"])
compare(f"remove, restart at step {RESTART_AT} of np 3, continued at np 2 distributed", ref_r, d,
        after=RESTART_AT)
check_mass("remove, continued at np 2", d, m0)

