#!/usr/bin/env python3
"""Prints one line per run of a split of an `nsf sweep` dataset: its file name and μ ("-" for a
dataset without μ). Standard library only; used by the scripts beside it.

  python3 scripts/manifest_runs.py data/sand_small/manifest.json train
"""
import json
import sys

if len(sys.argv) != 3 or sys.argv[2] not in ("train", "test"):
    sys.exit(f"usage: {sys.argv[0]} MANIFEST train|test")
manifest = json.load(open(sys.argv[1]))
split = sys.argv[2]
runs = manifest.get("runs") or [{"file": f, "split": split} for f in manifest.get(split, [])]
for run in runs:
    if run.get("split") == split:
        print(run["file"], repr(run["mu"]) if "mu" in run else "-")
