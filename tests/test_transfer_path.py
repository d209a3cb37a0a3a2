"""Transfer path identified from a record: synthetic records with a known mode, noise alone,
the healthy CWRU record, bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import signal as sps

from bearing_envelope.cli import main
from bearing_envelope.diagnosis.transfer_path import (MIN_EVENTS, NoImpulsesError, TransferPath,
                                                      identification_flags, background_noise, identify_path)

FS = 12_000.0
REAL = Path("/work/shared/data/real")
RATES = {"bpfo": 107.0, "bpfi": 162.0, "bsf2": 141.0}


def _ringing(n, fs, times_s, area, f_n, zeta, gain):
    """Sum of the analog resonator's impulse responses (written out, not the package's
    filter): ``g 2 zeta wn exp(-sigma t) (cos wd t - sigma/wd sin wd t)`` per impulse."""
    wn = 2 * math.pi * f_n
    sigma, wd = zeta * wn, wn * math.sqrt(1 - zeta ** 2)
    t = np.arange(n) / fs
    y = np.zeros(n)
    for t0 in times_s:
        tau = t - t0
        on = tau >= 0
        y[on] += area * gain * 2 * zeta * wn * np.exp(-sigma * tau[on]) * (
            np.cos(wd * tau[on]) - sigma / wd * np.sin(wd * tau[on]))
    return y


def _record(f_n=3300.0, zeta=0.03, gain=40.0, area=1e-3, noise=5.0, seconds=3.0, seed=1):
    n = int(seconds * FS)
    times = np.arange(0.01, seconds - 0.01, 1 / 107.0)
    y = _ringing(n, FS, times, area, f_n, zeta, gain)
    return y + noise * np.random.default_rng(seed).standard_normal(n)


def test_known_mode_is_identified():
    f_n, zeta, gain, area, noise = 3300.0, 0.03, 40.0, 1e-3, 5.0
    p = identify_path(_record(f_n, zeta, gain, area, noise), FS, RATES)
    assert p.event_name == "bpfo"
    assert p.event_hz == pytest.approx(107.0, rel=0.01)
    assert p.n_events >= 0.9 * p.n_periods
    assert p.f_n_hz == pytest.approx(f_n, rel=0.03)
    assert p.zeta == pytest.approx(zeta, rel=0.2)
    assert p.zeta_range[0] <= p.zeta * 1.2 and p.zeta_range[1] >= p.zeta / 1.2
    # the amplitude of one event's ringing: g 2 zeta wn A
    assert p.amplitude == pytest.approx(gain * 2 * zeta * 2 * math.pi * f_n * area, rel=0.2)
    assert p.mode(area).gain == pytest.approx(gain, rel=0.25)
    # the background: the white noise's rms
    assert p.background_rms == pytest.approx(noise, rel=0.2)


@pytest.mark.parametrize("zeta", [0.015, 0.08])
def test_damping_is_followed(zeta):
    p = identify_path(_record(zeta=zeta, f_n=4000.0), FS, RATES)
    assert p.zeta == pytest.approx(zeta, rel=0.25)


def test_result_round_trips_through_json():
    p = identify_path(_record(), FS, RATES)
    q = TransferPath.from_dict(json.loads(p.to_json()))
    assert q == p


def test_background_noise_has_the_identified_spectrum():
    p = identify_path(_record(noise=8.0), FS, RATES)
    y = background_noise(p, 60_000, seed=3)
    assert np.std(y) == pytest.approx(8.0, rel=0.15)


def test_shaped_noise_identifies_nothing():
    rng = np.random.default_rng(5)
    b, a = sps.iirpeak(3300.0, 10.0, fs=FS)
    x = sps.lfilter(b, a, rng.standard_normal(int(3 * FS)))
    with pytest.raises(NoImpulsesError, match="nothing identified"):
        identify_path(x, FS, RATES)


def test_too_short_is_refused_before_work():
    x = _record(seconds=0.1)
    with pytest.raises(ValueError, match=f"too short; allowed: >= {MIN_EVENTS} periods"):
        identify_path(x, FS, RATES)


def test_bad_rate_is_refused():
    with pytest.raises(ValueError, match=r"event_rates\['bpfo'\]"):
        identify_path(_record(), FS, {"bpfo": -1.0})


@pytest.mark.skipif(not (REAL / "cwru_097_normal_0hp.npz").exists(), reason="no real data")
def test_healthy_cwru_record_is_refused_in_one_line(capsys):
    rc = main(["identify-path", str(REAL / "cwru_097_normal_0hp.npz"), "--bearing", "6205"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2
    assert len(err) == 1 and "nothing identified" in err[0]


@pytest.mark.skipif(not (REAL / "cwru_130_OR007at6_0hp_DE12.npz").exists(),
                    reason="no real data")
def test_cwru_outer_race_record_gives_bpfo_events(tmp_path):
    out = tmp_path / "path.json"
    rc = main(["identify-path", str(REAL / "cwru_130_OR007at6_0hp_DE12.npz"), "--bearing",
               "6205", "-o", str(out)])
    assert rc == 0
    d = json.loads(out.read_text())
    # CWRU's published BPFO multiplier 3.5848 x 29.95 Hz = 107.36 Hz; lines sit within 0.5 %
    assert d["event_name"] == "bpfo"
    assert d["event_hz"] == pytest.approx(107.36, rel=0.005)
    assert 0.0 < d["zeta"] < 0.1


# ------------------------------------------------------------------ more than one mode
def _two_mode_record(modes, area=1e-3, noise=5.0, seconds=3.0, seed=2):
    """Two analytic resonators rung by the same impulses, plus white noise."""
    n = int(seconds * FS)
    times = np.arange(0.01, seconds - 0.01, 1 / 107.0)
    y = sum(_ringing(n, FS, times, area, f_n, zeta, gain) for f_n, zeta, gain in modes)
    return y + noise * np.random.default_rng(seed).standard_normal(n)


@pytest.mark.parametrize("modes", [
    ((2600.0, 0.03, 40.0), (3800.0, 0.02, 20.0)),   # the second 5 dB below in added power
    ((3400.0, 0.025, 40.0), (2600.0, 0.05, 30.0)),  # as CWRU 130 vs 144: 0.8 kHz apart
])
def test_two_known_modes_are_both_identified(modes):
    area = 1e-3
    p = identify_path(_two_mode_record(modes, area), FS, RATES)
    assert len(p.modes) == 2
    found = sorted(p.modes, key=lambda m: m["f_n_hz"])
    for m, (f_n, zeta, gain) in zip(found, sorted(modes)):
        assert m["f_n_hz"] == pytest.approx(f_n, rel=0.03)
        assert m["zeta"] == pytest.approx(zeta, rel=0.25)
        # one event's ringing of that resonator: g 2 zeta wn A
        assert m["amplitude"] == pytest.approx(gain * 2 * zeta * 2 * math.pi * f_n * area,
                                               rel=0.25)
    gains = sorted((mo.f_n_hz, mo.gain) for mo in p.structure(area))
    for (f, g), (_, _, gain) in zip(gains, sorted(modes)):
        assert g == pytest.approx(gain, rel=0.3)
    assert p.modes[0]["f_n_hz"] == p.f_n_hz and p.modes[0]["zeta"] == p.zeta


@pytest.mark.parametrize("f_n, zeta", [(3300.0, 0.03), (4000.0, 0.015), (4000.0, 0.08),
                                       (2600.0, 0.03)])
def test_one_mode_record_keeps_one_mode(f_n, zeta):
    p = identify_path(_record(f_n=f_n, zeta=zeta), FS, RATES)
    assert len(p.modes) == 1 and p.modes[0]["f_n_hz"] == p.f_n_hz
    assert len(p.structure()) == 1 and p.structure()[0] == p.mode()


def test_a_weak_second_mode_below_the_floor_is_not_a_mode():
    # 30 dB below the first in added power: under MODE_FLOOR (-20 dB), one mode
    p = identify_path(_two_mode_record(((3000.0, 0.03, 40.0), (4500.0, 0.03, 0.9))), FS, RATES)
    assert len(p.modes) == 1


def test_path_without_modes_reads_as_its_one_mode():
    p = identify_path(_record(), FS, RATES)
    d = p.to_dict()
    del d["modes"], d["modes_rejected"]  # a path written before modes were identified
    q = TransferPath.from_dict(d)
    assert q.structure(1e-3) == [p.mode(1e-3)]


def test_background_far_from_the_resonance_is_the_noise_floor():
    """Ringing at 2 kHz 28 dB over a weak white floor, 60 events a second, so that stretches
    free of it lie between the events: the background read there holds the floor's PSD far
    from the resonance (a rectangular gate would spread the ringing's power over the band
    through its edges)."""
    noise, rate = 0.05, 60.0
    n = int(4 * FS)
    x = _ringing(n, FS, np.arange(0.01, 3.99, 1 / rate), 1e-3, 2000.0, 0.05, 1.0)
    x = x + noise * np.random.default_rng(2).standard_normal(n)
    p = identify_path(x, FS, {"bpfo": rate})
    assert p.background_source == "record" and "background" not in p.not_identified
    f, psd = np.asarray(p.background_freq_hz), np.asarray(p.background_psd)
    far = (f > 4500.0) & (f < 5800.0)
    white = 2 * noise ** 2 / FS                      # one-sided PSD of the white floor
    assert 10 * np.log10(psd[far].mean() / white) == pytest.approx(0.0, abs=1.5)


# ------------------------------------------------ issue 43: partial detection, light damping
def _train(f_n, zeta, amplitude, noise, seconds=4.0, seed=7, jitter=0.003):
    """107 Hz impulses (each time jittered by ``jitter`` of a period) whose ringing starts at
    ``amplitude``, plus white noise; returns the record and the resonator's gain for
    impulses of area 1e-3."""
    rng = np.random.default_rng(seed)
    period = 1 / 107.0
    times = np.arange(0.004, seconds - 0.004, period)
    times = times + jitter * period * rng.standard_normal(times.size)
    wn = 2 * math.pi * f_n
    gain = amplitude / (1e-3 * 2 * zeta * wn)
    n = int(seconds * FS)
    x = _ringing(n, FS, times, 1e-3, f_n, zeta, gain) + noise * rng.standard_normal(n)
    return x, gain


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_lightly_damped_mode_under_noise_is_found(seed):
    """zeta 0.015 at 3 kHz, noise sigma 0.5: the kurtogram's best cell was noise (4-6 kHz)
    and the record was refused; the band is the one holding the event rate's line."""
    x, gain = _train(3000.0, 0.015, 1.0, 0.5, seed=seed)
    p = identify_path(x, FS, RATES)
    assert p.event_name == "bpfo"
    assert p.band_hz[0] < 3000.0 < p.band_hz[1]
    assert p.f_n_hz == pytest.approx(3000.0, rel=0.02)
    assert p.zeta == pytest.approx(0.015, rel=0.1) or "zeta" in p.not_identified


