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


def parse_args():
    p = argparse.ArgumentParser()
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"))
    return p.parse_args()


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
