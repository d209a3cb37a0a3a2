"""Handing typed values to workflow jobs: :class:`JobValue` params and :func:`job_settings`,
the one loader of a job (nothing parsed or checked again).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..physics.fidelity import Fidelity
from ..physics.scene import Scene
from ..physics.transfer import TransferModel
from .case_id import CaseId
from .sections import AnalysisSettings
from .tradeoff_settings import TradeoffSettings

__all__ = ["JobValue", "CaseSetup", "TradeoffSetup", "JobSettings", "JOB_PARAMS",
           "job_settings"]


class JobValue(str):
    """A validated value on its way to a workflow job: its canonical JSON text, carrying the
    value itself (:attr:`value`).

    Snakemake decides that a job must rerun by comparing its ``params`` with the last run's, and
    compares only plain values (a ``str`` by its text; a typed object is not compared at all),
    so a typed value travels as this text. Snakemake pickles a job's params into its script,
    so :attr:`value` arrives as the loader built it: :func:`job_settings` reads it without
    parsing or checking anything again.
    """

    value: Any

    def __new__(cls, text: str, value: Any) -> "JobValue":
        obj = super().__new__(cls, text)
        obj.value = value
        return obj

    def __reduce__(self):
        return (JobValue, (str(self), self.value))


@dataclass(frozen=True)
class CaseSetup:
    """What a simulate job runs: its case, the case's scene (built and validated by the loader)
    and the fidelity."""

    case: CaseId
    scene: Scene
    fidelity: Fidelity


@dataclass(frozen=True)
class TradeoffSetup:
    """What the trade-off job runs: the ``tradeoff:`` section (typed), the ``scene:`` section
    and the analysis settings."""

    settings: TradeoffSettings
    scene_mapping: dict
    analysis: AnalysisSettings


@dataclass(frozen=True)
class JobSettings:
    """The typed values a workflow job received (None: its rule hands none)."""

    simulation: CaseSetup | None = None
    analysis: AnalysisSettings | None = None
    sensor: TransferModel | None = None
    tradeoff: TradeoffSetup | None = None


#: The params :func:`job_settings` reads: name -> the type of its value.
JOB_PARAMS: dict[str, tuple[type, ...]] = {
    "simulation": (CaseSetup,), "analysis": (AnalysisSettings,),
    "sensor": (TransferModel, type(None)), "tradeoff": (TradeoffSetup,)}


def job_settings(snakemake) -> JobSettings:
    """The one loader of a workflow job: the typed values its rule handed it as params
    (:class:`JobValue`: ``Settings.simulation_param`` / ``analysis_param`` / ``sensor_param``
    / ``tradeoff_param``), as the workflow's loader built and validated them; nothing is parsed
    or checked again.

    Parameters
    ----------
    snakemake : object
        The ``snakemake`` object of a script job (its ``params``).

    Returns
    -------
    JobSettings
        The job's case setup (case, scene, fidelity), analysis, sensor and trade-off values;
        None for what its rule does not hand.

    Raises
    ------
    TypeError
        A param of :data:`JOB_PARAMS` that is not a :class:`JobValue` of the right type (a
        rule handing plain text).
    """
    params = snakemake.params
    values = {}
    for name, kinds in JOB_PARAMS.items():
        if not hasattr(params, name):
            continue
        p = getattr(params, name)
        if not isinstance(p, JobValue) or not isinstance(p.value, kinds):
            got = type(p.value if isinstance(p, JobValue) else p).__name__
            raise TypeError(f"params.{name}: got a {got}; allowed: a JobValue of "
                            f"{' | '.join(k.__name__ for k in kinds)} "
                            f"(Settings.{name}_param)")
        values[name] = p.value
    return JobSettings(**values)
