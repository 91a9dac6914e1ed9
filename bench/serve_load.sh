#!/usr/bin/env bash
# The latent stream under load (docs/BENCHMARKS.md, "The latent stream"): `nsf serve` on loopback
# at real time, first alone, then with N clients for S seconds (bench/serve_clients.cpp: frames
# lost, latency step -> client), then as fast as it steps, alone and with the N clients.
# Usage: bench/serve_load.sh MODEL SCENE [N] [S] -- [nsf serve options, e.g. --mu 0.1]
# Needs build/nsf and build/serve_clients.
set -euo pipefail
model=$1 scene=$2 n=${3:-50} s=${4:-30}
shift 4 || shift $#
[[ "${1:-}" == "--" ]] && shift
extra=("$@")
port=$((20000 + RANDOM % 20000))
nsf=build/nsf
frame_time=$(python3 -c "import json,sys; j=json.load(open(sys.argv[1]))['simulation']; print(j['dt']*j['substeps'])" "$scene")
frames=$(python3 -c "print(int(($s + 3) / $frame_time))")

serve() {  # serve LABEL FPS FRAMES CLIENTS
  local label=$1 fps=$2 count=$3 clients=$4
  "$nsf" serve "$model" "$scene" --port "$port" -j 1 --frames "$count" ${fps:+--fps "$fps"} \
    "${extra[@]}" >"/tmp/serve_$$.out" 2>/dev/null &
  local pid=$!
  for _ in $(seq 100); do grep -q "ws://" "/tmp/serve_$$.out" 2>/dev/null && break; sleep 0.1; done
  if ((clients > 0)); then
    build/serve_clients --port "$port" --clients "$clients" --seconds "$s" --warmup "${WARMUP:-10}" ||
      echo "$label: frames were lost"
  fi
  wait "$pid"
  echo "$label: $(grep 'frames,' "/tmp/serve_$$.out")"
}
serve "real time, no clients" "" "$frames" 0
serve "real time, $n clients" "" "$frames" "$n"
serve "as fast as it steps, no clients" 0 "$frames" 0
serve "as fast as it steps, $n clients" 0 "$frames" "$n"
rm -f "/tmp/serve_$$.out"
