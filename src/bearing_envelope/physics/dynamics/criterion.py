"""Model only what the scene needs: which model simulates a case, and why, in one line
(``docs/dynamics.md``, "Model only what the scene needs").

The criterion reads the defect's characteristic scales
(:func:`bearing_envelope.physics.defect_contact.defect_scales`, closed form, no contact solve):

- ``share = rigid drop / static approach`` of the pitted contact where the pit meets its event:
  the fraction of the element's static approach the pit takes away, i.e. the weight of the
  force the pit removes (the round CWRU pits at 6:00 keep 94-53 % of the load at 2-23 % of the
  approach; ``share >= 1``: centred over the pit the rigid element loses contact with the race);
- ``event_over_period = (w_x / v) / T_n``: the event's duration against the element's natural
  period between its two contacts.

The dynamics change the answer when the element's contact over the pit **opens** or nearly
opens (``share >= OPEN_SHARE``: free flight, a strike at the exit edge, rebounds, none of which
the quasi-static model has), or when a **sizeable** share of the approach is taken **fast**
enough for the element to strike the exit edge: ``share >= FAST_SHARE`` and
``share / event_over_period >= FAST_RATE`` (the share taken per natural period). Time scale
alone would flag the default sweep (its events last 0.2-1.7 natural periods) whose pits remove
under 1 % of the roller's force (share < 1e-3), and it does not part the measured strikes from
the scenes that followed (strikes at 0.42 and 0.62 natural periods, none at 0.32-0.74). The
thresholds are measured (``python -m benchmarks model_choice``, the table in the docs).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..defect_contact import defect_scales

__all__ = ["ModelChoice", "model_choice", "criterion_verdict", "OPEN_SHARE", "FAST_SHARE",
           "FAST_RATE", "QUASI_STATIC", "DYNAMIC"]

QUASI_STATIC, DYNAMIC = "quasi_static", "dynamic"

#: ``share`` at and above which the element's contact over the pit opens or nearly opens and
#: it strikes the exit edge (measured, ``python -m benchmarks model_choice``: at 0.94 the
#: contact kept 0.27 of its load and struck at 2.4 x it; at 0.36 and below, at the rig's speed,
#: it kept >= 0.68 and peaked at <= 1.12 x, the quasi-static answer within 3 dB; faster:
#: :data:`FAST_RATE`).
OPEN_SHARE = 0.5
#: ``share`` at and above which a fast event (:data:`FAST_RATE`) needs the dynamics.
FAST_SHARE = 0.1
#: ``share / event_over_period`` (the share of the static approach the pit takes per natural
#: period of the element) at and above which, with ``share >= FAST_SHARE``, the element strikes
#: the exit edge (measured, ``python -m benchmarks model_choice``, 2026-12-06, draft: strikes at
#: 1.56-1.64 x the static load at 0.35-0.38 per period; the scenes at 0.29 per period and below
#: peaked at <= 1.31 x and their answers stayed within 1.4 dB of the quasi-static one).
FAST_RATE = 0.32


@dataclass(frozen=True)
class ModelChoice:
    """The model a case uses and the reason.

    Attributes
    ----------
    model : {"quasi_static", "dynamic"}
        The model that simulates the case.
    asked : {"quasi_static", "dynamic", "auto"}
        ``scene.dynamics.model``.
    verdict : {"quasi_static", "dynamic"} or None
        The criterion's choice (None: no defect to judge).
    share : float
        Rigid drop over static approach of the pitted contact (nan without a defect).
    event_over_period : float
        Event duration over the element's natural period (nan without a defect).
    reason : str
        One line: the model, why, and the figures behind it.
    """

    model: str
    asked: str
    verdict: str | None
    share: float
    event_over_period: float
    reason: str


def criterion_verdict(share: float, ratio: float) -> tuple[str, str]:
    """The criterion's model for a pit's two scales, and its reason in words.

    Parameters
    ----------
    share : float
        Rigid drop over the pitted contact's static approach.
    ratio : float
        The event's duration over the element's natural period.

    Returns
    -------
    (str, str)
        ``dynamic`` or ``quasi_static``, and why (one line).
    """
    if share >= OPEN_SHARE:
        return DYNAMIC, f"the element's contact over the pit opens and strikes its exit edge " \
                        f"(drop/approach {share:.2g} >= {OPEN_SHARE:g})"
    rate = share / ratio if ratio > 0 else float("inf")
    if share >= FAST_SHARE and share >= FAST_RATE * ratio:
        return DYNAMIC, f"the pit takes {share:.2g} of the approach (>= {FAST_SHARE:g}) in " \
                        f"{ratio:.3g} natural periods ({rate:.2g} per period >= " \
                        f"{FAST_RATE:g}): a strike at the exit edge"
    why = f"drop/approach {share:.2g} < {OPEN_SHARE:g}" + (
        f", event {ratio:.3g} natural periods" if share < FAST_SHARE else
        f" and {rate:.2g} of it per natural period < {FAST_RATE:g} (event "
        f"{ratio:.3g} natural periods)")
    return QUASI_STATIC, f"the contact stays closed and follows the pit ({why})"


def model_choice(scene) -> ModelChoice:
    """Which model simulates ``scene`` (``scene.dynamics.model``; ``auto``: the criterion).

    Parameters
    ----------
    scene : Scene
        The case's validated scene (its ``dynamics`` section, defect, bearing, load).

    Returns
    -------
    ModelChoice
        The model and its one-line reason; the criterion's verdict is computed for a forced
        model too (the reason says when it disagrees).
    """
    asked = scene.dynamics.model
    if not scene.defect.active:
        model = DYNAMIC if asked == DYNAMIC else QUASI_STATIC
        return ModelChoice(model, asked, None, float("nan"), float("nan"),
                           f"{model} (scene.dynamics.model {asked}; no defect: nothing for the "
                           f"criterion to judge)")
    sc = defect_scales(scene)
    share, ratio = float(sc.drop_over_approach), float(sc.event_over_period)
    verdict, why = criterion_verdict(share, ratio)
    if asked == "auto":
        return ModelChoice(verdict, asked, verdict, share, ratio, f"{verdict} (auto: {why})")
    note = "agrees" if asked == verdict else f"the criterion says {verdict}"
    return ModelChoice(asked, asked, verdict, share, ratio,
                       f"{asked} (scene.dynamics.model {asked}; {note}: {why})")
