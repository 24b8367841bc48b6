"""fix fem/vtk under LAMMPS writes what it writes under LIGGGHTS: the same frames, the same .pvd
times, the same points, cells and point/cell data (both hosts fill them with the core's
fracdem::BodyFields), and refuses bad input naming the keyword.

Scene: the driven bar of test_energy_match (gravity, prescribed velocity with a ramp, a partial
support; its thermo agrees exactly between the hosts), written every 100 steps, at np 1 and 2 of
each host. Data arrays must agree to 1e-12 of each array's largest value (the
integration is the same to the bit; the tolerance leaves room for another compiler only).
"""
import os
import shutil
import sys
import tempfile

import numpy as np

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)
sys.path.insert(0, os.path.join(lh.ROOT, "python"))
from fracdem.fem import read_pvd, read_vtu  # noqa: E402

TOL = 1e-12
DT, STEPS, EVERY = 1e-6, 400, 100
FIELDS = {"point": {"displacement", "velocity"},
          "cell": {"stress", "von_mises", "strain_energy_density", "element_id", "region"}}


def scene_dir(tag):
    wd = tempfile.mkdtemp(prefix=f"lmp_vtk_{tag}_")
    for name in ("in.lammps_preamble", "in.liggghts_preamble", "in.vtk_bar"):
        shutil.copy(os.path.join(lh.INPUTS, name), wd)
    h.copy_inputs(["in.fe_common"], wd)
    h.make_box_mesh(os.path.join(wd, "bar.msh"), (20, 2, 2), (0.4, 0.04, 0.04), (0, -0.02, -0.02))
    return wd


def run(host, np_, model):
    wd = scene_dir(f"{host}{np_}")
    var = dict(host=host, model=model, dt=DT, steps=STEPS, every=EVERY)
    if host == "liggghts":
        h.run(args.exe, "in.vtk_bar", np_=np_, workdir=wd, variables=var)
    else:
        lmp.run("in.vtk_bar", np_=np_, workdir=wd, variables=var)
    series = read_pvd(os.path.join(wd, "bar.pvd"))
    what = f"{host} np {np_} {model}"
    want = [(k * EVERY * DT, f"bar_{k * EVERY:010d}.vtu") for k in range(STEPS // EVERY + 1)]
    got = [(t, os.path.basename(f)) for t, f in series]
    h.check(len(got) == len(want) and all(
        abs(t - tw) <= 1e-12 * DT and f == fw for (t, f), (tw, fw) in zip(got, want)),
        f"{what}: bar.pvd lists the {len(want)} frames at steps 0, {EVERY}, ... {STEPS} with "
        f"their times ({got[-1] if got else 'none'})")
    return [read_vtu(f) for _, f in series]


def worst_difference(ref, out, what):
    """Largest difference over frames and arrays, relative to each array's largest value."""
    worst, same_cells, names = 0.0, True, set()
    for a, b in zip(ref, out):
        same_cells &= a["cells"] == b["cells"]
        pairs = [(a["points"], b["points"])]
        for kind in ("point", "cell"):
            da, db = a[f"{kind}_data"], b[f"{kind}_data"]
            names.add((kind, tuple(sorted(da)), tuple(sorted(db))))
            pairs += [(da[n], db[n]) for n in sorted(da) if n in db]
        for x, y in pairs:
            scale = max(float(np.max(np.abs(x))), 1e-300)
            worst = max(worst, float(np.max(np.abs(np.asarray(x, float) - y))) / scale)
    h.check(same_cells, f"{what}: the same cells in every frame")
    for kind, na, nb in sorted(names):
        h.check(set(na) == set(nb) == FIELDS[kind], f"{what}: {kind} data {list(nb)} (LIGGGHTS {list(na)})")
    return worst


for model in ("elastic", "corotational"):
    for np_ in (1, 2):
        ref = run("liggghts", np_, model)
        moved = max(float(np.max(np.abs(f["point_data"]["displacement"]))) for f in ref)
        stressed = max(float(np.max(f["cell_data"]["von_mises"])) for f in ref)
        h.check(moved > 0 and stressed > 0, f"LIGGGHTS np {np_} {model}: the bar moves "
                                            f"({moved:.3g} m) and is stressed ({stressed:.3g} Pa)")
        out = run("lammps", np_, model)
        worst = worst_difference(ref, out, f"{model} np {np_}")
        h.check(worst <= TOL, f"{model} np {np_}: LAMMPS frames agree with LIGGGHTS (points + 7 "
                              f"arrays x {len(ref)} frames; largest difference {worst:.2e} of the "
                              f"array scale, <= {TOL:g})")

# Bad input: each error names the command and what is wrong.
wd = scene_dir("errors")
BODY = "fix body all fem/body file bar.msh type 2 density 7800 youngs 2e11 poisson 0.25"
cases = [
    ("fix out all fem/vtk 10 bar", "fix fem/vtk: expected 'fix ID group fem/vtk N PREFIX body BODY_FIX_ID'"),
    ("fix out all fem/vtk 10 bar bodies body", "fix fem/vtk: unknown keyword 'bodies'"),
    ("fix out all fem/vtk 0 bar body body", "fix fem/vtk: output interval N must be a whole number > 0, got '0'"),
    ("fix out all fem/vtk ten bar body body", "got 'ten'"),
    ("fix out all fem/vtk 10 bar body nobody", "fix fem/vtk: keyword 'body': no fix fem/body with ID 'nobody'"),
    ("fix grav all gravity 9.81 vector 0 -1 0\nfix out all fem/vtk 10 bar body grav",
     "fix fem/vtk: keyword 'body': fix 'grav' is of style 'gravity', expected fem/body"),
]
for k, (line, msg) in enumerate(cases):
    with open(os.path.join(wd, f"in.err{k}"), "w") as f:
        f.write(f"include in.lammps_preamble\n{BODY}\n{line}\nrun 1\n")
    out = lmp.run(f"in.err{k}", workdir=wd, expect_fail=True)
    err = [ln for ln in out.splitlines() if ln.startswith("ERROR")]
    h.check(bool(err) and msg in err[0], f"'{line.splitlines()[-1]}': {err[0] if err else out[-300:]}")
