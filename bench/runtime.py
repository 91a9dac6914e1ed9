#!/usr/bin/env python3
"""The torch-free runtime against the one that linked LibTorch, side by side (issue #53, item 1).

Builds libnsf_runtime.so twice: from this tree with -DNSF_WITH_TORCH=OFF (no LibTorch on the
machine is needed), and from git ref AGAINST (default 7322459, the last runtime that linked
LibTorch) in a worktree, both Release and portable. Reports each library's size, the number of
shared libraries ldd lists, and, alternating the two REPS times on THREADS threads through
bench/runtime/step_timer.cpp: the load time (model file, scene, the stepper's set-up) and the
median time of a frame of advance_frame(), and the whole process's wall time (which includes
loading the shared libraries). The older runtime reads MODEL as it is, so MODEL must be a file
that nsf wrote before the run-time record (format version 7 or older: the models the demo made
before); the torch-free one reads a copy rewritten by `nsf upgrade`. Needs build/nsf. Writes
docs/results/bench/runtime_torch_free.json with --json.

    python3 bench/runtime.py [--model models/metal_small.nsf] [--scene scenes/paper/metal_small.json]
                             [--mu 0.1] [--reps 5] [--threads 1] [--json FILE]
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORK = os.path.join(ROOT, "build-rt")
COMMON = ["-DNSF_BUILD_TESTS=OFF", "-DNSF_BUILD_BENCH=OFF", "-DNSF_BUILD_PYTHON=OFF",
          "-DCMAKE_BUILD_TYPE=Release"]


def build(source, path, flags):
    print(f"runtime: building {path}", file=sys.stderr, flush=True)
    subprocess.run(["cmake", "-S", source, "-B", path, "-G", "Ninja"] + COMMON + flags,
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", path, "--target", "nsf_runtime"], check=True,
                   stdout=subprocess.DEVNULL)
    return path


def reference_tree(ref):
    tree = os.path.join(WORK, "ref-src")
    if os.path.isdir(tree):
        subprocess.run(["git", "-C", tree, "checkout", "-q", "--detach", ref], check=True)
    else:
        subprocess.run(["git", "-C", ROOT, "worktree", "add", "-f", "--detach", tree, ref],
                       check=True, stdout=subprocess.DEVNULL)
    return tree


def library_facts(build_dir):
    lib = os.path.realpath(os.path.join(build_dir, "libnsf_runtime.so"))
    ldd = subprocess.run(["ldd", lib], check=True, capture_output=True, text=True).stdout
    names = [line.split()[0] for line in ldd.splitlines() if line.strip()]
    heavy = [n for n in names if any(k in n for k in ("torch", "c10", "opencv", "blas"))]
    return {"bytes": os.path.getsize(lib), "ldd_count": len(names), "torch_or_opencv": heavy}


def build_step_timer(library_dir, timer):
    """bench/runtime/step_timer.cpp, linked against the libnsf_runtime.so in library_dir."""
    subprocess.run(["g++", "-O2", "-std=c++17", "-I", os.path.join(ROOT, "include"),
                    os.path.join(ROOT, "bench", "runtime", "step_timer.cpp"), "-o", timer,
                    "-L", library_dir, "-lnsf_runtime"], check=True)
    return timer


def time_steps(timer, library_dir, model, scene, mu, threads, loader=()):
    """step_timer's JSON object, with the runtime from library_dir (through `loader`, a command
    line the timer runs under, if any), and the process's wall time."""
    env = dict(os.environ, LD_LIBRARY_PATH=library_dir, OMP_NUM_THREADS=str(threads),
               OMP_WAIT_POLICY="passive")
    start = time.perf_counter()
    out = subprocess.run(list(loader) + [timer, model, scene, str(mu), str(threads)], check=True,
                         env=env, capture_output=True, text=True).stdout
    return json.loads(out), time.perf_counter() - start


