"""Energy stress harness for breaking bodies under particle impact.

Steel balls (3D) or disks (2D) shot at a clamped concrete slab (tet4) or strip (tri3, plane
strain) that cracks (Rankine + fracture nodal), on unstructured Gmsh meshes of three sizes, over
impact speeds, `model elastic|corotational`, `contact_bodies yes|no` and 1 or 2 ranks. Each run's
energy account: at every output row, particles (kinetic + rotational) + body (kinetic + strain +
dissipated + eroded) against what was put in (the particles' initial kinetic energy + the body's
external and boundary work). The bound: never above by more than 1 %. Also recorded: the fraction
of elements at damage >= 0.5 on the last frame, splits, fragments, wall time; a picture of the
last frame's damage per case (PNG).

    python3 bench/fracture_stress.py [--exe build/fracdem] [--quick] [--only 3d|2d]
                                     [--levels 0 1 2] [--np 1 2] [--name NAME] [--out DIR]

--quick: the middle mesh, 50 m/s, both models and contact settings, 1 rank; --levels picks
mesh sizes (0 coarse .. 2 fine), --np the rank counts; default: the whole matrix (hours on 2
cores: the fine 3D slab with contact_bodies yes takes minutes a run).
Writes DIR/NAME.csv, DIR/NAME.png (excess against speed; NAME fracture_stress by default) and
DIR/fracture_stress_<case>.png (damage on the last frame).
"""
import argparse
import csv
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
from fracdem import stress  # noqa: E402

# mesh sizes (characteristic length, m) and speeds (m/s) per scene; the time step is dt_frac of
# the stable FE step the fix logs; `time` the simulated span after first contact
SCENES = {
    "3d": dict(make=stress.gmsh_slab, write=stress.slab_input, lc=(0.04, 0.025, 0.016),
               speeds=(5, 20, 50, 200), gap=0.0049, time=3e-4),
    "2d": dict(make=stress.gmsh_plate, write=stress.plate_input, lc=(0.004, 0.002, 0.001),
               speeds=(5, 20, 50, 200), gap=0.0005, time=1.5e-4),
}
DT_FRAC = 0.65
BOUND = 0.01


