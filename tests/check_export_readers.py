"""Every file nsf writes for other tools, read back by the real readers, against the run file.

Usage: check_export_readers.py NSF READER, READER one of
  meshio  meshio reads every exported frame (VTU, legacy VTK, PLY) and the XDMF export through its
          xdmf.TimeSeriesReader: every array, every time step, the run file's values
  vtk     VTK's vtkXMLUnstructuredGridReader (VTU), vtkUnstructuredGridReader (legacy VTK) and
          vtkPLYReader (PLY, which keeps positions only: docs/VISUALISE.md)
  xdmf3   the Xdmf3 library (what ParaView's XDMF3 readers build on), through its C interface:
          the XDMF export whole; the run file's XDMF sidecar's structure, times, connectivity and
          static arrays, and its hyperslabs as XDMF defines them (its per-frame hyperslabs are not
          read through this library, which reads them transposed: docs/OUTPUT.md)
Run by ctest (export_readers_*) with /usr/bin/python3, the interpreter of Debian's python3-meshio,
python3-vtk9 and python3-h5py. Exits 77 (ctest: skipped), saying which package is missing, when
the reader is not installed; scripts/install-deps.sh installs them all.
"""

import ctypes
import ctypes.util
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

SKIP = 77

SCENE = {
    "name": "two_bodies",
    "simulation": {"domain_lo": [0, 0, 0], "domain_hi": [1, 1, 1], "dx": 0.05, "dt": 1e-3,
                   "frames": 4, "substeps": 10, "ppc": 2, "density": 1000},
    "objects": [
        {"shape": {"type": "box", "min": [0.2, 0.2, 0.4], "max": [0.4, 0.35, 0.6]},
         "material": {"type": "fixed_corotated", "E": 2e4, "nu": 0.3}, "velocity": [1, -1, 0]},
        {"shape": {"type": "sphere", "center": [0.65, 0.3, 0.5], "radius": 0.1},
         "material": {"type": "drucker_prager", "E": 2e4, "nu": 0.3, "friction_angle": 30}},
    ],
    "colliders": [{"type": "plane", "point": [0, 0.15, 0], "normal": [0, 1, 0]}],
}

NAMES = ["v", "speed", "von_mises", "tau", "F", "material", "object"]  # docs/VISUALISE.md


def need(module, package):
    try:
        return __import__(module)
    except ImportError:
        print(f"SKIPPED: the Python module '{module}' is missing (Debian package {package}; "
              "scripts/install-deps.sh installs it)")
        sys.exit(SKIP)


class Failures:
    def __init__(self):
        self.count = 0

    def check(self, ok, what):
        if not ok:
            self.count += 1
            print(f"FAIL: {what}")


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stdout}")


def truth(h5py, np, path):
    """The run file's frames, and the derived arrays as docs/VISUALISE.md defines them."""
    with h5py.File(path, "r") as f:
        t = {k: f["/frames/" + k][...] for k in ("x", "v", "C", "F", "tau", "time")}
        t["material"], t["object"] = f["/material"][...], f["/object"][...]
    s = t["tau"]
    dev = s[..., :3] - s[..., :3].mean(axis=-1, keepdims=True)
    t["von_mises"] = np.sqrt(1.5 * ((dev**2).sum(-1) + 2 * (s[..., 3:] ** 2).sum(-1)))
    t["speed"] = np.linalg.norm(t["v"], axis=-1)
    return t


def expected(t, k, name):
    return t[name] if name in ("material", "object") else t[name][k]


def same(np, got, want, exact=True):
    got, want = np.asarray(got), np.asarray(want)
    if got.size != want.size:
        return False
    got, want = got.reshape(want.shape), want
    return np.array_equal(got, want) if exact else np.allclose(got, want, rtol=1e-12, atol=1e-12)


def export(nsf, run_file, fmt, out):
    run([nsf, "export", run_file, "-q", "--format", fmt, "--out", out])


def frame_files(out, ext, frames):
    return [os.path.join(out, f"run_{k:04d}.{ext}") for k in range(frames)]


