#!/usr/bin/env python3
"""How well a latent velocity can determine the affine field C of a dataset made by `nsf sweep`.

C is MLS-MPM's velocity gradient. This script estimates grad v at every particle of the held-out
(test) frames by weighted linear least squares over its nearest neighbours in the frame (a
Gaussian weight of the distance, its width the mean neighbour distance), from these velocity
fields:

  true      the frame's own particle velocities (what any velocity-derived C could reach);
  modes K   those velocities projected onto the first K modes of the training runs' x - X (the
            velocity that K displacement coefficients can carry; with K = r, a latent velocity
            of the modes encoder);

It prints the relative Frobenius error against the
stored C over every test particle and frame (frame 0 skipped), as issue #24 measures C.

Usage: python3 c_velocity_gradient_bound.py DATASET_DIR K [K ...] [--neighbours N]
(needs numpy, scipy, h5py: Debian's python3-numpy, python3-scipy, python3-h5py)
"""
import argparse
import json

import h5py
import numpy as np
from scipy.spatial import cKDTree


def runs(d, manifest, split):
    for run in manifest["runs"]:
        if run["split"] == split:
            with h5py.File(f"{d}/{run['file']}") as f:
                yield {k: f[k][:] for k in ("X", "frames/x", "frames/v", "frames/C")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset")
    ap.add_argument("modes", type=int, nargs="+")
    ap.add_argument("--neighbours", type=int, default=27)
    a = ap.parse_args()
    manifest = json.load(open(f"{a.dataset}/manifest.json"))

    u = np.concatenate([(r["frames/x"] - r["X"][None]).reshape(len(r["frames/x"]), -1)
                        for r in runs(a.dataset, manifest, "train")])
    _, _, modes = np.linalg.svd(u - u.mean(0), full_matrices=False)

    def grad(x, v):  # (n, 3) positions and velocities -> (n, 3, 3) d v / d x
        dist, nb = cKDTree(x).query(x, k=a.neighbours)
        w = np.exp(-(dist / dist[:, 1:].mean()) ** 2)[..., None]
        dx, dv = x[nb] - x[:, None], v[nb] - v[:, None]
        moment = np.einsum("pki,pkj->pij", w * dx, dx)
        # a neighbourhood that is nearly flat (a torn sliver) gets a little isotropic weight
        moment += 1e-2 * np.trace(moment, axis1=1, axis2=2)[:, None, None] / 3 * np.eye(3)
        return np.einsum("pki,pkj->pij", w * dv, dx) @ np.linalg.inv(moment)

    names = ["true"] + [f"modes {k}" for k in a.modes]
    err = dict.fromkeys(names, 0.0)
    norm = 0.0
    for r in runs(a.dataset, manifest, "test"):
        for t in range(1, len(r["frames/x"])):
            C = r["frames/C"][t].reshape(-1, 3, 3)
            x, v = r["frames/x"][t], r["frames/v"][t]
            norm += np.sum(C**2)
            err["true"] += np.sum((grad(x, v) - C) ** 2)
            for k in a.modes:
                vk = (v.reshape(-1) @ modes[:k].T @ modes[:k]).reshape(-1, 3)
                err[f"modes {k}"] += np.sum((grad(x, vk) - C) ** 2)
    print(a.dataset, " | ".join(f"{n}: {100 * np.sqrt(e / norm):.1f} %" for n, e in err.items()))


if __name__ == "__main__":
    main()
