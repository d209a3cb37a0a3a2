"""The routes of the verdict (diagnosis.routes): the rule that combines them, on spectra whose
lines are placed by construction, and every route on a synthetic outer-race record."""

import numpy as np
import pytest

from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal, fault_families
from bearing_envelope.diagnosis.routes import (RouteResult, combine_routes, random_part,
                                               route_name, route_spectrum, route_verdict,
                                               run_routes, spectra_verdict)
from bearing_envelope.signal.separation import discrete_random_separation

FR = 29.95
FREQS = {"bpfo": 107.36, "bpfi": 162.19, "ftf": 11.93, "bsf": 70.58}
FAMS = fault_families(FREQS, fr=FR)
SEARCH = {"search_percent": 0.5, "tolerance_hz": None, "min_search_bins": 2.0}


def _spectrum(lines, seed):
    """A Rayleigh noise floor (unit scale, 0.1 Hz bins to 1 kHz) with lines ``{Hz: amp}``."""
    f = np.arange(0.0, 1000.0, 0.1)
    a = np.random.default_rng(seed).rayleigh(1.0, f.size)
    for hz, amp in lines.items():
        a[int(round(hz / 0.1))] = amp
    return f, a


def _result(route, lines, seed):
    f, a = _spectrum(lines, seed)
    v = route_verdict(route, f, a, (0.0, 6000.0), FAMS, fr=FR, search=SEARCH, n_harmonics=3,
                      n_sidebands=1, pfa=0.01)
    return RouteResult(route, v, route_name(v), (0.0, 6000.0))


def _train(f0, amp, k=3):
    return {i * f0: amp for i in range(1, k + 1)}


def test_one_route_alone_names_a_family_and_nothing_else():
    r = _result("cpw", _train(2 * FREQS["bsf"], 40.0), 0)
    assert r.named == ("bsf2",)
    quiet = _result("ees", {}, 1)
    assert quiet.named == () and quiet.verdict.confidence is None


def test_routes_raise_a_ball_the_envelope_misses():
    # envelope: a weak BPFI series and a weak 2xBSF (one band, both low: cannot tell); two
    # other routes name 2xBSF: the ball is found by three routes, BPFI by one -> ball at
    # medium, by the routes
    env = _result("envelope", {**_train(FREQS["bpfi"], 9.0), **_train(2 * FREQS["bsf"], 8.0)}, 2)
    assert env.verdict.confidence == "cannot tell"
    res = {"envelope": env, "cpw": _result("cpw", _train(2 * FREQS["bsf"], 40.0), 3),
           "ees": _result("ees", _train(2 * FREQS["bsf"], 30.0), 4)}
    v = combine_routes(res)
    assert (v.diagnosis, v.confidence, v.decided_by) == ("bsf2", "medium", "routes")
    assert set(v.support["ball"]) == {"envelope", "cpw", "ees"}
    assert any("names 2xBSF" in e for e in v.evidence)
    # a race family is not raised by the routes (raises=("ball",)), only when asked
    res_i = {"envelope": env, "cpw": _result("cpw", _train(FREQS["bpfi"], 40.0), 5),
             "ees": _result("ees", _train(FREQS["bpfi"], 40.0), 6)}
    assert combine_routes(res_i).confidence == "cannot tell"
    assert combine_routes(res_i, raises=("bpfi",)).diagnosis == "bpfi"


def test_a_single_route_does_not_make_high_nor_raise():
    env = _result("envelope", _train(FREQS["bpfi"], 9.0), 7)
    res = {"envelope": env, "cpw": _result("cpw", _train(2 * FREQS["bsf"], 40.0), 8),
           "ees": _result("ees", {}, 9)}
    v = combine_routes(res)  # ball found by cpw alone: the envelope's verdict stands
    assert (v.diagnosis, v.confidence, v.decided_by) == ("bpfi", "low", "envelope")
    with pytest.raises(ValueError, match="envelope"):
        combine_routes({"cpw": res["cpw"]})


