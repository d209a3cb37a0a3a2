import math

import pytest
from hypothesis import given, settings, strategies as st

from bearing_envelope.contact import hertz


def test_sphere_textbook():
    c = hertz.sphere(100.0, 0.01, 1.15e11)
    assert c.a == pytest.approx((3 * 100 * 0.01 / (4 * 1.15e11)) ** (1 / 3), rel=1e-14)
    assert c.p0 == pytest.approx(2 * 1.15e11 * c.a / (math.pi * 0.01), rel=1e-12)
    assert c.approach == pytest.approx(c.a**2 / 0.01, rel=1e-14)
    assert c.mean_pressure == pytest.approx(2 * c.p0 / 3, rel=1e-14)


def test_elliptical_reduces_to_sphere():
    s = hertz.sphere(50.0, 0.02, 1e11)
    e = hertz.elliptical(50.0, 0.02, 0.02 * (1 + 1e-6), 1e11)
    assert e.a == pytest.approx(s.a, rel=1e-6)
    assert e.b == pytest.approx(s.b, rel=1e-6)
    assert e.p0 == pytest.approx(s.p0, rel=1e-6)
    assert e.approach == pytest.approx(s.approach, rel=1e-6)


def test_design_hand_numbers():
    # design.md: Rx = 7.68 mm, Ry = 4233 mm, E* = 115.4 GPa
    for force, b_mm, a_mm, p0_gpa in [(26.8e3, 15.9, 0.33, 2.5), (80.4e3, 22.9, 0.47, 3.6), (250e3, 33, 0.69, 5.2)]:
        c = hertz.elliptical(force, 7.68e-3, 4.233, 115.4e9)
        assert c.b * 1e3 == pytest.approx(b_mm, rel=0.02)
        assert c.a * 1e3 == pytest.approx(a_mm, rel=0.02)
        assert c.p0 / 1e9 == pytest.approx(p0_gpa, rel=0.03)


def test_elliptical_axes_follow_radii():
    c1 = hertz.elliptical(10.0, 0.01, 0.5, 1e11)
    c2 = hertz.elliptical(10.0, 0.5, 0.01, 1e11)
    assert c1.a < c1.b
    assert (c2.a, c2.b, c2.p0) == pytest.approx((c1.b, c1.a, c1.p0), rel=1e-12)


def test_known_axis_ratio_table():
    # the solved axis ratio satisfies the defining equation (Johnson eq. 4.39)
    from scipy.special import ellipe, ellipk

    k = hertz.elliptic_ratio(10.0)
    m = 1 - k * k
    assert (ellipe(m) / k**2 - ellipk(m)) / (ellipk(m) - ellipe(m)) == pytest.approx(10.0, rel=1e-10)


@settings(max_examples=30, deadline=None)
@given(
    f=st.floats(1.0, 1e6),
    rx=st.floats(1e-3, 1e-1),
    ratio=st.floats(1.0, 1e3),
    k=st.floats(1.1, 10.0),
)
def test_scaling_laws(f, rx, ratio, k):
    c1 = hertz.elliptical(f, rx, rx * ratio, 1e11)
    c2 = hertz.elliptical(k * f, rx, rx * ratio, 1e11)
    assert c2.p0 / c1.p0 == pytest.approx(k ** (1 / 3), rel=1e-9)
    assert c2.a / c1.a == pytest.approx(k ** (1 / 3), rel=1e-9)
    assert c2.approach / c1.approach == pytest.approx(k ** (2 / 3), rel=1e-9)
    assert 2 * math.pi * c1.a * c1.b * c1.p0 / 3 == pytest.approx(f, rel=1e-12)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_errors_name_the_field(bad):
    with pytest.raises(ValueError, match="force"):
        hertz.sphere(bad, 0.01, 1e11)
    with pytest.raises(ValueError, match="ry"):
        hertz.elliptical(1.0, 0.01, bad, 1e11)
    with pytest.raises(ValueError, match="e_star"):
        hertz.elliptical(1.0, 0.01, 0.01, bad)