@pytest.mark.parametrize("f_n, zeta, amplitude, noise", [(3000.0, 0.03, 0.6, 0.4),
                                                         (2660.0, 0.02, 0.5, 0.3),
                                                         (3000.0, 0.05, 0.9, 0.4)])
def test_partial_detection_gives_unbiased_damping_and_gain(f_n, zeta, amplitude, noise):
    """A minority of the events stand out one by one: averaging over the detected ones read
    zeta 0.03 as 0.034-0.049 and the amplitude 10-20 % high; every period's event, on the
    track of the rate's line, gives both within 10 % (or flags them)."""
    x, gain = _train(f_n, zeta, amplitude, noise, seconds=8.0)
    p = identify_path(x, FS, RATES)
    assert p.n_events < 0.6 * p.n_periods
    # each within 10 %, or listed as not identified (its standard error over subsets of the
    # events says so) and then still within 20 %
    for name, got, true in (("zeta", p.zeta, zeta), ("gain", p.mode(1e-3).gain, gain)):
        err = abs(got / true - 1)
        assert err <= 0.1 or (name in p.not_identified and err <= 0.2), (name, got, true)


def test_background_when_the_events_ring_through_every_period():
    """zeta 0.015 at 2.66 kHz: the ringing fills every period, no stretch between the events
    is long enough; the background was read from a few stretches, one holding an undetected
    event (+68 % rms, source 'record', no flag). The quiet part of each period still holds
    the previous event's ringing at the resonance, 20 dB down but far over the background
    there: the resonance's part stays flagged as not identified, the rms within 25 %."""
    noise = 0.2
    x, _ = _train(2660.0, 0.015, 2.4, noise, seconds=8.0)
    p = identify_path(x, FS, RATES)
    assert p.background_rms == pytest.approx(noise, rel=0.25)
    assert p.background_source != "record" and "background" in p.not_identified
    assert any(f.startswith("background not identified") for f in p.flags)
    flag = next(x for x in p.flags if x.startswith("background not identified"))
    spans = [[float(v) for v in s.split("-")]
             for s in flag.split(" Hz")[0].split(" at ")[1].split(", ")]
    assert any(lo <= 2660.0 <= hi for lo, hi in spans)
    assert sum(hi - lo for lo, hi in spans) < 0.5 * FS / 2  # the resonance, not the whole band


