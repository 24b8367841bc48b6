"""Runs one scene of tests/lammps/inputs under LIGGGHTS and LAMMPS and compares the histories
(test_fracture_match.py, test_body_contact_match.py)."""
import filecmp
import os
import re
import shutil
import subprocess
import sys
import tempfile

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)
# Both hosts build the same core sources with the same compiler and flags; see the tests' notes.
TOL = 1e-10
EVENT = re.compile(r"^fix fem/body body: step \d+: (crack at node|eroded|\d+ fragments).*$", re.M)


def scene_dir(scene, host, np_):
    """A scratch directory with every input of tests/lammps/inputs and the scene's meshes."""
    wd = tempfile.mkdtemp(prefix=f"lmp_{scene}_{host}_{np_}_")
    for name in os.listdir(lh.INPUTS):
        shutil.copy(os.path.join(lh.INPUTS, name), wd)
    h.copy_inputs(["in.fe_common"], wd)
    if scene == "body_contact2d":
        env = dict(os.environ, PYTHONPATH=os.path.join(h.ROOT, "python"))
        for name, el in (("a.msh", "tri3"), ("b.msh", "quad4")):
            subprocess.run([sys.executable, "-m", "fracdem.meshgen", "rect", "8", "8", "0.1", "0.1",
                            "-o", os.path.join(wd, name), "--element", el], check=True, env=env,
                           stdout=subprocess.DEVNULL)
    elif scene == "rigid_impact":
        h.make_box_mesh(os.path.join(wd, "block.msh"), (8, 8, 4), (0.04, 0.04, 0.02),
                        (-0.02, -0.02, -0.02))
    elif scene == "fracture_bar2d":
        subprocess.run([sys.executable, "-m", "fracdem.meshgen", "rect", "40", "10", "0.2", "0.05",
                        "-o", os.path.join(wd, "bar.msh"), "--element", "tri3"], check=True,
                       stdout=subprocess.DEVNULL,
                       env=dict(os.environ, PYTHONPATH=os.path.join(h.ROOT, "python")))
    elif scene == "j2_erosion":
        h.make_box_mesh(os.path.join(wd, "bar.msh"), (10, 2, 2), (0.1, 0.02, 0.02),
                        (0, -0.01, -0.01))
    return wd


def run_both(scene, np_, variables, energy="energy.csv"):
    """(workdir, output, energy columns) per host."""
    out = {}
    for host in ("liggghts", "lammps"):
        wd = scene_dir(scene, host, np_)
        var = dict(variables, host=host)
        if host == "liggghts":
            text = h.run(args.exe, f"in.{scene}", np_=np_, workdir=wd, variables=var)
        else:
            text = lmp.run(f"in.{scene}", np_=np_, workdir=wd, variables=var)
        out[host] = (wd, text, h.read_csv(os.path.join(wd, energy)))
    return out


def worst_difference(a, b, what):
    """Largest difference of two energy files' columns relative to each column's largest value."""
    h.check(list(a) == list(b) and len(a["step"]) == len(b["step"]) > 1,
            f"{what}: the same columns and {len(a['step'])} rows")
    worst = 0.0
    for col in a:
        scale = max(max(abs(v) for v in a[col]), 1e-300)
        worst = max(worst, max(abs(x - y) for x, y in zip(a[col], b[col])) / scale)
    return worst


def compare_hosts(scene, np_, runs, energy="energy.csv", events=True):
    """Checks the hosts' energy files (and split / erosion lines) agree; LAMMPS's columns."""
    what = f"{scene} np {np_} ({energy})"
    (wd_g, out_g, e_g), (wd_l, out_l, e_l) = runs["liggghts"], runs["lammps"]
    worst = worst_difference(e_g, e_l, what)
    same = filecmp.cmp(os.path.join(wd_g, energy), os.path.join(wd_l, energy), shallow=False)
    h.check(worst <= TOL, f"{what}: {len(e_g)} columns x {len(e_g['step'])} rows agree between "
                          f"hosts, largest difference {worst:.2e} of the column scale (<= {TOL:g}; "
                          f"files {'byte-identical' if same else 'differ in the last digits'})")
    if not events:
        return e_l
    lines_g = [m.group(0) for m in EVENT.finditer(out_g)]
    lines_l = [m.group(0) for m in EVENT.finditer(out_l)]
    h.check(lines_g == lines_l and len(lines_g) > 0,
            f"{what}: the same {len(lines_g)} split / fragment / erosion lines under both hosts")
    return e_l
