#!/usr/bin/env python3
"""The portable build against -march=native, side by side (issue #53, item 2).

Builds, without LibTorch, the full-order engine's benchmark (bench/mpm_throughput.cpp) and the
runtime (libnsf_runtime.so) twice: as every artefact is built (the x86-64-v2 baseline, with the
hot kernels' v3 and v4 clones picked at run time, src/core/isa.h, and the runtime's x86-64-v3
copy in glibc-hwcaps/, cmake/hwcaps.cmake) and with NSF_NATIVE=ON. Then, on one thread, REPS
alternated runs of each:
  - mpm: each scene's full-order throughput (median, min-max) and the ratio of the medians;
  - rom: the reduced-order step through the runtime (bench/runtime/step_timer.cpp, MODEL at MU):
    the median frame time of the portable runtime as the loader picks it on this CPU, of its
    baseline copy alone (the loader told to skip glibc-hwcaps/), and of the native build.
  - tool (--only tool, not in the default run: it builds nsf with LibTorch twice, or takes two
    build folders from --tool-builds): `nsf rom MODEL SCENE --mu MU -j 1`, both engines in one
    process, from the portable tool (its clones picked on this CPU) and the native one.
Writes docs/results/bench/isa_mpm.json, isa_rom.json and isa_tool.json with --json, --rom-json
and --tool-json.

    python3 bench/isa.py [--reps 5] [--step-scale 0.5] [--only mpm|rom|tool]
                         [--model models/metal_small.nsf] [--scene scenes/paper/metal_small.json]
                         [--mu 0.1] [--json docs/results/bench/isa_mpm.json]
                         [--rom-json docs/results/bench/isa_rom.json]
                         [--tool-builds PORTABLE_DIR NATIVE_DIR]
                         [--tool-json docs/results/bench/isa_tool.json]
"""
import argparse
import json
import os
import platform
import re
import statistics
import subprocess
import sys

from runtime import build_step_timer, time_steps  # bench/runtime.py: the runtime's step timer

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIGS = {"portable": [], "native": ["-DNSF_NATIVE=ON"]}


LOADER = "/lib64/ld-linux-x86-64.so.2"


def build(name, flags, targets, torch=False):
    path = os.path.join(ROOT, "build-isa", name)
    common = ["-DNSF_WITH_TORCH=" + ("ON" if torch else "OFF"), "-DNSF_BUILD_TESTS=OFF",
              "-DNSF_BUILD_PYTHON=OFF", "-DCMAKE_BUILD_TYPE=Release"]
    subprocess.run(["cmake", "-S", ROOT, "-B", path, "-G", "Ninja"] + common + flags,
                   check=True, stdout=subprocess.DEVNULL)
    print(f"isa: building {name} in {path}", file=sys.stderr, flush=True)
    subprocess.run(["cmake", "--build", path, "--target"] + targets, check=True,
                   stdout=subprocess.DEVNULL)
    return path


def run_rom(timer, library_dir, model, scene, mu, baseline_only=False):
    """The median frame time of the reduced-order step, and the copy of the runtime that ran."""
    # The loader told to search no glibc-hwcaps folder takes the baseline copy.
    loader = [LOADER, "--glibc-hwcaps-mask", "x86-64-v2"] if baseline_only else []
    r, _ = time_steps(timer, library_dir, model, scene, mu, 1, loader)
    return statistics.median(r["frame_s"]), r.get("build_arch", "?")


