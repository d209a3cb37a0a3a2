"""``bearing-envelope analyze`` on many records (issue 24 part 5-6) and its input robustness
(issue 22 part 6): every bad input is one line naming the file or the option."""

import re

import numpy as np
import pandas as pd
import pytest
import scipy.io
import scipy.io.wavfile

from bearing_envelope.cli import main
from bearing_envelope.io import records
from conftest import fault_signal

FS, FR = 20000.0, 15.8
BPFI_6205 = 4.5 * (1 + 7.94 / 39.04) * FR  # the 6205's BPFI at FR (9 balls, 7.94 / 39.04 mm)


@pytest.fixture(scope="module")
def x():
    return fault_signal(fs=FS, n=2**15, fr=FR, bpfi=BPFI_6205, fn=6000.0, seed=3)


@pytest.fixture
def folder(tmp_path, x):
    """Three records (a fault, noise, a fault) as .npz with fs, and a manifest of them."""
    d = tmp_path / "recs"
    d.mkdir()
    noise = np.random.default_rng(1).standard_normal(x.size)
    np.savez(d / "a_fault.npz", x=x, fs=FS)
    np.savez(d / "b_noise.npz", x=noise, fs=FS)
    np.savez(d / "c_fault.npz", x=x[::-1].copy(), fs=FS)
    pd.DataFrame({"file": ["a_fault.npz", "b_noise.npz", "c_fault.npz"], "fs": [FS] * 3,
                  "fr": [FR] * 3, "bearing": ["6205"] * 3}).to_csv(d / "manifest.csv",
                                                                  index=False)
    return d


def _one_line(err: str, pattern: str) -> str:
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert re.search(pattern, lines[0]), err
    return lines[0]


def test_folder_and_manifest_give_the_table(folder, tmp_path, capsys):
    common = ["--nlevel", "5", "--quiet"]
    t1, t2 = tmp_path / "t1.csv", tmp_path / "t2.csv"
    assert main(["analyze", str(folder), "--fr", str(FR), "--bearing", "6205",
                 "--table", str(t1), "--html", str(tmp_path / "r.html"), *common]) == 0
    assert main(["analyze", "--manifest", str(folder / "manifest.csv"), "--table", str(t2),
                 *common]) == 0
    out = capsys.readouterr().out
    assert "# 3 records: 3 analysed, 0 failed" in out
    a, b = pd.read_csv(t1), pd.read_csv(t2)
    fams = {"bpfo", "bpfi", "bsf", "bsf2", "ftf"}
    for t in (a, b):
        assert len(t) == 3 * 5 and set(t.family) == fams
        assert [p.split("/")[-1] for p in t.file.unique()] == ["a_fault.npz", "b_noise.npz",
                                                               "c_fault.npz"]
        diag = t[t.diagnosis]
        assert set(diag.record) == {"a_fault", "c_fault"} and set(diag.family) == {"bpfi"}
        for c in ("verdict", "band", "margin_db", "h1_hz", "h1_amplitude", "h2_hz",
                  "h1_band_peak", "h1_band_power", "total_band_power", "floor_ratio_db"):
            assert c in t.columns
        row = t[(t.record == "a_fault") & (t.family == "bpfi")].iloc[0]
        assert abs(row.h1_hz - BPFI_6205) < 0.01 * BPFI_6205 and row.h1_band_peak > 0
    cols = [c for c in a.columns if c != "file"]
    pd.testing.assert_frame_equal(a[cols], b[cols])
    page = (tmp_path / "r.html").read_text()
    assert page.count("<img") == 3 and "a_fault" in page
    assert len(list((tmp_path / "r_figures").glob("*_analysis.png"))) == 3


def test_parallel_and_serial_tables_are_identical(folder, tmp_path):
    outs = []
    for jobs in ("1", "2"):
        t = tmp_path / f"t{jobs}.csv"
        assert main(["analyze", str(folder), "--fr", str(FR), "--bearing", "6205", "--nlevel",
                     "5", "--jobs", jobs, "--table", str(t), "--csv", str(tmp_path / "l.csv"),
                     "--quiet"]) == 0
        outs.append((t.read_bytes(), (tmp_path / "l.csv").read_bytes()))
    assert outs[0] == outs[1]


