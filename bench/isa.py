#!/usr/bin/env python3
"""The portable build against -march=native, side by side (issue #53, item 2).

Builds the full-order engine's benchmark (bench/mpm_throughput.cpp) twice, without LibTorch: as
every artefact is built (the x86-64-v2 baseline, with the hot kernels' v3 and v4 clones picked at
run time, src/core/isa.h) and with NSF_NATIVE=ON. Runs the two alternately, REPS times each, on
one thread, and prints each scene's throughput (median, min-max) and the ratio of the medians.
Writes docs/results/bench/isa_mpm.json with --json.

    python3 bench/isa.py [--reps 5] [--step-scale 0.5] [--json docs/results/bench/isa_mpm.json]
"""
import argparse
import json
import os
import platform
import re
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIGS = {"portable": [], "native": ["-DNSF_NATIVE=ON"]}


def build(name, flags):
    path = os.path.join(ROOT, "build-isa", name)
    common = ["-DNSF_WITH_TORCH=OFF", "-DNSF_BUILD_TESTS=OFF", "-DNSF_BUILD_PYTHON=OFF",
              "-DCMAKE_BUILD_TYPE=Release"]
    subprocess.run(["cmake", "-S", ROOT, "-B", path, "-G", "Ninja"] + common + flags,
                   check=True, stdout=subprocess.DEVNULL)
    print(f"isa: building {name} in {path}", file=sys.stderr, flush=True)
    subprocess.run(["cmake", "--build", path, "--target", "mpm_throughput"], check=True,
                   stdout=subprocess.DEVNULL)
    return os.path.join(path, "mpm_throughput")


def run(binary, step_scale):
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive")
    out = subprocess.run([binary, "-j", "1", "--step-scale", str(step_scale)], check=True,
                         env=env, capture_output=True, text=True).stdout
    rows = {}
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 4 and cells[0].startswith("("):
            m = re.match(r"([0-9.]+)M", cells[3])
            if m:
                rows[cells[0]] = float(m.group(1)) * 1e6
    if not rows:
        sys.exit(f"isa: {binary} printed no rows")
    return rows


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--step-scale", type=float, default=0.5)
    ap.add_argument("--json", help="write the rows here")
    a = ap.parse_args()
    if a.reps < 1:
        ap.error("--reps must be at least 1")
    binaries = {name: build(name, flags) for name, flags in CONFIGS.items()}
    samples = {name: {} for name in CONFIGS}
    for rep in range(a.reps):
        for name, binary in binaries.items():
            for scene, value in run(binary, a.step_scale).items():
                samples[name].setdefault(scene, []).append(value)
        print(f"isa: {rep + 1}/{a.reps} rounds", file=sys.stderr, flush=True)
    rows = []
    for scene in samples["portable"]:
        p, n = samples["portable"][scene], samples["native"].get(scene, [])
        if not n:
            continue
        rows.append({"scene": scene, "portable": p, "native": n,
                     "ratio": statistics.median(p) / statistics.median(n)})
    print(f"Full-order throughput, particle-steps/s on one thread, {a.reps} alternated runs "
          f"each ({cpu_name()}): `python3 bench/isa.py --reps {a.reps}`\n")
    print("| scene | portable (x86-64-v2 + clones) | -march=native | portable / native |")
    print("|---|---|---|---|")
    fmt = lambda v: (f"{statistics.median(v) / 1e6:.2f}M "
                     f"({min(v) / 1e6:.2f}-{max(v) / 1e6:.2f})")
    for r in rows:
        print(f"| {r['scene']} | {fmt(r['portable'])} | {fmt(r['native'])} | {r['ratio']:.3f} |")
    if a.json:
        os.makedirs(os.path.dirname(os.path.abspath(a.json)), exist_ok=True)
        doc = {"command": f"python3 bench/isa.py --reps {a.reps} --step-scale {a.step_scale}",
               "cpu": cpu_name(), "threads": 1, "rows": rows}
        tmp = a.json + ".tmp"
        try:
            with open(tmp, "x") as f:
                json.dump(doc, f, indent=1)
        except FileExistsError:
            sys.exit(f"isa: {tmp} exists (an interrupted run?): remove it and run again")
        os.replace(tmp, a.json)


if __name__ == "__main__":
    main()
