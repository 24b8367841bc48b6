"""fracdem benchmarks: ratios measured side by side in one run, median over repetitions, CSV + PNG.

  python3 bench/run_benchmarks.py [--reps 5] [--steps 20000] [--out bench/results]

1. stock: the same particle-only script with `liggghts` and with `fracdem` (goal: within 2%).
2. rigid wall: particles on a rigid plate as a stock mesh wall (fix mesh/surface + wall/gran)
   and as a rigid `fix fem/body` on the same geometry (goal: no slower); also reports how far
   the two runs' particle kinetic energies agree.
3. FE throughput: element-steps per second per core (bench_fem_throughput from the build).
"""
import argparse
import csv
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))

import harness  # noqa: E402
from fracdem import meshgen  # noqa: E402


def write_plate(wd):
    X, E, G = meshgen.box_tet_mesh(10, 10, 1, 0.1, 0.1, 0.01, origin=(-0.05, -0.05, -0.01))
    meshgen.write_gmsh22(os.path.join(wd, "plate.msh"), X, E, G)
    meshgen.write_stl(os.path.join(wd, "plate.stl"), X, meshgen.group_triangles(G), "plate")


def timed_run(exe, script, wd, variables, np_=1):
    t0 = time.perf_counter()
    out = harness.run(exe, script, np_=np_, workdir=wd, variables=variables)
    wall = time.perf_counter() - t0
    loop = [float(l.split()[3]) for l in out.splitlines() if l.startswith("Loop time of")]
    return wall, sum(loop), out


def bench_stock(args, rows):
    liggghts = shutil.which("liggghts")
    for rep in range(args.reps):
        for name, exe in (("liggghts", liggghts), ("fracdem", args.exe)):  # interleaved
            wd = tempfile.mkdtemp(prefix="bench_stock_")
            shutil.copy(os.path.join(HERE, "inputs", "in.stock_packing"), wd)
            wall, loop, _ = timed_run(exe, "in.stock_packing", wd, dict(steps=args.steps))
            rows.append(dict(benchmark="stock_script", variant=name, repetition=rep, loop_s=loop, wall_s=wall))
            print(f"  stock_script {name:9s} rep {rep}: loop {loop:.3f} s")


def bench_rigid(args, rows):
    kes = {}
    for rep in range(args.reps):
        for variant in ("mesh", "fem"):
            wd = tempfile.mkdtemp(prefix="bench_rigid_")
            for f in ("in.rigid_plate", "in.wall_mesh", "in.wall_fem"):
                shutil.copy(os.path.join(HERE, "inputs", f), wd)
            write_plate(wd)
            wall, loop, out = timed_run(args.exe, "in.rigid_plate", wd, dict(steps=args.steps, WALL=variant))
            runs = harness.thermo_blocks(out)
            kes[variant] = harness.column(runs, "KinEng")
            rows.append(dict(benchmark="rigid_wall", variant=variant, repetition=rep, loop_s=loop, wall_s=wall))
            print(f"  rigid_wall   {variant:9s} rep {rep}: loop {loop:.3f} s")
    a, b = kes["mesh"], kes["fem"]
    scale = max(a)
    diff = max(abs(x - y) for x, y in zip(a, b)) / scale
    return diff


def bench_fem(args, rows):
    exe = os.path.join(ROOT, "build", "bench", "bench_fem_throughput")
    if not os.path.exists(exe):
        print("  (bench_fem_throughput not built; skipped)")
        return
    csv_path = os.path.join(args.out, "fem_throughput.csv")
    subprocess.run([exe, csv_path], check=True)


def summarize(rows, out, kediff):
    groups = {}
    for r in rows:
        groups.setdefault((r["benchmark"], r["variant"]), []).append(r["loop_s"])
    med = {k: statistics.median(v) for k, v in groups.items()}
    lines = ["| benchmark | variant | median loop time (s) | ratio |", "|---|---|---|---|"]
    ref = {"stock_script": "liggghts", "rigid_wall": "mesh"}
    for (b, v), m in sorted(med.items()):
        lines.append(f"| {b} | {v} | {m:.3f} | {m / med[(b, ref[b])]:.3f} |")
    if kediff is not None:
        lines.append(f"\nrigid_wall: max |KE_fem - KE_mesh| / max KE over the run = {kediff:.2e}")
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(text + "\n")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.5))
    labels = [f"{b}\n{v}" for (b, v) in sorted(med)]
    ax.bar(labels, [med[k] for k in sorted(med)], color=["C0", "C1", "C0", "C1"][: len(med)])
    for (b, v) in sorted(med):
        ax.scatter([f"{b}\n{v}"] * len(groups[(b, v)]), groups[(b, v)], color="k", s=8, zorder=3)
    ax.set_ylabel("loop time (s)")
    ax.set_title("fracdem vs stock LIGGGHTS (median, dots = repetitions)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "bench_runtime.png"), dpi=120)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--steps", type=int, default=20000)
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--only", choices=("stock", "rigid", "fem"), action="append")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows, kediff = [], None
    only = set(args.only or ("stock", "rigid", "fem"))
    if "stock" in only:
        bench_stock(args, rows)
    if "rigid" in only:
        kediff = bench_rigid(args, rows)
    if "fem" in only:
        bench_fem(args, rows)
    if rows:
        with open(os.path.join(args.out, "runtime.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        summarize(rows, args.out, kediff)


if __name__ == "__main__":
    main()
