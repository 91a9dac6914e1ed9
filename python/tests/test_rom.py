"""nsf.Rom over the embedding runtime: stepping, positions into the caller's array, a collider
moved from Python, and the errors."""

import numpy as np
import pytest

import nsf


@pytest.fixture()
def rom(tiny_model, tiny_scene):
    return nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2)


def test_steps_frames_and_writes_positions_into_the_callers_array(rom):
    P = rom.particle_count
    assert P == 864 and rom.frame_count == 12 and rom.steps_per_frame == 15
    out = np.zeros((P, 3), np.float32)
    got = rom.positions(out=out)
    assert got is out  # written in place, no new array
    start = out.copy()
    assert np.isfinite(start).all() and abs(start[:, 0].mean() - 0.44) < 0.05
    rom.advance_frame(2)
    assert rom.time == pytest.approx(2 * rom.frame_time)
    rom.positions(out=out)
    assert np.abs(out - start).max() > 1e-3  # the bar moved
    new = rom.positions()  # a new array, the same values
    assert new.dtype == np.float32 and new.shape == (P, 3) and not np.shares_memory(new, out)
    np.testing.assert_array_equal(new, out)
    v = rom.velocities()
    assert v.shape == (P, 3) and v[:, 0].mean() > 0.1  # thrown sideways at mu = 1 m/s


def test_trajectory_fills_one_array_frame_by_frame(tiny_model, tiny_scene):
    scene = nsf.load_scene(tiny_scene, mu=1.0)
    rom = nsf.Rom(tiny_model, scene, threads=2)
    first = rom.positions()
    x = rom.trajectory(3)
    assert x.shape == (4, 864, 3) and x.dtype == np.float32
    np.testing.assert_array_equal(x[0], first)
    np.testing.assert_array_equal(x[3], rom.positions())
    assert rom.time == pytest.approx(3 * rom.frame_time)


def run_with_floor(model, scene, lift):
    """The plane (collider 0) raised at `lift` m/s, pose and velocity set every frame."""
    rom = nsf.Rom(model, scene, mu=1.0, threads=2)
    assert rom.collider_count == 1 and rom.collider_type(0) == "plane"
    y0 = rom.collider_pose(0)["position"][1]
    for _ in range(rom.frame_count):
        pose = rom.collider_pose(0)
        pose["position"][1] = y0 + lift * rom.time
        pose["velocity"] = [0.0, lift, 0.0]
        rom.set_collider_pose(0, **pose)
        rom.advance_frame()
    return rom.collider_pose(0)["position"][1], rom.positions()


def test_moving_the_collider_moves_the_material(tiny_model, tiny_scene):
    y_moved, x_moved = run_with_floor(tiny_model, tiny_scene, 0.5)
    y_still, x_still = run_with_floor(tiny_model, tiny_scene, 0.0)
    assert y_moved - y_still == pytest.approx(0.5 * 12 * 0.015, abs=1e-6)
    assert np.abs(x_moved - x_still).max() > 1e-3
    assert x_moved[:, 1].min() > x_still[:, 1].min()  # the raised floor holds the bar higher


def test_collider_pose_round_trips(rom):
    pose = rom.collider_pose(0)
    assert pose["rotation"].shape == (3, 3)
    np.testing.assert_array_equal(pose["rotation"], np.eye(3))
    rom.set_collider_pose(0, position=pose["position"] + [0, 0.01, 0], velocity=[0, 0.1, 0])
    now = rom.collider_pose(0)
    np.testing.assert_allclose(now["position"], pose["position"] + [0, 0.01, 0])
    np.testing.assert_array_equal(now["velocity"], [0, 0.1, 0])


