"""Hostile ``analyze`` inputs: each refused in one line naming the field, or analysed right.

Regenerates the hostile-tester set of ``bearing-envelope analyze`` (issue 43's 106 inputs,
grown): files of every type ``analyze`` reads (``.npz``, ``.npy``, ``.csv``, ``.mat``, ``.wav``,
case files ``.h5``) written to a temporary folder with wrong shapes and dtypes, NaN and inf,
huge and tiny scales, constant, empty and too short signals; sampling rates that are 0,
negative, arrays, text or absurd; missing and contradicting shaft rates and ``meta_json``; bad
bearing designations and geometries; bad bands, options, windows and fault lines; CSV time
columns that are not uniform; empty, truncated and binary-garbage files; pickled objects in
``.npz``/``.npy`` (which must never be unpickled: a witness file would appear); symlinks,
folders, devices and FIFOs; and valid records as controls whose answer is known by
construction (an impact train at the inner- or outer-race rate of the CWRU 6205, from its
published multiples of the shaft rate, BPFI = 5.4152 fr and BPFO = 3.5848 fr; white noise:
no fault).

Each input runs through the real command line in a subprocess (``python -m bearing_envelope
analyze ...``) with a timeout (:data:`TIMEOUT_S`), and is classified:

- ``refused``: exit code 2, one line on stderr, naming what the input expects it to name (the
  option or the file's field): OK;
- ``analysed right``: exit code 0, nothing on stderr, the JSON verdict's family the one
  expected: OK;
- ``traceback``, ``silently wrong`` (analysed when it must be refused, a wrong family, a
  pickle run), ``refusal not naming`` (several lines, or the field not named),
  ``false refusal`` (a valid input refused), ``hang`` (past the timeout), ``noisy``
  (analysed, but warnings on stderr).

Usage::

    python -m benchmarks hostile_records [--quick] [--only TEXT] [--out results.csv]
    python -m benchmarks hostile_records --src /tmp/old/src   # the same set on older code

Figures (date, machine, CPU seconds) go to ``docs/validation.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import signal
import struct
import subprocess
import sys
import tempfile
import time
import wave
import zipfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

#: Wall seconds one ``analyze`` run may take before it counts as a hang.
TIMEOUT_S = 60.0

FS = 12_000.0           # Hz
FR = 29.95              # Hz, CWRU 1 hp
N = 2 ** 15             # samples (2.7 s)
#: The CWRU 6205's fault rates as multiples of the shaft rate (CWRU's bearing table; not the
#: project's kinematics).
BPFI_X, BPFO_X = 5.4152, 3.5848

#: File a pickled object creates if anything ever unpickles it.
PICKLE_WITNESS = Path(tempfile.gettempdir()) / "bearing_envelope_hostile_records_pickle_witness"

OK = ("refused", "analysed right")


class _Witness:
    """Unpickling this creates :data:`PICKLE_WITNESS` (a reader that unpickles is caught)."""

    def __reduce__(self):
        return (open, (str(PICKLE_WITNESS), "w"))


# ------------------------------------------------------------------------------ signals
def impacts(rate_hz: float, *, fr: float = FR, fs: float = FS, n: int = N, seed: int = 0,
            modulate: bool = True, noise: float = 0.3) -> np.ndarray:
    """An impact train at ``rate_hz`` ringing at 3 kHz (decay 2 ms), modulated once per shaft
    turn when ``modulate`` (inner race), in white noise of s.d. ``noise``."""
    t = np.arange(n) / fs
    tau = t % (1.0 / rate_hz)
    am = 1.0 + 0.5 * np.cos(2 * np.pi * fr * t) if modulate else 1.0
    x = am * np.exp(-tau / 2e-3) * np.sin(2 * np.pi * 3000.0 * tau)
    return x + noise * np.random.default_rng(seed).standard_normal(n)


def inner() -> np.ndarray:
    """The inner-race control record (12 kHz, 29.95 Hz)."""
    return impacts(BPFI_X * FR)


def outer() -> np.ndarray:
    """The outer-race control record (12 kHz, 29.95 Hz)."""
    return impacts(BPFO_X * FR, modulate=False, seed=1)


def noise(seed: int = 2) -> np.ndarray:
    """White noise: no fault."""
    return np.random.default_rng(seed).standard_normal(N)


# -------------------------------------------------------------------------------- files
class Writer:
    """Writes the inputs' files into one folder (names numbered, never reused)."""

    def __init__(self, work: Path):
        self.work = work
        self.i = 0

    def path(self, suffix: str, stem: str = "r") -> Path:
        """A new file name with ``suffix``."""
        self.i += 1
        return self.work / f"{stem}{self.i:03d}{suffix}"

    def npz(self, **arrays) -> str:
        """An ``.npz`` of ``arrays`` (object arrays pickled, as numpy writes them)."""
        p = self.path(".npz")
        np.savez(p, **arrays)
        return str(p)

    def npy(self, a) -> str:
        """An ``.npy`` of ``a``."""
        p = self.path(".npy")
        np.save(p, a, allow_pickle=True)
        return str(p)

    def raw(self, data: bytes, suffix: str) -> str:
        """A file of these bytes."""
        p = self.path(suffix)
        p.write_bytes(data)
        return str(p)

    def csv(self, rows, header: str | None = "time,x", fmt=lambda v: f"{v:.9g}",
            sep: str = ",") -> str:
        """A CSV of ``rows`` (tuples of numbers or texts)."""
        lines = [] if header is None else [header]
        lines += [sep.join(c if isinstance(c, str) else fmt(c) for c in r) for r in rows]
        return self.raw(("\n".join(lines) + "\n").encode(), ".csv")

    def wav(self, x, fs: int = int(FS), dtype=np.int16, channels: int = 1) -> str:
        """A PCM ``.wav`` (scipy's writer)."""
        from scipy.io import wavfile

        p = self.path(".wav")
        a = np.asarray(x)
        if dtype == np.int16:
            a = np.round(a / np.max(np.abs(a)) * 20000).astype(np.int16)
        else:
            a = a.astype(dtype)
        if channels > 1:
            a = np.column_stack([a] * channels)
        wavfile.write(p, fs, a)
        return str(p)

    def mat(self, **variables) -> str:
        """A MATLAB v5 ``.mat`` of ``variables``."""
        from scipy.io import savemat

        p = self.path(".mat")
        savemat(p, variables)
        return str(p)


def _t(n: int = N, fs: float = FS) -> np.ndarray:
    return np.arange(n) / fs


# --------------------------------------------------------------------------------- cases
#: A case: (name, class, argv after ``analyze``, expect) where expect is ``("refuse",
#: regex)`` (the one-line refusal must match the regex: the option or field it names) or
#: ``("analyse", family)`` (``family`` the JSON verdict's diagnosis, None for no fault).
BEARING = ["--bearing", "6205"]


