"""What fracture costs: loop time of one FE-only scene with elastic material, with the Rankine
material (no fracture), with Rankine + nodal fracture checked every step / every 10 steps, and
with the contact between the body's pieces that fracture turns on by default.
Variants run in turn within each repetition (so machine drift hits all alike); medians of the
repetitions, ratios to the elastic run, CSV + PNG.

  python3 bench/fracture_cost.py [--reps 5] [--steps 2000] [--out bench/results]

Scene: a plane-stress bar (200 x 40 tri3 = 16 000 elements) pulled (ramped) at 0.01 m/s, which
stays below its strength (an intact body: the checks are skipped while no point is damaged), and
"loaded" at 2 m/s, which cracks it within the run (fracture active: failure map, splits, erosion
checks). Figures for docs/benchmarks.md.
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))

from fracdem import meshgen  # noqa: E402

SCENE = """dimension 2
atom_style granular
atom_modify map array
boundary f f p
newton off
communicate single vel yes
units si
region box block -0.1 0.3 -0.1 0.15 -0.01 0.01 units box
create_box 2 box
neighbor 0.001 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 1e7 1e7
fix m2 all property/global poissonsRatio peratomtype 0.3 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5
fix m4 all property/global coefficientFriction peratomtypepair 2 0.3 0.3 0.3 0.3
pair_style gran model hertz tangential history
pair_coeff * *
timestep 1e-7
fix body all fem/body file bar.msh type 2 density 2400 youngs 30e9 poisson 0.2 plane stress &
    thickness 0.05 MATERIAL fixed xmin x fixed ymin y prescribed_velocity xmax VEL 0 0 ramp 1e-4
thermo 1000
run STEPS
"""
# name: (material keywords, end velocity): 0.01 m/s stays below the strength (intact body);
# 2 m/s cracks it within the run (damage, splits: fracture active).
VARIANTS = {
    "elastic": "",
    "rankine": "material rankine strength 3e6 fracture_energy 100",
    "rankine+fracture every 1": "material rankine strength 3e6 fracture_energy 100 "
                                "fracture nodal every 1 contact_bodies no",
    "rankine+fracture every 10": "material rankine strength 3e6 fracture_energy 100 "
                                 "fracture nodal every 10 contact_bodies no",
    "rankine+fracture+piece contact": "material rankine strength 3e6 fracture_energy 100 "
                                      "fracture nodal every 1 contact_bodies yes",
    "loaded: rankine": "material rankine strength 3e6 fracture_energy 100",
    "loaded: rankine+fracture every 1": "material rankine strength 3e6 fracture_energy 100 "
                                        "fracture nodal every 1 contact_bodies no",
}


def loop_time(exe, wd, name, material, steps):
    path = os.path.join(wd, f"in.{abs(hash(name))}")
    vel = "2" if name.startswith("loaded") else "0.01"
    with open(path, "w") as f:
        f.write(SCENE.replace("MATERIAL", material).replace("STEPS", str(steps)).replace("VEL", vel))
    out = subprocess.run([exe, "-echo", "none", "-in", path], cwd=wd, capture_output=True,
                         text=True, check=True).stdout
    if "ERROR" in out or ("crack at" in out and not name.startswith("loaded")):
        raise RuntimeError(f"{name}: unexpected output\n{out[-2000:]}")
    return float(re.search(r"Loop time of ([0-9.eE+-]+)", out).group(1))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--steps", type=int, default=2000)
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = p.parse_args()
    wd = tempfile.mkdtemp(prefix="fracture_cost_")
    X, E, G = meshgen.rect_mesh(200, 40, 0.2, 0.04, element="tri3")
    meshgen.write_gmsh22(os.path.join(wd, "bar.msh"), X, E, G)
    times = {k: [] for k in VARIANTS}
    for rep in range(a.reps):
        for name, material in VARIANTS.items():
            times[name].append(loop_time(a.exe, wd, name, material, a.steps))
        print(f"rep {rep + 1}/{a.reps}: " + ", ".join(f"{k} {v[-1]:.3f} s" for k, v in times.items()))
    base = statistics.median(times["elastic"])
    rows = []
    for name, t in times.items():
        med = statistics.median(t)
        rows.append({"variant": name, "median_loop_s": med, "min_s": min(t), "max_s": max(t),
                     "ratio_to_elastic": med / base, "reps": len(t), "steps": a.steps,
                     "elements": len(E)})
    for r in rows:
        ref = "loaded: rankine" if r["variant"].startswith("loaded") else "rankine"
        rk = statistics.median(times[ref])
        r["ratio_to_rankine"] = r["median_loop_s"] / rk
        print(f"{r['variant']:34s} {r['median_loop_s']:.3f} s  x{r['ratio_to_elastic']:.3f} elastic"
              f"  ({100 * (r['ratio_to_rankine'] - 1):+.1f} % over '{ref}')")
    os.makedirs(a.out, exist_ok=True)
    csv_path = os.path.join(a.out, "fracture_cost.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.barh([r["variant"] for r in rows], [r["median_loop_s"] for r in rows],
            xerr=[[r["median_loop_s"] - r["min_s"] for r in rows],
                  [r["max_s"] - r["median_loop_s"] for r in rows]])
    ax.set_xlabel(f"loop time, {a.steps} steps, {len(E)} tri3 (median of {a.reps})")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "fracture_cost.png"), dpi=120)
    print("wrote", csv_path)


if __name__ == "__main__":
    main()
