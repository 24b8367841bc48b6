"""An FE-only body runs with the ordinary particle preamble (pair gran, default atom sorting).

The same vibrating block as in.vibration, which uses today's FE-only preamble (no pair style,
'atom_modify sort 0 0.0'), must give the same thermo and energy history to 1e-12 relative at
np 1 and np 2; with the pair style left out and default sorting too. Sorting comes back once
particles arrive. The one empty-box case that still stops (a type-1 material stiffer than pair
gran accepts) stops at the first run with the host's error naming 'hard_particles yes', and runs
with it.
"""
import os
import tempfile

import harness as h

args = h.parse_args()
EXE = os.path.abspath(args.exe)  # runs happen in temporary directories
STEPS, EVERY, THERMO = 400, 10, 50
BASE = dict(steps=STEPS, every=EVERY, thermo=THERMO, model="elastic")
ORDINARY = dict(BASE, pair=1, E1=1e8, btype=2, hard=0, tail=0)


def scene(script, np_, variables, expect_fail=False, inputs=("in.fe_only_preamble",)):
    wd = tempfile.mkdtemp(prefix="fe_only_")
    h.make_box_mesh(os.path.join(wd, "block.msh"), (4, 3, 2), (0.2, 0.1, 0.05))
    h.copy_inputs(list(inputs), wd)
    out = h.run(EXE, script, np_=np_, workdir=wd, variables=variables,
                expect_fail=expect_fail)
    return wd, out


def history(wd, out):
    """Thermo rows of the body's run and the energy file, as one flat list of numbers."""
    runs = h.thermo_blocks(out)
    rows = [v for r in runs[0][1] for v in r]
    e = h.read_csv(os.path.join(wd, "energy.csv"))
    return rows, [v for k in ("kinetic", "strain", "total") for v in e[k]]


def max_rel(a, b):
    return max(h.rel_diff(x, y) for x, y in zip(a, b) if max(abs(x), abs(y)) > 1e-300)


# A probe run of the reference gives the stable step; half of it keeps the block vibrating.
_, probe = scene("in.vibration", 1, dict(BASE, dt=1e-9, steps=0, every=1, thermo=1),
                 inputs=("in.vibration", "in.fe_common"))
dt = 0.5 * h.stable_dt(probe)

for np_ in (1, 2):
    ref_wd, ref_out = scene("in.vibration", np_, dict(BASE, dt=dt),
                            inputs=("in.vibration", "in.fe_common"))
    ref_thermo, ref_energy = history(ref_wd, ref_out)
    h.check(len(ref_thermo) == 4 * (STEPS // THERMO + 1)
            and len(ref_energy) == 3 * (STEPS // EVERY + 1),
            f"np={np_}: reference (today's FE-only preamble) ran {STEPS} steps")
    for pair in (1, 0):
        what = "pair gran" if pair else "no pair style"
        wd, out = scene("in.fe_only_preamble", np_, dict(ORDINARY, dt=dt, pair=pair))
        thermo, energy = history(wd, out)
        h.check(len(thermo) == len(ref_thermo) and len(energy) == len(ref_energy),
                f"np={np_}, {what}, default sorting: runs {STEPS} steps with no particles")
        d = max(max_rel(thermo, ref_thermo), max_rel(energy, ref_energy))
        h.check(d <= 1e-12, f"np={np_}, {what}: thermo and energy history equal the reference "
                            f"(max rel. difference {d:.1e})")
        h.check("atom sorting off for this run" in out,
                f"np={np_}, {what}: the run says that atom sorting is off")

    # Particles created after an FE-only run are sorted again (input's default setting).
    wd, out = scene("in.fe_only_preamble", np_, dict(ORDINARY, dt=dt, steps=20, tail=1))
    with open(os.path.join(wd, "order.txt")) as f:
        ids = [int(l) for l in f.read().split("ITEM: ATOMS id")[1].split()]
    h.check(out.count("atom sorting off for this run") == 1,
            f"np={np_}: sorting is off only for the run without particles")
    if np_ == 1:
        h.check(ids == [2, 3, 1], f"np=1: atoms created against x order come out sorted ({ids})")
    else:
        h.check(sorted(ids) == [1, 2, 3], f"np=2: all three added atoms are there ({ids})")

# The case that still stops: pair gran checks the type-1 material even without particles.
for np_ in (1, 2):
    _, out = scene("in.fe_only_preamble", np_, dict(ORDINARY, dt=dt, E1=2e11), expect_fail=True)
    err = [l for l in out.splitlines() if "ERROR" in l]
    h.check(bool(err) and "hard_particles yes" in err[0] and "Step" not in out,
            f"np={np_}: stiff type-1 material stops before the first step, naming "
            f"'hard_particles yes' ({err[0].strip() if err else 'no ERROR line'})")
    _, out = scene("in.fe_only_preamble", np_, dict(ORDINARY, dt=dt, E1=2e11, hard=1))
    h.check(len(h.thermo_blocks(out)[0][1]) == STEPS // THERMO + 1,
            f"np={np_}: with 'hard_particles yes' the same scene runs")
