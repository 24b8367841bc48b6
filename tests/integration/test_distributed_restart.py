"""Restart files of `parallel distributed` bodies, read at another rank count (issue #13 item 5).

Scene (inputs/in.distributed_restart): the clamped steel block of test_distributed_body (768
tet4, corotational) made to yield (J2, yield 20 MPa, so that every element carries plastic
history and bulk-viscosity accounts), 600 steps, `write_restart`, 400 more. Each rank of a
distributed body writes its part's record (the nodes it owns and its elements by global index, and
its own state as it holds it); rank 0 writes them one after the other behind the element
partition. The same rank count takes each part back; another rank count, or a replicated
body, merges them into the whole body (a distributed body then takes its part of a new
partition). Asserted, against the uninterrupted np 1 replicated run:

* np 3 distributed restart continued at np 2 distributed, at np 1 (replicated), at np 4
  distributed; and the np 1 replicated restart continued at np 3 distributed: every thermo
  column of the continued run (body energy, kinetic, strain, dissipated, stable step, momentum,
  the clamp's reaction) within 1e-9 of the column's scale, the tolerance test_distributed_body
  holds distributed runs to (other summation orders at shared nodes);
* np 3 distributed continued at np 3 distributed (each rank takes its part of the record back as
  it was, with the stored partition): the thermo rows from step 600 on as the uninterrupted np 3
  run's, byte for byte;
* with --old-exe (a build writing the earlier format, one merged record): its np 3 file continued
  at np 3 and np 2 distributed, within the same tolerance;
* the continued runs start from the stored state: their first row (step 600) equals the
  uninterrupted run's row at step 600 within the same tolerance, and the kinetic energy there is
  not that of the initial velocities.
"""
import os
import sys
import tempfile

import harness as h

_parser = h.parser()
_parser.add_argument("--old-exe", default="",
                     help="a build that writes the earlier format (the parts merged into one "
                          "record, e.g. main before per-part records): its np 3 file is continued")
args = h.parse_args(_parser)
BASE = dict(dt=1e-7, thermo=100, first=600, rest=400)
TOL = 1e-9


def written(np_, parallel, exe=None):
    wd = tempfile.mkdtemp(prefix=f"dist_restart_{parallel}_{np_}_")
    h.copy_inputs(["in.distributed_restart", "in.distributed_continue", "in.fe_common"], wd)
    h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 4, 4), (0.4, 0.2, 0.2))
    text = h.run(exe or args.exe, "in.distributed_restart", np_=np_, workdir=wd,
                 variables=dict(BASE, parallel=parallel))
    return wd, h.thermo_blocks(text), text


def continued(wd, np_, parallel, text=False):
    out = h.run(args.exe, "in.distributed_continue", np_=np_, workdir=wd,
                variables=dict(BASE, parallel=parallel))
    return out if text else h.thermo_blocks(out)[-1]


def worst_scaled(ref, got):
    """h.worst_scaled of two thermo blocks (header, rows), which must have the same shape."""
    (head, a), (head_b, b) = ref, got
    if head != head_b or len(a) != len(b):
        return float("inf"), f"shape {len(a)} vs {len(b)} rows"
    as_columns = lambda rows: {n: [r[j] for r in rows] for j, n in enumerate(head)}  # noqa: E731
    return h.worst_scaled(as_columns(a), as_columns(b))


def main():
    wd1, runs1, _ = written(1, "replicated")
    reference = runs1[-1]  # steps 600..1000 of the uninterrupted run
    dissipated = reference[1][0][10]  # f_body[16]: plastic + viscous work at the restart step
    h.check(dissipated > 0, f"the block yields before the restart (dissipated {dissipated:.4g} J): "
                            "the record carries plastic and viscous history")
    wd3, runs3, text3 = written(3, "distributed")
    w, where = worst_scaled(reference, runs3[-1])
    h.check(w < TOL, f"np 3 distributed (uninterrupted) = np 1 replicated within {w:.1e} ({where})")
    ke0 = runs1[0][1][0][2]  # column 2: f_body[1], the kinetic energy
    for label, wd, np_, parallel in (("np 3 distributed -> np 2 distributed", wd3, 2, "distributed"),
                                     ("np 3 distributed -> np 1", wd3, 1, "replicated"),
                                     ("np 3 distributed -> np 4 distributed", wd3, 4, "distributed"),
                                     ("np 1 replicated -> np 3 distributed", wd1, 3, "distributed")):
        got = continued(wd, np_, parallel)
        w, where = worst_scaled(reference, got)
        h.check(w < TOL, f"{label}: continued thermo equals the uninterrupted run "
                         f"({len(got[1])} rows, worst {w:.1e} of scale in {where})")
        ke = got[1][0][2]
        h.check(abs(ke - ke0) > 1e-3 * abs(ke0),
                f"{label}: starts from the stored state (kinetic {ke:.6g} J, initial {ke0:.6g} J)")
    if args.old_exe:  # files of the earlier format are still read, at the same and another count
        wdo, _, _ = written(3, "distributed", exe=os.path.abspath(args.old_exe))
        for np_ in (3, 2):
            w, where = worst_scaled(reference, continued(wdo, np_, "distributed"))
            h.check(w < TOL, f"earlier format (np 3, {args.old_exe}) -> np {np_} distributed: "
                             f"continued thermo equals the uninterrupted run (worst {w:.1e} of "
                             f"scale in {where})")
    # At the rank count that wrote it: each rank takes its part back as it was, and the continued
    # run is the uninterrupted np 3 run byte for byte (thermo at 17 digits).
    h.check_rows_as_uninterrupted("np 3 distributed -> np 3 distributed (against the "
                                  "uninterrupted np 3 run)", BASE["first"], text3,
                                  continued(wd3, 3, "distributed", text=True))
    print("OK")


if __name__ == "__main__":
    sys.exit(main())
