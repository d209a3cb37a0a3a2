"""Cycle-synchronous averages against trains whose rate, width and element levels are known by
construction (a wrapped Gaussian's circular standard deviation is its own sigma, and its
Fourier coefficients fall as exp(-(2 pi k sigma)^2 / 2))."""

import math

import numpy as np
import pytest

from bearing_envelope.signal.cycles import (
    burst_width, cycle_rate, element_levels, synchronous_average)
from bearing_envelope.study.rig.events import (MIN_CONTRAST_DB, SECONDARY_MIN_CONTRAST_DB,
                                               event_shape)

FS = 12000.0
RATE = 107.3          # Hz: 111.84 samples per cycle, not an integer
DURATION = 10.0


def _train(sigma_s, amplitudes=(1.0,), rate=RATE, fs=FS, duration=DURATION, noise=0.0,
           seed=0):
    """Sum of Gaussian bursts (peak a_j, r.m.s. width sigma_s) at ``rate``, a_j cycling over
    the elements, plus white noise of standard deviation ``noise``."""
    t = np.arange(int(duration * fs)) / fs
    k = np.round(t * rate)
    amp = np.asarray(amplitudes)[k.astype(int) % len(amplitudes)]
    g = amp * np.exp(-0.5 * ((t - k / rate) / sigma_s) ** 2)
    return g + noise * np.random.default_rng(seed).standard_normal(t.size)


def test_rate_refined_to_far_below_the_resolution():
    x = _train(0.5e-3, noise=0.3)
    f = cycle_rate(x, FS, 106.5)            # nominal 0.75 % off
    assert abs(f - RATE) < 2e-3            # resolution 1/T = 0.1 Hz


def _cut_gaussian_sd(c=None):
    """R.m.s. width, in sigmas, of a Gaussian cut where it falls to a tenth of its peak."""
    c = math.sqrt(2 * math.log(10.0)) if c is None else c
    phi = math.exp(-c * c / 2) / math.sqrt(2 * math.pi)
    return math.sqrt(1 - 2 * c * phi / math.erf(c / math.sqrt(2)))


def test_width_of_a_gaussian_burst_is_its_sigma():
    assert _cut_gaussian_sd() == pytest.approx(0.907, abs=1e-3)
    for sigma in (0.3e-3, 1.0e-3):
        avg = synchronous_average(_train(sigma, noise=0.2), FS, RATE, bins=100)
        assert burst_width(avg) / RATE == pytest.approx(_cut_gaussian_sd() * sigma, rel=0.05)


def test_average_holds_the_burst_at_its_phase():
    avg = synchronous_average(_train(0.5e-3), FS, RATE, bins=100)
    # burst centred on t = k / rate: phase 0 (bins at the two ends of the cycle)
    assert np.argmax(avg) in (0, 99)
    assert avg.max() == pytest.approx(1.0, rel=0.05)


def test_element_levels_and_their_order():
    a = np.array([1.0, 0.2, 0.5, 3.0, 0.8, 1.5, 0.4, 2.0, 0.1])
    x = _train(0.6e-3, amplitudes=a, noise=0.05)
    avg = synchronous_average(x, FS, RATE / 9, bins=360)
    lv = element_levels(avg, 9)
    # each event's area: a_j sigma sqrt(2 pi) seconds, in bins of the cage's period
    area = np.roll(a, -int(np.argmax(a))) * 0.6e-3 * math.sqrt(2 * math.pi) * RATE / 9 * 360
    np.testing.assert_allclose(lv, area, rtol=0.03, atol=0.02 * area.max())


