"""LAMMPS's own balancer with fracdem's cost model: fix balance rcb weighted by compute fracdem/cost
(`weight var`) against `weight neigh`, `weight time` and no balancing, at 2 ranks.

Scenes (the LIGGGHTS settling bed of bench/inputs/in.settle_fracdem in LAMMPS's `pair granular`
syntax: same lattices, 0.008 m spheres of density 2500, E 5e6, nu 0.45, COR 0.3, friction 0.5,
Hertz with Mindlin tangential history, granular floor and roof walls, gravity, dt 1e-5):

  settle    the settling bed: a dense block on the floor (x, y periodic, 0.0045 < z < 0.13) and a
            dilute cloud above (0.14 < z < 0.31); 5346 spheres
  halfbed   dense and sparse side by side: the same dense block (4536 spheres) squeezed onto
            half of the floor (x < L/2, twice as high), the cloud's lattice over the other half
            from floor to roof; 5148 spheres of the same size and material. The dense
            column collapses sideways into the sparse half over the run.

Every run defines `compute cost all fracdem/cost` with the same relative costs (calibrated once,
at the start of the benchmark, by a run that uses the compute's default, then passed explicitly),
so the recorded cost is the same measure of work in every variant. Variants: `none` (stock z
slabs, `processors 1 1 *`), and `comm_style tiled` + `fix balance EVERY 1.05 rcb weight ...` with
`var w` (w = c_cost), `neigh 1.0`, `time 1.0`. Each run: a warm-up run of one balance interval,
then the measured run; reported: the imbalance (max/avg over ranks) of the recorded cost of the
measured run (the compute's vector 2), the loop time of the measured run, and the max/avg of
LAMMPS's own Pair time per rank. Repetitions alternate the variants (A B C D A B C D ...); the
wall-clock ratio to `none` is taken pair by pair within a repetition, its median reported.

  python3 bench/lammps_cost_balance.py [--scenes settle halfbed] [--steps 2000] [--reps 3]

Writes bench/results/lammps_cost_balance.csv (one row per run), lammps_cost_balance_summary.md and
lammps_cost_balance.png.
"""
import argparse
import csv
import glob
import os
import re
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
RESULTS = os.path.join(HERE, "results")

SCENE = """plugin          load ${plugin}
variable        L equal 0.1584
atom_style      sphere
atom_modify     map array
boundary        p p f
newton          off
comm_modify     vel yes
units           si
if "${balance} == none" then "processors 1 1 *" else "comm_style tiled"

region          box block 0 ${L} 0 ${L} 0 0.32 units box
create_box      1 box
neighbor        0.002 bin
neigh_modify    delay 0

variable        law string "hertz/material 5e6 0.3 0.45 tangential mindlin NULL 0.8424 0.5 damping coeff_restitution"
pair_style      granular
pair_coeff      * * ${law}
timestep        0.00001
fix             floor all wall/gran granular ${law} zplane 0.0 NULL
fix             roof all wall/gran granular ${law} zplane NULL 0.32

if "${scene} == halfbed" then &
  "region low block 0 0.0788 0 ${L} 0.0045 0.25 units box" &
  "region high block 0.0792 ${L} 0 ${L} 0.0045 0.31 units box" &
else &
  "region low block 0 ${L} 0 ${L} 0.0045 0.13 units box" &
  "region high block 0 ${L} 0 ${L} 0.14 0.31 units box"
lattice         sc 0.0088
create_atoms    1 region low
lattice         sc 0.0176
create_atoms    1 region high
set             group all diameter 0.008 density 2500
displace_atoms  all random 0.0006 0.0006 0.0006 49979687 units box
velocity        all set 0 0 -0.3 units box

fix             gravi all gravity 9.81 vector 0.0 0.0 -1.0
fix             integr all nve/sphere

compute         cost all fracdem/cost ${costs}
variable        w atom c_cost
if "${balance} == var" then "fix bal all balance ${every} 1.05 rcb weight var w"
if "${balance} == neigh" then "fix bal all balance ${every} 1.05 rcb weight neigh 1.0"
if "${balance} == time" then "fix bal all balance ${every} 1.05 rcb weight time 1.0"

thermo_style    custom step atoms ke c_cost[1] c_cost[2] c_cost[3] c_cost[4]
thermo_modify   lost error norm no format float %.10g
thermo          ${every}
run             ${every}
run             ${steps}
"""

