"""The background of an identified transfer path: the record's spectrum between its events,
or, where the events fill every period, the record's less the events' modelled one and the quiet
part of every period (:func:`bearing_envelope.diagnosis.transfer_path.identify_path`, step 5).
The noise a simulated record is given from it: :func:`.transfer_path.background_noise`."""

from __future__ import annotations

import math

import numpy as np

from scipy import ndimage, signal as sps

from ..signal.envelope import bandpass
from ..signal.validation import check_signal

from .path_constants import (FILTER_ORDER, IDENT_TOL, MAX_MODELLED, MIN_BACKGROUND, MIN_GAP,
                             MIN_PRE, MODE_SPAN, PRE_MARGIN, WELCH_SEGMENT)

__all__: list[str] = []


def _segments_spectra(x, starts, n, nfft, w) -> np.ndarray:
    seg = np.stack([x[s:s + n] for s in starts if 0 <= s and s + n <= x.size]) * w
    return np.abs(np.fft.rfft(seg, nfft)) ** 2


def _background(x, fs, events, gate, background, name, train):
    """Welch PSD of the healthy record, or of the record between its events (gated at every
    period's event, detected or not), or, when those stretches hold fewer than
    :data:`MIN_BACKGROUND` samples, :func:`_subtracted_background`. Returns ``(freq, psd,
    source, flag)``; ``flag`` is None or the warning that the background at the resonance is
    not identified."""
    if background is not None:
        b = check_signal(background, "background", min_length=WELCH_SEGMENT)
        f, p = sps.welch(b - b.mean(), fs, nperseg=WELCH_SEGMENT)
        return f, p, name, None
    keep = np.ones(x.size, bool)
    for pk in events:
        keep[max(pk - gate // 8 - 2, 0):pk + gate] = False
    f, gap, used = _gap_psd(x, fs, keep)
    if used >= MIN_BACKGROUND:
        return f, gap, "record", None
    return _subtracted_background(x, fs, events, train, used)


def _subtracted_background(x, fs, events, train, used):
    """The record's Welch PSD less the identified events' modelled spectrum
    (:func:`_train_psd`) where the model makes at most :data:`MAX_MODELLED` of it; where it
    makes more (widened by one rate: the lines' ripple left in the smoothed spectrum must leave
    no island of event power), the quiet part of every period (:func:`_quiet_part`). What
    neither measures is flagged: near a mode (:data:`MODE_SPAN`) interpolated (log-linear)
    from either side; far off (a real ringing's far spectrum is no damped cosine's: its force
    has a finite rise time) half the record's power; where the quiet part is measured but
    inconsistent, its upper bound. Never above the record's own spectrum."""
    hz, modes = train
    f, p = sps.welch(x, fs, nperseg=WELCH_SEGMENT)
    model = _train_psd(f, fs, hz, modes)
    w = max(int(round(hz / (f[1] - f[0]))), 1)
    smooth = np.convolve(np.pad(p, (w // 2, w - 1 - w // 2), mode="edge"), np.ones(w) / w,
                         mode="valid")  # the events' lines spread over one rate
    dom = ndimage.binary_dilation(model > MAX_MODELLED * smooth, iterations=w)
    out = smooth - model
    src = (f"record less the identified events' modelled spectrum ({used} samples between "
           f"the events; {MIN_BACKGROUND} needed)")
    ok, upper = ~dom, np.zeros(f.size, bool)
    quiet = _quiet_part(x, fs, events, hz, modes) if dom.any() else None
    if quiet is not None:
        est, measured, bound, n = quiet
        use = dom & measured
        out[use], ok, upper = est[use], ok | (use & ~bound), use & bound
        if use.any():
            src += (f"; at {_spans(f, use)}, where the events make most of it, the quietest "
                    f"{n} samples of every period less the earlier events' modelled ringing")
    bad = ~ok & ~upper
    if not (bad.any() or upper.any()):
        return f, out, src, None
    notes = []
    if bad.any():
        _fill_unmeasured(f, out, smooth, bad, ok | upper, modes, hz)
        notes.append(f"not identified at {_spans(f, bad)} (interpolated across the modes, "
                     "half the record's elsewhere): the events ring for most of each period and "
                     "make more than half of the record's power there, " + (
                         "and of its quiet part" if quiet is not None else
                         f"and no period leaves {MIN_PRE} samples before the next event"))
        src += "; interpolated across the modes, half the record's elsewhere where unmeasured"
    if upper.any():
        notes.append(f"only an upper bound at {_spans(f, upper)}: the quiet part of each "
                     f"period differs by more than {2 * IDENT_TOL:.0%} from the part half its "
                     "length earlier (ringing the model leaves out)")
        src += "; the smaller of the two where they differ"
    out = np.minimum(out, np.maximum(smooth, p))
    return f, out, src, "background " + "; ".join(notes)


def _fill_unmeasured(f, out, smooth, bad, ok, modes, hz) -> None:
    """In place: ``out`` where ``bad``, near a mode interpolated (log-linear) from the
    frequencies ``ok`` either side, elsewhere half the record's ``smooth`` PSD."""
    span = np.zeros(f.size, bool)
    for m in modes:
        span |= np.abs(f - m["f_n_hz"]) <= MODE_SPAN * m["zeta"] * m["f_n_hz"] + hz
    near, far = bad & span, bad & ~span
    if near.any() and ok.sum() >= 2:
        out[near] = np.exp(np.interp(f[near], f[ok], np.log(out[ok])))
    half = far | (near & (ok.sum() < 2))
    out[half] = 0.5 * smooth[half]


def _spans(f, mask, most: int = 4) -> str:
    """The frequencies ``mask`` marks as ranges: ``"a-b, c-d Hz"`` (rounded); past ``most``
    ranges, the first ``most`` and how many more, with the width they all cover."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    spans = [f"{f[a]:.0f}-{f[b - 1]:.0f}" for a, b in zip(edges[::2], edges[1::2])]
    if len(spans) <= most:
        return ", ".join(spans) + " Hz"
    return (f"{', '.join(spans[:most])} Hz and {len(spans) - most} more ranges "
            f"({mask.sum() * (f[1] - f[0]):.0f} Hz in all)")


def _quiet_part(x, fs, events, hz, modes):
    """The background from the quiet part of every period, or None when the period leaves
    none: the ``n`` samples of each period whose power, averaged over every period on the
    event track, is least (:func:`_quietest_lag`), their PSD less the earlier events' ringing
    modelled there (:func:`_pre_event_psd`). Measured where that remainder makes at most
    :data:`MAX_MODELLED` of it; checked against the same ``n / 2`` samples earlier (more
    ringing, the same background): where both are measured and differ by more than twice
    :data:`IDENT_TOL`, the smaller is kept as an upper bound. ``n``: the largest power of
    two within half of what the period leaves before the event's modelled onset
    (:func:`_onset_delay`), at least :data:`MIN_PRE`, at most ``WELCH_SEGMENT``.

    Returns
    -------
    (est, measured, bound, n)
        PSD (record units^2/Hz, on the Welch grid), the masks measured and upper bound only,
        and ``n``."""
    period = fs / hz
    delay = _onset_delay(modes[0], fs)
    n = min(1 << int(math.floor(math.log2(max((period - delay - PRE_MARGIN) / 2, 1)))),
            WELCH_SEGMENT)
    nxt = events[1:][(events[1:] - int(period) - n >= 0) & (events[1:] < x.size)]
    if n < MIN_PRE or nxt.size < 2:
        return None
    lag = _quietest_lag(x, nxt, int(period), n, delay + PRE_MARGIN)
    (q, rem), (q2, rem2) = (_pre_event_psd(x, fs, nxt, hz, modes, k, n, delay)
                            for k in (lag, lag - n // 2))
    est, est2 = q - rem, q2 - rem2
    measured, measured2 = rem <= MAX_MODELLED * q, rem2 <= MAX_MODELLED * q2
    bound = measured & measured2 & (np.abs(est2 / np.where(measured, est, 1.0) - 1)
                                    > 2 * IDENT_TOL)
    est = np.where(bound, np.minimum(est, est2), est)
    return est, measured, bound, n


def _pre_event_psd(x, fs, nxt, hz, modes, lag: int, n: int, delay: int):
    """The mean of the Hann periodograms (``nfft`` = :data:`WELCH_SEGMENT`) of the ``n``
    samples from ``lag`` (< 0) after each next event's track position ``nxt``, and the
    earlier events' ringing modelled there: every mode's ``a^2 / 2 (|C_j|^2 + |S_j|^2)``
    summed over the earlier events ``j`` (their phases at the mode independent), ``C_j,
    S_j`` the same periodograms of the damped cosine and sine from the stretch's lag after
    event ``j``'s modelled onset (``delay`` samples before its track position)."""
    period = fs / hz
    _, q = sps.periodogram(np.stack([x[s:s + n] for s in nxt + lag]), fs, window="hann",
                           nfft=WELCH_SEGMENT, axis=-1)
    rem = np.zeros(q.shape[1])
    for m in modes:
        wn = 2 * math.pi * m["f_n_hz"]
        s, th = m["zeta"] * wn / fs, wn * math.sqrt(1 - m["zeta"] ** 2) / fs
        j = np.arange(1, int(math.log(1e4) / (s * period)) + 2)  # until 1e-4 of the amplitude
        t = (j * period + lag + delay)[:, None] + np.arange(n)[None, :]
        decay = np.exp(-s * t)
        _, pc = sps.periodogram(np.concatenate([decay * np.cos(th * t), decay * np.sin(th * t)]),
                                fs, window="hann", nfft=WELCH_SEGMENT, axis=-1)
        rem += m["amplitude"] ** 2 / 2 * pc.sum(axis=0)
    return q.mean(axis=0), rem


def _quietest_lag(x, nxt, period: int, n: int, lead: int) -> int:
    """Lag (from the next event's track position, < 0) where the ``n`` samples whose mean
    power over every period is least start: within the period, ending ``lead`` samples or
    more before the event. On the CWRU records a real event's power rises 16-30 samples
    before its track position, earlier than a damped cosine's through the band-pass."""
    lags = np.arange(-period + 1, -lead)
    power = np.mean(x[nxt[:, None] + lags[None, :]] ** 2, axis=0)
    window = np.convolve(power, np.ones(n), mode="valid")  # windows starting at lags[:size]
    return int(lags[int(np.argmin(window))])


def _onset_delay(mode: dict, fs: float) -> int:
    """Samples from a mode's onset to the peak of its ringing's envelope through the mode's
    band-pass (where the event track places an event)."""
    wn = 2 * math.pi * mode["f_n_hz"]
    s, th = mode["zeta"] * wn / fs, wn * math.sqrt(1 - mode["zeta"] ** 2) / fs
    pad, k = 4 * WELCH_SEGMENT, np.arange(4 * WELCH_SEGMENT)
    c = np.r_[np.zeros(pad), np.exp(-s * k) * np.cos(th * k)]
    env = np.abs(sps.hilbert(bandpass(c, fs, tuple(mode["band_hz"]), order=FILTER_ORDER)))
    return max(int(np.argmax(env)) - pad, 0)


def _train_psd(f, fs: float, rate: float, modes: list) -> np.ndarray:
    """One-sided PSD of a train of ``rate`` events per second, each ringing every mode as the
    sampled ``a exp(-zeta wn t) cos(wd t)`` from its onset (an accelerometer's impulse
    response starts at its maximum), the events' phases at the mode independent:
    ``2 rate a^2 |D|^2 / fs^2`` with the sequence's transform
    ``D = (1 - r cos(th) / z) / (1 - 2 r cos(th) / z + r^2 / z^2)``, ``r = exp(-zeta wn / fs)``,
    ``th = wd / fs``, ``z = exp(2 pi i f / fs)`` (sampled, so that its tails far from the
    mode and near 0 and fs/2 are the record's, not the analog one's)."""
    zi = np.exp(-2j * np.pi * np.asarray(f) / fs)
    out = np.zeros(zi.shape)
    for m in modes:
        wn = 2 * math.pi * m["f_n_hz"]
        r = math.exp(-m["zeta"] * wn / fs)
        c = r * math.cos(wn * math.sqrt(1 - m["zeta"] ** 2) / fs)
        d = (1 - c * zi) / (1 - 2 * c * zi + r * r * zi * zi)
        out += 2 * rate * m["amplitude"] ** 2 * np.abs(d) ** 2 / fs ** 2
    return out


def _gap_psd(x, fs, keep) -> tuple[np.ndarray | None, np.ndarray | None, int]:
    """PSD of the record between its events: the mean of the Hann-windowed periodograms
    (``nfft`` = :data:`WELCH_SEGMENT`) of the stretches ``keep`` marks, each cut into pieces of
    at most ``WELCH_SEGMENT`` and at least :data:`MIN_GAP` samples, weighted by length. Each
    piece is windowed on its own: zeroing the events out of the record instead (a rectangular
    gate) would spread the resonance's power over the whole band through the gate's edges
    (on the 48 kHz CWRU records, 30 dB over the record's own floor at 12-18 kHz). ``(None,
    None)`` when no stretch is that long (hardly reachable: events are only detected where the
    envelope falls back between them, and the gates end where it has); the third value is the
    number of samples read."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], keep.astype(np.int8), [0]))))
    pieces = [(a, min(a + WELCH_SEGMENT, b)) for start, b in zip(edges[::2], edges[1::2])
              for a in range(start, b, WELCH_SEGMENT) if min(a + WELCH_SEGMENT, b) - a >= MIN_GAP]
    if not pieces:
        return None, None, 0
    acc, total = 0.0, 0
    for a, b in pieces:
        f, p = sps.periodogram(x[a:b], fs, window="hann", nfft=WELCH_SEGMENT)
        acc, total = acc + p * (b - a), total + (b - a)
    return f, acc / total, total
