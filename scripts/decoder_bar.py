#!/usr/bin/env python3
"""Issue #24's bar for the per-point bases, checked from the rows in docs/results/eval/.

For each scene, the basis row named below (the configuration that scene is measured with:
docs/TRAINING.md, "Decoder families") against the scene's MLP row: held-out stress and affine
errors at most a fifth of the MLP's, or within 1.5x of the bases' own projection bound where that
is higher, and encoded delta no worse than the MLP's. Prints one line per scene; exits 1 if a
row is missing or misses the bar.

Usage: python3 scripts/decoder_bar.py [DOCS_DIR]   (default: docs)
"""
import json
import sys

# scene -> the basis row it is measured with (docs/results/eval/<row>.json) and how it was made
ROWS = {
    "metal_small": "metal_small_basis_dense5",  # scripts/decoder_table_dense.sh metal_small 5
    "sand_small": "sand_small_basis_dense5",  # ... sand_small 5
    "bread_small": "bread_small_basis_dense4",  # ... bread_small 4
    "toothpaste_small": "toothpaste_small_basis_dense4",  # ... toothpaste_small 4
    "squishy_ball_small": "squishy_ball_small_basis_dense4",  # ... squishy_ball_small 4
    "cake_small": "cake_small_basis_dense1_train24",  # ... cake_small 1 24
    "jelly_small": "jelly_small_basis_dense4",  # ... jelly_small 4
    "sand_paper": "sand_paper_basis_modes",  # nsf train --encoder modes (docs/TRAINING.md)
    "metal_paper": "metal_paper_basis_modes",  # likewise
}


def main():
    docs = sys.argv[1] if len(sys.argv) > 1 else "docs"
    failed = False
    for scene, row in ROWS.items():
        try:
            b = json.load(open(f"{docs}/results/eval/{row}.json"))
            m = json.load(open(f"{docs}/results/eval/{scene}_mlp.json"))
        except OSError as e:
            print(f"{scene}: missing row ({e})")
            failed = True
            continue
        bound = b["projection_bound"]
        checks = []
        for key in ("stress_error", "affine_error"):
            bar = max(m[key] / 5, 1.5 * bound[key])
            checks.append((key.split("_")[0], b[key], bar, b[key] <= bar))
        checks.append(("delta encoded", b["delta_encoded"], m["delta_encoded"],
                       b["delta_encoded"] <= m["delta_encoded"]))
        ok = all(c[3] for c in checks)
        failed |= not ok
        print(f"{scene:19s} {row:34s} " + "  ".join(
            f"{name} {100 * v:.2f} <= {100 * bar:.2f} %{'' if good else ' MISSED'}"
            for name, v, bar, good in checks))
    print("the bar holds on every scene" if not failed else "the bar is missed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
