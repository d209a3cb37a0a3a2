"""A case file's fault-frequency attributes are the rates its own events run at.

The truth is the simulated history itself: ``defect_offset`` (the defect's arc offset from the
nearest roller's contact centre) jumps by a roller pitch each time the defect meets a roller
(inner and outer race) or a race (rolling element, which meets the inner and the outer race once
per spin turn each: twice per BSF period). The mean period of those jumps, read from the file,
must be 1 / the frequency the file states for its location's family: BPFI, BPFO (= Z x the
cage rate used), 2 x BSF, with the study's BPFI override (231.9 Hz, which acts through the cage
rate) and without it (geometry).
"""

from __future__ import annotations

import numpy as np
import pytest

from bearing_envelope.io import read_case, write_case
from bearing_envelope.physics.history import simulate
from bearing_envelope.physics.scene import Scene

#: Location -> (attribute, factor): the family's event rate is factor x the attribute.
FAMILY = {"inner_race": ("bpfi", 1.0), "outer_race": ("bpfo", 1.0), "rolling_element": ("bsf", 2.0)}
FS_HZ = 20000.0


def _event_period(case) -> tuple[float, int]:
    """Mean time between the jumps of ``defect_offset`` (s) and the number of jumps."""
    off = np.asarray(case.signals["defect_offset"])
    t = np.asarray(case.time)
    jumps = np.flatnonzero(np.abs(np.diff(off)) > 0.5 * np.ptp(off))
    assert jumps.size >= 5, jumps.size
    return float(t[jumps[-1]] - t[jumps[0]]) / (jumps.size - 1), int(jumps.size)


@pytest.mark.parametrize("override_hz", [231.9, None], ids=["study_override", "geometric"])
@pytest.mark.parametrize("location", sorted(FAMILY))
def test_case_attributes_state_the_rates_of_its_events(tmp_path, location, override_hz):
    scene = Scene.from_mapping({"operation": {"revolutions": 1.5, "bpfi_override_hz": override_hz,
                                              "fs_hz": FS_HZ, "acquisition": {"mode": "point"}},
                                "defect": {"location": location}}, load_kN=500, depth_um=20)
    path = tmp_path / "case.h5"
    write_case(path, simulate(scene, "draft"))
    case = read_case(path)
    key, factor = FAMILY[location]
    period, n = _event_period(case)
    # the jump times are known to one sample each: the mean period to 2 samples / (n - 1)
    assert period == pytest.approx(1.0 / (factor * case.attrs[key]),
                                   abs=2.0 / FS_HZ / (n - 1))
    # the cage rate the file states is the one its events imply, and with the override it is
    # not the geometric one (which the file keeps beside it)
    assert case.attrs["ftf"] == pytest.approx(case.attrs["cage_rate_used"], rel=1e-12)
    if override_hz is not None:
        assert abs(case.attrs["bpfo"] / case.attrs["bpfo_geometry"] - 1) > 0.2
    else:
        assert case.attrs["bpfo"] == pytest.approx(case.attrs["bpfo_geometry"], rel=1e-9)