def test_a_bad_record_is_a_row_and_the_others_run(folder, tmp_path, capsys):
    (folder / "d_bad.npy").write_bytes(b"not an npy file at all")
    t = tmp_path / "t.csv"
    rc = main(["analyze", str(folder), "--fr", str(FR), "--bearing", "6205", "--nlevel", "5",
               "--table", str(t), "--quiet"])
    assert rc == 1
    err = _one_line(capsys.readouterr().err, r"d_bad\.npy.*no valid \.npy header")
    assert err.startswith("bearing-envelope analyze: ")
    df = pd.read_csv(t)
    bad = df[df.status == "error"]
    assert list(bad.record) == ["d_bad"] and "no valid .npy header" in bad.error.iloc[0]
    assert (df.status == "ok").sum() == 15


def test_cwru_mat_layout(tmp_path, x, capsys):
    rpm = FR * 60
    scipy.io.savemat(tmp_path / "118.mat", {"X118_DE_time": x[:, None],
                                            "X118_FE_time": 0.5 * x[:, None],
                                            "X118RPM": np.array([[rpm]])})
    base = ["analyze", str(tmp_path / "118.mat"), "--fs", str(FS), "--bearing", "6205",
            "--nlevel", "5"]
    assert main(base) == 0
    out = capsys.readouterr().out
    assert "mat:X118_DE_time" in out and f"fr = {FR:g} Hz" in out
    assert "inner race fault" in out
    assert main([*base, "--channel", "FE"]) == 0
    assert "mat:X118_FE_time" in capsys.readouterr().out
    assert main([*base, "--channel", "BA"]) == 2
    _one_line(capsys.readouterr().err, r"--channel: .*118\.mat has no BA channel")


def test_wav(tmp_path, x, capsys):
    pcm = np.round(x / np.abs(x).max() * 20000).astype(np.int16)
    scipy.io.wavfile.write(tmp_path / "r.wav", int(FS), pcm)
    assert main(["analyze", str(tmp_path / "r.wav"), "--fr", str(FR), "--bearing", "6205",
                 "--nlevel", "5"]) == 0
    out = capsys.readouterr().out
    assert "(wav)" in out and "fs = 20000 Hz" in out


def test_csv_dialects(tmp_path, x):
    """Semicolons with decimal commas, semicolons with dots, tabs: the same numbers."""
    t = np.arange(200) / FS
    v = x[:200]
    sc = tmp_path / "semi_comma.csv"
    sc.write_text("time;DE\n" + "".join(f"{a:.9f};{b:.6f}\n".replace(".", ",")
                                        for a, b in zip(t, v)))
    sd = tmp_path / "semi_dot.csv"
    sd.write_text("".join(f"{a:.9f};{b:.6f}\n" for a, b in zip(t, v)))
    tab = tmp_path / "tab.csv"
    tab.write_text("t\tDE\n" + "".join(f"{a:.9f}\t{b:.6f}\n" for a, b in zip(t, v)))
    for p, col in ((sc, None), (sd, "1"), (tab, None)):
        rec = records.read_record(str(p), column=col)
        np.testing.assert_allclose(rec["x"], np.round(v, 6), atol=1e-12)
    assert records.read_record(str(sc))["fs"] == pytest.approx(FS)


