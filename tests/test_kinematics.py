import math

import pytest
from hypothesis import given, strategies as st

from bearing_envelope.physics.kinematics import fault_frequencies


def test_skf6205_multipliers():
    # Published SKF 6205 multipliers (design.md; e.g. the CWRU data set documentation).
    o = fault_frequencies(1.0, 9, 7.94e-3, 39.04e-3).orders()
    assert o["bpfi"] == pytest.approx(5.4152, abs=5e-5)
    assert o["bpfo"] == pytest.approx(3.5848, abs=5e-5)
    assert o["ftf"] == pytest.approx(0.3983, abs=5e-5)
    assert o["bsf"] == pytest.approx(2.357, abs=5e-4)


def test_source_study_geometry_gives_194hz_not_stated_231hz():
    # FAG 534176: 22 rollers per row, d = 17.45 mm, D = (110 + 180)/2 mm, 12.82 deg, 15.8 Hz.
    ff = fault_frequencies(15.8, 22, 17.45e-3, 145e-3, 12.82)
    assert ff.bpfi == pytest.approx(194.2, abs=0.05)
    # The stated 231.9 Hz needs about 26.3 rollers per row at this pitch diameter.
    n_equiv = 231.9 / (ff.bpfi / 22)
    assert n_equiv == pytest.approx(26.3, abs=0.05)


@given(
    n=st.integers(1, 60),
    d=st.floats(1e-3, 0.05),
    ratio=st.floats(1.2, 20.0),
    phi=st.floats(0.0, 60.0),
)
def test_identities(n, d, ratio, phi):
    ff = fault_frequencies(10.0, n, d, d * ratio, phi)
    # BPFO + BPFI = n fr, BPFO = n FTF (independent of geometry)
    assert ff.bpfo + ff.bpfi == pytest.approx(n * 10.0)
    assert ff.bpfo == pytest.approx(n * ff.ftf)
    assert ff.bpfi > ff.bpfo


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(fr=0.0), "fr"),
        (dict(n_rollers=0), "n_rollers"),
        (dict(roller_diameter=-1.0), "roller_diameter"),
        (dict(pitch_diameter=0.01), "roller_diameter"),
        (dict(contact_angle_deg=95.0), "contact_angle_deg"),
        (dict(fr=math.nan), "fr"),
    ],
)
def test_bad_input_names_field(kwargs, field):
    args = dict(fr=15.8, n_rollers=22, roller_diameter=17.45e-3, pitch_diameter=0.145,
                contact_angle_deg=12.82)
    args.update(kwargs)
    with pytest.raises(ValueError, match=field):
        fault_frequencies(**args)
