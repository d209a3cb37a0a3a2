r"""Defect length from the spacing of a pit's entry and exit events (issue 42, part 5).

A rolling element crossing a pit makes two events: at the entry edge it unloads (a step of the
contact force, mostly low-frequency) and at the exit edge it strikes (an impact, broadband). Their
spacing :math:`\Delta t` is the time the element takes to cross the pit,
:math:`L \approx v\,\Delta t`, with :math:`v` the speed at which the defect sweeps through the
contact (:meth:`~bearing_envelope.physics.locations.FaultLocation.speed_m_s`: :math:`2\pi f_c
R_o` on the outer race, 1.76 m/s in the CWRU 6205 at 1797 rpm). Sawalhi & Randall (2011, MSSP
25, 846-870) read it in the envelope of the pre-whitened signal; this module reads it in the
average of the events, each aligned on its exit:

1. pre-whitening by the inverse of an autoregressive model of the record (order
   :data:`AR_ORDER`, Yule-Walker; Sawalhi & Randall's choice): a minimum-phase inverse of the
   structure's resonances, so each event's ringing shortens towards the force that made it
   (the step at the entry, the impulse at the exit); a zero-phase band-pass (default
   :data:`BAND_FRACTIONS` of fs) and the squared envelope ``e`` follow. (Cepstrum
   pre-whitening flattens the magnitude only and leaves the resonances' phase ringing);
2. events: the peaks of ``e`` at least half an event period apart that exceed the floor's
   level at a false-alarm probability of :data:`EVENT_PFA` per period (a floor of complex
   Gaussian noise has an exponential squared envelope of mean :math:`\mu = \mathrm{median}/\ln
   2`: threshold :math:`\mu \ln(N_P / p)` over the :math:`N_P` samples of a period). Fewer
   than :data:`MIN_EVENTS`: no estimate. The peak of an event is its exit impact;
3. each event's profile *before* its peak, ``(e[peak - k] - mu) / (e[peak] - mu)``, k = 0 ..
   k_max, is averaged over the events: :math:`A(k)`, the exit's own lobe at 0 and the entry
   at :math:`k = \Delta t f_s`. Aligning each event on its own peak takes out the events'
   jitter; looking before the peak only keeps out what the structure does *after* an impact
   (its ringing and the beats of its modes, which are causal): in the autocorrelation of the
   events, which is symmetric, those read as echoes (they did on the records of
   ``tests/test_defect_size.py``);
4. resolvability: the entry is read only at lags ``k >= k_min = max(MIN_LAG_SAMPLES,
   LOBE_FACTOR x HWHM)``, where HWHM is the half-width at half maximum of :math:`A`'s main lobe
   (what is left of the resonance's decay after whitening, and the band's own width), and
   ``MIN_LAG_SAMPLES`` keeps the lag's quantisation (+-0.5 sample) within 1/6 of the spacing.
   The shortest length this record can show is ``L_min = v k_min / fs``. The entry is the
   largest local maximum of :math:`A` on ``[k_min, k_max]`` (``k_max``:
   :data:`MAX_LAG_FRACTION` of the event period) whose prominence over the lowest value
   between it and the main lobe exceeds :data:`ECHO_Z` x its bootstrap standard deviation and
   :data:`MIN_PROMINENCE` of the exit's peak, and
   that :data:`STABLE_FRACTION` of the bootstrap resamples find within
   :data:`STABLE_TOLERANCE`; otherwise "not resolvable at this fs";
5. the interval: the 2.5-97.5 % range of the entry's lag over :data:`N_BOOTSTRAP` resamples
   of the events (seeded), each refined by a parabola through its three highest lags, widened
   by half a sample (the lag grid).

What the length is not: the exit impact happens when the element's surface meets the exit
edge, slightly before its centre is over it, so ``v dt`` reads somewhat shorter than the pit's
length along rolling for a pit much longer than the contact, and the speed is the nominal
kinematics' (a slip of 1-2 % moves it by as much).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..lazy import lazy_module
from ..signal.envelope import bandpass, envelope
from ..signal.validation import check_fs, check_signal

sp_signal = lazy_module("scipy.signal")
sp_linalg = lazy_module("scipy.linalg")

__all__ = ["ESTIMATED", "NOT_RESOLVABLE", "NO_EVENTS", "Spacing", "DefectSize",
           "entry_exit_spacing", "defect_length", "record_scene", "FAMILY_LOCATIONS", "ar_whiten",
           "whitened_squared_envelope", "find_events", "event_profiles", "record_defect_size", "size_document"]

#: Status of a length read from the echo.
ESTIMATED = "estimated"
#: Status when events are found but no echo stands beyond the shortest lag this fs resolves.
NOT_RESOLVABLE = "not resolvable at this fs"
#: Status when the record holds too few events to read anything.
NO_EVENTS = "no events"

#: Order of the autoregressive model whose inverse whitens the record.
AR_ORDER = 32
#: Default band of the whitened signal, as fractions of fs (1.5 kHz - 21.6 kHz at 48 kHz).
BAND_FRACTIONS = (1.0 / 32.0, 0.45)
#: Shortest echo lag, samples: the lag grid's +-0.5 sample is then within 1/6 of the spacing.
MIN_LAG_SAMPLES = 3
#: The echo must lie beyond this many half-widths (at half maximum) of the event's own lobe.
LOBE_FACTOR = 2.0
#: Longest echo lag, as a fraction of the event period.
MAX_LAG_FRACTION = 0.2
#: False-alarm probability of an event, per event period, on a floor of Gaussian noise.
EVENT_PFA = 1e-3
#: Events needed for an estimate.
MIN_EVENTS = 8
#: Bootstrap resamples of the events (the interval and the echo's significance).
N_BOOTSTRAP = 200
#: Seed of the bootstrap (deterministic results).
BOOTSTRAP_SEED = 0
#: The echo's prominence must exceed this many bootstrap standard deviations.
ECHO_Z = 3.0
#: ... and this fraction of the exit's peak (an entry carries at least 5 % of the exit's squared
#: envelope; the whitening's residual before a lone impact reached 0.8 % on the control records
#: of ``benchmarks/defect_size.py``, a bump that consistent passes any bootstrap test).
MIN_PROMINENCE = 0.05
#: An echo is read only when this fraction of the event resamples find it within
#: :data:`STABLE_TOLERANCE` of the estimate (else two candidates compete: no estimate).
STABLE_FRACTION = 0.8
#: (samples, fraction of the lag): the larger is the tolerance of :data:`STABLE_FRACTION`.
STABLE_TOLERANCE = (1.5, 0.1)
#: Coverage of the interval (2.5 - 97.5 % of the bootstrap).
COVERAGE = 0.95

#: Fault family -> the location whose events it is (the analysis's families).
FAMILY_LOCATIONS = {"bpfo": "outer_race", "bpfi": "inner_race", "bsf": "rolling_element",
                    "bsf2": "rolling_element"}


@dataclass(frozen=True)
class Spacing:
    """The entry-exit spacing read from a record (:func:`entry_exit_spacing`).

    Attributes
    ----------
    status : str
        :data:`ESTIMATED`, :data:`NOT_RESOLVABLE` or :data:`NO_EVENTS`.
    dt_s : float or None
        The spacing (s); None unless estimated.
    interval_s : (float, float) or None
        Its :data:`COVERAGE` interval (s).
    min_dt_s : float or None
        The shortest spacing this record resolves, ``k_min / fs`` (None without events).
    n_events, n_periods : int
        Events found and event periods the record holds.
    band_hz : (float, float)
        Band of the whitened signal.
    reason : str
        Why the status, in words.
    profile : ndarray
        The events' mean profile before their peak ``A(k)``, k = 0 .. k_max
        (:func:`event_profiles`; empty without events).
    """

    status: str
    dt_s: float | None
    interval_s: tuple[float, float] | None
    min_dt_s: float | None
    n_events: int
    n_periods: int
    band_hz: tuple[float, float]
    reason: str
    profile: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))


@dataclass(frozen=True)
class DefectSize:
    """An estimated defect length (:func:`defect_length`).

    Attributes
    ----------
    location : str
        The fault location (``outer_race`` ...).
    speed_m_s : float
        The speed the defect sweeps through the contact (m/s).
    spacing : Spacing
        The entry-exit spacing it comes from.
    """

    location: str
    speed_m_s: float
    spacing: Spacing

    @property
    def status(self) -> str:
        """:data:`ESTIMATED`, :data:`NOT_RESOLVABLE` or :data:`NO_EVENTS`."""
        return self.spacing.status

    @property
    def length_mm(self) -> float | None:
        """``v dt`` (mm); None unless estimated."""
        dt = self.spacing.dt_s
        return None if dt is None else 1e3 * self.speed_m_s * dt

    @property
    def interval_mm(self) -> tuple[float, float] | None:
        """The length's interval (mm); None unless estimated."""
        iv = self.spacing.interval_s
        return None if iv is None else (1e3 * self.speed_m_s * iv[0],
                                        1e3 * self.speed_m_s * iv[1])

    @property
    def min_length_mm(self) -> float | None:
        """The shortest length this record resolves (mm)."""
        m = self.spacing.min_dt_s
        return None if m is None else 1e3 * self.speed_m_s * m

    def summary(self) -> str:
        """One line: the length and its interval, or the status and why.

        Returns
        -------
        str
            E.g. ``outer_race defect length 0.36 mm (0.31-0.41 mm, 95 %; 412/544 events,
            dt = 204 us at v = 1.761 m/s)``.
        """
        s = self.spacing
        ev = f"{s.n_events}/{s.n_periods} events"
        if self.status == ESTIMATED:
            lo, hi = self.interval_mm
            return (f"{self.location} defect length {self.length_mm:.3g} mm ({lo:.3g}-{hi:.3g} "
                    f"mm, {COVERAGE:.0%}; {ev}, dt = {1e6 * s.dt_s:.3g} us at v = "
                    f"{self.speed_m_s:.4g} m/s)")
        lmin = "" if self.min_length_mm is None else \
            f"; shortest resolvable {self.min_length_mm:.3g} mm"
        return f"{self.location} defect length: {self.status} ({s.reason}; {ev}{lmin})"

    def to_dict(self) -> dict:
        """JSON types only.

        Returns
        -------
        dict
            ``location``, ``status``, ``length_mm``, ``interval_mm``, ``min_length_mm``,
            ``dt_us``, ``speed_m_s``, ``n_events``, ``n_periods``, ``band_hz``, ``reason``.
        """
        s = self.spacing
        iv = self.interval_mm
        return {"location": self.location, "status": self.status, "length_mm": self.length_mm,
                "interval_mm": None if iv is None else list(iv),
                "min_length_mm": self.min_length_mm,
                "dt_us": None if s.dt_s is None else 1e6 * s.dt_s, "speed_m_s": self.speed_m_s,
                "n_events": s.n_events, "n_periods": s.n_periods, "band_hz": list(s.band_hz),
                "reason": s.reason}


