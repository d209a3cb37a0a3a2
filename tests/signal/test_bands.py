import numpy as np
import pytest
import yaml

from bearing_envelope.signal import (
    DEFAULT_BANDS,
    NYQUIST_MARGIN,
    band_fixed,
    band_fraction,
    band_orders,
    fast_kurtogram,
    resolve_band,
)
from conftest import fault_signal

FREQS = {"fr": 15.8, "bpfi": 231.9}


def test_fraction_default_fs4_3fs8():
    band, prov = band_fraction(65000.0)
    assert band == (16250.0, 24375.0)
    assert prov["strategy"] == "fraction" and not prov["clamped"]


def test_orders_3_6_and_10_13_bpfi():
    (lo, hi), prov = band_orders(231.9, 10, 13, 65000.0, base_name="bpfi")
    assert (lo, hi) == pytest.approx((2319.0, 3014.7))
    assert prov["base"] == "bpfi" and prov["base_hz"] == 231.9
    band, _ = resolve_band({"name": "b", "strategy": "orders", "low": 3, "high": 6,
                            "base": "bpfi"}, 65000.0, frequencies=FREQS)
    assert band == pytest.approx((695.7, 1391.4))
    band, _ = resolve_band({"strategy": "orders", "low": 3, "high": 6, "base": 100.0}, 65000.0)
    assert band == (300.0, 600.0)


def test_fixed():
    band, prov = band_fixed(5000, 9000, 65000.0)
    assert band == (5000.0, 9000.0) and prov == {"strategy": "fixed", "clamped": False,
                                                 "requested_high_hz": 9000.0}


def test_kurtogram_band_clamped_below_nyquist():
    fs = 20000.0
    x = fault_signal(fs=fs, n=2**15, fn=0.49 * fs, damping=1500.0, snr_db=-3.0, tone_ratio=1.0,
                     bpfi=50.0, seed=4)
    kg = fast_kurtogram(x, fs, 6)
    assert kg.band[1] == pytest.approx(fs / 2)  # topmost band ends at Nyquist
    band, prov = resolve_band({"name": "kurtogram", "strategy": "kurtogram"}, fs, kurtogram=kg)
    assert prov["clamped"] is True
    assert prov["requested_high_hz"] == pytest.approx(fs / 2)
    assert band[1] == pytest.approx(NYQUIST_MARGIN * fs / 2) and band[1] < fs / 2
    assert band[0] == pytest.approx(kg.band[0])
    assert prov["level"] == kg.level and prov["kurtosis"] == kg.kurtosis


def test_deep_kurtogram_cell_next_to_nyquist_keeps_its_bandwidth():
    """A deep top cell lies wholly above the clamp: the band keeps its width, ends at the clamp."""
    from dataclasses import replace

    fs = 65000.0
    x = fault_signal(fs=fs, n=2**16, fn=0.495 * fs, damping=800.0, snr_db=10.0, tone_ratio=1.0,
                     bpfi=231.9, seed=1)
    kg = fast_kurtogram(x, fs, 8)
    bw = fs * 2.0 ** -9  # level 8: 63.5 Hz wide
    top_cell = replace(kg, level=8.0, bandwidth=bw, fc=fs / 2 - bw / 2)
    assert top_cell.band[0] > NYQUIST_MARGIN * fs / 2  # nothing left after a plain clamp
    band, prov = resolve_band({"name": "kurtogram", "strategy": "kurtogram"}, fs, kurtogram=top_cell)
    assert band[1] == pytest.approx(NYQUIST_MARGIN * fs / 2)
    assert band[1] - band[0] == pytest.approx(bw)
    assert prov["clamped"] and prov["shifted_from_low_hz"] == pytest.approx(fs / 2 - bw)


