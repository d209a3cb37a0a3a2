"""Tests of the transfer path (structure filter, SNR, tones, config mapping)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize
from scipy import signal as sps

from bearing_envelope.physics.transfer import (
    Mode,
    NoiseSpec,
    Tone,
    TransferModel,
    apply_structure,
    excitation_from_history,
    impulse_response,
    measure_snr_db,
    mode_sos,
    select_excitation,
    synthesize_acceleration,
)

FS = 20_000.0


def _fit_damped_cosine(h: np.ndarray, fs: float, f0: float, sigma0: float):
    """Least-squares fit of A exp(-sigma t) cos(2 pi f t + phi) to h[1:], returns (f, sigma)."""
    n = np.arange(1, h.size)
    t = n / fs
    y = h[1:]

    def model(t, A, sigma, f, phi):
        return A * np.exp(-sigma * t) * np.cos(2 * np.pi * f * t + phi)

    # starting amplitude / phase from a linear fit at the guessed f, sigma
    basis = np.c_[np.exp(-sigma0 * t) * np.cos(2 * np.pi * f0 * t),
                  -np.exp(-sigma0 * t) * np.sin(2 * np.pi * f0 * t)]
    c, *_ = np.linalg.lstsq(basis, y, rcond=None)
    p0 = [math.hypot(*c), sigma0, f0, math.atan2(c[1], c[0])]
    popt, _ = optimize.curve_fit(model, t, y, p0=p0, maxfev=20000)
    return popt[2], popt[1]


@pytest.mark.parametrize("f_n, zeta", [(500.0, 0.01), (3000.0, 0.05), (6000.0, 0.2), (8500.0, 0.02)])
def test_impulse_response_rings_at_fd_with_implied_decay(f_n, zeta):
    mode = Mode(f_n, zeta, 1.0)
    sigma_true = zeta * 2 * math.pi * f_n  # 1/s
    n = int(min(6.0 / sigma_true * FS, 40_000))  # about 6 time constants
    h = impulse_response(TransferModel((mode,)), FS, n)
    # starting guesses perturbed by 5 % so the fit has to find the values
    f_fit, sigma_fit = _fit_damped_cosine(h, FS, 1.05 * mode.f_d_hz, 0.95 * sigma_true)
    assert f_fit == pytest.approx(mode.f_d_hz, rel=0.01)
    assert sigma_fit == pytest.approx(sigma_true, rel=0.01)
    zeta_fit = sigma_fit / math.hypot(sigma_fit, 2 * math.pi * f_fit)
    assert zeta_fit == pytest.approx(zeta, rel=0.01)


def test_log_decrement_of_lightly_damped_mode():
    """Log decrement between positive peaks 10 periods apart: delta = 2 pi zeta / sqrt(1-zeta^2)."""
    mode = Mode(400.0, 0.01, 1.0)
    h = impulse_response((mode,), FS, 20_000)
    peaks, _ = sps.find_peaks(h)
    # parabolic interpolation of each peak's height
    y0, y1, y2 = h[peaks - 1], h[peaks], h[peaks + 1]
    heights = y1 - 0.25 * (y0 - y2) ** 2 / (y0 - 2 * y1 + y2)
    pos = peaks + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
    k = 10
    delta = np.log(heights[:-k] / heights[k:]) / k
    expected = 2 * math.pi * mode.zeta / math.sqrt(1 - mode.zeta**2)
    assert np.median(delta[:30]) == pytest.approx(expected, rel=0.01)
    period = np.median(np.diff(pos[:30])) / FS
    assert 1 / period == pytest.approx(mode.f_d_hz, rel=0.01)


@pytest.mark.parametrize("method", ["impulse", "bilinear"])
def test_poles_inside_unit_circle_and_gain_at_fn(method):
    for f_n in np.linspace(0.002, 0.45, 12) * FS:
        for zeta in np.geomspace(0.001, 0.5, 8):
            sos = mode_sos(Mode(f_n, zeta, 2.5), FS, method)
            assert np.all(np.isfinite(sos))
            poles = np.roots(sos[0, 3:])
            assert np.all(np.abs(poles) < 1.0), (f_n, zeta, np.abs(poles))
            _, hf = sps.sosfreqz(sos, worN=[f_n, 0.0], fs=FS)
            assert abs(hf[0]) == pytest.approx(2.5, rel=1e-9)
            assert abs(hf[1]) < 1e-9  # no DC response (acceleration)
            if method == "impulse":  # poles exactly at exp(s T)
                s = 2 * math.pi * f_n * (-zeta + 1j * math.sqrt(1 - zeta**2))
                assert np.min(np.abs(poles - np.exp(s / FS))) < 1e-9


def test_modes_add_in_parallel():
    modes = (Mode(1000, 0.02, 1.0), Mode(4000, 0.05, 3.0))
    x = np.random.default_rng(0).standard_normal(4000)
    y = apply_structure(x, FS, modes)
    y1 = apply_structure(x, FS, modes[:1])
    y2 = apply_structure(x, FS, modes[1:])
    np.testing.assert_allclose(y, y1 + y2, atol=1e-12)


def _case_like_excitation(n=20_000, fs=FS, fr=15.8, bpfi=231.9, defect=0.05):
    t = np.arange(n) / fs
    base = 1e9 * (1 + 0.3 * np.cos(2 * np.pi * fr * t))
    pulses = np.zeros(n)
    idx = np.round(np.arange(0, n / fs, 1 / bpfi) * fs).astype(int)
    pulses[idx[idx < n]] = 1.0
    pulses = np.convolve(pulses, np.hanning(5), mode="same") * defect * base
    return base + pulses, base


def _sampled_resonator(mode: Mode, fs: float, n: int) -> np.ndarray:
    """Impulse response (``n`` samples) of a mode from its analog definition: the resonator
    ``H(s) = 2 zeta w_n s / (s^2 + 2 zeta w_n s + w_n^2)`` has
    ``h(t) = 2 zeta w_n exp(-sigma t) (cos w_d t - (sigma / w_d) sin w_d t)``; sampled as
    ``T h(nT)`` for ``n >= 1`` (impulse invariance), ``h[0]`` such that the DC gain is zero, as
    the analog one, then scaled to the gain ``|H| = g`` at ``w_n`` (docs/sensor.md)."""
    T, wn, z = 1.0 / fs, 2.0 * math.pi * mode.f_n_hz, mode.zeta
    sigma, wd = z * wn, wn * math.sqrt(1.0 - z * z)
    t = np.arange(n) * T
    h = T * 2.0 * z * wn * np.exp(-sigma * t) * (np.cos(wd * t) - sigma / wd * np.sin(wd * t))
    h[0] = -h[1:].sum()
    gain = abs(np.sum(h * np.exp(-1j * wn * t)))
    return h * (mode.gain / gain)


def _clean_response(x: np.ndarray, modes, n_taps: int = 4000) -> np.ndarray:
    """The noise-free response to ``x`` (per-sample input, as the synthesis filters it): the
    sum of the modes' :func:`_sampled_resonator` responses, by FIR convolution."""
    h = sum(_sampled_resonator(m, FS, n_taps) for m in modes)
    return sps.fftconvolve(x, h)[: x.size]


