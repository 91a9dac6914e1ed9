"""nsf from Python: load a scene, run it at full order, read run files, step a trained
reduced-order model while moving its colliders. docs/PYTHON.md.

    import nsf
    scene = nsf.load_scene("scenes/examples/rom_tiny.json", mu=1.0)
    run = nsf.simulate(scene)                 # full order: run.x is frames x P x 3
    rom = nsf.Rom("models/rom_tiny.nsf", scene)
    x = rom.trajectory()                      # the ROM: frames x P x 3, float32
"""

import operator
import os
import stat
import sys
import tempfile

try:
    import numpy as np
except ImportError as e:  # pragma: no cover - exercised by hand, see docs/PYTHON.md
    raise ImportError(
        "nsf needs numpy, which this Python (%s, %s) cannot import. On Debian: "
        "`apt-get install python3-numpy` and use /usr/bin/python3 (scripts/install-deps.sh "
        "installs it); for another interpreter, install numpy into it."
        % (sys.executable, sys.version.split()[0])
    ) from e

from . import _nsf

__version__ = _nsf.__version__
Scene = _nsf.Scene

__all__ = ["Scene", "Run", "Rom", "load_scene", "simulate", "read_run", "__version__", "build_arch"]


_KINDS = ((stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
          (stat.S_ISSOCK, "a socket"), (stat.S_ISFIFO, "a FIFO"))


def _existing_file(path, what):
    """`path` if it is a regular file, else FileNotFoundError, IsADirectoryError or OSError
    saying what it is (a device would be read without end, a pipe's open wait for a writer)."""
    path = os.fspath(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise FileNotFoundError("%s %s: no such file" % (what, path)) from None
    if stat.S_ISDIR(mode):
        raise IsADirectoryError("%s %s is a directory" % (what, path))
    if stat.S_ISREG(mode):
        return path
    kind = next((name for test, name in _KINDS if test(mode)), "not a file")
    raise OSError("%s %s is not a regular file (it is %s)" % (what, path, kind))


def _count(value, what):
    """`value` as a whole number of at least 0, else TypeError or ValueError naming `what`."""
    try:
        n = operator.index(value)
    except TypeError:
        raise TypeError("%s must be a whole number, got %r" % (what, value)) from None
    if n < 0:
        raise ValueError("%s must be 0 or more, got %d" % (what, n))
    return n


def load_scene(path, mu=None, overrides=()):
    """Loads a scene file (docs/SCENES.md) as the engine builds it: `overrides` ("a.b=value", as
    `--set` takes them) applied, then, when given, the sweep parameter `mu` through the scene's
    "sweep" templates. Raises FileNotFoundError, or RuntimeError naming the key at fault."""
    return _nsf.Scene(_existing_file(path, "scene"), mu, list(overrides))


def _scene(scene, mu, overrides):
    if isinstance(scene, Scene):
        if mu is not None or overrides:
            raise ValueError("give mu and overrides to load_scene, not with a loaded Scene")
        return scene
    return load_scene(scene, mu, overrides)


class Run:
    """A run file's contents (docs/OUTPUT.md) as numpy arrays, F frames of P particles:
    x, v (F, P, 3); C, F (F, P, 3, 3); tau (F, P, 6: xx yy zz xy yz xz); time (F,);
    X (P, 3) rest positions; mass, volume (P,); material, object (P,) uint16; latent (F, r) for a
    reduced-order run, else None; attrs: every root attribute (scene_name, scene_json, dt, mu, ...).
    A field not asked for (read_run's `fields`) is None."""

    def __init__(self, path, arrays):
        self.path = path
        self.attrs = arrays.pop("attrs")
        self.latent = arrays.pop("latent", None)
        for name in _nsf._frame_fields():
            setattr(self, name, arrays.pop(name, None))
        for name, value in arrays.items():
            setattr(self, name, value)

    @property
    def frame_count(self):
        """F, the frames held (the initial state first)."""
        return len(self.time)

    @property
    def particle_count(self):
        """P, the particles of each frame."""
        return len(self.X)

    def __repr__(self):
        return "nsf.Run(%r: %s, %d frames, %d particles)" % (
            self.path, self.attrs.get("scene_name", "?"), self.frame_count, self.particle_count)


def read_run(path, fields=None):
    """Reads a run file written by `nsf simulate`, `nsf sweep`, `nsf rom` or simulate(). `fields`:
    the per-frame datasets to read, some of "x", "v", "C", "F", "tau" (default all). Each is read
    by HDF5 straight into its numpy array. Raises FileNotFoundError, or RuntimeError naming the
    file and what is wrong with it."""
    known = _nsf._frame_fields()
    fields = known if fields is None else [fields] if isinstance(fields, str) else list(fields)
    for f in fields:
        if f not in known:
            raise ValueError("no per-frame field %r in a run file (%s are)" % (f, ", ".join(known)))
    path = _existing_file(path, "run file")
    return Run(path, _nsf._read_run(path, fields))


def simulate(scene, out=None, mu=None, overrides=(), threads=0, fields=None):
    """Runs `scene` (a Scene, or a scene file with `mu` and `overrides` as load_scene takes them)
    at full order from its initial state over its frames, writes the run file `out` (every frame,
    the initial state first; `mu` stored as an attribute) and returns read_run(out, fields). With
    out=None the file is a temporary one, removed after reading. `threads`: 0 for all cores.
    Ctrl-C stops it between frames, leaving no file."""
    scene = _scene(scene, mu, overrides)
    if out is None:
        with tempfile.TemporaryDirectory(prefix="nsf_simulate_") as tmp:
            path = os.path.join(tmp, "run.h5")
            _nsf._simulate(scene, path, threads)
            run = read_run(path, fields)
            run.path = None
            return run
    out = os.fspath(out)
    if os.path.exists(out) and os.path.samefile(out, scene.path):
        raise ValueError("out %s is the scene file itself" % out)
    _nsf._simulate(scene, out, threads)
    return read_run(out, fields)


def _vector(value, n, what):
    a = np.asarray(value, dtype=np.float64)
    if a.size != n or not (a.ndim == 1 or (n == 9 and a.shape == (3, 3))):
        raise ValueError("%s must be %s, got shape %s" % (
            what, "a 3x3 matrix" if n == 9 else "%d numbers" % n, a.shape))
    if not np.isfinite(a).all():
        raise ValueError("%s must be finite numbers, got %s" % (what, a.reshape(n).tolist()))
    return [float(v) for v in a.reshape(n)]


def _index(i, count, what):
    if not 0 <= i < count:
        raise IndexError("no %s %s: the scene has %d" % (what, i, count))
    return i


class Rom:
    """A trained reduced-order model (a .nsf file, `nsf train`) running on its scene, frame by
    frame, over nsf::Runtime (docs/EMBEDDING.md). `scene`: a Scene, or a scene file with `mu` (the
    sweep parameter, required when the scene has a sweep) and `overrides`. `samples`: |S| (0: the
    scene's "rom" section); `threads`: 0 for all cores."""

    def __init__(self, model, scene, mu=None, overrides=(), samples=0, threads=0):
        model = _existing_file(model, "model")
        if isinstance(scene, Scene):
            if mu is not None or overrides:
                raise ValueError("give mu and overrides to load_scene, not with a loaded Scene")
            path, mu, overrides = scene.path, scene.mu, scene.overrides
        else:
            path = _existing_file(scene, "scene")
        self._rt = _nsf.Runtime(model, path, mu, samples, threads, list(overrides))

    particle_count = property(lambda self: self._rt.particle_count, doc="the scene's particles, P")
    frame_count = property(lambda self: self._rt.frame_count, doc="the scene's frames")
    frame_time = property(lambda self: self._rt.frame_time, doc="seconds per frame")
    steps_per_frame = property(lambda self: self._rt.steps_per_frame,
                               doc="reduced-order steps per frame")
    time = property(lambda self: self._rt.time, doc="simulated seconds so far")
    object_count = property(lambda self: self._rt.object_count,
                            doc="the scene's objects (object_pose takes 0 to this - 1)")
    collider_count = property(lambda self: self._rt.collider_count,
                              doc="the scene's colliders (set_collider_pose takes 0 to this - 1)")
    latent_dim = property(lambda self: self._rt.latent_dim,
                          doc="the latent space's dimension r, the length of latent()")

    def advance_frame(self, frames=1):
        """Advances `frames` frames (steps_per_frame ROM steps each)."""
        for _ in range(_count(frames, "frames")):
            self._rt.advance_frame()

    def step(self):
        """One reduced-order step."""
        self._rt.step()

    @property
    def health(self):
        """How the run is doing, online (no truth needed; docs/EMBEDDING.md, "Error indicator"):
        a dict of indicator (the last step's: below 1 fine, 1 or more past a limit),
        misfit_cells (the inversion's rms misfit at the samples, in cells), courant (the fastest
        integration point's cells per step), grid_margin (cells left before the grid's edge),
        flagged (the last step's indicator was 1 or more, or it was redone), recoveries (steps
        redone so far instead of ending the run), last_recovery (what the last one did),
        outside_training (a collider was outside the model's training box in the last step),
        steps_outside (steps so far that it was) and training_note (what lay outside, the first
        time)."""
        return self._rt.health()

    @property
    def warnings(self):
        """What the set-up warned of, a list of str: mu outside the model's training range, a
        scene outside its training family (a value no training run's scene took, e.g. a collider
        set elsewhere through `overrides`; the run then reads the scene's rom.unseen profile:
        docs/GENERALIZE.md). Empty for a run inside both."""
        return list(self._rt.warnings)

    def positions(self, out=None):
        """Every particle's position now, (P, 3) float32, metres. With `out` (a writeable
        C-contiguous float32 array of that shape, or such a slice of a bigger one) the values are
        written into it and it is returned; else into a new array. No copy either way."""
        return self._rt.positions(out)

    def velocities(self, out=None):
        """Every particle's velocity (the last step's backward difference), as positions()."""
        return self._rt.velocities(out)

    def stress(self, out=None):
        """Every particle's Kirchhoff stress tau = J sigma now, (P, 3, 3) float32, Pa, from the
        source the reduced-order step itself takes tau from (the model's decoder; with
        rom.fields.stress = "tracked", the particles' own state). `out` as positions() takes it,
        of shape (P, 3, 3)."""
        return self._rt.stress(out)

    def affine(self, out=None):
        """Every particle's affine velocity C now (APIC's: the velocity about particle p varies as
        v_p + C_p (y - x_p)), (P, 3, 3) float32, 1/s, from the source the step takes C from (the
        model's decoder; rom.fields.affine = "tracked": the particles' own state; "none": zero).
        `out` as positions() takes it, of shape (P, 3, 3)."""
        return self._rt.affine(out)

    def latent(self, out=None):
        """The run's latent vector now, (latent_dim,) float32: what the reduced-order model steps
        (and `nsf serve` streams). `out` as positions() takes it, of shape (latent_dim,)."""
        return self._rt.latent(out)

    def trajectory(self, frames=None, out=None):
        """The positions now and after each of the next `frames` frames (default: the scene's
        frame_count): (frames + 1, P, 3) float32, each frame written in place into `out` or a new
        array, as read_run(...).x holds a full-order run."""
        frames = self.frame_count if frames is None else _count(frames, "frames")
        if out is None:
            out = np.empty((frames + 1, self.particle_count, 3), np.float32)
        elif not isinstance(out, np.ndarray):
            raise TypeError("out must be a numpy array of shape (frames + 1, %d, 3), got %s"
                            % (self.particle_count, type(out).__name__))
        elif out.shape[:1] != (frames + 1,):
            raise ValueError("out must hold frames + 1 = %d frames, its shape is %s"
                             % (frames + 1, out.shape))
        self.positions(out[0])
        for k in range(1, frames + 1):
            self._rt.advance_frame()
            self.positions(out[k])
        return out

    def object_pose(self, i):
        """Object i (the scene's "objects" order) as a rigid body fitted to its particles now: a
        dict of position (3,, its centre of mass), rotation (3, 3, rest to now, the best fit of
        its particles about the centres of mass), velocity (3,), angular_velocity (3,, about the
        centre of mass), rest_position (3,, the centre of mass at rest), numpy float64 arrays,
        and misfit (float, m: the particles' rms distance from that rigid copy of the rest
        shape). A rest point X sits near rotation @ (X - rest_position) + position. The first
        call after a step decodes every particle, as velocities() does."""
        p = self._rt.object_pose(_index(i, self.object_count, "object"))
        return {"position": np.array(p.position), "rotation": np.array(p.rotation).reshape(3, 3),
                "velocity": np.array(p.velocity), "angular_velocity": np.array(p.angular_velocity),
                "rest_position": np.array(p.rest_position), "misfit": float(p.misfit)}

    def collider_type(self, i):
        """"box", "cylinder", "plane", ... of collider i (the scene's "colliders" order)."""
        return self._rt.collider_type(_index(i, self.collider_count, "collider"))

    def collider_pose(self, i):
        """Collider i now: a dict of position (3,), rotation (3, 3, body to world), velocity (3,),
        angular_velocity (3,), numpy float64 arrays; set_collider_pose(i, **pose) takes it back."""
        p = self._rt.collider_pose(_index(i, self.collider_count, "collider"))
        return {"position": np.array(p.position), "rotation": np.array(p.rotation).reshape(3, 3),
                "velocity": np.array(p.velocity), "angular_velocity": np.array(p.angular_velocity)}

    def set_collider_pose(self, i, position=None, rotation=None, velocity=(0, 0, 0),
                          angular_velocity=(0, 0, 0)):
        """Takes collider i over: it is at `position` with `rotation` now (either left out: where
        it is) and moves on with `velocity` (m/s) and `angular_velocity` (rad/s; both zero unless
        given) until the next call; its scripted motion is ignored from then on. The material in
        contact feels those velocities, so give the ones the collider really has."""
        now = self._rt.collider_pose(_index(i, self.collider_count, "collider"))
        pose = _nsf.ColliderPose()
        pose.position = now.position if position is None else _vector(position, 3, "position")
        pose.rotation = now.rotation if rotation is None else _vector(rotation, 9, "rotation")
        pose.velocity = _vector(velocity, 3, "velocity")
        pose.angular_velocity = _vector(angular_velocity, 3, "angular_velocity")
        self._rt.set_collider_pose(i, pose)

    def __repr__(self):
        return "nsf.Rom(%d particles, t = %.4g s)" % (self.particle_count, self.time)


def build_arch():
    """The instruction set of the libnsf_runtime copy the loader took: "x86-64-v2", "x86-64-v3"
    (on a CPU with AVX2 and FMA, the copy built for it) or "native" (docs/EMBEDDING.md)."""
    return _nsf.build_arch()
