#!/usr/bin/env bash
# `mpirun -np 2 nsf sweep` on localhost (docs/DATASETS.md, "Sweeps across machines"):
#  1. two processes write the same run files, byte for byte (cmp), and the same manifest as one
#     process (`nsf sweep` without mpirun);
#  2. one process killed (SIGKILL) mid-run ends the job; the runs finished before stay, the next
#     mpirun leaves them untouched (same inode) and finishes the rest, again byte for byte the
#     one-process files, with no temporary file left.
# Usage: tests/check_mpi_sweep.sh NSF_BINARY [MPIRUN]. Run by ctest (mpi_sweep).
set -euo pipefail
nsf=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
mpirun=${2:-mpirun}
check=check_mpi_sweep
# shellcheck source=tests/mpi_localhost.sh
source "$(dirname "$0")/mpi_localhost.sh"
two=("$mpirun" --oversubscribe --bind-to none -np 2 "$nsf" sweep)

# Four runs of a soft bar of 864 particles thrown onto the floor, a few seconds each.
cd "$tmp"
cat >scene.json <<'EOF'
{
  "name": "mpi_tiny",
  "simulation": { "dx": 0.04, "dt": 0.001, "frames": 100, "substeps": 15, "ppc": 2,
                  "walls": { "contact": "slip" } },
  "objects": [ { "shape": { "type": "box", "min": [0.2, 0.2, 0.44], "max": [0.68, 0.32, 0.56] },
                 "material": { "type": "fixed_corotated", "E": 20000, "nu": 0.3 },
                 "velocity": [1.0, -1.0, 0] } ],
  "colliders": [ { "type": "plane", "point": [0, 0.12, 0], "normal": [0, 1, 0], "contact": "slip" } ],
  "sweep": { "parameter": "speed", "set": ["objects[0].velocity=[{mu},-1.0,0]"],
             "range": [0.5, 1.5], "train": 3, "test": 1 }
}
EOF
# Every file of DIR (run files, their .xdmf, the manifest) is the one-process sweep's, and no
# other file is there (no temporary file left).
same_as_one() {
  diff <(ls one) <(ls "$1") || die "$1 holds other files than the one-process sweep"
  for f in one/*; do
    cmp "$f" "$1/${f#one/}" || die "$1/${f#one/} differs from the one-process sweep's"
  done
}

step "one process"
"$nsf" sweep scene.json -o one -J 1 -j 1 -q >one.log 2>&1 || { cat one.log; die "nsf sweep failed"; }
for f in train_0.h5 train_1.h5 train_2.h5 test_0.h5 manifest.json; do
  [[ -f "one/$f" ]] || die "one process wrote no $f"
done

step "two processes"
"${two[@]}" scene.json -o two >two.log 2>&1 || { cat two.log; die "mpirun failed"; }
# Each process takes its share of the machine: half its cores (not bound to any: --bind-to none).
share=$(($(getconf _NPROCESSORS_ONLN) / 2))
share=$((share < 1 ? 1 : share))
grep -q "2 processes x $share jobs x 1 threads" two.log || { cat two.log; die "not 2 x $share"; }
grep -q "sweep: 4 runs, 4 simulated, 0 already complete" two.log || { cat two.log; die "summary"; }
same_as_one two

step "two processes, one killed mid-run"
"${two[@]}" scene.json -o killed -J 1 -j 1 >killed.log 2>&1 &
mpirun_pid=$!
# One run at a time per process. Wait for a finished run while another is still being written:
# then a process is mid-run.
for _ in $(seq 600); do
  if compgen -G "killed/*.h5" >/dev/null && compgen -G "killed/*.h5.tmp" >/dev/null; then break; fi
  kill -0 "$mpirun_pid" 2>/dev/null || { cat killed.log; die "mpirun ended before the kill"; }
  sleep 0.1
done
compgen -G "killed/*.h5.tmp" >/dev/null || die "no run in progress to kill"
# The process writing a run file (HDF5 holds it open until the rename).
victim=""
for pid in $(pgrep -P "$mpirun_pid" -x nsf || true); do
  if ls -l "/proc/$pid/fd" 2>/dev/null | grep -q '\.h5\.tmp$'; then victim=$pid; fi
done
[[ -n "$victim" ]] || die "no nsf process under mpirun is writing a run"
kill -9 "$victim"
if wait "$mpirun_pid"; then die "mpirun succeeded with a process killed"; fi
mpirun_pid=""
kept=$(cd killed && ls ./*.h5 2>/dev/null | sed 's|^\./||' | sort)
[[ -n "$kept" ]] || die "no finished run survived the kill"
[[ $(echo "$kept" | wc -w) -lt 4 ]] || die "all runs finished before the kill: nothing tested"
declare -A inode
for f in $kept; do
  cmp "one/$f" "killed/$f" || die "killed/$f (finished before the kill) differs"
  inode[$f]=$(stat -c %i "killed/$f")
done
echo "   finished before the kill:" $kept

step "the next mpirun finishes it"
"${two[@]}" scene.json -o killed >resumed.log 2>&1 || { cat resumed.log; die "mpirun failed"; }
done_before=$(echo "$kept" | wc -w)
grep -q "already complete" resumed.log || { cat resumed.log; die "no summary"; }
grep -q "$((4 - done_before)) simulated, $done_before already complete" resumed.log ||
  { cat resumed.log; die "the resumed sweep redid finished runs"; }
for f in $kept; do
  [[ $(stat -c %i "killed/$f") == "${inode[$f]}" ]] || die "killed/$f was rewritten"
done
same_as_one killed
step "passed"