# ------------------------------------------------------------------------------ the spacing
def _check_inputs(x, fs, event_rate_hz, band, max_lag_s):
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=4 * AR_ORDER)
    if np.ptp(x) == 0.0:
        raise ValueError(f"x: a constant signal ({x[0]:g}); allowed: a vibration record")
    rate = float(event_rate_hz)
    if not math.isfinite(rate) or not 0.0 < rate < fs / 2:
        raise ValueError(f"event_rate_hz: got {event_rate_hz!r}; allowed: a rate in "
                         f"(0, fs/2 = {fs / 2:g}) Hz")
    n_periods = int(x.size * rate / fs)
    if n_periods < MIN_EVENTS:
        raise ValueError(f"x: {x.size} samples hold {n_periods} periods of {rate:g} Hz; "
                         f"allowed: at least {MIN_EVENTS} (a longer record)")
    band = tuple(f * fs for f in BAND_FRACTIONS) if band is None else band
    try:
        lo, hi = float(band[0]), float(band[1])
    except (TypeError, ValueError, IndexError):
        raise ValueError(f"band: got {band!r}; allowed: (low_hz, high_hz)") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi < fs / 2):
        raise ValueError(f"band: got {band!r}; allowed: 0 < low_hz < high_hz < fs/2 = "
                         f"{fs / 2:g} Hz")
    k_max = int(MAX_LAG_FRACTION * fs / rate) if max_lag_s is None else int(float(max_lag_s) * fs)
    if max_lag_s is not None and (not math.isfinite(float(max_lag_s)) or
                                  not MIN_LAG_SAMPLES + 2 <= k_max <= 0.5 * fs / rate):
        raise ValueError(f"max_lag_s: got {max_lag_s!r}; allowed: {(MIN_LAG_SAMPLES + 2) / fs:g}"
                         f" .. half the event period ({0.5 / rate:g}) s")
    return x, fs, rate, n_periods, (lo, hi), k_max


