"""Run time against error for the Brazilian disc and the notched beam, so that a user can pick a mesh and time step.

Run time is the CPU time (user + system seconds) of each run (os.wait4 of its mpirun, which
waits for its rank): on a machine shared with other jobs the wall time (column wall_s, the
'Loop time' line) grows with the load, the CPU time much less. One run per row (no repetitions:
an error-vs-time figure; CPU times vary by ~10 % between runs).

Brazilian disc (--case disc): the concrete disc of tests/integration/test_fracture_validation.py
(tests/integration/inputs/in.brazilian, FE only, Rankine rotating crack, nodal fracture), on
ring spacings h = 6, 4.5 and 3 mm (meshgen.disc, D = 150 mm) and time steps of 0.9 and 0.5 of
the stable FE step printed at set-up, one run each at np 1:

* peak_stress_MPa: 2P/(pi D t) at the peak of the bottom reaction (energy file column
  reaction_bottom_y), and error_pct: its error against f_t = 3.33 MPa (Hondros' elastic
  solution at the centre, the validation test's reference);
* dissipated_J: the fracture energy (energy file column fracture_energy) at the end of the run.

Every disc run stops at the same time, STOP_TIME = 3.5 ms: shortly after the peak, which comes
at 2.5-3.1 ms on these meshes (the validation test runs h = 3 mm to 3.0 ms), so that the run
times and dissipated_J compare like with like across rows. If the peak is the last output row
(the load still rising), the run is repeated to 1.5 x the time (at most 7.9 ms): the figures
are those of the run kept, whose end time is the column t_end_ms (t_peak_ms: time of the peak).
A run that still peaks at its end is marked 'peak at end'. If a run stops with an ERROR, its
row has status 'aborted: <message>' and no error is computed from it.

Notched beam (--case beam): the beam of the validation test (tests/integration/inputs/
in.notched_beam: Petersson's 1981 concrete and section, depth D = 200 mm, zero-width notch
a = 100 mm, thickness 50 mm, span 4 D = 800 mm, the test's graded tri3 grid of spacing h, built
by meshgen.notched_beam on meshgen.capped_graded_axis: byte for byte the test's mesh), on
h = 20, 13.3, 10, 6.67 and 5 mm (--beam-h) and 0.9 and 0.5 of the stable step, each run to the
test's load-point deflection u = 1.2 mm (the beam is broken by then), two runs at a time
(--jobs), np 1:

* peak_N: the largest load-node reaction (-reaction_load_y), peak_err_pct: its error against
  the peak of the finest run of the bench (h = 5 mm at 0.5 of the stable step; column
  peak_ref). The validation test has no absolute reference for the peak of this short-span
  beam (it asserts the spread of h = 10, 6.67 and 5 mm, 10 %);
* dissipated_J: fracture_energy at the end, diss_err_pct: its error against G_f (D - a) t =
  0.62 J, the test's (open) target;
* splits, fragments, eroded (elements), max_substeps (the energy file's substeps column:
  sub-cycling after cracking), tail_load_N (mean load over the last 10 % of the run: broken
  when ~0), balance (worst |kinetic + strain + dissipated + eroded - boundary work| over the
  largest boundary work).

Every parameter (concrete E = 30 GPa, nu = 0.2, f_t = 3.33 MPa, G_f = 124 N/m after Petersson
1981; density 2400 kg/m^3 after EN 1991-1-1; disc D = 150 mm, t = 50 mm, 6 degree loading arcs,
platen velocity 0.05 m/s ramped over 0.4 ms; beam load-point velocity 15 mm/s ramped over 3 ms;
fracture check every 10 steps) is the same as in the validation test, whose docstring gives
their sources. The helpers below are copied from it (and tests/integration/harness.py),
adapted; nothing is imported from the tests.

  python3 bench/fracture_accuracy.py [--exe build/fracdem] [--out bench/results] [--case all|disc|beam]
  python3 bench/fracture_accuracy.py --table   # the beam table of docs/benchmarks.md from the CSV

Writes <out>/fracture_accuracy.{csv,png} (disc) and <out>/fracture_accuracy_beam.{csv,png}
(beam; the table of docs/benchmarks.md is printed from the CSV).
"""
import argparse
import concurrent.futures
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