def test_sampled_resonator_matches_the_modes_response():
    """The test's own resonator against the module's (a cross-check of both: they share no
    code)."""
    for m in (Mode(4000, 0.03, 1e-9), Mode(7000, 0.05, 5e-10), Mode(1000, 0.02, 2.0)):
        mine = _sampled_resonator(m, FS, 8000)
        theirs = impulse_response((m,), FS, 8000) / FS  # its input is a unit-area impulse
        np.testing.assert_allclose(theirs, mine, rtol=0, atol=1e-12 * np.abs(mine).max())


@pytest.mark.parametrize("target", [-20.0, 0.0, 15.0])
@pytest.mark.parametrize("exact", [True, False])
def test_measured_snr_equals_target(target, exact):
    p, base = _case_like_excitation()
    e, ref = excitation_from_history(p), excitation_from_history(base)
    model = TransferModel((Mode(4000, 0.03, 1e-9), Mode(7000, 0.05, 5e-10)),
                          noise=NoiseSpec(target, exact))
    acc, info = synthesize_acceleration(e, FS, model, reference=ref, seed=3)
    # independent measurement: rebuild the clean parts from the analog resonators' impulse
    # responses (FIR convolution; no filter coefficients of the module)
    y = _clean_response(e, model.modes)
    y_ref = _clean_response(ref, model.modes)
    noise = acc - y
    measured = 10 * math.log10(np.var(y - y_ref) / np.var(noise))
    assert measured == pytest.approx(target, abs=0.5)
    assert info["snr_db_achieved"] == pytest.approx(measured, abs=1e-6)
    if exact:
        assert measured == pytest.approx(target, abs=1e-9)
    assert info["snr_db_target"] == target
    assert info["defect_definition"] == "var(H e - H e_ref)"
    # the noise is white: its Welch PSD is flat at 2 var / fs
    f, psd = sps.welch(noise, fs=FS, nperseg=1024)
    inner = (f > 500) & (f < 9500)
    assert np.mean(psd[inner]) == pytest.approx(2 * np.var(noise) / FS, rel=0.05)


