"""Load-balance comparison: stock slabs vs fix balance/graph (a priori / a posteriori, cost
models) in fracdem, and on the settling bed also LAMMPS (`lmp`) slabs, fix balance shift and
rcb weight neigh/time as the spatial reference. Scenes:

  settle    3D settling bed, ~5300 spheres, z-slabs (LAMMPS reference too)
  hopper    3D hopper filling: spheres inserted above a rigid fem/body cone, z-slabs
  dragline  2D dragline bucket: a rigid fem/body bucket dragged through ~900 disks, x-slabs
  settle_large  the settling bed 4 x 4 times as wide (85 536 spheres, >= 5000 per rank at 16
                ranks; LAMMPS reference too), 300 steps, check every 100 (issue #11 item 6)
  hopper_large  a hopper twice the size, pre-filled with 87 317 spheres, 300 steps, check
                every 100

  python3 bench/balance_compare.py [--scene settle] [--ranks 1 2 4 6] [--steps N] [--reps 3]

On the settling bed a control runs first at each rank count that allows it: identical copies of
the scene on equal sub-domains (work model B = 1 exactly), so that its measured B is the noise
floor that the machine adds to every measured B of the same run.

Writes, per scene, balance_<scene>_runs.csv (one row per run), balance_<scene>_summary.md (tables
in the form of the paper's Tables 1-3), balance_<scene>_rank_work.png (per-rank CPU work at the
largest rank count, Fig. 4 form) and balance_<scene>_history.png (B over the run). Wall-clock figures are meaningful only where ranks <= cores;
the work-model figures (per-rank thread CPU time measured by fix balance/graph) hold at any count.
"""
import argparse
import csv
import os
import shutil
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))

import harness  # noqa: E402
from fracdem import balance  # noqa: E402

FRACDEM_METHODS = {  # name -> variables of in.settle_fracdem
    "slabs (fracdem, measured)": dict(thresh="1e30", model="aposteriori", cost="counts"),
    "graph a priori counts": dict(thresh=1.05, model="apriori", cost="counts"),
    "graph a posteriori counts": dict(thresh=1.05, model="aposteriori", cost="counts"),
    "graph a posteriori calibrated": dict(thresh=1.05, model="aposteriori", cost="calibrated"),
    "graph a posteriori timed": dict(thresh=1.05, model="aposteriori", cost="timed"),
    "graph a posteriori fitted": dict(thresh=1.05, model="aposteriori", cost="fitted"),
    "graph a posteriori timed scotch": dict(thresh=1.05, model="aposteriori", cost="timed",
                                            partitioner="scotch"),
    "graph a posteriori counts rcb": dict(thresh=1.05, model="aposteriori", cost="counts",
                                          partitioner="rcb"),
    "graph a posteriori counts layers": dict(thresh=1.05, model="aposteriori", cost="counts",
                                             partitioner="layers"),
}
# Control (settle only): the stock grid cut into px x py sub-domains holding identical copies of
# the scene (no jitter; lattices commensurate with the grid, atoms off the cuts). The work model
# says B = 1 exactly; the measured B is what the machine adds (timer noise, cores of unequal or
# varying speed): the floor of any balancer that trusts a work model, and the yardstick for the
# measured B of the others.
NOISE_FLOOR = "equal sub-domains (noise floor)"
NOISE_FLOOR_GRIDS = {1: (1, 1), 2: (2, 1), 4: (2, 2), 6: (2, 3), 8: (2, 4), 16: (4, 4)}
LOW_SPACING, NOISE_FLOOR_HISPACE = 0.0088, 0.0264  # in.settle_fracdem's bed lattice; the cloud's


def noise_floor_vars(np_, box_edge):
    """Input variables of the control at np_ ranks, or None where no grid cuts the box into
    identical copies (both lattices must have a whole number of columns per sub-domain)."""
    grid = NOISE_FLOOR_GRIDS.get(np_)
    if grid is None:
        return None
    for spacing in (LOW_SPACING, NOISE_FLOOR_HISPACE):
        columns = box_edge / spacing
        if abs(columns - round(columns)) > 1e-6 or any(round(columns) % p for p in grid):
            return None
    return dict(thresh="1e30", model="aposteriori", cost="counts", jitter=0,
                hispace=NOISE_FLOOR_HISPACE, origin=0.5, px=grid[0], py=grid[1], pz=1)


LAMMPS_METHODS = {  # name -> balance variable of in.settle_lammps
    "LAMMPS slabs": "none",
    "LAMMPS shift": "shift",
    "LAMMPS rcb neigh": "rcb_neigh",
    "LAMMPS rcb time": "rcb_time",
}