def rom_rows(builds, a):
    """The reduced-order step: portable (as loaded here), its baseline copy, native."""
    if not os.path.isfile(a.model):
        print(f"isa: no {a.model}: the reduced-order rows need a model (scripts/demo.sh makes "
              f"models/metal_small.nsf)", file=sys.stderr)
        return None
    timer = build_step_timer(builds["portable"], os.path.join(ROOT, "build-isa", "step_timer"))
    variants = {"portable": (builds["portable"], False),
                "portable_baseline": (builds["portable"], True),
                "native": (builds["native"], False)}
    frames = {name: [] for name in variants}
    arch = {}
    for rep in range(a.reps):
        for name, (path, baseline) in variants.items():
            frame, arch[name] = run_rom(timer, path, a.model, a.scene, a.mu, baseline)
            frames[name].append(frame)
        print(f"isa: rom {rep + 1}/{a.reps} rounds", file=sys.stderr, flush=True)
    native = statistics.median(frames["native"])
    rows = [{"runtime": name, "build_arch": arch[name], "frame_s": frames[name],
             "ratio_to_native": statistics.median(frames[name]) / native} for name in variants]
    print(f"\nReduced-order step through the runtime, {os.path.basename(a.model)} at mu = {a.mu}, "
          f"ms a frame on one thread, {a.reps} alternated runs each ({cpu_name()}): "
          f"`python3 bench/isa.py --only rom --reps {a.reps}`\n")
    print("| runtime | copy loaded | frame, ms (min-max) | native / this (speed) |")
    print("|---|---|---|---|")
    for r in rows:
        v = r["frame_s"]
        print(f"| {r['runtime']} | {r['build_arch']} | {1e3 * statistics.median(v):.2f} "
              f"({1e3 * min(v):.2f}-{1e3 * max(v):.2f}) | {1 / r['ratio_to_native']:.3f} |")
    return {"command": f"python3 bench/isa.py --only rom --reps {a.reps} --mu {a.mu}",
            "model": os.path.basename(a.model), "scene": os.path.relpath(a.scene, ROOT),
            "mu": a.mu, "cpu": cpu_name(), "threads": 1, "rows": rows}


TOOL_TIMES = ("rom_seconds", "inversion_seconds", "inference_seconds", "mpm_seconds",
              "fom_seconds")