def ar_whiten(x, ar_order: int = AR_ORDER) -> np.ndarray:
    """The record through the inverse of its autoregressive model (the prediction error).

    The model's coefficients solve the Yule-Walker equations on the record's biased
    autocorrelation (FFT, :func:`scipy.linalg.solve_toeplitz`); the inverse filter
    ``A(z) = 1 + a_1 z^-1 + ... + a_p z^-p`` is minimum phase, so it undoes the resonances'
    phase as well as their magnitude.

    Parameters
    ----------
    x : array_like, 1-D
        The record, longer than ``4 ar_order``.
    ar_order : int, default :data:`AR_ORDER`
        Model order ``p``.

    Returns
    -------
    ndarray
        The prediction error, same length.
    """
    x = np.asarray(x, dtype=float)
    x = x - x.mean()
    spec = np.fft.rfft(x, 2 * x.size)
    r = np.fft.irfft(np.abs(spec) ** 2)[:ar_order + 1]
    a = sp_linalg.solve_toeplitz(r[:ar_order], -r[1:ar_order + 1])
    return sp_signal.lfilter(np.concatenate([[1.0], a]), [1.0], x)


def whitened_squared_envelope(x, fs: float, band) -> np.ndarray:
    """The squared envelope of the AR-whitened (:func:`ar_whiten`), band-passed signal.

    Parameters
    ----------
    x : array_like, 1-D
        The record.
    fs : float
        Sampling rate (Hz).
    band : (float, float)
        Band (Hz) of the whitened signal.

    Returns
    -------
    ndarray
        ``|analytic(bandpass(ar_whiten(x)))|^2``, same length as ``x``.
    """
    return envelope(bandpass(ar_whiten(x), fs, band), squared=True)


