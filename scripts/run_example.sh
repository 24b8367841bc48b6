#!/usr/bin/env bash
# Sets up fracdem and runs the flagship example (spheres raining on an elastic slab) at 2 MPI ranks.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd examples/block_impact
mpirun -np "${NP:-2}" ../../build/fracdem -in in.block_impact
echo "Output: examples/block_impact/out/ — open body.pvd and particles_*.vtk in ParaView."