def check_meshio(nsf, run_file, work, fails):
    np, h5py, meshio = need("numpy", "python3-numpy"), need("h5py", "python3-h5py"), need(
        "meshio", "python3-meshio")
    import meshio.xdmf  # noqa: F401

    t = truth(h5py, np, run_file)
    frames = len(t["time"])
    for fmt in ("vtu", "vtk"):
        out = os.path.join(work, fmt)
        export(nsf, run_file, fmt, out)
        for k, path in enumerate(frame_files(out, fmt, frames)):
            m = meshio.read(path)
            fails.check(same(np, m.points, t["x"][k]), f"{path}: points")
            fails.check(sorted(m.point_data) == sorted(NAMES),
                        f"{path}: arrays {sorted(m.point_data)}, not {sorted(NAMES)}")
            for name in NAMES:
                if name in m.point_data:
                    exact = name not in ("speed", "von_mises")  # derived: nsf's own arithmetic
                    fails.check(same(np, m.point_data[name], expected(t, k, name), exact),
                                f"{path}: {name} differs from the run file's")
            fails.check([c.type for c in m.cells] == ["vertex"] and len(m.cells[0].data) == len(
                t["x"][k]), f"{path}: one vertex cell per particle")
    out = os.path.join(work, "ply")
    export(nsf, run_file, "ply", out)
    f32 = np.float32
    for k, path in enumerate(frame_files(out, "ply", frames)):
        m = meshio.read(path)
        want = {"v_x": t["v"][k][:, 0], "v_y": t["v"][k][:, 1], "v_z": t["v"][k][:, 2],
                "speed": t["speed"][k], "von_mises": t["von_mises"][k],
                "material": t["material"], "object": t["object"]}
        fails.check(same(np, m.points, t["x"][k].astype(f32)), f"{path}: points")
        fails.check(sorted(m.point_data) == sorted(want), f"{path}: properties {sorted(m.point_data)}")
        for name, values in want.items():
            if name in m.point_data:
                cast = values if name in ("material", "object") else values.astype(f32)
                exact = name not in ("speed", "von_mises")
                fails.check(same(np, m.point_data[name], cast, exact) or (
                    not exact and np.allclose(m.point_data[name], cast, rtol=1e-6)),
                            f"{path}: {name}")
    out = os.path.join(work, "xdmf")
    export(nsf, run_file, "xdmf", out)
    path = os.path.join(out, "run.series.xdmf")
    with meshio.xdmf.TimeSeriesReader(path) as r:
        points, cells = r.read_points_cells()
        fails.check(same(np, points, t["x"][0]), f"{path}: points of the first step")
        fails.check(r.num_steps == frames, f"{path}: {r.num_steps} time steps, not {frames}")
        for k in range(r.num_steps):
            time, point_data, _ = r.read_data(k)
            fails.check(time == t["time"][k], f"{path}: step {k} at t = {time}, not {t['time'][k]}")
            fails.check(sorted(point_data) == sorted(NAMES + ["x"]),
                        f"{path}: step {k} has {sorted(point_data)}")
            for name in NAMES + ["x"]:
                if name in point_data:
                    exact = name not in ("speed", "von_mises")
                    fails.check(same(np, point_data[name], expected(t, k, name), exact),
                                f"{path}: step {k}: {name} differs from the run file's")