def find_events(e: np.ndarray, period: float) -> tuple[np.ndarray, float]:
    """Events of a squared envelope: peaks above the floor at :data:`EVENT_PFA` per period.

    Parameters
    ----------
    e : ndarray
        Squared envelope.
    period : float
        Event period, samples.

    Returns
    -------
    peaks : ndarray of int
        Sample index of each event, at least half a period apart.
    floor : float
        The floor's mean level ``median(e) / ln 2``.
    """
    floor = float(np.median(e)) / math.log(2.0)
    threshold = floor * math.log(period / EVENT_PFA)
    peaks, _ = sp_signal.find_peaks(e, height=threshold, distance=max(1, int(0.5 * period)))
    return peaks, floor


def event_profiles(e: np.ndarray, peaks: np.ndarray, floor: float, k_max: int) -> np.ndarray:
    """What precedes each event's peak: ``e[peak - k] - floor`` for k = 0 .. k_max, normalised
    at k = 0.

    Parameters
    ----------
    e : ndarray
        Squared envelope.
    peaks : ndarray of int
        Event indices (:func:`find_events`); those within ``k_max`` of an end are left out.
    floor : float
        Level subtracted from each segment.
    k_max : int
        Longest lag, samples.

    Returns
    -------
    ndarray
        Shape ``(n_events, k_max + 1)``, each row 1 at lag 0.
    """
    p = peaks[(peaks >= k_max) & (peaks + k_max < e.size)]
    seg = e[p[:, None] - np.arange(k_max + 1)[None, :]] - floor
    return seg / seg[:, :1]


