"""The line search that survives a speed error (:func:`search_lines`): each family's fundamental
searched within ``f_nom * (1 +- p / 100)``, harmonics and sidebands following the line found,
each scored against its local floor."""

from __future__ import annotations

import math

import numpy as np

from ...signal.spectrum import DEFAULT_WINDOW, amplitude_at, default_tolerance
from ..detection import BACKGROUND_BAND, DEFAULT_PFA, detection_statistic
from .families import DEFAULT_SEARCH_PERCENT, FaultFamily

__all__ = ["search_lines"]


def _score(f, a, line_hz, half, *, fr, exclude, pfa):
    """Detection of one line (``diagnosis.detection_statistic``); None when the spectrum is
    too short for a background around it."""
    # only the background band [lo, hi] x line (+ the search window and the local-maximum
    # check's neighbours) enters the statistic: pass that slice, not the whole spectrum
    lo, hi = BACKGROUND_BAND
    df = f[1] - f[0]
    i0 = max(0, int(math.floor((lo * line_hz - half) / df)) - 2)
    i1 = min(f.size, int(math.ceil((hi * line_hz + half) / df)) + 3)
    try:
        return detection_statistic(f[i0:i1], a[i0:i1], line_hz, fr=fr, tolerance_hz=half,
                                   sidebands=0, exclude_hz=exclude, pfa=pfa)
    except ValueError:
        return None


