"""Cost of the ghost search (`borders`) under graph ownership: thread CPU per owned atom and call,
MPI excluded, from a build's opt-in statistics (environment FRACDEM_BORDERS_STATS; the PMPI
counter libfracdem_mpicount.so is preloaded so that its thread CPU inside MPI is subtracted).
Compares two builds (e.g. the code before and after a change) on the same scene, alternating
them within each repetition so that both see the same load on a shared machine.

    python3 bench/borders_cost.py --exe build/fracdem --before /tmp/fracdem_old \
        [--scene settle_large] [--ranks 2 4] [--steps 300] [--reps 3] [--csv out.csv]

Both builds must print the statistics (the older one with the same instrumentation patched in,
see docs/balance_comparison.md, "Ghost search cost").
"""
import argparse
import csv
import os
import re
import shutil
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
sys.path.insert(0, HERE)
import comm_counts  # noqa: E402
import mpicount  # noqa: E402

LINE = re.compile(r"fracdem borders stats rank (\d+): calls (\d+) owned_atom_calls (\S+) "
                  r"cpu_s (\S+) mpi_cpu_s (\S+)")


def borders_cost(exe, lib, scene, np_, steps, variables):
    """(us per owned atom and call, MPI excluded, over all ranks; the same for the slowest rank;
    borders calls per rank)."""
    fracdem_in, _, scene_vars, mesh = comm_counts.SCENES[scene]
    wd = tempfile.mkdtemp(prefix="borders_cost_")
    shutil.copy(os.path.join(HERE, "inputs", fracdem_in), wd)
    if mesh:
        import balance_compare  # noqa: E402

        balance_compare.write_mesh(mesh, wd)
    os.environ["FRACDEM_BORDERS_STATS"] = "1"
    text, _ = mpicount.run(exe, fracdem_in, np_, wd, lib, "b", dict(scene_vars, steps=steps,
                                                                      **variables))
    rows = [tuple(float(v) for v in m.groups()) for m in LINE.finditer(text)]
    if len(rows) != np_:
        raise RuntimeError(f"{exe}: expected {np_} borders statistics lines, got {len(rows)}")
    owned = sum(r[2] for r in rows)
    cpu = sum(r[3] - r[4] for r in rows)
    worst = max(1e6 * (r[3] - r[4]) / max(r[2], 1) for r in rows)
    return 1e6 * cpu / owned, worst, rows[0][1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    ap.add_argument("--before", required=True, help="the build to compare against")
    ap.add_argument("--lib", default=None, help="default: libfracdem_mpicount.so beside --exe")
    ap.add_argument("--scene", choices=sorted(comm_counts.SCENES), default="settle_large")
    ap.add_argument("--ranks", type=int, nargs="+", default=[2, 4])
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"))
    ap.add_argument("--csv")
    a = ap.parse_args()
    exe = os.path.abspath(a.exe)
    lib = a.lib or os.path.join(os.path.dirname(exe), "libfracdem_mpicount.so")
    variables = dict(dict(thresh=1.05, cost="counts", every=100), **dict(a.var))
    out = []
    for np_ in a.ranks:
        got = {"before": [], "now": []}
        for _ in range(a.reps):
            for label, path in (("before", os.path.abspath(a.before)), ("now", exe)):
                got[label].append(borders_cost(path, lib, a.scene, np_, a.steps, variables))
        med = {k: statistics.median(v[0] for v in got[k]) for k in got}
        row = dict(scene=a.scene, ranks=np_, steps=a.steps, reps=a.reps,
                   calls=got["now"][0][2], before_us=med["before"], now_us=med["now"],
                   before_us_all=" ".join(f"{v[0]:.3f}" for v in got["before"]),
                   now_us_all=" ".join(f"{v[0]:.3f}" for v in got["now"]),
                   ratio=med["before"] / med["now"])
        out.append(row)
        print(row, flush=True)
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(out[0]))
            w.writeheader()
            w.writerows(out)


if __name__ == "__main__":
    main()
