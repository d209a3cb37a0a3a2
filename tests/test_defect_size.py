"""Defect length from the entry-exit spacing (diagnosis.defect_size), against records whose
spacing is known by construction: a structure's resonances excited by a negative force step at
each pit entry and an impulse (with the load's return) at each exit, the spacing set, at the
event rate with jitter, in white noise."""

import math

import numpy as np
import pytest

from bearing_envelope.diagnosis.defect_size import (ESTIMATED, NO_EVENTS, NOT_RESOLVABLE,
                                                    defect_length, entry_exit_spacing,
                                                    record_scene)

RATE = 107.36           # BPFO of the 6205 at 1797 rpm, Hz
MODES = ((3500.0, 0.05), (9000.0, 0.04))   # (f_n Hz, zeta): what the step and impulse ring


def _mode(t, fn, zeta, kind):
    """Acceleration of a unit-mass mode after a unit force step (``step``) or impulse at t=0."""
    w = 2 * np.pi * fn
    wd = w * math.sqrt(1 - zeta**2)
    decay = np.exp(-zeta * w * t) * (t >= 0)
    return decay * (np.cos(wd * t) if kind == "step" else np.sin(wd * t))


def pit_record(fs, dt_s, *, duration_s=3.0, noise=0.05, jitter=0.01, entry=0.5, present=1.0,
               seed=1, modes=MODES):
    """A record with events at RATE (period jitter ``jitter``, r.m.s.), each an entry step of
    ``-entry`` and, ``dt_s`` later (1 % r.m.s. jitter), an impulse of unit ringing amplitude with
    the load's return; a fraction ``present`` of the periods hold an event; white noise of
    r.m.s. ``noise``."""
    rng = np.random.default_rng(seed)
    n = int(duration_s * fs)
    x = noise * rng.standard_normal(n)
    periods = (1 + jitter * rng.standard_normal(int(duration_s * RATE) + 2)) / RATE
    ring = int(0.004 * fs)
    for tx in np.cumsum(periods)[:-1]:
        if rng.random() > present:
            continue
        te = tx - dt_s * (1 + 0.01 * rng.standard_normal())
        i0 = int(te * fs)
        if i0 < 0 or i0 + ring > n:
            continue
        t = np.arange(i0, i0 + ring) / fs
        for fn, z in modes:
            x[i0:i0 + ring] += (-entry * _mode(t - te, fn, z, "step")
                                + entry * _mode(t - tx, fn, z, "step")
                                + _mode(t - tx, fn, z, "impulse"))
    return x


@pytest.mark.parametrize("dt_us", [101.0, 202.0, 303.0])
@pytest.mark.parametrize("noise", [0.02, 0.1])
def test_spacing_recovered_within_interval_at_48k(dt_us, noise):
    """The CWRU pits' crossing times (0.007 / 0.014 / 0.021 in at 1797 rpm) at 48 kHz, two noise
    levels (exit ringing 50x and 10x the noise r.m.s.): the set spacing lies in the interval."""
    s = entry_exit_spacing(pit_record(48000.0, dt_us * 1e-6, noise=noise), 48000.0, RATE)
    assert s.status == ESTIMATED
    lo, hi = s.interval_s
    assert lo <= dt_us * 1e-6 <= hi
    assert hi - lo < 0.3 * dt_us * 1e-6 + 2 / 48000.0   # narrow enough to rank the three


def test_lengths_rank_pit_sizes():
    """Three spacings give three lengths in the same order, intervals apart, ``v dt`` in mm."""
    scene = record_scene("6205", 29.95, "outer_race")
    got = [defect_length(pit_record(48000.0, dt, seed=3), 48000.0, scene, event_rate_hz=RATE)
           for dt in (101e-6, 202e-6, 303e-6)]
    assert all(g.status == ESTIMATED for g in got)
    lengths = [g.length_mm for g in got]
    assert lengths == sorted(lengths)
    assert got[0].interval_mm[1] < got[1].interval_mm[0] < got[1].interval_mm[1] < \
        got[2].interval_mm[0]
    # v = 2 pi f_c R_o = 1.761 m/s (docs/dynamics.md scales table): 303 us -> 0.533 mm
    assert got[2].speed_m_s == pytest.approx(1.761, abs=1e-3)
    assert got[2].interval_mm[0] <= 1.761 * 0.303 <= got[2].interval_mm[1]