SCENES = {  # scene -> (fracdem input, LAMMPS input or None, default steps, mesh writer)
    "settle": ("in.settle_fracdem", "in.settle_lammps", 4000, None),
    "hopper": ("in.hopper_fracdem", None, 16000, "hopper"),
    "dragline": ("in.balance_dragline", None, 8000, "bucket"),
    "settle_large": ("in.settle_fracdem", "in.settle_lammps", 300, None),
    "hopper_large": ("in.hopper_large_fracdem", None, 300, "hopper_large"),
}
# Scene-specific input variables (for LAMMPS too). The large bed: 4 x 4 times the area of the
# settling bed (L = 36 x 0.0176), 85 536 spheres, 5346 per rank at 16 ranks.
EXTRA = {"dragline": dict(every=200), "settle_large": dict(L=0.6336, every=100),
         "hopper_large": dict(every=100)}


def write_mesh(kind, wd):
    from fracdem import meshgen

    if kind == "hopper":
        X, E = meshgen.funnel_tet_mesh(0.02, 0.08, 0.1, 0.005, 36, 8, origin=(0, 0, 0.02))
        meshgen.write_gmsh22(os.path.join(wd, "hopper.msh"), X, E)
    elif kind == "hopper_large":
        X, E = meshgen.funnel_tet_mesh(0.04, 0.16, 0.2, 0.005, 72, 16, origin=(0, 0, 0.04))
        meshgen.write_gmsh22(os.path.join(wd, "hopper_large.msh"), X, E)
    elif kind == "bucket":
        harness.make_bucket_mesh(os.path.join(wd, "bucket.msh"))


def input_path(script):
    for d in (os.path.join(HERE, "inputs"), harness.INPUTS):
        if os.path.exists(os.path.join(d, script)):
            return os.path.join(d, script)
    raise FileNotFoundError(script)


