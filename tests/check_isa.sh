#!/usr/bin/env bash
# No installed artefact runs instructions above the baseline (x86-64-v2: up to SSE4.2 and POPCNT)
# except in the hot kernels' x86-64-v3 and -v4 clones, which the loader picks only on a CPU that
# has them (src/core/isa.h). Disassembles each file given and fails, naming the functions, on any
# VEX or EVEX instruction (AVX and later: a mnemonic in v…, a ymm, zmm or mask register) outside a
# function whose name ends in .arch_x86_64_v3 or .arch_x86_64_v4.
#
#   bash tests/check_isa.sh build/libnsf_runtime.so build/nsf
set -euo pipefail
[ $# -gt 0 ] || { echo "usage: $0 BINARY..." >&2; exit 2; }
command -v objdump >/dev/null || { echo "$0: objdump (binutils) is missing" >&2; exit 1; }
status=0
for f in "$@"; do
  [ -f "$f" ] || { echo "$0: no file $f" >&2; exit 1; }
  report="$(objdump -d --no-show-raw-insn -C "$f" | awk '
    /^[0-9a-f]+ <.*>:$/ { fn = substr($0, index($0, "<") + 1); sub(/>:$/, "", fn);
                          clone = (fn ~ /\.arch_x86_64_v[34]/); next }
    /^ +[0-9a-f]+:\t/ {
      split($0, parts, "\t"); insn = parts[2]; split(insn, w, " "); op = w[1];
      if (clone) { cloned++; next }
      if ((op ~ /^v/ && op !~ /^ver[rw]$/) || insn ~ /%[yz]mm|%k[0-7]/) { bad[fn]++; total++ }
    }
    END {
      for (fn in bad) printf "  %d in %s\n", bad[fn], fn | "sort -rn | head -10";
      close("sort -rn | head -10");
      printf "TOTAL %d %d\n", total, cloned;
    }')"
  total="$(echo "$report" | awk '/^TOTAL/ { print $2 }')"
  cloned="$(echo "$report" | awk '/^TOTAL/ { print $3 }')"
  if [ "$total" != "0" ]; then
    echo "check_isa: $f has $total instructions above x86-64-v2 outside the kernels' clones:"
    echo "$report" | grep -v '^TOTAL'
    status=1
  else
    echo "check_isa: $f: baseline x86-64-v2 outside the clones (${cloned} instructions in v3/v4 clones)"
  fi
done
exit $status
