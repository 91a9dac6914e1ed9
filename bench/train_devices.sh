#!/usr/bin/env bash
# Training on the CPU against training on a GPU, in one run (docs/BENCHMARKS.md, "Training on a
# GPU"): `nsf train` twice on the same dataset with the same options and the same host threads,
# once with --device cpu and once with --device cuda; prints each stage's optimiser steps per
# second on both and their ratio, and writes the row as JSON.
#
#   bash bench/train_devices.sh NSF DATA OUT.json [nsf train options...]
#
# NSF is an nsf built with a CUDA LibTorch (docs/TRAINING.md, "Training on a GPU"); the host
# threads are 2 (NSF_THREADS to change), as on the 2-core machines the CPU defaults are sized
# for. Each pair is run REPEATS times (default 2), CPU and GPU interleaved; the row keeps every
# repeat's seconds and reports the median ratio.
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 NSF DATA OUT.json [nsf train options...]" >&2
  exit 2
fi
nsf=$1 data=$2 out=$3
shift 3
threads=${NSF_THREADS:-2}
gpu=${NSF_GPU_DEVICE:-cuda}  # or cuda:N
repeats=${REPEATS:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

rows=()
for ((k = 1; k <= repeats; ++k)); do
  for side in cpu gpu; do
    device=cpu
    [ $side = gpu ] && device=$gpu
    echo "== repeat $k/$repeats, --device $device, $threads host threads" >&2
    "$nsf" train "$data" -o "$work/$side.nsf" --device "$device" -j "$threads" --fresh -q \
      --json "$work/$side-$k.json" "$@" >&2
    rows+=("$work/$side-$k.json")
  done
done

python3 - "$out" "$data" "$threads" "$*" "${rows[@]}" <<'EOF'
import json, os, statistics, sys
out, data, threads, options, files = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5:]
runs = [json.load(open(f)) for f in files]
by = {side: [r for f, r in zip(files, runs) if os.path.basename(f).startswith(side)]
      for side in ("cpu", "gpu")}
by["cuda"] = by.pop("gpu")
stages = []
print(f"{'stage':<12} {'steps':>6} {'cpu s':>14} {'cuda s':>14} {'speed-up':>9}")
for s in range(3):
    cpu = [r["stages"][s]["seconds"] for r in by["cpu"]]
    gpu = [r["stages"][s]["seconds"] for r in by["cuda"]]
    steps = by["cpu"][0]["stages"][s]["steps"]
    ratios = [c / g for c, g in zip(cpu, gpu) if g > 0]
    row = {"stage": s + 1, "name": by["cpu"][0]["stages"][s]["name"], "steps": steps,
           "cpu_seconds": cpu, "cuda_seconds": gpu,
           "speedup": statistics.median(ratios) if ratios else None,
           "speedup_range": [min(ratios), max(ratios)] if ratios else None,
           "cpu_final_loss": by["cpu"][0]["stages"][s]["final_loss"],
           "cuda_final_loss": by["cuda"][0]["stages"][s]["final_loss"]}
    stages.append(row)
    fmt = lambda v: f"{statistics.median(v):.2f} ({min(v):.2f}-{max(v):.2f})"
    sp = f"{row['speedup']:.1f}x" if row["speedup"] else "-"
    print(f"{row['name']:<12} {steps:>6} {fmt(cpu):>14} {fmt(gpu):>14} {sp:>9}")
total_cpu = sum(statistics.median(s["cpu_seconds"]) for s in stages)
total_gpu = sum(statistics.median(s["cuda_seconds"]) for s in stages)
print(f"all stages: {total_cpu:.1f} s on {threads} CPU threads, {total_gpu:.1f} s on cuda: "
      f"{total_cpu / total_gpu:.1f}x")
row = {"data": data, "decoder": by["cpu"][0]["decoder"], "host_threads": threads,
       "options": options, "repeats": len(by["cpu"]), "stages": stages,
       "speedup_all_stages": total_cpu / total_gpu,
       "gpu": os.environ.get("NSF_GPU_NAME", ""),
       "command": f"bash bench/train_devices.sh NSF {data} OUT.json {options}".strip()}
tmp = out + ".tmp"
with open(tmp, "w") as f:
    json.dump(row, f, indent=2)
    f.write("\n")
os.replace(tmp, out)
print(f"wrote {out}")
EOF
