#!/usr/bin/env bash
# Makes docs/scenes.png: the paper's seven scenes (small size), four frames each from start to
# end, one held-out test simulation (test_0) per scene, colliders drawn. The runs come from the
# scenes' sweeps in data/<name>_small (made here with --only test if missing; an existing full
# sweep is reused, and one made from an older scene file is redone).
#
# Works from any checkout or worktree: paths are relative to the repository this script is in.
# It builds build/ if needed but installs nothing (scripts/install-deps.sh does that). JOBS sets
# the build jobs and the sweeps' simulations at once (default: all cores); on a shared machine
# use JOBS=1.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${JOBS:-$(nproc)}"
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build build -j"$jobs" >/dev/null
runs=()
for name in bread cake sand metal toothpaste jelly squishy_ball; do
  ./build/nsf sweep "scenes/paper/${name}_small.json" --out "data/${name}_small" --only test \
    --jobs "$jobs" --threads 1 -q
  runs+=("data/${name}_small/test_0.h5")
done
./build/nsf contact-sheet "${runs[@]}" --out docs/scenes.png --columns 4 --size 400x300