@pytest.mark.parametrize("dt_us", [101.0, 202.0])
def test_short_spacing_at_12k_not_resolvable(dt_us):
    """101 and 202 us are 1.2 and 2.4 samples at 12 kHz, below the 3-sample lag floor: a
    status, no number."""
    s = entry_exit_spacing(pit_record(12000.0, dt_us * 1e-6, noise=0.02), 12000.0, RATE)
    assert s.status == NOT_RESOLVABLE
    assert s.dt_s is None and s.interval_s is None
    assert s.n_events > 0.9 * s.n_periods          # the events are there
    assert s.min_dt_s >= 3 / 12000.0 > dt_us * 1e-6


@pytest.mark.parametrize("dt_us", [101.0, 202.0, 303.0])
def test_loud_noise_never_a_wrong_interval(dt_us):
    """Noise r.m.s. 0.3 of the exit's ringing (a third of the periods lose their event): an
    estimate, where one is given, holds the set spacing."""
    s = entry_exit_spacing(pit_record(48000.0, dt_us * 1e-6, noise=0.3), 48000.0, RATE)
    assert s.status in (ESTIMATED, NOT_RESOLVABLE)
    if s.status == ESTIMATED:
        assert s.interval_s[0] <= dt_us * 1e-6 <= s.interval_s[1]


@pytest.mark.parametrize("noise", [0.02, 0.1])
def test_exit_alone_gives_no_length(noise):
    """The control: impacts with no entry step. Nothing precedes the exit but the whitening's
    residual (about 1 % of the peak), under the 5 % an entry must carry."""
    s = entry_exit_spacing(pit_record(48000.0, 101e-6, noise=noise, entry=0.0), 48000.0, RATE)
    assert s.status == NOT_RESOLVABLE and s.dt_s is None


def test_long_spacing_at_12k_resolved_with_a_wide_interval():
    """303 us = 3.6 samples at 12 kHz: read, its interval at least a sample wide."""
    s = entry_exit_spacing(pit_record(12000.0, 303e-6, noise=0.02), 12000.0, RATE)
    assert s.status == ESTIMATED
    lo, hi = s.interval_s
    assert lo <= 303e-6 <= hi and hi - lo >= 1 / 12000.0


def test_partial_detection_estimates_from_the_events_present():
    """A third of the periods hold an event: counted as such, the spacing still recovered."""
    s = entry_exit_spacing(pit_record(48000.0, 202e-6, noise=0.05, present=0.35), 48000.0,
                           RATE)
    assert s.status == ESTIMATED
    assert 0.2 * s.n_periods < s.n_events < 0.5 * s.n_periods
    assert s.interval_s[0] <= 202e-6 <= s.interval_s[1]


@pytest.mark.parametrize("fs", [12000.0, 48000.0])
def test_pure_noise_gives_no_estimate(fs):
    x = np.random.default_rng(7).standard_normal(int(3 * fs))
    res = defect_length(x, fs, record_scene("6205", 29.95, "outer_race"))
    assert res.status == NO_EVENTS
    assert res.length_mm is None and res.interval_mm is None
    assert "no events" in res.summary()


def test_summary_and_dict():
    scene = record_scene("6205", 29.95, "outer_race")
    res = defect_length(pit_record(48000.0, 202e-6), 48000.0, scene, event_rate_hz=RATE)
    d = res.to_dict()
    assert d["status"] == ESTIMATED and d["interval_mm"][0] <= d["length_mm"] <= \
        d["interval_mm"][1]
    assert "defect length" in res.summary() and "mm" in res.summary()
    low = defect_length(pit_record(12000.0, 101e-6), 12000.0, scene, event_rate_hz=RATE)
    assert NOT_RESOLVABLE in low.summary() and "shortest resolvable" in low.summary()


