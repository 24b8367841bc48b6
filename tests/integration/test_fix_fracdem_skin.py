"""fix fracdem/skin: a wetted stack thrown at a floor (tests/integration/inputs/in.skin_stack)
run with fixed skins and with the fix, which changes the skin up and down during the run, gives
the same trajectories within round-off (no contact or bridge missed), at np 1 and np 2; a control
run that rebuilds too seldom shows that the comparison sees a missed contact; the skin is kept
through a restart; the argument errors."""
import math
import os
import re
import tempfile

import numpy as np

import harness as h

args = h.parse_args()
SC = (1 + 0.35 / 2) * 4e-11 ** (1 / 3)  # the input's bridge rupture distance (Lian et al.)
STEPS, EVERY = 1000, 100
SMIN, SMAX = 0.00045, 0.002
# Round-off: positions are of order 1e-2 m; 1e-10 m leaves room for a different summation order
# (another rank split) and is four orders below the control's missed contacts.
TOL = 1e-10


def run(np_=1, expect_fail=False, script="in.skin_stack", wd=None, **variables):
    wd = wd or tempfile.mkdtemp(prefix=f"skin_{np_}_")
    h.copy_inputs(["in.skin_stack", "in.skin_stack_continue"], wd)
    v = dict(skin=0.001, tune=0, n=50, smin=SMIN, smax=SMAX, steps=STEPS, every=EVERY)
    v.update(variables)
    out = h.run(args.exe, script, np_=np_, workdir=wd, variables=v, expect_fail=expect_fail)
    return out, wd


def frames(wd):
    """Positions sorted by id, one (n, 3) array per dump frame."""
    with open(os.path.join(wd, "pos.dump")) as f:
        blocks = f.read().split("ITEM: TIMESTEP")[1:]
    out = []
    for b in blocks:
        lines = b.splitlines()
        start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
        out.append(np.array([[float(w) for w in l.split()] for l in lines[start:] if l.strip()]))
    return out


def worst(a, b):
    h.check(len(a) == len(b) == STEPS // EVERY + 1, f"{len(a)} and {len(b)} frames dumped")
    return max(float(np.abs(x[:, 1:] - y[:, 1:]).max()) for x, y in zip(a, b))


CHANGE = re.compile(r"fix fracdem/skin: step (\d+): skin (\S+) -> (\S+) from the next step")

# ---- fixed skins: the reference, and how far apart they are among themselves ---------------------
BUILDS = re.compile(r"Neighbor list builds = (\d+)")
fixed, builds = {}, {}
for s in (SMIN, 0.001, SMAX):
    out, wd = run(skin=s)
    fixed[s], builds[s] = frames(wd), int(BUILDS.findall(out)[-1])
ref = fixed[SMIN]
spread = max(worst(ref, f) for f in fixed.values())
h.check(spread <= TOL, f"fixed skins {sorted(fixed)}: trajectories agree within {spread:.3g} m "
        f"<= {TOL:g} m")
h.check(builds[SMIN] >= 10 and builds[SMIN] > builds[SMAX],
        f"list builds {builds}: the scene rebuilds often, less often with a larger skin")

# ---- the fix, at np 1 and np 2 -----------------------------------------------------------------
for np_, clock in ((1, "wall"), (2, "cpu")):
    out, wd = run(np_=np_, tune=1, clock=clock)
    changes = [(int(s), float(a), float(b)) for s, a, b in CHANGE.findall(out)]
    ups = sum(b > a for _, a, b in changes)
    downs = sum(b < a for _, a, b in changes)
    h.check(ups >= 2 and downs >= 2,
            f"np {np_}, clock {clock}: the fix changed the skin {len(changes)} times ({ups} up, {downs} down)")
    h.check(all(SMIN <= b <= SMAX for _, _, b in changes), f"np {np_}: every skin within bounds")
    d = worst(ref, frames(wd))
    h.check(d <= TOL, f"np {np_}: trajectories with the fix equal to the fixed skin's within "
            f"{d:.3g} m <= {TOL:g} m")
    if np_ == 1:
        tuned_wd, last_skin = wd, h.column(h.thermo_blocks(out), "sk")[-1]

# ---- control: lists rebuilt every 200 steps without a distance check miss contacts -------------
control = worst(ref, frames(run(skin=SMIN, nevery=200, check="no")[1]))
h.check(control > 1e4 * TOL, f"control (rebuilds every 200 steps, unchecked): trajectories differ "
        f"by {control:.3g} m, so the comparison sees missed contacts")

# ---- restart: the skin is kept ------------------------------------------------------------------
out, _ = run(script="in.skin_stack_continue", wd=tuned_wd, steps=0)
got = h.column(h.thermo_blocks(out), "sk")[0]
h.check(math.isclose(got, last_skin, rel_tol=1e-12),
        f"restart: the run goes on with the skin {got:.6g} of the restart file "
        f"(the first run ended at {last_skin:.6g}; 'neighbor' says 0.0015)")

# ---- errors -------------------------------------------------------------------------------------
ERRORS = [
    (dict(n=0), "N must be a whole number of steps >= 1"),
    (dict(n=2.5), "N must be a whole number of steps >= 1"),
    (dict(smin=0), "SKIN_MIN must be a number > 0"),
    (dict(smin=0.002, smax=0.001), "SKIN_MAX must be a number > SKIN_MIN"),
    (dict(smax="big"), "SKIN_MAX 'big' is not a number"),
    (dict(clock="sundial"), "keyword 'clock': expected 'cpu' or 'wall', got 'sundial'"),
    (dict(late_balance=1), "fix bal (balance/graph) must be defined before this fix"),
    (dict(smin=0.0003), f"write SKIN_MIN {math.ceil(SC * 1e6) / 1e6:.3g} or more"),
]
for variables, expected in ERRORS:
    out, _ = run(tune=1, steps=0, expect_fail=True, **variables)
    h.check(f"fix fracdem/skin: " in out and expected in out,
            f"error for {variables}: '{expected}'")
print("OK")
