"""Shared helpers for fracdem integration tests: run the executable under MPI, parse thermo."""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
INPUTS = os.path.join(HERE, "inputs")
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))


def parser(vtk=None):
    """The options every test takes: --exe; with vtk (the .pvd a test writes), also --vtk N."""
    p = argparse.ArgumentParser()
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    if vtk:
        p.add_argument("--vtk", type=int, default=10 ** 9,
                       help=f"write {vtk} for ParaView every N steps in the run's directory")
    return p


def parse_args(p=None):
    """The options of p (by default parser()), --exe made absolute: runs work in temporary
    directories."""
    args = (p or parser()).parse_args()
    args.exe = os.path.abspath(args.exe)
    return args


def mpirun(np_):
    cmd = ["mpirun", "-np", str(np_)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    if np_ > (os.cpu_count() or 1):
        cmd.append("--oversubscribe")
    return cmd


def run(exe, script, np_=1, workdir=None, variables=None, expect_fail=False, timeout=900):
    """Run `exe -in script` under mpirun in workdir; return combined stdout+stderr text."""
    workdir = workdir or tempfile.mkdtemp(prefix="fracdem_it_")
    cmd = mpirun(np_) + [exe, "-echo", "none", "-in", script]
    for k, v in (variables or {}).items():
        cmd += ["-var", k, str(v)]
    env = dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1")
    r = subprocess.run(cmd, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, errors="replace", timeout=timeout, env=env)
    if expect_fail:
        if r.returncode == 0 and "ERROR" not in r.stdout:
            raise AssertionError(f"expected failure, got success:\n{r.stdout[-3000:]}")
    elif r.returncode != 0 or "ERROR" in r.stdout:
        raise AssertionError(f"{' '.join(cmd)} failed (rc={r.returncode}) in {workdir}:\n{r.stdout[-5000:]}")
    return r.stdout


def thermo_blocks(text):
    """List of runs; each run is (header list, list of rows of floats)."""
    runs, header, rows = [], None, []
    for line in text.splitlines():
        w = line.split()
        if w and w[0] == "Step":
            header, rows = w, []
            continue
        if header is not None:
            if line.startswith("Loop time"):
                runs.append((header, rows))
                header = None
                continue
            try:
                vals = [float(x) for x in w]
            except ValueError:
                continue
            if len(vals) == len(header):
                rows.append(vals)
    if header is not None:
        runs.append((header, rows))
    return runs


def column(runs, name, run_index=-1):
    header, rows = runs[run_index]
    k = header.index(name)
    return [r[k] for r in rows]


def worst_scaled(a, b, scale_of=lambda name: name):
    """Largest difference of two runs' columns (dicts name -> values), each scaled by the largest
    magnitude of a column of `a` (its own, or the one scale_of(name) names); returns
    (difference, column name)."""
    worst, where = 0.0, ""
    for name in a:
        scale = max(max(abs(x) for x in a[scale_of(name)]), 1e-300)
        for x, y in zip(a[name], b[name]):
            if abs(x - y) / scale > worst:
                worst, where = abs(x - y) / scale, name
    return worst, where


def rel_diff(a, b):
    return abs(a - b) / max(abs(a), abs(b), 1e-300)


def check(cond, msg):
    if not cond:
        print("FAIL:", msg)
        sys.exit(1)
    print("ok:", msg)


def copy_inputs(names, dest):
    for n in names:
        shutil.copy(os.path.join(INPUTS, n), dest)


def make_box_mesh(path, n, l, origin=(0.0, 0.0, 0.0)):
    sys.path.insert(0, os.path.join(ROOT, "python"))
    from fracdem import meshgen

    X, E, G = meshgen.box_tet_mesh(*n, *l, origin=origin)
    meshgen.write_gmsh22(path, X, E, G)
    return X, E


def make_rect_mesh(path, n, l, origin=(0.0, 0.0), element="tri3"):
    sys.path.insert(0, os.path.join(ROOT, "python"))
    from fracdem import meshgen

    X, E, G = meshgen.rect_mesh(*n, *l, origin=origin, element=element)
    meshgen.write_gmsh22(path, X, E, G)
    return X, E


def make_bucket_mesh(path, origin=(-0.14, 0.002)):
    """The 2D dragline bucket of in.balance_dragline (tri3 U section, open towards +x)."""
    sys.path.insert(0, os.path.join(ROOT, "python"))
    from fracdem import meshgen

    X, E = meshgen.bucket_2d(0.12, 0.07, 0.01, 0.005, origin=origin)
    meshgen.write_gmsh22(path, X, E)
    return X, E


def read_csv(path):
    import csv

    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def stable_dt(text):
    m = re.search(r"stable FE time step ([0-9.eE+-]+)", text)
    return float(m.group(1)) if m else None


def run_at_stable_fraction(exe, script, wd, variables, fraction, duration, rows, np_=1):
    """Probe the stable FE step of `script` in wd (a run of 0 steps), then run it at `fraction`
    of that step for `duration` seconds with about `rows` energy-file rows (variables dt, steps,
    every); returns dt0, dt, steps, wall (s) and the energy file (energy.csv)."""
    import math
    import time

    dt0 = stable_dt(run(exe, script, workdir=wd, variables=dict(variables, dt=1e-12, steps=0, every=1)))
    dt = fraction * dt0
    steps = int(math.ceil(duration / dt))
    every = max(1, steps // rows)
    t0 = time.time()
    run(exe, script, np_=np_, workdir=wd, variables=dict(variables, dt=dt, steps=steps, every=every))
    return dict(dt0=dt0, dt=dt, steps=steps, wall=time.time() - t0,
                energy=read_csv(os.path.join(wd, "energy.csv")))


SPLIT_RE = re.compile(r"step (\d+): crack at node (\d+) -> new node (\d+), (normal)?")


def node_splits(wd, separations=True):
    """The node splits that log.liggghts in wd records, as (step, node, new node); separations
    (a node whose pieces touched only at it, logged without a normal) only if asked for."""
    with open(os.path.join(wd, "log.liggghts")) as f:
        return [(int(m.group(1)), int(m.group(2)), int(m.group(3))) for m in SPLIT_RE.finditer(f.read())
                if separations or m.group(4)]


def split_positions(splits, X):
    """Mesh position (a row of X) of the node of each split (step, node, new node); a split copy
    sits where its parent was split."""
    import numpy as np

    parent, pos = {}, []
    for _, old, new in splits:
        parent[new] = old
        node = old
        while node >= len(X):
            node = parent[node]
        pos.append(X[node])
    return np.array(pos).reshape(-1, len(X[0]))


def energy_balance(e):
    """Worst |kinetic + strain + dissipated + eroded - boundary work| over the rows of energy
    file e, scaled by the largest boundary work."""
    import numpy as np

    lhs = (np.array(e["kinetic"]) + np.array(e["strain"]) + np.array(e["fracture_energy"])
           + np.array(e["eroded_energy"]))
    work = np.array(e["boundary_work"])
    return float(np.max(np.abs(lhs - work)) / np.max(np.abs(work)))


def worst_energy_by_step(a, b):
    """Worst difference of two energy files (read_csv dicts) over the columns, each relative to
    its scale (largest |value| in a), and its column; b may start later (a continued run): rows
    matched by step. inf where b lacks a step or a column."""
    import numpy as _np  # only the tests that compare energy files need it

    worst, name = 0.0, ""
    rows = [a["step"].index(s) for s in b["step"] if s in a["step"]]
    if len(rows) != len(b["step"]) or not rows:
        return float("inf"), "step"
    for col in a:
        ra, rb = _np.array(a[col], float)[rows], _np.array(b.get(col, []), float)
        if ra.shape != rb.shape:
            return float("inf"), col
        w = float(_np.max(_np.abs(ra - rb))) / max(_np.max(_np.abs(ra)), 1e-300)
        if w > worst:
            worst, name = w, col
    return worst, name


def thermo_text_rows(text, block=-1):
    """The text lines of one thermo block (default: the last run's), keyed by their step."""
    blocks, rows = [], None
    for line in text.splitlines():
        w = line.split()
        if w and w[0] == "Step":
            rows = {}
            blocks.append(rows)
        elif rows is not None and line.startswith("Loop time"):
            rows = None
        elif rows is not None and w and w[0].isdigit():
            rows[int(w[0])] = line
    return blocks[block] if blocks else {}


def energy_text_rows(path):
    """The text lines of an energy file's rows, keyed by their step (the header left out)."""
    with open(path) as f:
        lines = f.read().splitlines()
    return {int(ln.split(",")[0]): ln for ln in lines[1:] if ln}


def same_text_rows(ref, got, first):
    """(number of rows compared, the first step whose row differs or None): the rows of got
    from step `first` on against ref's of the same step, as text (byte for byte); a step of got
    that ref lacks differs."""
    steps = sorted(s for s in got if s >= first)
    for s in steps:
        if ref.get(s) != got[s]:
            return len(steps), s
    return len(steps), None


def check_rows_as_uninterrupted(label, first, ref_out, got_out, ref_energy=None, got_energy=None):
    """Checks that a continued run's thermo rows (got_out's last block) and, where given, its
    energy-file rows (path got_energy) from step `first` on are the uninterrupted run's (ref_out,
    ref_energy) byte for byte; the first differing row is shown."""
    pairs = [("thermo", thermo_text_rows(ref_out), thermo_text_rows(got_out))]
    if ref_energy:
        pairs.append(("energy file", energy_text_rows(ref_energy), energy_text_rows(got_energy)))
    for what, ref_rows, got_rows in pairs:
        n, differs = same_text_rows(ref_rows, got_rows, first)
        check(n > 1 and differs is None,
              f"{label}: {n} {what} rows from step {first} on as the uninterrupted run's, byte "
              f"for byte" + ("" if differs is None else f" (step {differs} differs:\n  "
                                                         f"{ref_rows.get(differs)}\n  "
                                                         f"{got_rows[differs]})"))