def run(timer, build_dir, model, scene, mu, threads):
    r, process = time_steps(timer, build_dir, model, scene, mu, threads)
    return r["load_s"], statistics.median(r["frame_s"]), process, r["sum_positions"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--against", default="7322459")
    ap.add_argument("--model", default=os.path.join(ROOT, "models", "metal_small.nsf"))
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "paper", "metal_small.json"))
    ap.add_argument("--mu", type=float, default=0.1)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--json")
    a = ap.parse_args()
    nsf = os.path.join(ROOT, "build", "nsf")
    if not os.path.exists(nsf):
        sys.exit("runtime: build/nsf is missing (bash scripts/build.sh)")
    os.makedirs(WORK, exist_ok=True)
    builds = {
        "torch_free": build(ROOT, os.path.join(WORK, "new"), ["-DNSF_WITH_TORCH=OFF"]),
        "with_libtorch": build(reference_tree(a.against), os.path.join(WORK, "ref"), []),
    }
    models = {"torch_free": os.path.join(WORK, "model.nsf"), "with_libtorch": a.model}
    shutil.copyfile(a.model, models["torch_free"])
    subprocess.run([nsf, "upgrade", models["torch_free"], "--quiet"], check=True)
    timer = build_step_timer(builds["torch_free"], os.path.join(WORK, "step_timer"))
    facts = {name: library_facts(path) for name, path in builds.items()}
    loads = {name: [] for name in builds}
    frames = {name: [] for name in builds}
    processes = {name: [] for name in builds}
    sums = {}
    for rep in range(a.reps):
        for name, path in builds.items():
            load, frame, process, total = run(timer, path, models[name], a.scene, a.mu, a.threads)
            loads[name].append(load)
            frames[name].append(frame)
            processes[name].append(process)
            sums[name] = total
            print(f"runtime: rep {rep + 1}/{a.reps} {name}: load {load:.3f} s, "
                  f"frame {1e3 * frame:.2f} ms, process {process:.2f} s", file=sys.stderr,
                  flush=True)
    rows = []
    for name in builds:
        rows.append({
            "runtime": name, **facts[name],
            "load_s_median": statistics.median(loads[name]),
            "load_s_min": min(loads[name]), "load_s_max": max(loads[name]),
            "frame_s_median": statistics.median(frames[name]),
            "frame_s_min": min(frames[name]), "frame_s_max": max(frames[name]),
            "process_s_median": statistics.median(processes[name]),
            "process_s_min": min(processes[name]), "process_s_max": max(processes[name]),
            "sum_positions": sums[name]})
    ratio = rows[0]["frame_s_median"] / rows[1]["frame_s_median"]
    print(f"Torch-free runtime against LibTorch-linked ({a.against}), {os.path.basename(a.model)} "
          f"at mu = {a.mu}, {a.threads} thread(s), {a.reps} alternated runs each:\n")
    print("| runtime | size | ldd | load, s (min-max) | frame, ms (min-max) | process, s (min-max) |")
    print("|---|---:|---:|---|---|---|")
    for r in rows:
        print(f"| {r['runtime']} | {r['bytes'] / 1e6:.2f} MB | {r['ldd_count']} | "
              f"{r['load_s_median']:.3f} ({r['load_s_min']:.3f}-{r['load_s_max']:.3f}) | "
              f"{1e3 * r['frame_s_median']:.2f} ({1e3 * r['frame_s_min']:.2f}-"
              f"{1e3 * r['frame_s_max']:.2f}) | {r['process_s_median']:.2f} "
              f"({r['process_s_min']:.2f}-{r['process_s_max']:.2f}) |")
    print(f"\nframe time, torch-free over LibTorch-linked: {ratio:.3f}; final positions "
          f"{'agree' if rows[0]['sum_positions'] == rows[1]['sum_positions'] else 'differ'}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"command": "python3 bench/runtime.py " + " ".join(sys.argv[1:]),
                       "against": a.against, "model": os.path.basename(a.model), "mu": a.mu,
                       "threads": a.threads, "reps": a.reps, "rows": rows,
                       "frame_ratio": ratio}, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()
