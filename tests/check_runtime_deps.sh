#!/usr/bin/env bash
# The runtime a host ships depends on the C++ standard library, its C runtime and OpenMP alone
# (docs/EMBEDDING.md): no LibTorch, OpenCV, BLAS, HDF5, PNG or Assimp. Fails, naming them, on any
# other library the file asks for (its NEEDED entries) or the loader brings in (ldd).
#
#   bash tests/check_runtime_deps.sh build/libnsf_runtime.so
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 LIBRARY" >&2; exit 2; }
lib="$1"
[ -f "$lib" ] || { echo "$0: no file $lib" >&2; exit 1; }
allowed='^(linux-vdso\.so|ld-linux[-a-z0-9_]*\.so|libc\.so|libm\.so|libgcc_s\.so|libstdc\+\+\.so|libgomp\.so|libdl\.so|libpthread\.so)'
needed="$(readelf -d "$lib" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')"
loaded="$(ldd "$lib" | awk '{ print $1 }')"
extra="$(printf '%s\n%s\n' "$needed" "$loaded" | sed 's|.*/||' | sort -u | grep -Ev "$allowed" || true)"
if [ -n "$extra" ]; then
  echo "$0: $lib depends on libraries beyond libstdc++, libc and OpenMP:" >&2
  echo "$extra" | sed 's/^/  /' >&2
  exit 1
fi
echo "$lib: $(echo "$loaded" | wc -l) libraries loaded, all from the C++ runtime and OpenMP:"
echo "$loaded" | sed 's/^/  /'