def check_vtk(nsf, run_file, work, fails):
    np, h5py = need("numpy", "python3-numpy"), need("h5py", "python3-h5py")
    need("vtk", "python3-vtk9")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkObject
    from vtkmodules.vtkIOLegacy import vtkUnstructuredGridReader
    from vtkmodules.vtkIOPLY import vtkPLYReader
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    vtkObject.GlobalWarningDisplayOff()
    t = truth(h5py, np, run_file)
    frames = len(t["time"])
    for fmt, reader, time_array in (("vtu", vtkXMLUnstructuredGridReader, "TimeValue"),
                                    ("vtk", vtkUnstructuredGridReader, "TIME")):
        out = os.path.join(work, fmt)
        export(nsf, run_file, fmt, out)
        for k, path in enumerate(frame_files(out, fmt, frames)):
            r = reader()
            r.SetFileName(path)
            r.Update()
            grid = r.GetOutput()
            n = len(t["x"][k])
            fails.check(same(np, vtk_to_numpy(grid.GetPoints().GetData()), t["x"][k]),
                        f"{path}: points ({type(r).__name__})")
            fails.check(grid.GetNumberOfCells() == n and all(
                grid.GetCellType(i) == 1 for i in range(n)), f"{path}: VTK_VERTEX cells")
            pd = grid.GetPointData()
            names = sorted(pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays()))
            fails.check(names == sorted(NAMES), f"{path}: {type(r).__name__} reads {names}")
            for name in NAMES:
                if pd.GetArray(name) is not None:
                    exact = name not in ("speed", "von_mises")
                    fails.check(same(np, vtk_to_numpy(pd.GetArray(name)), expected(t, k, name),
                                     exact), f"{path}: {name} ({type(r).__name__})")
            fd = grid.GetFieldData().GetArray(time_array)
            fails.check(fd is not None and fd.GetValue(0) == t["time"][k], f"{path}: {time_array}")
    out = os.path.join(work, "ply")
    export(nsf, run_file, "ply", out)
    for k, path in enumerate(frame_files(out, "ply", frames)):
        r = vtkPLYReader()
        r.SetFileName(path)
        r.Update()
        pts = vtk_to_numpy(r.GetOutput().GetPoints().GetData())
        fails.check(same(np, pts, t["x"][k].astype(np.float32)), f"{path}: vtkPLYReader points")
        pd = r.GetOutput().GetPointData()
        if k == 0:
            print("vtkPLYReader keeps the arrays",
                  [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())])


class Xdmf3:
    """The few calls of the Xdmf3 library's C interface that reading a time series needs."""

    def __init__(self):
        name = ctypes.util.find_library("Xdmf") or "libXdmf.so.3"
        try:
            self.lib = ctypes.CDLL(name)
        except OSError:
            print("SKIPPED: the Xdmf3 library (libXdmf.so.3) is missing (Debian package libxdmf3; "
                  "scripts/install-deps.sh installs it)")
            sys.exit(SKIP)
        vp, u, i = ctypes.c_void_p, ctypes.c_uint, ctypes.c_int
        ip = ctypes.POINTER(i)
        sig = {
            "XdmfReaderNew": (vp, []), "XdmfReaderRead": (vp, [vp, ctypes.c_char_p, ip]),
            "XdmfDomainGetGridCollection": (vp, [vp, u]),
            "XdmfGridCollectionGetNumberUnstructuredGrids": (u, [vp]),
            "XdmfGridCollectionGetUnstructuredGrid": (vp, [vp, u]),
            "XdmfUnstructuredGridGetTopology": (vp, [vp]),
            "XdmfTopologyRead": (None, [vp, ip]), "XdmfTopologyGetNumberElements": (u, [vp, ip]),
            "XdmfTopologyGetSize": (u, [vp]),
            "XdmfTopologyGetValues": (vp, [vp, u, i, u, u, u, ip]),
            "XdmfUnstructuredGridGetGeometry": (vp, [vp]), "XdmfGeometryRead": (None, [vp, ip]),
            "XdmfGeometryGetSize": (u, [vp]),
            "XdmfGeometryGetValues": (vp, [vp, u, i, u, u, u, ip]),
            "XdmfUnstructuredGridGetNumberAttributes": (u, [vp]),
            "XdmfUnstructuredGridGetAttribute": (vp, [vp, u]),
            "XdmfAttributeGetName": (ctypes.c_char_p, [vp]), "XdmfAttributeRead": (None, [vp, ip]),
            "XdmfAttributeGetSize": (u, [vp]),
            "XdmfAttributeGetValues": (vp, [vp, u, i, u, u, u, ip]),
            "XdmfUnstructuredGridGetTime": (vp, [vp]), "XdmfTimeGetValue": (ctypes.c_double, [vp]),
        }
        for fn, (res, args) in sig.items():
            f = getattr(self.lib, fn)
            f.restype, f.argtypes = res, args
        self.status = ctypes.c_int(0)

    def __getattr__(self, fn):
        return getattr(self.lib, fn)

    def values(self, np, get, item, size):
        ptr = get(item, 0, 8, size, 1, 1, ctypes.byref(self.status))  # 8: XDMF_ARRAY_TYPE_FLOAT64
        return np.ctypeslib.as_array(ctypes.cast(ptr, ctypes.POINTER(ctypes.c_double)),
                                     (size,)).copy()

    def read(self, np, path, frame_arrays):
        """Per grid: time, topology (elements, connectivity), geometry and the named arrays."""
        st = ctypes.byref(self.status)
        domain = self.XdmfReaderRead(self.XdmfReaderNew(), str(path).encode(), st)
        if self.status.value < 0 or not domain:
            return None
        collection = self.XdmfDomainGetGridCollection(domain, 0)
        grids = []
        for g in range(self.XdmfGridCollectionGetNumberUnstructuredGrids(collection)):
            grid = self.XdmfGridCollectionGetUnstructuredGrid(collection, g)
            topo = self.XdmfUnstructuredGridGetTopology(grid)
            self.XdmfTopologyRead(topo, st)
            geo = self.XdmfUnstructuredGridGetGeometry(grid)
            self.XdmfGeometryRead(geo, st)
            out = {"time": self.XdmfTimeGetValue(self.XdmfUnstructuredGridGetTime(grid)),
                   "elements": self.XdmfTopologyGetNumberElements(topo, st),
                   "connectivity": self.values(np, self.XdmfTopologyGetValues, topo,
                                               self.XdmfTopologyGetSize(topo)),
                   "geometry": self.values(np, self.XdmfGeometryGetValues, geo,
                                           self.XdmfGeometryGetSize(geo)),
                   "arrays": {}}
            for a in range(self.XdmfUnstructuredGridGetNumberAttributes(grid)):
                attr = self.XdmfUnstructuredGridGetAttribute(grid, a)
                name = self.XdmfAttributeGetName(attr).decode()
                if name in frame_arrays:
                    self.XdmfAttributeRead(attr, st)
                    out["arrays"][name] = self.values(np, self.XdmfAttributeGetValues, attr,
                                                      self.XdmfAttributeGetSize(attr))
                else:
                    out["arrays"][name] = None
            grids.append(out)
        return grids


