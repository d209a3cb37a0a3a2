"""``subcell_displacement``: the displacement at the sub-rows of each cell by m coarse
convolutions equals the refined grid's (the pressure repeated on the sub-rows) and direct
summation of the patch influence coefficients (Love 1929)."""

import numpy as np
import pytest

from bearing_envelope.contact.halfspace import (ElasticHalfSpace, influence_coefficients,
                                                subcell_displacement)

E_STAR = 115.4e9
DX, DY = 2e-6, 2e-5


@pytest.fixture(scope="module")
def pressure():
    rng = np.random.default_rng(7)
    p = rng.uniform(0.0, 2e9, (23, 9))
    p[:4] = 0.0                        # unloaded rows, as around a contact
    return p


@pytest.mark.parametrize("m", [1, 2, 4])
def test_equals_the_refined_grid(pressure, m):
    fine = ElasticHalfSpace((pressure.shape[0] * m, pressure.shape[1]), DX / m, DY, E_STAR,
                            workers=1, backend="scipy")
    want = fine.displacement(np.repeat(pressure, m, axis=0))
    got = subcell_displacement(pressure, DX, DY, E_STAR, m)
    assert got.shape == want.shape
    assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))
    rows = subcell_displacement(pressure, DX, DY, E_STAR, m, rows=(5, 11))
    assert np.array_equal(rows, got[5 * m:11 * m])


def test_equals_direct_summation(pressure):
    m = 4
    got = subcell_displacement(pressure, DX, DY, E_STAR, m)
    nx, ny = pressure.shape
    xc, yc = (np.arange(nx) + 0.5) * DX, (np.arange(ny) + 0.5) * DY
    for k, j in [(0, 0), (37, 4), (91, 8), (50, 2)]:
        x = (k + 0.5) * DX / m                                   # sub-row k's centre
        u = np.sum(pressure * influence_coefficients(x - xc[:, None], yc[j] - yc[None, :],
                                                     DX, DY, E_STAR))
        assert got[k, j] == pytest.approx(u, rel=1e-10)
