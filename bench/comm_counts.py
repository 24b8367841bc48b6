"""Exact MPI communication counts per rank and step on the settling bed (stock slabs, graph
ownership with the METIS, the compact `rcb` and the brick-wall `layers` partitioner, and LAMMPS
rcb where Debian's `lmp` is installed), with the PMPI counter (build/libfracdem_mpicount.so,
LD_PRELOADed). Two runs of different lengths per method (tests/support/counted_runs.py, shared
with tests/integration/test_comm_counts.py); their difference is the traffic of the steps in
between, set-up excluded. Counts do not depend on the machine, so oversubscribed rank counts are
as valid as any.
Beside the counts, the balance of the same runs: B of the cost model (`cost counts`, so exact
too) at the checks in the window, from fix balance/graph's CSV; for LAMMPS the max/avg of
per-rank neighbour pairs at the end (what `fix balance rcb weight neigh` balances).

    python3 bench/comm_counts.py [--exe build/fracdem] [--ranks 4 8 16] [--steps 400 1400]
        [--scene settle|settle_large|hopper_large] [--var NAME VALUE]
        [--csv bench/results/comm_counts.csv [--append]] [--png bench/results/comm_counts.png]

The large scenes (issue #11 item 6) are those of bench/balance_compare.py: the settling bed 4 x 4
times as wide (85 536 spheres) and the pre-filled large hopper (no LAMMPS reference: LAMMPS has
no FE body).
"""
import argparse
import csv
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
sys.path.insert(0, os.path.join(ROOT, "python"))
import counted_runs  # noqa: E402
import mpicount  # noqa: E402

METHODS = {  # name -> variables of the scene's fracdem input (LAMMPS: of its LAMMPS input)
    "stock slabs": dict(thresh="1e30", cost="counts", every=200),
    "graph a posteriori counts": dict(thresh=1.05, cost="counts", every=200),
    "graph a posteriori counts rcb": dict(thresh=1.05, cost="counts", every=200, partitioner="rcb"),
    "graph a posteriori counts rcb, diffusion": dict(thresh=1.05, cost="counts", every=200,
                                                     partitioner="rcb repartition refine"),
    "graph a posteriori counts layers": dict(thresh=1.05, cost="counts", every=200,
                                             partitioner="layers"),
    "LAMMPS rcb neigh": dict(balance=counted_runs.LAMMPS_RCB, every=200, thresh=1.05),
}
SCENES = {  # scene -> (fracdem input, LAMMPS input or None, scene variables, mesh writer)
    "settle": ("in.settle_fracdem", "in.settle_lammps", {}, None),
    "settle_large": ("in.settle_fracdem", "in.settle_lammps", dict(L=0.6336), None),
    "hopper_large": ("in.hopper_large_fracdem", None, {}, "hopper_large"),
}
DEFAULT_METHODS = ["stock slabs", "graph a posteriori counts", "graph a posteriori counts rcb",
                   "LAMMPS rcb neigh"]


def balance_figures(wd, first_step):
    """B of the cost model at the checks after first_step (fix balance/graph's CSV of the last
    run): step-weighted mean and maximum; and the predicted B of the last repartition."""
    path = os.path.join(wd, "balance.csv")
    if not os.path.exists(path):
        return {}
    rows = list(csv.DictReader(open(path)))
    window = [r for r in rows if int(r["step"]) > first_step]
    if not window:
        return {}
    steps, prev, num = 0, first_step, 0.0
    for r in window:
        dt = int(r["step"]) - prev
        num += dt * float(r["imbalance"])
        steps += dt
        prev = int(r["step"])
    return {"model_B": num / max(steps, 1), "model_B_max": max(float(r["imbalance"])
                                                               for r in window),
            "repartitions": sum(int(r["repartitioned"]) for r in window)}


def measure(exe, lib, method, np_, steps, sites, scene="settle", extra=None):
    fracdem_in, lammps_in, scene_vars, mesh = SCENES[scene]
    script = lammps_in if method.startswith("LAMMPS") else fracdem_in
    variables = dict(METHODS[method], **scene_vars, **(extra or {}))
    if METHODS[method].get("thresh") == "1e30":
        variables["thresh"] = "1e30"  # the stock slabs stay unbalanced whatever --var says
    wd = tempfile.mkdtemp(prefix="comm_counts_")
    if mesh:
        import balance_compare  # noqa: E402

        balance_compare.write_mesh(mesh, wd)
    w = counted_runs.window(exe, lib, os.path.join(HERE, "inputs", script), np_, steps, variables,
                            wd)
    window = steps[1] - steps[0]
    if sites:
        print(f"## {method}, {np_} ranks: busiest call sites, steps {steps[0]}-{steps[1]}")
        for line in mpicount.site_lines(w.diffs, window, sites):
            print("   ", line)
    s = dict(w.summary)
    s.update(balance_figures(wd, steps[0]))
    if method.startswith("LAMMPS"):
        from fracdem import balance  # noqa: E402

        st = balance.run_stats(w.texts[-1])
        if st.get("neighs_ave"):
            s["neigh_B"] = st["neighs_max"] / st["neighs_ave"]
    return s


def merge_rows(path, rows):
    """The rows of an earlier CSV (numbers as floats, empty cells left out) whose (method, ranks)
    was not measured now, then the new rows, per rank count."""
    new = {(m, n) for m, n, _ in rows}
    old = []
    for r in csv.DictReader(open(path)):
        key = (r["method"], int(r["ranks"]))
        if key in new:
            continue
        s = {k: float(v) for k, v in r.items() if k not in ("method", "ranks") and v != ""}
        s["project_coll"] = {}
        old.append((key[0], key[1], s))
    merged = old + rows
    merged.sort(key=lambda t: t[1])  # stable: per rank count the earlier rows, then the new
    return merged


