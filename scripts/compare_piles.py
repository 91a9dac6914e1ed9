#!/usr/bin/env python3
"""Frame-by-frame comparison of two runs: written for an axisymmetric pile (the sand column
scenes); --extent and the von Mises column serve other shapes too (the metal frame).

Reads the PLY frames that `nsf export RUN.h5 -f ply -o DIR` writes (standard library only: no
h5py or numpy needed) and prints, per frame, for a run against its ground truth:
  - delta of that frame alone (eq. 11 restricted to one frame),
  - mean squared speed, mean height and top height of each run,
  - radius of gyration about the vertical axis through --axis,
  - the position error split into radial, tangential and vertical parts about that axis,
  - the mean von Mises stress of each run, when both files carry it (nsf export does),
  - with --extent AXIS, each run's extent along x, y or z (1st to 99th percentile).
With --regions FRAME it also prints where the particles of each part of the rest shape (bins of
initial height and radius) end up in both runs at that frame.

  nsf export out/report/sand_paper_q1_rom.h5 -f ply -o /tmp/rom
  nsf export out/report/sand_paper_q1_full_order.h5 -f ply -o /tmp/truth
  python3 scripts/compare_piles.py /tmp/rom /tmp/truth --floor 0.1 --regions 30
"""
import argparse
import math
import os
import re
import struct
import sys

# PLY type names, old and sized (nsf export writes float32, float64 and uint16).
TYPES = {"float": "f", "float32": "f", "double": "d", "float64": "d", "ushort": "H",
         "uint16": "H", "uchar": "B", "uint8": "B", "int": "i", "int32": "i", "uint": "I",
         "uint32": "I"}
FRAME = re.compile(r"_(\d+)\.ply$")


def read_ply(path):
    """Rows of (x, y, z, v_x, v_y, v_z, von Mises or None) from a binary little-endian PLY written
    by nsf export."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    count, props = 0, []
    for line in data[:end].decode().split("\n"):
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count = int(words[2])
        elif words[:1] == ["property"]:
            props.append((words[1], words[2]))
    names = [name for _, name in props]
    # v_x v_y v_z (docs/VISUALISE.md); nsf exports before that named them vx vy vz.
    velocity = ["v_x", "v_y", "v_z"] if "v_x" in names else ["vx", "vy", "vz"]
    need = ["x", "y", "z"] + velocity
    if any(n not in names for n in need):
        sys.exit(f"{path}: expected the properties {need}, found {names}")
    fmt = "<" + "".join(TYPES[t] for t, _ in props)
    cols = [names.index(n) for n in need]
    vm = names.index("von_mises") if "von_mises" in names else None
    rows = struct.iter_unpack(fmt, data[end : end + count * struct.calcsize(fmt)])
    return [tuple(r[c] for c in cols) + (None if vm is None else r[vm],) for r in rows]


def frame_files(directory):
    """{frame number: file name} of the frames `nsf export` wrote there (<run>_0012.ply)."""
    files = {}
    for f in sorted(os.listdir(directory)):
        m = FRAME.search(f)
        if not m:
            continue
        k = int(m.group(1))
        if k in files:
            sys.exit(f"{directory}: {files[k]} and {f} are both frame {k}: one run per directory")
        files[k] = f
    if not files:
        sys.exit(f"{directory}: no .ply frames (write them with `nsf export RUN -f ply -o DIR`)")
    return dict(sorted(files.items()))


def summary(rows, ax, az, extent_axis):
    n = len(rows)
    speed2 = sum(r[3] ** 2 + r[4] ** 2 + r[5] ** 2 for r in rows) / n
    height = sum(r[1] for r in rows) / n
    top = max(r[1] for r in rows)
    gyration = math.sqrt(sum((r[0] - ax) ** 2 + (r[2] - az) ** 2 for r in rows) / n)
    von_mises = None if rows[0][6] is None else sum(r[6] for r in rows) / n
    extent = None
    if extent_axis is not None:  # percentiles, so that a few stray particles do not set it
        c = sorted(r[extent_axis] for r in rows)
        extent = c[int(0.99 * (n - 1))] - c[int(0.01 * (n - 1))]
    return speed2, height, top, gyration, von_mises, extent


def error_parts(run, truth, ax, az):
    """Squared error sums: total, radial, tangential, vertical; and the truth's squared norm."""
    tot = rad = tan = ver = norm = 0.0
    for a, b in zip(run, truth):
        ex, ey, ez = a[0] - b[0], a[1] - b[1], a[2] - b[2]
        norm += b[0] ** 2 + b[1] ** 2 + b[2] ** 2
        tot += ex * ex + ey * ey + ez * ez
        ver += ey * ey
        dx, dz = b[0] - ax, b[2] - az
        r = math.hypot(dx, dz)
        if r > 1e-9:
            ux, uz = dx / r, dz / r
            rad += (ex * ux + ez * uz) ** 2
            tan += (ez * ux - ex * uz) ** 2
    return tot, rad, tan, ver, norm


