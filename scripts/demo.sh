#!/usr/bin/env bash
# The main job: sets up (packages, build), runs a full-order scene and writes its picture.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
# Threads sleep rather than spin at barriers: much faster when the machine is shared
# (docs/BENCHMARKS.md, "OpenMP and a shared machine"), as fast when it is not.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
mkdir -p out
./build/nsf simulate scenes/examples/sand_column.json --out out/sand_column.h5 \
  --png out/sand_column.png "$@"
echo "demo: picture in out/sand_column.png, all frames in out/sand_column.h5 (docs/OUTPUT.md)"
