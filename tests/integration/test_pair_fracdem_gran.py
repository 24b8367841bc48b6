"""pair_style fracdem/gran: two spheres joined by a liquid bridge against Willett's closed form
(capillary) and Pitois's (viscous) within 3 %, zero beyond Lian's rupture distance, a bridge that
forms only at contact; a bridged pair oscillating with no energy gained; np 1 = np 2; the skin rule
and the keyword errors; without a bridge, the thermo of a stock scene equal to pair gran's."""
import math
import os
import re
import tempfile

import harness as h

GAMMA, THETA, VOL = 0.072, 0.4, 8e-12  # the inputs' bridge
SC = (1 + THETA / 2) * VOL ** (1 / 3)  # Lian et al. 1993


def derjaguin(r1, r2):
    return 2 * r1 * r2 / (r1 + r2)


def willett(gap, rs):
    """Willett et al. 2000, closed form; gap >= 0."""
    s = gap * math.sqrt(rs / VOL)
    return 2 * math.pi * rs * GAMMA * math.cos(THETA) / (1 + 1.05 * s + 2.5 * s * s)


def pitois(gap, rate, rs, mu):
    """Pitois et al. 2000, viscous normal force; positive when the gap opens."""
    shape = 1 - 1 / math.sqrt(1 + 2 * VOL / (math.pi * rs * gap * gap))
    return 6 * math.pi * mu * rs * rs * rate / gap * shape * shape


def willett_potential(gap, rs, n=4000):
    """-int_gap^SC F ds by Simpson's rule (independent of the kernel's closed form)."""
    h_ = (SC - gap) / n
    s = sum((1 if k in (0, n) else 4 if k % 2 else 2) * willett(gap + k * h_, rs)
            for k in range(n + 1))
    return -s * h_ / 3


args = h.parse_args()


def run(script, np_=1, variables=None, expect_fail=False, edit=None):
    wd = tempfile.mkdtemp(prefix=f"pair_fracdem_{script[3:]}_{np_}_")
    h.copy_inputs([script], wd)
    if edit:
        path = os.path.join(wd, script)
        with open(path) as f:
            text = f.read()
        with open(path, "w") as f:
            f.write(edit(text))
    return h.run(args.exe, script, np_=np_, workdir=wd, variables=variables,
                 expect_fail=expect_fail)


def rows(block):
    header, data = block
    return [dict(zip(header, r)) for r in data]


# ---- pulling two unequal spheres apart: force against separation -------------------------------
RS = derjaguin(1e-3, 0.8e-3)
V = 0.05


def check_pull(blocks, mu, label):
    h.check(len(blocks) == 6, f"{label}: six phases ran")
    a, b, c, d, e = (rows(blocks[k]) for k in (0, 1, 2, 3, 5))
    h.check(min(r["gap"] for r in a) < 0.5 * SC and all(r["f1"] == 0 for r in a),
            f"{label}: approaching to {min(r['gap'] for r in a):.3g} m < S_c = {SC:.3g} m "
            "without touching: no force (no bridge before contact)")
    touch = [r for r in b if r["gap"] < 0]
    h.check(len(touch) > 0 and all(r["f1"] == 0 for r in b if r["gap"] > 0),
            f"{label}: no force until the surfaces touch ({len(touch)} samples in contact)")
    worst, n = 0.0, 0
    for r in c + e:
        if 1e-7 < r["gap"] < SC - 1e-9:  # thermo rounds the gap: no sample on the edge
            expected = willett(r["gap"], RS) + (pitois(r["gap"], V, RS, mu) if mu else 0)
            worst = max(worst, abs(r["f1"] - expected) / expected)
            n += 1
    h.check(n > 100 and worst < 0.03,
            f"{label}: bridged force against Willett's closed form"
            f"{' + Pitois' if mu else ''} over {n} gaps: worst {100 * worst:.2g} % (<= 3 %)")
    beyond = [r for r in c if r["gap"] >= SC + 1e-9]
    h.check(len(beyond) > 10 and all(r["f1"] == 0 for r in beyond),
            f"{label}: zero force at and beyond S_c ({len(beyond)} samples up to "
            f"{max(r['gap'] for r in beyond):.3g} m)")
    h.check(min(r["gap"] for r in d) < 0.5 * SC and all(r["f1"] == 0 for r in d),
            f"{label}: after rupture, approaching inside S_c without touching: no force "
            "(the bridge reforms only at contact)")
    h.check(any(r["gap"] > 0 and r["f1"] > 0 for r in e),
            f"{label}: after touching again the bridge pulls once more")


out1 = run("in.bridge_pull", variables=dict(skin=3e-4, mu=0, v=V))
pull1 = h.thermo_blocks(out1)
check_pull(pull1, 0, "np 1, no viscosity")
pull2 = h.thermo_blocks(run("in.bridge_pull", np_=2, variables=dict(skin=3e-4, mu=0, v=V)))
h.check(pull1 == pull2, "np 2 (the spheres on different ranks) gives the same thermo as np 1")
check_pull(h.thermo_blocks(run("in.bridge_pull", variables=dict(skin=3e-4, mu=0.05, v=V))),
           0.05, "viscosity 0.05 Pa s")

# ---- a wetted stack falling through a rank boundary: bridges migrate with their particles -----
stacks = [rows(h.thermo_blocks(run("in.bridge_stack", np_=n, variables=dict(steps=10000)))[0])
          for n in (1, 2)]
worst = max(max(abs(p[k] - q[k]) / max(abs(p[k]), 1e-300) for k in ("KinEng", "bridge"))
            for p, q in zip(*stacks) if p["Step"] > 0)
