"""The half-space convolution by pocketfft called directly (``halfspace.POCKETFFT``): the same
numbers as through :mod:`scipy.fft`, bit for bit, and the direct summation of Love's patch
influence coefficients (an independent truth) to rounding; the reused work arrays keep no
trace of an earlier call."""

import numpy as np
import pytest

from bearing_envelope.contact import halfspace
from bearing_envelope.contact.halfspace import ElasticHalfSpace, influence_coefficients

E_STAR = 115.4e9
DX, DY = 2e-6, 2e-5


def _pressures(shape, k=3):
    rng = np.random.default_rng(11)
    out = [rng.uniform(0.0, 3e9, shape) for _ in range(k)]
    out[1][: shape[0] // 3] = 0.0                     # unloaded rows, as around a contact
    return out


@pytest.mark.skipif(halfspace.POCKETFFT is None, reason="scipy without pypocketfft")
@pytest.mark.parametrize("shape", [(23, 9), (40, 18), (7, 31), (1, 5)])
def test_direct_pocketfft_equals_scipy_fft_to_the_bit(shape, monkeypatch):
    direct = ElasticHalfSpace(shape, DX, DY, E_STAR, workers=1, backend="scipy")
    got = [direct.displacement(p) for p in _pressures(shape)]
    got.append(direct.displacement(_pressures(shape)[0]))        # again, after other calls
    monkeypatch.setattr(halfspace, "POCKETFFT", None)
    public = ElasticHalfSpace(shape, DX, DY, E_STAR, workers=1, backend="scipy")
    want = [public.displacement(p) for p in _pressures(shape)]
    for g, w in zip(got, want + [want[0]]):
        assert g.shape == shape and g.flags.owndata
        np.testing.assert_array_equal(g, w)


def test_direct_pocketfft_equals_direct_summation():
    p = _pressures((23, 9))[1]
    op = ElasticHalfSpace(p.shape, DX, DY, E_STAR, workers=1, backend="scipy")
    u = op.displacement(p)
    out = np.empty_like(u)
    assert op.displacement(p, out=out) is out and np.array_equal(out, u)
    nx, ny = p.shape
    xc, yc = np.arange(nx) * DX, np.arange(ny) * DY
    for i, j in [(0, 0), (11, 4), (22, 8), (5, 2)]:
        want = np.sum(p * influence_coefficients(xc[i] - xc[:, None], yc[j] - yc[None, :],
                                                 DX, DY, E_STAR))
        assert u[i, j] == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("shape", [(16, 10), (15, 7), (1, 4)])
def test_rfft2_irfft2_equal_scipy_fft_to_the_bit(shape, monkeypatch):
    """The preconditioner's transforms: scipy.fft.rfft2 / irfft2(norm="forward") to the bit,
    through pocketfft directly and through the fallback; the round trip returns n x the input."""
    import scipy.fft as sfft

    x = np.random.default_rng(3).normal(size=shape)
    a = halfspace.rfft2(x)
    np.testing.assert_array_equal(a, sfft.rfft2(x))
    back = halfspace.irfft2(a, shape)
    np.testing.assert_array_equal(back, sfft.irfft2(a, s=shape, norm="forward"))
    np.testing.assert_allclose(back, x * x.size, rtol=0, atol=1e-12 * x.size * np.abs(x).max())
    monkeypatch.setattr(halfspace, "POCKETFFT", None)
    np.testing.assert_array_equal(halfspace.rfft2(x), a)
    np.testing.assert_array_equal(halfspace.irfft2(a, shape), back)


@pytest.mark.parametrize("shape,dx,dy", [((23, 9), DX, DY), ((1, 5), 1e-6, 3e-6),
                                          ((40, 18), 5e-7, 4.1e-5), ((7, 31), 2.3e-6, 2.3e-6)])
def test_kernel_spectrum_equals_the_direct_coefficients_to_the_bit(shape, dx, dy):
    """The padded kernel's primitives are evaluated on the non-negative offsets and mirrored
    (F is odd in each argument): the spectrum equals that of Love's coefficients evaluated at
    every offset of the wrap-around grid, bit for bit."""
    import scipy.fft as sfft

    nx, ny = shape
    ix = np.arange(2 * nx)
    iy = np.arange(2 * ny)
    ix = np.where(ix <= nx, ix, ix - 2 * nx)
    iy = np.where(iy <= ny, iy, iy - 2 * ny)
    k = influence_coefficients(ix[:, None] * dx, iy[None, :] * dy, dx, dy, E_STAR)
    want = sfft.rfft2(k, workers=1).real / (4 * nx * ny)
    halfspace.clear_kernel_cache()
    np.testing.assert_array_equal(halfspace.kernel_spectrum(shape, dx, dy, E_STAR), want)


def test_a_pocketfft_not_as_called_here_falls_back_to_scipy_fft():
    """The private module is checked at import: one that raises, or returns other numbers, is
    not used (the public scipy.fft path is); scipy's own passes (where it exists)."""

    class Moved:
        def r2c(self, *args):
            raise TypeError("r2c() takes other arguments")

    class Off:
        def r2c(self, x, axes, forward, inorm, out, workers):
            import scipy.fft as sfft
            return sfft.rfft2(x) * (1 + 1e-15)

        c2c = c2r = r2c

    assert halfspace.checked_pocketfft(Moved()) is None
    assert halfspace.checked_pocketfft(Off()) is None
    try:
        from scipy.fft._pocketfft import pypocketfft
    except ImportError:
        pytest.skip("scipy without pypocketfft")
    assert halfspace.checked_pocketfft(pypocketfft) is pypocketfft
