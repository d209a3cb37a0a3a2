"""Shared fixtures for the contact tests: tiny grids with a node at the centre."""

import numpy as np
import pytest


@pytest.fixture
def sphere_case():
    """Hertz sphere, 128 x 128 over a box of side 6a."""
    from bearing_envelope.contact import hertz

    R, F, E = 0.01, 10.0, 1.0e11
    ref = hertz.sphere(F, R, E)
    n = 128
    d = 6 * ref.a / n
    x = (np.arange(n) - n // 2) * d  # node n // 2 exactly at the centre
    gap = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    return dict(R=R, F=F, E=E, ref=ref, n=n, d=d, gap=gap)