def signal_cases(w: Writer) -> list:
    """Sample values, shapes and dtypes (an ``.npz`` with ``fs`` and ``fr``)."""
    x = inner()
    rec = lambda a, **kw: w.npz(x=a, fs=np.float64(FS), fr=np.float64(FR), **kw)  # noqa: E731
    nan1, inf1, ninf = x.copy(), x.copy(), x.copy()
    nan1[100] = np.nan
    inf1[5] = np.inf
    ninf[-1] = -np.inf
    refuse = lambda name, a, rx: (name, "samples", [rec(a), *BEARING], ("refuse", rx))  # noqa
    out = [
        ("control: inner race (.npz)", "control", [rec(x), *BEARING], ("analyse", "bpfi")),
        ("control: outer race (.npz)", "control", [rec(outer()), *BEARING], ("analyse", "bpfo")),
        ("control: white noise (.npz)", "control", [rec(noise()), *BEARING], ("analyse", None)),
        ("control: inner race x 1e40", "samples", [rec(x * 1e40), *BEARING], ("analyse", "bpfi")),
        ("control: inner race x 1e-40", "samples", [rec(x * 1e-40), *BEARING],
         ("analyse", "bpfi")),
        ("control: inner race, int16 counts", "samples",
         [rec(np.round(x * 3000).astype(np.int16)), *BEARING], ("analyse", "bpfi")),
        ("control: inner race, float32", "samples", [rec(x.astype(np.float32)), *BEARING],
         ("analyse", "bpfi")),
        ("control: inner race + DC 1e6", "samples", [rec(x + 1e6), *BEARING],
         ("analyse", "bpfi")),
        refuse("one NaN", nan1, r"non-finite"),
        refuse("all NaN", np.full(N, np.nan), r"non-finite"),
        refuse("one +inf", inf1, r"non-finite"),
        refuse("last -inf", ninf, r"non-finite"),
        refuse("scale 1e305", x * 1e305, r"peak at"),
        refuse("scale 1e-310", x * 1e-310, r"peak at"),
        refuse("scale 1e60", x * 1e60, r"peak at"),
        refuse("scale 1e-60", x * 1e-60, r"peak at"),
        refuse("float max", np.where(x > 0, np.finfo(float).max, -np.finfo(float).max),
               r"peak at"),
        refuse("constant 1.0", np.ones(N), r"constant"),
        refuse("zeros", np.zeros(N), r"constant"),
        refuse("empty", np.zeros(0), r"'x'|empty|no numeric signal"),
        refuse("one sample", np.ones(1) * 0.5, r"'x'|no numeric signal|samples"),
        refuse("15 samples", x[:15], r"samples"),
        refuse("16 samples", x[:16], r"samples|resolution|--fr|fr\b"),
        refuse("100 samples", x[:100], r"resolution|--fr|samples"),
        refuse("1000 samples (fr not resolved)", x[:1000], r"resolution|--fr"),
        refuse("complex", x.astype(complex), r"complex"),
        refuse("booleans", x > 0, r"boolean"),
        refuse("text", np.array(["a"] * 100), r"no numeric signal|'x'"),
        refuse("2-D (n, 2)", np.column_stack([x, x]), r"'x'.*shape"),
        refuse("2-D (2, n)", np.vstack([x, x]), r"'x'.*shape"),
        refuse("3-D", x[:32000].reshape(10, 40, 80), r"'x'.*shape"),
        refuse("datetime64", np.arange(N).astype("datetime64[s]"), r"no numeric signal|'x'"),
        refuse("structured", np.zeros(N, dtype=[("a", "f8"), ("b", "f8")]),
               r"no numeric signal|'x'"),
        ("float16 (inner race)", "samples", [rec(x.astype(np.float16)), *BEARING],
         ("analyse", "bpfi")),
        ("uint8 counts (inner race)", "samples",
         [rec(np.round(x * 20 + 128).clip(0, 255).astype(np.uint8)), *BEARING],
         ("analyse", "bpfi")),
        ("int64 huge counts", "samples",
         [rec((x * 2 ** 60).astype(np.int64)), *BEARING], ("analyse", "bpfi")),
        ("one-sample spike 1e10 in noise", "samples",
         [rec(np.where(np.arange(N) == 5000, 1e10, noise())), *BEARING], ("analyse", None)),
        ("square wave at BPFI (saturated)", "samples",
         [rec(np.sign(x) + 0.0), *BEARING], ("analyse", "bpfi")),
    ]
    return out