def hyperslabs_as_xdmf_defines_them(np, h5py, xdmf_path, t, fails):
    """Frame k of the sidecar, each HyperSlab applied as XDMF defines it (start, stride, count per
    dimension, slowest first), to the datasets it names: the run file's frame k."""
    xi = "{http://www.w3.org/2001/XInclude}include"
    root = ET.parse(xdmf_path).getroot()
    collection = root.find("Domain/Grid")
    grids = collection.findall("Grid")
    h5 = h5py.File(xdmf_path.with_suffix(".h5"), "r")
    checked = 0
    for k, grid in enumerate(grids):
        # Frame 0 holds the Polyvertex connectivity 0..P-1, the others include that topology.
        if k == 0:
            item = grid.find("Topology/DataItem")
            fails.check(item is not None and same(np, np.array(item.text.split(), dtype=int),
                                                  np.arange(len(t["x"][0]))),
                        f"{xdmf_path}: the connectivity of frame 0")
        else:
            inc = grid.find(xi)
            fails.check(inc is not None and inc.get("xpointer") ==
                        "xpointer(/Xdmf/Domain/Grid/Grid[1]/Topology)",
                        f"{xdmf_path}: grid {k} includes the topology of frame 0")
        for where, item in [("x", grid.find("Geometry/DataItem"))] + [
                (a.get("Name"), a.find("DataItem")) for a in grid.findall("Attribute")]:
            if item.get("ItemType") != "HyperSlab":
                continue
            slab, data = item.findall("DataItem")
            start, stride, count = np.array(slab.text.split(), dtype=int).reshape(3, -1)
            file, dataset = data.text.strip().split(":")
            fails.check(file == xdmf_path.with_suffix(".h5").name, f"{xdmf_path}: names {file}")
            index = tuple(slice(b, b + s * c, s) for b, s, c in zip(start, stride, count))
            fails.check(where in t and same(np, h5[dataset][index], t[where][k]),
                        f"{xdmf_path}: frame {k}: the hyperslab of {where}")
        checked += 1
    fails.check(checked == len(t["time"]), f"{xdmf_path}: {checked} grids, not {len(t['time'])}")


