#!/usr/bin/env bash
# Runs the reduced-order model MODEL at the μ of every training run of the dataset DATA and writes
# each output under the training run's file name into OUT: the directory that
#   nsf train DATA -o NEW.nsf --base-model MODEL --rom-latents OUT
# reads (docs/experiments/2026-11-25-rom-latents.md). Each ROM run is compared with its
# training run (--truth), and its δ is printed as it finishes; its full output is OUT/<run>.log.
# JOBS runs at a time (default 2), one thread each. Uses build/nsf of this checkout (build it
# first: scripts/build.sh).
#
#   scripts/rom_latents.sh models/sand_small.nsf scenes/paper/sand_small.json data/sand_small \
#       rom_latents
set -euo pipefail
if [ $# -ne 4 ]; then
  echo "usage: $0 MODEL SCENE DATA OUT" >&2
  exit 2
fi
model=$1 scene=$2 data=$3 out=$4
nsf="$(cd "$(dirname "$0")/.." && pwd)/build/nsf"
jobs="${JOBS:-2}"
[ -x "$nsf" ] || { echo "$0: $nsf is missing: run scripts/build.sh first" >&2; exit 1; }
[ -f "$data/manifest.json" ] || { echo "$0: $data/manifest.json is missing" >&2; exit 1; }
mkdir -p "$out"

# One line per training run: file name and μ ("-" for a dataset without μ).
runs=$(python3 "$(dirname "$0")/manifest_runs.py" "$data/manifest.json" train)
total=$(echo "$runs" | wc -l)
echo "$0: $total ROM runs of $model into $out, $jobs at a time"

run_one() {
  local file=$1 mu=$2 mu_flag=()
  [ "$mu" = "-" ] || mu_flag=(--mu "$mu")
  if "$nsf" rom "$model" "$scene" "${mu_flag[@]}" --truth "$data/$file" --no-full-order -j 1 \
    --out "$out/$file" >"$out/$file.log" 2>&1; then
    echo "  $file (mu $mu): $(grep -h 'delta (eq. 11)' "$out/$file.log" | sed 's/.*: //')"
  else
    echo "  $file (mu $mu) FAILED: $(tail -n 1 "$out/$file.log") ($out/$file.log)" >&2
    return 1
  fi
}
export -f run_one
export nsf model scene data out
echo "$runs" | xargs -P "$jobs" -L 1 bash -c 'run_one "$0" "$1"'
