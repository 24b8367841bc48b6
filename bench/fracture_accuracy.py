"""Run time against error for the Brazilian disc, so that a user can pick a mesh and time step.

Measures, for the concrete Brazilian disc of tests/integration/test_fracture_validation.py
(tests/integration/inputs/in.brazilian, FE only, Rankine rotating crack, nodal fracture), on
ring spacings h = 6, 4.5 and 3 mm (meshgen.disc, D = 150 mm) and time steps of 0.9 and 0.5 of
the stable FE step printed at set-up, one run each at np 1:

* wall_s: the 'Loop time' line of the run;
* peak_stress_MPa: 2P/(pi D t) at the peak of the bottom reaction (energy file column
  reaction_bottom_y), and error_pct: its error against f_t = 3.33 MPa (Hondros' elastic
  solution at the centre, the validation test's reference);
* dissipated_J: the fracture energy (energy file column fracture_energy) at the end of the run.

Every run stops at the same time, STOP_TIME = 3.5 ms: shortly after the peak, which comes at
2.5-3.1 ms on these meshes (the validation test runs h = 3 mm to 3.0 ms), so that wall_s and
dissipated_J compare like with like across rows. If the peak is the last output row (the load
still rising), the run is repeated to 1.5 x the time (at most 7.9 ms): wall_s, steps and
dissipated_J are those of the run kept, whose end time is the column t_end_ms (t_peak_ms: time
of the peak). A run that still peaks at its end is marked 'peak at end'. If a run stops with an
ERROR (e.g. the stable step falls below the host step after cracking, which is why the
validation test uses 0.4 of the stable step), its row has status 'aborted: <message>' and no
error is computed from it.

Every parameter (concrete E = 30 GPa, nu = 0.2, f_t = 3.33 MPa, G_f = 124 N/m after Petersson
1981; density 2400 kg/m^3 after EN 1991-1-1; D = 150 mm, t = 50 mm, 6 degree loading arcs,
platen velocity 0.05 m/s ramped over 0.4 ms, fracture check every 10 steps) is the same as in
the validation test, whose docstring gives their sources. The helpers below are copied from it
(and tests/integration/harness.py), adapted; nothing is imported from the tests.

  python3 bench/fracture_accuracy.py [--exe build/fracdem] [--out bench/results]

Writes <out>/fracture_accuracy.csv and <out>/fracture_accuracy.png (error vs wall time).
"""
import argparse
import csv
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
INPUTS = os.path.join(ROOT, "tests", "integration", "inputs")
sys.path.insert(0, os.path.join(ROOT, "python"))
from fracdem import meshgen  # noqa: E402

# Concrete, Petersson (1981); density EN 1991-1-1 (as in test_fracture_validation.py).
RHO, E, NU, FT, GF = 2400.0, 30e9, 0.2, 3.33e6, 124.0
FRACTURE_EVERY = 10
# Brazilian disc (as in test_fracture_validation.py).
DISC_D, DISC_T, DISC_FLAT = 0.150, 0.05, 6.0
DISC_V, DISC_RAMP = 0.05, 4e-4
STOP_TIME = 3.5e-3
EXTEND, MAX_TIME = 1.5, 7.875e-3
ROWS = 800  # energy-file rows over the run

SPACINGS = (0.006, 0.0045, 0.003)
DT_FRACTIONS = (0.9, 0.5)
COMMON = dict(rho=RHO, E=E, nu=NU, ft=FT, gf=GF, fevery=FRACTURE_EVERY, thermo=10 ** 9)


def mpirun(np_):
    cmd = ["mpirun", "-np", str(np_)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    return cmd


def run(exe, wd, variables, np_=1, timeout=1800):
    """Run in.brazilian in wd; returns (output text, error message or None)."""
    cmd = mpirun(np_) + [exe, "-echo", "none", "-in", "in.brazilian"]
    for k, v in variables.items():
        cmd += ["-var", k, str(v)]
    env = dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1")
    r = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, errors="replace", timeout=timeout, env=env)
    err = None
    if r.returncode != 0 or "ERROR" in r.stdout:
        lines = [l.strip() for l in r.stdout.splitlines() if "ERROR" in l]
        err = lines[0] if lines else f"rc={r.returncode}"
    return r.stdout, err


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}


def stable_dt(text):
    m = re.search(r"stable FE time step ([0-9.eE+-]+)", text)
    return float(m.group(1)) if m else None


def loop_time(text):
    m = re.search(r"Loop time of ([0-9.eE+-]+)", text)
    return float(m.group(1)) if m else None


