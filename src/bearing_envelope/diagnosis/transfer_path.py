"""The transfer path identified from a measured record: what the fault impulses excite.

A fault impulse (a ball meeting a pit) rings the structure between the bearing and the
accelerometer; the record holds that ringing, repeated at the fault's event rate, on top of the
machine's background. :func:`identify_path` recovers, from the record alone:

1. **The resonance band and the event rate**: the fast kurtogram's best cell (Antoni 2007) at a
   level wide enough to show the decay (:data:`MAX_LEVEL`), when its envelope spectrum holds a
   line at one of the candidate event rates (the bearing's BPFO, BPFI, BSF, 2 x BSF, or one
   given) over the exact detection threshold of
   :func:`bearing_envelope.diagnosis.detection.threshold_db` at :data:`DEFAULT_PFA`; else the
   cell whose line stands highest over that threshold, the probability then shared over the
   cells searched too (kurtosis alone picked a noise band for a lightly damped mode); no line
   over it: nothing is identified (:class:`NoImpulsesError`).
2. **The events**: every period's, detected one by one or not, on the track of that line's
   phase (:func:`_event_track`). The envelope maxima above the Rayleigh bound of the band's
   background (:data:`EVENT_PFA` per period) are counted (``n_events``), not selected:
   averaging over them alone biased zeta and the amplitude up at partial detection.
3. **Damping and natural frequency**: the squared envelope averaged over every period's event
   must hold the events' power at their peak (significant at :data:`DEFAULT_PFA`), and decays
   as the mode's envelope seen through the same band-pass; ``zeta`` is fitted to that decay
   past the peak with the filter and the earlier events' tails in the model (:func:`_fit_zeta`).
   ``f_n`` is the peak of the events' averaged spectrum over the background's, in the band.
   **More than one mode**: every further peak of that spectrum (the power the events add) that
   stands above its saddle by more than the false-alarm bound :data:`MODE_PFA` (the prominence
   over its standard error across the events) and within :data:`MODE_FLOOR` of the strongest
   is a mode of its own, fitted like the first in a band centred on it (narrowed to half the
   distance to the next mode); a record whose second peak is not significant keeps one mode.
4. **Amplitude**: the initial amplitude ``a`` of the mode's response to one event (record
   units, rms over every period's event), from the events' energy (the averaged squared
   envelope summed from the event's rise to the end of the decay fit, over the model's: it
   does not depend on where between two samples, or how scattered, the events start; read
   off the decay, it did, by 8 % a sample at zeta 0.05 and 3 kHz), the model's ringing
   averaged over onsets spread over a sample (:data:`ONSETS`). With an excitation impulse of
   area ``A`` (N s, say) the mode's gain at resonance is ``a / (A 2 zeta omega_n)``
   (:meth:`TransferPath.mode`). zeta and the gain whose standard error over
   :data:`SUBSETS` subsets of the events exceeds half of :data:`IDENT_TOL` are flagged and
   listed in ``not_identified``; so is the gain whenever zeta is (the energy fixes
   ``gain^2 zeta``). So are they when each event still rings at ``r`` of its amplitude as
   the next arrives and the events' phases at the mode are coherent
   (:func:`_coherent_overlap`): the model adds the earlier events' tails in power, and in
   phase their sum moves the amplitude by up to ``sqrt((1 + r) / (1 - r)) - 1`` times the coherence
   (:func:`identification_flags`).
5. **Background**: the power spectral density of the record between its events (every
   period's gated), when that leaves :data:`MIN_BACKGROUND` samples; else the record's less
   the events' modelled spectrum, and where the events make most of that, the quiet end of
   every period (its last samples before the next event) less the earlier events' ringing
   modelled there; where that too is mostly ringing, interpolated across the modes (flagged,
   ``not_identified``); or of a healthy record of the same machine when one is given.

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

from .path_constants import (UNIT_IMPULSE_AREA, MIN_EVENTS, DEFAULT_PFA, EVENT_PFA, MAX_LEVEL,
                             MIN_BAND_ORDER, F_MAX, MIN_DECAY_BAND, ZETA_MIN, ZETA_MAX,
                             FILTER_ORDER, DECAY_FLOOR, DECAY_FROM, RISE_MARGIN, ONSETS,
                             MODE_PFA, MODE_FLOOR, MAX_MODES, TRACK_SNR_DB, TRACK_PERIODS,
                             SUBSETS, IDENT_TOL, MIN_BACKGROUND, MAX_MODELLED, PRE_MARGIN,
                             MIN_PRE, MIN_GAP, MODE_SPAN, WELCH_SEGMENT)
from .path_background import _background, _segments_spectra

__all__ = ["TransferPath", "NoImpulsesError", "identify_path", "background_noise", "identification_flags",
           "MIN_EVENTS", "DEFAULT_PFA", "EVENT_PFA", "MAX_LEVEL", "MODE_PFA", "MODE_FLOOR",
           "MAX_MODES", "IDENT_TOL", "MIN_BACKGROUND", "MAX_MODELLED", "PRE_MARGIN", "MIN_PRE",
           "MIN_GAP", "MODE_SPAN", "WELCH_SEGMENT"]


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
        Events detected one by one (above the background's bound), periods searched; every
        period's event is averaged, detected or not.
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
        ``record`` (events gated out), the healthy record's name, or where each part of the
        spectrum comes from (the record less the events' modelled spectrum; the record before
        each event; interpolated where neither is measured).
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
    not_identified : list of str
        Quantities of the first mode the record does not identify within :data:`IDENT_TOL`
        (``zeta``, ``gain``: twice their standard error over :data:`SUBSETS` subsets of the
        events exceeds it, or with what ringing in phase from event to event may move,
        or zeta sits at the fit's bound; the gain also whenever zeta is not identified;
        ``background``: the events make most of the record's power at the resonance);
        each also has its line in ``flags``.
        Empty in a path written before this was reported.
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
    not_identified: list = field(default_factory=list)

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
            ``f_n_hz`` (Hz), ``zeta`` and the gain ``amplitude / (impulse_area 2 zeta
            omega_n)`` (record units per unit of excitation at resonance).

        Raises
        ------
        ValueError
            ``impulse_area`` not a finite number > 0 (one line naming it).
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
            One per entry of :attr:`modes` (at least :meth:`mode`'s), strongest first, each
            with its gain for ``impulse_area``.
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
            Every field by name; tuples (``band_hz``, ``zeta_range``) as lists.
        """
        d = asdict(self)
        d["band_hz"], d["zeta_range"] = list(self.band_hz), list(self.zeta_range)
        return d

    def to_json(self) -> str:
        """JSON text of :meth:`to_dict`.

        Returns
        -------
        str
            The JSON text (one-space indent), read back by :meth:`from_dict` of ``json.loads``.
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
            The path, ``band_hz`` and ``zeta_range`` as tuples again.
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
        The resonance band, the mode (natural frequency in Hz, damping ratio, amplitude in the
        record's units), the other modes found, the background's spectrum and the flags and
        quantities not identified to read with them.

    Raises
    ------
    ValueError
        Bad input, or a record too short for :data:`MIN_EVENTS` periods (one line).
    NoImpulsesError
        No event-rate line above the threshold, or events that add no significant power at
        their peak averaged over every period.
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
    band0, kurt, env0, (name, hz, line_db, thr) = _resonance_band(x, kg, f_low, fs, rates)
    n_post, pre = max(int(0.45 * fs / hz), 4), max(int(0.4 * fs / hz), 4)
    track = _event_track(env0, fs, hz, line_db, pre, n_post)
    f_n, extra = _mode_peaks(x, track, fs, (f_low, F_MAX * fs), n_post, fs / hz)
    half = max(band0[1] - band0[0], MIN_DECAY_BAND * fs) / 2
    centres, res = [f_n] + [e[0] for e in extra], fs / _segment_length(n_post)
    band = _mode_band(f_n, centres, half, res, f_low, fs)
    analytic = sps.hilbert(bandpass(x, fs, band, order=FILTER_ORDER))
    env = np.abs(analytic)
    peaks, n_periods = _events(env, fs, hz, band)  # detected one by one: reported only
    every = _align(env, track, max(n_post // 4, 1), pre, n_post)
    zeta, amp, zr, se = _fit_mode(env, every, fs, band, n_post, hz, f_n)
    overlap = _coherent_overlap(analytic, every, zeta, f_n, 1.0 / hz)
    modes = [{"f_n_hz": f_n, "zeta": zeta, "zeta_range": list(zr), "amplitude": amp,
              "band_hz": list(band), "n_events": int(peaks.size), "excess_db": 0.0,
              "prominence_z": None}]
    rejected = []
    for f_k, ex_db, z in extra:
        m = _extra_mode(x, fs, hz, f_k, _mode_band(f_k, centres, half, res, f_low, fs), n_post,
                        track)
        if isinstance(m, str):
            rejected.append({"f_n_hz": f_k, "reason": m})
        else:
            modes.append({**m, "excess_db": ex_db, "prominence_z": z})
    gate = _gate_samples(amp, zeta, f_n, fs, env, n_post, hz)
    freq, psd, src, bg_flag = _background(x, fs, every, gate, background, background_name,
                                          (hz, modes))
    flags, unknown = identification_flags(band, f_n, zeta, zr, se, gate, fs / hz, bg_flag,
                                          coherent_tail=overlap)
    return TransferPath(fs, tuple(band), kurt, name, hz, line_db, thr,
                        int(peaks.size), int(n_periods), f_n, zeta, zr, amp,
                        float(math.sqrt(np.trapezoid(psd, freq))), list(map(float, freq)),
                        list(map(float, psd)), src, flags, modes, rejected, unknown)


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

    The same impulses ring every mode, so the events are the first mode's track (every
    period), moved together to where their average in this band peaks within a quarter of
    ``n_post`` (:func:`_align`; a weak mode's own maxima rarely clear the background's bound
    one by one, and moving each event to its own maximum would pick the noise's)."""
    env = np.abs(sps.hilbert(bandpass(x, fs, band, order=FILTER_ORDER)))
    peaks = _align(env, events, max(n_post // 4, 1), max(int(0.4 * fs / hz), 4), n_post)
    try:
        zeta, amp, zr, _ = _fit_mode(env, peaks, fs, band, n_post, hz, f_n)
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


def _resonance_band(x, kg, f_low: float, fs: float, rates: dict):
    """The kurtogram's best cell at level <= MAX_LEVEL whose lower edge is >= ``f_low``, when
    its envelope spectrum holds an event-rate line over the threshold (false-alarm
    probability :data:`DEFAULT_PFA` over the rates); else, of all those cells, the one whose
    best line stands highest over its threshold, the probability then shared over the cells
    searched too (Bonferroni). Kurtosis alone picks a noise band when a lightly damped mode's
    events hardly raise it (zeta 0.015 at noise sigma 0.5: 4-6 kHz, kurtosis 0.19, where
    2.5-3.5 kHz holds the line 39 dB over its floor).

    Returns
    -------
    (band_hz, kurtosis, envelope, (name, hz, line_db, threshold_db))
        Raises :class:`NoImpulsesError` when no cell's line clears its threshold.
    """
    cells = [(float(k), i * kg.bandwidths[r], (i + 1) * kg.bandwidths[r])
             for r, level in enumerate(kg.levels) if level <= MAX_LEVEL
             for i, k in enumerate(kg.rows[r]) if i * kg.bandwidths[r] >= f_low]
    if not cells:
        raise ValueError(f"fs: {fs:g} Hz leaves no band above {f_low:g} Hz "
                         f"({MIN_BAND_ORDER} x the highest event rate); allowed: a higher fs")
    cells.sort(key=lambda c: -c[0])

    def cell(k, lo, hi, pfa):
        band = (lo, min(hi, 0.49 * fs))
        env = np.abs(sps.hilbert(bandpass(x, fs, band, order=FILTER_ORDER)))
        return band, k, env, _best_line(env, fs, rates, pfa)

    best = cell(*cells[0], DEFAULT_PFA / len(rates))
    if best[3][2] > best[3][3]:
        return best
    best = None
    for c in cells:
        cand = cell(*c, DEFAULT_PFA / (len(cells) * len(rates)))
        if best is None or cand[3][2] - cand[3][3] > best[3][2] - best[3][3]:
            best = cand
    line = best[3]
    if line[2] <= line[3]:
        raise NoImpulsesError(f"x: no envelope line at {', '.join(rates)} in any band: best "
                              f"{line[0]} {line[2]:.1f} dB over floor in {best[0][0]:.0f}-"
                              f"{best[0][1]:.0f} Hz, threshold {line[3]:.1f} dB; nothing "
                              "identified")
    return best


def identification_flags(band, f_n, zeta, zeta_range, se, gate, period, bg_flag, *,
                         coherent_tail=(0.0, 0.0)) -> tuple[list, list]:
    """Warnings a user must read with the numbers (one line each), and the quantities not
    identified (``zeta``, ``gain``, ``background``).

    Parameters
    ----------
    band : (float, float)
        The demodulation band, Hz.
    f_n, zeta : float
        The identified natural frequency (Hz) and damping ratio.
    zeta_range : (float, float)
        Damping identified on the record's two halves.
    se : (float, float)
        Relative standard errors of zeta and the gain over subsets of the events.
    gate : float
        Samples each event is gated over.
    period : float
        Samples per event period.
    bg_flag : str or None
        The background's own flag (None: read between the events).
    coherent_tail : (float, float)
        The earlier events' ringing left at the next event (fraction of its amplitude,
        ``exp(-zeta omega_n T)``) and the coherence of the events' phases at the mode, 0-1
        (:func:`_coherent_overlap`). Their sum, modelled as independent in phase, may move
        the amplitude by ``u = coherence (sqrt((1 + r) / (1 - r)) - 1)``: zeta is not
        identified when ``hypot(2 se_zeta, u)`` exceeds :data:`IDENT_TOL`, the gain when
        ``hypot(2 se_gain, 2 u)`` does (the amplitude's share and zeta's).

    Returns
    -------
    (list of str, list of str)
        The warning lines, and the names of the quantities not identified.
    """
    out, unknown = [], []
    if gate >= 0.9 * period - 1 and bg_flag is None:
        out.append("the events ring for most of a period: the background (events gated out) "
                   "holds part of their ringing")
    if min(f_n - band[0], band[1] - f_n) < 0.02 * (band[1] - band[0]):
        out.append(f"f_n {f_n:.0f} Hz at the band's edge: the resonance may lie outside "
                   f"{band[0]:.0f}-{band[1]:.0f} Hz")
    if zeta > 0.9 * ZETA_MAX or zeta < 1.1 * ZETA_MIN:
        out.append(f"zeta {zeta:.3g} at the fit's bound [{ZETA_MIN:g}, {ZETA_MAX:g}]: "
                   "damping not resolved")
        unknown += ["zeta", "gain"]
    if zeta_range[1] > 1.5 * zeta_range[0]:
        out.append(f"zeta differs by more than 1.5x between the halves of the record "
                   f"({zeta_range[0]:.3g}-{zeta_range[1]:.3g})")
    r, coherence = coherent_tail
    u = coherence * (math.sqrt((1 + r) / (1 - r)) - 1) if r < 1 else math.inf
    for name, e, k in (("zeta", se[0], 1), ("gain", se[1], 2)):
        if name in unknown:
            continue
        if not e <= IDENT_TOL / 2:
            out.append(f"{name} not resolved within {IDENT_TOL:.0%}: its standard error "
                       f"over {SUBSETS} subsets of the events is {e:.1%}")
            unknown.append(name)
        elif not math.hypot(2 * e, k * u) <= IDENT_TOL:
            out.append(f"{name} not identified within {IDENT_TOL:.0%}: each event still rings "
                       f"at {r:.0%} of its amplitude when the next arrives, in phase from event "
                       f"to event (coherence {coherence:.2f}), which the model of independent "
                       f"phases leaves out (up to {k * u:.0%})")
            unknown.append(name)
    if "zeta" in unknown and "gain" not in unknown:
        out.append("gain not identified: it rests on zeta (the events' energy fixes "
                   "gain^2 x zeta)")
        unknown.append("gain")
    if bg_flag is not None:
        out.append(bg_flag)
        unknown.append("background")
    return out, unknown


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


def _best_line(env, fs, rates, pfa) -> tuple[str, float, float, float]:
    """The candidate rate whose envelope line (+-1 %) stands highest over its floor (median
    over [0.5, 1.5] x the rate) relative to its threshold at ``pfa``: ``(name, hz, line_db,
    threshold_db)``."""
    n = env.size
    spec = np.abs(np.fft.rfft((env - env.mean()) * np.hanning(n)))
    df = fs / n
    best = None
    for name, hz in rates.items():
        lo, hi = int(hz * 0.99 / df), int(math.ceil(hz * 1.01 / df)) + 1
        k = lo + int(np.argmax(spec[lo:hi]))
        fl = np.r_[spec[int(0.5 * hz / df):lo - 2], spec[hi + 2:int(1.5 * hz / df)]]
        s_db = 20 * math.log10(max(spec[k], 1e-300) / max(np.median(fl), 1e-300))
        thr = threshold_db(pfa, n_bins=hi - lo, n_background=fl.size)
        if best is None or s_db - thr > best[2] - best[3]:
            best = (name, k * df, s_db, thr)
    return best


def _event_track(env, fs: float, hz: float, line_db: float, pre: int,
                 post: int) -> np.ndarray:
    """Every period's event position (samples), detected one by one or not, from the phase of
    the envelope's line at the event rate: the envelope demodulated at the rate (refined to a
    fraction of a bin, :func:`_refine_rate`) and averaged over enough periods for that line to
    stand :data:`TRACK_SNR_DB` over the floor (at least :data:`TRACK_PERIODS`) follows a
    wandering rate; its phase places period ``k``'s event at ``k P - phase P / 2 pi + c``, the
    offset ``c`` being where the envelope's average over all periods on that track peaks. No
    event's own noise moves its position, so averaging at these positions over every period
    carries no selection (averaging over the events whose maximum cleared a bound, those the
    noise raised, biased zeta and the amplitude up at partial detection)."""
    n = env.size
    hz = _refine_rate(env, fs, hz)
    period = fs / hz
    z = (env - env.mean()) * np.exp(-2j * np.pi * hz * np.arange(n) / fs)
    n_per = n / period
    span = n_per * 10 ** ((TRACK_SNR_DB - line_db) / 10)
    half = int(min(max(span, TRACK_PERIODS), n_per) * period / 2)
    cs = np.r_[0, np.cumsum(z)]
    i = np.arange(n)
    lo, hi = np.clip(i - half, 0, n), np.clip(i + half + 1, 0, n)
    phase = np.unwrap(np.angle((cs[hi] - cs[lo]) / (hi - lo)))
    k = np.arange(-1, int(n_per) + 2)
    pos0 = k * period - phase[np.clip((k * period).astype(int), 0, n - 1)] * period / (2 * np.pi)
    whole = pos0[(pos0 >= 0) & (pos0 + period < n - 1)].astype(int)
    fold = np.mean(env[whole[:, None] + np.arange(int(period))[None, :]] ** 2, axis=0)
    pos = np.round(pos0 + int(np.argmax(fold))).astype(int)
    return pos[(pos >= pre) & (pos + post < n)]


def _align(env, pos, w: int, pre: int, post: int) -> np.ndarray:
    """``pos`` moved together by the lag within ``+-w`` at which the envelope's power averaged
    over all of them peaks (one lag for all: a band's envelope may peak a few samples from
    another's)."""
    pos = pos[(pos - w >= pre) & (pos + w + post < env.size)]
    lags = np.arange(-w, w + 1)
    power = np.mean(env[pos[:, None] + lags[None, :]] ** 2, axis=0)
    return pos + int(lags[np.argmax(power)])


def _refine_rate(env, fs: float, hz: float) -> float:
    """The event rate at the maximum of the envelope's transform within one bin of ``hz``."""
    n = env.size
    e = (env - env.mean()) * np.hanning(n)
    t = np.arange(n) / fs

    def neg(f):
        return -abs(np.dot(e, np.exp(-2j * np.pi * f * t)))

    res = optimize.minimize_scalar(neg, bounds=(hz - fs / n, hz + fs / n), method="bounded",
                                   options={"xatol": 1e-3 * fs / n})
    return float(res.x)


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


def _model_power(zeta, f_n, fs, band, pre, post, period) -> tuple[np.ndarray, np.ndarray]:
    """Squared envelope, at lags ``-pre .. post - 1`` from its peak, of a unit damped cosine
    through the band-pass, demodulated like the record, averaged over onsets spread evenly
    over the sample before the first one (:data:`ONSETS`); and the same of the three before
    it, one ``period`` apart each (their powers added: the events' phases at the mode are
    independent), whose tails reach into this event's window.

    A record's events start between its samples, each at its own fraction of a sample: the
    first sample of a ringing that started ``u`` samples earlier holds
    ``exp(-zeta wn u / fs)`` of its amplitude at a phase ``wd u / fs`` on. Modelled as
    starting on a sample, the decay sat ``exp(-zeta wn / 2 fs)`` higher and peaked higher
    relative to its tail than the record's events: the amplitude read 8-10 % and the gain
    6-8 % low at zeta 0.05, 3 kHz, 12 kHz with no noise. The ringing with onset ``u`` is
    ``exp(-s u)(cos(th u) c_k - sin(th u) s_k)`` (``s = zeta wn / fs``, ``th = wd / fs``,
    ``c_k, s_k`` the damped cosine and sine from a sample): the band-pass and its analytic
    signal are linear, so two filtered sequences give every onset's power."""
    per = int(round(period))
    pad = 4 * post + pre
    n = pad + pre + post + 4 * per
    wn = 2 * math.pi * f_n
    s, th = zeta * wn / fs, wn * math.sqrt(1 - zeta * zeta) / fs
    k_ = np.arange(n - pad)
    c, sn = np.zeros(n), np.zeros(n)
    c[pad:], sn[pad:] = np.exp(-s * k_) * np.cos(th * k_), np.exp(-s * k_) * np.sin(th * k_)
    hc, hs = (sps.hilbert(bandpass(y, fs, band, order=FILTER_ORDER)) for y in (c, sn))
    u = (np.arange(ONSETS) + 0.5) / ONSETS
    w = np.exp(-2 * s * u)
    e = (np.mean(w * np.cos(th * u) ** 2) * np.abs(hc) ** 2
         + np.mean(w * np.sin(th * u) ** 2) * np.abs(hs) ** 2
         - np.mean(w * np.sin(2 * th * u)) * np.real(hc * np.conj(hs)))
    k = int(np.argmax(e))
    lags = np.arange(-pre, post)
    tails = sum(e[np.clip(k + lags + j * per, 0, e.size - 1)] for j in (1, 2, 3))
    return e[k - pre:k + post], tails


def _fit_zeta(p, f_n, fs, band, pre, post, period):
    """zeta and amplitude from ``p``, the squared envelope averaged over the events at lags
    ``-pre .. post - 1`` from their peaks.

    zeta: least squares of ``A m(zeta)`` to ``p - B`` over the decay, from
    :data:`DECAY_FROM` samples after the peak down to :data:`DECAY_FLOOR` of its amplitude
    (:func:`_model_power`; ``A``, the amplitude squared, profiled out for each zeta). ``B``,
    the background's power, is the median of ``p`` over lags ``-pre .. -pre/2`` less the
    earlier events' modelled tails there (a lightly damped mode still rings there: taking it
    for background read zeta 6-14 % high at zeta 0.015). The peak itself is left out: the
    events' timing scatter rounds it off. On the power, not its logarithm, whose mean over
    noisy values sits below the logarithm of their mean.

    Amplitude: from the events' energy, ``sum(p - B) / sum(m + tails)`` over the event, from
    its rise (:func:`_rise`) to the end of the decay fit. The decay alone fixes ``A exp(-2
    zeta wn t0)``, not ``A``: read off it, the amplitude rests on where the events start,
    which the record resolves to a sample at best (at zeta 0.05, 3 kHz, 12 kHz one sample is
    8 % of the amplitude; aligning the model's peak on the events' read the gain 6-11 % low,
    or 3-8 % high once the onsets between samples were modelled). The energy of an event is
    the same wherever between two samples it starts, and any timing scatter moves it across
    the window without changing it."""
    bg0 = float(np.median(p[:pre // 2]))
    top = p[pre] - bg0
    end = pre + (int(np.argmax(p[pre:] - bg0 < top * DECAY_FLOOR ** 2)) or post)
    lags = np.arange(pre + DECAY_FROM, max(end, pre + DECAY_FROM + 3))

    def solve(z, bg):
        m, tails = _model_power(z, f_n, fs, band, pre, post, period)
        y, mm = p[lags] - bg, m[lags]
        a2 = float(np.dot(y, mm) / np.dot(mm, mm))
        return a2, float(np.sum((y - a2 * mm) ** 2)), float(np.median(tails[:pre // 2]))

    bg, z = bg0, None
    for _ in range(3):  # the tails' share of the pre-event level follows the fit
        res = optimize.minimize_scalar(lambda lz: solve(math.exp(lz), bg)[1],
                                       bounds=(math.log(ZETA_MIN), math.log(ZETA_MAX)),
                                       method="bounded", options={"xatol": 1e-3})
        z = math.exp(res.x)
        a2, _, tail = solve(z, bg)
        bg = bg0 - max(a2, 0.0) * tail
    m, tails = _model_power(z, f_n, fs, band, pre, post, period)
    w = slice(_rise(m, pre), lags[-1] + 1)
    a2 = float(np.sum(p[w] - bg) / np.sum(m[w] + tails[w]))
    if not a2 > 0:
        raise NoImpulsesError(f"x: the events add no power above the background at their "
                              f"peak around f_n {f_n:.0f} Hz; nothing to fit a decay to")
    return z, math.sqrt(a2)


def _rise(m, pre: int) -> int:
    """Lag index where the modelled event ``m`` (peak at ``pre``) rises: the last before the
    peak below :data:`DECAY_FLOOR` squared of it, less :data:`RISE_MARGIN` samples for the
    events' timing scatter; never before ``pre // 2`` (the lags ``B`` is read from)."""
    low = np.flatnonzero(m[:pre] < DECAY_FLOOR ** 2 * m[pre])
    return max(int(low[-1]) - RISE_MARGIN if low.size else 0, pre // 2)


def _fit_mode(env, peaks, fs, band, n_post, hz, f_n):
    """zeta and amplitude from the events' averaged decay, zeta on each half of the events,
    and the relative standard errors of zeta and of the gain ``amplitude / zeta`` (from the
    spread of the same fit over :data:`SUBSETS` interleaved subsets of the events)."""
    pre = max(int(0.4 * fs / hz), 4)
    _check_events_add_power(env, peaks, pre, f_n)

    def fit(idx):
        return _fit_zeta(_aligned_power(env, idx, pre, n_post), f_n, fs, band, pre, n_post,
                         fs / hz)

    z, amp = fit(peaks)
    sub = []
    for idx in [peaks[: peaks.size // 2], peaks[peaks.size // 2:]] + [
            peaks[j::SUBSETS] for j in range(SUBSETS)]:
        try:
            sub.append(fit(idx))
        except NoImpulsesError:
            sub.append((ZETA_MAX, 0.0))  # a subset with no power above the background
    zs, sub = [e[0] for e in sub[:2]], sub[2:]
    zk, gk = np.array([e[0] for e in sub]), np.array([e[1] / e[0] for e in sub])
    se = (float(np.std(zk, ddof=1) / math.sqrt(SUBSETS) / z),
          float(np.std(gk, ddof=1) / math.sqrt(SUBSETS) / (amp / z)))
    return z, amp, (min(zs), max(zs)), se


def _coherent_overlap(analytic, peaks, zeta: float, f_n: float,
                      period_s: float) -> tuple[float, float]:
    """How much of each event's ringing is left when the next arrives, ``r = exp(-zeta
    omega_n T)`` (``T = period_s``, one period), and how coherent the events' phases at the
    mode are: ``|sum z_k+1 conj(z_k)| / sum |z_k+1| |z_k|`` over consecutive events'
    band-passed analytic signal ``z`` at their peaks (0.6-0.85 on the benchmark's events,
    periodic to 0.3 % of a period; about ``1 / sqrt(n)`` for independent phases, a bearing's
    slip). The model adds the earlier events' tails in power; in phase, their sum scales the
    events' amplitude by ``sqrt(1 - r^2) / (1 + r)`` to ``sqrt(1 - r^2) / (1 - r)`` of that
    (-38 to +46 % in the gain on the benchmark's 190-230 Hz events, r 0.2-0.3)."""
    r = math.exp(-zeta * 2 * math.pi * f_n * period_s)
    z = analytic[peaks]
    den = float(np.sum(np.abs(z[1:]) * np.abs(z[:-1])))
    coherence = float(abs(np.sum(z[1:] * np.conj(z[:-1]))) / den) if den > 0 else 0.0
    return r, coherence


def _check_events_add_power(env, peaks, pre: int, f_n: float) -> None:
    """Refuse (one line) when the events, averaged over every period of the track, add no
    significant power at their peak: the mean over periods of the peak's power less the
    period's own pre-event level must exceed the normal quantile of :data:`DEFAULT_PFA`
    times its standard error (the periods' spread)."""
    d = env[peaks] ** 2 - np.mean(env[peaks[:, None] - np.arange(pre // 2, pre)] ** 2, axis=1)
    z = float(np.mean(d) / (np.std(d, ddof=1) / math.sqrt(d.size)))
    if not z > stats.norm.isf(DEFAULT_PFA):
        raise NoImpulsesError(f"x: the events add {z:.1f} standard errors of power at their "
                              f"peak over {d.size} periods around f_n {f_n:.0f} Hz; allowed: > "
                              f"{stats.norm.isf(DEFAULT_PFA):.1f}; nothing identified")


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


def background_noise(path: TransferPath, n: int, *, seed: int = 0) -> np.ndarray:
    """Gaussian noise of ``n`` samples with the path's background spectrum.

    Parameters
    ----------
    path : TransferPath
        An identified path: its ``fs_hz`` (Hz), ``background_freq_hz`` and ``background_psd``
        (record units^2/Hz).
    n : int
        Samples, > 1.
    seed : int
        Seed of the numpy generator.

    Returns
    -------
    ndarray
        Noise whose Welch PSD follows ``path.background_psd`` (record units).

    Raises
    ------
    ValueError
        ``n`` below 2 (one line naming it).
    """
    if int(n) < 2:
        raise ValueError(f"n: got {n!r}; allowed: >= 2 samples")
    rng = np.random.default_rng(seed)
    spec = np.fft.rfft(rng.standard_normal(int(n)))
    f = np.fft.rfftfreq(int(n), 1 / path.fs_hz)
    psd = np.interp(f, path.background_freq_hz, path.background_psd)
    y = np.fft.irfft(spec * np.sqrt(psd * path.fs_hz / 2), int(n))
    return y
