"""One in-memory case type: a simulated history becomes an ``io.Case`` in one function
(``Case.from_history``), and that Case is field by field what its file gives back.

The truth is the file: ``read_case(write_case(h))`` for the same history, on a tiny scene of
each defect location (a rolling element has two tables). Only the attributes a write adds or
stamps differ (the digest, the creation time).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd
import pytest

from bearing_envelope.io import Case, read_case, write_case
from bearing_envelope.io.integrity import DIGEST_ATTR
from bearing_envelope.physics.history import simulate
from bearing_envelope.physics.scene import Scene
from bearing_envelope.study.accuracy import case_error_model
from bearing_envelope.study.pipeline import history_case

#: Attributes a write stamps (the time of writing) or adds (the digest of the file).
WRITE_STAMPS = ("created_utc", DIGEST_ATTR)


def _same(a, b, where: str) -> None:
    """Equal values, recursively; arrays by dtype, shape and bytes; NaN equals NaN."""
    if isinstance(a, dict) or isinstance(b, dict):
        assert isinstance(a, dict) and isinstance(b, dict), where
        assert sorted(a) == sorted(b), (where, sorted(set(a) ^ set(b)))
        for k in a:
            _same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        assert isinstance(a, np.ndarray) and isinstance(b, np.ndarray), where
        assert (a.dtype, a.shape) == (b.dtype, b.shape), where
        assert a.tobytes() == b.tobytes(), where
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{where}[{i}]")
    elif isinstance(a, float) and math.isnan(a):
        assert isinstance(b, float) and math.isnan(b), where
    else:
        assert type(a) is type(b) and a == b, (where, a, b)


@pytest.mark.parametrize("location", ["inner_race", "outer_race", "rolling_element"])
def test_case_from_history_is_what_its_file_gives_back(tmp_path, location):
    scene = Scene.from_mapping({"operation": {"revolutions": 1.0, "fs_hz": 20000.0},
                                "defect": {"location": location}}, load_kN=500, depth_um=20)
    h = simulate(scene, "draft", progress=False)
    extra = {"workflow_rule": "test", "case": "F500kN_h20um"}
    em = case_error_model(h)
    made = Case.from_history(h, extra_attrs=extra, error_model=em)
    read = read_case(write_case(tmp_path / "case.h5", h, extra_attrs=extra, error_model=em))
    for f in dataclasses.fields(Case):
        a, b = getattr(made, f.name), getattr(read, f.name)
        if f.name == "attrs":
            a = {k: v for k, v in a.items() if k not in WRITE_STAMPS}
            b = {k: v for k, v in b.items() if k not in WRITE_STAMPS}
        if f.name == "error_model":
            assert (a.point, a.kind, a.basis, a.withheld) == (b.point, b.kind, b.basis,
                                                              b.withheld)
            pd.testing.assert_frame_equal(a.table.reset_index(drop=True),
                                          b.table.reset_index(drop=True), check_dtype=False,
                                          check_like=True)  # h5 lists columns by name
            continue
        _same(a, b, f.name)
    assert set(read.other_tables) == ({"outer"} if location == "rolling_element" else set())
    # the fidelity is carried as its value, not as text to parse again
    assert made.attrs["fidelity"] == read.attrs["fidelity"]
    # a Case is written as it is: the same file content as writing the history
    again = read_case(write_case(tmp_path / "again.h5", made))
    _same({k: v for k, v in again.attrs.items() if k not in WRITE_STAMPS},
          {k: v for k, v in read.attrs.items() if k not in WRITE_STAMPS}, "rewritten attrs")
    _same(again.table, read.table, "rewritten table")
    _same(again.signals, read.signals, "rewritten signals")


def test_history_case_is_a_case_with_its_error_model():
    scene = Scene.from_mapping({"operation": {"revolutions": 0.5, "fs_hz": 20000.0}},
                               load_kN=500, depth_um=0)
    h = simulate(scene, "draft", progress=False)
    case = history_case(h)
    assert isinstance(case, Case)
    em = case_error_model(h)
    assert (case.error_model.point, case.error_model.kind, case.error_model.basis) == \
        (em.point, em.kind, em.basis)
    assert case.attrs["fidelity"]["name"] == "draft"