def test_snr_without_reference_uses_response_variance():
    e = np.random.default_rng(1).standard_normal(10_000)
    model = TransferModel((Mode(2000, 0.05),), noise=NoiseSpec(6.0))
    acc, info = synthesize_acceleration(e, FS, model, seed=0)
    y = _clean_response(e, model.modes)  # independent of the module's filters
    assert info["defect_definition"] == "var(H e)"
    assert 10 * math.log10(np.var(y) / np.var(acc - y)) == pytest.approx(6.0, abs=1e-9)
    assert measure_snr_db(y, acc - y) == pytest.approx(6.0, abs=1e-9)
    assert info["p_defect"] == pytest.approx(np.var(y), rel=1e-12)


def test_seeded_and_overridable():
    e = np.random.default_rng(1).standard_normal(5_000)
    model = TransferModel((Mode(2000, 0.05),), noise=NoiseSpec(0.0),
                          tones=(Tone(order=1.0, amplitude=0.1),), seed=7)
    a1, i1 = synthesize_acceleration(e, FS, model, fr=15.8)
    a2, _ = synthesize_acceleration(e, FS, model, fr=15.8, seed=7)
    a3, _ = synthesize_acceleration(e, FS, model, fr=15.8, seed=8)
    np.testing.assert_array_equal(a1, a2)
    assert not np.allclose(a1, a3)
    assert i1["seed"] == 7
    a4, i4 = synthesize_acceleration(e, FS, model, fr=15.8, snr_db=None)
    assert i4["p_noise"] == 0.0 and i4["snr_db_target"] is None


def test_tones_land_at_requested_frequency_and_level():
    n = 20_000
    e = np.random.default_rng(2).standard_normal(n)
    model = TransferModel((Mode(3000, 0.05, 1.0),),
                          tones=(Tone(order=2.0, amplitude=0.5, phase_rad=0.0),
                                 Tone(frequency_hz=1200.0, level_db=10.0)))
    acc, info = synthesize_acceleration(e, FS, model, fr=15.0, seed=0)
    clean = _clean_response(e, model.modes)  # independent of the module's filters
    tones = acc - clean  # no noise
    spec = 2 * np.abs(np.fft.rfft(tones)) / n
    f = np.fft.rfftfreq(n, 1 / FS)
    assert spec[np.argmin(np.abs(f - 30.0))] == pytest.approx(0.5, rel=1e-9)
    a_gm = spec[np.argmin(np.abs(f - 1200.0))]
    assert 10 * math.log10(a_gm**2 / 2 / info["p_defect"]) == pytest.approx(10.0, abs=1e-6)
    assert [t["frequency_hz"] for t in info["tones"]] == [30.0, 1200.0]


def test_from_mapping_round_trip_and_defaults():
    cfg = {
        "excitation": "pressure",
        "excitation_scale": 1e-6,
        "modes": [{"f_n_hz": 3000, "zeta": 0.05, "gain": 2.0}, {"f_n_hz": 9000, "zeta": 0.1}],
        "noise": {"snr_db": 10, "exact": False},
        "tones": [{"order": 1, "amplitude": 0.1}, {"frequency_hz": 1250, "level_db": -3}],
        "seed": 4,
    }
    m = TransferModel.from_mapping(cfg, fs=FS)
    assert m.modes[1].gain == 1.0 and m.noise.snr_db == 10.0 and not m.noise.exact
    assert TransferModel.from_mapping(m.to_dict()) == m
    m2 = TransferModel.from_mapping({"modes": [{"f_n_hz": 3000, "zeta": 0.05}], "snr_db": -5})
    assert m2.noise.snr_db == -5.0 and m2.discretization == "impulse" and m2.seed == 0


