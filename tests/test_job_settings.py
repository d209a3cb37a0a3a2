"""Workflow jobs receive the loader's typed values and check nothing again.

Truths: Snakemake's own handling of params (a ``str`` param is compared by its ``repr``, a job's
params reach its script pickled), and the loader's values themselves (a job's value is equal to
the one the loader built, and arrives with every validating function disabled).
"""

from __future__ import annotations

import pickle
from pathlib import Path
from types import SimpleNamespace

import pytest

from bearing_envelope.physics.scene import Scene
from bearing_envelope.physics.transfer import TransferModel
from bearing_envelope.study import settings as st
from bearing_envelope.study.job_transport import job_settings
from bearing_envelope.study.sections import AnalysisSettings
from bearing_envelope.study.tradeoff_settings import TradeoffSettings

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def settings():
    return st.load_settings(ROOT / "tests" / "data" / "config_draft.yaml")


def _as_job(**params):
    """A ``snakemake`` object as a script job gets it: its params pickled and read back."""
    return pickle.loads(pickle.dumps(SimpleNamespace(params=SimpleNamespace(**params))))


def test_job_values_arrive_as_built_without_a_check(settings, monkeypatch):
    case = settings.cases[-1]
    params = {"simulation": settings.simulation_param(case),
              "analysis": settings.analysis_param(), "sensor": settings.sensor_param(),
              "tradeoff": settings.tradeoff_param()}
    data = pickle.dumps(SimpleNamespace(params=SimpleNamespace(**params)))

    def refuse(*a, **k):
        raise AssertionError("a job validated a value again")

    for owner, name in ((Scene, "from_mapping"), (TransferModel, "from_mapping"),
                        (AnalysisSettings, "from_mapping"), (st, "fidelity_from"),
                        (TradeoffSettings, "from_mapping")):
        monkeypatch.setattr(owner, name, refuse)
    monkeypatch.setattr(type(settings.fidelity), "__post_init__", refuse)
    job = job_settings(pickle.loads(data))
    assert job.simulation.case == case
    assert job.simulation.scene == settings.scene(case)
    assert job.simulation.fidelity == settings.fidelity
    assert job.analysis == settings.analysis
    assert job.sensor == settings.sensor
    assert job.tradeoff.settings == settings.tradeoff
    assert job.tradeoff.analysis == settings.analysis


def test_the_rerun_trigger_is_the_canonical_text(settings):
    # Snakemake compares a str param by repr(value) (persistence._serialize_param_builtin)
    for p, text in ((settings.analysis_param(), settings.analysis.to_json()),
                    (settings.simulation_param(settings.cases[0]), settings.simulation.to_json()),
                    (settings.sensor_param(), settings.sensor.to_json())):
        assert isinstance(p, str) and repr(p) == repr(text)


def test_a_plain_text_param_is_refused_in_one_line(settings):
    with pytest.raises(TypeError, match=r"^params\.analysis: got a str; allowed: a JobValue of "
                                        r"AnalysisSettings \(Settings\.analysis_param\)$"):
        job_settings(_as_job(analysis=settings.analysis.to_json()))
    with pytest.raises(TypeError, match=r"^params\.sensor: got a AnalysisSettings"):
        job_settings(_as_job(sensor=settings.analysis_param()))
