"""Amplitudes of given lines and their harmonics: the raw spectrum's terms (0 Hz, k x fr,
k x BPFI) and a base line's harmonics with shaft-rate sidebands, both through the fault line
search (:func:`bearing_envelope.diagnosis.faults.search_lines`)."""

from __future__ import annotations

import numpy as np

from ..signal.spectrum import DEFAULT_WINDOW, amplitude_spectrum
from ..signal.validation import check_fs, check_positive, check_signal
from .faults import DEFAULT_SEARCH_PERCENT, FaultFamily, search_lines

__all__ = ["harmonic_amplitudes", "raw_terms"]


def harmonic_amplitudes(
    f,
    amplitude,
    base: float,
    *,
    fr: float | None = None,
    n_harmonics: int,
    n_sidebands: int,
    search_percent: float | None = None,
    tolerance: float | None = None,
    interpolate: bool = False,
    window=DEFAULT_WINDOW,
    n: int | None = None,
) -> list[dict]:
    r"""Amplitudes at the fundamental near :math:`f_b`, its harmonics and sidebands.

    The search of :func:`bearing_envelope.diagnosis.faults.search_lines`: the fundamental
    :math:`f_1` is the largest bin within :math:`f_b (1 \pm p/100)`; harmonic k is searched
    around :math:`k f_1`, its sidebands around :math:`k f_1 \pm m s f_r` with
    :math:`s = f_1/f_b` (the speed error moves every line by the same ratio), within
    ``max(2 df, 0.002 f)`` (at most ``fr/4``).

    Parameters
    ----------
    f, amplitude : ndarray
        An (envelope) spectrum.
    base : float
        Nominal base frequency :math:`f_b` (Hz), e.g. BPFI.
    fr : float, optional
        Sideband spacing (Hz), the shaft rate. Needed when ``n_sidebands > 0``.
    n_harmonics : int
        Orders k = 1..K.
    n_sidebands : int
        Sidebands m = 1..M on each side.
    search_percent : float, optional
        Half-width ``p`` of the fundamental's search (percent); default
        :data:`~bearing_envelope.diagnosis.faults.DEFAULT_SEARCH_PERCENT` (1 %).
    tolerance : float, optional
        A fixed search half-width (Hz) for every line instead.
    interpolate, window, n
        See :func:`amplitude_at`.

    Returns
    -------
    list of dict
        Records with ``order`` (k), ``sideband`` (signed m, 0 for the harmonic itself),
        ``target_hz`` (the nominal base for k = 1, m = 0, else the speed-corrected centre),
        ``frequency_hz`` (the peak found) and ``amplitude`` (unit of ``amplitude``), plus
        ``floor``, ``floor_ratio_db``, ``threshold_db``, ``detected`` (see
        :func:`~bearing_envelope.diagnosis.faults.search_lines`). Lines beyond the spectrum are
        skipped.
    """
    base = check_positive(base, "base")
    n_harmonics = int(n_harmonics)
    n_sidebands = int(n_sidebands)
    if n_harmonics < 1:
        raise ValueError(f"n_harmonics must be >= 1, got {n_harmonics}")
    if n_sidebands < 0:
        raise ValueError(f"n_sidebands must be >= 0, got {n_sidebands}")
    if n_sidebands > 0:
        fr = check_positive(fr, "fr")
    fam = FaultFamily("base", base, "fr" if n_sidebands else None, fr if n_sidebands else None,
                      "base line")
    return search_lines(f, amplitude, fam, fr=fr, n_harmonics=n_harmonics,
                        n_sidebands=n_sidebands,
                        search_percent=DEFAULT_SEARCH_PERCENT if search_percent is None
                        else search_percent,
                        tolerance_hz=tolerance, interpolate=interpolate, window=window, n=n)


def raw_terms(
    x,
    fs: float,
    *,
    fr: float,
    bpfi: float,
    n_harmonics: int,
    tolerance: float | None = None,
    window=DEFAULT_WINDOW,
    interpolate: bool = False,
    search_percent: float | None = None,
) -> list[dict]:
    """Raw-spectrum terms: the 0 Hz term, k x fr and k x BPFI (k = 1..n_harmonics).

    Parameters
    ----------
    x : array_like, 1-D
        Real signal (unit ``U``), not de-meaned: the 0 Hz term is its mean.
    fs, fr, bpfi : float
        Sampling frequency, nominal shaft rate and inner-race fault frequency (Hz).
    n_harmonics : int
        Orders k of fr and BPFI (the analysis's: ``AnalysisOptions.n_raw_harmonics``).
    tolerance : float, optional
        A fixed search half-width (Hz) around every target instead of the default search.
    window, interpolate
        See :func:`amplitude_spectrum` and :func:`amplitude_at`.
    search_percent : float, optional
        Half-width of the search for fr and BPFI, percent of the nominal value (default 1 %);
        their harmonics are searched around k x the line found within
        ``max(2 df, 0.002 f)`` (:func:`bearing_envelope.diagnosis.faults.search_lines`).

    Returns
    -------
    list of dict
        One record per term with keys ``base`` ("dc", "fr", "bpfi"), ``order``,
        ``target_hz``, ``frequency_hz`` and ``amplitude`` (in ``U``; the 0 Hz amplitude is the
        signal mean, the others the amplitude of the sinusoid, window-corrected), and for the
        lines ``floor``, ``floor_ratio_db``, ``threshold_db``, ``detected``.
    """
    fs = check_fs(fs)
    fr = check_positive(fr, "fr")
    bpfi = check_positive(bpfi, "bpfi")
    x = check_signal(x, "x")
    f, a = amplitude_spectrum(x, fs, window=window)
    out = [
        {
            "base": "dc",
            "order": 0,
            "target_hz": 0.0,
            "frequency_hz": 0.0,
            # exact mean (the windowed 0 Hz bin equals it only for a constant signal)
            "amplitude": float(np.mean(x)),
        }
    ]
    p = DEFAULT_SEARCH_PERCENT if search_percent is None else search_percent
    for name, base in (("fr", fr), ("bpfi", bpfi)):
        if base >= fs / 2:
            continue
        fam = FaultFamily(name, base, None, None, name)
        for r in search_lines(f, a, fam, fr=fr, n_harmonics=int(n_harmonics), n_sidebands=0,
                              search_percent=p, tolerance_hz=tolerance,
                              interpolate=interpolate, window=window, n=x.size):
            r.pop("sideband")
            out.append({"base": name, **r})
    return out
