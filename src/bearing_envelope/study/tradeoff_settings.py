"""The ``tradeoff:`` section of a config, typed and checked once (:class:`TradeoffSettings`).

Its defaults (:data:`TRADEOFF_DEFAULTS`) and the knobs' meaning (:func:`apply_knob`) live here,
below :mod:`bearing_envelope.study.settings`, whose loader builds the section once per run
(``Settings.tradeoff``); :mod:`bearing_envelope.study.tradeoff` runs the study from it without
checking it again (and re-exports these names).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..physics.fidelity import PRESETS, Fidelity, fidelity_from

__all__ = ["DEFAULT_CASES", "DEFAULT_KNOBS", "TRADEOFF_DEFAULTS", "TradeoffSettings",
           "apply_knob"]

#: (load_kN, depth_um) of the representative cases.
DEFAULT_CASES: tuple[tuple[float, float], ...] = (
    (250.0, 0.0), (250.0, 15.0), (250.0, 100.0), (750.0, 0.0), (750.0, 15.0), (750.0, 100.0))

#: Knob values, coarse to fine (the base value of each knob is added if missing).
DEFAULT_KNOBS: dict[str, list] = {
    "global_dx_um": [20.0, 10.0, 5.0],
    "global_dy_um": [300.0, 150.0, 75.0],
    "local_dx_um": [8.0, 4.0, 2.0],
    "local_dy_um": [40.0, 20.0, 10.0],
    "tol": [1e-4, 1e-5, 1e-6, 1e-8],
    "n_loads": [3, 5, 8],
    "offset_density": [0.5, 1.0, 2.0],
    "element": ["uniform", "linear"],
    "edge_radius_um": [40.0, 20.0, 10.0],
}

_SCENE_KNOBS = ("edge_radius_um",)
_OFFSET_FIELDS = ("n_offsets", "offsets_per_width", "max_offsets")


def _replace(base: Fidelity, **kw) -> Fidelity:
    """``base`` with ``kw``; the base's rim strips (and axial end strips) are dropped where they
    cannot refine the new setting (linear elements, or a window spacing they do not divide by an
    integer >= 2): the default has rim strips since issue 25, and a knob of the window must
    still be measurable."""
    for spacing, parent in (("rim_dx_um", "local_dx_um"), ("end_dy_um", "local_dy_um")):
        if spacing not in kw and getattr(base, spacing) is not None:
            d, el = kw.get(parent, getattr(base, parent)), kw.get("element", base.element)
            r = d / getattr(base, spacing)
            if el != "uniform" or r < 2 - 1e-9 or abs(r - round(r)) > 1e-6:
                kw[spacing] = None
    return dataclasses.replace(base, **kw)


def apply_knob(base: Fidelity, knob: str, value) -> tuple[Fidelity, dict]:
    """The fidelity of one knob value and the scene overrides it implies.

    Parameters
    ----------
    base : Fidelity
        The fidelity the knob is varied around.
    knob : str
        A fidelity field, ``offset_density`` (a factor on the table's offset nodes), a scene
        knob (``edge_radius_um``), or any of these with ``[linear]`` (linear elements).
    value : float or int
        The knob's value (the factor for ``offset_density``).

    Returns
    -------
    tuple of (Fidelity, dict)
        The fidelity with the knob set, and the scene overrides (``{"defect": {...}}`` for a
        scene knob, else empty).

    Raises
    ------
    ValueError
        An unknown knob, or an ``offset_density`` factor not > 0.
    """
    if knob in _SCENE_KNOBS:
        return base, {"defect": {knob: float(value)}}
    if knob == "offset_density":
        f = float(value)
        if not f > 0:
            raise ValueError(f"tradeoff.knobs.offset_density: factors must be > 0, got {value!r}")
        return dataclasses.replace(
            base, n_offsets=max(3, int(round(base.n_offsets * f))),
            offsets_per_width=base.offsets_per_width * f,
            max_offsets=max(3, int(round(base.max_offsets * f))),
            offset_step_um=base.offset_step_um / f), {}
    if knob.endswith("[linear]"):
        fid, sc = apply_knob(base, knob[:-len("[linear]")], value)
        return _replace(fid, element="linear"), sc
    names = {f.name for f in dataclasses.fields(Fidelity)}
    if knob not in names or knob in ("name",):
        raise ValueError(f"tradeoff.knobs: unknown knob {knob!r}; allowed: fidelity fields "
                         f"{sorted(names - {'name'})}, offset_density, edge_radius_um")
    ftype = type(getattr(base, knob))
    v = value
    if ftype is int and isinstance(v, float) and v.is_integer():
        v = int(v)
    elif ftype is float and isinstance(v, int):
        v = float(v)
    return _replace(base, **{knob: v}), {}


#: Defaults of the ``tradeoff:`` config section, written here only (the schema holds none;
#: :class:`TradeoffSettings` reads them). ``knobs`` None: :data:`DEFAULT_KNOBS`.
TRADEOFF_DEFAULTS: dict[str, Any] = {
    "cases": DEFAULT_CASES, "revolutions": 4.0, "base": "standard", "reference": "finest",
    "reference_element": "uniform", "element_series": ("local_dx_um",),
    "presets": ("draft", "standard", "paper"), "knobs": None,
}


@dataclass(frozen=True)
class TradeoffSettings:
    """The trade-off study's settings, checked (:meth:`from_mapping`; meaning of the keys:
    :func:`bearing_envelope.study.tradeoff.tradeoff_study`).

    Attributes
    ----------
    section : dict
        The mapping as given (the trade-off job's rerun trigger).
    cases : tuple of (float, float)
        ``(load_kN, depth_um)`` of each case.
    revolutions : float
    base : Fidelity
    reference : str or Fidelity
        ``"finest"``, ``"per_knob"`` or the explicit reference (named ``reference``).
    reference_element : {"uniform", "linear"}
    element_series : tuple of str
    presets : dict of str to Fidelity
    knobs : dict of str to list
        Knob -> values as given, coarse to fine (:data:`DEFAULT_KNOBS` when not given).
    """

    section: dict
    cases: tuple
    revolutions: float
    base: Fidelity
    reference: Any
    reference_element: str
    element_series: tuple
    presets: dict
    knobs: dict

    @classmethod
    def from_mapping(cls, section: Mapping[str, Any] | None) -> "TradeoffSettings":
        """Check a ``tradeoff:`` mapping (missing keys: :data:`TRADEOFF_DEFAULTS`) and type it.

        Parameters
        ----------
        section : mapping or None
            The config's ``tradeoff:`` section (values may also be Fidelity objects).

        Returns
        -------
        TradeoffSettings
            The cases ``(load_kN, depth_um)``, revolutions, base and reference fidelities, the
            presets and the knobs (each a list of values, coarse to fine), checked.

        Raises
        ------
        ValueError
            One line naming the key (``tradeoff.knobs.tol``), the value and what is allowed.
        """
        given = dict(section or {})
        for key in given:
            if key not in TRADEOFF_DEFAULTS:
                raise ValueError(f"tradeoff.{key}: unknown key; allowed: "
                                 f"{', '.join(TRADEOFF_DEFAULTS)}")
        s = {**TRADEOFF_DEFAULTS, **given}
        base = _fidelity("tradeoff.base", s["base"])
        knobs = _knobs(s["knobs"], base)
        element_series = tuple(s["element_series"] or ())
        for k in element_series:
            if k not in knobs:
                raise ValueError(f"tradeoff.element_series: {k!r} is not one of the knobs "
                                 f"{sorted(knobs)}")
        if s["reference_element"] not in ("uniform", "linear"):
            raise ValueError(f"tradeoff.reference_element: got {s['reference_element']!r}; "
                             f"allowed: uniform | linear")
        presets = s["presets"] or {}
        if not isinstance(presets, Mapping):
            presets = {str(p): p for p in presets}
        return cls(section=given, cases=_cases(s["cases"]), revolutions=_revolutions(s["revolutions"]),
                   base=base, reference=_reference(s["reference"]),
                   reference_element=s["reference_element"], element_series=element_series,
                   presets={str(n): _fidelity(f"tradeoff.presets.{n}", p)
                            for n, p in presets.items()},
                   knobs=knobs)


def _fidelity(where: str, spec) -> Fidelity:
    try:
        return fidelity_from(spec)
    except (ValueError, TypeError) as exc:
        msg = str(exc)
        raise ValueError(msg if msg.startswith("tradeoff") else f"{where}: {msg}") from None


def _cases(cases) -> tuple:
    out = []
    for c in cases:
        if isinstance(c, (str, bytes)) or not isinstance(c, Sequence) or len(c) != 2 or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) and v >= 0 for v in c):
            raise ValueError(f"tradeoff.cases: got {c!r}; allowed: [load_kN, depth_um]")
        out.append((float(c[0]), float(c[1])))
    return tuple(out)


def _revolutions(rev) -> float:
    if isinstance(rev, bool) or not isinstance(rev, (int, float)) or not rev > 0:
        raise ValueError(f"tradeoff.revolutions: got {rev!r}; allowed: a number > 0")
    return float(rev)


def _knobs(knobs, base: Fidelity) -> dict[str, list]:
    """Knob -> values (checked: a known knob, each value applies to the base)."""
    knobs = DEFAULT_KNOBS if knobs is None else knobs
    if not isinstance(knobs, Mapping):
        raise ValueError(f"tradeoff.knobs: got {knobs!r}; allowed: a mapping knob -> values")
    out = {}
    for knob, values in knobs.items():
        if isinstance(values, str) or not isinstance(values, Sequence) or not values:
            raise ValueError(f"tradeoff.knobs.{knob}: got {values!r}; allowed: a list of "
                             f"values, coarse to fine")
        if knob == "element" and any(v not in ("uniform", "linear") for v in values):
            raise ValueError(f"tradeoff.knobs.element: got {list(values)!r}; allowed: "
                             f"uniform | linear")
        for v in values:
            try:
                apply_knob(base, str(knob), v)
            except (ValueError, TypeError) as exc:
                msg = " ".join(str(exc).split())
                raise ValueError(msg if msg.startswith("tradeoff") else
                                 f"tradeoff.knobs.{knob}: {v!r}: {msg}") from None
        out[str(knob)] = list(values)
    return out


def _reference(reference):
    """``"finest"``, ``"per_knob"`` or the explicit reference fidelity (named ``reference``)."""
    if isinstance(reference, str) and reference in ("finest", "per_knob"):
        return reference
    if isinstance(reference, (Mapping, Fidelity)) or reference in PRESETS:
        return dataclasses.replace(_fidelity("tradeoff.reference", reference), name="reference")
    raise ValueError(f"tradeoff.reference: got {reference!r}; allowed: finest | per_knob | "
                     f"a preset name | a fidelity mapping")
