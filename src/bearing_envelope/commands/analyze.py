"""``bearing-envelope analyze``: envelope analysis of one recording or case file.

Reads a signal (.csv, .npy, .npz, MATLAB .mat, or a case file .h5 written by
``bearing-envelope simulate``), runs :func:`bearing_envelope.signal.analyze_signal` (raw
spectrum terms, fast kurtogram, envelope spectra in every band, BPFI harmonics and shaft-rate
sidebands) and prints the table. The fault frequency comes from ``--bpfi`` or from the bearing
geometry (``--n-rollers --roller-diameter-mm --pitch-diameter-mm [--contact-angle-deg]``); a
case file carries fs, fr and BPFI itself. See ``docs/signal.md``.

Examples::

    bearing-envelope analyze accel.csv --fs 12000 --fr 29.95 --bpfi 162.2 --column DE
    bearing-envelope analyze 105.mat --fs 12000 --fr 29.95 --n-rollers 9 \\
        --roller-diameter-mm 7.94 --pitch-diameter-mm 39.04 --column X105_DE_time
    bearing-envelope analyze results/cases/F500kN_h50um.h5 --csv out.csv --plot figs/
"""

from __future__ import annotations

import argparse
import json
import os
import sys

_TIME_NAMES = ("time", "t", "time_s", "times", "seconds")
_FS_NAMES = ("fs", "Fs", "FS", "sampling_rate", "sample_rate", "sampling_frequency")