def search_lines(
    f,
    amplitude,
    family: FaultFamily,
    *,
    fr: float | None = None,
    n_harmonics: int,
    n_sidebands: int,
    search_percent: float = DEFAULT_SEARCH_PERCENT,
    tolerance_hz: float | None = None,
    pfa: float = DEFAULT_PFA,
    interpolate: bool = False,
    window=DEFAULT_WINDOW,
    n: int | None = None,
    min_search_bins: float = 0.0,
) -> list[dict]:
    r"""Fundamental, harmonics and sidebands of one fault family in a spectrum.

    Parameters
    ----------
    f, amplitude : ndarray
        A one-sided spectrum (uniform ``f`` from 0 Hz), e.g. from
        :func:`~bearing_envelope.signal.envelope_spectrum`.
    family : FaultFamily
        The family (see :func:`fault_families`).
    fr : float, optional
        Shaft rate (Hz): its harmonics are kept out of the floor.
    n_harmonics : int
        Harmonics k = 1..K (the analysis's: ``AnalysisOptions.n_harmonics``).
    n_sidebands : int
        Sidebands m = 1..M per side (only for a family with a sideband spacing).
    search_percent : float, default 1.0
        Half-width of the fundamental's search, percent of its nominal frequency.
    tolerance_hz : float, optional
        A fixed half-width (Hz) for every line instead (the fundamental searched around its
        nominal frequency, everything else around the speed-corrected targets).
    pfa : float, default 0.01
        False-alarm probability of each line's detection threshold.
    interpolate, window, n
        Refine the reported frequency and amplitude of each peak bin, see
        :func:`~bearing_envelope.signal.amplitude_at` (the floor ratio stays the bin's).
    min_search_bins : float, default 0
        The fundamental's search half-width is at least this many bins (the resolution floor
        the harmonics' :func:`~bearing_envelope.signal.spectrum.default_tolerance` has: a line
        between two bins shows in either; 0.5 % of a 12 Hz cage rate is less than one bin of
        a 10 s record).

    Returns
    -------
    list of dict
        One record per line with ``order`` (k), ``sideband`` (signed m), ``target_hz`` (the
        nominal fundamental for k = 1, m = 0; else ``k f_1 + m s f_sb``), ``frequency_hz`` and
        ``amplitude`` (the largest bin of the window, or interpolated), ``floor`` (local
        median), ``floor_ratio_db``, ``threshold_db``, ``detected`` (NaN / None where the
        spectrum holds no background around the line). Lines beyond the spectrum are skipped;
        if the fundamental is, the list is empty.

    Raises
    ------
    ValueError
        ``n_harmonics`` < 1, ``n_sidebands`` < 0 or ``search_percent`` outside (0, 50).

    Notes
    -----
    With :math:`f_1` the largest bin within :math:`f_{nom}(1 \pm p/100)` and
    :math:`s = f_1 / f_{nom}`, harmonic k is the largest bin within
    :math:`k f_1 \pm \max(2\Delta f, 0.002\,k f_1)`, sideband m of it within
    :math:`k f_1 + m s f_{sb} \pm` the same (at most :math:`f_{sb}/4`).
    """
    f = np.asarray(f, dtype=np.float64)
    a = np.asarray(amplitude, dtype=np.float64)
    n_harmonics = int(n_harmonics)
    n_sidebands = int(n_sidebands) if family.sideband_hz else 0
    if n_harmonics < 1:
        raise ValueError(f"n_harmonics must be >= 1, got {n_harmonics}")
    if n_sidebands < 0:
        raise ValueError(f"n_sidebands must be >= 0, got {n_sidebands}")
    p = float(search_percent)
    if not math.isfinite(p) or not 0.0 < p < 50.0:
        raise ValueError(f"search_percent must be in (0, 50), got {search_percent!r}")
    df = float(f[1] - f[0])
    fmax = float(f[-1])
    F = float(family.frequency_hz)
    spacing = float(family.sideband_hz) if n_sidebands else 0.0

    def exclusions(f1, sp):
        # every line of the family inside the background band of the highest harmonic
        jmax = int(math.ceil(BACKGROUND_BAND[1] * (n_harmonics + 1))) + 1
        out = [j * f1 for j in range(1, jmax + 1)]
        out += [j * f1 + m * sp for j in range(1, jmax + 1) for m in
                range(-n_sidebands, n_sidebands + 1) if m and sp]
        return out

    def line(order, sideband, target, centre, half, excl):
        if centre + half > fmax or centre - half < 0:
            return None
        det = _score(f, a, centre, half, fr=fr, exclude=excl, pfa=pfa)
        if det is not None:
            ff, aa = det.peak_hz, det.peak_amplitude
        else:
            ff, aa = amplitude_at(f, a, centre, half)
        rec = {"order": order, "sideband": sideband, "target_hz": target, "frequency_hz": ff,
               "amplitude": aa,
               "floor": math.nan if det is None else det.background,
               "floor_ratio_db": math.nan if det is None else det.statistic_db,
               "threshold_db": math.nan if det is None else det.threshold_db,
               "detected": None if det is None else bool(det.detected)}
        if interpolate:
            rec["frequency_hz"], rec["amplitude"] = amplitude_at(f, a, ff, 0.0, interpolate=True,
                                                                 window=window, n=n)
        return rec, ff

    half1 = (float(tolerance_hz) if tolerance_hz is not None
             else max(p / 100.0 * F, float(min_search_bins) * df))
    first = line(1, 0, F, F, half1, exclusions(F, spacing))
    if first is None:
        return []
    rec1, f1 = first
    s = f1 / F
    sp = s * spacing
    excl = exclusions(f1, sp)
    out = []
    for k in range(1, n_harmonics + 1):
        if k == 1:
            rec_k, fk = rec1, f1
        else:
            c = k * f1
            half = float(tolerance_hz) if tolerance_hz is not None else default_tolerance(c, df)
            got = line(k, 0, c, c, half, excl)
            if got is None:
                break
            rec_k, fk = got
        recs = [rec_k]
        for m in range(1, n_sidebands + 1):
            for sign in (-1, 1):
                c = k * f1 + sign * m * sp
                half = (float(tolerance_hz) if tolerance_hz is not None
                        else default_tolerance(c, df, sp))
                got = line(k, sign * m, c, c, half, excl)
                if got is not None:
                    recs.append(got[0])
        out.extend(sorted(recs, key=lambda r: r["sideband"]))
    return out
