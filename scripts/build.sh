#!/usr/bin/env bash
# Installs the Debian packages nsf needs, then configures and builds a Release tree in build/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
# `import nsf` (docs/PYTHON.md): nsf.pth in the user site-packages of the interpreter the bindings
# were built for puts build/python on its path (and on that of any Python 3.11 of this user).
if [ -f build/python/nsf.pth ]; then
  site="$("$(cat build/python/interpreter)" -m site --user-site)"
  mkdir -p "$site" && cp build/python/nsf.pth "$site/nsf.pth"
  echo "nsf: import nsf finds build/python ($site/nsf.pth)"
fi