def _hwhm(r: np.ndarray) -> float:
    """Half-width (samples) where ``r`` (1 at 0) first falls below 1/2, interpolated."""
    below = np.flatnonzero(r < 0.5)
    if below.size == 0:
        return float(r.size)
    k = int(below[0])
    return k - 1 + (r[k - 1] - 0.5) / (r[k - 1] - r[k])


def _echo(r: np.ndarray, k_min: int) -> tuple[int, int] | None:
    """The highest local maximum of ``r`` on ``[k_min, end - 1)`` and the lag of the lowest
    value between the main lobe and it; None when there is none."""
    k = np.arange(max(k_min, 1), r.size - 1)
    local = k[(r[k] > r[k - 1]) & (r[k] >= r[k + 1])]
    if local.size == 0:
        return None
    peak = int(local[np.argmax(r[local])])
    valley = int(np.argmin(r[1:peak])) + 1
    return peak, valley


def _refine(r: np.ndarray, k: int) -> float:
    """Lag of the parabola's vertex through ``r[k-1:k+2]``."""
    a, b, c = r[k - 1], r[k], r[k + 1]
    den = a - 2 * b + c
    return k + (0.5 * (a - c) / den if den < 0 else 0.0)


def entry_exit_spacing(x, fs: float, event_rate_hz: float, *, band=None,
                       max_lag_s: float | None = None) -> Spacing:
    """The spacing of a pit's entry and exit events, or why it cannot be read.

    Parameters
    ----------
    x : array_like, 1-D
        The vibration record (any unit), at least :data:`MIN_EVENTS` event periods long.
    fs : float
        Sampling rate (Hz).
    event_rate_hz : float
        The rate at which the defect's events repeat (Hz): BPFO, BPFI or 2 x BSF, as measured.
    band : (float, float), optional
        Band (Hz) of the whitened signal; default :data:`BAND_FRACTIONS` x fs.
    max_lag_s : float, optional
        Longest spacing searched (s); default :data:`MAX_LAG_FRACTION` of the event period.

    Returns
    -------
    Spacing
        ``status`` :data:`ESTIMATED` with ``dt_s`` and ``interval_s``, or
        :data:`NOT_RESOLVABLE` (events, no echo beyond ``min_dt_s``) or :data:`NO_EVENTS`.

    Raises
    ------
    ValueError
        In one line, before any work: a record not 1-D, non-finite, constant or shorter than
        :data:`MIN_EVENTS` periods; fs or the rate out of range; a band outside (0, fs/2).
    """
    x, fs, rate, n_periods, band, k_max = _check_inputs(x, fs, event_rate_hz, band, max_lag_s)
    e = whitened_squared_envelope(x, fs, band)
    peaks, floor = find_events(e, fs / rate)
    out = dict(n_periods=n_periods, band_hz=band)
    if peaks.size < MIN_EVENTS:
        return Spacing(NO_EVENTS, None, None, None, int(peaks.size),
                       reason=f"{peaks.size} event(s) above the floor at {EVENT_PFA:g} false "
                              f"alarms per period, fewer than {MIN_EVENTS}", **out)
    acs = event_profiles(e, peaks, floor, k_max)
    r = acs.mean(axis=0)
    k_min = max(MIN_LAG_SAMPLES, int(math.ceil(LOBE_FACTOR * _hwhm(r))))
    out.update(min_dt_s=k_min / fs, n_events=int(acs.shape[0]), profile=r)
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    boot = acs[rng.integers(0, acs.shape[0], (N_BOOTSTRAP, acs.shape[0]))].mean(axis=1)
    peak = _significant_echo(r, boot, k_min, k_max)
    if peak is None:
        return Spacing(NOT_RESOLVABLE, None, None,
                       reason=f"no entry stands {ECHO_Z:g} bootstrap s.d. and {MIN_PROMINENCE:g} of the "
                              f"exit above the lobe between "
                              f"{k_min} and {k_max} samples", **out)
    dt = _refine(r, peak)
    lo, hi, stable = _interval(boot, k_min, dt)
    if stable < STABLE_FRACTION:
        return Spacing(NOT_RESOLVABLE, None, None,
                       reason=f"the entry at {dt:.1f} samples is found by {stable:.0%} of the "
                              f"event resamples, fewer than {STABLE_FRACTION:.0%}", **out)
    return Spacing(ESTIMATED, dt / fs, (lo / fs, hi / fs),
                   reason=f"entry {dt:.2f} samples before the exit, found by {stable:.0%} of "
                          f"the event resamples", **out)