def rate_cases(w: Writer) -> list:
    """Sampling and shaft rates in the file and on the command line."""
    x = inner()
    npz = lambda **kw: w.npz(x=x, **kw)  # noqa: E731
    f64 = np.float64
    fs_bad = [("fs 0", f64(0)), ("fs -12000", f64(-FS)), ("fs NaN", f64(np.nan)),
              ("fs inf", f64(np.inf)), ("fs [12000, 12000]", np.array([FS, FS])),
              ("fs text '12000'", np.array("12000")), ("fs complex", np.complex128(FS)),
              ("fs True", np.bool_(True)), ("fs 1e300", f64(1e300)), ("fs empty array", np.zeros(0)),
              ("fs 1 Hz", f64(1.0)), ("fs 300 Hz (BPFI above Nyquist)", f64(300.0)),
              ("fs 1e-300", f64(1e-300))]
    out = [(name, "fs", [npz(fs=v, fr=f64(FR)), *BEARING], ("refuse", r"\bfs\b"))
           for name, v in fs_bad]
    out += [
        ("fs int 12000", "fs", [npz(fs=np.int64(12000), fr=f64(FR)), *BEARING],
         ("analyse", "bpfi")),
        ("fs as 0-d and 1-element", "fs", [npz(fs=np.array([FS]), fr=f64(FR)), *BEARING],
         ("analyse", "bpfi")),
        ("no fs anywhere", "fs", [npz(fr=f64(FR)), *BEARING], ("refuse", r"--fs")),
        ("no fs, --fs 12000", "fs", [npz(fr=f64(FR)), "--fs", "12000", *BEARING],
         ("analyse", "bpfi")),
        ("fs 6000 in file, --fs 12000 (caller wins)", "fs",
         [npz(fs=f64(6000.0), fr=f64(FR)), "--fs", "12000", *BEARING], ("analyse", "bpfi")),
        ("fs 0 in file, --fs 12000 (caller wins)", "fs",
         [npz(fs=f64(0.0), fr=f64(FR)), "--fs", "12000", *BEARING], ("analyse", "bpfi")),
        ("fs and sampling_rate contradict", "fs",
         [npz(fs=f64(FS), sampling_rate=f64(24000.0), fr=f64(FR)), *BEARING],
         ("refuse", r"\bfs\b.*sampling_rate|sampling_rate.*\bfs\b")),
    ]
    good = npz(fs=f64(FS), fr=f64(FR))
    for v in ("0", "-12000", "nan", "inf", "-inf", "1e-300", "1e300", "abc", "", "12000x",
              "300"):
        # 1e-300, 1e300 and 300 Hz are numbers > 0: refused with the line they cannot hold,
        # which the message gives with its fs ("--fr: 29.95 Hz is at or above the Nyquist
        # frequency ... (fs = 300 Hz)")
        out.append((f"--fs {v!r}", "fs", [good, "--fs", v, *BEARING],
                    ("refuse", r"--fs|fs = |fs/n")))
    fr_bad = [("fr 0", f64(0)), ("fr -29.95", f64(-FR)), ("fr NaN", f64(np.nan)),
              ("fr inf", f64(np.inf)), ("fr [29.95, 29.95]", np.array([FR, FR])),
              ("fr text", np.array("29.95")), ("rpm -1797", f64(-1797.0)),
              ("rpm 0", f64(0.0))]
    for name, v in fr_bad:
        key = "rpm" if name.startswith("rpm") else "fr"
        out.append((name, "shaft rate", [npz(fs=f64(FS), **{key: v}), *BEARING],
                    ("refuse", rf"--fr|\b{key}\b")))
    meta = lambda m: npz(fs=f64(FS), meta_json=np.array(m))  # noqa: E731
    out += [
        ("no shaft rate anywhere", "shaft rate", [npz(fs=f64(FS)), *BEARING],
         ("refuse", r"--fr")),
        ("rpm 1797 (29.95 Hz)", "shaft rate", [npz(fs=f64(FS), rpm=f64(1797.0)), *BEARING],
         ("analyse", "bpfi")),
        ("fr and rpm contradict (29.95 Hz, 900 rpm)", "shaft rate",
         [npz(fs=f64(FS), fr=f64(FR), rpm=f64(900.0)), *BEARING],
         ("refuse", r"\bfr\b.*rpm|rpm.*\bfr\b")),
        ("fr and shaft_hz contradict", "shaft rate",
         [npz(fs=f64(FS), fr=f64(FR), shaft_hz=f64(15.0)), *BEARING],
         ("refuse", r"\bfr\b.*shaft_hz|shaft_hz.*\bfr\b")),
        ("meta_json shaft_hz 29.95", "meta_json", [meta(json.dumps({"shaft_hz": FR})),
                                                   *BEARING], ("analyse", "bpfi")),
        ("meta_json shaft_hz -29.95", "meta_json", [meta(json.dumps({"shaft_hz": -FR})),
                                                    *BEARING], ("refuse", r"fr|shaft_hz")),
        ("meta_json shaft_hz 0", "meta_json", [meta(json.dumps({"shaft_hz": 0})), *BEARING],
         ("refuse", r"fr|shaft_hz")),
        ("meta_json shaft_hz text", "meta_json",
         [meta(json.dumps({"shaft_hz": "fast"})), *BEARING], ("refuse", r"shaft_hz")),
        ("meta_json shaft_hz list", "meta_json",
         [meta(json.dumps({"shaft_hz": [FR]})), *BEARING], ("refuse", r"shaft_hz")),
        ("meta_json shaft_hz true", "meta_json",
         [meta(json.dumps({"shaft_hz": True})), *BEARING], ("refuse", r"shaft_hz")),
        ("meta_json shaft_hz 1e999 (inf)", "meta_json", [meta('{"shaft_hz": 1e999}'),
                                                         *BEARING], ("refuse", r"fr|shaft_hz")),
        ("meta_json shaft_hz NaN", "meta_json", [meta('{"shaft_hz": NaN}'), *BEARING],
         ("refuse", r"fr|shaft_hz")),
        ("meta_json not JSON", "meta_json", [meta("{shaft_hz: 29.95"), *BEARING],
         ("refuse", r"meta_json")),
        ("meta_json a list", "meta_json", [meta("[29.95]"), *BEARING],
         ("refuse", r"meta_json")),
        ("meta_json a number array", "meta_json",
         [npz(fs=f64(FS), fr=f64(FR), meta_json=np.arange(3.0)), *BEARING],
         ("refuse", r"meta_json")),
        ("meta_json 2 texts", "meta_json",
         [npz(fs=f64(FS), fr=f64(FR), meta_json=np.array(["{}", "{}"])), *BEARING],
         ("refuse", r"meta_json")),
        ("meta_json contradicts fr (15 vs 29.95)", "meta_json",
         [npz(fs=f64(FS), fr=f64(FR), meta_json=np.array(json.dumps({"shaft_hz": 15.0}))),
          *BEARING], ("refuse", r"shaft_hz.*\bfr\b|\bfr\b.*shaft_hz")),
        ("meta_json agrees with fr", "meta_json",
         [npz(fs=f64(FS), fr=f64(FR), meta_json=np.array(json.dumps({"shaft_hz": FR}))),
          *BEARING], ("analyse", "bpfi")),
        ("meta_json without shaft_hz, --fr", "meta_json",
         [meta(json.dumps({"load_hp": 1})), "--fr", str(FR), *BEARING], ("analyse", "bpfi")),
        ("meta_json 1 MB of nesting", "meta_json", [meta("[" * 100000 + "]" * 100000),
                                                    *BEARING], ("refuse", r"meta_json")),
    ]
    good = npz(fs=f64(FS))
    for v in ("0", "-29.95", "nan", "inf", "1e-300", "1e300", "abc", "7000", "0.001"):
        out.append((f"--fr {v!r}", "shaft rate", [good, "--fr", v, *BEARING],
                    ("refuse", r"--fr|--bearing")))
    out.append(("--fr 29.95 over file's 15 Hz (caller wins)", "shaft rate",
                [npz(fs=f64(FS), fr=f64(15.0)), "--fr", str(FR), *BEARING],
                ("analyse", "bpfi")))
    return out


def bearing_cases(w: Writer) -> list:
    """Designations and geometries."""
    f = w.npz(x=inner(), fs=np.float64(FS), fr=np.float64(FR))
    out = []
    for v, ok in (("6205", True), ("SKF 6205-2RS", True), ("skf 6205-2rs", True),
                  (" 6205 ", True), ("9999", False), ("", False), ("6205\x01", False),
                  ("../../etc/passwd", False), ("\uff16\uff12\uff10\uff15", False),
                  ("6205" * 2500, False), ("6205; rm -rf /", False), ("6205\n6203", False),
                  ("None", False), ("-1", False), ("6203", None)):
        if ok is True:
            exp = ("analyse", "bpfi")
        elif ok is None:   # the wrong bearing: the 6203's lines are not the record's
            exp = ("analyse", None)
        else:
            exp = ("refuse", r"--bearing")
        out.append((f"--bearing {v[:20]!r}", "bearing", [f, "--bearing", v], exp))
    geo = ["--n-rollers", "9", "--roller-diameter-mm", "7.94", "--pitch-diameter-mm", "39.04"]
    out.append(("geometry of the 6205 (mm)", "bearing", [f, *geo], ("analyse", "bpfi")))
    out.append(("geometry of the 6205 (inch)", "bearing",
                [f, "--n-rollers", "9", "--roller-diameter-in", "0.3126",
                 "--pitch-diameter-in", "1.537"], ("analyse", "bpfi")))

    def bad(label, args, rx):
        out.append((label, "bearing", [f, *args], ("refuse", rx)))

    def geo_with(opt, v):
        g = list(geo)
        if opt in g:
            g[g.index(opt) + 1] = v
        else:
            g += [opt, v]
        return g
    for opt, vals in (("--n-rollers", ("0", "-3", "1", "100000", "2.5", "x")),
                      ("--roller-diameter-mm", ("0", "-7.94", "nan", "inf", "39.04", "50",
                                                "1e-300")),
                      ("--pitch-diameter-mm", ("0", "-1", "nan", "inf", "7.94", "1e300")),
                      ("--contact-angle-deg", ("90", "89.999", "-1", "180", "nan", "1e300"))):
        for v in vals:
            if (opt, v) == ("--contact-angle-deg", "89.999"):   # allowed: [0, 90)
                out.append((f"{opt} {v}", "bearing", [f, *geo_with(opt, v)],
                            ("analyse", None)))   # BPFO = BPFI = 4.5 fr: not the record's
                continue
            bad(f"{opt} {v}", geo_with(opt, v), re.escape(opt) + r"|roller|pitch")
    bad("geometry without --n-rollers", geo[2:], r"--n-rollers")
    bad("geometry without --pitch-diameter-mm", geo[:4], r"--pitch-diameter")
    bad("--bearing and geometry", ["--bearing", "6205", *geo], r"--bearing|--n-rollers")
    bad("mm and inch", [*geo, "--roller-diameter-in", "0.3126"], r"--roller-diameter")
    bad("no fault frequency at all", [], r"--bpfi|--fault|--bearing")
    return out


