#!/usr/bin/env bash
# No installed artefact runs instructions above the baseline (x86-64-v2: up to SSE4.2 and POPCNT)
# except in the hot kernels' x86-64-v3 and -v4 clones, which the loader picks only on a CPU that
# has them (src/core/isa.h). Disassembles each file given and fails, naming the functions, on any
# VEX or EVEX instruction (AVX and later: a mnemonic in v…, a ymm, zmm or mask register) outside a
# function whose name ends in .arch_x86_64_v3 or .arch_x86_64_v4. With --level x86-64-v3 (the
# runtime's copy for such CPUs, cmake/hwcaps.cmake), AVX2 and FMA are allowed and only EVEX
# instructions (AVX-512: an 0x62 prefix, a zmm or mask register) outside the v4 clones fail.
#
#   bash tests/check_isa.sh build/libnsf_runtime.so build/nsf
#   bash tests/check_isa.sh --level x86-64-v3 build/glibc-hwcaps/x86-64-v3/libnsf_runtime.so.0
set -euo pipefail
level=x86-64-v2
if [ "${1:-}" = --level ]; then
  level=${2:-}
  shift 2 || true
fi
case "$level" in
  x86-64-v2) clones='\\.arch_x86_64_v[34]' ;;
  x86-64-v3) clones='\\.arch_x86_64_v4' ;;
  *) echo "$0: --level is x86-64-v2 or x86-64-v3, not '$level'" >&2; exit 2 ;;
esac
[ $# -gt 0 ] || { echo "usage: $0 [--level x86-64-v2|x86-64-v3] BINARY..." >&2; exit 2; }
command -v objdump >/dev/null || { echo "$0: objdump (binutils) is missing" >&2; exit 1; }
status=0
for f in "$@"; do
  [ -f "$f" ] || { echo "$0: no file $f" >&2; exit 1; }
  report="$(objdump -d -C "$f" | awk -v clones="$clones" -v level="$level" '
    /^[0-9a-f]+ <.*>:$/ { fn = substr($0, index($0, "<") + 1); sub(/>:$/, "", fn);
                          clone = (fn ~ clones); next }
    /^ +[0-9a-f]+:\t/ {
      n = split($0, parts, "\t"); if (n < 3) next;  # the rest of a long instruction
      raw = parts[2]; insn = parts[3]; split(insn, w, " "); op = w[1];
      if (clone) { cloned++; next }
      if (level == "x86-64-v2") above = (op ~ /^v/ && op !~ /^ver[rw]$/) || insn ~ /%[yz]mm|%k[0-7]/;
      else above = raw ~ /^62 / || insn ~ /%zmm|%k[0-7]/;
      if (above) { bad[fn]++; total++ }
    }
    END {
      for (fn in bad) printf "  %d in %s\n", bad[fn], fn | "sort -rn | head -10";
      close("sort -rn | head -10");
      printf "TOTAL %d %d\n", total, cloned;
    }')"
  total="$(echo "$report" | awk '/^TOTAL/ { print $2 }')"
  cloned="$(echo "$report" | awk '/^TOTAL/ { print $3 }')"
  if [ "$total" != "0" ]; then
    echo "check_isa: $f has $total instructions above $level outside the kernels' clones:"
    echo "$report" | grep -v '^TOTAL'
    status=1
  else
    echo "check_isa: $f: $level outside the clones (${cloned} instructions in the clones above it)"
  fi
done
exit $status
