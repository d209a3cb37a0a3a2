"""The actual shaft rate, measured from the shaft harmonics of the raw spectrum.

A record's nominal speed (the motor's rating plate, a tachometer reading taken once) differs
from the actual one by a fraction of a percent (CWRU: 1797 rpm nominal, 1796 rpm measured at
0 hp; 1730 nominal, 1720 measured at 3 hp). Every kinematic fault frequency scales with the
shaft rate, so an uncorrected speed error moves every line the same way and forces a wide search
window around each fundamental; within a wide window the largest bin may be an unrelated line.
The rotor's own unbalance and misalignment put lines at ``k fr`` into any accelerometer record on
the machine, so the shaft rate can be read off the raw spectrum: the peak of each of the first
:data:`SPEED_ORDERS` shaft harmonics within :data:`SPEED_SEARCH_PERCENT` of its nominal value,
refined by parabolic interpolation of the log-amplitude, divided by its order; the median over
the orders (robust to one order masked by an electrical line: 4 x 30 Hz = 2 x 60 Hz mains) is
the estimate. What remains between a race fault line and its kinematic value at the measured
speed is slip of the rolling elements, which the line search then covers
(:data:`MEASURED_SPEED_SEARCH_PERCENT`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..signal.spectrum import DEFAULT_WINDOW, amplitude_spectrum

__all__ = ["MEASURED_SPEED_SEARCH_PERCENT", "SPEED_ORDERS", "SPEED_SEARCH_PERCENT", "ShaftRate",
           "SPEED_LINE_MIN_DB", "SPEED_MIN_ORDERS", "SPEED_AGREEMENT_PERCENT",
           "estimate_shaft_rate"]

#: A shaft harmonic counts only when its peak stands this far above the median of the spectrum
#: around it (+-5 x the search half-width, dB): on a record without rotor lines the largest bin
#: of a 2 % window is noise, and a speed read from it would move every fault line. For Rayleigh
#: noise a bin 15 dB above the median has probability ~3e-10 (10 dB: ~1e-3, which two of 20
#: white-noise records passed in the test); the 28 CWRU development records' 1-3 x fr lines
#: stand 15.7-54 dB above it, at least two of each record's three above 22 dB.
SPEED_LINE_MIN_DB = 15.0
#: Harmonics that must count and agree with their median within SPEED_AGREEMENT_PERCENT (of the
#: shaft rate) for the speed to be taken as measured (one masked order is outvoted); otherwise
#: the nominal rate is kept (``ShaftRate.measured`` False) and the analysis keeps its
#: nominal-speed search window.
SPEED_MIN_ORDERS = 2
SPEED_AGREEMENT_PERCENT = 0.2
#: The floor around a harmonic spans this many search half-widths on each side.
SPEED_FLOOR_SPAN = 5

#: Shaft harmonics whose peaks give the speed (the first three: the strongest rotor lines, and
#: below the 4th, which a 60 Hz mains harmonic can mask on a 30 Hz shaft).
SPEED_ORDERS = (1, 2, 3)
#: Half-width of the search for each shaft harmonic, percent of its nominal frequency: an
#: induction motor's slip between no load and full load (1797 -> 1730 rpm on the CWRU rig is
#: 3.7 % over the whole load range, the nominal value of each load lies within 1 % of the actual).
SPEED_SEARCH_PERCENT = 2.0
#: Half-width (percent) of the search for a fault fundamental once the speed is measured: the
#: slip of the rolling elements (race lines of the 12 clearly diagnosable CWRU records sit within
#: 0.3 % of their kinematic value at the measured speed; Randall & Antoni 2011 quote 1-2 % for
#: the cage and ball, less for the races) instead of speed error plus slip (1 %).
MEASURED_SPEED_SEARCH_PERCENT = 0.5


@dataclass(frozen=True)
class ShaftRate:
    """A measured shaft rate.

    Attributes
    ----------
    hz : float
        The estimate (Hz): median over the orders.
    nominal_hz : float
        The nominal rate it was searched around (Hz).
    per_order : tuple of float
        The estimate of each order ``k`` of :data:`SPEED_ORDERS` whose line stands out (peak
        frequency / k, Hz).
    measured : bool
        False when fewer than :data:`SPEED_MIN_ORDERS` lines stand out and agree: ``hz`` is
        then the nominal rate.
    """

    hz: float
    nominal_hz: float
    per_order: tuple[float, ...]
    measured: bool = True

    @property
    def ratio(self) -> float:
        """``hz / nominal_hz``: the factor every kinematic frequency is scaled by."""
        return self.hz / self.nominal_hz


def estimate_shaft_rate(x, fs: float, fr_nominal: float, *, orders=SPEED_ORDERS,
                        search_percent: float = SPEED_SEARCH_PERCENT,
                        window=DEFAULT_WINDOW, spectrum=None) -> ShaftRate:
    """The shaft rate from the peaks of its first harmonics in the raw spectrum.

    Parameters
    ----------
    x : array_like, 1-D
        The record (any unit).
    fs : float
        Sampling frequency (Hz).
    fr_nominal : float
        Nominal shaft rate (Hz).
    orders : sequence of int, default :data:`SPEED_ORDERS`
        Shaft harmonics used.
    search_percent : float, default :data:`SPEED_SEARCH_PERCENT`
        Half-width of each harmonic's search, percent of ``k fr_nominal``.
    window : str or tuple, default "hann"
        Window of the raw spectrum.
    spectrum : (f, amplitude), optional
        The raw spectrum ``amplitude_spectrum(x, fs, window=window)`` when the caller has it
        (not computed again).

    Returns
    -------
    ShaftRate
        The median of the per-order estimates of the lines that stand out
        (:data:`SPEED_LINE_MIN_DB`); unless :data:`SPEED_MIN_ORDERS` of them agree with that
        median within :data:`SPEED_AGREEMENT_PERCENT`, the nominal rate unchanged with
        ``measured`` False.
    """
    f, a = (amplitude_spectrum(np.asarray(x, dtype=np.float64), fs, window=window)
            if spectrum is None else spectrum)
    df = float(f[1] - f[0])
    est = [e for e in (_order_estimate(f, a, df, k, float(fr_nominal), search_percent)
                       for k in orders) if e is not None]
    hz = float(np.median(est)) if est else float(fr_nominal)
    agree = [e for e in est if abs(e - hz) / float(fr_nominal) * 100.0 <= SPEED_AGREEMENT_PERCENT]
    if len(agree) < SPEED_MIN_ORDERS:
        return ShaftRate(float(fr_nominal), float(fr_nominal), tuple(est), measured=False)
    return ShaftRate(hz, float(fr_nominal), tuple(est))


def _order_estimate(f, a, df: float, k: int, fr_nominal: float,
                    search_percent: float) -> float | None:
    """The shaft rate from harmonic ``k`` (Hz), or None when its peak is beyond the spectrum or
    does not stand :data:`SPEED_LINE_MIN_DB` above the median around it."""
    c = k * fr_nominal
    half = max(2.0 * df, search_percent / 100.0 * c)
    i0, i1 = int(math.floor((c - half) / df)), int(math.ceil((c + half) / df)) + 1
    span = int(math.ceil(SPEED_FLOOR_SPAN * half / df))
    if i0 < 1 or i1 >= f.size - 1:
        return None
    i = i0 + int(np.argmax(a[i0:i1]))
    around = np.r_[a[max(1, i0 - span):i0], a[i1:min(f.size, i1 + span)]]
    floor = float(np.median(around)) if around.size else 0.0
    if not a[i] > floor * 10.0 ** (SPEED_LINE_MIN_DB / 20.0):
        return None
    return _interpolated_bin(a, i) * df / k


def _interpolated_bin(a, i: int) -> float:
    """Fractional bin of the peak at ``i``: parabola through the log-amplitudes of ``i - 1, i,
    i + 1`` (exact for a Gaussian main lobe, within 0.05 bin for a Hann window)."""
    y0, y1, y2 = (math.log(max(float(v), 1e-300)) for v in a[i - 1:i + 2])
    den = y0 - 2.0 * y1 + y2
    return float(i) if den >= 0.0 else i + 0.5 * (y0 - y2) / den
