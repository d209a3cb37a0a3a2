"""The fused numba kernel against a slow, literal implementation of the same equations."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import signal as sp_signal

from bearing_envelope.signal import fast_kurtogram


def _split(z, w, dec, shifts):
    """Children of node z: demodulate by each shift, filter with w (from rest), keep
    samples dec*m + dec - 1 (np.convolve, full length)."""
    t = np.arange(z.size)
    out = []
    for f in shifts:
        y = np.convolve(z * np.exp(-2j * np.pi * f * t), w)[: z.size]
        out.append(y[dec - 1 :: dec][: z.size // dec])
    return out


def _kurt(c, drop):
    c = c[drop:]
    a2 = np.abs(c) ** 2
    return max(np.mean(a2**2) / np.mean(a2) ** 2 - 2.0, 0.0)


def reference_rows(x, nlevel):
    w2 = sp_signal.firwin(17, 0.4)
    w3 = sp_signal.firwin(25, 0.4 * 2 / 3)
    x = x - x.mean()
    rows = {0: None}
    nodes, centre, drop = [x.astype(complex)], 0.25, 0
    for k in range(nlevel):
        if 2 * k + 2 < 2 * nlevel:  # ternary split of level k (not of the deepest level)
            d3 = max(0, math.ceil((25 - 3 + drop) / 3))
            rows[2 * k + 2] = np.array([
                _kurt(c, d3) for z in nodes
                for c in _split(z, w3, 3, (centre - 1 / 6, centre, centre + 1 / 6))])
        d2 = max(0, math.ceil((17 - 2 + drop) / 2))
        nodes = [c for z in nodes for c in _split(z, w2, 2, (centre - 1 / 8, centre + 1 / 8))]
        rows[2 * k + 1] = np.array([_kurt(c, d2) for c in nodes])
        centre, drop = 0.0, d2
    return rows


@pytest.mark.parametrize("n, nlevel, seed", [(2**11, 3, 0), (3001, 4, 1), (5000, 5, 2)])
def test_kernel_matches_literal_implementation(n, nlevel, seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n) + 3.0
    x[:: 97] += 8.0  # impulsive content so the values are not all ~0
    kg = fast_kurtogram(x, 1000.0, nlevel)
    ref = reference_rows(x, nlevel)
    for r in range(1, 2 * nlevel):
        np.testing.assert_allclose(kg.rows[r], ref[r], rtol=1e-9, atol=1e-12, err_msg=f"row {r}")


@settings(max_examples=15, deadline=None)
@given(scale=st.floats(1e-6, 1e9), offset=st.floats(-1e6, 1e6), seed=st.integers(0, 2**16))
def test_scale_and_offset_invariance(scale, offset, seed):
    x = np.random.default_rng(seed).standard_normal(4096)
    x[::500] += 6.0
    a = fast_kurtogram(x, 100.0, 4)
    b = fast_kurtogram(scale * x + offset * scale, 100.0, 4)
    np.testing.assert_allclose(b.matrix, a.matrix, rtol=1e-5, atol=1e-6)
    assert (b.level, b.fc) == (a.level, a.fc)
