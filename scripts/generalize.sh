#!/usr/bin/env bash
# The benchmark of unseen interactions (docs/GENERALIZE.md) over scenes: for each NAME (metal,
# sand, ...; SIZE=small by default, SIZE=paper for the paper-size scenes), makes the dataset and
# the model where they are missing (nsf sweep, nsf train: resumable, as nsf report does), then runs
# `nsf generalize` on one thread with --docs docs, which stores
# docs/results/generalize/NAME_SIZE.json and rebuilds docs/RESULTS.md. Flags after `--` go to every
# nsf generalize (a lever to measure: --latent-prior 0, --tracked, --set rom.sampling=qdeim, ...;
# then give JSON_DIR=DIR to keep the rows out of docs).
#
#   bash scripts/generalize.sh metal sand jelly
#   JSON_DIR=/tmp/g bash scripts/generalize.sh metal -- --latent-prior 0
set -euo pipefail
cd "$(dirname "$0")/.."
size="${SIZE:-small}"
names=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do names+=("$1"); shift; done
[ $# -gt 0 ] && shift
[ ${#names[@]} -gt 0 ] || { echo "usage: [SIZE=small|paper] [JSON_DIR=DIR] $0 NAME... [-- FLAGS]" >&2; exit 2; }
nsf=build/nsf
[ -x "$nsf" ] || { echo "$0: $nsf is missing: run scripts/build.sh first" >&2; exit 1; }
export OMP_WAIT_POLICY=passive
for name in "${names[@]}"; do
  scene="scenes/paper/${name}_${size}.json" data="data/${name}_${size}" model="models/${name}_${size}.nsf"
  [ -f "$scene" ] || { echo "$0: no scene $scene" >&2; exit 2; }
  "$nsf" sweep "$scene" --out "$data" -q
  [ -f "$model" ] || "$nsf" train "$data" --out "$model" -q
  if [ -n "${JSON_DIR:-}" ]; then
    mkdir -p "$JSON_DIR"
    "$nsf" generalize "$model" "$data" --scene "$scene" -j 1 --json "$JSON_DIR/${name}_${size}.json" "$@"
  else
    "$nsf" generalize "$model" "$data" --scene "$scene" -j 1 --docs docs "$@"
  fi
done
