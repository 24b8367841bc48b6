"""Under LAMMPS, fix fem/body refuses what it does not support by name: unknown keywords, keywords
of the LIGGGHTS adapter that are not yet supported here, and bad values (as the LIGGGHTS adapter).
"""
import os
import shutil
import tempfile

import lammps_harness as h_lmp

h = h_lmp.harness
args = h_lmp.parse_args()
lmp = h_lmp.Lammps(args)
wd = tempfile.mkdtemp(prefix="lmp_errors_")
shutil.copy(os.path.join(h_lmp.INPUTS, "in.lammps_preamble"), wd)
h.make_box_mesh(os.path.join(wd, "block.msh"), (2, 2, 2), (0.1, 0.1, 0.1))

BODY = "fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3"
cases = [
    (BODY + " colour red", "fix fem/body: unknown keyword 'colour'"),
    (BODY + " fracture nodal", "keyword 'fracture' is not yet supported under LAMMPS"),
    (BODY + " rigid yes", "keyword 'rigid' is not yet supported under LAMMPS"),
    (BODY + " energy_file e.csv 10", "keyword 'energy_file' is not yet supported under LAMMPS"),
    (BODY + " contact_model hooke", "keyword 'contact_model' is not yet supported under LAMMPS"),
    (BODY + " material rankine strength 3e6 fracture_energy 100",
     "keyword 'material rankine' is not yet supported under LAMMPS"),
    (BODY + " model plastic", "keyword 'model' got 'plastic'"),
    (BODY + " fixed top", "no physical group 'top'"),
    (BODY + " gravity maybe", "keyword 'gravity' expects yes or no"),
    (BODY.replace("poisson 0.3", "poisson 0.6"), "'poisson' must lie in (-1, 0.5)"),
    (BODY.replace("type 2", "type 9"), "keyword 'type' is required"),
    (BODY.replace("block.msh", "nothere.msh"), "nothere.msh"),
    (BODY + " plane strain", "keyword 'plane' applies to 2D runs"),
]
for i, (line, expected) in enumerate(cases):
    script = f"in.err{i}"
    with open(os.path.join(wd, script), "w") as f:
        f.write(f"include in.lammps_preamble\ntimestep 1e-7\n{line}\nrun 0\n")
    out = lmp.run(script, workdir=wd, expect_fail=True)
    err = [x for x in out.splitlines() if x.startswith("ERROR")]
    label = line.split("fem/body ", 1)[1]
    h.check(err and expected in err[0], f"'{label}': {err[0] if err else out[-300:]}")

# The sphere style is required now, so that inputs stay valid once particle contact arrives.
with open(os.path.join(wd, "in.atomic"), "w") as f:
    f.write("plugin load ${plugin}\nunits si\nregion box block -1 2 -1 1 -1 1\n"
            "create_box 2 box\n" + BODY + "\n")
out = lmp.run("in.atomic", workdir=wd, expect_fail=True)
h.check("requires atom_style sphere" in out, "atom_style atomic refused: needs atom_style sphere")