def check_xdmf3(nsf, run_file, work, fails):
    np, h5py = need("numpy", "python3-numpy"), need("h5py", "python3-h5py")
    x3 = Xdmf3()
    t = truth(h5py, np, run_file)
    frames, p = len(t["time"]), len(t["x"][0])
    out = os.path.join(work, "xdmf")
    export(nsf, run_file, "xdmf", out)
    path = pathlib.Path(out) / "run.series.xdmf"
    grids = x3.read(np, path, set(NAMES + ["x"]))
    fails.check(grids is not None and len(grids) == frames, f"{path}: the Xdmf3 library reads "
                f"{None if grids is None else len(grids)} grids, not {frames}")
    for k, g in enumerate(grids or []):
        fails.check(g["time"] == t["time"][k], f"{path}: grid {k} at t = {g['time']}")
        fails.check(g["elements"] == p and same(np, g["connectivity"], np.arange(p)),
                    f"{path}: grid {k}: {g['elements']} Polyvertex elements, not {p}")
        fails.check(same(np, g["geometry"], t["x"][k]), f"{path}: grid {k}: geometry")
        fails.check(sorted(g["arrays"]) == sorted(NAMES + ["x"]), f"{path}: {sorted(g['arrays'])}")
        for name in NAMES + ["x"]:
            if g["arrays"].get(name) is not None:
                exact = name not in ("speed", "von_mises")
                fails.check(same(np, g["arrays"][name], expected(t, k, name), exact),
                            f"{path}: grid {k}: {name} differs from the run file's")

    # The sidecar: what the Xdmf3 library reads right (structure, times, connectivity, the static
    # arrays), then its hyperslabs as XDMF defines them.
    sidecar = pathlib.Path(run_file).with_suffix(".xdmf")
    static = {"X": "/X", "mass": "/mass", "volume": "/volume", "material": "/material",
              "object": "/object"}
    grids = x3.read(np, sidecar, set(static))
    fails.check(grids is not None and len(grids) == frames,
                f"{sidecar}: the Xdmf3 library reads {None if grids is None else len(grids)} grids")
    with h5py.File(run_file, "r") as h5:
        for k, g in enumerate(grids or []):
            fails.check(g["time"] == t["time"][k], f"{sidecar}: grid {k} at t = {g['time']}")
            fails.check(g["elements"] == p and same(np, g["connectivity"], np.arange(p)),
                        f"{sidecar}: grid {k}: {g['elements']} Polyvertex elements, not {p}")
            fails.check(sorted(g["arrays"]) == sorted(["v", "C", "F", "tau"] + list(static)),
                        f"{sidecar}: arrays {sorted(g['arrays'])}")
            for name, dataset in static.items():
                if g["arrays"].get(name) is not None:
                    fails.check(same(np, g["arrays"][name], h5[dataset][...]),
                                f"{sidecar}: grid {k}: {name}")
    hyperslabs_as_xdmf_defines_them(np, h5py, sidecar, t, fails)


def main():
    if len(sys.argv) != 3 or sys.argv[2] not in ("meshio", "vtk", "xdmf3"):
        sys.exit(__doc__)
    nsf, reader = sys.argv[1:]
    # What the reader needs, checked before simulating anything.
    for module, package in [("numpy", "python3-numpy"), ("h5py", "python3-h5py")] + {
            "meshio": [("meshio", "python3-meshio")], "vtk": [("vtk", "python3-vtk9")],
            "xdmf3": []}[reader]:
        need(module, package)
    if reader == "xdmf3":
        Xdmf3()
    with tempfile.TemporaryDirectory(prefix="nsf_export_readers_") as work:
        scene = os.path.join(work, "scene.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f)
        run_file = os.path.join(work, "run.h5")
        run([nsf, "simulate", scene, "-q", "-j", "2", "--out", run_file])
        fails = Failures()
        {"meshio": check_meshio, "vtk": check_vtk, "xdmf3": check_xdmf3}[reader](
            nsf, run_file, work, fails)
        print(f"{reader}: {'no failures' if fails.count == 0 else str(fails.count) + ' failures'}")
        sys.exit(1 if fails.count else 0)


if __name__ == "__main__":
    main()
