"""nsf.Rom's fields beyond the positions: the latent, τ and C of every particle, new arrays or
written into the caller's (out=), as positions() does."""

import numpy as np
import pytest

import nsf


@pytest.fixture()
def rom(tiny_model, tiny_scene):
    rom = nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2)
    rom.advance_frame(2)
    return rom


def test_latent_is_the_state_the_model_steps(rom, tiny_model, tiny_scene):
    assert rom.latent_dim == 2  # the fixture's -r 2
    z = rom.latent()
    assert z.dtype == np.float32 and z.shape == (2,) and np.isfinite(z).all()
    np.testing.assert_array_equal(rom.latent(), z)  # a second call: the same, a new array
    assert not np.shares_memory(rom.latent(), z)
    out = np.full(2, np.nan, np.float32)
    assert rom.latent(out=out) is out
    np.testing.assert_array_equal(out, z)
    rom.advance_frame()
    assert np.abs(rom.latent() - z).max() > 0  # it moves on with the run
    start = nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2).latent()
    assert np.abs(start - z).max() > 0


@pytest.mark.parametrize("field", ["stress", "affine"])
def test_per_particle_matrices(rom, field):
    P = rom.particle_count
    get = getattr(rom, field)
    a = get()
    assert a.dtype == np.float32 and a.shape == (P, 3, 3) and np.isfinite(a).all()
    assert np.abs(a).max() > 0
    np.testing.assert_array_equal(get(), a)  # nothing changes between two calls
    out = np.full((P, 3, 3), np.nan, np.float32)
    assert get(out=out) is out  # written in place, no new array
    np.testing.assert_array_equal(out, a)
    big = np.zeros((2, P, 3, 3), np.float32)  # a slice of a bigger array, as trajectory() uses
    get(out=big[1])
    np.testing.assert_array_equal(big[1], a)
    assert not big[0].any()
    rom.advance_frame()
    assert np.abs(get() - a).max() > 0


def test_stress_is_pascal_sized_and_symmetric(rom):
    tau = rom.stress()
    np.testing.assert_allclose(tau, tau.transpose(0, 2, 1), atol=1e-3 * np.abs(tau).max())
    assert np.abs(tau).max() > 1.0  # Pa: the bar is stressed, not at rest


def test_affine_is_zero_without_an_affine_field(tiny_model, tiny_scene):
    rom = nsf.Rom(tiny_model, tiny_scene, mu=1.0, threads=2,
                  overrides=['rom={"samples":64,"fields":{"affine":"none"}}'])
    rom.advance_frame()
    C = rom.affine()
    assert C.shape == (rom.particle_count, 3, 3) and not C.any()
    assert np.abs(rom.stress()).max() > 0


@pytest.mark.parametrize("field", ["stress", "affine", "latent"])
def test_a_bad_out_array_says_what_it_must_be(rom, field):
    get = getattr(rom, field)
    shape = (rom.latent_dim,) if field == "latent" else (rom.particle_count, 3, 3)
    want = r"%s: out must be a writeable, C-contiguous float32 array of shape \(%s" % (
        field, ", ".join(str(n) for n in shape))
    with pytest.raises(ValueError, match=want + r".*got shape \(5, 3\)"):
        get(out=np.empty((5, 3), np.float32))
    with pytest.raises(ValueError, match="got dtype float64"):
        get(out=np.empty(shape))
    read_only = np.empty(shape, np.float32)
    read_only.setflags(write=False)
    with pytest.raises(ValueError, match="a read-only array"):
        get(out=read_only)
    if field != "latent":
        with pytest.raises(ValueError, match="not C-contiguous"):
            get(out=np.empty((3, 3, rom.particle_count), np.float32).T)
    with pytest.raises(TypeError, match="out must be"):
        get(out=[0.0] * 9)