@pytest.mark.parametrize(
    "cfg, fragments",
    [
        ({"modes": [{"f_n_hz": 10_000, "zeta": 0.05}]}, ["sensor.modes[0].f_n_hz", "10000", "fs/2"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.0}]}, ["sensor.modes[0].zeta", "0.0", "(0, 1)"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 1.0}]}, ["zeta", "1.0", "(0, 1)"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.1, "gain": -1}]}, ["sensor.modes[0].gain", "-1", "> 0"]),
        ({"modes": [{"f_n_hz": -5, "zeta": 0.1}]}, ["f_n_hz", "-5", "> 0"]),
        ({"modes": [{"f_n_hz": 3000}]}, ["sensor.modes[0].zeta", "required"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.1, "q": 3}]}, ["sensor.modes[0]", "'q'"]),
        ({"modes": []}, ["sensor.modes", "non-empty"]),
        ({}, ["sensor.modes", "required"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.1}], "snr_db": 500}, ["snr_db", "500", "[-80, 200]"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.1}], "discretization": "zoh"},
         ["discretization", "zoh", "impulse"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.1}], "excitation": "torque"}, ["excitation", "torque"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.1}], "seed": -1}, ["seed", "-1"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.1}], "tones": [{"order": 1, "frequency_hz": 5,
                                                                 "amplitude": 1}]},
         ["sensor.tones[0]", "frequency_hz", "order"]),
        ({"modes": [{"f_n_hz": 3000, "zeta": 0.1}], "noise": {"snr": 3}}, ["sensor.noise", "'snr'"]),
        ({"modes": [{"f_n_hz": "fast", "zeta": 0.1}]}, ["f_n_hz", "fast"]),
    ],
)
def test_bad_config_names_the_field(cfg, fragments):
    with pytest.raises(ValueError) as err:
        TransferModel.from_mapping(cfg, fs=FS)
    for frag in fragments:
        assert frag in str(err.value), (frag, str(err.value))


def test_bad_runtime_inputs():
    model = TransferModel((Mode(3000, 0.1),))
    with pytest.raises(ValueError, match="f_n_hz must be < fs/2"):
        synthesize_acceleration(np.ones(100), 5000.0, model)
    with pytest.raises(ValueError, match="reference"):
        synthesize_acceleration(np.ones(100), FS, model, reference=np.ones(50))
    with pytest.raises(ValueError, match="zero power"):
        synthesize_acceleration(np.ones(100), FS, model.with_snr(0.0), reference=np.ones(100))
    with pytest.raises(ValueError, match="fr"):
        synthesize_acceleration(np.ones(100), FS,
                                TransferModel(model.modes, tones=(Tone(order=1, amplitude=1),)))
    with pytest.raises(ValueError, match="excitation"):
        excitation_from_history(np.ones((3, 3)))
    with pytest.raises(KeyError, match="roller_load"):
        select_excitation({"p_max": np.ones(3)}, "force")
    name, x = select_excitation({"p_max": np.ones(3), "roller_load": np.ones(3)}, "force")
    assert name == "roller_load"
    # a format-2 case: the blocked force (roller load minus removed force) wins over the load
    sig = {"roller_load": np.full(3, 1e4), "contact_force": np.array([1e4, 9.9e3, 1e4])}
    name, x = select_excitation(sig, "force")
    assert name == "contact_force" and x[1] == 9.9e3


# ------------------------------------------------------------------ CLI `sensor`
def _write_config(tmp_path, snr=5.0):
    cfg = tmp_path / "config.yaml"
    cfg.write_text(
        "scene: {}\n"
        "sensor:\n"
        "  excitation: pressure\n"
        "  modes:\n"
        "    - {f_n_hz: 4000, zeta: 0.03, gain: 1.0e-9}\n"
        f"  noise: {{snr_db: {snr}}}\n"
        "  tones:\n"
        "    - {order: 1, amplitude: 0.01}\n"
        "  seed: 3\n"
    )
    return cfg


def _fake_case(defect=0.05):
    from types import SimpleNamespace

    p, base = _case_like_excitation(n=8000, defect=defect)
    return SimpleNamespace(fs=FS, fr=15.8, bpfi=231.9, bpfo=180.0, ftf=7.0, bsf=80.0,
                           load_kN=500.0, depth_um=50.0, signals={"p_max": p, "p_max_defect": p},
                           roller_load=np.full(p.size, 8e4))


