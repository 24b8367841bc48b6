"""Fracture convergence harness: a case on unstructured Gmsh meshes at h, h/2, h/4, two time-step
fractions and the fracture variants (cracks along element boundaries, and through elements with
`min_size`), recording crack angle, branches, cracks started elsewhere, crack length against time,
dissipated energy against G_f x crack area, fragments and run time. CSV + PNG (crack paths and
measures) in bench/results; the table goes to docs/validation.md ("Convergence: Kalthoff-Winkler").

  python3 bench/fracture_convergence.py [--levels 0 1 2] [--fractions 0.5 0.25]
      [--variants edges cuts] [--fracture-args "..."] [--name fracture_convergence]

Case: the Kalthoff-Winkler edge impact (python/fracdem/kalthoff.py: geometry, material and
loading from the experiment; the experiment's crack leaves the notch tip at about 70 deg, one
crack, none from other edges). Mesh sizes: h = 2 mm, 1 mm, 0.5 mm (level 3: 0.25 mm). The time
step is a fraction of the stable FE step the fix reports for each mesh.
"""
import argparse
import csv
import math
import os
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


def run_case(exe, wd, msh, h, frac, variant, extra, elements):
    fracture = (VARIANTS[variant] + " " + extra).strip()
    dt0 = stress.stable_step(exe, wd, kalthoff.input_text(msh, 1e-8, fracture=fracture))
    dt = frac * dt0
    start = time.time()
    rc, out = stress.run(exe, wd, kalthoff.input_text(msh, dt, fracture=fracture), timeout=3600)
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
    return dict(h_mm=h * 1e3, elements=elements, dt_fraction=frac, variant=variant,
                fracture_args=fracture, dt=dt, angle_deg=m["angle"],
                angle_error_deg=m["angle"] - kalthoff.EXPERIMENT_ANGLE,
                branches=m["branches"], stray_failed=m["stray"], length_mm=m["length"] * 1e3,
                tip_speed=speed, dissipated_J=dissipated, gf_area_J=gf_area,
                dissipated_over_gf_area=dissipated / gf_area if gf_area > 0 else float("nan"),
                split_nodes=int(float(rows[-1]["split_nodes"])),
                fragments=int(float(rows[-1]["fragments"])), loop_s=kalthoff.loop_time(out),
                wall_s=wall, lengths_mm=" ".join(f"{x * 1e3:.1f}" for x in history),
                frame=frames[-1])


def picture(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cols = sorted({(r["variant"], r["dt_fraction"]) for r in rows})
    sizes = sorted({r["h_mm"] for r in rows}, reverse=True)
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
                pts = kalthoff.failed_centres(r["frame"]) * 1e3
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
                r = run_case(a.exe, wd, msh, h, frac, variant, a.fracture_args, elements)
                rows.append(r)
                print(f"h {r['h_mm']:g} mm ({elements} tri), {variant}, dt {frac}: angle "
                      f"{r['angle_deg']:.1f} deg, crossings {r['branches']}, stray "
                      f"{r['stray_failed']}, length {r['length_mm']:.1f} mm, dissipated/G_f A "
                      f"{r['dissipated_over_gf_area']:.2f}, loop {r['loop_s']:.1f} s", flush=True)
    os.makedirs(a.out, exist_ok=True)
    keys = [k for k in rows[0] if k != "frame"]
    with open(os.path.join(a.out, a.name + ".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    picture(rows, os.path.join(a.out, a.name + ".png"))
    print(f"wrote {a.out}/{a.name}.csv and .png (runs in {base})")


if __name__ == "__main__":
    main()
