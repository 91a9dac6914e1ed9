#!/usr/bin/env bash
# The main job: sets up (packages, build), runs a full-order scene and writes its picture.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
mkdir -p out
./build/nsf simulate scenes/examples/elastic_drop.json --out out/elastic_drop.h5 \
  --png out/elastic_drop.png "$@"
echo "demo: picture in out/elastic_drop.png, frames in out/elastic_drop.h5 (docs/OUTPUT.md)"