def one_case(exe, scene, lc, speed, model, contact, np_, outdir):
    sc = SCENES[scene]
    name = f"{scene}_h{lc:g}_v{speed:g}_{model[:5]}_cb{contact}_np{np_}"
    work = tempfile.mkdtemp(prefix="stress_")
    nel = sc["make"](os.path.join(work, "body.msh"), lc)
    probe = sc["write"]("body.msh", speed, model, contact, 1e-7, 10)
    dt = DT_FRAC * stress.stable_step(exe, work, probe)
    steps = int((sc["gap"] / speed + sc["time"]) / dt)
    every = max(1, steps // 200)
    steps = every * (steps // every)
    text = sc["write"]("body.msh", speed, model, contact, dt, steps, every)
    t0 = time.time()
    rc, out = stress.run(exe, work, text, np_)
    wall = time.time() - t0
    row = dict(case=name, scene=scene, lc=lc, elements=nel, speed=speed, model=model,
               contact_bodies=contact, np=np_, dt=dt, steps=steps, wall_s=round(wall, 2),
               warnings=out.count("WARNING"), error=int(rc != 0 or "ERROR" in out))
    try:
        acc = stress.energy_account(out, os.path.join(work, "energy.csv"))
        excess = [(now - put) / put for _, now, put in acc]
        row.update(E0=acc[0][2], max_excess=max(excess), final_ratio=acc[-1][1] / acc[-1][2],
                   worst_step=acc[excess.index(max(excess))][0])
    except (RuntimeError, OSError) as e:
        row.update(E0=0, max_excess=float("inf"), final_ratio=float("nan"), worst_step=-1)
        print(f"{name}: no energy account ({e})", file=sys.stderr)
    last = thermo_last(out)
    row.update(splits=last.get("body[17]", 0), fragments=last.get("body[18]", 0),
               damaged_fraction=float("nan"))
    vtu = os.path.join(work, "out", f"body_{steps:010d}.vtu")
    if os.path.exists(vtu):
        frac, centres, damage = stress.damage_fraction(vtu)
        row["damaged_fraction"] = frac
        picture(os.path.join(outdir, f"fracture_stress_{name}.png"), name, centres, damage,
                scene)
    row["pass"] = int(row["error"] == 0 and row["max_excess"] <= BOUND)
    print(f"{name}: {nel} elements, dt {dt:.3g}, {steps} steps, max excess "
          f"{row['max_excess']:+.4f}, final {row['final_ratio']:.3f}, splits {row['splits']:g}, "
          f"{wall:.0f} s", flush=True)
    return row


def thermo_last(out):
    header, last = None, {}
    for line in out.splitlines():
        w = line.split()
        if w and w[0] == "Step":
            header = w
        elif header and len(w) == len(header):
            try:
                last = dict(zip(header, (float(x) for x in w)))
            except ValueError:
                pass
    return last


def picture(path, title, centres, damage, scene):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    views = [(0, 1, "x", "y"), (0, 2, "x", "z")] if scene == "3d" else [(0, 1, "x", "y")]
    fig, axes = plt.subplots(1, len(views), figsize=(5 * len(views), 4), squeeze=False)
    for ax, (a, b, la, lb) in zip(axes[0], views):
        order = damage.argsort()
        sc = ax.scatter(centres[order, a], centres[order, b], c=damage[order], s=4, cmap="inferno",
                        vmin=0, vmax=1)
        ax.set_xlabel(la)
        ax.set_ylabel(lb)
        ax.set_aspect("equal")
    fig.colorbar(sc, ax=axes[0].tolist(), label="damage")
    fig.suptitle(title)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def summary_plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for scene, marker in (("3d", "o"), ("2d", "s")):
        for lc in sorted({r["lc"] for r in rows if r["scene"] == scene}):
            sel = [r for r in rows if r["scene"] == scene and r["lc"] == lc]
            ax.scatter([r["speed"] for r in sel], [100 * r["max_excess"] for r in sel],
                       marker=marker, label=f"{scene}, h {lc:g} m")
    ax.axhline(100 * BOUND, color="r", ls="--", label="bound (1 %)")
    ax.set_xscale("log")
    ax.set_xlabel("impact speed (m/s)")
    ax.set_ylabel("max over the run of (E_now - E_in) / E_in (%)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--exe", default=os.path.join(HERE, "..", "build", "fracdem"))
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--quick", action="store_true")
    p.add_argument("--only", choices=sorted(SCENES))
    p.add_argument("--levels", type=int, nargs="+", default=[0, 1, 2])
    p.add_argument("--np", type=int, nargs="+", default=[1, 2])
    p.add_argument("--name", default="fracture_stress")
    a = p.parse_args()
    exe = os.path.abspath(a.exe)
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for scene, sc in SCENES.items():
        if a.only and scene != a.only:
            continue
        sizes = sc["lc"][1:2] if a.quick else [sc["lc"][k] for k in a.levels]
        speeds = sc["speeds"][2:3] if a.quick else sc["speeds"]
        for lc in sizes:
            for speed in speeds:
                for model in ("elastic", "corotational"):
                    for contact in ("yes", "no"):
                        for np_ in ((1,) if a.quick else a.np):
                            rows.append(one_case(exe, scene, lc, speed, model, contact, np_,
                                                 a.out))
    with open(os.path.join(a.out, a.name + ".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    summary_plot(rows, os.path.join(a.out, a.name + ".png"))
    failed = [r["case"] for r in rows if not r["pass"]]
    print(f"{len(rows) - len(failed)} passed, {len(failed)} failed")
    for c in failed:
        print("over the bound or failed:", c)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