BAD = {
    # name: (writer(tmp) -> path, extra options, pattern of the one line)
    "ambiguous-decimal-comma": (lambda d: _text(d / "a.csv", "0,037719\n0,012345\n0,020000\n"),
                                [], r"file: .*a\.csv: ',' may be the delimiter or the decimal"),
    "not-a-number-csv": (lambda d: _text(d / "n.csv", "DE\n1.5\nabc\n2.5\n"), [],
                         r"file: .*n\.csv: column 'DE', line 3: 'abc' is not a number"),
    "empty-npz": (lambda d: _npz_empty(d / "e.npz"), [], r"file: .*e\.npz holds no arrays"),
    "truncated-npz": (lambda d: _truncated(d / "t.npz"), [],
                      r"file: .*t\.npz is not a readable \.npz"),
    "lying-npy-header": (lambda d: _lying(d / "l.npy"), [],
                         r"file: .*l\.npy: the array has a header that claims shape "
                         r"\(1000000000000,\) .* "
                         r"truncated or its header is wrong"),
    "complex-npy": (lambda d: _npy(d / "c.npy", np.ones(4096) * (1 + 1j)), [],
                    r"file: .*c\.npy: the array holds complex values"),
    "bool-npy": (lambda d: _npy(d / "b.npy", np.ones(4096, bool)), [],
                 r"file: .*b\.npy: the array holds booleans"),
    "object-npy": (lambda d: _npy(d / "o.npy", np.array([1, "a"], dtype=object)), [],
                   r"file: .*o\.npy: the array holds Python objects"),
    "no-numeric-npz": (lambda d: _npz(d / "s.npz", name=np.array("text")), [],
                       r"file: .*s\.npz holds no numeric signal"),
    "column-not-an-index": (lambda d: _npy(d / "x2.npy", np.ones((4096, 2))), ["--column", "x"],
                            r"--column: 'x' is not an index; .*x2\.npy holds 2 channels"),
    "bands-bad-yaml": (lambda d: _npy(d / "x.npy", None), ["--bands", "{bands}"],
                       r"--bands: .*bands\.yaml is not valid YAML at line \d"),
    "harmonics-100": (lambda d: _npy(d / "x.npy", None), ["--harmonics", "100"],
                      r"--harmonics: got 100; allowed: 1 \.\. \d+ for this record"),
    "unknown-bearing": (lambda d: _npy(d / "x.npy", None), ["--bearing", "6299"],
                        r"--bearing: got '6299'; allowed: .*SKF 6205-2RS"),
    "table-under-a-file": (lambda d: _npy(d / "x.npy", None), ["--table", "{tmp}/x.npy/t.csv"],
                           r"--table: cannot create .*x\.npy"),
    "html-is-directory": (lambda d: _npy(d / "x.npy", None), ["--html", "{tmp}"],
                          r"--html: .* is a directory"),
}


def _text(p, s):
    p.write_text(s)
    return p


def _npy(p, a):
    np.save(p, a if a is not None else np.random.default_rng(0).standard_normal(4096),
            allow_pickle=a is not None and a.dtype == object)
    return p


def _npz(p, **arrays):
    np.savez(p, **arrays)
    return p


def _npz_empty(p):
    np.savez(p)
    return p


