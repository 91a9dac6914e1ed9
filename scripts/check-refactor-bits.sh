#!/usr/bin/env bash
# Issue #26's "the ROM's results are unchanged to the digit": builds nsf as it was when the issue
# was filed (152848e, before the runtime's refactor), trains a small MLP model with it, and runs
# the ROM with that model and the same options through both the old binary and this tree's
# build/nsf; every frame of both outputs (x, v, tau, C, F) must be bit-identical. About 15
# minutes on 2 cores (the old build ~8, the sweep and a short training ~2, four ROM runs ~5).
# Usage: bash scripts/check-refactor-bits.sh [WORKDIR]   (default: a new temporary directory)
set -euo pipefail
cd "$(dirname "$0")/.."
here=$(pwd)
old_rev=152848e
[ -x build/nsf ] || { echo "check-refactor-bits: build/nsf is missing: run scripts/build.sh" >&2; exit 1; }
/usr/bin/python3 -c "import h5py, numpy" 2>/dev/null ||
  { echo "check-refactor-bits: needs python3-h5py and python3-numpy (apt-get install)" >&2; exit 1; }
work=${1:-$(mktemp -d)}
old="$work/nsf_$old_rev"
step() { printf '== %s (%s)\n' "$1" "$(date +%T)"; }

step "the tree at $old_rev into $old"
[ -d "$old" ] || git clone -q "$here" "$old"
git -C "$old" checkout -q "$old_rev"
step "building it (nsf only)"
cmake -S "$old" -B "$old/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$old/build" --target nsf -j"$(nproc)" | tail -n 1
cd "$old"
step "metal_small's sweep and a short MLP training, with the old nsf"
[ -f data/metal_small/manifest.json ] || build/nsf sweep scenes/paper/metal_small.json --out data/metal_small >/dev/null
[ -f models/m.nsf ] || build/nsf train data/metal_small -o models/m.nsf --steps 600,400,400 -j 2 >/dev/null
mu=$(/usr/bin/python3 -c "import h5py; print(repr(float(h5py.File('data/metal_small/test_0.h5').attrs['mu'])))")

same() {  # compare two ROM outputs frame by frame
  /usr/bin/python3 - "$1" "$2" <<'EOF'
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r")["frames"] for p in sys.argv[1:3])
bad = [k for k in ("x", "v", "tau", "C", "F") if a[k].shape != b[k].shape or not np.array_equal(a[k][:], b[k][:])]
print("   bit-identical: x, v, tau, C, F over %d frames" % a["x"].shape[0] if not bad else "   DIFFER: " + ", ".join(bad))
sys.exit(1 if bad else 0)
EOF
}
status=0
for options in "" "--quadrature 1 --dt-ratio 2 --seed 3 -k 120"; do
  what=${options:-the scene settings}
  step "nsf rom with '$what', old and new"
  args=(models/m.nsf scenes/paper/metal_small.json --mu "$mu" --truth data/metal_small/test_0.h5
        --no-full-order -j 1 $options)
  build/nsf rom "${args[@]}" -o "$work/old.h5" | grep "delta (eq. 11)"
  "$here/build/nsf" rom "${args[@]}" -q -o "$work/new.h5" | grep "delta (eq. 11)"
  same "$work/old.h5" "$work/new.h5" || status=1
done
[ $status = 0 ] && echo "check-refactor-bits: the ROM gives the same bits before and after the refactor"
exit $status