# Notched beam (as in test_fracture_validation.py): Petersson's section, span 4 D, run to a
# load-point deflection of 1.2 mm, where the beam is broken.
BEAM_S, BEAM_DEPTH, BEAM_A, BEAM_T = 0.8, 0.2, 0.1, 0.05
BEAM_FINE, BEAM_GROWTH, BEAM_CAP = 0.06, 1.2, 4.0
BEAM_V, BEAM_RAMP, BEAM_U = 0.015, 0.003, 1.2e-3
BEAM_GFA = GF * (BEAM_DEPTH - BEAM_A) * BEAM_T  # G_f (D - a) t = 0.62 J
BEAM_SPACINGS = (0.02, 0.02 / 1.5, 0.01, 0.02 / 3, 0.005)
DT_FRACTIONS = (0.9, 0.5)
COMMON = dict(rho=RHO, E=E, nu=NU, ft=FT, gf=GF, fevery=FRACTURE_EVERY, thermo=10 ** 9)


def mpirun(np_):
    cmd = ["mpirun", "-np", str(np_)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    return cmd


def run_timed(exe, wd, variables, script="in.brazilian", np_=1):
    """Run `script` in wd under mpirun; returns (output text, error message or None, CPU
    seconds). The CPU time (user + system) is that of mpirun and the ranks it waited for
    (os.wait4 of mpirun), which a machine shared with other jobs does not inflate as it does
    the wall time."""
    cmd = mpirun(np_) + [exe, "-echo", "none", "-in", script]
    for k, v in variables.items():
        cmd += ["-var", k, str(v)]
    env = dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1")
    with tempfile.TemporaryFile(mode="w+", errors="replace") as log:
        p = subprocess.Popen(cmd, cwd=wd, stdout=log, stderr=subprocess.STDOUT, env=env)
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        log.seek(0)
        text = log.read()
    err = None
    if p.returncode != 0 or "ERROR" in text:
        lines = [l.strip() for l in text.splitlines() if "ERROR" in l]
        err = lines[0] if lines else f"rc={p.returncode}"
    return text, err, usage.ru_utime + usage.ru_stime


def run(exe, wd, variables, np_=1):
    """Run in.brazilian in wd; returns (output text, error message or None)."""
    return run_timed(exe, wd, variables, np_=np_)[:2]


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
    out, err, cpu = run_timed(exe, wd, dict(var, dt=dt, steps=steps, every=every))
    row = dict(h_mm=hh * 1e3, dt_fraction=frac, elements=nelem, steps=steps, dt_s=dt,
               wall_s=loop_time(out), cpu_s=cpu, peak_stress_MPa=None, error_pct=None, dissipated_J=None,
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
                  f"to {stop * 1e3:.2f} ms: {row['cpu_s']:.1f} s CPU, peak at {row['t_peak_ms']:.2f} ms, "
                  f"2P/(pi D t) = {row['peak_stress_MPa']:.3f} MPa ({row['error_pct']:+.1f} %), "
                  f"dissipated {row['dissipated_J']:.4f} J, {row['status']}", flush=True)
        rows.append(row)
    shutil.rmtree(wd, ignore_errors=True)
    return rows


# ---------------------------------------------------------------------------- notched beam

def beam_mesh(path, hh):
    """The validation test's beam (test_fracture_validation.beam_mesh: tri3, zero-width notch,
    spacing hh in y and for |x| <= BEAM_FINE, growing by BEAM_GROWTH to BEAM_CAP x hh along x,
    supports at the ends); returns the element count."""
    fine = max(1, round(BEAM_FINE / hh)) * hh
    xs = meshgen.capped_graded_axis(fine, hh, BEAM_S / 2, BEAM_GROWTH, BEAM_CAP * hh)
    X, E_, G = meshgen.notched_beam(BEAM_S, BEAM_DEPTH, BEAM_A, hh, notch_width=0.0, span=BEAM_S,
                                    xs=xs)
    del G["ligament"]  # the test's mesh names support_left, support_right and load only
    meshgen.write_gmsh22(path, X, E_, G)
    return len(E_)


def beam_time(deflection):
    # load-point deflection u(t) = v t^2 / (2 ramp) for t < ramp, then v (t - ramp / 2)
    return deflection / BEAM_V + BEAM_RAMP / 2


def beam_run(exe, hh, frac):
    """One beam run at frac of the stable step on the mesh of spacing hh, to u = BEAM_U; its row
    (the reference errors are filled in later)."""
    wd = tempfile.mkdtemp(prefix="fracture_accuracy_beam_")
    for n in ("in.notched_beam", "in.fe_common_2d"):
        shutil.copy(os.path.join(INPUTS, n), wd)
    nelem = beam_mesh(os.path.join(wd, "beam.msh"), hh)
    var = dict(COMMON, mesh="beam.msh", t=BEAM_T, v=BEAM_V, ramp=BEAM_RAMP)
    out, err, _ = run_timed(exe, wd, dict(var, dt=1e-12, steps=0, every=1), "in.notched_beam")
    dt0 = stable_dt(out)
    if dt0 is None:
        raise RuntimeError(f"no stable step printed for h = {hh}: {err}\n{out[-2000:]}")
    dt = frac * dt0
    full = int(math.ceil(beam_time(BEAM_U) / dt))
    every = max(1, full // ROWS)
    steps = full // every * every
    out, err, cpu = run_timed(exe, wd, dict(var, dt=dt, steps=steps, every=every), "in.notched_beam")
    row = dict(case="beam", h_mm=hh * 1e3, dt_fraction=frac, elements=nelem, steps=steps,
               dt_stable_s=dt0, cpu_s=cpu, wall_s=loop_time(out), status="ok")
    with open(os.path.join(wd, "log.liggghts")) as f:
        log = f.read()
    row["eroded"] = log.count("eroded\n")
    if err is not None:
        row["status"] = "aborted: " + err
    if os.path.exists(os.path.join(wd, "energy.csv")):
        e = read_csv(os.path.join(wd, "energy.csv"))
        P = -np.array(e["reaction_load_y"])
        k = int(np.argmax(P))
        t = np.array(e["time"])
        u = np.where(t < BEAM_RAMP, BEAM_V * t ** 2 / (2 * BEAM_RAMP), BEAM_V * (t - BEAM_RAMP / 2))
        nsplit = np.array(e["split_nodes"])
        work = np.array(e["boundary_work"])
        lhs = np.array(e["kinetic"]) + np.array(e["strain"]) + np.array(e["fracture_energy"]) \
            + np.array(e["eroded_energy"])
        row.update(peak_N=P[k], u_peak_mm=u[k] * 1e3,
                   peak_before_split=bool(nsplit[k] == 0 and nsplit[-1] > 0),
                   dissipated_J=e["fracture_energy"][-1], u_end_mm=u[-1] * 1e3,
                   tail_load_N=float(np.mean(P[int(0.9 * len(P)):])),
                   splits=int(nsplit[-1]), fragments=int(e["fragments"][-1]),
                   max_substeps=int(max(e["substeps"])),
                   balance=float(np.max(np.abs(lhs - work)) / np.max(np.abs(work))))
    shutil.rmtree(wd, ignore_errors=True)
    print(f"beam h = {hh * 1e3:.3g} mm ({nelem} tri3), {frac} x {dt0:.3g} s, {steps} steps: "
          f"{cpu:.1f} s CPU, " + (f"peak {row['peak_N']:.0f} N at u = {row['u_peak_mm']:.3f} mm, "
          f"dissipated {row['dissipated_J']:.4f} J, {row['splits']} splits, {row['eroded']} eroded, "
          f"max substeps {row['max_substeps']}, " if "peak_N" in row else "") + row["status"],
          flush=True)
    return row


def beam_case(exe, spacings, fractions, jobs):
    """Every (mesh, dt fraction) run, `jobs` at a time, the longest first; errors of the peak
    against the finest mesh at the smallest fraction, of the dissipation against G_f (D - a) t."""
    todo = sorted(((hh, f) for hh in spacings for f in fractions), key=lambda c: (c[0], c[1]))
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futs = {c: pool.submit(beam_run, exe, *c) for c in todo}
        rows = [futs[c].result() for c in sorted(todo, key=lambda c: (-c[0], -c[1]))]
    ref = min(rows, key=lambda r: (r["h_mm"], r["dt_fraction"]))
    for r in rows:
        ok = r["status"] == "ok" and "peak_N" in r
        r["peak_ref"] = f"h={ref['h_mm']:.3g} mm, {ref['dt_fraction']} dt"
        r["peak_err_pct"] = 100 * (r["peak_N"] / ref["peak_N"] - 1) if ok else None
        r["diss_err_pct"] = 100 * (r["dissipated_J"] / BEAM_GFA - 1) if ok else None
    return rows


BEAM_COLS = ["case", "h_mm", "dt_fraction", "elements", "steps", "cpu_s", "wall_s", "peak_N",
             "u_peak_mm", "peak_err_pct", "peak_ref", "dissipated_J", "diss_err_pct", "splits",
             "fragments", "eroded", "max_substeps", "tail_load_N", "balance", "status"]
BEAM_FMT = dict(h_mm=".4g", cpu_s=".2f", wall_s=".2f", peak_N=".1f", u_peak_mm=".4f",
                peak_err_pct=".2f", dissipated_J=".5f", diss_err_pct=".2f", tail_load_N=".1f",
                balance=".2e")


def write_beam_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(BEAM_COLS)
        for r in rows:
            w.writerow([fmt(r.get(c), BEAM_FMT[c]) if c in BEAM_FMT else r.get(c, "")
                        for c in BEAM_COLS])


def read_beam_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    num = set(BEAM_FMT) | {"dt_fraction", "elements", "steps", "splits", "fragments", "eroded",
                           "max_substeps"}
    return [{k: (float(v) if k in num and v != "" else (None if v == "" else v))
             for k, v in r.items()} for r in rows]


def beam_table(rows):
    """The markdown table of docs/benchmarks.md, from the rows (as read from the CSV)."""
    ref = rows[0]["peak_ref"] if rows else ""
    lines = [f"| h (mm) | dt / stable | elements | steps | CPU (s) | peak load (N) | peak vs {ref} "
             "| dissipated (J) | vs G_f (D - a) t | splits | eroded | max substeps | energy balance "
             "| status |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['h_mm']:.3g} | {r['dt_fraction']:g} | {int(r['elements'])} | {int(r['steps'])} | "
            f"{fmt(r['cpu_s'], '.1f')} | {fmt(r['peak_N'], '.0f')} | {fmt(r['peak_err_pct'], '+.1f')} % | "
            f"{fmt(r['dissipated_J'], '.3f')} | {fmt(r['diss_err_pct'], '+.1f')} % | "
            f"{fmt(r['splits'], '.0f')} | {fmt(r['eroded'], '.0f')} | {fmt(r['max_substeps'], '.0f')} | "
            f"{fmt(r['balance'], '.1e')} | {r['status']} |")
    return "\n".join(lines)


def beam_plot(path, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    markers = {0.9: "o", 0.5: "s"}
    hs = sorted({r["h_mm"] for r in rows}, reverse=True)
    colors = dict(zip(hs, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    for ax, key, label in ((axes[0], "peak_err_pct", f"|peak load / peak of {rows[0]['peak_ref']} - 1| (%)"),
                           (axes[1], "diss_err_pct", "|dissipated / G_f (D - a) t - 1| (%)")):
        for r in rows:
            if r[key] is None:
                continue
            ax.plot(r["cpu_s"], abs(r[key]), markers.get(r["dt_fraction"], "^"),
                    color=colors[r["h_mm"]], ms=8,
                    label=f"h = {r['h_mm']:.3g} mm, {r['dt_fraction']:g} x stable")
        ax.set_xscale("log")
        ax.set_xlabel("CPU time of the run, np 1 (s)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7, loc="best")
    aborted = [f"h={r['h_mm']:.3g} mm, {r['dt_fraction']:g} dt" for r in rows if r["status"] != "ok"]
    if aborted:
        axes[0].text(0.02, 0.02, "not ok: " + "; ".join(aborted), transform=axes[0].transAxes,
                     fontsize=7, va="bottom")
    fig.suptitle(f"Notched beam (Petersson concrete, span {BEAM_S * 1e3:.0f} mm), to u = "
                 f"{BEAM_U * 1e3:.1f} mm: error vs run time (one run each)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def fmt(v, spec):
    return "" if v is None else format(v, spec)


# ---------------------------------------------------------------------------- disc output

def write_disc(out, rows):
    cols = ["h", "dt_fraction", "elements", "steps", "cpu_s", "wall_s", "peak_stress_MPa",
            "error_pct", "dissipated_J", "status", "t_peak_ms", "t_end_ms"]
    with open(os.path.join(out, "fracture_accuracy.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([f"{r['h_mm']:g}", r["dt_fraction"], r["elements"], r["steps"],
                        fmt(r["cpu_s"], ".2f"), fmt(r["wall_s"], ".2f"),
                        fmt(r["peak_stress_MPa"], ".4f"), fmt(r["error_pct"], ".2f"),
                        fmt(r["dissipated_J"], ".5f"), r["status"], fmt(r["t_peak_ms"], ".3f"),
                        fmt(r["t_end_ms"], ".3f")])

    print("\n| h (mm) | dt / stable | elements | steps | CPU (s) | 2P/(pi D t) at peak (MPa) "
          "| error vs f_t | dissipated at end (J) | peak / end (ms) | status |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['h_mm']:g} | {r['dt_fraction']} | {r['elements']} | {r['steps']} | "
              f"{fmt(r['cpu_s'], '.1f')} | {fmt(r['peak_stress_MPa'], '.3f')} | "
              f"{fmt(r['error_pct'], '+.1f')} % | {fmt(r['dissipated_J'], '.2f')} | "
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
        ax.plot(r["cpu_s"], abs(r["error_pct"]), markers.get(r["dt_fraction"], "^"),
                color=colors.get(r["h_mm"] / 1e3, "k"), ms=8)
        ax.annotate(f"h={r['h_mm']:g} mm, {r['dt_fraction']} dt", (r["cpu_s"], abs(r["error_pct"])),
                    textcoords="offset points", fontsize=7,
                    xytext=(6, 5) if r["dt_fraction"] >= 0.7 else (6, -11))
    aborted = [f"h={r['h_mm']:g} mm, {r['dt_fraction']} dt" for r in rows if r["error_pct"] is None]
    if aborted:
        ax.text(0.02, 0.02, "aborted (not shown): " + "; ".join(aborted), transform=ax.transAxes,
                fontsize=7, va="bottom")
    ax.set_xscale("log")
    ax.set_ylim(bottom=-0.5)
    ax.set_xlabel("CPU time of the run, np 1 (s)")
    ax.set_ylabel("|2P/(pi D t) at peak / f_t - 1| (%)")
    ax.set_title("Brazilian disc D = 150 mm: error vs run time\n(f_t = 3.33 MPa; all runs to 3.5 ms, shortly after the peak)",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fracture_accuracy.png"), dpi=120)
    print(f"\nwrote {os.path.join(out, 'fracture_accuracy.csv')} and fracture_accuracy.png")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    p.add_argument("--case", choices=("all", "disc", "beam"), default="all")
    p.add_argument("--beam-h", type=float, nargs="+", default=[x * 1e3 for x in BEAM_SPACINGS],
                   help="beam mesh spacings (mm); the finest at the smallest fraction is the "
                        "peak load's reference")
    p.add_argument("--jobs", type=int, default=2, help="beam runs at a time")
    p.add_argument("--table", action="store_true",
                   help="only print the beam table of docs/benchmarks.md from <out>/"
                        "fracture_accuracy_beam.csv and redraw its PNG (no runs)")
    args = p.parse_args()
    exe = os.path.abspath(args.exe)
    os.makedirs(args.out, exist_ok=True)
    beam_csv = os.path.join(args.out, "fracture_accuracy_beam.csv")
    beam_png = os.path.join(args.out, "fracture_accuracy_beam.png")
    if args.table:
        rows = read_beam_csv(beam_csv)
        beam_plot(beam_png, rows)
        print(beam_table(rows))
        return

    if args.case in ("all", "disc"):
        rows = []
        for hh in SPACINGS:
            rows += disc_case(exe, hh, DT_FRACTIONS)
        write_disc(args.out, rows)

    if args.case in ("all", "beam"):
        rows = beam_case(exe, [x / 1e3 for x in args.beam_h], DT_FRACTIONS, args.jobs)
        write_beam_csv(beam_csv, rows)
        rows = read_beam_csv(beam_csv)  # the table and the figure from the CSV, as --table does
        beam_plot(beam_png, rows)
        print("\n" + beam_table(rows))
        print(f"\nwrote {beam_csv} and {beam_png}")


if __name__ == "__main__":
    main()
