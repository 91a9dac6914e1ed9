#!/usr/bin/env python3
"""A proxy of nsf's coefficient maps, for trying their inputs and training rows in seconds.

The latent is the training frames' first r principal components of x - X (as `nsf train
--encoder modes`), the latent velocity the particle velocities projected on the same modes; a
thin-plate spline (scipy) maps (latent, mu[, latent velocity]) of the training frames to the
field's first 64 modes, and is scored on the held-out (test) frames, as `nsf eval` scores a map:
relative Frobenius error over every test particle and frame, at each smoothing of a small grid.

  --every K        fit on every K-th frame of each training run only (fewer rows per run)
  --test-every K   score every K-th test frame (a dataset written K times as often as another
                   scores on the other's frames)
  --velocity       give the latent velocity to the stress map too (C's map always reads it)

Usage: python3 coefficient_map_proxy.py DATASET_DIR r {tau,C} [--every K] [--test-every K]
       [--velocity]   (needs numpy, scipy, h5py: Debian's python3-numpy, python3-scipy,
       python3-h5py)
"""
import argparse
import json

import h5py
import numpy as np
from scipy.interpolate import RBFInterpolator


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset")
    ap.add_argument("r", type=int)
    ap.add_argument("field", choices=("tau", "C"))
    ap.add_argument("--every", type=int, default=1)
    ap.add_argument("--test-every", type=int, default=1)
    ap.add_argument("--velocity", action="store_true")
    a = ap.parse_args()
    manifest = json.load(open(f"{a.dataset}/manifest.json"))

    def load(split, every):
        u, v, y, mu = [], [], [], []
        for run in manifest["runs"]:
            if run["split"] != split:
                continue
            with h5py.File(f"{a.dataset}/{run['file']}") as f:
                X, n = f["X"][:], f["frames/x"].shape[0]
                k = np.arange(0, n, every)
                u.append((f["frames/x"][:][k] - X[None]).reshape(len(k), -1))
                v.append(f["frames/v"][:][k].reshape(len(k), -1))
                y.append(f["frames/" + a.field][:][k].reshape(len(k), -1))
                mu += [run["mu"]] * len(k)
        return [np.concatenate(t) for t in (u, v, y)] + [np.array(mu)]

    U, V, Y, M = load("train", a.every)
    Ut, Vt, Yt, Mt = load("test", a.test_every)
    um = U.mean(0)
    modes = np.linalg.svd(U - um, full_matrices=False)[2][: a.r]
    ym = Y.mean(0)
    ymodes = np.linalg.svd(Y - ym, full_matrices=False)[2][:64]
    with_velocity = a.field == "C" or a.velocity

    def inputs(u, v, mu):
        cols = [(u - um) @ modes.T, mu[:, None]]
        if with_velocity:
            cols.append(v @ modes.T)
        return np.concatenate(cols, 1)

    F, Ft = inputs(U, V, M), inputs(Ut, Vt, Mt)
    shift, scale = F.mean(0), np.where(F.std(0) > 0, F.std(0), 1)
    F, Ft = (F - shift) / scale, (Ft - shift) / scale
    targets = (Y - ym) @ ymodes.T
    norm = np.linalg.norm(Yt)
    errors = []
    for s in (1e-6, 1e-4, 1e-2, 1e-1, 1):
        rbf = RBFInterpolator(F, targets, kernel="thin_plate_spline", smoothing=s)
        errors.append(f"{100 * np.linalg.norm(Yt - (rbf(Ft) @ ymodes + ym)) / norm:.1f} % (s {s:g})")
    print(f"{a.dataset} {a.field}, r {a.r}, every {a.every}: {len(F)} training rows; held out: "
          + ", ".join(errors))


if __name__ == "__main__":
    main()