def plot(rows, path, suptitle):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    methods = list(dict.fromkeys(m for m, _, _ in rows))
    ranks = sorted({n for _, n, _ in rows})
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    width = 0.8 / max(len(methods), 1)
    panels = [("step_partners", "forward-comm partners / rank (avg, bar = max)"),
              ("msgs", "messages / rank / step (avg, bar = max)"),
              ("B", "B of the cost model (mean over checks; LAMMPS: neighbour pairs)")]
    for ax, (key, title) in zip(axes, panels):
        for k, m in enumerate(methods):
            xs, ys, tops = [], [], []
            for i, n in enumerate(ranks):
                s = next((s for mm, nn, s in rows if mm == m and nn == n), None)
                if s is None:
                    continue
                if key == "step_partners":
                    y, top = s["step_partners_avg"], s["step_partners_max"]
                elif key == "msgs":
                    y, top = s["msgs_avg"], s["msgs_max"]
                else:
                    y = s.get("model_B", s.get("neigh_B"))
                    top = s.get("model_B_max", y)
                    if y is None:
                        continue
                xs.append(i + k * width)
                ys.append(y)
                tops.append(top - y)
            ax.bar(xs, ys, width, yerr=[[0] * len(tops), tops], capsize=2, label=m)
        ax.set_xticks([i + 0.4 - width / 2 for i in range(len(ranks))])
        ax.set_xticklabels([str(n) for n in ranks])
        ax.set_xlabel("ranks")
        ax.set_title(title, fontsize=9)
        if key == "B":
            ax.set_ylim(1.0, None)
    axes[0].legend(fontsize=7)
    fig.suptitle(suptitle)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    ap.add_argument("--lib", default=None, help="default: libfracdem_mpicount.so beside --exe")
    ap.add_argument("--ranks", type=int, nargs="+", default=[4, 8, 16])
    ap.add_argument("--steps", type=int, nargs=2, default=[400, 1400])
    ap.add_argument("--methods", nargs="+", default=DEFAULT_METHODS, choices=list(METHODS))
    ap.add_argument("--sites", type=int, default=0, help="list the N busiest call sites")
    ap.add_argument("--scene", choices=sorted(SCENES), default="settle")
    ap.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"),
                    help="input variable for every run (e.g. --var every 100), over the method's")
    ap.add_argument("--csv", help="write one row per method and rank count here")
    ap.add_argument("--png", help="plot partners, messages and B here")
    ap.add_argument("--append", action="store_true",
                    help="keep the rows of --csv for other (method, ranks) and plot them all")
    a = ap.parse_args()
    exe_path = os.path.abspath(a.exe)
    lib = a.lib or os.path.join(os.path.dirname(exe_path), "libfracdem_mpicount.so")
    lmp = counted_runs.lmp()
    rows = []
    for np_ in a.ranks:
        for method in a.methods:
            exe = exe_path
            if method.startswith("LAMMPS"):
                if not SCENES[a.scene][1]:
                    print(f"note: {method} skipped: no LAMMPS input for scene {a.scene}")
                    continue
                if not lmp:
                    print(f"note: {method} skipped: Debian `lmp` is not installed")
                    continue
                exe = lmp
            s = measure(exe, lib, method, np_, a.steps, a.sites, a.scene, dict(a.var))
            print(method, "|", mpicount.format_summary(s), "| model B",
                  f"{s.get('model_B', float('nan')):.4f}", flush=True)
            rows.append((method, np_, s))
    print("\n| run | ranks | messages / rank / step avg (max) | partners avg (max) | per-step "
          "partners avg (max) | bytes / rank / step avg (max) | B mean (max) | collectives / "
          "step | of which project code |")
    print("|---|---|---|---|---|---|---|---|---|")
    for method, np_, s in rows:
        pc = ", ".join(f"{k} {v:.3f}" for k, v in sorted(s["project_coll"].items())) or "—"
        if "model_B" in s:
            b = f"{s['model_B']:.3f} ({s['model_B_max']:.3f})"
        elif "neigh_B" in s:
            b = f"neighs {s['neigh_B']:.3f}"
        else:
            b = "—"
        print(f"| {method} | {np_} | {s['msgs_avg']:.2f} ({s['msgs_max']:.2f}) | "
              f"{s['partners_avg']:.2f} ({s['partners_max']}) | {s['step_partners_avg']:.2f} "
              f"({s['step_partners_max']}) | {s['bytes_avg']:.0f} "
              f"({s['bytes_max']:.0f}) | {b} | {s['coll_max']:.3f} | {pc} |")
    if a.append and a.csv and os.path.exists(a.csv):
        rows = merge_rows(a.csv, rows)
    if a.csv:
        cols = ["method", "ranks", "msgs_avg", "msgs_max", "partners_avg", "partners_max",
                "step_partners_avg", "step_partners_max", "bytes_avg", "bytes_max",
                "dest_rate_max", "coll_max", "recv_wait_avg", "model_B", "model_B_max",
                "repartitions", "neigh_B"]
        with open(a.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(cols)
            for method, np_, s in rows:
                w.writerow([method, np_] + [s.get(c, "") if not isinstance(s.get(c), float)
                                            else f"{s[c]:.6g}" for c in cols[2:]])
    if a.png and rows:
        titles = {"settle": "Settling bed (5346 spheres)",
                  "settle_large": "Large settling bed (85 536 spheres)",
                  "hopper_large": "Large hopper (rigid fem/body, 87 317 spheres)"}
        plot(rows, a.png, f"{titles[a.scene]}: exact MPI counts, steps {a.steps[0]}-{a.steps[1]}")


if __name__ == "__main__":
    main()