def _outer_race_record(seed=0, fs=12000.0, n=2**17):
    """Decaying 3.5 kHz bursts at BPFO with a 0.5 % jitter in unit noise, plus shaft tones."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    x = 0.5 * rng.standard_normal(n) + 2.0 * np.sin(2 * np.pi * FR * t)
    tt = np.arange(80) / fs
    burst = 3.0 * np.exp(-tt / 1.5e-3) * np.sin(2 * np.pi * 3500.0 * tt)
    starts = np.cumsum(fs / FREQS["bpfo"] * (1 + 0.005 * rng.standard_normal(3000))).astype(int)
    for i in starts[starts < n - tt.size]:
        x[i:i + tt.size] += burst
    return x, fs


def test_every_route_names_the_outer_race_of_a_synthetic_record():
    x, fs = _outer_race_record()
    _, det = analyze_signal(x, fs, fr=FR, fault_frequencies=FREQS,
                            options=AnalysisOptions(n_harmonics=3), full_output=True)
    res = run_routes(x, fs, det)
    for r in ("envelope", "cpw", "drs_sk", "ees"):
        assert res[r].named == ("bpfo",), r
    v = combine_routes(res)
    assert v.diagnosis == "bpfo" and v.confidence in ("high", "medium")
    with pytest.raises(ValueError, match="routes"):
        run_routes(x, fs, det, ("nope",))


def test_infogram_routes_demodulate_the_repeating_band():
    # not default routes (measured, not kept): on request, the spectral infogram's band of the
    # record (info) and of its random part (drs_info) holds the 3.5 kHz bursts at BPFO
    x, fs = _outer_race_record()
    _, det = analyze_signal(x, fs, fr=FR, fault_frequencies=FREQS,
                            options=AnalysisOptions(n_harmonics=3), full_output=True)
    res = run_routes(x, fs, det, ("envelope", "drs_info", "info"))
    for r in ("drs_info", "info"):
        lo, hi = res[r].band
        assert lo <= 3500.0 <= hi and hi - lo >= 2 * 3 * FREQS["bpfi"], (r, res[r].band)
        assert res[r].named == ("bpfo",), r
    assert "drs_info" not in run_routes(x, fs, det)


def test_ball_named_by_2xbsf_or_bsf_with_cage_sidebands_never_by_the_cage():
    bsf, ftf = FREQS["bsf"], FREQS["ftf"]
    cage = _result("cpw", _train(ftf, 40.0, k=4), 10)
    assert cage.named == ()                      # the cage rate alone names nothing
    plain = _result("cpw", _train(bsf, 40.0), 11)
    assert "bsf" not in plain.named              # BSF without its FTF sidebands: not a name
    lines = {**_train(bsf, 40.0),
             **{k * bsf + m * ftf: 25.0 for k in (1, 2, 3) for m in (-1, 1)}}
    assert "bsf" in _result("cpw", lines, 12).named
    # cage lines in every route do not raise anything
    env = _result("envelope", _train(ftf, 30.0, k=4), 13)
    ees = _result("ees", _train(ftf, 30.0, k=4), 14)
    v = combine_routes({"envelope": env, "cpw": cage, "ees": ees})
    assert v.decided_by == "envelope" and v.diagnosis is None


def test_high_needs_a_second_route():
    # BPFO in three distinct envelope bands, 30 dB lines: high on its own; with no other route
    # finding it the verdict is medium, with one it stays high
    spectra = {}
    for i, name in enumerate(("a", "b", "c")):
        f, a = _spectrum(_train(FREQS["bpfo"], 60.0), 20 + i)
        spectra[name] = ((1000.0 * i, 1000.0 * (i + 1)), f, a)
    env_v = spectra_verdict(spectra, FAMS, fr=FR, search=SEARCH, n_harmonics=3, n_sidebands=1,
                     pfa=0.01)
    assert env_v.confidence == "high" and env_v.diagnosis.family == "bpfo"
    env = RouteResult("envelope", env_v, route_name(env_v), (0.0, 6000.0))
    alone = combine_routes({"envelope": env, "cpw": _result("cpw", {}, 30)})
    assert (alone.confidence, alone.decided_by) == ("medium",
                                                    "envelope, high needs a second route")
    both = combine_routes({"envelope": env,
                           "cpw": _result("cpw", _train(FREQS["bpfo"], 40.0), 31)})
    assert (both.diagnosis, both.confidence, both.decided_by) == ("bpfo", "high", "envelope")


def test_ees_reads_the_random_part_not_a_periodic_modulation():
    # the outer-race record plus a strictly periodic 2 kHz carrier pulsed at the BPFI rate (a
    # deterministic component, lines at 2000 +- k BPFI Hz, as a gear mesh's): its power
    # repeats at BPFI, so the coherence of the record itself names BPFI beside BPFO; the EES
    # route reads the random part, where the carrier is gone and the bursts at BPFO remain
    x, fs = _outer_race_record(seed=3)
    t = np.arange(x.size) / fs
    pulse = np.exp(2.0 * (np.cos(2 * np.pi * FREQS["bpfi"] * t) - 1.0))
    x = x + pulse * np.sin(2 * np.pi * 2000.0 * t)
    search = {"search_percent": 0.5, "tolerance_hz": None, "min_search_bins": 2.0}

    def named(random):
        f, a, band = route_spectrum("ees", x, fs, alpha_max_hz=800.0, min_bandwidth=1000.0,
                                    random=random)
        v = route_verdict("ees", f, a, band, FAMS, fr=FR, search=search, n_harmonics=3,
                          n_sidebands=1, pfa=0.01)
        return route_name(v)

    assert named(x) == ("bpfo", "bpfi")           # the record's own coherence
    assert named(None) == ("bpfo",)               # its random part
    _, rnd = discrete_random_separation(x, fs)
    assert np.allclose(random_part(x, fs), rnd)
    _, det = analyze_signal(x, fs, fr=FR, fault_frequencies=FREQS,
                            options=AnalysisOptions(n_harmonics=3), full_output=True)
    assert run_routes(x, fs, det, ("envelope", "ees"))["ees"].named == ("bpfo",)
