#!/usr/bin/env bash
# `mpirun -np 2 nsf train` on localhost (docs/TRAINING.md, "Training across machines"):
#  1. two processes train a tiny model to the loss curve of one process with the same global
#     batch (--frames-per-batch 4: the two processes compute the entries of its frames each holds),
#     for the per-point bases and for the MLP fields, every step within a relative 1e-3;
#  2. the two-process run stopped twice (--stop-after, once mid-stage and once across a stage's
#     end) and resumed under mpirun writes the loss curve of the uninterrupted run, byte for byte;
#  3. one process killed mid-training, or an error on one process, ends the job (no process is
#     left waiting for it).
# Tolerance: the processes draw the same batches from the same seed and sum gradients that are
# each weighted by the global batch, so a step differs from one process's only in the order of
# float sums (about 1e-7 relative); over the 180 steps here that grew to at most 1e-5
# (docs/experiments/2026-11-26-data-parallel-training.md). Batches drawn differently on each
# process (seeded by rank) move the curve by 820 % (checked by mutating the trainer). A common
# scale of the gradients (an average instead of the sum) leaves Adam's steps unchanged.
# Usage: tests/check_mpi_train.sh NSF_BINARY SOURCE_DIR [MPIRUN]. Run by ctest (mpi_train).
set -euo pipefail
nsf=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
src=$(cd "$2" && pwd)
mpirun=${3:-mpirun}
check=check_mpi_train
# shellcheck source=tests/mpi_localhost.sh
source "$(dirname "$0")/mpi_localhost.sh"
two=("$mpirun" --oversubscribe --bind-to none -np 2 "$nsf" train)

cd "$tmp"
step "dataset: the tiny sweep (4 training runs of 13 frames, 864 particles)"
"$nsf" sweep "$src/scenes/examples/rom_tiny.json" -o data -q >sweep.log 2>&1 ||
  { cat sweep.log; die "nsf sweep failed"; }

basis=(--steps 60,60,60 --frames-per-batch 4 --widths 32 -r 4 --modes 8 --refine-latents 0
       --checkpoint-every 20 -q)
mlp=(--decoder mlp --steps 60,60,60 --frames-per-batch 4 --particles-per-frame 128 --widths 32
     -r 4 --depth 2 --refine-latents 2 --checkpoint-every 20 -q)

# Every row of $2 has the stage and step of $1's row and a loss within 1e-3 of it.
same_curve() {
  [[ $(wc -l <"$1") == $(wc -l <"$2") ]] || die "$2 has other rows than $1"
  paste -d, "$1" "$2" | awk -F, -v what="$2" 'NR > 1 {
      if ($1 != $7 || $3 != $9) { print what ": row " NR " is another step"; bad = 1; exit }
      d = ($4 - $10) / $4; if (d < 0) d = -d; if (d > worst) worst = d
    } END {
      if (bad) exit 1
      printf "   %s: largest relative difference %.2g\n", what, worst
      if (worst > 1e-3) { print what ": loss differs by more than 1e-3"; exit 1 }
    }' || die "the two-process loss curve $2 is not the one-process $1"
}

for family in basis mlp; do
  declare -n flags=$family
  step "$family: one process, then two"
  "$nsf" train data --out "one_$family/m.nsf" "${flags[@]}" -j 1 >"one_$family.log" 2>&1 ||
    { cat "one_$family.log"; die "nsf train failed"; }
  "${two[@]}" data --out "two_$family/m.nsf" "${flags[@]}" >"two_$family.log" 2>&1 ||
    { cat "two_$family.log"; die "mpirun nsf train failed"; }
  grep -q "2 processes x 1 threads" "two_$family.log" || { cat "two_$family.log"; die "not 2 x 1"; }
  [[ -f "two_$family/m.nsf" && ! -e "two_$family/m.nsf.ckpt" ]] || die "no model, or a checkpoint left"
  same_curve "one_$family/m.loss.csv" "two_$family/m.loss.csv"
done

step "mlp: two processes stopped twice and resumed"
run=("${two[@]}" data --out resumed/m.nsf "${mlp[@]}")
"${run[@]}" --stop-after 50 >r1.log 2>&1 || { cat r1.log; die "first part failed"; }
grep -q "stopped early" r1.log || { cat r1.log; die "did not stop"; }
[[ -f resumed/m.nsf.ckpt && ! -e resumed/m.nsf ]] || die "no checkpoint after --stop-after"
# From step 40 (the last checkpoint) 50 steps on: past stage 1's end into stage 2.
"${run[@]}" --resume --stop-after 50 >r2.log 2>&1 || { cat r2.log; die "second part failed"; }
grep -q "stopped early" r2.log || { cat r2.log; die "did not stop"; }
"${run[@]}" --resume >r3.log 2>&1 || { cat r3.log; die "the last part failed"; }
[[ -f resumed/m.nsf && ! -e resumed/m.nsf.ckpt ]] || die "no model after resuming"
cmp resumed/m.loss.csv two_mlp/m.loss.csv || die "the resumed run's loss curve is not the uninterrupted run's"

step "one process killed mid-training ends the job"
"${two[@]}" data --out killed/m.nsf --steps 1000000,1,1 --frames-per-batch 4 --widths 32 -r 4 \
  --modes 8 --refine-latents 0 --checkpoint-every 20 -q >killed.log 2>&1 &
mpirun_pid=$!
# Training is under way once process 0 has written a checkpoint.
for _ in $(seq 600); do
  [[ -f killed/m.nsf.ckpt ]] && break
  kill -0 "$mpirun_pid" 2>/dev/null || { cat killed.log; die "mpirun ended before the kill"; }
  sleep 0.1
done
[[ -f killed/m.nsf.ckpt ]] || die "no checkpoint after 60 s"
victim=$(pgrep -P "$mpirun_pid" -x nsf | tail -1 || true)
[[ -n "$victim" ]] || die "no nsf process under mpirun"
kill -9 "$victim"
for _ in $(seq 300); do
  kill -0 "$mpirun_pid" 2>/dev/null || break
  sleep 0.1
done
if kill -0 "$mpirun_pid" 2>/dev/null; then die "30 s after the kill the job still runs"; fi
if wait "$mpirun_pid"; then die "mpirun succeeded with a process killed"; fi
mpirun_pid=""
[[ ! -e killed/m.nsf ]] || die "a model written by a killed job"

step "an error on process 0 alone ends the job"
# Process 0 cannot write its checkpoint (a folder where its temporary file goes) while process 1,
# which writes nothing, waits for it in the next step's sum: MPI_Abort must end both.
mkdir -p failed/m.nsf.ckpt.tmp
status=0
timeout 120 "${two[@]}" data --out failed/m.nsf --steps 60,1,1 --frames-per-batch 4 --widths 32 \
  -r 4 --modes 8 --refine-latents 0 --checkpoint-every 1 -q >failed.log 2>&1 || status=$?
[[ $status != 124 ]] || die "the job hung after process 0's error"
[[ $status != 0 ]] || die "mpirun succeeded although process 0 failed"
grep -q "nsf: error (process 0 of 2): .*m.nsf.ckpt.tmp exists and is not a regular file" failed.log ||
  { cat failed.log; die "no message"; }
step "passed"
