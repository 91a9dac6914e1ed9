#!/usr/bin/env bash
# Runs the reduced-order model MODEL at the μ of every test run of the dataset DATA, each against
# that run as its ground truth, and prints δ (eq. 11) and how far the latent strayed from the
# training runs' latents; the flags after `--` go to every `nsf rom` (an option to measure). Extra
# ground truths (a run beyond the training range, say) come as FILE:MU in EXTRA. JOBS runs at a
# time (default 2), one thread each; each run's whole output is in OUT (default a temporary
# directory). Uses build/nsf of this checkout (build it first: scripts/build.sh). The tables of
# docs/experiments/2026-11-25-latent-prior.md were made this way:
#
#   EXTRA=data/sand_paper44.h5:44 scripts/rom_test_runs.sh models/sand_paper.nsf \
#       scenes/paper/sand_paper.json data/sand_paper -- --quadrature 1 --latent-prior 0.001
set -euo pipefail
if [ $# -lt 3 ] || { [ $# -gt 3 ] && [ "$4" != "--" ]; }; then
  echo "usage: [EXTRA='FILE:MU ...'] [JOBS=N] [OUT=DIR] $0 MODEL SCENE DATA [-- NSF_ROM_FLAGS...]" >&2
  exit 2
fi
model=$1 scene=$2 data=$3
shift 3
[ $# -gt 0 ] && shift
nsf="$(cd "$(dirname "$0")/.." && pwd)/build/nsf"
jobs="${JOBS:-2}"
out="${OUT:-$(mktemp -d)}"
[ -x "$nsf" ] || { echo "$0: $nsf is missing: run scripts/build.sh first" >&2; exit 1; }
[ -f "$data/manifest.json" ] || { echo "$0: $data/manifest.json is missing" >&2; exit 1; }
mkdir -p "$out"

# One line per run: truth file and μ.
runs=$(python3 "$(dirname "$0")/manifest_runs.py" "$data/manifest.json" test |
  while read -r file mu; do echo "$data/$file $mu"; done)
for extra in ${EXTRA:-}; do runs+=$'\n'"${extra%:*} ${extra##*:}"; done
echo "$0: $(echo "$runs" | wc -l) ROM runs of $model ($*), $jobs at a time; logs in $out"

run_one() {
  local truth=$1 mu=$2 mu_flag=() flags=() log
  eval "flags=($rom_flags)"
  log="$out/$(basename "$truth" .h5)_rom.log"
  [ "$mu" = "-" ] || mu_flag=(--mu "$mu")
  if "$nsf" rom "$model" "$scene" "${mu_flag[@]}" --truth "$truth" --no-full-order -j 1 "${flags[@]}" \
    >"$log" 2>&1; then
    echo "  $truth (mu $mu): delta $(grep -h 'delta (eq. 11)' "$log" | sed 's/.*: //');" \
      "$(grep -h '  latent: ' "$log" | sed 's/^ *latent: //')"
  else
    echo "  $truth (mu $mu) FAILED: $(tail -n 1 "$log") ($log)"
    return 1
  fi
}
export -f run_one
rom_flags="$(printf '%q ' "$@")"
export nsf model scene out rom_flags
echo "$runs" | xargs -P "$jobs" -L 1 bash -c 'run_one "$0" "$1"'