def register(subparsers) -> None:
    """Add the ``analyze`` sub-command."""
    p = subparsers.add_parser(
        "analyze",
        help="envelope analysis (kurtogram, bands, BPFI harmonics) of a recording or case file",
        description=__doc__.split("\n\n")[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("file", help="signal file: .csv, .npy, .npz, .mat or a case file .h5")
    p.add_argument("--fs", type=float, default=None,
                   help="sampling frequency, Hz (else from the file: a case file, an 'fs' entry "
                        "of .npz/.mat, or a time column of a CSV)")
    p.add_argument("--fr", type=float, default=None, help="shaft rate, Hz (case file: its own)")
    p.add_argument("--bpfi", type=float, default=None,
                   help="inner-race fault frequency, Hz (else from the geometry or the case)")
    g = p.add_argument_group("bearing geometry (instead of --bpfi)")
    g.add_argument("--n-rollers", type=int, default=None, help="rolling elements per row")
    g.add_argument("--roller-diameter-mm", type=float, default=None, help="roller diameter, mm")
    g.add_argument("--pitch-diameter-mm", type=float, default=None, help="pitch diameter, mm")
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
                   default=None, help="add a fixed band (Hz)")
    p.add_argument("--harmonics", type=int, default=2, help="BPFI harmonics K (default 2)")
    p.add_argument("--sidebands", type=int, default=1, help="fr sidebands M per side (default 1)")
    p.add_argument("--raw-harmonics", type=int, default=1,
                   help="orders of fr and BPFI in the raw spectrum (default 1)")
    p.add_argument("--nlevel", type=int, default=None,
                   help="kurtogram levels (default 8, or as deep as a short signal allows)")
    p.add_argument("--max-level", type=float, default=None, help="kurtogram guard: max level")
    p.add_argument("--min-bandwidth", type=float, default=None,
                   help="kurtogram guard: minimum bandwidth, Hz")
    p.add_argument("--filter-order", type=int, default=4, help="Butterworth order (default 4)")
    p.add_argument("--window", default="hann", help="spectrum window (default hann)")
    p.add_argument("--squared", action="store_true", help="squared envelope")
    p.add_argument("--interpolate", action="store_true",
                   help="interpolated, scalloping-corrected peak amplitudes")
    p.add_argument("--csv", default=None, metavar="OUT", help="write the full table as CSV")
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
    import math

    def positive(opt, v, *, allow_zero=False):
        if v is not None and (not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero)):
            raise ValueError(f"{opt}: {opt.lstrip('-').replace('-', '_')} must be a finite "
                             f"number {'>= 0' if allow_zero else '> 0'}, got {v!r}")

    positive("--fs", args.fs)
    positive("--fr", args.fr)
    positive("--bpfi", args.bpfi)
    positive("--roller-diameter-mm", args.roller_diameter_mm)
    positive("--pitch-diameter-mm", args.pitch_diameter_mm)
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
def run(args) -> int:
    """Execute ``bearing-envelope analyze``."""
    import pandas as pd

    from bearing_envelope.signal import DEFAULT_BANDS, analyze_signal

    check_args(args)
    loaded = load_signal(args.file, column=args.column, signal=args.signal)
    check_signal_args(args, loaded["x"])
    fs = args.fs if args.fs is not None else loaded["fs"]
    if fs is None:
        raise ValueError("fs: the file does not give the sampling frequency; pass --fs")
    fr = args.fr if args.fr is not None else loaded["fr"]
    if fr is None:
        raise ValueError("fr: pass the shaft rate with --fr (Hz)")
    faults = None
    bpfi = args.bpfi
    geometry = (args.n_rollers, args.roller_diameter_mm, args.pitch_diameter_mm)
    if bpfi is None and any(v is not None for v in geometry):
        if any(v is None for v in geometry):
            raise ValueError("bearing geometry: give --n-rollers, --roller-diameter-mm and "
                             "--pitch-diameter-mm together")
        from bearing_envelope.kinematics import fault_frequencies

        ff = fault_frequencies(fr, args.n_rollers, args.roller_diameter_mm,
                               args.pitch_diameter_mm, args.contact_angle_deg)
        bpfi = ff.bpfi
        faults = {"bpfi": ff.bpfi, "bpfo": ff.bpfo}
    if bpfi is None:
        bpfi = loaded["bpfi"]
    if bpfi is None:
        raise ValueError("bpfi: pass --bpfi or the bearing geometry (--n-rollers, "
                         "--roller-diameter-mm, --pitch-diameter-mm)")
    bands = load_bands(args.bands)
    if args.fixed_band is not None:
        bands = list(DEFAULT_BANDS if bands is None else bands)
        bands.append({"name": "fixed", "strategy": "fixed", "low_hz": args.fixed_band[0],
                      "high_hz": args.fixed_band[1]})
    table, det = analyze_signal(
        loaded["x"], fs, fr=fr, bpfi=bpfi if faults is None else None,
        fault_frequencies=faults, bands=bands, n_harmonics=args.harmonics,
        n_sidebands=args.sidebands, n_raw_harmonics=args.raw_harmonics, nlevel=args.nlevel,
        max_level=args.max_level, min_bandwidth=args.min_bandwidth,
        filter_order=args.filter_order, squared=args.squared, window=args.window,
        interpolate=args.interpolate, full_output=True)

    out = sys.stdout
    print(f"# {args.file} ({loaded['source']}): {loaded['x'].size} samples, fs = {fs:g} Hz, "
          f"fr = {fr:g} Hz, " + ", ".join(f"{k} = {v:g} Hz" for k, v in
                                          det["frequencies"].items() if k != "fr"), file=out)
    kg = det["kurtogram"]
    if kg is not None:
        print(f"# kurtogram: level {kg.level:.3f}, fc = {kg.fc:g} Hz, bandwidth = "
              f"{kg.bandwidth:g} Hz, kurtosis = {kg.kurtosis:.3f}", file=out)
    show = table.drop(columns=["scaling", "band_kind"])
    with pd.option_context("display.max_rows", None, "display.width", 200,
                           "display.float_format", "{:.6g}".format):
        print(show.to_string(index=False), file=out)
    if args.csv:
        d = os.path.dirname(os.path.abspath(args.csv))
        os.makedirs(d, exist_ok=True)
        table.to_csv(args.csv, index=False)
        print(f"# table written to {args.csv}", file=out)
    if args.plot:
        from bearing_envelope.signal.plots import save_analysis_figures

        stem = os.path.splitext(os.path.basename(args.file))[0]
        paths = save_analysis_figures(det, args.plot, prefix=f"{stem}_",
                                      n_harmonics=max(args.harmonics, 5),
                                      n_sidebands=args.sidebands)
        print(f"# figures: {', '.join(paths)}", file=out)
    return 0