def test_an_objects_pose_is_the_best_rigid_fit_of_its_particles(rom, tiny_scene):
    assert rom.object_count == 1
    rom.advance_frame(3)
    pose = rom.object_pose(0)
    X = nsf.load_scene(tiny_scene, mu=1.0).rest_positions
    x = rom.positions().astype(np.float64)
    R, c, c0 = pose["rotation"], pose["position"], pose["rest_position"]
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(c, x.mean(axis=0), atol=1e-6)  # one material: equal masses
    np.testing.assert_allclose(c0, X.mean(axis=0), atol=1e-12)
    rms = lambda Q: np.sqrt(np.mean(np.sum(((X - c0) @ Q.T + c - x) ** 2, axis=1)))
    assert pose["misfit"] == pytest.approx(rms(R), rel=1e-5)
    for axis in np.eye(3):  # no turn by a milliradian about any axis fits better
        K = np.cross(np.eye(3), axis)  # [axis]x, so that K @ v = axis x v
        turn = np.eye(3) + np.sin(1e-3) * K + (1 - np.cos(1e-3)) * K @ K
        assert rms(turn @ R) > pose["misfit"]
        assert rms(turn.T @ R) > pose["misfit"]
    with pytest.raises(IndexError, match="no object 1: the scene has 1"):
        rom.object_pose(1)


def test_bad_input_raises_a_clear_exception(rom, tiny_model, tiny_scene, tmp_path):
    P = rom.particle_count
    with pytest.raises(FileNotFoundError, match="model .*missing.nsf: no such file"):
        nsf.Rom(tmp_path / "missing.nsf", tiny_scene, mu=1.0)
    with pytest.raises(RuntimeError, match=r"give its value \(nsf rom --mu, RuntimeOptions::mu, Python.s Rom\(mu=...\)\)"):
        nsf.Rom(tiny_model, tiny_scene)
    with pytest.raises(ValueError, match=r"shape \(864, 3\).*got shape \(10, 3\)"):
        rom.positions(out=np.empty((10, 3), np.float32))
    with pytest.raises(ValueError, match="got dtype float64"):
        rom.positions(out=np.empty((P, 3)))
    with pytest.raises(ValueError, match="not C-contiguous"):
        rom.velocities(out=np.empty((3, P), np.float32).T)
    with pytest.raises(TypeError, match="out must be"):
        rom.positions(out=[[0.0] * 3] * P)
    with pytest.raises(IndexError, match="no collider 3: the scene has 1"):
        rom.collider_pose(3)
    with pytest.raises(ValueError, match="position must be 3 numbers"):
        rom.set_collider_pose(0, position=[0, 1])
    with pytest.raises(RuntimeError, match="not a rotation matrix"):
        rom.set_collider_pose(0, rotation=2 * np.eye(3))


def test_a_run_thrown_into_the_wall_recovers_and_reports_its_health(tiny_model, tiny_scene):
    # Thrown at 8 m/s, eight times the sweep's fastest: the latent carries the bar into the wall,
    # where its points would leave the grid. The run goes on to the scene's end, and says so.
    rom = nsf.Rom(tiny_model, tiny_scene, mu=8.0, threads=2)
    healthy = rom.health
    assert set(healthy) == {"indicator", "misfit_cells", "courant", "grid_margin", "flagged",
                            "recoveries", "last_recovery", "outside_training", "steps_outside",
                            "training_note"}
    worst = 0.0
    for _ in range(rom.frame_count):
        rom.advance_frame()
        worst = max(worst, rom.health["indicator"])
    x = rom.positions()
    assert np.isfinite(x).all() and (x > 0).all() and (x < 1).all()
    h = rom.health
    assert worst >= 1.0
    assert h["recoveries"] > 0 and "redone" in h["last_recovery"]


def test_a_floor_moved_beyond_where_training_kept_it_is_reported(tiny_model, tiny_scene):
    # The model keeps the box its training runs spanned; the floor never moved in them.
    rom = nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2)
    rom.advance_frame()
    assert not rom.health["outside_training"] and rom.health["training_note"] == ""
    rom.set_collider_pose(0, position=[0, 0.02, 0])
    rom.step()
    h = rom.health
    assert h["outside_training"] and h["steps_outside"] == 1
    assert "collider 0's centre" in h["training_note"] and "in y" in h["training_note"]


def test_a_scene_outside_the_training_family_is_named_in_the_warnings(tiny_model, tiny_scene):
    # The floor set lower than in every training run: the model's training family never held it.
    assert nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2).warnings == []
    rom = nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2,
                  overrides=["colliders[0].point=[0,0.07,0]"])
    assert len(rom.warnings) == 1
    assert "outside the model's training family (/colliders/0/point/1" in rom.warnings[0]