def regions(rest, run, truth, ax, az, floor, h_bins, r_bins):
    heights = [X[1] - floor for X in rest]
    radii = [math.hypot(X[0] - ax, X[2] - az) for X in rest]
    h_step = (max(heights) + 1e-9) / h_bins
    r_step = (max(radii) + 1e-9) / r_bins
    acc = {}
    for h, r0, a, b in zip(heights, radii, run, truth):
        key = (min(int(h / h_step), h_bins - 1), min(int(r0 / r_step), r_bins - 1))
        e = acc.setdefault(key, [0, 0.0, 0.0, 0.0, 0.0])
        e[0] += 1
        e[1] += math.hypot(a[0] - ax, a[2] - az)
        e[2] += math.hypot(b[0] - ax, b[2] - az)
        e[3] += a[1] - floor
        e[4] += b[1] - floor
    print(f"\nwhere each part of the rest shape ends up (mm; run/truth): rows are initial height "
          f"bins of {1000 * h_step:.0f} mm from the bottom, columns initial radius bins of "
          f"{1000 * r_step:.0f} mm from the axis")
    for hb in range(h_bins - 1, -1, -1):
        cells = []
        for rb in range(r_bins):
            e = acc.get((hb, rb))
            if not e:
                cells.append(" " * 30)
                continue
            k = 1000.0 / e[0]
            cells.append(f"r {e[1] * k:4.0f}/{e[2] * k:4.0f} height {e[3] * k:4.0f}/{e[4] * k:4.0f}")
        print(f"h{hb}  " + " | ".join(cells))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("run", help="PLY frames of the run (e.g. the ROM's)")
    p.add_argument("truth", help="PLY frames of the ground truth, same particles and frames")
    p.add_argument("--axis", type=float, nargs=2, default=[0.5, 0.5], metavar=("X", "Z"),
                   help="the pile's vertical axis (default 0.5 0.5, the sand scenes)")
    p.add_argument("--floor", type=float, default=0.0, help="height of the floor (m)")
    p.add_argument("--every", type=int, default=3, help="print every k-th frame (and the last)")
    p.add_argument("--regions", type=int, metavar="FRAME", help="the region table at this frame")
    p.add_argument("--extent", choices="xyz", help="also print each run's extent along this axis")
    a = p.parse_args()
    extent_axis = None if a.extent is None else "xyz".index(a.extent)
    ax, az = a.axis
    files = frame_files(a.truth)
    run_files = frame_files(a.run)
    if list(run_files) != list(files):
        sys.exit(f"{a.run} and {a.truth} hold different frames")
    print("frame  delta_k | speed^2 run/truth | height run/truth | top run/truth | "
          "gyration run/truth | rms error mm: radial tangential vertical"
          + ("" if a.extent is None else f" | {a.extent} extent run/truth")
          + " | von Mises run/truth")
    total = norm_total = 0.0
    for k, frame in enumerate(files):
        run = read_ply(os.path.join(a.run, run_files[frame]))
        truth = read_ply(os.path.join(a.truth, files[frame]))
        if len(run) != len(truth):
            sys.exit(f"frame {frame}: {len(run)} particles in the run, {len(truth)} in the truth")
        tot, rad, tan, ver, norm = error_parts(run, truth, ax, az)
        if k > 0:  # eq. 11 sums over n = 1 … N: frame 0 is the initial state
            total += tot
            norm_total += norm
        if k % a.every and k != len(files) - 1:
            continue
        s, t = summary(run, ax, az, extent_axis), summary(truth, ax, az, extent_axis)
        n = len(run)
        line = (f"{k:5d}  {100 * math.sqrt(tot / norm):6.2f}% | {s[0]:.4f}/{t[0]:.4f} | "
                f"{s[1] - a.floor:+.4f}/{t[1] - a.floor:+.4f} | {s[2] - a.floor:.4f}/{t[2] - a.floor:.4f}"
                f" | {s[3]:.4f}/{t[3]:.4f} | {1000 * math.sqrt(rad / n):5.1f} "
                f"{1000 * math.sqrt(tan / n):5.1f} {1000 * math.sqrt(ver / n):5.1f}")
        if extent_axis is not None:
            line += f" | {s[5]:.4f}/{t[5]:.4f}"
        if s[4] is not None and t[4] is not None:
            line += f" | {s[4]:.0f}/{t[4]:.0f}"
        print(line)
    print(f"delta over frames 1 to {len(files) - 1} (eq. 11): {100 * math.sqrt(total / norm_total):.2f}%")
    if a.regions is not None:
        if a.regions not in files:
            sys.exit(f"--regions {a.regions}: no frame {a.regions}")
        rest = read_ply(os.path.join(a.truth, next(iter(files.values()))))
        regions(rest, read_ply(os.path.join(a.run, run_files[a.regions])),
                read_ply(os.path.join(a.truth, files[a.regions])), ax, az, a.floor, 5, 5)


if __name__ == "__main__":
    main()
