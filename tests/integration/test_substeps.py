"""Sub-cycling of a body whose stable FE step is below the host step (`substeps auto|N|off`).

(a) Free vibration of an elastic block (in.vibration) at host step dt = 2.9 x its stable step:
    `substeps auto` takes 3 FE steps of dt / 3 per host step, and every energy-file row equals,
    digit for digit, the row at the same time of a run at host step dt / 3 without sub-cycling
    (no contact: the same FE operations in the same order, so the same bits); `substeps 3` gives
    the same file as `auto`.
(b) A sphere hits a free steel block obliquely (in.substeps_impact: restitution 1, no friction,
    no gravity) at a host step of 2.5 x the block's stable step (3 substeps), np 1 and 2:
    particle + body momentum conserved at every thermo step to 1e-9 of its scale (the tolerance
    of test_contact_momentum), particle + body energy after the rebound within 1 % of the
    impact energy (the tolerance of test_fast_impact), and the body's own account (kinetic +
    strain = contact work, nothing else acts) closed within 1e-3 of the impact energy.
(c) The notched concrete beam of test_fracture_stress (in.fracture_stress_notched) struck at
    100 m/s at a host step of 7.7e-7 s, 0.994 of its set-up stable step 7.746e-7 s: its stable
    step falls below the host step at a fracture check (the log shows the crack or erosion and
    the change to 2 FE substeps at the same step), the run finishes with finite output; with
    `substeps off` the same run stops at that step (dt_check error), naming the cracked body.
(d) n = 1 (host step 0.5 x stable): `substeps auto` writes the same energy file as
    `substeps off` but the last column (substeps, all 1), and the same thermo output.
About 20 s.
"""
import math
import os
import re
import subprocess
import sys
import tempfile

import harness as h

args = h.parse_args()


def vibration(wd, dt, steps, every, extra=""):
    """in.vibration (corotational) with `extra` keywords; returns (energy file lines, output)."""
    with open(os.path.join(wd, "in.vibration"), "w") as f:
        text = open(os.path.join(h.ROOT, "tests", "integration", "inputs", "in.vibration")).read()
        f.write(text.replace("energy_file energy.csv", extra + " energy_file energy.csv"))
    out = h.run(args.exe, "in.vibration", workdir=wd,
                variables=dict(dt=repr(dt), model="corotational", steps=steps, every=every,
                               thermo=every))
    with open(os.path.join(wd, "energy.csv")) as f:
        return f.read().splitlines(), out


# (a) and (d): the block of test_fem_energy_drift.
wd = tempfile.mkdtemp(prefix="substeps_vibration_")
h.make_box_mesh(os.path.join(wd, "block.msh"), (4, 3, 2), (0.2, 0.1, 0.05))
h.copy_inputs(["in.fe_common"], wd)
_, probe = vibration(wd, 1e-12, 0, 1)
dts = h.stable_dt(probe)
dt = 2.9 * dts
sub, out = vibration(wd, dt, 300, 10)
h.check(re.search(r"stable FE time step \S+ < host time step \S+: 3 FE substeps per host step",
                  out) is not None, "(a) dt = 2.9 x stable: 'substeps auto' logs 3 FE substeps")
one, _ = vibration(wd, dt / 3, 900, 30, "substeps off")
fixed, _ = vibration(wd, dt, 300, 10, "substeps 3")
h.check(sub[0] == one[0] + ",substeps", "(a) header: the columns of 'substeps off' + substeps")
same = len(sub) == len(one) == 32 and all(
    a.split(",", 1)[1] == b.split(",", 1)[1] + ",3" for a, b in zip(sub[1:], one[1:]))
h.check(same, f"(a) all {len(sub) - 1} rows (time, energies, works, substeps 3) equal digit for "
              f"digit those of host step dt / 3 without sub-cycling at the same times")
h.check(fixed == sub, "(a) 'substeps 3' writes the same energy file as 'substeps auto'")
strain = [float(r.split(",")[3]) for r in sub[1:]]
h.check(max(strain) > 0.2 * float(sub[1].split(",")[2]), "(a) the block does vibrate")

auto1, out_auto = vibration(wd, 0.5 * dts, 500, 10)
off1, out_off = vibration(wd, 0.5 * dts, 500, 10, "substeps off")
h.check(auto1[0] == off1[0] + ",substeps"
        and all(a == b + ",1" for a, b in zip(auto1[1:], off1[1:])) and len(auto1) == 52,
        "(d) n = 1: 'substeps auto' writes the rows of 'substeps off' (+ substeps 1), byte for byte")
