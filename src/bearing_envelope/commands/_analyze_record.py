"""One record of ``bearing-envelope analyze``: read, check, analyse, and its compact result
(verdict-table rows, lines, JSON, figure) for the batch.

:func:`analyze_record` is the whole path of one record; :func:`finish_record` turns it into the
picklable result that a batch worker returns (:mod:`._analyze_batch`).
"""

# numpy, pandas, scipy, matplotlib and the package's modules are imported inside the functions
# that use them, on purpose: bearing_envelope.cli imports every command module to build its
# parser (`bearing-envelope --help` must not pay ~3 s of imports), and a batch sets the
# thread-count variables before numpy loads (._analyze_batch.single_threaded).
from __future__ import annotations

import math
import os

#: A frequency given to analyze must lie at least this many bins (fs / n) above 0 Hz: the
#: floor around a line is measured over [0.5, 1.5] x its frequency.
MIN_BINS = 10


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


def check_orders(args, sources: dict[str, tuple[float, str]], fr: float, fs: float) -> None:
    """``--harmonics`` and ``--raw-harmonics`` within what fs/2 holds for the highest fault
    frequency (with the search margin), ``--sidebands`` above 0 Hz: refused, never clipped."""
    nyq = fs / 2.0
    top_name, (top, _) = max(sources.items(), key=lambda kv: kv[1][0])
    margin = (1.0 + args.search_percent / 100.0) * 1.002  # search window + harmonic tolerance
    for opt, k, f in (("--harmonics", args.harmonics, top),
                      ("--raw-harmonics", args.raw_harmonics, max(top, fr))):
        kmax = int(nyq / (f * margin))
        if k > kmax:
            raise ValueError(f"{opt}: got {k}; allowed: 1 .. {max(kmax, 1)} for this record "
                             f"({max(kmax, 1)} x {top_name.upper() if f == top else 'fr'} "
                             f"{f:g} Hz with the search margin stays below fs/2 = {nyq:g} Hz)")
    if args.sidebands and "bpfi" in sources and args.sidebands * fr >= sources["bpfi"][0]:
        mmax = max(int(sources["bpfi"][0] / fr - 1e-9), 0)
        raise ValueError(f"--sidebands: got {args.sidebands}; allowed: 0 .. {mmax} (the lower "
                         f"sideband BPFI - M x fr must stay above 0 Hz)")


def record_nlevel(nlevel, n: int) -> int:
    """Kurtogram depth for ``n`` samples: ``nlevel`` if the length allows it (else refused),
    without ``--nlevel`` 8 or the deepest level the length allows."""
    from bearing_envelope.signal.kurtogram import max_kurtogram_level

    nmax = max_kurtogram_level(n)
    if nlevel is None:
        return max(1, min(8, nmax))
    if nlevel > nmax:
        raise ValueError(f"--nlevel: got {nlevel}; allowed: 1 .. {max(nmax, 1)} for "
                         f"{n} samples (at least 128 samples per band at the deepest level)")
    return nlevel


def fault_sources(args, fr: float, loaded: dict, geometry: dict | None
                  ) -> dict[str, tuple[float, str]]:
    """Fault frequencies (Hz) with the option that gave each: the bearing (designation or
    geometry), then ``--bpfi`` and ``--fault`` (overriding the geometry's value of the same
    name); a case file's BPFI unless one of them gives BPFI."""
    out: dict[str, tuple[float, str]] = {}
    if geometry is not None:
        from bearing_envelope.physics.kinematics import fault_frequencies

        label = f"--bearing {geometry['designation']}" if geometry.get("designation") \
            else "bearing geometry"
        try:
            ff = fault_frequencies(fr, geometry["n_rollers"], geometry["roller_diameter_mm"],
                                   geometry["pitch_diameter_mm"], geometry["contact_angle_deg"])
        except ValueError as exc:
            raise ValueError(f"{label}: {exc}") from None
        for name in ("bpfo", "bpfi", "bsf", "ftf"):
            out[name] = (getattr(ff, name), label)
    if args.bpfi is not None:
        out["bpfi"] = (args.bpfi, "--bpfi")
    for name, hz in args.faults.items():
        out[name] = (hz, "--fault")
    if "bpfi" not in out and loaded.get("bpfi") is not None:
        out["bpfi"] = (float(loaded["bpfi"]), "the case file")
    if not out:
        raise ValueError("bpfi: pass --bpfi, --fault NAME=HZ, --bearing or the bearing "
                         "geometry (--n-rollers, --roller-diameter-mm/-in, "
                         "--pitch-diameter-mm/-in)")
    if "bsf" in out and "bsf2" not in out:
        out["bsf2"] = (2.0 * out["bsf"][0], out["bsf"][1])
    return out