VARIANTS = ["none", "var", "neigh", "time"]
LABELS = {"none": "no balance (z slabs)", "var": "rcb weight var (fracdem/cost)",
          "neigh": "rcb weight neigh", "time": "rcb weight time"}


class Lammps:
    def __init__(self, venv):
        self.venv = venv
        self.lmp = glob.glob(os.path.join(venv, "lib", "python3*", "site-packages", "lammps",
                                          "lmp"))[0]
        self.mpiexec = os.path.join(venv, "bin", "mpiexec")
        self.plugin = os.path.join(ROOT, "build-lammps", "fracdemplugin.so")
        self.env = dict(os.environ, OMP_NUM_THREADS="1")
        self.env["LD_LIBRARY_PATH"] = os.path.join(venv, "lib") + (
            ":" + os.environ["LD_LIBRARY_PATH"] if os.environ.get("LD_LIBRARY_PATH") else "")

    def run(self, script_text, np_, variables):
        wd = tempfile.mkdtemp(prefix="lmp_cost_bench_")
        with open(os.path.join(wd, "in.scene"), "w") as f:
            f.write(script_text)
        cmd = [self.mpiexec, "-n", str(np_), self.lmp, "-echo", "none", "-log", "none",
               "-in", "in.scene", "-var", "plugin", self.plugin]
        for k, v in variables.items():
            cmd += ["-var", k, str(v)]
        r = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, errors="replace", env=self.env, timeout=1800)
        if r.returncode != 0 or "ERROR" in r.stdout:
            sys.exit(f"failed ({' '.join(cmd)}) in {wd}:\n{r.stdout[-3000:]}")
        return r.stdout


def calibrated_costs(lmp):
    """The compute's default relative costs on this machine (one micro-benchmark), as keywords."""
    script = ("plugin load ${plugin}\natom_style sphere\nregion b block 0 1 0 1 0 1\n"
              "create_box 1 b\ncompute c all fracdem/cost\n")
    out = lmp.run(script, 1, {})
    m = re.search(r"relative costs.*?: base (\S+), check (\S+), pair (\S+), facet_check (\S+), "
                  r"facet (\S+)\n", out)
    base, check, pair, fcheck, facet = m.groups()
    return f"cost base {base} check {check} pair {pair} facet_check {fcheck} facet {facet}"


