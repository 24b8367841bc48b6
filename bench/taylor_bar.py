"""Run time against error for the Taylor bar (issue #10, deliverable 8): which mesh and time step
buy which accuracy in final length and foot radius.

The problem is the one of tests/integration/test_taylor_bar.py (python/fracdem/taylor.py: copper
rod, L0 32.4 mm, R0 3.2 mm, 227 m/s onto a rigid frictionless wall, j2 yield 400 MPa, hardening
100 MPa, 80 us, `plane axisymmetric` quad4, `model corotational`; sources in docs/validation.md,
"Taylor bar"). For nr = 4, 6, 8 radial cells (square cells: 4 x 40, 6 x 61, 8 x 81), each case
at np 1, REPS runs:

* dt 0.2 and 0.1 of the stable FE step printed at set-up, default bulk viscosity (0.06 1.2);
* dt 0.2 with `bulk_viscosity off`.

Columns: wall_s (median 'Loop time' of the repetitions), t_stop_us (80 when the run completes,
else the step of its ERROR line times dt), length_mm / radius_mm at the last energy row (columns
displacement_tail_y, displacement_foot_x), their errors against the published midpoints 21.45 /
7.05 mm (only for completed runs), energy_err_pct (kinetic + strain + plastic + viscous work
against the initial kinetic energy, largest over the rows), status ('ok', 'aborted: <the
ERROR line>', or 'unstable: ...' for a run that completes with its energy balance off by more than
5 %: a too-large step can blow up without inverting an element). A run that stops with an
error is repeated like the others; its wall time is the wall clock of the command (start-up
included: it prints no Loop time).

  python3 bench/taylor_bar.py [--exe build/fracdem] [--out bench/results] [--reps 3] [--meshes 4 6 8]

Writes <out>/taylor_bar.csv and <out>/taylor_bar.png.
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
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))
from fracture_accuracy import loop_time, mpirun, read_csv, stable_dt  # noqa: E402

from fracdem import taylor  # noqa: E402

MESHES = (4, 6, 8)
CASES = ((0.2, ""), (0.1, ""), (0.2, "bulk_viscosity off"))  # (dt fraction, extra keywords)
ROWS = 100  # energy-file rows over the run
UNSTABLE = 0.05  # a completed run whose energy balance is off by more is unstable (no error)
INPUTS = os.path.join(ROOT, "tests", "integration", "inputs")


def run(exe, wd, variables):
    """Run in.taylor in wd at np 1; returns (output, first ERROR line or None, wall time): the
    'Loop time' line, or the wall clock of the whole command when the run stops with an error."""
    cmd = mpirun(1) + [exe, "-echo", "none", "-in", "in.taylor"]
    for k, v in variables.items():
        cmd += ["-var", k, str(v)]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       errors="replace", timeout=3600)
    wall = time.perf_counter() - t0
    errors = [l.strip() for l in r.stdout.splitlines() if "ERROR" in l]
    err = None if r.returncode == 0 else f"rc={r.returncode}"
    if errors:  # the first ERROR line without its source location
        err = re.sub(r" \(/\S+:\d+\)$", "", errors[0])
    return r.stdout, err, (loop_time(r.stdout) if err is None else wall)


def write_scene(wd, extra):
    with open(os.path.join(wd, "in.taylor"), "w") as f:
        f.write("include in.fe_common_2d\ntimestep ${dt}\n"
                + taylor.body_command("bar.msh", "energy.csv", "${every}", extra) + "\n"
                "thermo ${every}\nrun ${steps}\n")


def case(exe, nr, frac, extra, reps):
    """REPS runs of one mesh / time step / variant; returns its row."""
    wd = tempfile.mkdtemp(prefix=f"taylor_bench_{nr}_")
    shutil.copy(os.path.join(INPUTS, "in.fe_common_2d"), wd)
    _, elems = taylor.bar_mesh(os.path.join(wd, "bar.msh"), nr)
    write_scene(wd, extra)
    out, err, _ = run(exe, wd, dict(dt=1e-12, every=1, steps=0))
    dt0 = stable_dt(out)
    if dt0 is None:
        raise RuntimeError(f"nr = {nr}: no stable step printed: {err}")
    dt = frac * dt0
    every = max(1, int(round(taylor.T_END / dt)) // ROWS)
    steps = every * int(round(taylor.T_END / dt / every))
    walls = []
    for _ in range(reps):
        out, err, wall = run(exe, wd, dict(dt=dt, every=every, steps=steps))
        walls.append(wall)
    e = read_csv(os.path.join(wd, "energy.csv"))
    length, radius = (v[-1] for v in taylor.final_shape(e))
    done = err is None and abs(e["time"][-1] - steps * dt) < 0.5 * dt
    balance = taylor.energy_balance_error(e)
    if done and balance > UNSTABLE:  # it ran to the end, but not stably
        done, err = False, f"unstable: energy balance off by {100 * balance:.0f} %"
    err = None if done else (err or "stopped early")
    m = re.search(r"at step (\d+)", err or "")
    t_stop = taylor.T_END if done else (int(m.group(1)) * dt if m else e["time"][-1])
    row = dict(nr=nr, nz=taylor.cells_along(nr), elements=len(elems), dt_fraction=frac,
               variant=extra or "bulk viscosity 0.06 1.2", dt_s=dt, steps=steps, reps=reps,
               wall_s=statistics.median(walls), t_stop_us=t_stop * 1e6,
               length_mm=length * 1e3, radius_mm=radius * 1e3,
               length_err_pct=100 * (length / taylor.REF_LENGTH - 1) if done else None,
               radius_err_pct=100 * (radius / taylor.REF_RADIUS - 1) if done else None,
               energy_err_pct=100 * balance,
               status="ok" if done else (err if err.startswith("unstable") else "aborted: " + err))
    shutil.rmtree(wd, ignore_errors=True)
    return row


COLS = ["nr", "nz", "elements", "dt_fraction", "variant", "dt_s", "steps", "reps", "wall_s",
        "t_stop_us", "length_mm", "radius_mm", "length_err_pct", "radius_err_pct",
        "energy_err_pct", "status"]


def fmt(v):
    return "" if v is None else (f"{v:.4g}" if isinstance(v, float) else str(v))


def plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    ok = [r for r in rows if r["length_err_pct"] is not None]
    for r in ok:
        lab = f"{r['nr']}x{r['nz']}, {r['dt_fraction']} dt, {r['variant']}"
        axes[0].plot(r["wall_s"], abs(r["length_err_pct"]), "o", label="length " + lab)
        axes[0].plot(r["wall_s"], abs(r["radius_err_pct"]), "s", label="radius " + lab)
    if ok:
        axes[0].legend(fontsize=6)
    else:
        axes[0].text(0.5, 0.5, "no run reached 80 us\n(see the right panel and the CSV status)",
                     ha="center", va="center", transform=axes[0].transAxes)
    axes[0].set_xlabel("median wall time, np 1 (s)")
    axes[0].set_ylabel("|error| vs published (%)")
    axes[0].set_title("final length / foot radius at 80 us", fontsize=10)
    for (frac, extra) in CASES:
        sel = [r for r in rows if r["dt_fraction"] == frac and r["variant"] == (extra or "bulk viscosity 0.06 1.2")]
        axes[1].plot([r["elements"] for r in sel], [r["t_stop_us"] for r in sel], "o-",
                     label=f"{frac} dt, {extra or 'bulk viscosity 0.06 1.2'}")
    axes[1].axhline(taylor.T_END * 1e6, color="k", lw=0.8, ls="--")
    axes[1].set_xlabel("elements (quad4)")
    axes[1].set_ylabel("time the run stopped (us)")
    axes[1].set_title("where each run stopped (80 us = complete)", fontsize=10)
    axes[1].legend(fontsize=7)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--meshes", type=int, nargs="+", default=list(MESHES), help="radial cell counts")
    args = p.parse_args()
    exe = os.path.abspath(args.exe)
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for nr in args.meshes:
        for frac, extra in CASES:
            r = case(exe, nr, frac, extra, args.reps)
            print(" ".join(f"{k}={fmt(r[k])}" for k in COLS), flush=True)
            rows.append(r)
    with open(os.path.join(args.out, "taylor_bar.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLS)
        for r in rows:
            w.writerow([fmt(r[k]) for k in COLS])
    plot(rows, os.path.join(args.out, "taylor_bar.png"))
    print(f"wrote {os.path.join(args.out, 'taylor_bar.csv')} and taylor_bar.png")


if __name__ == "__main__":
    main()
