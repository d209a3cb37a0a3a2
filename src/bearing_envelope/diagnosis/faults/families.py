"""Fault families: a characteristic bearing frequency with its harmonics and its own sideband
spacing (:class:`FaultFamily`, :func:`fault_families`), and their display names."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from ...physics.kinematics import spin_events

__all__ = ["DEFAULT_SEARCH_PERCENT", "FAMILY_LABELS", "SIDEBAND_SPACING", "FaultFamily",
           "display_name", "fault_families"]


#: Default half-width (percent of the nominal frequency) of the search for a fundamental.
DEFAULT_SEARCH_PERCENT = 1.0

#: What a detected family means.
FAMILY_LABELS = {
    "bpfo": "outer race fault",
    "bpfi": "inner race fault",
    "bsf": "rolling element fault",
    "bsf2": "rolling element fault",
    "ftf": "cage fault",
}

#: Sideband spacing of each known family: the name of another frequency, or None.
SIDEBAND_SPACING = {"bpfi": "fr", "bsf": "ftf", "bsf2": "ftf", "bpfo": None, "ftf": None}

_DISPLAY = {"bpfo": "BPFO", "bpfi": "BPFI", "bsf": "BSF", "bsf2": "2xBSF", "ftf": "FTF",
            "fr": "fr"}


def display_name(name: str) -> str:
    """The display form of a fault-family name: ``"bpfi" -> "BPFI"``, ``"bsf2" -> "2xBSF"``.

    Parameters
    ----------
    name : str
        A family name as the tables store it (``bpfi``, ``bpfo``, ``bsf``, ``bsf2``, ``ftf``,
        ``fr``) or any other string.

    Returns
    -------
    str
        The name for figures and reports; a name that is not a family comes back unchanged.
    """
    return _DISPLAY.get(name, name)


@dataclass(frozen=True)
class FaultFamily:
    """One fault family.

    Attributes
    ----------
    name : str
        Key of the frequency (``bpfo``, ``bpfi``, ``bsf``, ``bsf2``, ``ftf`` or a user name).
    frequency_hz : float
        Nominal fundamental (Hz).
    sideband_name : str or None
        Name of the sideband spacing (``"fr"``, ``"ftf"``) or None for no sidebands.
    sideband_hz : float or None
        The nominal spacing (Hz).
    label : str
        What a detection means (``"inner race fault"``; a user family: ``"<name> line"``).
    """

    name: str
    frequency_hz: float
    sideband_name: str | None
    sideband_hz: float | None
    label: str


def fault_families(frequencies: Mapping[str, float], *, fr: float,
                   sidebands: Mapping[str, str | None] | None = None) -> tuple[FaultFamily, ...]:
    """Fault families of the named frequencies (Hz), with their sideband spacing.

    Parameters
    ----------
    frequencies : mapping
        ``name -> Hz`` of the fault lines (``bpfo``, ``bpfi``, ``bsf``, ``bsf2``, ``ftf``, or
        any other name). A ``bsf`` without ``bsf2`` adds ``bsf2 = 2 bsf`` (a spall on a rolling
        element strikes both races once per spin revolution).
    fr : float
        Shaft rate (Hz), the spacing named ``"fr"``.
    sidebands : mapping, optional
        ``name -> spacing name`` (``"fr"``, another family's name, or None), overriding
        :data:`SIDEBAND_SPACING`. Families not listed anywhere get no sidebands. A spacing
        whose frequency is unknown (``bsf`` without ``ftf``) gives no sidebands. A spacing may
        also be a pair ``(name, Hz)``: a spacing that is not itself a searched family (the
        sweep's rolling-element cases: ``{"bsf2": ("ftf", f_c)}``).

    Returns
    -------
    tuple of FaultFamily
        In the order given (``bsf2`` right after ``bsf``).
    """
    freqs = {str(k): float(v) for k, v in frequencies.items()}
    if "bsf" in freqs and "bsf2" not in freqs:
        items = []
        for k, v in freqs.items():
            items.append((k, v))
            if k == "bsf":
                items.append(("bsf2", spin_events(v)))
        freqs = dict(items)
    spacing_map = {**SIDEBAND_SPACING, **dict(sidebands or {})}
    known = {"fr": float(fr), **freqs}
    out = []
    for name, hz in freqs.items():
        sb = spacing_map.get(name)
        if isinstance(sb, tuple):
            sb, sb_hz = str(sb[0]), float(sb[1])
        else:
            sb_hz = known.get(sb) if sb is not None else None
        if sb_hz is None:
            sb = None
        out.append(FaultFamily(name, hz, sb, sb_hz, FAMILY_LABELS.get(name, f"{name} line")))
    return tuple(out)
