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
#   plugin   core, mpm, io, data, nn (libnsf_mlp.so: an MLP model's networks behind the C table of
#         nn/mlp_plugin_abi.h, which the runtime opens; neither includes the other)
#   net   core (the WebSocket server of nsf serve: no model, no engine)
#   app   anything
# The embedding API's public header, include/nsf/runtime.h, includes nothing of src/ at all.
# The tests and the Python module beside src/ keep the same table:
#   tests/unit/LAYER/   a unit test of LAYER: what LAYER may include (tests/unit/rom/eval and
#         rom/calibration also io), the public API <nsf/...> counting as runtime, and tests/support/,
#         whose headers count with what they include
#   tests/support/   the helpers every test may include: anything but app
#   tests/app/, tests/cli/   the tests of src/app and of the nsf tool: anything
#   python/src/   the pybind module: the runtime's public API (<nsf/...>) and the layers libnsf
#         holds, which it links (core, mpm, io, data); the ROM comes through the runtime, and
#         nn, rom and src/runtime, hidden inside libnsf_runtime.so, would not link
# Usage: tests/check_layers.sh [SRC_DIR] (default: the src/ next to this script). Run by ctest.
set -euo pipefail
src="${1:-$(dirname "$0")/../src}"
[[ -d "$src/core" && -d "$src/app" ]] || { echo "check_layers: no src tree at $src" >&2; exit 2; }
root="$src/.."

allowed() {
  case "$1" in
    core) echo "core" ;;
    mpm) echo "core mpm" ;;
    io | data | nn) echo "core mpm io data nn" ;;
    rom) echo "core mpm data nn rom" ;;
    runtime) echo "core mpm data nn rom runtime" ;;
    plugin) echo "core mpm io data nn plugin" ;;
    net) echo "core net" ;;
    app) echo "core mpm io data nn rom runtime net app" ;;
    *) return 1 ;;
  esac
}

# FILE's includes, one a line as LINE:TARGET: TARGET is the directory of src/ of a quoted
# "dir/..." include, <nsf> for the public API <nsf/...>, =NAME for a quoted include without a
# directory (a header beside FILE or in tests/support/), and ?PATH for one that climbs (../).
includes_at() {
  grep -nE '^[[:space:]]*#[[:space:]]*include' "$1" | sed -nE \
    -e 's/^([0-9]+):[[:space:]]*#[[:space:]]*include[[:space:]]*"([a-z_]+)\/.*/\1:\2/p' \
    -e 's/^([0-9]+):[[:space:]]*#[[:space:]]*include[[:space:]]*<nsf\/.*/\1:<nsf>/p' \
    -e 's/^([0-9]+):[[:space:]]*#[[:space:]]*include[[:space:]]*"([^"/]+)".*/\1:=\2/p' \
    -e 's/^([0-9]+):[[:space:]]*#[[:space:]]*include[[:space:]]*"(\.[^"]*)".*/\1:?\2/p' || true
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

# The tests and the Python module, where this tree has them.
tests="$root/tests"
support="$tests/support"

# reaches[NAME]: the layers of src/ that support header NAME reaches, by its own includes and
# through the support headers it includes (reach NAME fills it in).
declare -A reaches=()
reach() {
  local name=$1 line target found=""
  [[ -n "${reaches[$name]+x}" ]] && return 0
  reaches[$name]=""  # an include cycle stops here
  while IFS=: read -r line target; do
    case "$target" in
      =*)
        if [[ -f "$support/${target#=}" ]]; then
          reach "${target#=}"
          found="$found ${reaches[${target#=}]}"
        fi ;;
      \?*) ;;
      *) found="$found $target" ;;
    esac
  done < <(includes_at "$support/$name")
  reaches[$name]=$(tr ' ' '\n' <<<"$found" | sort -u | tr '\n' ' ')
}

# A layer as the messages name it: dir/, or <nsf/...> for the public API.
shown() { if [[ $1 == "<nsf>" ]]; then echo "<nsf/...>"; else echo "$1/"; fi; }

# Checks FILE (shown as REL) against OK, the layers WHO may include. <nsf> is the public API,
# which counts as runtime; a support header counts with every layer it reaches.
check_file() {
  local file=$1 rel=$2 who=$3 ok=$4 line target t
  [[ " $ok " == *" runtime "* ]] && ok="$ok <nsf>"
  while IFS=: read -r line target; do
    case "$target" in
      \?*)
        echo "$rel:$line: includes ${target#?}, past the directories the layer check reads"
        bad=1 ;;
      =*)
        [[ -f "$(dirname "$file")/${target#=}" ]] && continue  # beside it: checked in its own right
        [[ -f "$support/${target#=}" ]] || continue  # a header of the system or a library
        reach "${target#=}"
        for t in ${reaches[${target#=}]}; do
          if [[ " $ok " != *" $t "* ]]; then
            echo "$rel:$line: $who may not include $(shown "$t") (through tests/support/${target#=}; allowed: $ok)"
            bad=1
          fi
        done ;;
      *)
        if [[ " $ok " != *" $target "* ]]; then
          echo "$rel:$line: $who may not include $(shown "$target") (allowed: $ok)"
          bad=1
        fi ;;
    esac
  done < <(includes_at "$file")
}

if [[ -d "$tests" ]]; then
  while IFS= read -r file; do
    rel=tests/${file#"$tests"/}
    case "${file#"$tests"/}" in
      unit/*/*)
        layer=${file#"$tests"/unit/}
        layer=${layer%%/*}
        if ! ok=$(allowed "$layer"); then
          echo "$rel: tests/unit/$layer is in no layer; name a layer of src/ (tests/check_layers.sh)"
          bad=1
          continue
        fi
        case "${file#"$tests"/unit/}" in rom/eval/* | rom/calibration/*) ok="$ok io" ;; esac
        check_file "$file" "$rel" "tests/unit/$layer" "$ok" ;;
      support/*) check_file "$file" "$rel" "tests/support" "$(allowed runtime) io net" ;;
      app/* | cli/*) ;;
      *)
        echo "$rel: a test outside tests/unit/LAYER/, tests/app/ and tests/cli/, or a helper outside tests/support/"
        bad=1 ;;
    esac
  done < <(find "$tests" -type f \( -name '*.cpp' -o -name '*.h' -o -name '*.c' \) | sort)
fi
python_src="$root/python/src"
if [[ -d "$python_src" ]]; then
  while IFS= read -r file; do
    check_file "$file" "python/src/${file#"$python_src"/}" "python/src" "core mpm io data <nsf>"
  done < <(find "$python_src" -type f \( -name '*.cpp' -o -name '*.h' \) | sort)
fi

if ((bad)); then
  echo "check_layers: includes point the wrong way (core -> mpm -> io/data/nn -> rom -> runtime -> app)" >&2
  exit 1
fi
echo "check_layers: every include in src/, tests/unit/, tests/support/ and python/src/ points down the layers"
