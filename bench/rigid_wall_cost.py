"""Rigid `fix fem/body` against the stock mesh wall on a large curved surface: a conical hopper
shell (13 500 tet4, 9 360 boundary triangles) as a rigid fem/body and, as an STL of the same
boundary triangles, as `fix mesh/surface` + `fix wall/gran`. 3 200 spheres rain into it
(`fix insert/rate/region`, the balance benchmark's hopper filling, outlet closed by a plane) and
settle; both variants run the same script but for the wall lines.

  python3 bench/rigid_wall_cost.py [--reps 3] [--steps 16000] [--out bench/results]

The variants run in turn within each repetition (machine drift hits both alike). Figures: the
median over repetitions of the per-repetition ratio fem / stock of LIGGGHTS "Loop time", and of
the loop's CPU time (process user + system time minus that of the same script run for 1 step, so
without set-up: on a shared machine CPU time is the steadier figure). Physics check: the spheres'
kinetic energy of the two variants at every thermo row, relative to the largest of the stock run,
beside the drift between two stock runs that differ only in round-off (skin 2 mm and 2.1 mm).
Writes rigid_wall_cost.csv (one row per run), rigid_wall_cost.md and rigid_wall_cost.png.
"""
import argparse
import csv
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))

import harness  # noqa: E402
from fracdem import meshgen  # noqa: E402

# Cone: inner radius 0.02 at z = 0.02 to 0.08 at z = 0.12, wall 5 mm (as bench/inputs/in.hopper_fracdem).
CONE = dict(r_outlet=0.02, r_top=0.08, height=0.1, thickness=0.005)

SCENE = """atom_style      granular
atom_modify     map array
boundary        f f f
newton          off
communicate     single vel yes
units           si
region          box block -0.1 0.1 -0.1 0.1 0 0.2 units box
create_box      2 box
neighbor        {skin} bin
neigh_modify    delay 0
fix             m1 all property/global youngsModulus peratomtype 5.e6 1.e9
fix             m2 all property/global poissonsRatio peratomtype 0.45 0.3
fix             m3 all property/global coefficientRestitution peratomtypepair 2 0.3 0.3 0.3 0.3
fix             m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5
pair_style      gran model hertz tangential history
pair_coeff      * *
timestep        0.00001
WALL
fix             outlet all wall/gran model hertz tangential history primitive type 1 zplane 0.02
fix             floor all wall/gran model hertz tangential history primitive type 1 zplane 0.0
fix             pts all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant 0.003
fix             pdd all particledistribution/discrete 32452843 1 pts 1.0
region          ins cylinder z 0 0 0.05 0.14 0.18 units box
fix             ins all insert/rate/region seed 32452867 distributiontemplate pdd nparticles {n} &
                particlerate 25000 insert_every 250 overlapcheck yes vel constant 0 0 -1.0 region ins
fix             gravi all gravity 9.81 vector 0.0 0.0 -1.0
fix             integr all nve/sphere
thermo_style    custom step atoms ke
thermo_modify   format float %.10g
thermo_modify   lost error norm no
thermo          1000
run             {steps}
"""
WALLS = {
    "stock": "fix             hopper all mesh/surface file hopper.stl type 2\n"
             "fix             wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes hopper",
    "fem": "fix             hopper all fem/body file hopper.msh type 2 rigid yes",
}
LABELS = {"stock": "fix mesh/surface + wall/gran", "fem": "rigid fix fem/body"}


def hopper_mesh(n_around, n_up):
    """meshgen.funnel_tet_mesh with its theta seam merged: a closed wall, no seam facets (a stock
    mesh wall refuses the seam's coincident faces)."""
    X, E = meshgen.funnel_tet_mesh(CONE["r_outlet"], CONE["r_top"], CONE["height"], CONE["thickness"],
                                   n_around, n_up, origin=(0, 0, 0.02))
    # box_tet_mesh numbering: i + 2 (j + (n_around + 1) k); j = n_around is theta = 2 pi.
    idx = np.arange(len(X))
    j = (idx // 2) % (n_around + 1)
    E = np.where(j == n_around, idx - 2 * n_around, idx)[E]
    keep = np.unique(E)
    renum = -np.ones(len(X), dtype=int)
    renum[keep] = np.arange(len(keep))
    return X[keep], renum[E]


def boundary_triangles(E):
    """Faces that belong to one tet only, oriented away from it (tets are positively oriented)."""
    faces = {}
    for t in E:
        for f in ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)):
            tri = tuple(t[list(f)])
            key = tuple(sorted(tri))
            faces[key] = None if key in faces else tri
    return [tri for tri in faces.values() if tri is not None]


def write_scene(wd, n_around, n_up):
    X, E = hopper_mesh(n_around, n_up)
    meshgen.write_gmsh22(os.path.join(wd, "hopper.msh"), X, E)
    tris = boundary_triangles(E)
    meshgen.write_stl(os.path.join(wd, "hopper.stl"), X, tris, "hopper")
    return len(E), len(tris)


