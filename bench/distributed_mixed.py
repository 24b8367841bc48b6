"""Mixed scene of issue #13 item 7: particles hitting a 10^6-element FE body, replicated against
`parallel distributed`, at 1 and 2 ranks, through `fix fem/body` (LIGGGHTS loop time).

A layer of 8 mm steel spheres (bench/inputs/in.distributed_mixed: 10 mm lattice over the top face,
5 m/s downwards) hits a clamped steel block of 12 c^3 tet4 (c = --cells, 44: 1.02 x 10^6); the
runs of one repetition go in turn (variants and rank counts alternate, so drift hits all alike);
reported: the median loop time per step over the repetitions, the speedup against 1 rank of the
same variant, and that the spheres hit the body (their kinetic energy falls). CSV + PNG.

  python3 bench/distributed_mixed.py [--exe build/fracdem] [--reps 3] [--cells 44] [--steps 100]
"""
import argparse
import csv
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))


def mpirun(np_):
    return ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(np_)]


def run(exe, wd, np_, parallel, steps, dt):
    cmd = mpirun(np_) + [exe, "-echo", "none", "-in", "in.distributed_mixed", "-var", "parallel",
                         parallel, "-var", "steps", str(steps), "-var", "dt", str(dt)]
    r = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0 or "ERROR" in r.stdout:
        raise SystemExit(f"{' '.join(cmd)} failed in {wd}:\n{r.stdout[-3000:]}")
    loop = float(re.search(r"Loop time of ([0-9.eE+-]+)", r.stdout).group(1))
    rows = re.findall(r"^\s*(\d+)\s+(\d+)\s+([0-9.eE+-]+)", r.stdout, re.M)
    ke0, ke1 = float(rows[0][2]), float(rows[-1][2])
    return dict(ms_per_step=1e3 * loop / steps, atoms=int(rows[0][1]), ke0=ke0, ke1=ke1)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--cells", type=int, default=44)
    p.add_argument("--steps", type=int, default=100)
    p.add_argument("--dt", type=float, default=1e-7)
    p.add_argument("--np", type=int, nargs="+", default=[1, 2])
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    a = p.parse_args()
    from fracdem import meshgen
    wd = tempfile.mkdtemp(prefix="distributed_mixed_")
    shutil.copy(os.path.join(HERE, "inputs", "in.distributed_mixed"), wd)
    c = a.cells
    X, E, G = meshgen.box_tet_mesh(2 * c, c, c, 0.4, 0.2, 0.2)
    meshgen.write_gmsh22(os.path.join(wd, "block.msh"), X, E, G)
    elements = len(E)
    del X, E, G
    samples = {}
    for _ in range(a.reps):
        for np_ in a.np:
            for parallel in ("replicated", "distributed"):
                got = run(os.path.abspath(a.exe), wd, np_, parallel, a.steps, a.dt)
                samples.setdefault((parallel, np_), []).append(got)
                print(parallel, np_, got, flush=True)
    rows = []
    for (parallel, np_), runs in sorted(samples.items()):
        ms = statistics.median(r["ms_per_step"] for r in runs)
        base = statistics.median(r["ms_per_step"] for r in samples[(parallel, a.np[0])])
        rows.append({"variant": parallel, "elements": elements, "spheres": runs[0]["atoms"],
                     "np": np_, "steps": a.steps, "ms_per_step_median": f"{ms:.3f}",
                     "speedup": f"{base / ms * a.np[0]:.3f}",
                     "sphere_ke_start": f"{runs[0]['ke0']:.6g}",
                     "sphere_ke_end": f"{runs[0]['ke1']:.6g}"})
        print(rows[-1])
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, "distributed_mixed.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {path}")
    plot(rows, os.path.join(a.out, "distributed_mixed.png"))
    shutil.rmtree(wd, ignore_errors=True)


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for variant in ("replicated", "distributed"):
        sel = [r for r in rows if r["variant"] == variant]
        ax.plot([r["np"] for r in sel], [float(r["ms_per_step_median"]) for r in sel], "o-",
                label=variant)
    ax.set(xlabel="ranks", ylabel="loop time per step (ms, median)",
           title=f"spheres on a {int(rows[0]['elements']):.2e}-tet body")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
