#!/usr/bin/env bash
# The main job: sets up (packages, build), then `nsf demo`: sweep a small scene into a dataset,
# train the neural fields, run the reduced-order model at a held-out parameter against the
# full-order engine, print the summary and write ground truth | ROM pictures to out/.
# Datasets (data/) and models (models/) that already exist are reused.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
# Threads sleep rather than spin at barriers: much faster when the machine is shared
# (docs/BENCHMARKS.md, "OpenMP and a shared machine"), as fast when it is not.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
./build/nsf demo "$@"
