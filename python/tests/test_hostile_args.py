"""Hostile arguments (issue #54 items 10, 13, 18): every argument of the module gets the command
line's checks and raises a Python exception naming it; nothing aborts or hangs the interpreter.
The calls that used to kill it (libgomp asked for 10**9 threads) or hang it (/dev/zero read as a
scene) run in a child interpreter, so that a regression fails this test instead of ending pytest."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import nsf


def run_child(code, timeout=60):
    """`code` in a fresh interpreter; (exit status, its output)."""
    p = subprocess.run([sys.executable, "-c", "import nsf\n" + code], capture_output=True,
                       text=True, timeout=timeout, env=dict(os.environ))
    return p.returncode, p.stdout + p.stderr


def test_threads_out_of_range_is_a_value_error_not_a_dead_interpreter(tiny_scene):
    code = (
        "s = nsf.load_scene(%r, mu=1.0)\n"
        "for t in (10**9, 1025, -1):\n"
        "    try:\n"
        "        nsf.simulate(s, threads=t)\n"
        "    except ValueError as e:\n"
        "        print('ValueError', e)\n"
        "try:\n"
        "    nsf._nsf._simulate(s, 'x.h5', 10**9)\n"
        "except ValueError as e:\n"
        "    print('ValueError', e)\n" % tiny_scene)
    status, out = run_child(code)
    assert status == 0, out
    assert out.count("ValueError threads") == 4, out
    assert "0 to 1024" in out, out


def test_a_device_given_as_a_file_is_an_os_error_at_once(tiny_model, tiny_scene):
    code = (
        "for call in (lambda: nsf._nsf.Scene('/dev/zero', None, []),\n"
        "             lambda: nsf.load_scene('/dev/zero'),\n"
        "             lambda: nsf._nsf._read_run('/dev/zero', ['x']),\n"
        "             lambda: nsf.Rom('/dev/zero', %r, mu=1.0),\n"
        "             lambda: nsf._nsf.Runtime(%r, '/dev/zero', 1.0, 0, 0, [])):\n"
        "    try:\n"
        "        call()\n"
        "    except OSError as e:\n"
        "        print(type(e).__name__, e)\n" % (tiny_scene, tiny_model))
    status, out = run_child(code, timeout=30)
    assert status == 0, out
    assert out.count("/dev/zero is not a regular file") == 5, out
    assert "does not exist" not in out and "no such file" not in out, out


def test_mu_that_is_not_finite_is_named(tiny_model, tiny_scene):
    for mu in (math.nan, math.inf, -1e301):
        with pytest.raises(ValueError, match="mu must be a finite number"):
            nsf.load_scene(tiny_scene, mu=mu)
        with pytest.raises(ValueError, match="mu must be a finite number"):
            nsf._nsf.Scene(tiny_scene, mu, [])
        with pytest.raises(ValueError, match="mu must be a finite number"):
            nsf.Rom(tiny_model, tiny_scene, mu=mu)


def test_rom_counts_are_checked_as_the_command_line_checks_them(tiny_model, tiny_scene):
    with pytest.raises(ValueError, match="samples must be 0 .* or 1 to 100000000, got -1"):
        nsf.Rom(tiny_model, tiny_scene, mu=1.0, samples=-1)
    with pytest.raises(ValueError, match="samples"):
        nsf._nsf.Runtime(tiny_model, tiny_scene, 1.0, -1, 0, [])
    for threads in (-1, 1025, 10**9):
        with pytest.raises(ValueError, match="threads must be 0 to 1024"):
            nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=threads)
    rom = nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2)
    for bad in (-5, -1):
        with pytest.raises(ValueError, match="frames must be 0 or more, got %d" % bad):
            rom.advance_frame(bad)
        with pytest.raises(ValueError, match="frames must be 0 or more, got %d" % bad):
            rom.trajectory(frames=bad)
    with pytest.raises(TypeError, match="frames must be a whole number"):
        rom.advance_frame(1.5)
    with pytest.raises(TypeError, match="out must be a numpy array"):
        rom.trajectory(frames=1, out=[0.0])
    assert rom.time == 0.0  # nothing stepped
    assert rom.trajectory(frames=0).shape == (1, rom.particle_count, 3)


def test_collider_poses_are_bounded(tiny_model, tiny_scene):
    rom = nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2)
    before = rom.collider_pose(0)
    # Each used to be taken: the rotation turned NaN, or the floor went to 1e308 m.
    cases = [
        (dict(angular_velocity=[1e308, 0, 0]), "angular velocity"),
        (dict(angular_velocity=[1e4, 0, 0]), "angular velocity"),
        (dict(velocity=[0, 1e308, 0]), "velocity"),
        (dict(velocity=[0, 1e3, 0]), "velocity"),
        (dict(position=[0, 1.7976931348623157e308, 0]), "position"),
        (dict(position=[1e308, 1e308, 1e308]), "position"),
        (dict(position=[0, 5, 0]), "position"),
    ]
    for pose, what in cases:
        with pytest.raises(RuntimeError, match="collider 0's %s .* (limit|outside)" % what):
            rom.set_collider_pose(0, **pose)
    for pose in (dict(velocity=[math.nan, 0, 0]), dict(position=[0, math.inf, 0])):
        with pytest.raises(ValueError, match="finite"):
            rom.set_collider_pose(0, **pose)
    after = rom.collider_pose(0)
    for key in before:
        np.testing.assert_array_equal(after[key], before[key])
    rom.advance_frame()
    assert np.isfinite(rom.collider_pose(0)["rotation"]).all()
    # Within the limits it is taken, as before.
    rom.set_collider_pose(0, position=[0, 0.2, 0], velocity=[0, 1, 0], angular_velocity=[0, 1, 0])
    np.testing.assert_array_equal(rom.collider_pose(0)["angular_velocity"], [0, 1, 0])
