#!/usr/bin/env bash
# Makes docs/scenes.png: the paper's seven scenes (small size), four frames each from start to
# end, one held-out test simulation (test_0) per scene. The runs come from the scenes' sweeps in
# data/<name>_small (made here with --only test if missing; an existing full sweep is reused).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
runs=()
for name in bread cake sand metal toothpaste jelly squishy_ball; do
  ./build/nsf sweep "scenes/paper/${name}_small.json" --out "data/${name}_small" --only test -q
  runs+=("data/${name}_small/test_0.h5")
done
./build/nsf contact-sheet "${runs[@]}" --out docs/scenes.png --columns 4 --size 400x300