def test_explicit_band_above_nyquist_raises_or_clamps():
    with pytest.raises(ValueError, match=r"fixed band: high edge 40000 Hz is at or above the Nyquist"):
        resolve_band({"strategy": "fixed", "low_hz": 20000, "high_hz": 40000}, 65000.0)
    with pytest.raises(ValueError, match=r"orders band \(10 - 150 x bpfi\)"):
        resolve_band({"strategy": "orders", "low": 10, "high": 150, "base": "bpfi"}, 65000.0,
                     frequencies=FREQS)
    with pytest.raises(ValueError, match="fraction band"):
        band_fraction(1000.0, 0.25, 0.6)
    band, prov = resolve_band({"strategy": "fixed", "low_hz": 20000, "high_hz": 40000,
                               "clamp": True}, 65000.0)
    assert band == (20000.0, NYQUIST_MARGIN * 32500.0) and prov["clamped"]


@pytest.mark.parametrize(
    "spec, match",
    [
        ({"strategy": "bogus"}, "strategy must be one of"),
        ({"name": "x", "strategy": "fixed", "low_hz": 1}, "missing key 'high_hz'"),
        ({"strategy": "orders", "low": 3, "high": 6, "base": "bpfo"}, "base 'bpfo' is not a known"),
        ({"strategy": "fixed", "low_hz": 1, "high_hz": 2, "hgih": 3}, "unknown key"),
        ({"strategy": "kurtogram"}, "needs a kurtogram"),
        (["fixed", 1, 2], "must be a mapping"),
    ],
)
def test_bad_specs(spec, match):
    with pytest.raises(ValueError, match=match):
        resolve_band(spec, 1000.0, frequencies=FREQS)


def test_yaml_round_trip_of_band_list():
    """A band list written to YAML and read back is the list written, and resolves to the bands
    its numbers give by hand at fs = 65 kHz; the kurtogram band's guard reaches the kurtogram."""
    written = [
        {"name": "kurtogram", "strategy": "kurtogram", "max_level": 6},
        {"name": "fs4_3fs8", "strategy": "fraction", "low": 0.25, "high": 0.375},
        {"name": "bpfi_3_6", "strategy": "orders", "low": 3, "high": 6, "base": "bpfi"},
        {"name": "fixed", "strategy": "fixed", "low_hz": 5000, "high_hz": 9000},
    ]
    text = yaml.safe_dump({"bands": written + [dict(b) for b in DEFAULT_BANDS]})
    read = yaml.safe_load(text)["bands"]
    assert read[:4] == written and read[4:] == [dict(b) for b in DEFAULT_BANDS]
    fs = 65000.0
    x = fault_signal(fs=fs, n=2**14, fn=0.2 * fs, damping=1500.0, snr_db=0.0, tone_ratio=1.0,
                     bpfi=231.9, seed=3)
    guards = []

    def kurtogram(max_level, min_bandwidth):
        guards.append((max_level, min_bandwidth))
        return fast_kurtogram(x, fs, 6, max_level=max_level, min_bandwidth=min_bandwidth)

    bands = {p["name"]: band for band, p in
             (resolve_band(s, fs, frequencies=FREQS, kurtogram=kurtogram) for s in read[:4])}
    assert guards == [(6, None)]
    assert bands["fs4_3fs8"] == (fs / 4, 3 * fs / 8)
    assert bands["bpfi_3_6"] == pytest.approx((3 * 231.9, 6 * 231.9))
    assert bands["fixed"] == (5000.0, 9000.0)
    lo, hi = bands["kurtogram"]  # a cell of the 1/3-binary grid: width fs / 2^(level + 1)
    level = np.log2(fs / (hi - lo)) - 1
    assert level <= 6 and min(abs(level - k) for k in _kurtogram_levels_up_to(6)) < 1e-9


def _kurtogram_levels_up_to(nlevel):
    """0, 1, 1 + log2(3) - 1, 2, ... nlevel (the rows of Antoni's kurtogram)."""
    return [0.0] + [v for k in range(1, nlevel + 1) for v in (k, k + np.log2(3) - 1)][:-1]