def _significant_echo(r, boot, k_min: int, k_max: int) -> int | None:
    """The echo's lag (samples) if its prominence exceeds :data:`ECHO_Z` bootstrap s.d."""
    found = _echo(r, k_min) if k_min < k_max - 1 else None
    if found is None:
        return None
    peak, valley = found
    prom = boot[:, peak] - boot[:, valley]
    height = r[peak] - r[valley]
    return peak if height > max(ECHO_Z * prom.std(), MIN_PROMINENCE) else None


def _interval(boot, k_min: int, dt: float) -> tuple[float, float, float]:
    """The :data:`COVERAGE` interval of the echo's lag over the resamples, widened by half a
    sample (samples), and the fraction of resamples whose echo lies within
    :data:`STABLE_TOLERANCE` of ``dt``."""
    lags = []
    for rb in boot:
        hit = _echo(rb, k_min)
        lags.append(_refine(rb, hit[0]) if hit is not None else np.nan)
    lags = np.asarray(lags)
    lo, hi = np.nanpercentile(lags, [50 * (1 - COVERAGE), 50 * (1 + COVERAGE)])
    near = np.abs(lags - dt) <= max(STABLE_TOLERANCE[0], STABLE_TOLERANCE[1] * dt)
    return min(lo, dt) - 0.5, max(hi, dt) + 0.5, float(np.mean(near))


# ----------------------------------------------------------------------------- the length
def record_scene(bearing: str, shaft_hz: float, location: str):
    """The kinematic scene of a record: a catalogue bearing at a shaft rate, a defect location.

    Parameters
    ----------
    bearing : str
        A catalogue designation (``"6205"``, :func:`~bearing_envelope.physics.catalogue.
        resolve_designation`).
    shaft_hz : float
        Shaft rate (Hz), > 0.
    location : str
        A fault location (``outer_race``, ``inner_race``, ``rolling_element``).

    Returns
    -------
    Scene
        The scene (no defect depth: only its kinematics are read).
    """
    from ..physics.scene import Scene   # the scene's validation, on first use

    return Scene.from_mapping({"bearing": {"designation": bearing},
                               "operation": {"shaft_rate_hz": float(shaft_hz)},
                               "defect": {"location": location}}, load_kN=1.0, depth_um=0.0)


