#!/usr/bin/env bash
# "The ROM's results are unchanged to the digit" across a move of code (issues #26, #56): builds
# nsf as it was at OLD_REV (default 470b4dc, before issue #56's split of the model; 6ddd54a was
# before its first move, but cannot read a scene with a rom.unseen profile) in WORKDIR, and runs the
# ROM through both that binary and this tree's build/nsf on each small scene whose model and
# dataset are here (models/NAME.nsf, data/NAME/test_0.h5), at the held-out μ, with the scene's
# settings, against the stored truth. Every frame of both outputs (x, v, tau, C, F) and every
# figure of both rows but the machine's (times, memory) must be bit-identical. Where no model is
# here, metal_small's sweep and a short MLP training are made with the old binary first.
# About 5 minutes per scene on 2 cores, plus the old build (a few minutes with ccache).
# Usage: bash scripts/check-refactor-bits.sh [OLD_REV] [WORKDIR] [SCENE...]
set -euo pipefail
cd "$(dirname "$0")/.."
here=$(pwd)
old_rev=${1:-470b4dc}
work=${2:-$(mktemp -d)}
shift $(($# > 2 ? 2 : $#))
[ -x build/nsf ] || { echo "check-refactor-bits: build/nsf is missing: run scripts/build.sh" >&2; exit 1; }
/usr/bin/python3 -c "import h5py, numpy" 2>/dev/null ||
  { echo "check-refactor-bits: needs python3-h5py and python3-numpy (apt-get install)" >&2; exit 1; }
old="$work/nsf_$old_rev"
step() { printf '== %s (%s)\n' "$1" "$(date +%T)"; }

step "the tree at $old_rev into $old"
[ -d "$old" ] || git clone -q "$here" "$old"
git -C "$old" checkout -q "$old_rev"
step "building it (the nsf tool only, with this tree's build options)"
native=$(sed -n 's/^NSF_NATIVE:BOOL=//p' build/CMakeCache.txt)
cmake -S "$old" -B "$old/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DNSF_NATIVE="${native:-OFF}" \
  -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
cmake --build "$old/build" --target nsf_cli -j"$(nproc)" | tail -n 1
old_nsf="$old/build/nsf"

# Each case: a scene of scenes/paper, its model and its dataset.
declare -A model data
for name in "$@"; do model[$name]=models/$name.nsf data[$name]=data/$name; done
if [ $# = 0 ]; then
  for m in models/*_small.nsf; do
    name=$(basename "$m" .nsf)
    [ -f "data/$name/test_0.h5" ] && [ -f "scenes/paper/$name.json" ] && model[$name]=$m data[$name]=data/$name
  done
fi
if [ ${#model[@]} = 0 ]; then
  step "no small model here: metal_small's sweep and a short MLP training with the old nsf"
  "$old_nsf" sweep scenes/paper/metal_small.json --out "$work/data" -q >/dev/null
  "$old_nsf" train "$work/data" -o "$work/metal_small.nsf" --decoder mlp --steps 600,400,400 -j 2 \
    -q >/dev/null
  model[metal_small]=$work/metal_small.nsf data[metal_small]=$work/data
fi

same() {  # two ROM outputs frame by frame, and two rows figure by figure
  /usr/bin/python3 - "$@" <<'EOF'
import json, sys, h5py, numpy as np
a, b = (h5py.File(p, "r")["frames"] for p in sys.argv[1:3])
bad = [k for k in ("x", "v", "tau", "C", "F") if k in a and (k not in b or a[k].shape != b[k].shape or not np.array_equal(a[k][:], b[k][:]))]
ra, rb = (json.load(open(p)) for p in sys.argv[3:5])
machine = lambda k: k.endswith(("_seconds", "_mib")) or k in ("speedup", "coarse_speedup", "threads", "cpu", "picture")
bad += ["row: " + k for k in sorted(set(ra) | set(rb)) if not machine(k) and ra.get(k) != rb.get(k)]
print("   bit-identical: x, v, tau, C, F over %d frames, and the row" % a["x"].shape[0] if not bad else "   DIFFER: " + ", ".join(bad))
sys.exit(1 if bad else 0)
EOF
}
status=0
for name in "${!model[@]}"; do
  truth=${data[$name]}/test_0.h5
  mu=$(/usr/bin/python3 -c "import h5py; print(repr(float(h5py.File('$truth').attrs['mu'])))")
  args=("${model[$name]}" "scenes/paper/$name.json" --mu "$mu" --truth "$truth" --no-full-order -j 1 -q)
  step "$name at mu = $mu: nsf rom, old and new"
  "$old_nsf" rom "${args[@]}" -o "$work/$name.old.h5" --json "$work/$name.old.json" >/dev/null
  build/nsf rom "${args[@]}" -o "$work/$name.new.h5" --json "$work/$name.new.json" >/dev/null
  same "$work/$name.old.h5" "$work/$name.new.h5" "$work/$name.old.json" "$work/$name.new.json" || status=1
done
[ $status = 0 ] && echo "check-refactor-bits: the ROM gives the same bits at $old_rev and now (${!model[*]})"
exit $status
