"""Bad input stops with a clear error naming the command, keyword and what was expected; a body
placed outside the box is refused, one that leaves it is refused (prescribed motion) or warned
about (its own dynamics)."""
import os
import tempfile

import harness as h

args = h.parse_args()
cases = [
    ("fix b all fem/body file nothere.msh type 2 density 1 youngs 1 poisson 0.3",
     "nothere.msh"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 colour red",
     "unknown keyword 'colour'"),
    # A misspelt keyword names the nearest one, of the table or of the clause before it.
    ("fix b all fem/body file block.msh type 2 density 7800 young 2e11 poisson 0.3",
     "fix fem/body: unknown keyword 'young'; did you mean 'youngs'?"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 100 fracture nodal evry 5",
     "unknown keyword 'evry'; did you mean 'every' (in 'fracture nodal')?"),
    ("fix b all fem/vtk 10 out bdy b",
     "fix fem/vtk: unknown keyword 'bdy' (expected 'fix ID group fem/vtk N PREFIX body "
     "BODY_FIX_ID'); did you mean 'body'?"),
    # Concrete (snap-back limit 2 E G_f / f_t^2 = 0.67 m) on a 100 mm block written in mm: the
    # error says the mesh may be in millimetres and names the keyword that converts it.
    ("fix b all fem/body file block_mm.msh type 2 density 2400 youngs 30e9 poisson 0.2 material rankine strength 3e6 fracture_energy 100",
     "The mesh (100 across) may be in millimetres: fracdem takes SI values, so its coordinates are "
     "metres; 'scale 0.001' on fix fem/body converts a mesh drawn in mm."),
    ("fix b all fem/body file block.msh type 2 youngs 2e11 poisson 0.3",
     "'density'"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 model plastic",
     "keyword 'model' got 'plastic'"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 fixed top",
     "no physical group 'top'"),
    ("fix b all fem/body file block.msh type 9 density 7800 youngs 2e11 poisson 0.3",
     "keyword 'type'"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.6",
     "'poisson'"),
    ("fix b all fem/body file garbage.msh type 2 density 7800 youngs 2e11 poisson 0.3",
     "garbage.msh"),
    ("fix b all fem/body file inverted.msh type 2 density 7800 youngs 2e11 poisson 0.3",
     "inverted"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 gravity maybe",
     "keyword 'gravity' expects yes or no"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 compliance both",
     "keyword 'compliance' expects particle or combined"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 dt_check",
     "keyword 'dt_check' expects error or warn"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6",
     "keyword 'material rankine': strength and fracture_energy are required"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength -1 fracture_energy 100",
     "keyword 'material rankine': strength FT must be > 0"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 0",
     "keyword 'material rankine': fracture_energy GF must be > 0"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material brittle",
     "keyword 'material': unknown model 'brittle' (one of elastic, rankine, j2"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 100 softening cubic",
     "keyword 'material rankine': softening: 'cubic' is neither linear nor exponential"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material j2 yield abc hardening 1e9",
     "keyword 'material j2': yield: 'abc' is not a number (expected 'material j2 yield SY hardening H"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material j2 yield 5e8 hardening 1e9 eos mie_gruneisen 4570 1.49",
     "keyword 'eos mie_gruneisen': missing GAMMA0"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material j2 yield 5e8 hardening 1e9 bulk_viscosity -0.06 1.2",
     "keyword 'bulk_viscosity': Q1 (linear coefficient) must be >= 0"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 bulk_viscosity 0.06 -1",
     "keyword 'bulk_viscosity': Q2 (quadratic coefficient) must be >= 0"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 bulk_viscosity 0.06",
     "keyword 'bulk_viscosity' expects 'off' or 'Q1 Q2'"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 bulk_viscosity",
     "keyword 'bulk_viscosity' expects 'off' or 'Q1 Q2'"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 bulk_viscosity 0.06 fixed xmin",
     "keyword 'bulk_viscosity' expects a finite number, got 'fixed'"),
    ("fix b all fem/body file block.msh type 2 rigid yes bulk_viscosity 0.06 1.2",
     "keyword 'bulk_viscosity' applies to deformable bodies"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 density abc",
     "keyword 'density' expects a finite number, got 'abc'"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 fracture nodal",
     "keyword 'fracture' needs a material that fails"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 100 fracture nodal min_size 0.6",
     "keyword 'fracture nodal min_size' expects a fraction F with 0 < F < 0.5"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 100 fracture nodal every 0",
     "'fracture nodal every' expects N >= 1"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 100 fracture nodal erode_cracked maybe",
     "'fracture nodal erode_cracked' expects yes or no"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 100 fracture tensile",
     "keyword 'fracture' expects 'nodal"),
    ("fix b all fem/body file block.msh type 2 rigid yes material rankine strength 3e6 fracture_energy 100",
     "a rigid body neither deforms nor breaks"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e8 fracture_energy 1",
     "above the snap-back limit"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 prescribed_velocity all 1 0 0 ramp 0",
     "needs T > 0"),
    ("fix b all fem/vtk 10 out body nobody",
     "fem/vtk"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 rotate axis 0 0 0 angle 30",
     "keyword 'rotate' got axis 0 0 0, expected a non-zero axis"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 plane axisymmetric",
     "keyword 'plane' applies to 2D runs"),
    # The box of in.fe_common is x -1 to 2 with fixed faces; the block spans 0 to 0.1.
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 move 1.95 0 0",
     "in the box (x -1 to 2, y -1 to 1, z -1 to 1) reaches beyond its fixed x-high face"),
    # Periodic in x (period 3): crossing the boundary is fine, being longer than the period not.
    ("change_box all boundary p f f\n"
     "fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 scale 31",
     "is longer than its period in the periodic dimension x"),
    ("timestep 1e-3\nfix b all fem/body file block.msh type 2 rigid yes motion linear 10 0 0\nrun 300",
     "its prescribed 'motion' has carried it out of the box: the body (x 2 to 2.1"),
    # erosion: values out of range, criteria that could never trigger, rigid bodies.
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material j2 yield 5e8 hardening 2e9 erosion plastic_strain -0.3",
     "keyword 'erosion' expects one or more of 'plastic_strain EPS' (EPS > 0)"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material j2 yield 5e8 hardening 2e9 erosion plastic_strain 0",
     "keyword 'erosion' expects one or more of 'plastic_strain EPS' (EPS > 0)"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material j2 yield 5e8 hardening 2e9 erosion min_dt 1e-9 plastic_strain -1",
     "keyword 'erosion': expects one or more of 'plastic_strain EPS' (EPS > 0)"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 100 erosion damage 1.5",
     "keyword 'erosion damage': D must lie in (0, 1]"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material rankine strength 3e6 fracture_energy 100 erosion damage 0",
     "keyword 'erosion' expects one or more"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 material j2 yield 5e8 hardening 2e9 erosion damage 0.9",
     "keyword 'erosion damage': this body's material does not damage"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 erosion plastic_strain 0.3",
     "keyword 'erosion plastic_strain': this body's material never yields"),
    ("fix b all fem/body file block.msh type 2 rigid yes erosion min_dt 1e-8",
     "keyword 'erosion': a rigid body neither deforms nor loses elements"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 erosion",
     "keyword 'erosion' expects one or more"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 erosion min_dt abc",
     "keyword 'erosion min_dt' expects a finite number, got 'abc'"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 erosion min_dt 1e-9 erosion_mass lose",
     "keyword 'erosion_mass' expects keep or remove"),
    ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 erosion_mass remove",
     "keyword 'erosion_mass' applies to bodies that erode"),
]
big_dt = ("fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3", "exceeds the stable FE time step")