def parse(out):
    """Last thermo row of the measured run, its loop time and the Pair max/avg."""
    loops = re.findall(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", out)
    blocks = out.split("Loop time of")
    header, last = None, None
    for line in blocks[-2].splitlines():
        w = line.split()
        if w and w[0] == "Step":
            header = w
        elif header and len(w) == len(header):
            try:
                last = [float(v) for v in w]
            except ValueError:
                pass
    row = dict(zip(header, last))
    pair = re.findall(r"^Pair\s*\|\s*(\S+)\s*\|\s*(\S+)\s*\|\s*(\S+)", out, re.M)[-1]
    pair_min, pair_avg, pair_max = (float(v) for v in pair)
    return dict(loop=float(loops[-1][0]), atoms=int(loops[-1][3]),
                cost_imbalance=row["c_cost[2]"], cost_max=row["c_cost[3]"],
                cost_avg=row["c_cost[4]"], pair_imbalance=pair_max / pair_avg if pair_avg else 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", nargs="+", default=["settle", "halfbed"])
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--every", type=int, default=200)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--np", type=int, default=2)
    ap.add_argument("--venv", default=os.path.join(ROOT, ".venv-lammps"))
    ap.add_argument("--out", default=RESULTS)
    a = ap.parse_args()
    lmp = Lammps(os.path.abspath(a.venv))
    costs = calibrated_costs(lmp)
    print("relative costs:", costs, flush=True)

    rows = []
    for scene in a.scenes:
        for rep in range(a.reps):
            for v in VARIANTS:
                out = lmp.run(SCENE, a.np, dict(scene=scene, balance=v, steps=a.steps,
                                                every=a.every, costs=costs))
                r = dict(scene=scene, variant=v, rep=rep, ranks=a.np, steps=a.steps, **parse(out))
                rows.append(r)
                print(f"{scene} {v:6s} rep {rep}: cost B {r['cost_imbalance']:.3f}, pair-time B "
                      f"{r['pair_imbalance']:.3f}, loop {r['loop']:.2f} s", flush=True)

    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "lammps_cost_balance.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)

    summary = {}
    for scene in a.scenes:
        base = {r["rep"]: r["loop"] for r in rows if r["scene"] == scene and r["variant"] == "none"}
        for v in VARIANTS:
            rs = [r for r in rows if r["scene"] == scene and r["variant"] == v]
            summary[scene, v] = dict(
                atoms=rs[0]["atoms"],
                cost_imbalance=statistics.median(r["cost_imbalance"] for r in rs),
                pair_imbalance=statistics.median(r["pair_imbalance"] for r in rs),
                loop=statistics.median(r["loop"] for r in rs),
                ratio=statistics.median(r["loop"] / base[r["rep"]] for r in rs),
                ratio_min=min(r["loop"] / base[r["rep"]] for r in rs),
                ratio_max=max(r["loop"] / base[r["rep"]] for r in rs))

    cores = os.cpu_count()
    load = os.getloadavg()[0]
    with open(os.path.join(a.out, "lammps_cost_balance_summary.md"), "w") as f:
        f.write(f"LAMMPS 22 Jul 2025 + fracdemplugin.so, {a.np} ranks, {a.steps} measured steps "
                f"after {a.every} warm-up steps, fix balance every {a.every} steps (thresh 1.05), "
                f"{a.reps} repetitions (medians); machine with {cores} cores, load average "
                f"{load:.1f} at the end. Relative costs: `{costs}`.\n\n")
        f.write("| scene | atoms | variant | recorded-cost B (max/avg) | Pair-time B | loop time "
                "(s) | wall / no balance (min-max) |\n|---|---|---|---|---|---|---|\n")
        for (scene, v), s in summary.items():
            f.write(f"| {scene} | {s['atoms']} | {LABELS[v]} | {s['cost_imbalance']:.3f} | "
                    f"{s['pair_imbalance']:.3f} | {s['loop']:.2f} | {s['ratio']:.3f} "
                    f"({s['ratio_min']:.3f}-{s['ratio_max']:.3f}) |\n")
    print(open(os.path.join(a.out, "lammps_cost_balance_summary.md")).read())

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib missing: no figure")
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    width = 0.8 / len(VARIANTS)
    for k, v in enumerate(VARIANTS):
        xs = [i + (k - 1.5) * width for i in range(len(a.scenes))]
        axes[0].bar(xs, [summary[s, v]["cost_imbalance"] for s in a.scenes], width,
                    label=LABELS[v])
        axes[1].bar(xs, [summary[s, v]["ratio"] for s in a.scenes], width, label=LABELS[v])
    for ax, title in ((axes[0], "imbalance of recorded cost (max/avg)"),
                      (axes[1], "wall clock / no balance (median)")):
        ax.set_xticks(range(len(a.scenes)))
        ax.set_xticklabels(a.scenes)
        ax.axhline(1.0, color="k", lw=0.6)
        ax.set_title(title, fontsize=10)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"LAMMPS fix balance rcb, {a.np} ranks, {a.steps} steps", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "lammps_cost_balance.png"), dpi=120)


if __name__ == "__main__":
    main()