def _resonant_background(n, white, hump, zeta_b, f_b, seed):
    """White noise plus white noise through a two-pole resonator at ``f_b`` (a machine's
    broadband excitation rings the structure too); returns the noise and the one-sided PSD
    function of the truth (from the resonator's frequency response, scipy's freqz)."""
    rng = np.random.default_rng(seed)
    r, th = math.exp(-zeta_b * 2 * math.pi * f_b / FS), 2 * math.pi * f_b / FS
    den = [1.0, -2 * r * math.cos(th), r * r]
    y = white * rng.standard_normal(n) + hump * sps.lfilter([1.0], den, rng.standard_normal(n))

    def psd(f):
        h = sps.freqz([1.0], den, worN=f, fs=FS)[1]
        return 2 * (white ** 2 + hump ** 2 * np.abs(h) ** 2) / FS
    return y, psd


@pytest.mark.parametrize("rate, f_n, zeta, amplitude, white, hump", [
    (107.0, 3000.0, 0.03, 2.4, 0.2, 0.04),   # the background's own hump at the mode, 7.7 dB
    (230.0, 3000.0, 0.05, 2.4, 0.4, 0.0),    # 52-sample periods: no gap of MIN_GAP samples
])
def test_background_from_the_quiet_part_of_every_period(rate, f_n, zeta, amplitude, white, hump):
    """Events ring through most of every period (no 4096 samples between them). The
    background at the mode was interpolated across it from either side and flagged: with
    the background's own resonance there (as a machine's is) it read 34 % low in rms within
    5 half bandwidths of f_n. Read from the quietest samples of each period, less the
    earlier events' modelled ringing there, it is within 20 % and identified."""
    n, gain = int(8.0 * FS), amplitude / (1e-3 * 2 * zeta * 2 * math.pi * f_n)
    x = _ringing(n, FS, np.arange(0.004, 7.996, 1 / rate), 1e-3, f_n, zeta, gain)
    noise, truth = _resonant_background(n, white, hump, 0.03, f_n, seed=11)
    p = identify_path(x + noise, FS, {k: v * rate / 107.0 for k, v in RATES.items()})
    f, psd = np.asarray(p.background_freq_hz), np.asarray(p.background_psd)
    near = np.abs(f - f_n) <= 5 * zeta * f_n
    assert math.sqrt(psd[near].mean() / truth(f[near]).mean()) == pytest.approx(1.0, abs=0.2)
    assert p.background_rms == pytest.approx(math.sqrt(np.trapezoid(truth(f), f)), rel=0.2)
    assert "samples of every period" in p.background_source
    assert "background" not in p.not_identified


