#!/usr/bin/env bash
# Installs everything fracdem needs on Debian bookworm (idempotent) and builds it into build/.
# Debian's LAMMPS (`lammps`: `lmp`) is the spatial-balancer reference of the balance benchmark and
# of tests/integration/test_comm_counts.py (messages and partners at most LAMMPS rcb's), so it is
# in the default set: 14 MB to download, 69 MiB installed (docs/balance_comparison.md). `--bench`
# is still accepted and installs nothing more.
set -euo pipefail
cd "$(dirname "$0")/.."

DEBS=(liggghts libliggghts-dev openmpi-bin libopenmpi-dev libmetis-dev libscotch-dev libptscotch-dev
      libtrilinos-zoltan-dev libvtk9-dev libgtest-dev cmake g++ make python3-vtk9 lammps)
missing=()
for p in "${DEBS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup] installing Debian packages: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  # --no-install-recommends: liggghts recommends paraview, which conflicts with libvtk9-dev.
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

PY=${PYTHON:-python3}
if ! $PY -c "import fracdem, numpy, pandas, matplotlib, pytest, vtk, gmsh" 2>/dev/null; then
  echo "[setup] installing the fracdem Python package and its dependencies"
  $PY -m pip install -q --disable-pip-version-check -e "python[vtk,mesh]" pytest
fi

echo "[setup] building (build/)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
echo "[setup] done: build/fracdem"
bash scripts/setup_lammps.sh # LAMMPS host (preview): .venv-lammps + build-lammps/fracdemplugin.so