@pytest.mark.parametrize("kwargs, match", [
    (dict(x=np.zeros(48000)), "constant"),
    (dict(x=np.ones((2, 100))), "x"),
    (dict(x=np.r_[np.nan, np.ones(47999)]), "x"),
    (dict(fs=-1.0), "fs"),
    (dict(event_rate_hz=30000.0), "event_rate_hz"),
    (dict(event_rate_hz=0.0), "event_rate_hz"),
    (dict(x=np.random.default_rng(0).standard_normal(2000)), "periods"),
    (dict(band=(0.0, 5000.0)), "band"),
    (dict(band=(1000.0, 30000.0)), "band"),
    (dict(band="wide"), "band"),
    (dict(max_lag_s=1.0), "max_lag_s"),
])
def test_bad_input_refused_in_one_line(kwargs, match):
    args = dict(x=np.random.default_rng(0).standard_normal(48000), fs=48000.0,
                event_rate_hz=RATE)
    args.update(kwargs)
    x, fs, rate = args.pop("x"), args.pop("fs"), args.pop("event_rate_hz")
    with pytest.raises(ValueError, match=match) as exc:
        entry_exit_spacing(x, fs, rate, **args)
    assert "\n" not in str(exc.value)


def test_analyze_reports_the_length(tmp_path, capsys):
    """``bearing-envelope analyze`` on a record of known spacing: the diagnosed family's length
    printed and in the JSON, the truth (v dt) inside its interval; at 12 kHz for a short
    spacing the status instead of a number."""
    import json

    from bearing_envelope.cli import main

    for fs, dt, status in ((48000.0, 202e-6, ESTIMATED), (12000.0, 101e-6, NOT_RESOLVABLE)):
        f = tmp_path / f"pit_{int(fs)}.npz"
        np.savez(f, x=pit_record(fs, dt, duration_s=1.0), fs=fs)
        out = tmp_path / f"pit_{int(fs)}.json"
        assert main(["analyze", str(f), "--fr", "29.95", "--bearing", "6205", "--speed",
                     "nominal", "--routes", "envelope", "--nlevel", "4", "--json", str(out)]) == 0
        printed = capsys.readouterr().out
        assert "defect length (entry-exit spacing, docs/analysis.md): outer_race defect length" \
            in printed
        size = json.loads(out.read_text())["defect_size"]
        assert size["status"] == status
        if status == ESTIMATED:
            lo, hi = size["interval_mm"]
            assert lo <= 1e3 * size["speed_m_s"] * dt <= hi
        else:
            assert size["length_mm"] is None and size["min_length_mm"] > 1e3 * 1.761 * dt


def test_a_batch_reports_each_records_length(tmp_path, capsys):
    """``analyze`` on several records (the batch path, worker processes): each record's length
    or status in its JSON entry and printed under it, the same as one record alone; the
    truth (v dt) inside the interval of the resolvable one."""
    import json

    from bearing_envelope.cli import main

    files = []
    for fs, dt in ((48000.0, 202e-6), (12000.0, 101e-6)):
        f = tmp_path / f"pit_{int(fs)}.npz"
        np.savez(f, x=pit_record(fs, dt, duration_s=1.0), fs=fs)
        files.append(str(f))
    out = tmp_path / "batch.json"
    assert main(["analyze", *files, "--fr", "29.95", "--bearing", "6205", "--speed", "nominal",
                 "--routes", "envelope", "--nlevel", "4", "--jobs", "1", "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert printed.count("defect length (entry-exit spacing): outer_race defect length") == 2
    recs = json.loads(out.read_text())["records"]
    assert [r["defect_size"]["status"] for r in recs] == [ESTIMATED, NOT_RESOLVABLE]
    lo, hi = recs[0]["defect_size"]["interval_mm"]
    assert lo <= 1e3 * recs[0]["defect_size"]["speed_m_s"] * 202e-6 <= hi