def run_one(exe, wd, var, hh, nelem, dt0, frac, stop):
    """One run of in.brazilian at frac x dt0 to time `stop`; returns its row."""
    dt = frac * dt0
    full = int(math.ceil(stop / dt))
    every = max(1, full // ROWS)
    steps = full // every * every
    energy = os.path.join(wd, "energy.csv")
    if os.path.exists(energy):
        os.remove(energy)
    out, err = run(exe, wd, dict(var, dt=dt, steps=steps, every=every))
    row = dict(h_mm=hh * 1e3, dt_fraction=frac, elements=nelem, steps=steps, dt_s=dt,
               wall_s=loop_time(out), peak_stress_MPa=None, error_pct=None, dissipated_J=None,
               t_peak_ms=None, t_end_ms=stop * 1e3, status="ok")
    if err is not None:
        row["status"] = "aborted: " + err
        return row
    e = read_csv(energy)
    P = np.array(e["reaction_bottom_y"])
    k = int(np.argmax(P))
    sigma = 2 * P[k] / (math.pi * DISC_D * DISC_T)
    row.update(peak_stress_MPa=sigma / 1e6, error_pct=100 * (sigma / FT - 1),
               dissipated_J=e["fracture_energy"][-1], t_peak_ms=e["time"][k] * 1e3,
               t_end_ms=e["time"][-1] * 1e3)
    if k == len(P) - 1:
        row["status"] = "peak at end"
    return row


def disc_case(exe, hh, fractions):
    """Mesh the disc at ring spacing hh, probe the stable step, run each dt fraction."""
    wd = tempfile.mkdtemp(prefix="fracture_accuracy_")
    for n in ("in.brazilian", "in.fe_common_2d"):
        shutil.copy(os.path.join(INPUTS, n), wd)
    X, E_, G = meshgen.disc(DISC_D / 2, hh, flat_angle_deg=DISC_FLAT)
    meshgen.write_gmsh22(os.path.join(wd, "disc.msh"), X, E_, G)
    var = dict(COMMON, mesh="disc.msh", t=DISC_T, v=DISC_V, ramp=DISC_RAMP)
    out, err = run(exe, wd, dict(var, dt=1e-12, steps=0, every=1))
    dt0 = stable_dt(out)
    if dt0 is None:
        raise RuntimeError(f"no stable step printed for h = {hh}: {err}\n{out[-2000:]}")
    rows = []
    for frac in fractions:
        # run to STOP_TIME; while the peak is the last row (load still rising), run again to
        # EXTEND x the time, at most MAX_TIME: each run stops shortly after its peak
        stop = STOP_TIME
        while True:
            row = run_one(exe, wd, var, hh, len(E_), dt0, frac, stop)
            if row["status"] != "peak at end" or stop >= MAX_TIME - 1e-12:
                break
            stop = min(MAX_TIME, EXTEND * stop)
        if row["error_pct"] is None:
            print(f"h = {hh * 1e3:g} mm, {frac} x dt: {row['status']}", flush=True)
        else:
            print(f"h = {hh * 1e3:g} mm ({len(E_)} tri3), {frac} x {dt0:.3g} s, {row['steps']} steps "
                  f"to {stop * 1e3:.2f} ms: {row['wall_s']:.1f} s, peak at {row['t_peak_ms']:.2f} ms, "
                  f"2P/(pi D t) = {row['peak_stress_MPa']:.3f} MPa ({row['error_pct']:+.1f} %), "
                  f"dissipated {row['dissipated_J']:.4f} J, {row['status']}", flush=True)
        rows.append(row)
    shutil.rmtree(wd, ignore_errors=True)
    return rows


def fmt(v, spec):
    return "" if v is None else format(v, spec)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    args = p.parse_args()
    exe = os.path.abspath(args.exe)
    os.makedirs(args.out, exist_ok=True)

    rows = []
    for hh in SPACINGS:
        rows += disc_case(exe, hh, DT_FRACTIONS)

    cols = ["h", "dt_fraction", "elements", "steps", "wall_s", "peak_stress_MPa", "error_pct",
            "dissipated_J", "status", "t_peak_ms", "t_end_ms"]
    with open(os.path.join(args.out, "fracture_accuracy.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([f"{r['h_mm']:g}", r["dt_fraction"], r["elements"], r["steps"],
                        fmt(r["wall_s"], ".2f"), fmt(r["peak_stress_MPa"], ".4f"),
                        fmt(r["error_pct"], ".2f"), fmt(r["dissipated_J"], ".5f"), r["status"],
                        fmt(r["t_peak_ms"], ".3f"), fmt(r["t_end_ms"], ".3f")])

    print("\n| h (mm) | dt fraction | elements | steps | wall (s) | 2P/(pi D t) at peak (MPa) "
          "| error vs f_t (%) | dissipated at end (J) | peak / end (ms) | status |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['h_mm']:g} | {r['dt_fraction']} | {r['elements']} | {r['steps']} | "
              f"{fmt(r['wall_s'], '.1f')} | {fmt(r['peak_stress_MPa'], '.3f')} | "
              f"{fmt(r['error_pct'], '+.1f')} | {fmt(r['dissipated_J'], '.4f')} | "
              f"{fmt(r['t_peak_ms'], '.2f')} / {fmt(r['t_end_ms'], '.2f')} | {r['status']} |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    markers = {0.9: "o", 0.5: "s"}
    colors = {0.006: "tab:blue", 0.0045: "tab:orange", 0.003: "tab:green"}
    for r in rows:
        if r["error_pct"] is None:
            continue
        ax.plot(r["wall_s"], abs(r["error_pct"]), markers.get(r["dt_fraction"], "^"),
                color=colors.get(r["h_mm"] / 1e3, "k"), ms=8)
        ax.annotate(f"h={r['h_mm']:g} mm, {r['dt_fraction']} dt", (r["wall_s"], abs(r["error_pct"])),
                    textcoords="offset points", fontsize=7,
                    xytext=(6, 5) if r["dt_fraction"] >= 0.7 else (6, -11))
    aborted = [f"h={r['h_mm']:g} mm, {r['dt_fraction']} dt" for r in rows if r["error_pct"] is None]
    if aborted:
        ax.text(0.02, 0.02, "aborted (not shown): " + "; ".join(aborted), transform=ax.transAxes,
                fontsize=7, va="bottom")
    ax.set_xscale("log")
    ax.set_ylim(bottom=-0.5)
    ax.set_xlabel("wall time, np 1 (s, Loop time)")
    ax.set_ylabel("|2P/(pi D t) at peak / f_t - 1| (%)")
    ax.set_title("Brazilian disc D = 150 mm: error vs run time\n(f_t = 3.33 MPa; all runs to 3.5 ms, shortly after the peak)",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "fracture_accuracy.png"), dpi=120)
    print(f"\nwrote {os.path.join(args.out, 'fracture_accuracy.csv')} and fracture_accuracy.png")


if __name__ == "__main__":
    main()
