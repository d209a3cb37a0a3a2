"""The transfer path identified from a measured record: what the fault impulses excite.

A fault impulse (a ball meeting a pit) rings the structure between the bearing and the
accelerometer; the record holds that ringing, repeated at the fault's event rate, on top of the
machine's background. :func:`identify_path` recovers, from the record alone:

1. **The resonance band**: the fast kurtogram's best band (Antoni 2007), its level limited so
   that the band is wide enough to show the decay (:data:`MAX_LEVEL`).
2. **The event rate and the events**: the envelope spectrum of that band must hold a line at
   one of the candidate event rates (the bearing's BPFO, BPFI, BSF, 2 x BSF, or one given),
   above the exact detection threshold of :func:`bearing_envelope.diagnosis.detection.threshold_db`
   at :data:`DEFAULT_PFA`; else nothing is identified (:class:`NoImpulsesError`). The events are
   the envelope maxima, one per period of that rate, above the Rayleigh bound of the
   band's background at :data:`EVENT_PFA` per period.
3. **Damping and natural frequency**: the squared envelopes of the events, aligned on their
   peaks and averaged (the background's power subtracted), decay as the mode's envelope seen
   through the same band-pass; ``zeta`` is fitted to that decay with the filter in the model
   (a 1-D least-squares fit of a damped sine, band-passed and demodulated like the record).
   ``f_n`` is the peak of the events' averaged spectrum over the background's, in the band.
   **More than one mode**: every further peak of that spectrum (the power the events add) that
   stands above its saddle by more than the false-alarm bound :data:`MODE_PFA` (the prominence
   over its standard error across the events) and within :data:`MODE_FLOOR` of the strongest
   is a mode of its own, fitted like the first in a band centred on it (narrowed to half the
   distance to the next mode); a record whose second peak is not significant keeps one mode.
4. **Amplitude**: the initial amplitude ``a`` of the mode's response to one event (record
   units), from the same fit. With an excitation impulse of area ``A`` (N s, say) the mode's
   gain at resonance is ``a / (A 2 zeta omega_n)`` (:meth:`TransferPath.mode`).
5. **Background**: the power spectral density of the record with the events gated out (Welch),
   or of a healthy record of the same machine when one is given.

The result (:class:`TransferPath`) is JSON-serialisable, so that a simulated excitation can be
made a record of that machine (:meth:`TransferPath.mode`, :func:`background_noise`).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field

import numpy as np
from scipy import optimize, signal as sps, stats

from ..physics.transfer import Mode
from ..signal.envelope import bandpass
from ..signal.kurtogram import fast_kurtogram, max_kurtogram_level
from ..signal.validation import check_fs, check_signal
from .detection import threshold_db

#: Area of the excitation impulse a mode's gain refers to when none is given: a unit impulse.
UNIT_IMPULSE_AREA = 1.0

__all__ = ["TransferPath", "NoImpulsesError", "identify_path", "background_noise",
           "MIN_EVENTS", "DEFAULT_PFA", "EVENT_PFA", "MAX_LEVEL", "MODE_PFA", "MODE_FLOOR",
           "MAX_MODES"]

#: Fewest detected events an identification accepts (a record shorter than this many periods
#: of the event rate is refused before any work).
MIN_EVENTS = 20
#: False-alarm probability of the event-rate line over all candidate rates.
DEFAULT_PFA = 0.001
#: False-alarm probability of one period's envelope maximum being called an event.
EVENT_PFA = 0.01
#: Deepest kurtogram level the band may come from: fs/16 wide at least (fs/2^(level+1)).
MAX_LEVEL = 3.0
#: The resonance band's lower edge is at least this many times the highest event rate (the
#: band must hold the ringing, not the event rate's own low harmonics).
MIN_BAND_ORDER = 5
#: f_n is searched below this fraction of fs (above it: the recorder's anti-alias filter).
F_MAX = 0.45
#: The decay is read in a band centred on f_n, the kurtogram's band's width or this
#: fraction of fs, whichever is wider.
MIN_DECAY_BAND = 1.0 / 12.0
#: Bounds of the damping fit.
ZETA_MIN, ZETA_MAX = 5e-4, 0.3
#: Butterworth order of the band-pass (applied forward and backward).
FILTER_ORDER = 4
#: Samples per Welch segment of the background spectrum (its transform length).
WELCH_SEGMENT = 1024
#: Shortest stretch between events the background spectrum is read from (samples).
MIN_GAP = 64
#: The decay is fitted from the peak down to this fraction of the peak's amplitude.
DECAY_FLOOR = 0.1
#: False-alarm probability of a further mode: over the resolution cells searched (Bonferroni),
#: a peak of the power the events add whose prominence over its standard error (across the
#: events) exceeds the normal quantile is a mode, not the spread of noise.
MODE_PFA = 0.001
#: A further mode must add at least this fraction of the strongest mode's power (-20 dB: the
#: decay fit's own floor, ``DECAY_FLOOR`` squared); weaker ones change no feature read.
MODE_FLOOR = DECAY_FLOOR ** 2
#: Most modes identified from one record (the strongest first).
MAX_MODES = 4


class NoImpulsesError(ValueError):
    """The record holds no periodic impulses to identify a path from (message: one line)."""


@dataclass(frozen=True)
class TransferPath:
    """The structural response the fault impulses excite, identified from one record.

    Attributes
    ----------
    fs_hz : float
        Sampling rate of the record, Hz.
    band_hz : tuple of float
        Resonance band (kurtogram's best band), Hz.
    band_kurtosis : float
        Kurtosis of the band (the kurtogram's).
    event_name : str
        Candidate rate the events repeat at (``bpfo``, ``bpfi``, ...).
    event_hz : float
        The event rate measured on the envelope spectrum, Hz.
    line_db : float
        Height of that line above its floor, dB (threshold in ``threshold_db``).
    threshold_db : float
        Detection threshold of the line, dB.
    n_events, n_periods : int
        Events detected, periods searched.
    f_n_hz : float
        Natural frequency of the excited mode, Hz.
    zeta : float
        Damping ratio of the mode.
    zeta_range : tuple of float
        ``zeta`` fitted on the first and second halves of the events (a spread, not a bound).
    amplitude : float
        Initial amplitude of the mode's response to one event, record units (rms over events).
    background_rms : float
        rms of the background, record units.
    background_freq_hz, background_psd : list of float
        Background power spectral density (record units^2/Hz).
    background_source : str
        ``record`` (events gated out) or the healthy record's name.
    flags : list of str
        Warnings to read with the numbers (resonance at the band's edge, damping at the fit's
        bound, halves disagreeing).
    modes : list of dict
        Every mode identified, the strongest (the one above) first: ``f_n_hz``, ``zeta``,
        ``zeta_range``, ``amplitude`` (as above, in the mode's own band), ``band_hz``,
        ``n_events``, ``excess_db`` (power the events add at ``f_n_hz``, re the first mode)
        and ``prominence_z`` (the peak's prominence over its standard error; None for the
        first). Empty in a path written before modes were identified: the one mode above.
    modes_rejected : list of dict
        Significant peaks that gave no mode (``f_n_hz``, ``reason``: damping at the fit's
        bound, no power above the background at the events' peak).
    """

    fs_hz: float
    band_hz: tuple
    band_kurtosis: float
    event_name: str
    event_hz: float
    line_db: float
    threshold_db: float
    n_events: int
    n_periods: int
    f_n_hz: float
    zeta: float
    zeta_range: tuple
    amplitude: float
    background_rms: float
    background_freq_hz: list = field(repr=False)
    background_psd: list = field(repr=False)
    background_source: str = "record"
    flags: list = field(default_factory=list)
    modes: list = field(default_factory=list)
    modes_rejected: list = field(default_factory=list)

    def mode(self, impulse_area: float = UNIT_IMPULSE_AREA) -> Mode:
        """The mode whose response to an impulse of area ``impulse_area`` starts at
        ``amplitude`` (:class:`bearing_envelope.physics.transfer.Mode`, impulse-invariant
        convention ``h(0+) = 2 zeta omega_n gain``).

        Parameters
        ----------
        impulse_area : float
            Area of one excitation impulse (e.g. N s), > 0.

        Returns
        -------
        Mode
        """
        if not (math.isfinite(impulse_area) and impulse_area > 0):
            raise ValueError(f"impulse_area: got {impulse_area!r}; allowed: > 0")
        wn = 2.0 * math.pi * self.f_n_hz
        return Mode(self.f_n_hz, self.zeta, self.amplitude / (impulse_area * 2 * self.zeta * wn))

    def structure(self, impulse_area: float = UNIT_IMPULSE_AREA) -> list:
        """Every identified mode, each with its gain for an impulse of area ``impulse_area``
        (as :meth:`mode`; the first is :meth:`mode`'s).

        Parameters
        ----------
        impulse_area : float
            Area of one excitation impulse (e.g. N s), > 0.

        Returns
        -------
        list of Mode
        """
        first = self.mode(impulse_area)
        out = [first]
        for m in self.modes[1:]:
            wn = 2.0 * math.pi * m["f_n_hz"]
            out.append(Mode(m["f_n_hz"], m["zeta"],
                            m["amplitude"] / (impulse_area * 2 * m["zeta"] * wn)))
        return out

    def to_dict(self) -> dict:
        """The path as plain types (JSON).

        Returns
        -------
        dict
        """
        d = asdict(self)
        d["band_hz"], d["zeta_range"] = list(self.band_hz), list(self.zeta_range)
        return d

    def to_json(self) -> str:
        """JSON text of :meth:`to_dict`.

        Returns
        -------
        str
        """
        return json.dumps(self.to_dict(), indent=1)

    @classmethod
    def from_dict(cls, d: dict) -> TransferPath:
        """Inverse of :meth:`to_dict`.

        Parameters
        ----------
        d : dict
            As written by :meth:`to_dict`.

        Returns
        -------
        TransferPath
        """
        d = dict(d)
        d["band_hz"], d["zeta_range"] = tuple(d["band_hz"]), tuple(d["zeta_range"])
        return cls(**d)


def identify_path(x, fs: float, event_rates: dict, *, background=None,
                  background_name: str = "healthy record") -> TransferPath:
    """Identify the transfer path the fault impulses of a record excite.

    Parameters
    ----------
    x : array_like, 1-D
        The measured record (any unit: the results carry it).
    fs : float
        Sampling rate, Hz.
    event_rates : dict
        Candidate event rates, name -> Hz (e.g. the bearing's BPFO, BPFI, BSF, 2 x BSF at the
        record's shaft rate); the one whose envelope line stands highest is used.
    background : array_like, optional
        A healthy record of the same machine at ``fs``: its spectrum is the background. Default:
        the record with its events gated out.
    background_name : str
        Name recorded for that healthy record.

    Returns
    -------
    TransferPath

    Raises
    ------
    ValueError
        Bad input, or a record too short for :data:`MIN_EVENTS` periods (one line).
    NoImpulsesError
        No event-rate line above the threshold, or fewer than :data:`MIN_EVENTS` events.
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=16)
    x = x - x.mean()
    rates = _check_rates(event_rates, fs)
    slowest = min(rates.values())
    if x.size < MIN_EVENTS * fs / slowest or max_kurtogram_level(x.size) < 1:
        raise ValueError(f"x: {x.size} samples ({x.size / fs:.3g} s) are too short; allowed: "
                         f">= {MIN_EVENTS} periods of {slowest:g} Hz "
                         f"({MIN_EVENTS / slowest:.3g} s)")
    kg = fast_kurtogram(x, fs, min(8, max_kurtogram_level(x.size)), max_level=MAX_LEVEL)
    f_low = MIN_BAND_ORDER * max(rates.values())
    band0, kurt = _resonance_band(kg, f_low, fs)
    env0 = np.abs(sps.hilbert(bandpass(x, fs, band0, order=FILTER_ORDER)))
    name, hz, line_db, thr = _event_line(env0, fs, rates)
    peaks0, _ = _events(env0, fs, hz, band0)
    if peaks0.size < MIN_EVENTS:
        raise NoImpulsesError(f"x: {peaks0.size} events above the background in "
                              f"{int(x.size * hz / fs)} periods of {name} {hz:.4g} Hz; "
                              f"allowed: >= {MIN_EVENTS}")
    n_post = max(int(0.45 * fs / hz), 4)
    f_n, extra = _mode_peaks(x, peaks0, fs, (f_low, F_MAX * fs), n_post, fs / hz)
    half = max(band0[1] - band0[0], MIN_DECAY_BAND * fs) / 2
    centres, res = [f_n] + [e[0] for e in extra], fs / _segment_length(n_post)
    band = _mode_band(f_n, centres, half, res, f_low, fs)
    env = np.abs(sps.hilbert(bandpass(x, fs, band, order=FILTER_ORDER)))
    peaks, n_periods = _events(env, fs, hz, band)
    if peaks.size < MIN_EVENTS:
        raise NoImpulsesError(f"x: {peaks.size} events above the background in {n_periods} "
                              f"periods of {name} {hz:.4g} Hz around f_n {f_n:.0f} Hz; "
                              f"allowed: >= {MIN_EVENTS}")
    zeta, amp, zr = _fit_mode(env, peaks, fs, band, n_post, hz, f_n)
    modes = [{"f_n_hz": f_n, "zeta": zeta, "zeta_range": list(zr), "amplitude": amp,
              "band_hz": list(band), "n_events": int(peaks.size), "excess_db": 0.0,
              "prominence_z": None}]
    rejected = []
    for f_k, ex_db, z in extra:
        m = _extra_mode(x, fs, hz, f_k, _mode_band(f_k, centres, half, res, f_low, fs), n_post,
                        peaks)
        if isinstance(m, str):
            rejected.append({"f_n_hz": f_k, "reason": m})
        else:
            modes.append({**m, "excess_db": ex_db, "prominence_z": z})
    gate = _gate_samples(amp, zeta, f_n, fs, env, n_post, hz)
    freq, psd, src = _background(x, fs, peaks, gate, background, background_name)
    return TransferPath(fs, tuple(band), kurt, name, hz, line_db, thr,
                        int(peaks.size), int(n_periods), f_n, zeta, zr, amp,
                        float(math.sqrt(np.trapezoid(psd, freq))), list(map(float, freq)),
                        list(map(float, psd)), src, _flags(band, f_n, zeta, zr, gate, fs / hz),
                        modes, rejected)


def _mode_band(f_n, centres, half, resolution, f_low, fs) -> tuple[float, float]:
    """The band a mode's decay is read in: centred on ``f_n``, ``half`` wide each side, but
    no closer than half-way to the next identified mode (nor narrower than one resolution
    cell of the events' spectrum each side)."""
    gaps = [abs(f_n - c) for c in centres if c != f_n]
    if gaps:
        half = min(half, max(0.5 * min(gaps), resolution))
    return (max(f_n - half, f_low), min(f_n + half, 0.49 * fs))


def _extra_mode(x, fs, hz, f_n, band, n_post, events):
    """A further mode fitted in its own band: its parameters, or why it gave none (str).

    The same impulses ring every mode, so the events are the first mode's, each moved to the
    envelope's maximum in this band within a quarter of ``n_post`` of it (a weak mode's own
    maxima rarely clear the background's bound one by one; their average does)."""
    env = np.abs(sps.hilbert(bandpass(x, fs, band, order=FILTER_ORDER)))
    w = max(n_post // 4, 1)
    events = events[(events >= w) & (events + w < env.size)]
    idx = events[:, None] + np.arange(-w, w + 1)[None, :]
    peaks = events - w + np.argmax(env[idx], axis=1)
    try:
        zeta, amp, zr = _fit_mode(env, peaks, fs, band, n_post, hz, f_n)
    except NoImpulsesError as exc:
        return str(exc).removeprefix("x: ")
    if zeta > 0.9 * ZETA_MAX or zeta < 1.1 * ZETA_MIN:
        return f"zeta {zeta:.3g} at the fit's bound [{ZETA_MIN:g}, {ZETA_MAX:g}]"
    return {"f_n_hz": f_n, "zeta": zeta, "zeta_range": list(zr), "amplitude": amp,
            "band_hz": list(band), "n_events": int(peaks.size)}

def _rayleigh_scale(env) -> float:
    """Rayleigh scale of the background's envelope from its 10th percentile (the events
    raise the upper quantiles, hardly the lowest): ``a_q = sigma sqrt(-2 ln(1 - q))``."""
    return float(np.quantile(env, 0.1)) / math.sqrt(-2 * math.log(0.9))


def _gate_samples(amp, zeta, f_n, fs, env, n_post, hz) -> int:
    """Samples after an event's peak until its ringing falls below 0.3 x the band's
    background level (capped at 0.9 of a period)."""
    sigma = _rayleigh_scale(env)
    ratio = max(amp / (0.3 * sigma), 1.0)
    n = int(math.ceil(math.log(ratio) / (zeta * 2 * math.pi * f_n) * fs))
    return int(min(max(n, n_post // 2), 0.9 * fs / hz))


def _resonance_band(kg, f_low: float, fs: float) -> tuple[tuple[float, float], float]:
    """The kurtogram's best cell at level <= MAX_LEVEL whose lower edge is >= ``f_low``."""
    best = None
    for r, level in enumerate(kg.levels):
        if level > MAX_LEVEL:
            continue
        bw = kg.bandwidths[r]
        for i, k in enumerate(kg.rows[r]):
            if i * bw >= f_low and (best is None or k > best[0]):
                best = (float(k), i * bw, (i + 1) * bw)
    if best is None:
        raise ValueError(f"fs: {fs:g} Hz leaves no band above {f_low:g} Hz "
                         f"({MIN_BAND_ORDER} x the highest event rate); allowed: a higher fs")
    return (best[1], min(best[2], 0.49 * fs)), best[0]


def _flags(band, f_n, zeta, zeta_range, gate, period) -> list:
    """Warnings a user must read with the numbers (one line each)."""
    out = []
    if gate >= 0.9 * period - 1:
        out.append("the events ring for most of a period: the background (events gated out) "
                   "holds part of their ringing")
    if min(f_n - band[0], band[1] - f_n) < 0.02 * (band[1] - band[0]):
        out.append(f"f_n {f_n:.0f} Hz at the band's edge: the resonance may lie outside "
                   f"{band[0]:.0f}-{band[1]:.0f} Hz")
    if zeta > 0.9 * ZETA_MAX or zeta < 1.1 * ZETA_MIN:
        out.append(f"zeta {zeta:.3g} at the fit's bound [{ZETA_MIN:g}, {ZETA_MAX:g}]: "
                   "damping not resolved")
    if zeta_range[1] > 1.5 * zeta_range[0]:
        out.append(f"zeta differs by more than 1.5x between the halves of the record "
                   f"({zeta_range[0]:.3g}-{zeta_range[1]:.3g})")
    return out


def _check_rates(event_rates, fs: float) -> dict:
    if not isinstance(event_rates, dict) or not event_rates:
        raise ValueError(f"event_rates: got {event_rates!r}; allowed: a mapping name -> Hz")
    out = {}
    for k, v in event_rates.items():
        v = float(v)
        if not (math.isfinite(v) and 0 < v < fs / 4):
            raise ValueError(f"event_rates[{k!r}]: got {v!r} Hz; allowed: 0 < Hz < fs/4 "
                             f"= {fs / 4:g}")
        out[str(k)] = v
    return out


def _event_line(env, fs, rates) -> tuple[str, float, float, float]:
    """The candidate rate with the highest envelope line over its floor, if above threshold."""
    n = env.size
    spec = np.abs(np.fft.rfft((env - env.mean()) * np.hanning(n)))
    df = fs / n
    best = None
    for name, hz in rates.items():
        lo, hi = int(hz * 0.99 / df), int(math.ceil(hz * 1.01 / df)) + 1
        k = lo + int(np.argmax(spec[lo:hi]))
        fl = np.r_[spec[int(0.5 * hz / df):lo - 2], spec[hi + 2:int(1.5 * hz / df)]]
        s_db = 20 * math.log10(spec[k] / np.median(fl))
        thr = threshold_db(DEFAULT_PFA / len(rates), n_bins=hi - lo, n_background=fl.size)
        if best is None or s_db - thr > best[2] - best[3]:
            best = (name, k * df, s_db, thr)
    if best[2] <= best[3]:
        raise NoImpulsesError(f"x: no envelope line at {', '.join(rates)} in band: best "
                              f"{best[0]} {best[2]:.1f} dB over floor, threshold "
                              f"{best[3]:.1f} dB; nothing identified")
    return best


def _events(env, fs, hz, band) -> tuple[np.ndarray, int]:
    """Per period of ``hz``: the envelope's maximum, kept if above the Rayleigh bound."""
    period = fs / hz
    n_periods = int(env.size / period) - 1
    starts = (np.arange(n_periods) * period).astype(int)
    width = int(period)
    blocks = np.stack([env[s:s + width] for s in starts])
    arg = blocks.argmax(axis=1)
    top = blocks[np.arange(n_periods), arg]
    sigma = _rayleigh_scale(env)
    n_ind = max(width * (band[1] - band[0]) / fs, 1.0)  # independent envelope samples per period
    bound = sigma * math.sqrt(2 * math.log(n_ind / EVENT_PFA))
    keep = top > bound
    peaks = starts[keep] + arg[keep]
    edge = int(0.5 * period)
    peaks = peaks[(peaks > edge) & (peaks < env.size - edge)]
    return peaks, n_periods


def _aligned_power(sig, peaks, pre: int, post: int) -> np.ndarray:
    idx = peaks[:, None] + np.arange(-pre, post)[None, :]
    return np.mean(sig[idx] ** 2, axis=0)


def _model_envelope(zeta, f_n, fs, band, n_post, pad) -> np.ndarray:
    """Squared envelope of a unit damped sine through the band-pass, from its peak on."""
    t = np.arange(pad + n_post + pad) / fs
    h = np.zeros_like(t)
    wn = 2 * math.pi * f_n
    wd = wn * math.sqrt(1 - zeta * zeta)
    h[pad:] = np.exp(-zeta * wn * t[:-pad]) * np.cos(wd * t[:-pad])
    e = np.abs(sps.hilbert(bandpass(h, fs, band, order=FILTER_ORDER))) ** 2
    k = int(np.argmax(e))
    return e[k:k + n_post]


def _fit_zeta(s2, f_n, fs, band, n_post, pad):
    """zeta and amplitude fitting the decay of the averaged squared envelope ``s2``."""
    top = s2[0]
    if not top > 0:
        raise NoImpulsesError(f"x: the events add no power above the background at their "
                              f"peak around f_n {f_n:.0f} Hz; nothing to fit a decay to")
    m = int(np.argmax(s2 < top * DECAY_FLOOR ** 2)) or s2.size
    m = max(m, 3)
    y = np.log(np.maximum(s2[:m], top * 1e-6))

    def cost(log_z):
        e = _model_envelope(math.exp(log_z), f_n, fs, band, n_post, pad)[:m]
        r = y - np.log(np.maximum(e, 1e-300))
        return float(np.sum((r - r.mean()) ** 2))

    res = optimize.minimize_scalar(cost, bounds=(math.log(ZETA_MIN), math.log(ZETA_MAX)), method="bounded",
                                   options={"xatol": 1e-3})
    z = math.exp(res.x)
    e = _model_envelope(z, f_n, fs, band, n_post, pad)[:m]
    amp = math.exp(0.5 * float(np.mean(y - np.log(np.maximum(e, 1e-300)))))
    return z, amp


def _fit_mode(env, peaks, fs, band, n_post, hz, f_n):
    """zeta and amplitude from the events' averaged decay, and zeta on each half."""
    pre = max(int(0.4 * fs / hz), 4)
    p = _aligned_power(env, peaks, pre, n_post)
    bg = float(np.median(p[: pre // 2]))
    pad = 4 * n_post
    z, amp = _fit_zeta(np.maximum(p[pre:] - bg, 0.0), f_n, fs, band, n_post, pad)
    zs = []
    for h in (peaks[: peaks.size // 2], peaks[peaks.size // 2:]):
        ph = _aligned_power(env, h, pre, n_post)
        zs.append(_fit_zeta(np.maximum(ph[pre:] - bg, 0.0), f_n, fs, band, n_post, pad)[0])
    return z, amp, (min(zs), max(zs))


def _segments_spectra(x, starts, n, nfft, w) -> np.ndarray:
    seg = np.stack([x[s:s + n] for s in starts if 0 <= s and s + n <= x.size]) * w
    return np.abs(np.fft.rfft(seg, nfft)) ** 2


def _segment_length(n_post: int) -> int:
    """Samples per event segment of the events' spectrum (a power of two >= 32)."""
    return 1 << int(math.ceil(math.log2(max(n_post, 32))))


def _mode_peaks(x, peaks, fs, f_range, n_post, period):
    """The power the events add: the averaged spectrum of the segments starting at the events
    minus that of the same segments half a period later. Its maximum within ``f_range`` is
    the first mode; every further peak in the range is a mode when its prominence over the
    standard error of that prominence (the spread across the events, at the peak and at its
    saddle) exceeds the normal quantile of :data:`MODE_PFA` over the range's resolution
    cells, and its power is >= :data:`MODE_FLOOR` x the first's.

    Returns
    -------
    (float, list of (f_n_hz, excess_db, prominence_z))
        The first mode's f_n, and the further modes (strongest first, at most
        :data:`MAX_MODES` - 1).
    """
    n = _segment_length(n_post)
    nfft = 16 * n
    w = np.hanning(2 * n)[n:]  # half window: the event's start carries the most
    start = peaks - n // 8
    a = _segments_spectra(x, start, n, nfft, w)
    b = _segments_spectra(x, start + int(period / 2), n, nfft, w)
    excess = a.mean(axis=0) - b.mean(axis=0)
    se = np.sqrt(a.var(axis=0, ddof=1) / len(a) + b.var(axis=0, ddof=1) / len(b))
    f = np.fft.rfftfreq(nfft, 1 / fs)
    inb = (f >= f_range[0]) & (f <= f_range[1])
    i0 = int(np.flatnonzero(inb)[np.argmax(excess[inb])])
    pk, props = sps.find_peaks(excess, prominence=0.0)
    lb, rb = props["left_bases"], props["right_bases"]
    saddle = np.where(excess[lb] > excess[rb], lb, rb)
    z = props["prominences"] / np.sqrt(se[pk] ** 2 + se[saddle] ** 2)
    cells = max((f_range[1] - f_range[0]) / (fs / n), 1.0)  # independent resolution cells
    z_crit = stats.norm.isf(MODE_PFA / cells)
    ok = (inb[pk] & (np.abs(f[pk] - f[i0]) > fs / n) & (z > z_crit)
          & (excess[pk] >= MODE_FLOOR * excess[i0]))
    extra = sorted(((float(f[k]), float(10 * math.log10(excess[k] / excess[i0])), float(zk))
                    for k, zk in zip(pk[ok], z[ok])), key=lambda e: -e[1])
    return float(f[i0]), extra[:MAX_MODES - 1]

def _background(x, fs, peaks, gate, background, name):
    """Welch PSD of the healthy record, or of the record with its events gated out."""
    if background is not None:
        b = check_signal(background, "background", min_length=WELCH_SEGMENT)
        f, p = sps.welch(b - b.mean(), fs, nperseg=WELCH_SEGMENT)
        return f, p, name
    keep = np.ones(x.size, bool)
    for pk in peaks:
        keep[max(pk - gate // 8 - 2, 0):pk + gate] = False
    f, p = _gap_psd(x, fs, keep)
    if f is None:
        return (*sps.welch(x, fs, nperseg=WELCH_SEGMENT),
                f"record, events included (no stretch of {MIN_GAP} samples between them)")
    return f, p, "record"


def _gap_psd(x, fs, keep) -> tuple[np.ndarray | None, np.ndarray | None]:
    """PSD of the record between its events: the mean of the Hann-windowed periodograms
    (``nfft`` = :data:`WELCH_SEGMENT`) of the stretches ``keep`` marks, each cut into pieces of
    at most ``WELCH_SEGMENT`` and at least :data:`MIN_GAP` samples, weighted by length. Each
    piece is windowed on its own: zeroing the events out of the record instead (a rectangular
    gate) would spread the resonance's power over the whole band through the gate's edges
    (on the 48 kHz CWRU records, 30 dB over the record's own floor at 12-18 kHz). ``(None,
    None)`` when no stretch is that long (hardly reachable: events are only detected where the
    envelope falls back between them, and the gates end where it has)."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], keep.astype(np.int8), [0]))))
    pieces = [(a, min(a + WELCH_SEGMENT, b)) for start, b in zip(edges[::2], edges[1::2])
              for a in range(start, b, WELCH_SEGMENT) if min(a + WELCH_SEGMENT, b) - a >= MIN_GAP]
    if not pieces:
        return None, None
    acc, total = 0.0, 0
    for a, b in pieces:
        f, p = sps.periodogram(x[a:b], fs, window="hann", nfft=WELCH_SEGMENT)
        acc, total = acc + p * (b - a), total + (b - a)
    return f, acc / total


def background_noise(path: TransferPath, n: int, *, seed: int = 0) -> np.ndarray:
    """Gaussian noise of ``n`` samples with the path's background spectrum.

    Parameters
    ----------
    path : TransferPath
    n : int
        Samples, > 1.
    seed : int
        Seed of the numpy generator.

    Returns
    -------
    ndarray
        Noise whose Welch PSD follows ``path.background_psd`` (record units).
    """
    if int(n) < 2:
        raise ValueError(f"n: got {n!r}; allowed: >= 2 samples")
    rng = np.random.default_rng(seed)
    spec = np.fft.rfft(rng.standard_normal(int(n)))
    f = np.fft.rfftfreq(int(n), 1 / path.fs_hz)
    psd = np.interp(f, path.background_freq_hz, path.background_psd)
    y = np.fft.irfft(spec * np.sqrt(psd * path.fs_hz / 2), int(n))
    return y
