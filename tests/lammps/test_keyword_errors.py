"""Under LAMMPS, fix fem/body refuses what it does not support by name: unknown keywords, the
LIGGGHTS adapter's contact-law keywords, and bad values of every keyword (as the LIGGGHTS adapter);
the contact law after 'contact' (LAMMPS's granular syntax): typos, models the core's law cannot
express, a missing damping or tangential model, a body outside the box, atom_style atomic.
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
    (BODY.replace("youngs", "young"), "fix fem/body: unknown keyword 'young'; did you mean 'youngs'?"),
    # The keywords of fracture, plasticity, erosion, rigid bodies and the energy file are the
    # LIGGGHTS adapter's, checked by the same core code.
    (BODY + " fracture nodal", "keyword 'fracture' needs a material that fails"),
    (BODY + " rigid yes material rankine strength 3e6 fracture_energy 100",
     "keywords 'material' and 'fracture' apply to deformable bodies"),
    (BODY + " energy_file e.csv 0", "keyword 'energy_file' needs N > 0"),
    (BODY + " energy_file nodir/e.csv 10", "keyword 'energy_file': cannot open 'nodir/e.csv'"),
    (BODY + " material rankine strength 3e6", "keyword 'material rankine': strength and "
                                              "fracture_energy are required"),
    (BODY + " material rankine strength 3e8 fracture_energy 1",
     "keyword 'material rankine': element 0 of mesh 'block.msh' is"),
    (BODY + " erosion_mass remove", "keyword 'erosion_mass' applies to bodies that erode"),
    (BODY + " contact_model hooke", "keyword 'contact_model' is the LIGGGHTS adapter's"),
    (BODY + " tangential history", "keyword 'tangential' is the LIGGGHTS adapter's"),
    (BODY + " model plastic", "keyword 'model' got 'plastic'"),
    (BODY + " fixed top", "no physical group 'top'"),
    (BODY + " gravity maybe", "keyword 'gravity' expects yes or no"),
    (BODY.replace("poisson 0.3", "poisson 0.6"), "'poisson' must lie in (-1, 0.5)"),
    (BODY.replace("type 2", "type 9"), "keyword 'type' is required"),
    (BODY.replace("block.msh", "nothere.msh"), "nothere.msh"),
    (BODY + " plane strain", "keyword 'plane' applies to 2D runs"),
    (BODY + " history_slots 0", "keyword 'history_slots' expects 1 .. 64"),
    (BODY + " buffer -1", "keyword 'buffer' must be >= 0"),
    (BODY + " compliance both", "keyword 'compliance' expects particle or combined"),
]
# The contact law: LAMMPS's granular words, the supported subset.
LAW = "contact granular hertz/material 1e7 0.5 0.3"
TANG = "tangential mindlin NULL 0.907485 0.3"
DAMP = "damping coeff_restitution"
C = "fix fem/body: keyword 'contact': "
cases += [
    (f"{BODY} contact", C + "expects a granular style"),
    (f"{BODY} contact granula hertz/material 1e7 0.5 0.3", C + "expects 'granular', got 'granula'"),
    (f"{BODY} contact hooke/history 1e5 NULL 0 NULL 0.5 1", C + "style 'hooke/history'"),
    (f"{BODY} contact granular hertz/materal 1e7 0.5 0.3", C + "unknown normal model 'hertz/materal'"),
    (f"{BODY} contact granular hooke 1e5 0.5 {DAMP} {TANG}", C + "tangential mindlin K_T = NULL takes the stiffness from the material"),
    (f"{BODY} contact granular jkr 1e7 0.5 0.3 10", C + "normal model 'jkr' is not supported"),
    (f"{BODY} contact granular hertz/material 1e7 0.5", C + "expects hertz/material NU"),
    (f"{BODY} contact granular hertz/material 1e7 0.5 0.7 {DAMP} {TANG}", C + "hertz/material NU must lie in (-1, 0.5)"),
    (f"{BODY} {LAW} {TANG}", C + "needs 'damping coeff_restitution' or 'damping tsuji'"),
    (f"{BODY} {LAW} damping viscoelastic {TANG}", C + "damping model 'viscoelastic' is not supported"),
    (f"{BODY} {LAW} damping tsuij {TANG}", C + "unknown damping model 'tsuij'"),
    (f"{BODY} {LAW} {DAMP}", C + "needs a tangential model"),
    (f"{BODY} {LAW} {DAMP} tangential linear_history 1e5 1.0 0.3", C + "tangential model 'linear_history' is not supported"),
    (f"{BODY} {LAW} {DAMP} tangential mindlin 1e5 1.0 0.3", C + "tangential mindlin k_t = 1e5 is not supported"),
    (f"{BODY} {LAW} {DAMP} tangential mindlin NULL 1.0 0.3", C + "tangential mindlin XT = 1 is not supported"),
    (f"{BODY} {LAW} {DAMP} tangential mindlin NULL 1.0", C + "expects tangential mindlin MU"),
    (f"{BODY} {LAW} {DAMP} tangential linear_nohistory 1.0 0.3", C + "tangential linear_nohistory is supported frictionless only"),
    (f"{BODY} {LAW} {DAMP} tangential mindlinn NULL 1.0 0.3", C + "unknown tangential model 'mindlinn'"),
    (f"{BODY} {LAW} {DAMP} {TANG} rolling sds 1e3 1e3 0.1 0.2", C + "rolling model 'sds' is not supported"),
    (f"{BODY} {LAW} {DAMP} {TANG} twisting marshall", C + "twisting model 'marshall' is not supported"),
    (f"{BODY} {LAW} {DAMP} {TANG} heat area 1.0", C + "option 'heat' is not supported"),
    (f"{BODY} {LAW} {DAMP} {TANG} limit_damping", C + "option 'limit_damping' is not supported"),
    (f"{BODY} {LAW} {DAMP} {TANG} dampin tsuji", "fix fem/body: unknown keyword 'dampin'"),
    (f"{BODY} contact granular hertz/material 1e7 0 0.3 {DAMP} {TANG}", C + "damping coeff_restitution needs a coefficient of restitution COR in (0, 1]"),
    (f"{BODY} {LAW} {DAMP} {TANG} {LAW} {DAMP} {TANG}", C + "given twice"),
    (f"{BODY} move 5 0 0 {LAW} {DAMP} {TANG}", "reaches beyond its fixed x-high face"),
]
for i, (line, expected) in enumerate(cases):
    script = f"in.err{i}"
    with open(os.path.join(wd, script), "w") as f:
        f.write(f"include in.lammps_preamble\ntimestep 1e-7\n{line}\nrun 0\n")
    out = lmp.run(script, workdir=wd, expect_fail=True)
    err = [x for x in out.splitlines() if x.startswith("ERROR")]
    label = line.split("fem/body ", 1)[1]
    h.check(err and expected in err[0], f"'{label}': {err[0] if err else out[-300:]}")

# The sphere style is required (radius, rmass, omega, torque); with 'contact' the error names it.
for i, (extra, expected) in enumerate([
        ("", "fix fem/body requires atom_style sphere (radius, rmass, omega); this run has "
             "atom_style atomic"),
        (f" {LAW} {DAMP} {TANG}", "fix fem/body: keyword 'contact' needs per-atom radius, rmass, "
                                  "omega and torque: it requires atom_style sphere (this run has "
                                  "atom_style atomic)")]):
    with open(os.path.join(wd, f"in.atomic{i}"), "w") as f:
        f.write("plugin load ${plugin}\nunits si\nregion box block -1 2 -1 1 -1 1\n"
                "create_box 2 box\n" + BODY + extra + "\n")
    out = lmp.run(f"in.atomic{i}", workdir=wd, expect_fail=True)
    err = [x for x in out.splitlines() if x.startswith("ERROR")]
    h.check(err and expected in err[0], f"atom_style atomic{extra[:8]}: {err[0] if err else out[-300:]}")

# Bodies take SI values: other units (here cgs) are refused, naming both.
with open(os.path.join(wd, "in.cgs"), "w") as f:
    f.write("plugin load ${plugin}\nunits cgs\natom_style sphere\n"
            "region box block -1 2 -1 1 -1 1\ncreate_box 2 box\n" + BODY + "\n")
out = lmp.run("in.cgs", workdir=wd, expect_fail=True)
err = [x for x in out.splitlines() if x.startswith("ERROR")]
h.check(err and "fix fem/body: needs 'units si'" in err[0] and "'units cgs'" in err[0],
        f"units cgs: {err[0] if err else out[-300:]}")

# Particles in the group but no 'contact': they would pass through the body; the run warns.
with open(os.path.join(wd, "in.nocontact"), "w") as f:
    f.write("include in.lammps_preamble\ntimestep 1e-7\n" + BODY + "\n"
            "create_atoms 1 single 0.5 0.5 0.5 units box\nrun 0\n")
out = lmp.run("in.nocontact", workdir=wd)
h.check("group 'all' has particles but the fix has no keyword 'contact'" in out,
        "particles without 'contact': warned that they pass through the body")