def run_one(exe, script, np_, variables, mesh=None):
    wd = tempfile.mkdtemp(prefix="bench_balance_")
    shutil.copy(input_path(script), wd)
    if mesh:
        write_mesh(mesh, wd)
    text = harness.run(exe, script, np_=np_, workdir=wd, variables=variables, timeout=1800)
    stats = balance.run_stats(text)
    csv_path = os.path.join(wd, "balance.csv")
    df = balance.read_balance_csv(csv_path) if os.path.exists(csv_path) else None
    return stats, df


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 6])
    ap.add_argument("--scene", choices=sorted(SCENES), default="settle")
    ap.add_argument("--steps", type=int, default=None, help="default: per scene")
    ap.add_argument("--reps", type=int, default=3,
                    help="repetitions (medians are reported; oversubscribed rank counts too, "
                         "whose work figures hold while their wall clock does not)")
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--no-lammps", action="store_true")
    ap.add_argument("--methods", nargs="+", help="only methods whose name contains one of these")
    ap.add_argument("--skip", nargs="+", default=[],
                    help="leave out methods whose name contains one of these (e.g. scotch)")
    ap.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"),
                    help="input variable for every run, e.g. --var L 0.3168; overrides the "
                         "method's own, for every method (e.g. --var thresh 1.03 --var every 100) "
                         "except the threshold of the stock slabs")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    script, lammps_script, default_steps, mesh = SCENES[args.scene]
    steps = args.steps or default_steps
    lmp = None if (args.no_lammps or not lammps_script) else shutil.which("lmp")
    cores = os.cpu_count() or 1
    tag = f"balance_{args.scene}"

    extra = dict(EXTRA.get(args.scene, {}), **dict(args.var))
    def wanted(name):
        return ((not args.methods or any(m in name for m in args.methods))
                and not any(m in name for m in args.skip))

    methods = {k: v for k, v in FRACDEM_METHODS.items() if wanted(k)}
    lammps_methods = {k: v for k, v in LAMMPS_METHODS.items() if wanted(k)}
    want_floor = args.scene.startswith("settle") and (not args.methods or
                                             any(m in NOISE_FLOOR for m in args.methods))
    rows, rank_work, history = [], {}, {}
    for np_ in args.ranks:
        reps = args.reps
        rank_methods = dict(methods)
        floor = noise_floor_vars(np_, float(extra.get("L", 0.1584))) if want_floor else None
        if floor:
            rank_methods = {NOISE_FLOOR: floor, **rank_methods}
        elif want_floor:
            print(f"no noise-floor control at {np_} ranks (no grid of identical sub-domains)")
        for name, var in rank_methods.items():
            run_vars = dict(dict(steps=steps, balance=1, **var), **extra)
            if var.get("thresh") == "1e30":
                run_vars["thresh"] = "1e30"  # the stock slabs stay unbalanced whatever --var says
            if name == NOISE_FLOOR:
                run_vars.update(var)  # its sub-domains must stay identical whatever --var says
            loops, reps_stats, last = [], [], None
            for _ in range(reps):
                stats, df = run_one(args.exe, script, np_, run_vars, mesh)
                loops.append(stats["loop_s"])
                reps_stats.append(balance.summarize_balance(df, np_, stats["loop_s"]))
                last = (stats, df)
            stats, df = last
            # Medians over the repetitions of every scalar figure; per-rank work and the history
            # plot come from the last repetition.
            s = dict(reps_stats[-1])
            for key, value in reps_stats[-1].items():
                if isinstance(value, (int, float)):
                    s[key] = statistics.median(r[key] for r in reps_stats)
            row = dict(method=name, ranks=np_, reps=reps, loop_s=statistics.median(loops),
                       measured_B=s["measured_B"], model_B=s["model_B"], speedup=s["speedup"],
                       ghosts_ave=stats.get("nghost_ave"), ghosts_max=stats.get("nghost_max"),
                       neighs_max_over_ave=stats.get("neighs_max", 0) / max(stats.get("neighs_ave", 1), 1e-30),
                       repartitions=s["repartitions"], migrated=s["migrated"],
                       partition_share=s.get("partition_share"))
            rows.append(row)
            print(row, flush=True)
            if np_ == max(args.ranks):
                rank_work[name] = s.get("work_per_rank", [])
                history[name] = (df["step"].tolist(), df["measured_imbalance"].tolist())
        if lmp:
            for name, bal in lammps_methods.items():
                loops, last = [], None
                for _ in range(reps):
                    lvars = dict(dict(steps=steps, balance=bal), **extra)
                    stats, _ = run_one(lmp, lammps_script, np_, lvars)
                    loops.append(stats["loop_s"])
                    last = stats
                stats = last
                pair_b = stats["pair_max_s"] / stats["pair_avg_s"] if stats.get("pair_avg_s") else 1.0
                row = dict(method=name, ranks=np_, reps=reps, loop_s=statistics.median(loops),
                           measured_B=None, model_B=None, pair_time_B=pair_b,
                           ghosts_ave=stats.get("nghost_ave"), ghosts_max=stats.get("nghost_max"),
                           neighs_max_over_ave=stats.get("neighs_max", 0) / max(stats.get("neighs_ave", 1), 1e-30))
                rows.append(row)
                print(row, flush=True)

    cols = ["method", "ranks", "reps", "loop_s", "measured_B", "model_B", "pair_time_B", "speedup",
            "neighs_max_over_ave", "ghosts_ave", "ghosts_max", "repartitions", "migrated",
            "partition_share"]
    with open(os.path.join(args.out, f"{tag}_runs.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for r in rows:
            w.writerow({c: r.get(c) for c in cols})

    # Speedups relative to 1 rank of the same code, from the median loop times.
    base = {r["method"]: r["loop_s"] for r in rows if r["ranks"] == 1}
    for r in rows:
        if r["method"] in base and r["ranks"] <= cores:
            r["wall_speedup"] = base[r["method"]] / r["loop_s"]

    fmt = lambda rs, c: balance.markdown_table(rs, c)  # noqa: E731
    with open(os.path.join(args.out, f"{tag}_summary.md"), "w") as f:
        f.write(f"Scene {args.scene}, {steps} steps; machine with {cores} cores "
                f"(wall-clock speedups only where ranks <= cores).\n\n")
        f.write("Table 1: imbalance and speedup\n\n")
        f.write(fmt(rows, ["method", "ranks", "measured_B", "model_B", "pair_time_B",
                           "neighs_max_over_ave", "speedup", "wall_speedup", "loop_s"]) + "\n\n")
        f.write("Table 2: ghosts per rank\n\n")
        f.write(fmt(rows, ["method", "ranks", "ghosts_ave", "ghosts_max"]) + "\n\n")
        f.write("Table 3: repartitioning cost\n\n")
        graph_rows = [r for r in rows if r["method"].startswith("graph")]
        f.write(fmt(graph_rows, ["method", "ranks", "repartitions", "migrated", "partition_share"]) + "\n")
    if rank_work:
        balance.plot_rank_work(rank_work, out=os.path.join(args.out, f"{tag}_rank_work.png"),
                               title=f"Per-rank CPU work, {args.scene}, {max(args.ranks)} ranks")
        balance.plot_imbalance_history(history, out=os.path.join(args.out, f"{tag}_history.png"),
                                       title=f"Measured B, {args.scene}, {max(args.ranks)} ranks")
    print(open(os.path.join(args.out, f"{tag}_summary.md")).read())


if __name__ == "__main__":
    main()