for line, expected in cases + [big_dt]:
    wd = tempfile.mkdtemp(prefix="errors_")
    h.make_box_mesh(os.path.join(wd, "block.msh"), (2, 2, 2), (0.1, 0.1, 0.1))
    h.make_box_mesh(os.path.join(wd, "block_mm.msh"), (2, 2, 2), (100, 100, 100))
    with open(os.path.join(wd, "garbage.msh"), "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 x\n")
    with open(os.path.join(wd, "inverted.msh"), "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                "$EndNodes\n$Elements\n1\n1 4 2 1 1 1 3 2 4\n$EndElements\n")
    h.copy_inputs(["in.fe_common"], wd)
    with open(os.path.join(h.INPUTS, "in.errors_template")) as f:
        text = f.read().replace("BADLINE", line)
    with open(os.path.join(wd, "in.case"), "w") as f:
        f.write(text)
    dt = 1e-3 if (line, expected) == big_dt else 1e-8
    out = h.run(args.exe, "in.case", workdir=wd, variables=dict(dt=dt), expect_fail=True)
    err = [l for l in out.splitlines() if "ERROR" in l]
    h.check(bool(err) and expected in err[0] and "fem/" in err[0],
            f"'{line.split('fem/')[1][:50]}...' -> {err[0].strip() if err else 'no ERROR line'}")

# A deformable body that leaves the box by its own motion (here thrown at 8 km/s) is warned about
# once, and the run goes on: only the part outside is out of the particles' reach.
wd = tempfile.mkdtemp(prefix="errors_")
h.make_box_mesh(os.path.join(wd, "block.msh"), (2, 2, 2), (0.1, 0.1, 0.1))
h.copy_inputs(["in.fe_common"], wd)
with open(os.path.join(wd, "in.case"), "w") as f:
    f.write("include in.fe_common\ntimestep 1e-6\n"
            "fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3 "
            "velocity all 8000 0 0\nrun 400\n")
out = h.run(args.exe, "in.case", workdir=wd)
warn = [l for l in out.splitlines() if "WARNING" in l and "out of the box" in l]
h.check(len(warn) == 1 and "its nodes have moved out of the box" in warn[0]
        and "fixed x-high face" in warn[0],
        f"a deformable body leaving the box: one warning, the run goes on ({warn})")

# The remedy the mm error names: the same mesh and material with 'scale 0.001' set up and run.
wd = tempfile.mkdtemp(prefix="errors_")
h.make_box_mesh(os.path.join(wd, "block_mm.msh"), (2, 2, 2), (100, 100, 100))
h.copy_inputs(["in.fe_common"], wd)
with open(os.path.join(wd, "in.case"), "w") as f:
    f.write("include in.fe_common\ntimestep 1e-8\n"
            "fix b all fem/body file block_mm.msh type 2 density 2400 youngs 30e9 poisson 0.2 "
            "material rankine strength 3e6 fracture_energy 100 scale 0.001\nrun 10\n")
out = h.run(args.exe, "in.case", workdir=wd)
h.check("ERROR" not in out and "fix fem/body b: block_mm.msh" in out,
        "the mm mesh with 'scale 0.001' is taken and runs")

# Bodies take SI values: host units other than si are refused, naming both (the preamble of the
# cases above with its units line changed, or dropped: LIGGGHTS's default is lj).
with open(os.path.join(h.INPUTS, "in.fe_common")) as f:
    common = f.read()
for units_line, expected in [("units           cgs", "'units cgs'"),
                             ("", "'units lj' (the default of an input without a 'units' command)")]:
    wd = tempfile.mkdtemp(prefix="errors_")
    h.make_box_mesh(os.path.join(wd, "block.msh"), (2, 2, 2), (0.1, 0.1, 0.1))
    with open(os.path.join(wd, "in.case"), "w") as f:
        f.write(common.replace("units           si", units_line) + "timestep 1e-8\n"
                "fix b all fem/body file block.msh type 2 density 7800 youngs 2e11 poisson 0.3\n"
                "run 10\n")
    out = h.run(args.exe, "in.case", workdir=wd, expect_fail=True)
    err = [l for l in out.splitlines() if "ERROR" in l]
    h.check(bool(err) and "fix fem/body: needs 'units si'" in err[0] and expected in err[0],
            f"units '{units_line.split()[-1] if units_line else 'none'}' -> "
            f"{err[0].strip() if err else 'no ERROR line'}")
