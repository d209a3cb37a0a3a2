"""The scene's ``dynamics:`` section: which bearing model simulates a case, and the assumed
structure of the dynamic one (``docs/dynamics.md``, "Model only what the scene needs").

::

    dynamics:
      model: quasi_static      # quasi_static | dynamic | auto (the criterion decides)
      structure:               # optional: any key of physics.dynamics.params.STRUCTURE_DEFAULTS
        housing_mass_kg: 5.0
        resonator_hz: 4000.0

The default (``quasi_static``, no structure override) is written once, in
:data:`bearing_envelope.physics.scene.DEFAULT_SCENE`; the structure's defaults once, here
(:data:`STRUCTURE_DEFAULTS`; ``physics.dynamics.params`` re-exports it). This module is a leaf
(the scene builder and the dynamic model import it); the criterion behind ``auto`` is
:func:`bearing_envelope.physics.dynamics.criterion.model_choice`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

__all__ = ["DYNAMICS_MODELS", "Dynamics", "build_dynamics", "STRUCTURE_DEFAULTS",
           "STRUCTURE_POSITIVE"]

#: ``scene.dynamics.model``: the quasi-static contact model (``physics/history.py``), the
#: lumped-parameter dynamic model (``physics/dynamics``), or the criterion's choice.
DYNAMICS_MODELS = ("quasi_static", "dynamic", "auto")

#: Assumed structural values of the dynamic model (not published for any rig; identify them per
#: rig): shaft with inner ring 2 kg carried by this bearing alone (no support stiffness), outer
#: ring with housing 5 kg on 1e8 N/m with 5 % damping, a 4 kHz resonator of 50 g with 5 %
#: damping on the load axis, contact damping 2 % of critical for an element between its two
#: contacts at the static load. ``scene.dynamics.structure`` overrides any of them.
STRUCTURE_DEFAULTS = {
    "shaft_mass_kg": 2.0, "shaft_stiffness_n_m": 0.0, "shaft_damping_ns_m": 0.0,
    "housing_mass_kg": 5.0, "housing_stiffness_n_m": 1e8, "housing_zeta": 0.05,
    "resonator_hz": 4000.0, "resonator_zeta": 0.05, "resonator_mass_kg": 0.05,
    "sensor_angle_deg": 0.0, "contact_zeta": 0.02,
}

#: Structure keys that must be > 0 (the others: >= 0; ``sensor_angle_deg`` any finite angle).
STRUCTURE_POSITIVE = ("shaft_mass_kg", "housing_mass_kg", "resonator_hz", "resonator_mass_kg")


@dataclass(frozen=True)
class Dynamics:
    """``scene.dynamics``, validated.

    Attributes
    ----------
    model : {"quasi_static", "dynamic", "auto"}
        The model asked for (``auto``: :func:`~bearing_envelope.physics.dynamics.criterion.
        model_choice` decides per case).
    structure : tuple of (str, float)
        Overrides of the assumed structure (keys of ``STRUCTURE_DEFAULTS``, their units in the
        names), sorted by key; empty: the defaults.
    """

    model: str
    structure: tuple[tuple[str, float], ...]

    def to_mapping(self) -> dict[str, Any]:
        """The config layout of this section.

        Returns
        -------
        dict
            ``{"model": ..., "structure": {...} or None}``.
        """
        return {"model": self.model, "structure": dict(self.structure) or None}


def _bad(field: str, value: Any, allowed: str) -> ValueError:
    return ValueError(f"scene.dynamics.{field}: got {value!r}; allowed: {allowed}")


def build_dynamics(m: Mapping[str, Any]) -> Dynamics:
    """Validate the merged ``scene.dynamics`` mapping (once, at load).

    Parameters
    ----------
    m : mapping
        ``model`` (one of :data:`DYNAMICS_MODELS`) and ``structure`` (None or a mapping of
        ``STRUCTURE_DEFAULTS`` keys to numbers).

    Returns
    -------
    Dynamics
        The typed section.

    Raises
    ------
    ValueError
        One line naming the field (``scene.dynamics.model``, ``scene.dynamics.structure.<key>``),
        the value and what is allowed.
    """
    model = m.get("model")
    if model not in DYNAMICS_MODELS:
        raise _bad("model", model, " | ".join(DYNAMICS_MODELS))
    given = m.get("structure")
    if given is None:
        return Dynamics(model, ())
    if not isinstance(given, Mapping):
        raise _bad("structure", given, f"null or a mapping with keys {sorted(STRUCTURE_DEFAULTS)}")
    out = {}
    for key, value in given.items():
        if key not in STRUCTURE_DEFAULTS:
            raise _bad(f"structure.{key}", value, f"a key of {sorted(STRUCTURE_DEFAULTS)}")
        ok = not isinstance(value, bool) and isinstance(value, (int, float)) \
            and math.isfinite(value)
        lo = ">" if key in STRUCTURE_POSITIVE else ">=" if key != "sensor_angle_deg" else None
        if ok and lo is not None:
            ok = value > 0 if lo == ">" else value >= 0
        if not ok:
            raise _bad(f"structure.{key}", value,
                       "a finite number" + (f" {lo} 0" if lo else ""))
        out[key] = float(value)
    return Dynamics(model, tuple(sorted(out.items())))
