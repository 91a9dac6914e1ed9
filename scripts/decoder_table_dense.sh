#!/usr/bin/env bash
# The per-point bases trained on frames dense in time (docs/TRAINING.md, "Decoder families",
# Training frames dense in time): for SCENE and a factor F, the scene's sweep again with F times
# the frames and 1/F the substeps per frame (the same simulations, bit for bit, written F times as
# often) into data/SCENE_denseF, a basis model with the modes encoder and τ and C maps of the
# latent velocity trained on it (models/SCENE_basis_denseF.nsf, unless it exists), and `nsf eval`
# of that model on the held-out runs of the scene's own dataset data/SCENE (the frames every other
# row of the table is measured on), written to docs/results/eval/SCENE_basis_denseF.json. With
# RUNS, the dense sweep has RUNS training runs instead of the scene's (names end in _trainRUNS;
# the held-out runs are still the scene's own, in data/SCENE).
# Uses build/nsf (scripts/build.sh) and python3 (to read the scene's frames and substeps).
#
#   scripts/decoder_table_dense.sh jelly_small 4
#   scripts/decoder_table_dense.sh cake_small 5 24
set -euo pipefail
[ $# -eq 2 ] || [ $# -eq 3 ] || { echo "usage: $0 SCENE FACTOR [RUNS]" >&2; exit 2; }
cd "$(dirname "$0")/.."
scene=$1 factor=$2 runs=${3:-}
nsf=build/nsf
json=scenes/paper/$scene.json
[ -x "$nsf" ] || { echo "$0: $nsf is missing: run scripts/build.sh first" >&2; exit 1; }
[ -f "$json" ] || { echo "$0: no scene $json" >&2; exit 1; }
read -r frames substeps < <(python3 -c '
import json, sys
s = json.load(open(sys.argv[1]))["simulation"]
print(s["frames"], s["substeps"])' "$json")
if ! [[ $factor =~ ^[1-9][0-9]*$ ]] || ((substeps % factor != 0)); then
  echo "$0: FACTOR must be a whole number dividing the scene's $substeps substeps per frame" >&2
  exit 2
fi
if [ -n "$runs" ] && ! [[ $runs =~ ^[1-9][0-9]*$ ]]; then
  echo "$0: RUNS must be a whole number of training runs" >&2
  exit 2
fi
tag=${runs:+_train$runs} sweep_runs=()
[ -z "$runs" ] || sweep_runs=(--set "sweep.train=$runs")
dense=data/${scene}_dense$factor$tag model=models/${scene}_basis_dense$factor$tag.nsf
mkdir -p docs/results/eval models data
export OMP_WAIT_POLICY=passive
"$nsf" sweep "$json" --out "data/$scene" -q # the held-out runs (resumable)
"$nsf" sweep "$json" --out "$dense" --gzip 1 -q \
  --set "simulation.frames=$((frames * factor))" --set "simulation.substeps=$((substeps / factor))" \
  "${sweep_runs[@]}"
[ -f "$model" ] ||
  "$nsf" train "$dense" --out "$model" --decoder basis --encoder modes --coefficients map,map \
    --stress-input velocity --no-calibrate -j 2
"$nsf" eval "$model" "data/$scene" --refine 10 -j 2 --json "docs/results/eval/${scene}_basis_dense$factor$tag.json"