def option_cases(w: Writer) -> list:
    """Bands, fixed bands, the chain's options, fault lines, routes."""
    f = w.npz(x=inner(), fs=np.float64(FS), fr=np.float64(FR))
    out = []

    def case(label, args, exp, cls="options"):
        out.append((label, cls, [f, *BEARING, *args], exp))

    def bad(label, args, rx, cls="options"):
        case(label, args, ("refuse", rx), cls)
    band = lambda **kw: json.dumps([{"name": "b", "strategy": "fixed", **kw}])  # noqa: E731
    for label, text in (("[]", "[]"), ("{}", "{}"), ("not JSON", "[{"), ("a number", "5"),
                        ("list of numbers", "[1, 2]"), ("null", "null"),
                        ("low > high", band(low_hz=4000, high_hz=2000)),
                        ("negative low", band(low_hz=-100, high_hz=2000)),
                        ("above Nyquist", band(low_hz=7000, high_hz=9000)),
                        ("NaN edge", '[{"name": "b", "strategy": "fixed", "low_hz": NaN, '
                                     '"high_hz": 2000}]'),
                        ("text edge", band(low_hz="low", high_hz=2000)),
                        ("unknown strategy", json.dumps([{"name": "b", "strategy": "magic"}])),
                        ("no strategy", json.dumps([{"name": "b"}])),
                        ("unknown key", band(low_hz=2000, high_hz=4000, colour="red")),
                        ("duplicate names", json.dumps([{"name": "b", "strategy": "kurtogram"},
                                                        {"name": "b", "strategy": "kurtogram"}])),
                        ("zero width", band(low_hz=3000, high_hz=3000))):
        bad(f"--bands {label}", ["--bands", text], r"--bands")
    case("--bands one fixed 2-4 kHz", ["--bands", band(low_hz=2000, high_hz=4000)],
         ("analyse", "bpfi"))
    case("--bands without a name (named after its strategy)",
         ["--bands", json.dumps([{"strategy": "kurtogram"}])], ("analyse", "bpfi"))
    case("--bands a name of 10k characters",
         ["--bands", json.dumps([{"name": "b" * 10000, "strategy": "kurtogram"}])],
         ("analyse", "bpfi"))
    # 1 Hz wide: its envelope holds nothing above 1 Hz, so no line: right for that band
    case("--bands 1 Hz wide", ["--bands", band(low_hz=3000, high_hz=3001)], ("analyse", None))
    bfile = w.raw(b"", ".yaml")
    bad("--bands empty file", ["--bands", bfile], r"--bands")
    bad("--bands binary file", ["--bands", w.raw(bytes(range(256)) * 8, ".yaml")], r"--bands")
    bad("--bands a folder", ["--bands", str(w.work)], r"--bands")
    bad("--bands /dev/null", ["--bands", "/dev/null"], r"--bands")
    bad("--bands YAML alias bomb", ["--bands", w.raw(
        ("a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
            f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n" for i in range(1, 9))).encode(),
        ".yaml")], r"--bands")
    for lo, hi in (("5000", "4000"), ("-1", "10"), ("nan", "2000"), ("0", "inf"),
                   ("7000", "8000"), ("0", "1e9"), ("3000", "3000")):
        bad(f"--fixed-band {lo} {hi}", ["--fixed-band", lo, hi], r"--fixed-band")
    case("--fixed-band 2000 4000", ["--fixed-band", "2000", "4000"], ("analyse", "bpfi"))
    case("--fixed-band 0 6000 (full band)", ["--fixed-band", "0", "6000"], ("analyse", "bpfi"))
    case("--fixed-band 1000 9000 --clamp", ["--fixed-band", "1000", "9000", "--clamp"],
         ("analyse", "bpfi"))
    for opt, vals in (("--nlevel", ("0", "-1", "100", "1.5")),
                      ("--harmonics", ("0", "-1", "1000")),
                      ("--sidebands", ("-1", "1000")),
                      ("--raw-harmonics", ("0", "1000000")),
                      ("--search-percent", ("0", "-5", "100", "nan", "inf")),
                      ("--pfa", ("0", "1", "2", "nan", "-0.01")),
                      ("--filter-order", ("0", "-2", "1000")),
                      ("--max-level", ("-1", "nan", "1e300")),
                      ("--min-bandwidth", ("-1", "nan", "1e9")),
                      ("--window", ("nonsense", "", "kaiser", "('kaiser', 'x')", "boxcar;rm")),
                      ("--level0", ("imaginary",)),
                      ("--routes", ("magic", ",", "envelope,,magic", "")),
                      ("--fmax", ("0", "-1", "nan")),
                      ("--jobs", ("-1", "100000"))):
        for v in vals:
            bad(f"{opt} {v!r}", [opt, v], re.escape(opt))
    for v in ("bpfi=nan", "bpfi=-1", "bpfi=0", "fr=10", "dc=5", "=5", "bpfi", "bpfi=abc",
              "x=1e300", "1abc=5", "bpfi=7000", "bpfi=0.001"):
        bad(f"--fault {v!r}", ["--fault", v], r"--fault|--bearing")
    case("--fault bpfi=162.19 (same as the bearing's)", ["--fault", f"bpfi={BPFI_X * FR}"],
         ("analyse", "bpfi"))
    case("--routes envelope", ["--routes", "envelope"], ("analyse", "bpfi"))
    case("--window hamming", ["--window", "hamming"], ("analyse", "bpfi"))
    case("--nlevel 3", ["--nlevel", "3"], ("analyse", "bpfi"))
    case("--harmonics 1", ["--harmonics", "1"], ("analyse", "bpfi"))
    case("--speed nominal", ["--speed", "nominal"], ("analyse", "bpfi"))
    # a half-width of 1e-300 % is a number in (0, 50): the nearest bin is searched
    case("--search-percent 1e-300", ["--search-percent", "1e-300"], ("analyse", "bpfi"))
    for opt in ("--csv", "--table", "--html", "--json"):
        for label, target in (("a folder", str(w.work)), ("/dev/full", "/dev/full"),
                              ("/proc/x", "/proc/self/x"), ("under a file", f + "/out")):
            bad(f"{opt} {label}", [opt, target], re.escape(opt), "outputs")
    bad("--plot a file", ["--plot", f], r"--plot", "outputs")
    return out


def csv_cases(w: Writer) -> list:
    """CSV dialects and time columns."""
    x = inner()
    t = _t()
    fr = ["--fr", str(FR), *BEARING]
    out = []

    def case(label, path, exp, extra=()):
        out.append((label, "csv", [path, *fr, *extra], exp))
    case("control: time,x (9 digits)", w.csv(zip(t, x)), ("analyse", "bpfi"))
    case("time to 6 decimals", w.csv(zip(t, x), fmt=lambda v: f"{v:.6f}"), ("analyse", "bpfi"))
    case("time to 6 decimals, --fs 12000", w.csv(zip(t, x), fmt=lambda v: f"{v:.6f}"),
         ("analyse", "bpfi"), ("--fs", "12000"))
    case("time to 3 decimals (1 ms)", w.csv(zip(t, x), fmt=lambda v: f"{v:.3f}"),
         ("refuse", r"time column"))
    case("time to 3 decimals, --fs 12000", w.csv(zip(t, x), fmt=lambda v: f"{v:.3f}"),
         ("analyse", "bpfi"), ("--fs", "12000"))
    case("no time column, no --fs", w.csv(((v,) for v in x), header="x"), ("refuse", r"--fs"))
    case("no time column, --fs 12000", w.csv(((v,) for v in x), header="x"),
         ("analyse", "bpfi"), ("--fs", "12000"))
    case("no header, one column, --fs", w.csv(((v,) for v in x), header=None),
         ("analyse", "bpfi"), ("--fs", "12000"))
    jit = t.copy()
    jit[N // 2:] += 5e-6
    case("a 6 % long step", w.csv(zip(jit, x)), ("refuse", r"time column.*--fs"))
    case("a 6 % long step, --fs 12000", w.csv(zip(jit, x)), ("analyse", "bpfi"),
         ("--fs", "12000"))
    gap = t.copy()
    gap[N // 2:] += 1.0
    case("a 1 s gap in time", w.csv(zip(gap, x)), ("refuse", r"time column"))
    case("time decreasing", w.csv(zip(t[::-1], x)), ("refuse", r"time column"))
    dup = t.copy()
    dup[10] = dup[9]
    case("a repeated time", w.csv(zip(dup, x)), ("refuse", r"time column"))
    tn = t.astype(object)
    tn[50] = "nan"
    case("NaN in time", w.csv(zip(tn, x)), ("refuse", r"time"))
    case("time in ms named time", w.csv(zip(t * 1000, x)),
         ("refuse", r"--fr.*fs = 12 Hz"))  # read as a 12 Hz record: 29.95 Hz above Nyquist
    case("time only", w.csv(((v,) for v in t), header="time"), ("refuse", r"column|signal"))
    case("two data columns", w.csv(zip(t, x, x), header="time,a,b"), ("refuse", r"--column"))
    case("two data columns, --column b", w.csv(zip(t, x, x), header="time,a,b"),
         ("analyse", "bpfi"), ("--column", "b"))
    case("--column 7 of 3", w.csv(zip(t, x, x), header="time,a,b"), ("refuse", r"--column"),
         ("--column", "7"))
    case("--column missing name", w.csv(zip(t, x)), ("refuse", r"--column"),
         ("--column", "nope"))
    case("semicolons, decimal commas", w.csv(zip(t, x), header="time;x", sep=";",
                                             fmt=lambda v: f"{v:.9f}".replace(".", ",")),
         ("analyse", "bpfi"))
    case("ambiguous commas", w.csv(((f"{int(v * 1000)}",) for v in np.abs(x[:2000]) + 1),
                                   header=None),
         ("refuse", r"--delimiter|--decimal|--fs"))
    for name, at, cell, want in (("a word among the samples", 1234, "abc", r"'x'.*line"),
                                 ("'nan' among the samples", 20, "nan", r"non-finite"),
                                 ("1e400 among the samples", 20, "1e400", r"non-finite|'x'"),
                                 ("an empty cell", 20, "", r"'x'|line")):
        xc = x.astype(object)
        xc[at] = cell
        case(name, w.csv(zip(t, xc)), ("refuse", want))
    case("empty file", w.raw(b"", ".csv"), ("refuse", r"data line|CSV"))
    case("header only", w.raw(b"time,x\n", ".csv"), ("refuse", r"data line"))
    case("one line", w.raw(b"0.0,1.0\n", ".csv"), ("refuse", r"samples|--fs|time column|"
                                                             r"--column"))
    case("binary garbage .csv", w.raw(bytes(np.random.default_rng(5).integers(0, 256, 70000,
                                                                              dtype=np.uint8)),
                                      ".csv"), ("refuse", r"UTF-8|CSV"))
    case("UTF-16 CSV", w.raw(("time,x\n" + "".join(f"{a:.9g},{b:.9g}\n" for a, b in
                                                   zip(t[:4000], x[:4000]))).encode("utf-16"),
                             ".csv"), ("refuse", r"UTF-8|CSV"))
    case("BOM and CRLF", w.raw(b"\xef\xbb\xbf" + ("time,x\r\n" + "".join(
        f"{a:.9g},{b:.9g}\r\n" for a, b in zip(t, x))).encode(), ".csv"), ("analyse", "bpfi"))
    case("one 10 MB line", w.raw(b"x\n" + b"1" * 10_000_000 + b"\n", ".csv"),
         ("refuse", r"."), ("--fs", "12000"))
    case("ragged rows", w.raw(("time,x\n" + "".join(
        f"{a:.9g},{b:.9g}" + (",5\n" if i == 300 else "\n") for i, (a, b) in
        enumerate(zip(t, x)))).encode(), ".csv"), ("refuse", r"CSV|line|field"))
    case("quoted numbers", w.raw(("time,x\n" + "".join(
        f'"{a:.9g}","{b:.9g}"\n' for a, b in zip(t, x))).encode(), ".csv"), ("analyse", "bpfi"))
    case("comment lines", w.raw(("# recorded 2026\ntime,x\n" + "".join(
        f"{a:.9g},{b:.9g}\n" for a, b in zip(t, x))).encode(), ".csv"), ("analyse", "bpfi"))
    case("time to 6 decimals at 48 kHz", w.csv(zip(np.arange(4 * N) / 48000.0,
                                                   impacts(BPFI_X * FR, fs=48000.0, n=4 * N)),
                                               fmt=lambda v: f"{v:.6f}"), ("analyse", "bpfi"))
    case("--delimiter ';' on a comma file", w.csv(zip(t, x)), ("refuse", r"--delimiter|--fs|CSV|column"),
         ("--delimiter", ";"))
    case("--decimal ',' on a comma file", w.csv(zip(t, x)), ("refuse", r"--decimal"),
         ("--decimal", ","))
    return out


def file_cases(w: Writer) -> list:
    """Broken, truncated, garbage and strange files of every type; pickles; paths."""
    x = inner()
    fr = ["--fr", str(FR), *BEARING]
    out = []

    def case(label, cls, path, exp, extra=(), with_fr=True):
        out.append((label, cls, [path, *(fr if with_fr else BEARING), *extra], exp))
    good = w.npz(x=x, fs=np.float64(FS))
    blob = Path(good).read_bytes()
    garbage = bytes(np.random.default_rng(7).integers(0, 256, 4096, dtype=np.uint8))
    for suffix in (".npz", ".npy", ".mat", ".wav", ".h5"):
        case(f"empty {suffix}", "file", w.raw(b"", suffix), ("refuse", r"file"))
        case(f"garbage {suffix}", "file", w.raw(garbage, suffix), ("refuse", r"file"))
    case("truncated .npz (half)", "file", w.raw(blob[: len(blob) // 2], ".npz"),
         ("refuse", r"file"))
    case("truncated .npz (100 bytes)", "file", w.raw(blob[:100], ".npz"), ("refuse", r"file"))
    case(".npz with no arrays", "file", w.raw(_zip({"readme.txt": b"hi"}), ".npz"),
         ("refuse", r"file.*no arrays"))
    case(".npz member with a broken header", "file",
         w.raw(_zip({"x.npy": b"\x93NUMPY\x01\x00\x10\x00{'descr': <f8"}), ".npz"),
         ("refuse", r"'x'|member"))
    case(".npz zip bomb (1 GB of zeros declared)", "file", _zip_bomb(w), ("refuse", r"file|'x'"))
    case(".npz, x pickled (object array)", "pickle",
         w.npz(x=np.array([_Witness()] * 3, dtype=object), fs=np.float64(FS)),
         ("refuse", r"'x'|objects|no numeric"))
    case(".npz, fs pickled", "pickle",
         w.npz(x=x, fs=np.array([_Witness()], dtype=object)), ("refuse", r"\bfs\b"))
    case(".npz, meta_json pickled", "pickle",
         w.npz(x=x, fs=np.float64(FS), meta_json=np.array([_Witness()], dtype=object)),
         ("refuse", r"meta_json"))
    case(".npz, a pickled extra member", "pickle",
         w.npz(x=x, fs=np.float64(FS), extra=np.array([_Witness(), 1], dtype=object)),
         ("analyse", "bpfi"))
    case(".npy pickled", "pickle", w.npy(np.array([_Witness()] * 3, dtype=object)),
         ("refuse", r"objects"), ("--fs", "12000"))
    case("control: .npy 1-D", "file", w.npy(x), ("analyse", "bpfi"), ("--fs", "12000"))
    case(".npy without --fs", "file", w.npy(x), ("refuse", r"--fs"))
    case(".npy 2-D, no --column", "file", w.npy(np.column_stack([x, x, x])),
         ("refuse", r"--column"), ("--fs", "12000"))
    case(".npy 2-D, --column 1", "file", w.npy(np.column_stack([noise(), x, noise()])),
         ("analyse", "bpfi"), ("--fs", "12000", "--column", "1"))
    case(".npy Fortran order 2-D, --column 0", "file",
         w.npy(np.asfortranarray(np.column_stack([x, noise()]))), ("analyse", "bpfi"),
         ("--fs", "12000", "--column", "0"))
    case(".npy 0-d", "file", w.npy(np.float64(1.0)), ("refuse", r"file|1-D"),
         ("--fs", "12000"))
    case(".npy (N, 1)", "file", w.npy(x[:, None]), ("analyse", "bpfi"), ("--fs", "12000"))
    arr = Path(w.npy(x)).read_bytes()
    case(".npy truncated", "file", w.raw(arr[: len(arr) // 3], ".npy"), ("refuse", r"truncated"),
         ("--fs", "12000"))
    case(".npy header only", "file", w.raw(arr[:128], ".npy"), ("refuse", r"file"),
         ("--fs", "12000"))
    case(".npy header claims 1e12 samples", "file",
         w.raw(_npy_header((10 ** 12,)) + arr[128:], ".npy"), ("refuse", r"file"),
         ("--fs", "12000"))
    case(".npy sparse 8 GB", "file", _sparse_npy(w, 10 ** 9), ("refuse", r"memory|file"),
         ("--fs", "12000"))
    case(".npy version 3 header", "file", w.raw(_npy_header((N,), version=3) + x.tobytes(),
                                                 ".npy"), ("analyse", "bpfi"),
         ("--fs", "12000"))
    case(".npy a lying descr '<c16'", "file", w.raw(_npy_header((N // 2,), descr="<c16")
                                                     + x.tobytes(), ".npy"),
         ("refuse", r"complex"), ("--fs", "12000"))
    case(".npy descr 'O' with data", "pickle", w.raw(_npy_header((3,), descr="|O")
                                                      + b"\x00" * 24, ".npy"),
         ("refuse", r"objects"), ("--fs", "12000"))
    case(".npy header with code", "file",
         w.raw(_npy_header_text("{'descr': __import__('os').system('touch "
                                + str(PICKLE_WITNESS) + "'), 'fortran_order': False, "
                                "'shape': (3,), }") + b"\x00" * 24, ".npy"),
         ("refuse", r"header"), ("--fs", "12000"))
    # MATLAB
    cw = {"X105_DE_time": x[:, None], "X105_FE_time": noise()[:, None],
          "X105RPM": np.array([[1797.0]])}
    case("control: CWRU .mat (DE, RPM)", "mat", w.mat(**cw), ("analyse", "bpfi"),
         ("--fs", "12000"), with_fr=False)
    case("CWRU .mat, --channel BA missing", "mat", w.mat(**cw), ("refuse", r"--channel"),
         ("--fs", "12000", "--channel", "BA"), with_fr=False)
    case("CWRU .mat, RPM 0", "mat", w.mat(**{**cw, "X105RPM": np.array([[0.0]])}),
         ("refuse", r"--fr|\bfr\b|RPM"), ("--fs", "12000"), with_fr=False)
    case("CWRU .mat, RPM NaN", "mat", w.mat(**{**cw, "X105RPM": np.array([[np.nan]])}),
         ("refuse", r"--fr|\bfr\b|RPM"), ("--fs", "12000"), with_fr=False)
    case("CWRU .mat, RPM a text", "mat", w.mat(**{**cw, "X105RPM": "1797"}),
         ("refuse", r"--fr|RPM"), ("--fs", "12000"), with_fr=False)
    case("CWRU .mat, no fs", "mat", w.mat(**cw), ("refuse", r"--fs"), with_fr=False)
    case(".mat, fs variable 0", "mat", w.mat(sig=x, fs=0.0), ("refuse", r"\bfs\b"))
    case(".mat, fs variable [12000 12000]", "mat", w.mat(sig=x, fs=np.array([FS, FS])),
         ("refuse", r"\bfs\b"))
    case(".mat, fs a text", "mat", w.mat(sig=x, fs="12000"), ("refuse", r"\bfs\b"))
    case(".mat, a cell", "mat", w.mat(c=np.array([x, x], dtype=object), fs=FS),
         ("refuse", r"file|variable|signal"))
    case(".mat, a struct", "mat", w.mat(s={"a": x}, fs=FS), ("refuse", r"file|variable"))
    case(".mat, two signals", "mat", w.mat(a=x, b=x, fs=FS), ("refuse", r"--column"))
    case(".mat, a 2-D matrix", "mat", w.mat(a=np.vstack([x, x]), fs=FS),
         ("refuse", r"'a'.*shape"))
    case(".mat, complex", "mat", w.mat(a=x.astype(complex), fs=FS), ("refuse", r"complex"))
    case(".mat, a time vector", "mat", w.mat(a=x, time=_t()), ("analyse", "bpfi"))
    tj = _t().copy()
    tj[N // 2:] += 5e-6
    case(".mat, an uneven time vector", "mat", w.mat(a=x, time=tj),
         ("refuse", r"time.*--fs"))
    case(".mat, an uneven time vector, --fs", "mat", w.mat(a=x, time=tj),
         ("analyse", "bpfi"), ("--fs", "12000"))
    case(".mat v7.3 (HDF5)", "mat", _h5(w, ".mat"), ("refuse", r"v7\.3|file"))
    # WAV
    case("control: .wav int16", "wav", w.wav(x), ("analyse", "bpfi"))
    case(".wav float32", "wav", w.wav(x, dtype=np.float32), ("analyse", "bpfi"))
    case(".wav stereo, no --column", "wav", w.wav(x, channels=2), ("refuse", r"--column"))
    case(".wav stereo, --column 1", "wav", w.wav(x, channels=2), ("analyse", "bpfi"),
         ("--column", "1"))
    wv = Path(w.wav(x)).read_bytes()
    case(".wav truncated", "wav", w.raw(wv[: len(wv) // 2], ".wav"), ("refuse", r"truncated"))
    case(".wav header only", "wav", w.raw(wv[:44], ".wav"), ("refuse", r"file"))
    case(".wav rate 0", "wav", w.raw(_wav_rate(wv, 0), ".wav"), ("refuse", r"\bfs\b|rate"))
    case(".wav rate 1 Hz", "wav", w.raw(_wav_rate(wv, 1), ".wav"), ("refuse", r"\bfs\b|--fr|"
                                                                            r"--bearing|Nyquist"))
    case(".wav rate 4e9 Hz", "wav", w.raw(_wav_rate(wv, 4_000_000_000), ".wav"),
         ("refuse", r"\bfs\b|resolution|--fr|nSamplesPerSec"))
    case(".wav rate 0, --fs 12000", "wav", w.raw(_wav_rate(wv, 0), ".wav"),
         ("analyse", "bpfi"), ("--fs", "12000"))
    case(".wav 8-bit", "wav", _wav8(w, x), ("analyse", "bpfi"))
    case(".wav chunk size 4 GB", "wav", w.raw(wv[:40] + b"\xff\xff\xff\xff" + wv[44:], ".wav"),
         ("refuse", r"file"))
    # case files
    case("HDF5 that is not a case file", "h5", _h5(w, ".h5"), ("refuse", r"file|case"))
    # paths
    case("unsupported suffix .txt", "path", w.raw(b"1\n2\n", ".txt"), ("refuse", r"file.*\.txt"))
    case("no suffix", "path", w.raw(blob, ""), ("refuse", r"file"))
    case("upper-case .NPZ", "path", w.raw(blob, ".NPZ"), ("analyse", "bpfi"))
    case("nonexistent file", "path", str(w.work / "nope.npz"), ("refuse", r"nope\.npz"))
    d = w.work / "adir.npz"
    d.mkdir()
    case("a folder named .npz", "path", str(d), ("refuse", r"file.*directory|folder"))
    empty_dir = w.work / "emptydir"
    empty_dir.mkdir()
    case("an empty folder", "path", str(empty_dir), ("refuse", r"file.*empty"))
    link = w.path(".npz")
    os.symlink(good, link)
    case("symlink to a good record", "path", str(link), ("analyse", "bpfi"))
    dangling = w.path(".npz")
    os.symlink(w.work / "gone.npz", dangling)
    case("dangling symlink", "path", str(dangling), ("refuse", r"file|no such"))
    loop = w.path(".npz")
    os.symlink(loop, loop)
    case("symlink loop", "path", str(loop), ("refuse", r"file|symbolic|loop"))
    for dev, suffix in (("/dev/zero", ".npy"), ("/dev/zero", ".csv"), ("/dev/urandom", ".csv"),
                        ("/dev/null", ".npz"), ("/dev/zero", ".wav"), ("/dev/zero", ".mat"),
                        ("/dev/zero", ".h5")):
        ln = w.path(suffix)
        os.symlink(dev, ln)
        case(f"symlink to {dev} as {suffix}", "path", str(ln), ("refuse", r"file"),
             ("--fs", "12000"))
    fifo = w.path(".csv")
    os.mkfifo(fifo)
    case("a FIFO named .csv", "path", str(fifo), ("refuse", r"file"), ("--fs", "12000"))
    fifo2 = w.path(".npz")
    os.mkfifo(fifo2)
    case("a FIFO named .npz", "path", str(fifo2), ("refuse", r"file"))
    odd = w.work / "name with\nnewline.npz"
    odd.write_bytes(blob)
    case("a newline in the file name", "path", str(odd), ("analyse", "bpfi"))
    case("/proc/self/status as .csv", "path", _link(w, "/proc/self/status", ".csv"),
         ("refuse", r"file"), ("--fs", "12000"))
    # manifests and folders (several records)
    man = w.raw(b"", ".csv")
    out.append(("empty manifest", "manifest", ["--manifest", man, *fr],
                ("refuse", r"--manifest")))
    out.append(("manifest without a file column", "manifest",
                ["--manifest", w.raw(b"path,fs\na.npz,12000\n", ".csv"), *fr],
                ("refuse", r"--manifest.*file")))
    out.append(("manifest fs -1", "manifest",
                ["--manifest", w.raw(f"file,fs\n{good},-1\n".encode(), ".csv"), *fr],
                ("refuse", r"--manifest.*fs")))
    out.append(("manifest bearing 9999", "manifest",
                ["--manifest", w.raw(f"file,bearing\n{good},9999\n".encode(), ".csv"), *fr],
                ("refuse", r"--manifest.*9999")))
    out.append(("manifest channel XX", "manifest",
                ["--manifest", w.raw(f"file,channel\n{good},XX\n".encode(), ".csv"), *fr],
                ("refuse", r"--manifest.*channel")))
    out.append(("manifest a folder", "manifest", ["--manifest", str(w.work), *fr],
                ("refuse", r"--manifest")))
    out.append(("manifest binary", "manifest", ["--manifest", w.raw(garbage, ".csv"), *fr],
                ("refuse", r"--manifest")))
    return out


# ---------------------------------------------------------------------------- helpers
def _zip(members: dict) -> bytes:
    import io

    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        for k, v in members.items():
            zf.writestr(k, v)
    return buf.getvalue()


def _zip_bomb(w: Writer) -> str:
    """An .npz whose x.npy declares and inflates to 1 GB of float64 zeros (a few MB on disk)."""
    p = w.path(".npz")
    n = 125_000_000
    with zipfile.ZipFile(p, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        with zf.open("x.npy", "w", force_zip64=True) as fh:
            fh.write(_npy_header((n,)))
            block = b"\x00" * (1 << 20)
            left = n * 8
            while left > 0:
                fh.write(block[: min(left, len(block))])
                left -= len(block)
        zf.writestr("fs.npy", _npy_header(()) + np.float64(FS).tobytes())
    return str(p)


def _npy_header_text(d: str, version: int = 1) -> bytes:
    magic = b"\x93NUMPY" + bytes([version, 0])
    body = d.encode("latin-1")
    fmt = "<H" if version == 1 else "<I"
    hlen = len(magic) + struct.calcsize(fmt) + len(body) + 1
    pad = (64 - hlen % 64) % 64
    body = body + b" " * pad + b"\n"
    return magic + struct.pack(fmt, len(body)) + body


def _npy_header(shape: tuple, descr: str = "<f8", version: int = 1) -> bytes:
    return _npy_header_text(f"{{'descr': '{descr}', 'fortran_order': False, "
                            f"'shape': {shape!r}, }}", version)


def _sparse_npy(w: Writer, n: int) -> str:
    p = w.path(".npy")
    with open(p, "wb") as fh:
        fh.write(_npy_header((n,)))
        fh.truncate(fh.tell() + 8 * n)
    return str(p)


def _wav_rate(wv: bytes, rate: int) -> bytes:
    """The same WAV with its fmt chunk's sampling rate (and byte rate) replaced."""
    i = wv.index(b"fmt ") + 8
    channels, bits = struct.unpack("<H", wv[i + 2:i + 4])[0], \
        struct.unpack("<H", wv[i + 14:i + 16])[0]
    byte_rate = (rate * channels * bits // 8) & 0xFFFFFFFF
    return wv[:i + 4] + struct.pack("<II", rate, byte_rate) + wv[i + 12:]


def _wav8(w: Writer, x) -> str:
    p = w.path(".wav")
    with wave.open(str(p), "wb") as fh:
        fh.setnchannels(1)
        fh.setsampwidth(1)
        fh.setframerate(int(FS))
        fh.writeframes(np.round(x / np.max(np.abs(x)) * 100 + 128).astype(np.uint8).tobytes())
    return str(p)


def _h5(w: Writer, suffix: str) -> str:
    import h5py

    p = w.path(suffix)
    with h5py.File(p, "w") as fh:
        fh["x"] = inner()
        fh.attrs["fs"] = FS
    return str(p)


def _link(w: Writer, target: str, suffix: str) -> str:
    p = w.path(suffix)
    os.symlink(target, p)
    return str(p)


def generate(work: Path) -> list:
    """Write the hostile set under ``work``: ``[(name, class, argv, expect)]``."""
    w = Writer(work)
    out = []
    for make in (signal_cases, rate_cases, bearing_cases, option_cases, csv_cases, file_cases):
        out += make(w)
    return out


#: The ``--quick`` subset (names): one of each kind, for the test suite.
QUICK = ("control: inner race (.npz)", "one NaN", "fs [12000, 12000]", "--bands []",
         "a FIFO named .csv", ".npz, x pickled (object array)", "--bearing '9999'")


# ----------------------------------------------------------------------------- running
def run_one(argv: list, work: Path, timeout: float = TIMEOUT_S, src: Path = ROOT / "src"
            ) -> dict:
    """``bearing-envelope analyze ARGV --json OUT`` in a subprocess (the package of ``src``);
    its exit code, stderr, stdout, the JSON verdict, CPU seconds and whether it timed out."""
    out_json = work / "out.json"
    if out_json.exists():
        out_json.unlink()
    want_json = "--json" not in argv
    cmd = [sys.executable, "-m", "bearing_envelope", "analyze", *argv,
           *(["--json", str(out_json)] if want_json else [])]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(src), os.environ.get("PYTHONPATH", "")]), "PYTHONWARNINGS": "default",
        "MPLBACKEND": "Agg"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            stdin=subprocess.DEVNULL, env=env, cwd=str(work),
                            start_new_session=True)
    try:
        so, se = proc.communicate(timeout=timeout)
        hung = False
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        so, se = proc.communicate()
        hung = True
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    verdict = None
    if out_json.exists():
        try:
            verdict = json.loads(out_json.read_text())["verdict"]
        except (ValueError, KeyError):
            verdict = None
    return {"rc": proc.returncode, "stdout": so.decode("utf-8", "replace"),
            "stderr": se.decode("utf-8", "replace"), "verdict": verdict, "cpu_s": cpu,
            "hung": hung}


def classify(expect: tuple, r: dict, unpickled: bool, timeout: float = TIMEOUT_S
             ) -> tuple[str, str]:
    """(class, message) of one run against what the input expects (module docstring)."""
    err = r["stderr"].strip()
    lines = [ln for ln in err.splitlines() if ln.strip()]
    msg = lines[-1] if lines else ""
    if unpickled:
        return "silently wrong", "a pickled object was unpickled (the witness file exists)"
    if r["hung"]:
        return "hang", f"still running after {timeout:g} s (wall)"
    if "Traceback (most recent call last)" in err or r["rc"] not in (0, 1, 2):
        return "traceback", (msg or f"exit code {r['rc']}")
    kind, what = expect
    if r["rc"] == 0:
        fam = (r["verdict"] or {}).get("diagnosis")
        if kind == "refuse":
            return "silently wrong", f"analysed (verdict {fam}); expected a refusal"
        if fam != what:
            return "silently wrong", f"verdict {fam}; expected {what}"
        if lines:
            return "noisy", f"analysed right, but stderr: {msg}"
        return "analysed right", f"verdict {fam}"
    if kind == "analyse":
        return "false refusal", msg
    if len(lines) != 1 and not _argparse_error(lines):
        return "refusal not naming", f"{len(lines)} lines: {msg}"
    if not re.search(what, msg):
        return "refusal not naming", msg
    return "refused", msg


def _argparse_error(lines: list) -> bool:
    """argparse's own refusal of a malformed option value: its usage lines, then one error line
    naming the option (``argument --fs: invalid float value: 'abc'``)."""
    return lines[0].startswith("usage:") and re.search(r"error: argument --", lines[-1]) is not None


def main(argv: list[str] | None = None) -> int:
    """Generate the hostile set, run each input through ``analyze``, print a table.

    Parameters
    ----------
    argv : list of str, optional
        ``[--quick] [--only REGEX] [--classes REGEX] [--out CSV] [--timeout S] [--src DIR]``.

    Returns
    -------
    int
        0 when every input was refused in one line naming its field or analysed right; else 1.
    """
    ap = argparse.ArgumentParser(prog="python -m benchmarks hostile_records",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="the QUICK subset only")
    ap.add_argument("--only", default=None, help="inputs whose name matches this regex")
    ap.add_argument("--classes", default=None, help="inputs whose class matches this regex")
    ap.add_argument("--out", default=None, help="write the per-input results as CSV")
    ap.add_argument("--timeout", type=float, default=TIMEOUT_S, help="seconds per run")
    ap.add_argument("--src", default=str(ROOT / "src"),
                    help="the source tree whose package runs (default this checkout's src; "
                         "another, e.g. an exported older commit, gives its 'before')")
    args = ap.parse_args(argv)
    rows = run_set(quick=args.quick, only=args.only, classes=args.classes,
                   timeout=args.timeout, echo=True, src=Path(args.src))
    if args.out:
        import pandas as pd

        pd.DataFrame(rows).to_csv(args.out, index=False)
    return summary(rows)


def run_set(*, quick: bool = False, only: str | None = None, classes: str | None = None,
            timeout: float = TIMEOUT_S, echo: bool = False, src: Path = ROOT / "src"
            ) -> list[dict]:
    """Generate and run the set (or its quick subset) with the package of ``src``; one row
    per input."""
    rows = []
    with tempfile.TemporaryDirectory(prefix="hostile-records-") as tmp:
        work = Path(tmp)
        cases = generate(work)
        if quick:
            cases = [c for c in cases if c[0] in QUICK]
        if only:
            cases = [c for c in cases if re.search(only, c[0])]
        if classes:
            cases = [c for c in cases if re.search(classes, c[1])]
        for name, cls, argv, expect in cases:
            if PICKLE_WITNESS.exists():
                PICKLE_WITNESS.unlink()
            t0 = time.time()
            r = run_one(argv, work, timeout, src)
            status, msg = classify(expect, r, PICKLE_WITNESS.exists(), timeout)
            rows.append({"name": name, "class": cls, "expect": expect[0], "status": status,
                         "cpu_s": r["cpu_s"], "wall_s": time.time() - t0, "message": msg})
            if echo:
                print(f"{status:>18}  {r['cpu_s']:5.2f} s  {cls:<10} {name[:44]:<44} "
                      f"{msg[:120]}", flush=True)
    return rows


def summary(rows: list[dict]) -> int:
    """Print the table of counts per class and status, and every finding; 1 if any."""
    import pandas as pd

    df = pd.DataFrame(rows)
    table = pd.crosstab(df["class"], df["status"], margins=True, margins_name="total")
    print("\n" + table.to_markdown())
    bad = df[~df["status"].isin(OK)]
    print(f"\n{len(df)} inputs: " + ", ".join(f"{k} {v}" for k, v in
                                                df["status"].value_counts().items())
          + f"; CPU s total {df['cpu_s'].sum():.0f}, max {df['cpu_s'].max():.1f}")
    for _, r in bad.iterrows():
        print(f"  FINDING {r['status']}: {r['name']}: {r['message']}")
    return 1 if len(bad) else 0


def smoke() -> None:
    """Tiny run for the test suite: the quick subset, each refused or analysed right."""
    rows = run_set(quick=True)
    assert len(rows) == len(QUICK), [r["name"] for r in rows]
    bad = [r for r in rows if r["status"] not in OK]
    assert not bad, bad


if __name__ == "__main__":
    sys.path.insert(0, os.fspath(ROOT))
    sys.exit(main(sys.argv[1:]))