h.check(len(stacks[0]) == len(stacks[1]) == 21 and all(r["bridge"] < 0 for r in stacks[0]),
        f"wetted stack: bridged throughout "
        f"(bridge energy {stacks[0][-1]['bridge']:.3g} J at the end)")
# A bridge lost in an exchange or a rebuild would shift the bridge energy by ~1e-8 J in 3e-5 J.
h.check(worst < 1e-9, f"wetted stack split along z: np 2 equals np 1 in kinetic and bridge energy "
                      f"(worst relative difference {worst:.2g})")

# ---- a bridged pair released from rest: no energy gained ---------------------------------------
osc = rows(h.thermo_blocks(run("in.bridge_oscillate"))[0])
RE = derjaguin(1e-3, 1e-3)
contacts = sum(1 for p, q in zip(osc, osc[1:]) if p["gap"] > 0 >= q["gap"])
h.check(contacts >= 3 and max(r["gap"] for r in osc) < SC,
        f"the wetted pair oscillates inside its bridge: {contacts} contacts, largest gap "
        f"{max(r['gap'] for r in osc):.3g} m < S_c")
apart = [r for r in osc if r["gap"] > 0]
worst_pe = max(abs(r["bridge"] - willett_potential(r["gap"], RE)) for r in apart[::50])
e0 = osc[0]["KinEng"] + osc[0]["bridge"]
h.check(worst_pe < 1e-6 * abs(e0),
        f"the pair energy is the bridge potential -int_S^S_c F ds "
        f"(worst {worst_pe:.2g} J of {abs(e0):.3g} J)")
gain = max(r["KinEng"] + r["bridge"] - e0 for r in apart)
h.check(gain < 1e-4 * abs(e0), f"kinetic + bridge energy never exceeds its start "
                               f"(largest excess {gain:.2g} J, start {e0:.4g} J)")
# Between two contacts nothing dissipates: the energy of one flight is constant.
flights, current = [], []
for r in osc:
    if r["gap"] > 0:
        current.append(r["KinEng"] + r["bridge"])
    elif current:
        flights.append(current)
        current = []
drift = max(max(f) - min(f) for f in flights if len(f) > 2)
h.check(drift < 1e-4 * abs(e0), f"energy constant within each flight (drift {drift:.2g} J)")

# ---- the skin rule and the keyword errors -------------------------------------------------------
out = run("in.bridge_pull", variables=dict(skin=1e-4, mu=0, v=V), expect_fail=True)
m = re.search(r"write 'neighbor (\S+) bin'", out)
h.check(m is not None and SC <= float(m.group(1)) <= 1.01 * SC,
        f"a skin below S_c = {SC:.6g} is refused with the number to write "
        f"({m.group(1) if m else out[-300:]})")
blocks = h.thermo_blocks(run("in.bridge_pull", variables=dict(skin=m.group(1), mu=0, v=V)))
h.check(blocks == pull1, f"with the skin it names ({m.group(1)}) the run goes through, same thermo")
for bad, word, named in (("surface_tension 0.072", "surface_tension -1", "surface_tension"),
                         ("volume 8e-12", "volume -8e-12", "volume"),
                         ("contact_angle 0.4", "contact_angle 1.6", "contact_angle"),
                         ("bridge willett", "bridge rabinovich", "rabinovich"),
                         ("model hertz", "model hooke", "hooke"),
                         ("contact_angle 0.4", "angle 0.4", "angle"),
                         ("surface_tension 0.072", "surface_tenison 0.072",
                          "did you mean 'surface_tension'?")):
    out = run("in.bridge_pull", variables=dict(skin=3e-4, mu=0, v=V), expect_fail=True,
              edit=lambda t, a=bad, b=word: t.replace(a, b))
    m = re.search(r"ERROR.*pair_style fracdem/gran: ([^\n]*)", out)
    h.check(m is not None and f"'{named}'" in m.group(1) or (m and named in m.group(1)),
            f"'{word}' is refused naming '{named}': {m.group(1) if m else out[-300:]}")

# ---- without a bridge: the stock settling scene gives pair gran's thermo ------------------------
stock = h.thermo_blocks(run("in.packing"))
ours = h.thermo_blocks(run("in.packing", edit=lambda t: t.replace(
    "pair_style gran model hertz", "pair_style fracdem/gran model hertz")))
h.check(len(stock) == 3 and stock == ours,
        f"stock packing scene: fracdem/gran's thermo equals pair gran's "
        f"({sum(len(b[1]) for b in stock)} rows)")

# ---- restart mid-run: the bridge state travels in the restart file ----------------------------
full = rows(h.thermo_blocks(run("in.bridge_oscillate", variables=dict(steps=12000)))[0])
wd = tempfile.mkdtemp(prefix="pair_fracdem_restart_")
h.copy_inputs(["in.bridge_oscillate", "in.bridge_oscillate_continue"], wd)
with open(os.path.join(wd, "in.bridge_oscillate"), "a") as f:
    f.write("write_restart\tstate.restart\n")
h.run(args.exe, "in.bridge_oscillate", workdir=wd, variables=dict(steps=6000))
h.run(args.exe, "in.bridge_oscillate_continue", np_=2, workdir=wd, variables=dict(steps=6000))
# From rank 0's log: the host's restart reader prints a line on every rank, which may land in the
# middle of a thermo line of the combined output.
with open(os.path.join(wd, "log.liggghts")) as f:
    later = rows(h.thermo_blocks(f.read())[0])
tail = [r for r in full if r["Step"] >= 6000]
h.check(0 < full[600]["gap"] < SC and full[600]["bridge"] < 0,
        f"at the restart (step 6000) the pair is apart and bridged (gap {full[600]['gap']:.3g} m)")
h.check(later == tail, f"restarted at step 6000 (np 2, wet no) the thermo equals the "
                       f"uninterrupted run's ({len(tail)} rows)")