def run_tool(nsf, a, out):
    """One `nsf rom` run on one thread: its JSON row."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive")
    if os.path.exists(out):
        os.remove(out)
    subprocess.run([nsf, "rom", a.model, a.scene, "--mu", str(a.mu), "-j", "1", "-q",
                    "--json", out], check=True, env=env, stdout=subprocess.DEVNULL)
    with open(out) as f:
        return json.load(f)


def tool_rows(a):
    """`nsf rom` from the portable tool and the native one, alternated."""
    if not os.path.isfile(a.model):
        print(f"isa: no {a.model}: the tool's rows need a model (scripts/demo.sh makes "
              f"models/metal_small.nsf)", file=sys.stderr)
        return None
    if a.tool_builds:
        dirs = dict(zip(CONFIGS, a.tool_builds))
    else:
        dirs = {name: build("tool-" + name, flags, ["nsf"], torch=True)
                for name, flags in CONFIGS.items()}
    runs = {name: [] for name in dirs}
    out = os.path.join(ROOT, "build-isa", "tool_row.json")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    for rep in range(a.reps):
        for name, path in dirs.items():
            runs[name].append(run_tool(os.path.join(path, "nsf"), a, out))
        print(f"isa: tool {rep + 1}/{a.reps} rounds", file=sys.stderr, flush=True)
    med = lambda name, key: statistics.median(r[key] / r["frames"] for r in runs[name])
    rows = []
    for name in dirs:
        row = {"tool": name, "kernels": run_isa(os.path.join(dirs[name], "nsf"))}
        for key in TOOL_TIMES:
            row[key.replace("_seconds", "_ms_per_frame")] = [1e3 * r[key] / r["frames"]
                                                            for r in runs[name]]
        row["speedup"] = [r["speedup"] for r in runs[name]]
        row["delta"] = [r["delta"] for r in runs[name]]
        row["rom_ratio_to_native"] = med(name, "rom_seconds") / med("native", "rom_seconds")
        rows.append(row)
    builds = f" --tool-builds {' '.join(a.tool_builds)}" if a.tool_builds else ""
    print(f"\n`nsf rom {os.path.basename(a.model)} --mu {a.mu} -j 1`, ms a frame, {a.reps} "
          f"alternated runs each ({cpu_name()}): `python3 bench/isa.py --only tool --reps "
          f"{a.reps}{builds}`\n")
    print("| nsf | kernels | reduced order (min-max) | inversion | inference | MPM on N | "
          "full order | speed-up (min-max) | native / this (ROM speed) |")
    print("|---|---|---|---|---|---|---|---|---|")
    rng = lambda v: f"{statistics.median(v):.2f} ({min(v):.2f}-{max(v):.2f})"
    for r in rows:
        m = lambda key: f"{statistics.median(r[key]):.2f}"
        print(f"| {r['tool']} | {r['kernels']} | {rng(r['rom_ms_per_frame'])} | "
              f"{m('inversion_ms_per_frame')} | {m('inference_ms_per_frame')} | "
              f"{m('mpm_ms_per_frame')} | {m('fom_ms_per_frame')} | "
              f"{statistics.median(r['speedup']):.2f}x ({min(r['speedup']):.2f}-"
              f"{max(r['speedup']):.2f}) | {1 / r['rom_ratio_to_native']:.3f} |")
    return {"command": f"python3 bench/isa.py --only tool --reps {a.reps} --mu {a.mu}{builds}",
            "model": os.path.basename(a.model), "scene": os.path.relpath(a.scene, ROOT),
            "mu": a.mu, "cpu": cpu_name(), "threads": 1, "rows": rows}


def run_isa(nsf):
    """The clone of the hot kernels that a tool runs on this CPU (`nsf --version`)."""
    text = subprocess.run([nsf, "--version"], check=True, capture_output=True, text=True).stdout
    m = re.search(r"hot kernels[^:]*: *(.+)", text)
    return m.group(1).strip() if m else "?"


def write_json(path, doc):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = path + ".tmp"
    try:
        with open(tmp, "x") as f:
            json.dump(doc, f, indent=1)
    except FileExistsError:
        sys.exit(f"isa: {tmp} exists (an interrupted run?): remove it and run again")
    os.replace(tmp, path)


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


def mpm_rows(builds, a):
    binaries = {name: os.path.join(path, "mpm_throughput") for name, path in builds.items()}
    samples = {name: {} for name in CONFIGS}
    for rep in range(a.reps):
        for name, binary in binaries.items():
            for scene, value in run(binary, a.step_scale).items():
                samples[name].setdefault(scene, []).append(value)
        print(f"isa: mpm {rep + 1}/{a.reps} rounds", file=sys.stderr, flush=True)
    rows = []
    for scene in samples["portable"]:
        p, n = samples["portable"][scene], samples["native"].get(scene, [])
        if not n:
            continue
        rows.append({"scene": scene, "portable": p, "native": n,
                     "ratio": statistics.median(p) / statistics.median(n)})
    print(f"Full-order throughput, particle-steps/s on one thread, {a.reps} alternated runs "
          f"each ({cpu_name()}): `python3 bench/isa.py --only mpm --reps {a.reps}`\n")
    print("| scene | portable (x86-64-v2 + clones) | -march=native | portable / native |")
    print("|---|---|---|---|")
    fmt = lambda v: (f"{statistics.median(v) / 1e6:.2f}M "
                     f"({min(v) / 1e6:.2f}-{max(v) / 1e6:.2f})")
    for r in rows:
        print(f"| {r['scene']} | {fmt(r['portable'])} | {fmt(r['native'])} | {r['ratio']:.3f} |")
    return {"command": f"python3 bench/isa.py --only mpm --reps {a.reps} --step-scale {a.step_scale}",
            "cpu": cpu_name(), "threads": 1, "rows": rows}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--step-scale", type=float, default=0.5)
    ap.add_argument("--only", choices=["mpm", "rom", "tool"])
    ap.add_argument("--model", default=os.path.join(ROOT, "models", "metal_small.nsf"))
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "paper", "metal_small.json"))
    ap.add_argument("--mu", type=float, default=0.1)
    ap.add_argument("--json", help="write the full-order rows here")
    ap.add_argument("--rom-json", help="write the reduced-order rows here")
    ap.add_argument("--tool-builds", nargs=2, metavar=("PORTABLE_DIR", "NATIVE_DIR"),
                    help="time these builds' nsf (a default build and a -DNSF_NATIVE=ON one) "
                         "instead of building both under build-isa/")
    ap.add_argument("--tool-json", help="write the tool's rows here")
    a = ap.parse_args()
    if a.reps < 1:
        ap.error("--reps must be at least 1")
    if a.only == "tool":
        doc = tool_rows(a)
        if doc and a.tool_json:
            write_json(a.tool_json, doc)
        return
    targets = {"mpm": ["mpm_throughput"], "rom": ["nsf_runtime"], None: ["mpm_throughput", "nsf_runtime"]}
    builds = {name: build(name, flags, targets[a.only]) for name, flags in CONFIGS.items()}
    if a.only in (None, "mpm"):
        doc = mpm_rows(builds, a)
        if a.json:
            write_json(a.json, doc)
    if a.only in (None, "rom"):
        doc = rom_rows(builds, a)
        if doc and a.rom_json:
            write_json(a.rom_json, doc)


if __name__ == "__main__":
    main()