def test_event_shape_of_a_record_rolls_off_as_the_gaussian_says():
    sigma = 1.0e-3                       # of the squared envelope's burst
    t = np.arange(int(DURATION * FS)) / FS
    a = np.array([1.0, 0.5, 2.0, 1.0, 1.0, 0.25, 1.0, 1.0, 1.0])   # power per element
    g = _train(sigma, amplitudes=a)
    x = np.sqrt(g) * np.cos(2 * np.pi * 3600.0 * t)
    x += 0.02 * np.random.default_rng(1).standard_normal(t.size)
    r = event_shape(x, FS, 106.8, n_elements=9, band=(3000.0, 4500.0))
    assert r["rate_hz"] == pytest.approx(RATE, abs=2e-3)
    assert r["width_ms"] == pytest.approx(1e3 * sigma * _cut_gaussian_sd(), rel=0.1)
    s2 = (2 * math.pi * sigma * RATE) ** 2
    assert r["h2_db"] == pytest.approx(20 * np.log10(math.exp(-s2 * 3 / 2)), abs=0.5)
    assert r["h3_db"] == pytest.approx(20 * np.log10(math.exp(-s2 * 8 / 2)), abs=0.7)
    assert r["element_spread_db"] == pytest.approx(10 * np.log10(2.0 / 0.25), abs=0.5)


def test_noise_alone_gives_no_event():
    x = np.random.default_rng(2).standard_normal(int(DURATION * FS))
    r = event_shape(x, FS, RATE, n_elements=9)
    assert r["contrast_db"] < MIN_CONTRAST_DB
    assert math.isnan(r["width_ms"]) and math.isnan(r["element_spread_db"])


@pytest.mark.parametrize("kwargs, match", [
    ({"rate_hz": 7000.0}, "rate_hz: got 7000.0; allowed: a rate in"),
    ({"rate_hz": 0.5}, "rate_hz: the record holds 5.0 cycles"),
    ({"rate_hz": RATE, "bins": 500}, "bins: got 500; allowed"),
])
def test_bad_input_one_line(kwargs, match):
    x = np.ones(int(DURATION * FS))
    with pytest.raises(ValueError, match=match):
        synchronous_average(x, FS, **kwargs)


def test_bad_element_count():
    with pytest.raises(ValueError, match="n_elements: got 1; allowed"):
        element_levels(np.arange(20.0), 1)


def test_secondary_events_counted_per_element():
    """Each passage a main burst and, 1.6 ms later, one of half its height: one secondary
    event per element; without it none."""
    t = np.arange(int(DURATION * FS)) / FS
    carrier = np.cos(2 * np.pi * 3600.0 * t)
    main = _train(0.2e-3)
    later = np.roll(main, int(round(1.6e-3 * FS)))
    noise = 0.01 * np.random.default_rng(3).standard_normal(t.size)
    for g, want in ((main, 0.0), (main + 0.5 * later, 1.0)):
        r = event_shape(np.sqrt(g) * carrier + noise, FS, RATE, n_elements=9,
                        band=(3000.0, 4500.0))
        assert r["secondary_events"] == want


def test_secondary_events_not_read_from_a_weak_fold():
    """A burst train barely over its noise (contrast between 3 and 6 dB): its width is read,
    its secondary events are not (the floor's wiggles would count)."""
    t = np.arange(int(DURATION * FS)) / FS
    g = _train(0.3e-3)
    x = np.sqrt(g) * np.cos(2 * np.pi * 3600.0 * t)
    x += 1.0 * np.random.default_rng(4).standard_normal(t.size)
    r = event_shape(x, FS, RATE, n_elements=9, band=(3000.0, 4500.0))
    assert MIN_CONTRAST_DB <= r["contrast_db"] < SECONDARY_MIN_CONTRAST_DB
    assert math.isfinite(r["width_ms"]) and math.isnan(r["secondary_events"])


@pytest.mark.parametrize("kwargs, match", [
    ({"fs": -1.0, "rate_hz": RATE}, "fs"),
    ({"fs": FS, "rate_hz": RATE, "band": (5000.0, 7000.0)}, "band"),
])
def test_event_shape_refuses_bad_input_in_one_line(kwargs, match):
    with pytest.raises(ValueError, match=match):
        event_shape(np.ones(int(DURATION * FS)), **kwargs)