def test_not_identified_round_trips_and_defaults_to_empty():
    x, _ = _train(3000.0, 0.03, 1.2, 0.3, seconds=3.0)
    p = identify_path(x, FS, RATES)
    assert TransferPath.from_dict(json.loads(p.to_json())) == p
    d = p.to_dict()
    del d["not_identified"]  # a path written before it was reported
    assert TransferPath.from_dict(d).not_identified == []


@pytest.mark.parametrize("f_n, zeta, amplitude, noise", [(3000.0, 0.05, 1.0, 0.05),
                                                         (2660.0, 0.05, 1.0, 0.05),
                                                         (2660.0, 0.05, 2.4, 0.2),
                                                         (3000.0, 0.03, 2.4, 0.2)])
def test_gain_at_full_detection_is_unbiased(f_n, zeta, amplitude, noise):
    """Every event stands out; each starts between two samples (the record's clock knows
    nothing of the impulses). Read off the averaged decay aligned on its peak, the amplitude
    rested on where the events start, and the gain read 5-13 % low at zeta 0.05 (3-4 % at
    0.03) whatever the noise; from the events' energy it is within 5 %, and zeta within 10 %."""
    x, gain = _train(f_n, zeta, amplitude, noise, seconds=8.0, seed=1)
    p = identify_path(x, FS, RATES)
    assert p.n_events > 0.95 * p.n_periods
    assert p.zeta == pytest.approx(zeta, rel=0.1)
    assert p.mode(1e-3).gain == pytest.approx(gain, rel=0.05)
    assert not {"zeta", "gain"} & set(p.not_identified)


