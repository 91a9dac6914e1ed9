"""Shared fixtures: the nsf tool and source tree (set by ctest, see python/CMakeLists.txt), the
tiny scene, and a tiny model of it trained once per session with the built `nsf`, the way
tests/check_install.sh trains one."""

import os
import subprocess

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.environ.get("NSF_SOURCE_DIR", os.path.normpath(os.path.join(HERE, "..", "..")))


@pytest.fixture(scope="session")
def nsf_cli():
    cli = os.environ.get("NSF_CLI", os.path.join(SOURCE_DIR, "build", "nsf"))
    if not os.access(cli, os.X_OK):
        pytest.fail("no nsf tool at %s: build it, or set NSF_CLI" % cli)
    return cli


@pytest.fixture(scope="session")
def tiny_scene():
    """864 particles, 12 frames, a sweep over the throw speed mu in [0.5, 1.5], a plane collider."""
    return os.path.join(SOURCE_DIR, "scenes", "examples", "rom_tiny.json")


@pytest.fixture(scope="session")
def tiny_model(nsf_cli, tiny_scene, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("model")
    quiet = dict(check=True, stdout=subprocess.DEVNULL)
    subprocess.run([nsf_cli, "sweep", tiny_scene, "--out", str(tmp / "data"), "--jobs", "2", "-j", "1",
                    "-q"], **quiet)
    model = tmp / "tiny.nsf"
    subprocess.run([nsf_cli, "train", str(tmp / "data"), "--out", str(model), "-r", "2", "--depth",
                    "2", "--widths", "32,16,16",
                    "--encoder-hidden", "8", "--steps", "100,50,50", "--refine-latents", "0",
                    "-j", "2", "-q", "--frames-per-batch", "2", "--particles-per-frame", "64"],
                   **quiet)
    return str(model)