def record_bands(args, fs: float):
    """The band list for a record at ``fs``: ``--bands`` (or the defaults) plus
    ``--fixed-band``, checked against its Nyquist frequency."""
    from bearing_envelope.signal import DEFAULT_BANDS

    bands = args.band_specs
    if args.fixed_band is None:
        return bands
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
    return bands


def _rate(task_value, opt_value, file_value, name: str, path: str) -> float:
    """fs or fr of a record: the manifest's, the option's, else the file's (checked > 0)."""
    v = next((u for u in (task_value, opt_value, file_value) if u is not None), None)
    if v is None:
        if name == "fs":
            raise ValueError("fs: the file does not give the sampling frequency; pass --fs")
        raise ValueError("fr: pass the shaft rate with --fr (Hz)")
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"--{name}: the file gives {name} = {v!r}; pass a "
                         f"{'sampling frequency' if name == 'fs' else 'shaft rate'} > 0 with "
                         f"--{name}")
    return float(v)


def analyze_record(task: dict, args) -> dict:
    """Read, check and analyse one record.

    Parameters
    ----------
    task : dict
        ``{"file", "fs", "fr", "bearing", "column", "channel"}`` (a manifest row; None: the
        options', then the file's).
    args : argparse.Namespace
        The checked options (:func:`check_args`).

    Returns
    -------
    dict
        ``file, loaded, fs, fr, bearing, sources, nlevel, table`` (tidy) and ``det`` (the
        details of :func:`bearing_envelope.signal.analyze_signal`).
    """
    from bearing_envelope.io.records import bearing_geometry, read_record
    from bearing_envelope.study.tables import tidy_from_analysis

    path = task["file"]
    delim = {"tab": "\t"}.get(args.delimiter, args.delimiter)
    loaded = read_record(path, column=task.get("column") or args.column,
                         channel=task.get("channel") or args.channel, signal=args.signal,
                         delimiter=delim, decimal=args.decimal)
    x = loaded["x"]
    check_record(x, path)
    nlevel = record_nlevel(args.nlevel, x.size)
    fs = _rate(task.get("fs"), args.fs, loaded["fs"], "fs", path)
    fr = _rate(task.get("fr"), args.fr, loaded["fr"], "fr", path)
    geometry = bearing_geometry(task["bearing"]) if task.get("bearing") else args.geometry
    sources = fault_sources(args, fr, loaded, geometry)
    check_frequencies({"fr": (fr, "--fr"), **sources}, fs, x.size)
    check_orders(args, sources, fr, fs)
    bands = record_bands(args, fs)
    try:
        table, det = run_chain(x, fs, fr, {k: v for k, (v, _) in sources.items()}, bands,
                               nlevel, args)
    except (ValueError, KeyError) as exc:  # the library's own checks: name the record too
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else str(exc)
        where = "--bands" if args.bands is not None else "bands"
        raise ValueError(f"file: {path}: {where}: {msg}" if "band" in str(msg)
                         else f"file: {path}: {msg}") from None
    return {"file": path, "name": task.get("name"), "loaded": loaded, "fs": fs, "fr": fr,
            "sources": sources,
            "bearing": None if geometry is None else geometry.get("designation"),
            "nlevel": nlevel, "table": tidy_from_analysis(table), "det": det}


