#!/usr/bin/env bash
# Sets up fracdem and runs every test: C++ unit + integration (ctest) and Python (pytest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
status=0
(cd build && ctest --output-on-failure -j2) || status=1
PY=${PYTHON:-python3}
FRACDEM_EXE="$PWD/build/fracdem" $PY -m pytest tests/python -q || status=1
exit $status
