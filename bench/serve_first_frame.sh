#!/usr/bin/env bash
# How long a newcomer to `nsf serve` waits for its first frame and for the whole basis
# (docs/BENCHMARKS.md, "The latent stream"): N clients of a server on loopback, each reading at
# most RATE bytes a second (as over a slower link; 0: no limit), with the whole basis in the model
# message (--basis-message 1e9) and with the default (the leading modes first, the rest between
# frames). Usage: bench/serve_first_frame.sh MODEL SCENE [N] [RATES] -- [nsf serve options]
#   bench/serve_first_frame.sh models/metal_small.nsf scenes/paper/metal_small.json 5 "0 2e6" -- --mu 0.1
# Needs build/nsf and build/serve_clients.
set -euo pipefail
model=$1 scene=$2 n=${3:-5} rates=${4:-0 2e6}
shift 4 || shift $#
[[ "${1:-}" == "--" ]] && shift
extra=("$@")
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for rate in $rates; do
  for bytes in 1000000000 262144; do
    port=$((20000 + RANDOM % 20000))
    build/nsf serve "$model" "$scene" --port "$port" -j 1 --frames 100000 --basis-message "$bytes" \
      -q "${extra[@]}" >"$out" 2>&1 &
    pid=$!
    for _ in $(seq 100); do grep -q "ws://" "$out" && break; sleep 0.1; done
    echo "read rate $rate B/s per client, --basis-message $bytes:"
    build/serve_clients --port "$port" --clients "$n" --seconds 8 --warmup 4 --read-rate "$rate" |
      sed 's/^/  /'
    kill "$pid"
    wait "$pid" 2>/dev/null || true
  done
done