def run_chain(x, fs, fr, faults, bands, nlevel, args):
    """``analyze_signal`` with the command's options (the one call of the library)."""
    from bearing_envelope.diagnosis import AnalysisOptions, analyze_signal
    from bearing_envelope.diagnosis.routes import DEFAULT_ROUTES

    routes = getattr(args, "routes", None)
    options = AnalysisOptions(
        bands=bands, n_harmonics=args.harmonics, n_sidebands=args.sidebands,
        n_raw_harmonics=args.raw_harmonics, nlevel=nlevel, max_level=args.max_level,
        min_bandwidth=args.min_bandwidth, filter_order=args.filter_order, squared=args.squared,
        window=args.window, interpolate=args.interpolate, level0=args.level0,
        search_percent=args.search_percent, pfa=args.pfa,
        measure_speed=getattr(args, "speed", "measured") == "measured",
        routes=DEFAULT_ROUTES if routes is None else routes)
    return analyze_signal(x, fs, fr=fr, fault_frequencies=faults, options=options,
                          full_output=True)


def _clean(v):
    import numpy as np
    import pandas as pd

    if isinstance(v, (np.floating, float)):
        return None if not math.isfinite(float(v)) else float(v)
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.bool_):
        return bool(v)
    if v is None or v is pd.NA:
        return None
    return v


