#!/usr/bin/env bash
# Builds the ghost search as it was before issue #11 item 2 (commit b2d31a0^: cover cells half a
# cutoff wide, 125-cell stencil per owned atom) with the borders statistics of today's code
# patched in (bench/borders_before.patch), for bench/borders_cost.py --before. It swaps the
# CommGraph sources of this checkout for the old ones, builds `fracdem` incrementally in build/,
# copies it to $1 (default /tmp/fracdem_borders_before) and restores the sources and the build.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/fracdem_borders_before}
files="src/liggghts/comm_graph.h src/liggghts/comm_graph.cpp src/liggghts/comm_graph_borders.cpp src/liggghts/comm_graph_forward.cpp"
save=$(mktemp -d)
cp $files "$save"/
restore() {
  for f in $files; do cp "$save/$(basename "$f")" "$f"; done
  cmake --build build -j2 --target fracdem >/dev/null
}
trap restore EXIT
git show b2d31a0^:src/liggghts/comm_graph.h >src/liggghts/comm_graph.h
git show b2d31a0^:src/liggghts/comm_graph.cpp >src/liggghts/comm_graph.cpp
echo "// (not in the code before b2d31a0)" >src/liggghts/comm_graph_borders.cpp
echo "// (not in the code before b2d31a0)" >src/liggghts/comm_graph_forward.cpp
patch -p1 <bench/borders_before.patch
cmake --build build -j2 --target fracdem
cp build/fracdem "$out"
echo "wrote $out"