def _truncated(p):
    np.savez(p, x=np.random.default_rng(0).standard_normal(4096), fs=FS)
    data = p.read_bytes()
    p.write_bytes(data[: len(data) // 2])
    return p


def _lying(p):
    np.save(p, np.zeros(16))
    data = bytearray(p.read_bytes())
    header = data[:128].decode("latin1")
    new = header.replace("(16,)", "(1000000000000,)")
    p.write_bytes(new[: len(header)].encode("latin1") + data[128:])
    return p


@pytest.mark.parametrize("key", sorted(BAD))
def test_bad_input_is_one_line_naming_file_or_option(tmp_path, capsys, key):
    write, extra, pattern = BAD[key]
    path = write(tmp_path)
    (tmp_path / "bands.yaml").write_text("bands:\n  - {name: f, strategy: [fixed\n")
    extra = [a.replace("{tmp}", str(tmp_path)).replace("{bands}", str(tmp_path / "bands.yaml"))
             for a in extra]
    assert main(["analyze", str(path), "--fs", "2000", "--fr", "10", "--bpfi", "55",
                 "--nlevel", "3", *extra]) == 2
    _one_line(capsys.readouterr().err, pattern)


def test_outputs_checked_before_the_analysis(tmp_path, capsys, monkeypatch):
    """An unwritable output is refused before any record is read."""
    import bearing_envelope.commands.analyze as analyze

    calls = []
    monkeypatch.setattr(analyze, "analyze_task", lambda *a: calls.append(a))
    np.save(tmp_path / "x.npy", np.ones(4096))
    (tmp_path / "f").write_text("")
    assert main(["analyze", str(tmp_path / "x.npy"), "--fs", "2000", "--fr", "10", "--bpfi",
                 "55", "--csv", str(tmp_path / "f" / "t.csv")]) == 2
    _one_line(capsys.readouterr().err, r"--csv: cannot create")
    assert calls == []


def test_memory_checked_before_reading(tmp_path, capsys, monkeypatch):
    np.save(tmp_path / "x.npy", np.random.default_rng(0).standard_normal(100000))
    monkeypatch.setattr(records, "available_memory", lambda: 10_000_000)
    assert main(["analyze", str(tmp_path / "x.npy"), "--fs", "2000", "--fr", "10", "--bpfi",
                 "55"]) == 2
    _one_line(capsys.readouterr().err, r"file: .*x\.npy: analysing its 100000 samples needs "
                                       r"about 19.2 MB of memory .* 10 MB available")


def test_bearing_designations_give_the_published_factors():
    """6205 and 6203 resolve through the bearing catalogue; their geometry gives the CWRU data
    center's defect factors (x fr): exactly for the 6205 (CWRU drive end), within 0.05 % for
    the catalogue's 6203 (Paderborn/KAt: pitch 28.55 mm against CWRU's fan-end 1.122 in =
    28.50 mm)."""
    from bearing_envelope.physics.catalogue import bearing_geometry
    from bearing_envelope.physics.kinematics import fault_frequencies

    for name, cat, bpfi, bpfo, ftf, rel in (
            ("6205", "SKF 6205-2RS", 5.4152, 3.5848, 0.39828, 1e-4),
            ("6205-2RS JEM SKF", "SKF 6205-2RS", 5.4152, 3.5848, 0.39828, 1e-4),
            ("6203", "SKF 6203", 4.9469, 3.0530, 0.3817, 5e-4)):
        g = bearing_geometry(name)
        assert g["designation"] == cat
        ff = fault_frequencies(1.0, g["n_rollers"], g["roller_diameter_mm"],
                               g["pitch_diameter_mm"], g["contact_angle_deg"])
        assert ff.bpfi == pytest.approx(bpfi, rel=rel)
        assert ff.bpfo == pytest.approx(bpfo, rel=rel)
        assert ff.ftf == pytest.approx(ftf, rel=rel)


def test_plot_options(folder, tmp_path):
    """--db, --fmax, --orders: the figures are written (and differ from the default)."""
    sizes = []
    for opts in ([], ["--db", "--fmax", "400", "--orders"]):
        d = tmp_path / ("a" if not opts else "b")
        assert main(["analyze", str(folder / "a_fault.npz"), "--fr", str(FR), "--bearing",
                     "6205", "--nlevel", "5", "--html", str(d / "r.html"), *opts]) == 0
        png = d / "r_figures" / "a_fault_analysis.png"
        sizes.append(png.read_bytes())
    assert sizes[0] != sizes[1]


def test_batch_json_on_stdout_and_no_progress_bar_off_a_terminal(folder, capsys):
    import json

    assert main(["analyze", str(folder / "a_fault.npz"), str(folder / "b_noise.npz"), "--fr",
                 str(FR), "--bearing", "6205", "--nlevel", "5", "--json", "-"]) == 0
    cap = capsys.readouterr()
    doc = json.loads(cap.out)
    assert [r["file"].split("/")[-1] for r in doc["records"]] == ["a_fault.npz", "b_noise.npz"]
    assert doc["records"][0]["verdict"]["diagnosis"] == "bpfi"
    assert "analyze:" not in cap.err and "record/s" not in cap.err  # no tqdm bar off a TTY
    assert "# 2 records: 2 analysed, 0 failed" in cap.err


@pytest.mark.parametrize("column, value, pattern", [
    ("bearing", "6299", r"--manifest: .*manifest\.csv line 3: got '6299'; allowed: "),
    ("channel", "XY", r"--manifest: .*manifest\.csv line 3: channel = 'XY'; allowed: DE, FE, BA"),
    ("fs", "-5", r"--manifest: .*manifest\.csv line 3: fs = '-5'; allowed: a number > 0"),
])
def test_bad_manifest_is_refused_before_any_record(folder, capsys, column, value, pattern):
    m = pd.read_csv(folder / "manifest.csv")
    m[column] = m[column].astype(object) if column in m else None
    m.loc[1, column] = value
    m.to_csv(folder / "manifest.csv", index=False)
    assert main(["analyze", "--manifest", str(folder / "manifest.csv")]) == 2
    _one_line(capsys.readouterr().err, pattern)
