"""ParaView reads nsf's XDMF files (issue #53, item 5): run with ParaView's Python, e.g.

    pvpython scripts/check_paraview.py RUN.h5 EXPORT.series.xdmf [--json OUT]

RUN.h5 is a run file with its sidecar RUN.xdmf beside it (`nsf simulate`, `nsf sweep`, `nsf rom`),
EXPORT.series.xdmf what `nsf export RUN.h5 -f xdmf -o DIR` wrote of the same run. For each it
checks, against the run file read with h5py: every time step, every particle, every array, and
the positions of the first and last frame. The sidecar is read with ParaView's "XDMF Reader" (the
Xdmf 2 one: the file's hyperslabs are what the Xdmf 3 library reads transposed, docs/OUTPUT.md);
the export with the reader ParaView picks for it (OpenDataFile). Also says what ParaView's default
reader makes of the sidecar. Exits 1 when a check fails. Needs Debian's paraview and python3-h5py
(not installed by scripts/install-deps.sh: ParaView is too large for CI)."""
import argparse
import json
import sys

import h5py
import numpy as np
from paraview import simple

# What `nsf export` writes of each frame (docs/VISUALISE.md), beside the positions.
EXPORT_ARRAYS = ["v", "speed", "von_mises", "tau", "F", "material", "object"]


def read(reader):
    """Per time step: points (n × 3) and point arrays {name: components}."""
    reader.UpdatePipelineInformation()
    steps = list(reader.TimestepValues)
    frames = []
    for t in (steps[0], steps[-1]):
        reader.UpdatePipeline(t)
        d = reader.GetClientSideObject().GetOutputDataObject(0)
        if d.IsA("vtkMultiBlockDataSet"):
            d = d.GetBlock(0)
        pts = np.array([d.GetPoint(i) for i in range(d.GetNumberOfPoints())])
        pd = d.GetPointData()
        arrays = {pd.GetArrayName(i): pd.GetArray(i).GetNumberOfComponents()
                  for i in range(pd.GetNumberOfArrays())}
        frames.append((pts, arrays))
    return steps, frames


def check(name, reader, run, want_arrays):
    steps, frames = read(reader)
    x = run["frames/x"]
    row = {"file": name, "reader": reader.GetXMLName(), "steps": len(steps),
           "run_frames": int(x.shape[0]), "particles": int(x.shape[1]), "problems": []}
    if len(steps) != x.shape[0]:
        row["problems"].append(f"{len(steps)} time steps for {x.shape[0]} frames")
    for (pts, arrays), k in zip(frames, (0, x.shape[0] - 1)):
        row.setdefault("arrays", sorted(arrays))
        if len(pts) != x.shape[1]:
            row["problems"].append(f"frame {k}: {len(pts)} points for {x.shape[1]} particles")
            continue
        err = float(np.abs(pts - x[k]).max())
        row[f"max_position_error_frame_{k}"] = err
        if err > 1e-5:
            row["problems"].append(f"frame {k}: positions off by {err}")
        missing = sorted(set(want_arrays) - set(arrays))
        if missing:
            row["problems"].append(f"frame {k}: arrays missing: {missing}")
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run")
    ap.add_argument("export")
    ap.add_argument("--json")
    a = ap.parse_args()
    run = h5py.File(a.run, "r")
    per_frame = [k for k in run["frames"] if k not in ("x", "time")]
    static = [k for k in run if isinstance(run[k], h5py.Dataset) and run[k].shape[:1] == (run["X"].shape[0],)]
    sidecar = a.run[:-3] + ".xdmf"
    rows = [check(sidecar, simple.XDMFReader(FileNames=[sidecar]), run, per_frame + static),
            check(a.export, simple.OpenDataFile(a.export), run, EXPORT_ARRAYS)]
    default = simple.OpenDataFile(sidecar)
    steps, frames = read(default)
    rows.append({"file": sidecar, "reader": default.GetXMLName() + " (ParaView's default)",
                 "steps": len(steps), "points": len(frames[0][0]),
                 "note": "reads no points: open the sidecar with 'XDMF Reader', or the export"})
    from paraview import servermanager
    out = {"paraview": servermanager.vtkSMProxyManager.GetParaViewSourceVersion(),
           "command": "pvpython scripts/check_paraview.py " + " ".join(sys.argv[1:]), "rows": rows}
    print(json.dumps(out, indent=2))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=2)
            f.write("\n")
    sys.exit(1 if any(r.get("problems") for r in rows) else 0)


if __name__ == "__main__":
    main()
