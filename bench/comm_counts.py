"""Exact MPI communication counts per rank and step on the settling bed (stock slabs, graph
ownership, and LAMMPS rcb where Debian's `lmp` is installed), with the PMPI counter
(build/libfracdem_mpicount.so, LD_PRELOADed). Two runs of different lengths per method; their
difference is the traffic of the steps in between, set-up excluded. Counts do not depend on the
machine, so oversubscribed rank counts are as valid as any.

    python3 bench/comm_counts.py [--exe build/fracdem] [--ranks 4 16] [--steps 400 1400]
"""
import argparse
import os
import shutil
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
import mpicount  # noqa: E402

METHODS = {  # name -> (input, variables)
    "stock slabs": ("in.settle_fracdem", dict(thresh="1e30", cost="counts", every=200)),
    "graph a posteriori counts": ("in.settle_fracdem", dict(thresh=1.05, cost="counts",
                                                             every=200)),
    "LAMMPS rcb neigh": ("in.settle_lammps", dict(balance="rcb_neigh", every=200, thresh=1.05)),
}


def measure(exe, lib, method, np_, steps, sites):
    script, variables = METHODS[method]
    wd = tempfile.mkdtemp(prefix="comm_counts_")
    shutil.copy(os.path.join(HERE, "inputs", script), wd)
    runs = []
    for n in steps:
        _, ranks = mpicount.run(exe, script, np_, wd, lib, f"s{n}", dict(variables, steps=n))
        runs.append(ranks)
    diffs = mpicount.difference(runs[1], runs[0])
    window = steps[1] - steps[0]
    if sites:
        print(f"## {method}, {np_} ranks: busiest call sites, steps {steps[0]}-{steps[1]}")
        for line in mpicount.site_lines(diffs, window, sites):
            print("   ", line)
    return mpicount.summarise(diffs, window)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    ap.add_argument("--lib", default=None, help="default: libfracdem_mpicount.so beside --exe")
    ap.add_argument("--ranks", type=int, nargs="+", default=[4, 16])
    ap.add_argument("--steps", type=int, nargs=2, default=[400, 1400])
    ap.add_argument("--methods", nargs="+", default=list(METHODS))
    ap.add_argument("--sites", type=int, default=0, help="list the N busiest call sites")
    a = ap.parse_args()
    lib = a.lib or os.path.join(os.path.dirname(os.path.abspath(a.exe)), "libfracdem_mpicount.so")
    lmp = shutil.which("lmp")
    rows = []
    for np_ in a.ranks:
        for method in a.methods:
            exe = a.exe
            if method.startswith("LAMMPS"):
                if not lmp:
                    print(f"note: {method} skipped: Debian `lmp` is not installed")
                    continue
                exe = lmp
            s = measure(exe, lib, method, np_, a.steps, a.sites)
            print(method, "|", mpicount.format_summary(s), flush=True)
            rows.append((method, np_, s))
    print("\n| run | ranks | messages / rank / step avg (max) | partners avg (max) | per-step "
          "partners avg (max) | bytes / rank / step avg (max) | collectives / step | of which "
          "project code |")
    print("|---|---|---|---|---|---|---|---|")
    for method, np_, s in rows:
        pc = ", ".join(f"{k} {v:.3f}" for k, v in sorted(s["project_coll"].items())) or "—"
        print(f"| {method} | {np_} | {s['msgs_avg']:.2f} ({s['msgs_max']:.2f}) | "
              f"{s['partners_avg']:.2f} ({s['partners_max']}) | {s['step_partners_avg']:.2f} "
              f"({s['step_partners_max']}) | {s['bytes_avg']:.0f} "
              f"({s['bytes_max']:.0f}) | {s['coll_max']:.3f} | {pc} |")


if __name__ == "__main__":
    main()
