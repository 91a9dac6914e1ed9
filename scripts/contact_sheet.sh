#!/usr/bin/env bash
# Makes docs/scenes.png: the paper's seven scenes (small size, each at the μ in its file),
# simulated by the full-order engine, four frames each from start to end.
# Usage: bash scripts/contact_sheet.sh [extra nsf simulate args]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
out=out/contact_sheet
mkdir -p "$out"
runs=()
for name in bread cake sand metal toothpaste jelly squishy_ball; do
  scene="scenes/paper/${name}_small.json"
  if [ ! -f "$out/$name.h5" ]; then
    ./build/nsf simulate "$scene" --out "$out/$name.h5" -q "$@" >/dev/null
  fi
  echo "contact sheet: $name done"
  runs+=("$out/$name.h5")
done
./build/nsf contact-sheet "${runs[@]}" --out docs/scenes.png --columns 4 --size 400x300
