"""What the defect meets, known before any contact solve: the loads of its passages.

The defect changes the history only while it is inside a loaded contact (design.md section 2).
From the load distribution and the location alone (no solve) this module gives, per contact
(race) the defect passes through, the element loads of its passages, sampled uniformly over
the angles at which they happen (the location's
:meth:`~bearing_envelope.physics.locations.FaultLocation.passage_angles`):

- inner race: the defect turns with the shaft; it passes elements at every angle ``psi`` from
  the load direction (uniformly over a record of whole revolutions): ``Q_i(psi)``;
- outer race: the defect is fixed at ``phi_d``; ``smooth``: every passage at ``Q_o(phi_d)``;
  ``discrete``: the load of the element over the pit, at the angles where the pit lies inside
  its contact (``phi_d +- (a_H + w_x/2)/R_o``);
- rolling element: the element orbits with the cage; its defect meets the inner race at
  ``Q_i(theta_c)`` and the outer race at ``Q_o(theta_c)``, ``theta_c`` uniform.

A passage is loaded when its load exceeds the rounding of the load law
(:meth:`~bearing_envelope.physics.loads.LoadDistribution.loaded`: ``delta_r cos(pi/2)`` is
6e-17 ``delta_r``, not a load).

From those: whether the defect ever meets a loaded contact (a case that never does is reported
before its 416 solves of zeros, :func:`exposure`), the range of loads the table must cover
(solved from the smallest load met, not held below a node), and, per passage, whether the pit
is bridged by the contact (its axial extent within :data:`BRIDGE_MAX_FRACTION` x 2b, the
validated limit) or longer than the whole contact (2b, Hertz): there the model's traction-free
hole is not the contact that happens (the element drops into the pit onto its rim).
"""

from __future__ import annotations


import numpy as np

from .geometry import hertz_estimate
from .loads import LoadDistribution

__all__ = ["BRIDGE_MAX_FRACTION", "PASSAGE_SAMPLES", "passage_loads", "exposure", "exposure_line"]

#: A ball bridges a pit wider than its contact (2a across rolling) when the pit is short
#: axially against the contact ellipse (2b): the contact keeps both axial lobes and the pit
#: bottom is never reached. Validated up to this fraction of 2b, the largest measured
#: (``benchmarks/wide_pit.py``: the CWRU 0.021 in pit at 1 kN, 0.25 of 2b on the inner race,
#: 0.26 on the outer; window solve vs whole-ellipse solve, docs/benchmarks.md, issue 23 parts 5-6).
BRIDGE_MAX_FRACTION = 0.26

#: Angles sampled per contact (uniform over the passages' angles).
PASSAGE_SAMPLES = 3600


def passage_loads(scene, ld: LoadDistribution, n: int = PASSAGE_SAMPLES) -> dict[str, np.ndarray]:
    """Element loads (N) of the defect's passages per contact race, sampled uniformly over the
    angles at which they happen (module docstring).

    Parameters
    ----------
    scene : Scene
        The case's scene: its defect's location and the bearing's kinematics.
    ld : LoadDistribution
        The case's load distribution (:func:`~.loads.scene_load_distribution`).
    n : int
        Samples per race.

    Returns
    -------
    dict
        ``{"inner": loads}``, ``{"outer": loads}`` or both (rolling element).
    """
    angles = scene.defect.fault_location.passage_angles(scene, ld, n)
    return {race: ld.load_at(psi, race) for race, psi in angles.items()}


def _pit_limits(scene, race: str) -> tuple[float, float]:
    """``(Q_bridge, Q_longer)`` (N): below ``Q_bridge`` the pit's axial extent exceeds
    :data:`BRIDGE_MAX_FRACTION` x 2b (Hertz, ``b`` the axial semi-axis, ``b ~ Q^(1/3)``), below
    ``Q_longer`` it exceeds 2b (the whole contact)."""
    b1 = hertz_estimate(scene.for_race(race), 1.0).b
    ey = scene.defect.extent_y_m
    return (ey / (2.0 * BRIDGE_MAX_FRACTION * b1)) ** 3, (ey / (2.0 * b1)) ** 3


def exposure(scene, ld: LoadDistribution) -> dict:
    """Before any solve: does the defect meet a loaded contact, over which loads, and is the pit
    bridged at each passage.

    Parameters
    ----------
    scene : Scene
        The case's scene (defect location, extent, position).
    ld : LoadDistribution
        Its load distribution (:func:`~.loads.scene_load_distribution`).

    Returns
    -------
    dict
        ``loaded`` (bool), and per race (``inner`` / ``outer``): ``q_min_N``, ``q_max_N`` (loads
        met, loaded passages only; 0 when none), ``loaded_fraction`` (passages with a load above
        the rounding of the load law, :meth:`~.loads.LoadDistribution.loaded`),
        ``bridge_load_N`` and ``longer_load_N`` (:func:`_pit_limits`), and among the loaded
        passages the fractions ``beyond_bridge_fraction`` (pit longer than 0.26 x 2b) and
        ``longer_than_contact_fraction`` (pit longer than 2b). Without a defect only ``loaded``
        and the loads.
    """
    out: dict = {"loaded": False, "races": {}}
    for race, q in passage_loads(scene, ld).items():
        on = q[ld.loaded(q)]
        r = {"q_min_N": float(on.min()) if on.size else 0.0,
             "q_max_N": float(on.max()) if on.size else 0.0,
             "loaded_fraction": float(on.size / q.size)}
        if scene.defect.active and on.size:
            qb, ql = _pit_limits(scene, race)
            r.update(bridge_load_N=qb, longer_load_N=ql,
                     beyond_bridge_fraction=float(np.mean(on < qb)),
                     longer_than_contact_fraction=float(np.mean(on < ql)))
        out["races"][race] = r
        out["loaded"] = out["loaded"] or bool(on.size)
    return out


def exposure_line(scene, exp: dict) -> str | None:
    """One line for the user when the case needs one: the defect never meets a loaded contact,
    or some of its passages are beyond the pit-bridging limit.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    exp : dict
        Its :func:`exposure`.

    Returns
    -------
    str or None
        The line, None when the case needs none.
    """
    if not scene.defect.active:
        return None
    if not exp["loaded"]:
        where = scene.defect.fault_location.where(scene)
        return (f"{where}: the defect never meets a loaded contact (element load 0, or within the "
                f"load law's rounding, at every passage; load.centrifugal or a preload would "
                f"load it): no contact solve, the history is that of an unloaded contact")
    parts = []
    for race, r in exp["races"].items():
        if r.get("beyond_bridge_fraction", 0.0) > 0:
            parts.append(f"{race} race: pit ({1e6 * scene.defect.extent_y_m:.4g} um axially) beyond "
                         f"{BRIDGE_MAX_FRACTION:g} x 2b below {r['bridge_load_N']:.3g} N in "
                         f"{100 * r['beyond_bridge_fraction']:.2g} % of the loaded passages, longer "
                         f"than the contact below {r['longer_load_N']:.3g} N in "
                         f"{100 * r['longer_than_contact_fraction']:.2g} %")
    return "; ".join(parts) or None