def _write_minimal_case(path, case):
    """A case file in the layout of bearing_envelope.io (its current format version), by hand."""
    import h5py

    from bearing_envelope.io import FORMAT_VERSION, seal

    with h5py.File(path, "w") as h5:
        h5.attrs["format"] = "bearing_envelope.case"
        h5.attrs["format_version"] = FORMAT_VERSION
        for k in ("fs", "fr", "bpfi", "bpfo", "ftf", "bsf", "load_kN", "depth_um"):
            h5.attrs[k] = getattr(case, k)
        h5.attrs["bpfi_geometry"] = case.bpfi
        n = case.signals["p_max"].size
        h5["time"] = np.arange(n) / case.fs
        h5["signals/p_max"] = case.signals["p_max"]
        h5["signals/p_max_defect"] = case.signals["p_max_defect"]
        h5["signals/roller_load"] = case.roller_load
        h5["signals/defect_offset"] = np.zeros(n)
        seal(h5)  # the attribute digest every case file of this version carries
    return str(path)


@pytest.mark.parametrize("suffix", [".npz", ".h5"])
def test_cli_sensor_writes_acceleration_with_provenance(tmp_path, monkeypatch, suffix):
    import json

    from bearing_envelope import cli
    from bearing_envelope.commands import sensor

    cases = {"case.h5": _fake_case(), "ref.h5": _fake_case(defect=0.0)}
    case_path = _write_minimal_case(tmp_path / "case.h5", cases["case.h5"])
    monkeypatch.setattr(sensor, "_read_case", lambda path: cases[path.split("/")[-1]])
    cfg = _write_config(tmp_path)
    out = tmp_path / f"out{suffix}"
    rc = cli.main(["sensor", case_path, "--config", str(cfg), "--snr-db", "-3",
                   "--reference", "ref.h5", "-o", str(out)])
    assert rc == 0 and out.exists()
    if suffix == ".npz":
        data = np.load(out)
        acc, info = data["acceleration"], json.loads(str(data["provenance"]))
        assert float(data["bpfi"]) == 231.9
    else:
        import h5py

        with h5py.File(out) as h5:
            acc = h5["signals/acceleration"][...]
            info = json.loads(h5["signals/acceleration"].attrs["provenance"])
            assert h5.attrs["fs"] == FS and "p_max" in h5["signals"]  # the case is kept
    assert acc.shape == (8000,)
    assert info["snr_db_target"] == -3.0 and info["snr_db_achieved"] == pytest.approx(-3.0)
    assert info["seed"] == 3 and info["excitation_signal"] == "p_max"
    assert info["defect_definition"] == "var(H e - H e_ref)"
    assert info["source_case"] == case_path and info["model"]["modes"][0]["f_n_hz"] == 4000.0


def test_cli_sensor_bad_config_reports_field(tmp_path, monkeypatch, capsys):
    from bearing_envelope import cli
    from bearing_envelope.commands import sensor

    monkeypatch.setattr(sensor, "_read_case", lambda path: _fake_case())
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("sensor:\n  modes:\n    - {f_n_hz: 12000, zeta: 0.03}\n")
    rc = cli.main(["sensor", "case.h5", "--config", str(cfg), "-o", str(tmp_path / "o.npz")])
    assert rc == 2
    assert "sensor.modes[0].f_n_hz must be < fs/2" in capsys.readouterr().err
    assert not (tmp_path / "o.npz").exists()


def test_cli_sensor_on_real_case_file(tmp_path):
    """End to end through bearing_envelope.io.read_case: the output is a case with a 2nd signal."""
    io = pytest.importorskip("bearing_envelope.io", reason="bearing_envelope.io not written yet")
    from bearing_envelope import cli
    from bearing_envelope.diagnosis.detection import detect

    case_path = _write_minimal_case(tmp_path / "F500kN_h50um.h5", _fake_case())
    cfg = _write_config(tmp_path, snr=0.0)
    out = tmp_path / "sensor" / "F500kN_h50um.h5"
    assert cli.main(["sensor", case_path, "--config", str(cfg), "-o", str(out)]) == 0
    case = io.read_case(out)
    acc = case.signals["acceleration"]
    assert acc.shape == case.p_max.shape and case.bpfi == 231.9
    # the envelope spectrum of the synthetic acceleration shows BPFI
    sos = sps.butter(4, [3000, 5000], btype="bandpass", fs=case.fs, output="sos")
    env = np.abs(sps.hilbert(sps.sosfiltfilt(sos, acc)))
    env -= env.mean()
    f = np.fft.rfftfreq(env.size, 1 / case.fs)
    stat, detected = detect(f, 2 * np.abs(np.fft.rfft(env)) / env.size, case.bpfi, fr=case.fr)
    assert detected, stat
