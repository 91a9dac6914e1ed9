#!/usr/bin/env python3
"""An MLP model through the runtime and its MLP plugin, against the tool's `nsf rom` (issue #53).

Reports the plugin's size and the number of shared libraries ldd lists for it (beside the
runtime's, which links no LibTorch), then alternates, REPS times on THREADS threads: the runtime
(bench/runtime/step_timer.cpp, linked against BUILD/libnsf_runtime.so, which opens
BUILD/libnsf_mlp.so for the model) and `BUILD/nsf rom MODEL SCENE --mu MU --no-full-order` on the
same model and scene. For each: the load (the runtime's constructor: model file, plugin, scene and
set-up; the tool's stepper set-up alone, as its report prints it), the time of a ROM step (the runtime's
median frame over its steps per frame; the tool's ROM time over its steps) and the process's wall
time, each as a median with its min-max. Without --model, trains a tiny MLP model of
scenes/examples/rom_tiny.json first (seconds). Writes the rows as JSON with --json.

    python3 bench/runtime_mlp.py [--build build] [--model M --scene S --mu MU] [--reps 5]
                                 [--threads 1] [--json FILE]
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from runtime import ROOT, build_step_timer, library_facts, time_steps


def plugin_facts(build_dir):
    plugin = os.path.join(build_dir, "libnsf_mlp.so")
    if not os.path.exists(plugin):
        sys.exit(f"runtime_mlp: no {plugin} (build the nsf_mlp target with LibTorch)")
    ldd = subprocess.run(["ldd", plugin], check=True, capture_output=True, text=True).stdout
    names = [line.split()[0] for line in ldd.splitlines() if line.strip()]
    return {"bytes": os.path.getsize(plugin), "ldd_count": len(names),
            "torch": [n for n in names if "torch" in n or "c10" in n]}


def tiny_model(nsf, work):
    scene = os.path.join(ROOT, "scenes", "examples", "rom_tiny.json")
    model = os.path.join(work, "tiny_mlp.nsf")
    data = os.path.join(work, "data")
    print("runtime_mlp: training a tiny MLP model of rom_tiny", file=sys.stderr, flush=True)
    subprocess.run([nsf, "sweep", scene, "--out", data, "--jobs", "2", "-j", "1", "-q"],
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run([nsf, "train", data, "--out", model, "--decoder", "mlp", "-r", "2", "--depth",
                    "2", "--widths", "32,16,16", "--encoder-hidden", "8", "--steps", "100,50,50",
                    "--refine-latents", "0", "-j", "2", "-q", "--frames-per-batch", "2",
                    "--particles-per-frame", "64"], check=True, stdout=subprocess.DEVNULL)
    return model, scene, 1.0


def run_runtime(timer, build_dir, model, scene, mu, threads):
    r, process = time_steps(timer, build_dir, model, scene, mu, threads)
    return r["load_s"], statistics.median(r["frame_s"]) / r["steps_per_frame"], process


def run_tool(nsf, model, scene, mu, threads, work):
    row = os.path.join(work, "rom_row.json")
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_WAIT_POLICY="passive")
    start = time.perf_counter()
    out = subprocess.run([nsf, "rom", model, scene, "--mu", str(mu), "--no-full-order",
                          "--threads", str(threads), "--json", row], check=True, env=env,
                         capture_output=True, text=True).stdout
    process = time.perf_counter() - start
    with open(row) as f:
        j = json.load(f)
    setup = re.search(r"setup ([0-9.]+) s", out)
    if not setup:
        sys.exit("runtime_mlp: no set-up time in nsf rom's report:\n" + out)
    steps = j["frames"] * j["rom_steps_per_frame"]
    return float(setup.group(1)), j["rom_seconds"] / steps, process


def spread(values):
    return {"median": statistics.median(values), "min": min(values), "max": max(values)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--model")
    ap.add_argument("--scene")
    ap.add_argument("--mu", type=float)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--json")
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    nsf = os.path.join(build, "nsf")
    if not os.path.exists(nsf):
        sys.exit(f"runtime_mlp: {nsf} is missing (bash scripts/build.sh)")
    work = tempfile.mkdtemp(prefix="nsf_runtime_mlp_")
    try:
        measure(a, nsf, build, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def measure(a, nsf, build, work):
    if a.model:
        if not a.scene or a.mu is None:
            sys.exit("runtime_mlp: --model needs --scene and --mu")
        model, scene, mu = os.path.abspath(a.model), os.path.abspath(a.scene), a.mu
    else:
        model, scene, mu = tiny_model(nsf, work)
    timer = build_step_timer(build, os.path.join(work, "step_timer"))
    facts = {"runtime": library_facts(build), "plugin": plugin_facts(build)}
    times = {name: {"load_s": [], "step_s": [], "process_s": []} for name in ("runtime", "tool")}
    for rep in range(a.reps):
        for name in ("runtime", "tool"):
            if name == "runtime":
                got = run_runtime(timer, build, model, scene, mu, a.threads)
            else:
                got = run_tool(nsf, model, scene, mu, a.threads, work)
            for key, value in zip(("load_s", "step_s", "process_s"), got):
                times[name][key].append(value)
            print(f"runtime_mlp: rep {rep + 1}/{a.reps} {name}: load {got[0]:.3f} s, "
                  f"step {1e3 * got[1]:.3f} ms, process {got[2]:.2f} s", file=sys.stderr,
                  flush=True)
    rows = {name: {k: spread(v) for k, v in t.items()} for name, t in times.items()}
    ratio = rows["runtime"]["step_s"]["median"] / rows["tool"]["step_s"]["median"]
    print(f"An MLP model through the runtime and its plugin against nsf rom, "
          f"{os.path.basename(model)} at mu = {mu}, {a.threads} thread(s), {a.reps} alternated "
          f"runs each:\n")
    for name in ("runtime", "plugin"):
        f = facts[name]
        print(f"lib{'nsf_runtime' if name == 'runtime' else 'nsf_mlp'}.so: "
              f"{f['bytes'] / 1e6:.2f} MB, ldd lists {f['ldd_count']} libraries")
    print("\n| run | load, s (min-max) | step, ms (min-max) | process, s (min-max) |")
    print("|---|---|---|---|")
    for name, label in (("runtime", "runtime + plugin"), ("tool", "nsf rom")):
        r = rows[name]
        print(f"| {label} | {r['load_s']['median']:.3f} ({r['load_s']['min']:.3f}-"
              f"{r['load_s']['max']:.3f}) | {1e3 * r['step_s']['median']:.3f} "
              f"({1e3 * r['step_s']['min']:.3f}-{1e3 * r['step_s']['max']:.3f}) | "
              f"{r['process_s']['median']:.2f} ({r['process_s']['min']:.2f}-"
              f"{r['process_s']['max']:.2f}) |")
    print("\nload: the runtime's constructor (model file through the plugin, scene, set-up); "
          "nsf rom's\nstepper set-up alone, as its report prints it (its model load is in the "
          "process time).")
    print(f"step time, runtime + plugin over nsf rom: {ratio:.3f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"command": "python3 bench/runtime_mlp.py " + " ".join(sys.argv[1:]),
                       "model": os.path.basename(model), "mu": mu, "threads": a.threads,
                       "reps": a.reps, "libraries": facts, "rows": rows, "step_ratio": ratio},
                      f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()
