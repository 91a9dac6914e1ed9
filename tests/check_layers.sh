#!/usr/bin/env bash
# The layers of src/ point one way: core -> mpm -> io, data, nn -> rom -> runtime -> app. Fails,
# listing each offending line, when a file includes a header of a layer it may not use:
#   core  only itself
#   mpm   core
#   io, data, nn   core, mpm and one another; not rom or app
#   rom   core, mpm, data, nn; not io (files are the harness's job) or app
#   rom/eval, rom/calibration   also io: they run the ROM against a truth read from, and written
#         to, run files (the library behind nsf rom, report, calibrate and generalize)
#   runtime   core, mpm, data, nn, rom (the embedding API; it writes no files either)
#   net   core (the WebSocket server of nsf serve: no model, no engine)
#   app   anything
# The embedding API's public header, include/nsf/runtime.h, includes nothing of src/ at all.
# Usage: tests/check_layers.sh [SRC_DIR] (default: the src/ next to this script). Run by ctest.
set -euo pipefail
src="${1:-$(dirname "$0")/../src}"
[[ -d "$src/core" && -d "$src/app" ]] || { echo "check_layers: no src tree at $src" >&2; exit 2; }

allowed() {
  case "$1" in
    core) echo "core" ;;
    mpm) echo "core mpm" ;;
    io | data | nn) echo "core mpm io data nn" ;;
    rom) echo "core mpm data nn rom" ;;
    runtime) echo "core mpm data nn rom runtime" ;;
    net) echo "core net" ;;
    app) echo "core mpm io data nn rom runtime net app" ;;
    *) return 1 ;;
  esac
}

bad=0
for layer_dir in "$src"/*/; do
  layer=$(basename "$layer_dir")
  if ! ok=$(allowed "$layer"); then
    echo "check_layers: src/$layer is in no layer; add it to tests/check_layers.sh" >&2
    bad=1
    continue
  fi
  # Quoted includes of another directory of src/: #include "dir/...".
  while IFS=: read -r file line target; do
    allowed_here=$ok
    case "${file#"$src"/}" in rom/eval/* | rom/calibration/*) allowed_here="$ok io" ;; esac
    if [[ " $allowed_here " != *" $target "* ]]; then
      echo "${file#"$src"/}:$line: $layer may not include $target/ (allowed: $ok)"
      bad=1
    fi
  done < <(grep -rnE --include='*.h' --include='*.cpp' '^[[:space:]]*#[[:space:]]*include[[:space:]]*"[a-z_]+/' \
             "$layer_dir" | sed -E 's/^([^:]+):([0-9]+):.*#[[:space:]]*include[[:space:]]*"([a-z_]+)\/.*/\1:\2:\3/')
done
public="$src/../include/nsf"
if [[ -d "$public" ]] && grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$public"; then
  echo "check_layers: the public headers in include/nsf include headers of src/ (above)"
  bad=1
fi
if ((bad)); then
  echo "check_layers: includes point the wrong way (core -> mpm -> io/data/nn -> rom -> runtime -> app)" >&2
  exit 1
fi
echo "check_layers: every include in $src points down the layers"
