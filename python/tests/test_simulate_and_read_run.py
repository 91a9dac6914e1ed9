"""load_scene, simulate and read_run, checked against h5py reading the same file and against the
`nsf simulate` tool."""

import json
import subprocess

import h5py
import numpy as np
import pytest

import nsf


@pytest.fixture(scope="module")
def scene(tiny_scene):
    return nsf.load_scene(tiny_scene, mu=0.7)


@pytest.fixture(scope="module")
def run_file(scene, tmp_path_factory):
    path = tmp_path_factory.mktemp("run") / "tiny.h5"
    run = nsf.simulate(scene, out=path, threads=2)
    return path, run


def test_load_scene_builds_it_at_mu(scene, tiny_scene):
    assert scene.name == "rom_tiny"
    assert scene.particle_count == 864
    assert (scene.frames, scene.substeps, scene.dt) == (12, 15, 0.001)
    assert scene.colliders == ["plane"]
    assert scene.sweep["parameter"] == "speed" and (scene.sweep["lo"], scene.sweep["hi"]) == (0.5, 1.5)
    assert scene.mu == 0.7 and scene.path == tiny_scene
    # The sweep's template put mu into the object's velocity.
    assert json.loads(scene.json)["objects"][0]["velocity"] == [0.7, -1.0, 0]
    x = scene.rest_positions
    assert x.shape == (864, 3) and x.dtype == np.float64
    assert x[:, 0].min() > 0.2 and x[:, 0].max() < 0.68


def test_rest_positions_are_a_read_only_view_of_the_scene(scene):
    a, b = scene.rest_positions, scene.rest_positions
    assert np.shares_memory(a, b)  # both views of the scene's own array: no copy
    assert not a.flags.writeable
    with pytest.raises(ValueError):
        a[0, 0] = 1.0


def test_simulate_writes_the_run_that_h5py_reads(run_file, scene):
    path, run = run_file
    assert run.x.shape == (13, 864, 3) and run.frame_count == 13 and run.particle_count == 864
    assert run.C.shape == run.F.shape == (13, 864, 3, 3) and run.tau.shape == (13, 864, 6)
    np.testing.assert_array_equal(run.x[0], scene.rest_positions)
    assert run.attrs["mu"] == 0.7 and run.attrs["scene_name"] == "rom_tiny"
    assert run.latent is None
    with h5py.File(path, "r") as f:
        for name in ("x", "v", "tau", "time"):
            np.testing.assert_array_equal(getattr(run, name), f["frames/" + name][()], err_msg=name)
        for name in ("C", "F"):
            np.testing.assert_array_equal(getattr(run, name),
                                          f["frames/" + name][()].reshape(13, 864, 3, 3))
        for name in ("X", "mass", "volume", "material", "object"):
            np.testing.assert_array_equal(getattr(run, name), f[name][()], err_msg=name)
        assert run.material.dtype == f["material"].dtype == np.uint16
        assert set(run.attrs) == set(f.attrs)
        for key, value in f.attrs.items():
            assert run.attrs[key] == value, key
    # The material moved: thrown sideways at mu = 0.7 m/s and falling.
    drift = run.x[-1].mean(axis=0) - run.x[0].mean(axis=0)
    assert drift[0] > 0.05 and drift[1] < -0.01


def test_simulate_matches_the_nsf_tool(run_file, nsf_cli, tiny_scene, tmp_path):
    path, run = run_file
    tool = tmp_path / "tool.h5"
    subprocess.run([nsf_cli, "simulate", tiny_scene, "--out", str(tool), "-j", "2", "-q",
                    "--set", "objects[0].velocity=[0.7,-1.0,0]"], check=True,
                   stdout=subprocess.DEVNULL)
    np.testing.assert_array_equal(nsf.read_run(tool, "x").x, run.x)


def test_simulate_to_a_temporary_file_and_only_some_fields(tiny_scene, run_file):
    run = nsf.simulate(tiny_scene, mu=0.7, threads=2, fields=["x", "tau"])
    assert run.path is None and run.v is None and run.C is None
    np.testing.assert_array_equal(run.x, run_file[1].x)
    np.testing.assert_array_equal(run.tau, run_file[1].tau)


def test_read_run_refuses_bad_input(tmp_path, tiny_scene):
    with pytest.raises(FileNotFoundError, match="run file .*nope.h5: no such file"):
        nsf.read_run(tmp_path / "nope.h5")
    with pytest.raises(RuntimeError, match="not an HDF5 file"):
        nsf.read_run(tiny_scene)
    with pytest.raises(ValueError, match="no per-frame field 'y'"):
        nsf.read_run(tiny_scene, fields=["y"])


def test_load_scene_refuses_bad_input(tmp_path, tiny_scene):
    with pytest.raises(FileNotFoundError, match="scene .*missing.json: no such file"):
        nsf.load_scene(tmp_path / "missing.json")
    with pytest.raises(RuntimeError, match="nonsense"):
        nsf.load_scene(tiny_scene, overrides=["simulation.nonsense=1"])
    plain = tmp_path / "plain.json"
    scene = json.load(open(tiny_scene))
    del scene["sweep"], scene["rom"]
    plain.write_text(json.dumps(scene))
    with pytest.raises(RuntimeError, match="no \"sweep\" section"):
        nsf.load_scene(plain, mu=1.0)
    with pytest.raises(ValueError, match="not with a loaded Scene"):
        nsf.simulate(nsf.load_scene(plain), mu=1.0)
    with pytest.raises(ValueError, match="is the scene file itself"):
        nsf.simulate(plain, out=plain)