def result_json(args, res: dict) -> dict:
    """The machine-readable result of ``--json`` for one analysed record."""
    det, table, loaded = res["det"], res["table"], res["loaded"]
    kg = det["kurtogram"]
    rows = [{k: _clean(v) for k, v in rec.items()}
            for rec in table.drop(columns=["scaling"]).to_dict(orient="records")]
    return {
        "file": res["file"], "source": loaded["source"], "n_samples": int(loaded["x"].size),
        "fs_hz": res["fs"], "fr_hz": res["fr"], "bearing": res["bearing"],
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


def write_text(path: str, text: str) -> None:
    """Write ``text`` to ``path``, creating its folder."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)


def is_batch(args) -> bool:
    """Several records (or a folder, or a manifest): the batch mode."""
    return args.manifest is not None or len(args.files) != 1 or os.path.isdir(args.files[0])


def figure_dir(args) -> str | None:
    """Where the per-record analyst figures go: ``--plot`` in batch mode, else beside
    ``--html`` (``<stem>_figures/``); None without ``--html`` and batch ``--plot``."""
    if args.html:
        if args.plot and is_batch(args):
            return args.plot
        stem = os.path.splitext(os.path.abspath(args.html))[0]
        return f"{stem}_figures"
    return args.plot if is_batch(args) else None


def finish_record(res: dict, args, fig_dir: str | None) -> dict:
    """The compact, picklable result of one record: its verdict-table rows, its lines (for
    ``--csv``), its JSON (for ``--json``), its verdict lines and its figure."""
    from bearing_envelope.diagnosis.plots import save_record_figure

    fig = None
    if fig_dir is not None:
        stem = res.get("name") or os.path.splitext(os.path.basename(res["file"]))[0]
        fig = save_record_figure(res["loaded"]["x"], res["det"], os.path.join(
            fig_dir, f"{stem}_analysis.png"), n_harmonics=args.harmonics, db=args.db,
            fmax=args.fmax, orders=args.orders, title=res["file"])
    return {"file": res["file"], "ok": True, "error": None, "rows": record_rows(res, args),
            "lines": res["table"] if args.csv else None,
            "json": result_json(args, res) if args.json is not None else None,
            "summary": res["det"]["verdict"].summary_lines(), "figure": fig}


# ------------------------------------------------------------------------- verdict table
def record_rows(res: dict, args) -> list[dict]:
    """Rows of the verdict table for one analysed record: one per fault family.

    Columns: the record (``file, record, status, error, source, n_samples, fs_hz, fr_hz,
    bearing``), the record's verdict (``verdict`` = its summary line, ``record_*`` = every
    scalar of ``Verdict.to_dict()``), the family (``family, nominal_hz, diagnosis`` and every
    scalar of its ``FamilyVerdict``, lists joined by ``;``, and ``margin_db``), its lines in
    the band of its verdict (``h{k}_hz, h{k}_amplitude, h{k}_db, h{k}_detected``) and the
    fault-band metrics there (:func:`bearing_envelope.diagnosis.fault_band_metrics`:
    ``h{k}_band_peak, h{k}_band_peak_hz, h{k}_band_power, total_band_power``).
    """
    det = res["det"]
    vd = det["verdict"].to_dict()
    loaded = res["loaded"]
    head = {"file": res["file"], "record": os.path.splitext(os.path.basename(res["file"]))[0],
            "status": "ok", "error": None, "source": loaded["source"],
            "n_samples": int(loaded["x"].size), "fs_hz": res["fs"], "fr_hz": res["fr"],
            "bearing": res["bearing"], "verdict": (vd.get("summary") or [None])[0]}
    for k, v in vd.items():
        if k not in ("families", "summary", "statistic") and _flat(v):
            head[f"record_{k}"] = _joined(v)
    fams = {f.name: f for f in det["families"]}
    rows = []
    for fv in vd["families"]:
        name = fv["family"]
        row = dict(head, family=name, nominal_hz=fams[name].frequency_hz,
                   diagnosis=name == vd.get("diagnosis"))
        for k, v in fv.items():
            if k != "family" and _flat(v):
                row[k] = _joined(v)
        sr, th = fv.get("floor_ratio_db"), fv.get("threshold_db")
        row["margin_db"] = sr - th if sr is not None and th is not None else None
        row.update(_line_columns(res["table"], name, fv.get("band"), args.harmonics))
        row.update(_band_metrics(det, fams[name], fv.get("band"), args))
        rows.append(row)
    return rows


def _scalar(v) -> bool:
    return v is None or isinstance(v, (str, bool, int, float))


def _flat(v) -> bool:
    """A scalar, or a list of scalars (a table cell joined by ``;``)."""
    return _scalar(v) or (isinstance(v, (list, tuple)) and all(_scalar(u) for u in v))


def _joined(v):
    return ";".join(map(str, v)) if isinstance(v, (list, tuple)) else v


def _line_columns(table, family: str, band, n_harmonics: int) -> dict:
    out = {}
    sel = table[(table["band"] == band) & (table["base"] == family)
                & (table["sideband"] == 0)
                & table["quantity"].astype(str).str.startswith("envelope")] \
        if band is not None else table.iloc[0:0]
    by_k = {int(r["order"]): r for _, r in sel.iterrows()}
    for k in range(1, n_harmonics + 1):
        r = by_k.get(k)
        out[f"h{k}_hz"] = None if r is None else float(r["frequency_hz"])
        out[f"h{k}_amplitude"] = None if r is None else float(r["amplitude"])
        out[f"h{k}_db"] = None if r is None else float(r["floor_ratio_db"])
        out[f"h{k}_detected"] = None if r is None or r["detected"] is None or \
            str(r["detected"]) == "<NA>" else bool(r["detected"])
    return out


def _band_metrics(det: dict, fam, band, args) -> dict:
    from bearing_envelope.diagnosis.detection import fault_band_metrics

    k_max = args.harmonics
    out = {f"h{k}_{c}": None for k in range(1, k_max + 1)
           for c in ("band_peak", "band_peak_hz", "band_power")}
    out["total_band_power"] = None
    b = det["bands"].get(band) if band is not None else None
    if b is None:
        return out
    m = fault_band_metrics(b["f"], b["amplitude"], {fam.name: fam.frequency_hz},
                           harmonics=k_max, sidebands=0,
                           bandwidth=2.0 * args.search_percent / 100.0,
                           enbw=1.5 if args.window == "hann" else 1.0)
    for _, r in m.iterrows():
        k = int(r["order"])
        out[f"h{k}_band_peak"] = _num(r["peak_amplitude"])
        out[f"h{k}_band_peak_hz"] = _num(r["peak_hz"])
        out[f"h{k}_band_power"] = _num(r["band_power"])
        out["total_band_power"] = _num(r["total_band_power"])
    return out


def _num(v):
    v = float(v)
    return v if math.isfinite(v) else None