def test_gain_is_not_identified_where_zeta_is_not():
    """The events' energy fixes ``gain^2 zeta``: a zeta not identified (its subsets disagree
    by 20 %) leaves the gain unidentified however well the subsets agree on it (at 2.5 %
    detection, zeta 0.05 read -34 % and flagged, the gain +32 % without a flag)."""
    band, f_n, period = (2000.0, 3300.0), 2660.0, 112.0
    _, unknown = identification_flags(band, f_n, 0.05, (0.045, 0.055), (0.2, 0.01), 50, period, None)
    assert unknown == ["zeta", "gain"]
    flags, unknown = identification_flags(band, f_n, 0.05, (0.045, 0.055), (0.01, 0.01), 50, period, None)
    assert unknown == [] and flags == []


# ------------------------------------ issue 43: events ringing into the next one, in phase
def _periodic_train(rate, f_n, zeta, amplitude, noise, jitter, seconds=6.0, seed=3):
    """Impulses at ``rate`` Hz (each time jittered by ``jitter`` of a period, not
    accumulated) ringing the analytic resonator, plus white noise; the record and the gain."""
    rng = np.random.default_rng(seed)
    times = np.arange(0.004, seconds - 0.004, 1 / rate)
    times = times + jitter / rate * rng.standard_normal(times.size)
    gain = amplitude / (1e-3 * 2 * zeta * 2 * math.pi * f_n)
    n = int(seconds * FS)
    return _ringing(n, FS, times, 1e-3, f_n, zeta, gain) + noise * rng.standard_normal(n), gain


@pytest.mark.parametrize("rate, f_n, zeta", [(190.0, 2660.0, 0.015), (230.0, 2660.0, 0.03)])
def test_events_ringing_into_the_next_in_phase_are_not_a_confident_answer(rate, f_n, zeta):
    """Events periodic to 0.3 % of a period meet the previous one's ringing (22-30 % of its
    amplitude at zeta 0.015, 11 % at 0.03) nearly in phase; the model adds it in power.
    Before, zeta read +12 % (190 Hz, zeta 0.015) and the gain -11 % (230 Hz, zeta 0.03), not
    flagged: each is now within 10 % or listed as not identified, the flag naming why."""
    x, gain = _periodic_train(rate, f_n, zeta, 2.4, 0.2, jitter=0.003)
    p = identify_path(x, FS, {k: v * rate / 107.0 for k, v in RATES.items()})
    for name, got, true in (("zeta", p.zeta, zeta), ("gain", p.mode(1e-3).gain, gain)):
        assert abs(got / true - 1) <= 0.1 or name in p.not_identified, (name, got, true)
    assert "gain" in p.not_identified
    assert any("in phase from event to event" in f for f in p.flags)


def test_overlap_flags_need_both_ringing_left_and_coherent_phases():
    """The bound on what ringing in phase moves (``sqrt((1 + r)/(1 - r)) - 1``, 0.36 at r
    0.3): coherent, it takes zeta and the gain; with independent phases (coherence 0.05:
    a bearing's slip) or little ringing left (r 0.02), neither."""
    band, f_n, period = (2000.0, 3300.0), 2660.0, 63.0
    args = (band, f_n, 0.015, (0.0149, 0.0151), (0.01, 0.01), 50, period, None)
    _, unknown = identification_flags(*args, coherent_tail=(0.3, 0.8))
    assert unknown == ["zeta", "gain"]
    assert identification_flags(*args, coherent_tail=(0.3, 0.05)) == ([], [])
    assert identification_flags(*args, coherent_tail=(0.02, 0.9)) == ([], [])
    # the gain carries zeta's share too: twice the bound (u = 0.9 x 0.062 = 0.056)
    _, unknown = identification_flags(*args, coherent_tail=(0.06, 0.9))
    assert unknown == ["gain"]
