#!/usr/bin/env bash
# Both decoder families on the scenes named, side by side: for each SCENE, the dataset
# data/SCENE (nsf sweep: what is missing), the paper's MLP fields models/SCENE_mlp.nsf and the
# per-point bases models/SCENE_basis.nsf (nsf train, unless they exist), then `nsf eval` of each
# on the held-out runs, written to docs/results/eval/SCENE_mlp.json and SCENE_basis.json. Both
# evaluate h and l at latents refined as training refined them and as the ROM's inversion finds
# them (--refine 10); the JSON also holds δ at the encoder's own latents (delta_encoded). These
# rows make the table of docs/TRAINING.md, "Decoder families". TRAIN_FLAGS go to both trainings,
# BASIS_FLAGS to the basis one (e.g. "--modes 32,64,64"). Uses build/nsf (scripts/build.sh).
#
#   scripts/decoder_table.sh metal_small sand_small jelly_small
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: [TRAIN_FLAGS=...] [BASIS_FLAGS=...] $0 SCENE..." >&2; exit 2; }
cd "$(dirname "$0")/.."
nsf=build/nsf
[ -x "$nsf" ] || { echo "$0: $nsf is missing: run scripts/build.sh first" >&2; exit 1; }
mkdir -p docs/results/eval models data
export OMP_WAIT_POLICY=passive
for scene in "$@"; do
  json=scenes/paper/$scene.json
  [ -f "$json" ] || { echo "$0: no scene $json" >&2; exit 1; }
  "$nsf" sweep "$json" --out "data/$scene" -q # resumable: runs only what is missing
  # shellcheck disable=SC2086
  [ -f "models/${scene}_mlp.nsf" ] ||
    "$nsf" train "data/$scene" --out "models/${scene}_mlp.nsf" --decoder mlp ${TRAIN_FLAGS:-}
  # shellcheck disable=SC2086
  [ -f "models/${scene}_basis.nsf" ] ||
    "$nsf" train "data/$scene" --out "models/${scene}_basis.nsf" --decoder basis \
      ${TRAIN_FLAGS:-} ${BASIS_FLAGS:-}
  for family in mlp basis; do
    model=models/${scene}_$family.nsf
    "$nsf" eval "$model" "data/$scene" --refine 10 --json "docs/results/eval/${scene}_$family.json"
  done
done
