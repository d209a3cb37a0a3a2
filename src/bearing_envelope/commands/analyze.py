"""``bearing-envelope analyze``: envelope analysis of one recording or case file.

Reads a signal (.csv, .npy, .npz, MATLAB .mat, or a case file .h5 written by
bearing-envelope simulate) and runs the envelope-analysis chain: raw spectrum, fast kurtogram,
envelope spectra in every band, and for every fault family (BPFO, BPFI, BSF, 2 x BSF, FTF, or
lines given with --fault NAME=HZ) the peak found within +-1 % (--search-percent) of its nominal
frequency, its harmonics and its own sidebands (fr for BPFI, FTF for BSF, none for BPFO), each
with its height above the local spectral floor. Ends with a verdict per family (detected or
not, at a record-wise false-alarm probability of 1 %, --pfa) and a one-line diagnosis. Fault
frequencies come from --bpfi / --fault, from the bearing geometry (mm or inch), or from a case
file. See docs/signal.md.

Examples::

    bearing-envelope analyze cwru_105.npz --fr 29.95 --n-rollers 9 \\
        --roller-diameter-in 0.3126 --pitch-diameter-in 1.537 --plot figs/
    bearing-envelope analyze accel.csv --fs 12000 --fr 29.95 --fault bpfi=162.2 --column DE
    bearing-envelope analyze rec.npy --fs 12000 --fr 29.95 --bpfi 162.2 --fixed-band 0 6000 --json -
    bearing-envelope analyze results/cases/F500kN_h50um.h5 --csv out.csv --plot figs/
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys

_TIME_NAMES = ("time", "t", "time_s", "times", "seconds")
_FS_NAMES = ("fs", "Fs", "FS", "sampling_rate", "sample_rate", "sampling_frequency")
_MM_PER_INCH = 25.4

#: A frequency given to analyze must lie at least this many bins (fs / n) above 0 Hz: the
#: floor around a line is measured over [0.5, 1.5] x its frequency.
MIN_BINS = 10


def plain_text(text: str) -> str:
    """Help text without reStructuredText markup: ``:func:`x``` -> ``x``, double back-quotes
    and ``::`` removed, escaped backslashes unescaped."""
    text = re.sub(r":[a-z]+:`~?([^`]+)`", r"\1", text)
    text = text.replace("``", "").replace("::", ":").replace("\\\\", "\\")
    return text


def register(subparsers) -> None:
    """Add the ``analyze`` sub-command."""
    doc = __doc__.split("\n\n")
    p = subparsers.add_parser(
        "analyze",
        help="envelope analysis of a recording or case file: every fault family, the real "
             "peaks, a verdict",
        description=plain_text(doc[1]),
        epilog=plain_text("\n\n".join(doc[2:])),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("file", help="signal file: .csv, .npy, .npz, .mat or a case file .h5")
    p.add_argument("--fs", type=float, default=None,
                   help="sampling frequency, Hz (else from the file: a case file, an 'fs' entry "
                        "of .npz/.mat, or a time column of a CSV)")
    p.add_argument("--fr", type=float, default=None, help="shaft rate, Hz (case file: its own)")
    p.add_argument("--bpfi", type=float, default=None,
                   help="inner-race fault frequency, Hz (same as --fault bpfi=HZ)")
    p.add_argument("--fault", action="append", default=None, metavar="NAME=HZ",
                   help="a fault frequency, Hz; repeatable. Names bpfo, bpfi, bsf, bsf2 (2 x "
                        "BSF), ftf get their sidebands (fr for bpfi, ftf for bsf/bsf2, none for "
                        "bpfo/ftf; bsf brings bsf2); other names none. Overrides the geometry's "
                        "value of the same name")
    g = p.add_argument_group("bearing geometry (fault frequencies BPFO, BPFI, FTF, BSF, 2 x BSF)")
    g.add_argument("--n-rollers", type=int, default=None, help="rolling elements per row")
    g.add_argument("--roller-diameter-mm", type=float, default=None, help="roller diameter, mm")
    g.add_argument("--pitch-diameter-mm", type=float, default=None, help="pitch diameter, mm")
    g.add_argument("--roller-diameter-in", type=float, default=None,
                   help="roller diameter, inch (instead of mm)")
    g.add_argument("--pitch-diameter-in", type=float, default=None,
                   help="pitch diameter, inch (instead of mm)")
    g.add_argument("--contact-angle-deg", type=float, default=0.0,
                   help="contact angle, degrees (default 0)")
    p.add_argument("--column", default=None,
                   help="CSV column (name or 0-based index), .npz key, .mat variable, or column "
                        "index of a 2-D .npy")
    p.add_argument("--signal", default="p_max",
                   help="signal of a case file (default p_max; e.g. p_max_defect)")
    p.add_argument("--bands", default=None,
                   help="band list: a YAML/JSON file (a list, or a mapping with a 'bands' key) "
                        "or an inline JSON list; default: kurtogram, fs/4-3fs/8, 3-6 and 10-13 x "
                        "BPFI")
    p.add_argument("--fixed-band", nargs=2, type=float, metavar=("LOW_HZ", "HIGH_HZ"),
                   default=None,
                   help="add a fixed band (Hz); LOW_HZ 0 gives a low-pass, HIGH_HZ = fs/2 means "
                        "up to Nyquist (clamped to 0.98 fs/2, recorded), e.g. --fixed-band 0 "
                        "6000 at fs = 12 kHz is the full band")
    p.add_argument("--clamp", action="store_true",
                   help="clamp a fixed band's upper edge above Nyquist to 0.98 fs/2 instead of "
                        "refusing it")
    p.add_argument("--search-percent", type=float, default=1.0,
                   help="half-width of the search for each fault fundamental, percent of its "
                        "nominal frequency (default 1; real lines sit 0.2-0.7 %% off when the "
                        "nominal speed is not the actual one); harmonics are searched around "
                        "k x the frequency found")
    p.add_argument("--pfa", type=float, default=0.01,
                   help="record-wise false-alarm probability of the verdict (default 0.01); each "
                        "family x band test runs at pfa / number of tests")
    p.add_argument("--harmonics", type=int, default=3, help="harmonics K per family (default 3)")
    p.add_argument("--sidebands", type=int, default=1,
                   help="sidebands M per side of each harmonic (default 1)")
    p.add_argument("--raw-harmonics", type=int, default=1,
                   help="orders of fr and of each fault frequency in the raw spectrum (default 1)")
    p.add_argument("--nlevel", type=int, default=None,
                   help="kurtogram levels (default 8, or as deep as a short signal allows)")
    p.add_argument("--max-level", type=float, default=None, help="kurtogram guard: max level")
    p.add_argument("--min-bandwidth", type=float, default=None,
                   help="kurtogram guard: minimum bandwidth, Hz")
    p.add_argument("--level0", choices=("analytic", "real"), default="analytic",
                   help="kurtosis of the kurtogram's level 0 (whole band): analytic signal "
                        "(default) or the real signal as in Antoni's code (E x^4/(E x^2)^2 - 3)")
    p.add_argument("--filter-order", type=int, default=4, help="Butterworth order (default 4)")
    p.add_argument("--window", default="hann", help="spectrum window (default hann)")
    p.add_argument("--squared", action="store_true", help="squared envelope")
    p.add_argument("--interpolate", action="store_true",
                   help="interpolated, scalloping-corrected peak amplitudes")
    p.add_argument("--csv", default=None, metavar="OUT", help="write the full table as CSV")
    p.add_argument("--json", default=None, metavar="OUT", nargs="?", const="-",
                   help="machine-readable result (frequencies, bands, every line, verdict) as "
                        "JSON to OUT, or alone on stdout with '--json' or '--json -'")
    p.add_argument("--plot", default=None, metavar="DIR",
                   help="write the kurtogram and envelope-spectrum figures (PNG) to DIR")
    p.set_defaults(func=run)


# --------------------------------------------------------------------------------- loading
def _pick(names, column, what, path):
    names = list(names)
    if column is not None:
        if column in names:
            return column
        raise ValueError(f"{path}: no {what} {column!r} (available: {names})")
    if len(names) == 1:
        return names[0]
    raise ValueError(f"{path}: several {what}s {names}; choose one with --column")


def _fs_from_time(t, path):
    import numpy as np

    t = np.asarray(t, dtype=float)
    dt = np.diff(t)
    if t.size < 3 or not np.all(dt > 0):
        raise ValueError(f"{path}: the time column is not increasing; give --fs")
    step = float(np.median(dt))
    if np.max(np.abs(dt - step)) > 1e-3 * step:
        raise ValueError(f"{path}: the time column is not uniformly sampled; give --fs")
    return 1.0 / step


def load_signal(path: str, *, column=None, signal: str = "p_max") -> dict:
    """Read a 1-D signal and whatever the file says about it.

    Returns ``{"x": ndarray, "fs": float | None, "fr": float | None, "bpfi": float | None,
    "source": str}``.
    """
    import numpy as np

    if not os.path.exists(path):
        raise FileNotFoundError(f"no such file: {path}")
    ext = os.path.splitext(path)[1].lower()
    out = {"fs": None, "fr": None, "bpfi": None}
    if ext in (".h5", ".hdf5"):
        from bearing_envelope.io import read_case  # lazy: a separate layer, HDF5 only

        case = read_case(path)
        signals = dict(getattr(case, "signals", {}) or {})
        if signal not in signals and getattr(case, signal, None) is not None:
            signals[signal] = getattr(case, signal)
        if signal not in signals:
            raise ValueError(f"{path}: no signal {signal!r} (available: {sorted(signals)})")
        out.update(x=np.asarray(signals[signal], dtype=float), fs=float(case.fs),
                   fr=float(case.fr), bpfi=float(case.bpfi), source=f"case:{signal}")
        return out
    if ext == ".csv":
        import pandas as pd

        df = pd.read_csv(path)
        if all(_is_number(c) for c in df.columns):  # no header line
            df = pd.read_csv(path, header=None)
            df.columns = [str(c) for c in df.columns]
        cols = [str(c) for c in df.columns]
        df.columns = cols
        tcols = [c for c in cols if c.strip().lower() in _TIME_NAMES]
        data_cols = [c for c in cols if c not in tcols]
        if column is not None and column not in cols and str(column).lstrip("-").isdigit():
            if not -len(cols) <= int(column) < len(cols):
                raise ValueError(f"--column: index {column} is out of range; {path} has "
                                 f"{len(cols)} columns {cols} (0-based)")
            column = cols[int(column)]
        name = _pick(data_cols if column is None else cols, column, "column", path)
        out["x"] = pd.to_numeric(df[name], errors="raise").to_numpy(dtype=float)
        if tcols:
            out["fs"] = _fs_from_time(df[tcols[0]].to_numpy(), path)
        out["source"] = f"csv:{name}"
        return out
    if ext == ".npy":
        a = np.load(path, allow_pickle=False)
        if a.ndim > 2 or (a.ndim == 1 and column is not None):
            raise ValueError(f"{'--column' if column is not None else 'file'}: {path} holds a "
                             f"{a.ndim}-D array of shape {a.shape}; "
                             f"allowed: a 1-D signal (without --column) or a 2-D array of "
                             f"channels (--column = channel index)")
        if a.ndim == 2 and column is None and min(a.shape) > 1:
            raise ValueError(f"--column: {path} holds a 2-D array of shape {a.shape} "
                             f"({min(a.shape)} channels); choose one with --column INDEX")
        if a.ndim == 2:
            idx = 0 if column is None else int(column)
            n_ch = min(a.shape)
            if not -n_ch <= idx < n_ch:
                raise ValueError(f"--column: index {idx} is out of range; {path} has {n_ch} "
                                 f"channels (shape {a.shape})")
            a = a[:, idx] if a.shape[0] >= a.shape[1] else a[idx]
        out.update(x=np.asarray(a, dtype=float).ravel(), source="npy")
        return out
    if ext == ".npz":
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        return _from_mapping(arrays, column, path, out, "npz")
    if ext == ".mat":
        from scipy.io import loadmat

        m = {k: v for k, v in loadmat(path).items() if not k.startswith("__")}
        return _from_mapping(m, column, path, out, "mat")
    raise ValueError(f"{path}: unsupported file type {ext!r} (.csv, .npy, .npz, .mat, .h5)")


def _from_mapping(arrays, column, path, out, kind):
    import numpy as np

    for k in _FS_NAMES:
        if k in arrays and np.size(arrays[k]) == 1:
            out["fs"] = float(np.asarray(arrays[k]).ravel()[0])
            break
    candidates = [k for k, v in arrays.items()
                  if np.issubdtype(np.asarray(v).dtype, np.number) and np.size(v) > 1
                  and k.lower() not in _TIME_NAMES]
    name = _pick(candidates if column is None else list(arrays), column, "variable", path)
    shape = np.shape(arrays[name])
    if sum(d > 1 for d in shape) > 1:
        raise ValueError(f"{path}: variable {name!r} has shape {shape}; allowed: one signal "
                         f"(a vector; save one channel per variable)")
    out["x"] = np.asarray(arrays[name], dtype=float).ravel()
    if out["fs"] is None:
        for k in arrays:
            if k.lower() in _TIME_NAMES and np.size(arrays[k]) == out["x"].size:
                out["fs"] = _fs_from_time(np.ravel(arrays[k]), path)
    out["source"] = f"{kind}:{name}"
    return out


def _is_number(s) -> bool:
    try:
        float(s)
    except (TypeError, ValueError):
        return False
    return True


def load_bands(text: str | None):
    """Band list from a YAML/JSON file or an inline JSON list (None: the defaults)."""
    if text is None:
        return None
    if os.path.exists(text):
        import yaml

        with open(text, encoding="utf-8") as fh:
            data = yaml.safe_load(fh)
    else:
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(f"--bands: neither a file nor a JSON list ({exc})") from None
    if isinstance(data, dict):
        data = data.get("bands")
    if not isinstance(data, list):
        raise ValueError("--bands: expected a list of band mappings (or a mapping with 'bands')")
    return data


# ------------------------------------------------------------------------------ validation
def check_args(args) -> None:
    """Refuse bad arguments before any file is read; ``ValueError`` naming the option.

    Numbers must be finite and in range (``--nlevel`` >= 1: the kurtogram is never silently run
    at another depth), ``--csv`` must not be a directory and ``--plot`` not a file.
    """
    def positive(opt, v, *, allow_zero=False):
        if v is not None and (not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero)):
            raise ValueError(f"{opt}: {opt.lstrip('-').replace('-', '_')} must be a finite "
                             f"number {'>= 0' if allow_zero else '> 0'}, got {v!r}")

    positive("--fs", args.fs)
    positive("--fr", args.fr)
    positive("--bpfi", args.bpfi)
    positive("--roller-diameter-mm", args.roller_diameter_mm)
    positive("--pitch-diameter-mm", args.pitch_diameter_mm)
    positive("--roller-diameter-in", args.roller_diameter_in)
    positive("--pitch-diameter-in", args.pitch_diameter_in)
    for unit in ("roller", "pitch"):
        if getattr(args, f"{unit}_diameter_mm") is not None and \
                getattr(args, f"{unit}_diameter_in") is not None:
            raise ValueError(f"--{unit}-diameter-in: give the {unit} diameter once, in mm or "
                             f"in inch")
    if not (math.isfinite(args.search_percent) and 0 < args.search_percent < 50):
        raise ValueError(f"--search-percent: got {args.search_percent!r}; allowed: 0 < percent "
                         f"< 50")
    if not (math.isfinite(args.pfa) and 0 < args.pfa < 1):
        raise ValueError(f"--pfa: got {args.pfa!r}; allowed: 0 < pfa < 1")
    args.faults = parse_faults(args.fault)
    positive("--min-bandwidth", args.min_bandwidth)
    positive("--max-level", args.max_level, allow_zero=True)
    if args.n_rollers is not None and args.n_rollers < 1:
        raise ValueError(f"--n-rollers: got {args.n_rollers}; allowed: an integer >= 1")
    if not math.isfinite(args.contact_angle_deg) or not 0 <= args.contact_angle_deg < 90:
        raise ValueError(f"--contact-angle-deg: got {args.contact_angle_deg!r}; allowed: 0 <= angle < 90")
    for opt, v, lo in (("--nlevel", 1 if args.nlevel is None else args.nlevel, 1),
                       ("--harmonics", args.harmonics, 1),
                       ("--sidebands", args.sidebands, 0), ("--raw-harmonics", args.raw_harmonics, 1),
                       ("--filter-order", args.filter_order, 1)):
        if v < lo:
            raise ValueError(f"{opt}: got {v}; allowed: an integer >= {lo}")
    if args.max_level is not None and args.nlevel is not None and args.max_level > args.nlevel:
        raise ValueError(f"--max-level: got {args.max_level:g}; allowed: <= --nlevel ({args.nlevel})")
    if args.fixed_band is not None:
        lo, hi = args.fixed_band
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
            raise ValueError(f"--fixed-band: got {lo!r} {hi!r}; allowed: 0 <= LOW_HZ < HIGH_HZ")
    if os.path.isdir(args.file):
        raise ValueError(f"file: {args.file!r} is a directory; allowed: a signal file")
    if args.csv is not None and (os.path.isdir(args.csv) or args.csv.endswith(os.sep)):
        raise ValueError(f"--csv: {args.csv!r} is a directory; allowed: a file path (.csv)")
    if args.plot is not None and os.path.exists(args.plot) and not os.path.isdir(args.plot):
        raise ValueError(f"--plot: {args.plot!r} is a file; allowed: a directory")


def parse_faults(items) -> dict[str, float]:
    """``["bpfi=162.2", "gear=87"]`` -> ``{"bpfi": 162.2, "gear": 87.0}`` (``--fault``)."""
    out: dict[str, float] = {}
    for item in items or []:
        name, sep, value = str(item).partition("=")
        name = name.strip().lower()
        if not sep or not re.fullmatch(r"[a-z][a-z0-9_]*", name):
            raise ValueError(f"--fault: expected NAME=HZ with a name of letters, digits and _ "
                             f"(e.g. bpfo=107.4), got {item!r}")
        try:
            hz = float(value)
        except ValueError:
            raise ValueError(f"--fault {name}: {value!r} is not a number (Hz)") from None
        if not math.isfinite(hz) or hz <= 0:
            raise ValueError(f"--fault {name}: got {hz!r}; allowed: a frequency > 0 Hz")
        if name in ("fr", "dc"):
            raise ValueError(f"--fault {name}: {name!r} is reserved (the shaft rate is --fr)")
        out[name] = hz
    return out


def check_record(x, path: str) -> None:
    """Refuse a record no spectrum can be read from: empty, non-finite values, constant."""
    import numpy as np

    if x.size == 0:
        raise ValueError(f"file: {path} holds an empty signal")
    bad = int(np.count_nonzero(~np.isfinite(x)))
    if bad:
        raise ValueError(f"file: {path} holds {bad} non-finite value(s) (NaN or inf) in "
                         f"{x.size} samples; clean or cut the record first")
    if x.size < 16:
        raise ValueError(f"file: {path} holds {x.size} samples; at least 16 are needed")
    if np.ptp(x) == 0.0:
        raise ValueError(f"file: {path} holds a constant signal ({x[0]:g}): no spectrum line, "
                         f"no envelope")


def check_frequencies(sources: dict[str, tuple[float, str]], fs: float, n: int) -> None:
    """Each frequency (name -> (Hz, option that gave it)) below Nyquist and resolvable."""
    nyq, df = fs / 2.0, fs / n
    for name, (hz, opt) in sources.items():
        label = f"{opt}" if opt in ("--fr", "--bpfi") else f"{opt} ({name} = {hz:g} Hz)"
        if hz >= nyq:
            raise ValueError(f"{label}: {hz:g} Hz is at or above the Nyquist frequency "
                             f"{nyq:g} Hz (fs = {fs:g} Hz)")
        if hz < MIN_BINS * df:
            raise ValueError(f"{label}: {hz:g} Hz is below the resolution of this record "
                             f"(at least {MIN_BINS} bins of fs/n = {df:.4g} Hz, i.e. "
                             f"{MIN_BINS * df:.4g} Hz; a longer record resolves it)")


def check_signal_args(args, x) -> None:
    """Checks that need the loaded signal: ``--nlevel`` within what its length allows (without
    ``--nlevel``: 8, or the deepest level the length allows)."""
    from bearing_envelope.signal.kurtogram import max_kurtogram_level

    nmax = max_kurtogram_level(x.size)
    if args.nlevel is None:
        args.nlevel = max(1, min(8, nmax))
    elif args.nlevel > nmax:
        raise ValueError(f"--nlevel: got {args.nlevel}; allowed: 1 .. {max(nmax, 1)} for "
                         f"{x.size} samples (at least 128 samples per band at the deepest level)")


# ------------------------------------------------------------------------------------- run
def fault_sources(args, fr: float, loaded: dict) -> dict[str, tuple[float, str]]:
    """Fault frequencies (Hz) with the option that gave each: the geometry (mm or inch), then
    ``--bpfi`` and ``--fault`` (overriding the geometry's value of the same name); a case
    file's BPFI unless one of them gives BPFI."""
    out: dict[str, tuple[float, str]] = {}
    d_mm = args.roller_diameter_mm
    p_mm = args.pitch_diameter_mm
    if args.roller_diameter_in is not None:
        d_mm = args.roller_diameter_in * _MM_PER_INCH
    if args.pitch_diameter_in is not None:
        p_mm = args.pitch_diameter_in * _MM_PER_INCH
    geometry = (args.n_rollers, d_mm, p_mm)
    if any(v is not None for v in geometry):
        if any(v is None for v in geometry):
            raise ValueError("bearing geometry: give --n-rollers, --roller-diameter-mm (or -in) "
                             "and --pitch-diameter-mm (or -in) together")
        from bearing_envelope.physics.kinematics import fault_frequencies

        try:
            ff = fault_frequencies(fr, args.n_rollers, d_mm, p_mm, args.contact_angle_deg)
        except ValueError as exc:
            raise ValueError(f"bearing geometry: {exc}") from None
        for name in ("bpfo", "bpfi", "bsf", "ftf"):
            out[name] = (getattr(ff, name), "bearing geometry")
    if args.bpfi is not None:
        out["bpfi"] = (args.bpfi, "--bpfi")
    for name, hz in args.faults.items():
        out[name] = (hz, "--fault")
    if "bpfi" not in out and loaded.get("bpfi") is not None:
        out["bpfi"] = (float(loaded["bpfi"]), "the case file")
    if not out:
        raise ValueError("bpfi: pass --bpfi, --fault NAME=HZ or the bearing geometry "
                         "(--n-rollers, --roller-diameter-mm/-in, --pitch-diameter-mm/-in)")
    if "bsf" in out and "bsf2" not in out:
        out["bsf2"] = (2.0 * out["bsf"][0], out["bsf"][1])
    return out


def result_json(args, loaded, fs, fr, table, det) -> dict:
    """The machine-readable result of ``--json``."""
    import numpy as np

    def clean(v):
        if isinstance(v, (np.floating, float)):
            return None if not math.isfinite(float(v)) else float(v)
        if isinstance(v, (np.integer,)):
            return int(v)
        if isinstance(v, (np.bool_,)):
            return bool(v)
        if v is None or v is getattr(__import__("pandas"), "NA", None):
            return None
        return v

    kg = det["kurtogram"]
    rows = []
    for rec in table.drop(columns=["scaling"]).to_dict(orient="records"):
        rows.append({k: clean(v) for k, v in rec.items()})
    return {
        "file": args.file, "source": loaded["source"], "n_samples": int(loaded["x"].size),
        "fs_hz": fs, "fr_hz": fr,
        "families": [{"name": f.name, "frequency_hz": f.frequency_hz,
                      "sideband": f.sideband_name, "sideband_hz": f.sideband_hz,
                      "label": f.label} for f in det["families"]],
        "search_percent": args.search_percent,
        "kurtogram": None if kg is None else {
            "level": float(kg.level), "fc_hz": float(kg.fc), "bandwidth_hz": float(kg.bandwidth),
            "kurtosis": float(kg.kurtosis), "level0": args.level0},
        "bands": [{"name": n, "low_hz": float(b["band"][0]), "high_hz": float(b["band"][1]),
                   "strategy": b["provenance"]["strategy"],
                   "clamped": bool(b["provenance"].get("clamped", False))}
                  for n, b in det["bands"].items()],
        "lines": rows,
        "verdict": det["verdict"].to_dict(),
    }


def run(args) -> int:
    """Execute ``bearing-envelope analyze``."""
    import pandas as pd

    from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
    from bearing_envelope.signal import DEFAULT_BANDS

    check_args(args)
    loaded = load_signal(args.file, column=args.column, signal=args.signal)
    check_record(loaded["x"], args.file)
    check_signal_args(args, loaded["x"])
    fs = args.fs if args.fs is not None else loaded["fs"]
    if fs is None:
        raise ValueError("fs: the file does not give the sampling frequency; pass --fs")
    if not (math.isfinite(fs) and fs > 0):
        raise ValueError(f"--fs: the file gives fs = {fs!r}; pass a sampling frequency > 0 "
                         f"with --fs")
    fr = args.fr if args.fr is not None else loaded["fr"]
    if fr is None:
        raise ValueError("fr: pass the shaft rate with --fr (Hz)")
    sources = fault_sources(args, fr, loaded)
    check_frequencies({"fr": (fr, "--fr"), **sources}, fs, loaded["x"].size)
    bands = load_bands(args.bands)
    if args.fixed_band is not None:
        lo, hi = args.fixed_band
        nyq = fs / 2.0
        if lo >= nyq:
            raise ValueError(f"--fixed-band: LOW_HZ {lo:g} is at or above the Nyquist frequency "
                             f"{nyq:g} Hz (fs = {fs:g} Hz)")
        if hi > nyq and not args.clamp:
            raise ValueError(f"--fixed-band: HIGH_HZ {hi:g} is above the Nyquist frequency "
                             f"{nyq:g} Hz (fs = {fs:g} Hz); lower it or add --clamp")
        bands = list(DEFAULT_BANDS if bands is None else bands)
        bands.append({"name": "fixed", "strategy": "fixed", "low_hz": lo, "high_hz": hi,
                      "clamp": bool(args.clamp or hi >= nyq)})
    faults = {k: v for k, (v, _) in sources.items()}
    options = AnalysisOptions(
        bands=bands, n_harmonics=args.harmonics, n_sidebands=args.sidebands,
        n_raw_harmonics=args.raw_harmonics, nlevel=args.nlevel, max_level=args.max_level,
        min_bandwidth=args.min_bandwidth, filter_order=args.filter_order, squared=args.squared,
        window=args.window, interpolate=args.interpolate, level0=args.level0,
        search_percent=args.search_percent, pfa=args.pfa)
    table, det = analyze_signal(loaded["x"], fs, fr=fr, fault_frequencies=faults,
                                options=options, full_output=True)
    # the sweep's tidy vocabulary (docs/file-format.md, "Tidy tables") in every output
    from bearing_envelope.study.tables import tidy_from_analysis

    table = tidy_from_analysis(table)
    verdict = det["verdict"]
    json_only = args.json == "-"
    if args.json is not None:
        doc = json.dumps(result_json(args, loaded, fs, fr, table, det), indent=1,
                         allow_nan=False)
        if json_only:
            print(doc)
        else:
            d = os.path.dirname(os.path.abspath(args.json))
            os.makedirs(d, exist_ok=True)
            with open(args.json, "w", encoding="utf-8") as fh:
                fh.write(doc + "\n")

    out = sys.stderr if json_only else sys.stdout
    print(f"# {args.file} ({loaded['source']}): {loaded['x'].size} samples, fs = {fs:g} Hz, "
          f"fr = {fr:g} Hz, " + ", ".join(f"{k} = {v:g} Hz" for k, v in
                                          det["frequencies"].items() if k != "fr"), file=out)
    kg = det["kurtogram"]
    if kg is not None:
        print(f"# kurtogram: level {kg.level:.3f}, fc = {kg.fc:g} Hz, bandwidth = "
              f"{kg.bandwidth:g} Hz, kurtosis = {kg.kurtosis:.3f} (level 0: {args.level0} "
              f"signal)", file=out)
    for name, b in det["bands"].items():
        lo, hi = b["band"]
        print(f"# band {name}: {lo:g} - {hi:g} Hz ({b['provenance']['strategy']}"
              f"{', clamped' if b['provenance'].get('clamped') else ''})", file=out)
    if not json_only:
        show = table[["band", "quantity", "base", "order", "sideband", "target_hz",
                      "frequency_hz", "amplitude", "floor_ratio_db", "threshold_db",
                      "detected"]]
        with pd.option_context("display.max_rows", None, "display.width", 200,
                               "display.float_format", "{:.6g}".format):
            print(show.to_string(index=False), file=out)
    print(f"# search: fundamentals within +-{args.search_percent:g} % of nominal, harmonics "
          f"around k x the line found; verdict at a record-wise false-alarm probability of "
          f"{verdict.pfa:g} ({verdict.n_tests} family x band tests at {verdict.pfa_test:.2g} "
          f"each; a family needs its fundamental and 2nd harmonic)", file=out)
    for fv in verdict.families:
        print(f"#   {fv.summary()}", file=out)
    for i, line in enumerate(verdict.summary_lines()):
        print(f"{'verdict: ' if i == 0 else '         '}{line}", file=out)
    if args.csv:
        d = os.path.dirname(os.path.abspath(args.csv))
        os.makedirs(d, exist_ok=True)
        table.to_csv(args.csv, index=False)
        print(f"# table written to {args.csv}", file=out)
    if args.json is not None and not json_only:
        print(f"# JSON written to {args.json}", file=out)
    if args.plot:
        from bearing_envelope.diagnosis.plots import save_analysis_figures

        stem = os.path.splitext(os.path.basename(args.file))[0]
        paths = save_analysis_figures(det, args.plot, prefix=f"{stem}_",
                                      n_harmonics=max(args.harmonics, 3),
                                      n_sidebands=args.sidebands)
        print(f"# figures: {', '.join(paths)}", file=out)
    return 0