def run(exe, wd, wall, steps, n, skin=0.002):
    """(loop s, process CPU s, thermo KE column, atoms) of one run of the scene, np 1."""
    path = os.path.join(wd, f"in.{wall}" + ("" if skin == 0.002 else ".floor"))
    with open(path, "w") as f:
        f.write(SCENE.replace("WALL", WALLS[wall]).format(n=n, steps=steps, skin=skin))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run([exe, "-echo", "none", "-in", path], cwd=wd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0 or "ERROR" in r.stdout:
        raise RuntimeError(f"{wall} run failed in {wd}:\n{r.stdout[-3000:]}{r.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    loop = sum(float(m) for m in re.findall(r"Loop time of ([0-9.eE+-]+)", r.stdout))
    runs = harness.thermo_blocks(r.stdout)
    return loop, cpu, harness.column(runs, "KinEng"), int(harness.column(runs, "Atoms")[-1])


def plot(rows, out_dir, title):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(8, 3.5))
    for ax, key, label in zip(axes, ("loop_s", "loop_cpu_s"), ("loop time (s)", "loop CPU time (s)")):
        for k, wall in enumerate(WALLS):
            t = [r[key] for r in rows if r["variant"] == wall]
            ax.bar(k, statistics.median(t), color=f"C{k}")
            ax.scatter([k] * len(t), t, color="k", s=8, zorder=3)
        ax.set_xticks(range(len(WALLS)), [LABELS[w] for w in WALLS], fontsize=8)
        ax.set_ylabel(label)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "rigid_wall_cost.png"), dpi=120)


def summary(rows, kes, floor_ke, a, ntets, ntris):
    ratio = {k: [f[k] / s[k] for s, f in zip(rows[0::2], rows[1::2])] for k in ("loop_s", "loop_cpu_s")}
    scale = max(kes["stock"])
    ke_diff = [abs(x - y) / scale for x, y in zip(kes["fem"], kes["stock"])]
    lines = [f"{rows[-1]['atoms']} spheres, {ntets} tet4, {ntris} boundary triangles, {a.steps} steps, "
             f"{a.reps} repetitions, np 1", "",
             "| variant | median loop time (s) | range (s) | median loop CPU (s) | range (s) |",
             "|---|---|---|---|---|"]
    for w in WALLS:
        t = [r["loop_s"] for r in rows if r["variant"] == w]
        c = [r["loop_cpu_s"] for r in rows if r["variant"] == w]
        lines.append(f"| {LABELS[w]} | {statistics.median(t):.3f} | {min(t):.3f} - {max(t):.3f} | "
                     f"{statistics.median(c):.3f} | {min(c):.3f} - {max(c):.3f} |")
    for k, name in (("loop_s", "loop time"), ("loop_cpu_s", "loop CPU time")):
        lines.append(f"\nfem / stock {name}: median of per-repetition ratios {statistics.median(ratio[k]):.3f} "
                     f"(range {min(ratio[k]):.3f} - {max(ratio[k]):.3f})")
    lines.append(f"\nparticle KE, |fem - stock| / max KE(stock), last repetition: at the end "
                 f"{ke_diff[-1]:.2e}, largest over the {len(ke_diff)} thermo rows {max(ke_diff):.2e}")
    if floor_ke:  # the same stock scene with a 5 % larger skin: other summation orders only
        floor = [abs(x - y) / scale for x, y in zip(floor_ke, kes["stock"])]
        lines.append(f"round-off floor, stock with skin 2.1 mm vs 2 mm: at the end {floor[-1]:.2e}, "
                     f"largest {max(floor):.2e}")
    return "\n".join(lines), statistics.median(ratio["loop_cpu_s"])


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--steps", type=int, default=16000)
    p.add_argument("--particles", type=int, default=3200)
    p.add_argument("--around", type=int, default=90, help="hexes around the cone")
    p.add_argument("--up", type=int, default=25, help="hexes along the cone")
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--no-floor", action="store_true", help="skip the round-off floor run of the KE check")
    a = p.parse_args()
    wd = tempfile.mkdtemp(prefix="rigid_wall_cost_")
    ntets, ntris = write_scene(wd, a.around, a.up)
    print(f"scene in {wd} (in.stock, in.fem, hopper.msh, hopper.stl: to profile one variant)", flush=True)
    rows, kes = [], {}
    for rep in range(a.reps):
        for wall in WALLS:  # interleaved: stock, fem
            setup_cpu = run(a.exe, wd, wall, 1, a.particles)[1]
            loop, cpu, ke, natoms = run(a.exe, wd, wall, a.steps, a.particles)
            kes[wall] = ke
            rows.append(dict(variant=wall, repetition=rep, loop_s=loop, cpu_s=cpu, setup_cpu_s=setup_cpu,
                             loop_cpu_s=cpu - setup_cpu, final_ke=ke[-1], atoms=natoms, tets=ntets,
                             facets=ntris, steps=a.steps))
            print(f"rep {rep + 1}/{a.reps} {wall:5s}: loop {loop:.3f} s, loop CPU {cpu - setup_cpu:.3f} s, "
                  f"KE {ke[-1]:.10g}", flush=True)
    # Granular flow amplifies round-off: how far two runs of the same stock scene drift apart when
    # only the order of the force sums differs (neighbour lists rebuilt at other steps).
    floor_ke = None if a.no_floor else run(a.exe, wd, "stock", a.steps, a.particles, skin=0.0021)[2]
    text, cpu_ratio = summary(rows, kes, floor_ke, a, ntets, ntris)
    print(text)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "rigid_wall_cost.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, "rigid_wall_cost.md"), "w") as f:
        f.write(text + "\n")
    plot(rows, a.out, f"{rows[-1]['atoms']} spheres into a cone of {ntris} triangles, {a.steps} steps "
                      f"(median of {a.reps}): fem / stock loop CPU {cpu_ratio:.3f}")


if __name__ == "__main__":
    main()
