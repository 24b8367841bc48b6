"""The neighbour skin against run time on the settling and hopper scenes (bench/inputs/
in.settle_fracdem, in.hopper_fracdem, their balance fix left out), one rank: a sweep of fixed
skins and `fix fracdem/skin N SKIN_MIN SKIN_MAX` started from the stock skin (2 mm), each run
--reps times (variants interleaved within a repetition), medians compared.

  python3 bench/skin_sweep.py [--reps 3] [--scenes settle hopper] [--out bench/results]

Time is the CPU time of the fracdem process (user + system, from the operating system: on a
shared machine wall time counts the neighbours' work too), the LIGGGHTS "Loop time" is kept
beside it. Goal: the fix within 5 % of the best fixed skin. Writes skin_sweep.csv (one row per
run), skin_sweep.md and skin_sweep.png.
"""
import argparse
import csv
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))
sys.path.insert(0, os.path.join(ROOT, "python"))

import harness  # noqa: E402

SKINS = [0.0005, 0.001, 0.0015, 0.002, 0.003, 0.004, 0.006]
# scene: input, steps, fix interval N
SCENES = {
    "settle": ("in.settle_fracdem", 8000, 250),
    "hopper": ("in.hopper_fracdem", 16000, 500),
}
STOCK_SKIN = "neighbor        0.002 bin"


def scene_text(name):
    with open(os.path.join(HERE, "inputs", SCENES[name][0])) as f:
        text = f.read()
    assert STOCK_SKIN in text
    text = text.replace(STOCK_SKIN, "neighbor        ${skin} bin")
    # Only the skin fix: the balance fix's measurements would be time of their own.
    text = re.sub(r"^fix\s+bal .*?(?:&\n.*?)?\n", "", text, flags=re.M)
    text = re.sub(r" f_bal\S*", "", text)
    assert "balance/graph" not in text
    tune = "if \"${tune} == 1\" then \"fix sk all fracdem/skin ${n} ${smin} ${smax}\"\n"
    return text.replace("\nthermo_style", "\n" + tune + "thermo_style", 1)


def prepare(name, wd):
    with open(os.path.join(wd, "in.scene"), "w") as f:
        f.write(scene_text(name))
    if name == "hopper":
        from fracdem import meshgen
        X, E = meshgen.funnel_tet_mesh(0.02, 0.08, 0.1, 0.005, 36, 8, origin=(0, 0, 0.02))
        meshgen.write_gmsh22(os.path.join(wd, "hopper.msh"), X, E)


def run_once(exe, name, wd, skin, tune):
    """One run without mpirun (a singleton MPI process): (CPU s, loop s, final skin, changes)."""
    _, steps, n = SCENES[name]
    v = dict(skin=skin, tune=int(tune), n=n, smin=SKINS[0], smax=SKINS[-1], steps=steps)
    cmd = [exe, "-echo", "none", "-in", "in.scene"]
    for k, val in v.items():
        cmd += ["-var", k, str(val)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0 or "ERROR" in r.stdout:
        raise RuntimeError(f"{' '.join(cmd)} failed in {wd}:\n{r.stdout[-3000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    loop = float(re.search(r"^Loop time of (\S+)", r.stdout, re.M).group(1))
    changes = re.findall(r"fix fracdem/skin: step \d+: skin \S+ -> (\S+)", r.stdout)
    final = float(changes[-1]) if changes else skin
    return cpu, loop, final, len(changes)


def summary(rows):
    lines = []
    for scene in SCENES:
        rs = [r for r in rows if r["scene"] == scene]
        med = {}
        for variant in sorted({r["variant"] for r in rs}, key=lambda v: (v == "fix", v)):
            sel = [r for r in rs if r["variant"] == variant]
            med[variant] = (statistics.median(r["cpu_s"] for r in sel),
                            statistics.median(r["loop_s"] for r in sel),
                            statistics.median(r["final_skin"] for r in sel))
        fixed = {v: m for v, m in med.items() if v != "fix"}
        best = min(fixed, key=lambda v: fixed[v][0])
        ratio = med["fix"][0] / fixed[best][0]
        stock = med["fix"][0] / fixed[f"{0.002:g}"][0]
        lines += [f"### {scene} ({SCENES[scene][1]} steps, fix interval {SCENES[scene][2]})", "",
                  "| skin (m) | CPU s (median) | loop s (median) |", "|---|---|---|"]
        lines += [f"| {v} | {m[0]:.3f} | {m[1]:.3f} |" for v, m in fixed.items()]
        lines += [f"| fix fracdem/skin (ends at {med['fix'][2]:.4g}) | {med['fix'][0]:.3f} | "
                  f"{med['fix'][1]:.3f} |", "",
                  f"fix / best fixed skin ({best} m): {ratio:.3f} (goal <= 1.05); "
                  f"fix / stock skin 0.002 m: {stock:.3f}.", ""]
    return "\n".join(lines)


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(SCENES), figsize=(5 * len(SCENES), 3.5))
    for ax, scene in zip(axes, SCENES):
        rs = [r for r in rows if r["scene"] == scene]
        xs = sorted({r["skin"] for r in rs if r["variant"] != "fix"})
        ys = [statistics.median(r["cpu_s"] for r in rs if r["variant"] != "fix" and r["skin"] == x)
              for x in xs]
        ax.plot([1e3 * x for x in xs], ys, "o-", label="fixed skin")
        fix = [r for r in rs if r["variant"] == "fix"]
        t = statistics.median(r["cpu_s"] for r in fix)
        ax.axhline(t, color="C1", ls="--", label="fix fracdem/skin")
        ax.plot([1e3 * statistics.median(r["final_skin"] for r in fix)], [t], "s", color="C1")
        ax.set_xlabel("skin (mm)")
        ax.set_ylabel("CPU time (s, median)")
        ax.set_title(f"{scene}, 1 rank")
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    p = harness.parser()
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    args = harness.parse_args(p)
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for scene in args.scenes:
        wd = tempfile.mkdtemp(prefix=f"bench_skin_{scene}_")
        prepare(scene, wd)
        for rep in range(args.reps):
            for variant in [f"{s:g}" for s in SKINS] + ["fix"]:
                skin = 0.002 if variant == "fix" else float(variant)
                cpu, loop, final, changes = run_once(args.exe, scene, wd, skin, variant == "fix")
                rows.append(dict(scene=scene, variant=variant, repetition=rep, skin=skin,
                                 cpu_s=cpu, loop_s=loop, final_skin=final, changes=changes))
                print(f"  {scene} {variant:7s} rep {rep}: CPU {cpu:.3f} s, loop {loop:.3f} s"
                      + (f", {changes} changes, ends at {final:.4g}" if variant == "fix" else ""),
                      flush=True)
        shutil.rmtree(wd, ignore_errors=True)
    name = "skin_sweep" if len(args.scenes) == len(SCENES) else "skin_sweep_" + "_".join(args.scenes)
    with open(os.path.join(args.out, name + ".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    text = summary([r for r in rows])
    with open(os.path.join(args.out, name + ".md"), "w") as f:
        f.write(text)
    plot(rows, os.path.join(args.out, name + ".png"))
    print(text)


if __name__ == "__main__":
    main()