def defect_length(x, fs: float, scene, *, event_rate_hz: float | None = None, band=None,
                  max_lag_s: float | None = None) -> DefectSize:
    """A defect's length along rolling, ``v dt``, from its events' entry-exit spacing.

    Parameters
    ----------
    x : array_like, 1-D
        The vibration record.
    fs : float
        Sampling rate (Hz).
    scene : Scene
        Its bearing, shaft rate and defect location (:func:`record_scene`): the speed
        ``scene.defect_speed_m_s`` (the location's
        :meth:`~bearing_envelope.physics.locations.FaultLocation.speed_m_s`) and, unless given,
        the event rate (the location's family among
        :func:`~bearing_envelope.physics.locations.scene_event_frequencies`).
    event_rate_hz : float, optional
        The event rate as measured (Hz); default the scene's.
    band : (float, float), optional
        Band of the whitened signal (Hz), :func:`entry_exit_spacing`.
    max_lag_s : float, optional
        Longest spacing searched (s), :func:`entry_exit_spacing`.

    Returns
    -------
    DefectSize
        ``length_mm`` and ``interval_mm`` where estimated, else the status (``summary()``).

    Raises
    ------
    ValueError
        As :func:`entry_exit_spacing`.

    Examples
    --------
    >>> import numpy as np
    >>> from bearing_envelope.diagnosis.defect_size import defect_length, record_scene
    >>> rng = np.random.default_rng(0)
    >>> res = defect_length(rng.standard_normal(48000), 48000.0,
    ...                     record_scene("6205", 29.95, "outer_race"))
    >>> res.status, res.length_mm
    ('no events', None)
    """
    from ..physics.locations import scene_event_frequencies

    loc = scene.defect.fault_location
    rate = loc.event_rate(scene_event_frequencies(scene)) if event_rate_hz is None \
        else event_rate_hz
    sp = entry_exit_spacing(x, fs, rate, band=band, max_lag_s=max_lag_s)
    return DefectSize(loc.name, float(scene.defect_speed_m_s), sp)


def record_defect_size(res) -> DefectSize | str:
    """The defect length of an analysed record's diagnosed family (``bearing-envelope analyze``).

    Parameters
    ----------
    res : RecordAnalysis
        A record's analysis with its samples (:func:`~bearing_envelope.diagnosis.records.
        analyze_record`).

    Returns
    -------
    DefectSize or str
        The estimate (or its status) at the diagnosed family's measured rate and the measured
        shaft rate; a str saying why none was attempted: no family diagnosed, a family of no
        location (``ftf``, a named line), no catalogue bearing, or a record shorter than
        :data:`MIN_EVENTS` periods.
    """
    diag = res.verdict.diagnosis
    if diag is None:
        return "no fault diagnosed"
    location = FAMILY_LOCATIONS.get(diag.family)
    if location is None:
        return f"{diag.family}: no fault location makes this family's events"
    if res.bearing is None:
        return "no catalogue bearing (--bearing): the defect's speed needs its radii"
    if res.signal is None:
        return "the record's samples were not kept"
    fr = float(res.frequencies.get("fr", res.shaft_hz))
    scene = record_scene(res.bearing, fr, location)
    rate = res.frequencies.get(scene.defect.fault_location.family)
    try:
        return defect_length(res.signal, res.fs, scene, event_rate_hz=rate)
    except ValueError as exc:
        return f"not estimated: {exc}"


def size_document(res) -> dict:
    """The diagnosed defect's length from its entry-exit spacing as a JSON-able document, or
    why there is none (:func:`record_defect_size`; what ``analyze`` prints and stores, for one
    record and in a batch).

    Parameters
    ----------
    res : RecordAnalysis
        The record's analysis (with its samples).

    Returns
    -------
    dict
        ``summary`` (one line) and, where attempted, the estimate's fields
        (:meth:`DefectSize.to_dict`: ``status``, ``length_mm``, ``interval_mm``,
        ``min_length_mm``, ...); ``status`` ``not attempted`` with the reason otherwise.
    """
    size = record_defect_size(res)
    if isinstance(size, str):
        return {"status": "not attempted", "summary": size}
    return {**size.to_dict(), "summary": size.summary()}