h.check(h.thermo_blocks(out_auto) == h.thermo_blocks(out_off), "(d) n = 1: the same thermo output")

# (b) Impact on a free block.
wd = tempfile.mkdtemp(prefix="substeps_impact_")
h.copy_inputs(["in.substeps_impact"], wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (10, 10, 5), (0.1, 0.1, 0.05))
probe = h.run(args.exe, "in.substeps_impact", workdir=wd,
              variables=dict(dt=1e-12, bodykw="", every=1, steps=0))
dts = h.stable_dt(probe)
for np_ in (1, 2):
    dt = 2.5 * dts
    out = h.run(args.exe, "in.substeps_impact", np_=np_, workdir=wd,
                variables=dict(dt=repr(dt), bodykw="", every=1, steps=int(1.2e-4 / dt)))
    runs = h.thermo_blocks(out)
    n = h.column(runs, "body[24]")
    contacts = h.column(runs, "body[7]")
    h.check(min(n) == max(n) == 3 and max(contacts) == 1 and contacts[-1] == 0,
            f"(b) np {np_}: 3 substeps per host step throughout, one contact, ended")
    for comp in ("px", "py", "pz"):
        p = h.column(runs, comp)
        worst = max(abs(x - p[0]) for x in p) / max(abs(x) for x in p)
        h.check(worst < 1e-9, f"(b) np {np_}: particle + body {comp[1]}-momentum conserved at every "
                              f"step, max relative change {worst:.1e}")
    tot = h.column(runs, "tot")
    ratio = tot[-1] / tot[0]
    h.check(abs(ratio - 1) < 0.01, f"(b) np {np_}: particle + body energy after the rebound / "
                                   f"impact energy {ratio:.5f} within 1 %")
    e = h.read_csv(os.path.join(wd, "energy.csv"))
    gap = max(abs(t - w) for t, w in zip(e["total"], e["contact_work"])) / tot[0]
    h.check(gap < 1e-3, f"(b) np {np_}: the body's account kinetic + strain = contact work closes "
                        f"within {gap:.1e} of the impact energy (< 1e-3)")

# (c) The shattering beam.
wd = tempfile.mkdtemp(prefix="substeps_fracture_")
subprocess.run([sys.executable, "-m", "fracdem.meshgen", "notched_beam", "0.2", "0.05", "0.01",
                "0.005", "beam.msh"], cwd=wd, check=True, stdout=subprocess.DEVNULL,
               env=dict(os.environ, PYTHONPATH=os.path.join(h.ROOT, "python")))
text = open(os.path.join(h.ROOT, "tests", "integration", "inputs",
                         "in.fracture_stress_notched")).read()
text = text.replace("timestep        2.5e-7", "timestep        7.7e-7")
for name, extra in (("auto", ""), ("off", " substeps off")):
    with open(os.path.join(wd, f"in.{name}"), "w") as f:
        f.write(text.replace("contact_bodies ${contact}", "contact_bodies ${contact}" + extra))
out = h.run(args.exe, "in.auto", workdir=wd, variables=dict(steps=1500))
log = open(os.path.join(wd, "log.liggghts")).read()
m = re.search(r"stable FE time step ([0-9.e+-]+), host time step ([0-9.e+-]+)", out)
h.check(m is not None and abs(float(m.group(2)) / float(m.group(1)) - 0.994) < 0.001,
        f"(c) host step {m.group(2)} = 0.994 x the set-up stable step {m.group(1)}")
changes = re.findall(r"fix fem/body beam: step (\d+): stable FE time step \S+ < host time step "
                     r"\S+: (\d+) FE substeps per host step", out)
topology = set(re.findall(r"fix fem/body beam: step (\d+): (?:crack at node|failed element|"
                          r"element \d+ inverted|eroded)", log))
at_topology = [(s, n) for s, n in changes if s in topology]
h.check(len(at_topology) > 0, f"(c) the stable step fell below the host step after a topology "
                              f"change: n > 1 from step(s) {at_topology} (changes: {changes})")
rows = h.thermo_blocks(out)
values = [v for _, block in rows for row in block for v in row]
h.check(h.column(rows, "Step")[-1] == 1500 and all(math.isfinite(v) for v in values),
        "(c) the sub-cycled run reaches step 1500 with finite thermo output")
out = h.run(args.exe, "in.off", workdir=wd, variables=dict(steps=1500), expect_fail=True)
first = at_topology[0][0] if at_topology else "?"
h.check(f"at step {first} the stable FE time step of the cracked body is" in out,
        f"(c) with 'substeps off' the same run stops at step {first} (dt_check error)")
