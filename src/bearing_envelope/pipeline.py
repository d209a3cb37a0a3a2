"""Per-case analysis steps of the sweep, as plain functions the workflow scripts call.

- :func:`case_bands`: the kurtogram of a case's signal and the limits of every configured band
  (``analysis.bands``), with provenance (clamping below Nyquist recorded).
- :func:`case_harmonics`: raw-spectrum terms and, for every band, the envelope harmonics
  k x BPFI with sidebands k x BPFI +- m x fr and the band-passed peak, as a tidy table
  (columns :data:`bearing_envelope.tables.TIDY_COLUMNS` plus ``base``, ``target_hz``,
  ``clamped``, ``scaling``).
- :func:`case_summary`: one row of peak pressures and simulation diagnostics per case.

Quantity names in the tidy table: ``raw_dc`` (signal mean), ``raw_fr`` (k x fr), ``raw_bpfi``
(k x BPFI) from the raw amplitude spectrum; ``envelope_bpfi`` from the envelope spectrum;
``bandpass_peak`` (max |band-passed signal|); ``kurtogram_kurtosis`` (best cell). Units: those
of the signal named in the ``signal`` column (Pa for the pressure histories ``p_max`` and
``p_max_defect``, the sensor's units for ``acceleration``; squared for a squared envelope).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from .tables import TIDY_COLUMNS

__all__ = ["case_signal", "case_frequencies", "case_bands", "case_harmonics", "case_summary",
           "case_diagnosability", "QUANTITY_NAMES", "log_to"]

QUANTITY_NAMES = {
    ("raw_spectrum", "dc"): "raw_dc",
    ("raw_spectrum", "fr"): "raw_fr",
    ("raw_spectrum", "bpfi"): "raw_bpfi",
    ("envelope_spectrum", "bpfi"): "envelope_bpfi",
    ("bandpass_peak", None): "bandpass_peak",
    ("kurtogram_kurtosis", None): "kurtogram_kurtosis",
}


def case_signal(case, name: str = "p_max") -> np.ndarray:
    """The named 1-D signal of a case: ``p_max``, ``p_max_defect``, an integral signal
    (``removed_force``, ``contact_force``, ``approach``, ``approach_change``, ``contact_area``;
    format 2 case files) or any other stored signal."""
    if name not in case.signals:
        raise ValueError(f"analysis.signal = {name!r}; the case holds {sorted(case.signals)}")
    x = np.asarray(case.signals[name], dtype=float)
    if not np.all(np.isfinite(x)):
        raise ValueError(f"signal {name!r} of case F{case.load_kN:g}kN_h{case.depth_um:g}um has non-finite values")
    return x


def case_frequencies(case) -> dict[str, float]:
    """Base frequencies (Hz) of a case: fr, the BPFI used, and the geometric BPFO, FTF, BSF."""
    return {"fr": float(case.fr), "bpfi": float(case.bpfi), "bpfo": float(case.bpfo),
            "ftf": float(case.ftf), "bsf": float(case.bsf)}


def _kurtogram(x, fs, analysis: Mapping[str, Any]):
    from .signal import fast_kurtogram, max_kurtogram_level

    nlevel = int(analysis.get("nlevel", 8))
    nlevel = min(nlevel, max_kurtogram_level(x.size))
    return fast_kurtogram(
        x - x.mean(), fs, nlevel,
        max_level=analysis.get("max_level"),
        min_bandwidth=analysis.get("min_bandwidth_hz"),
    )


def case_bands(case, analysis: Mapping[str, Any]) -> tuple[dict, Any]:
    """Kurtogram and band limits of one case.

    Parameters
    ----------
    case : bearing_envelope.io.Case
    analysis : mapping
        The config's ``analysis`` section (``signal``, ``nlevel``, ``max_level``,
        ``min_bandwidth_hz``, ``bands``).

    Returns
    -------
    doc : dict
        JSON-able: ``case``, ``load_kN``, ``depth_um``, ``fs``, ``signal``, ``kurtogram``
        (best ``level``, ``fc``, ``bandwidth``, ``kurtosis``) and ``bands`` (list of
        ``name``, ``strategy``, ``low_hz``, ``high_hz``, ``clamped``, ``provenance``).
    kurtogram : bearing_envelope.signal.Kurtogram or None
        None when no band uses the kurtogram strategy.
    """
    from .config import case_name
    from .signal import resolve_band

    x = case_signal(case, analysis.get("signal", "p_max"))
    fs = float(case.fs)
    freqs = case_frequencies(case)
    need_kg = any(b["strategy"] == "kurtogram" for b in analysis["bands"])
    kg = _kurtogram(x, fs, analysis) if need_kg else None
    bands = []
    for spec in analysis["bands"]:
        (lo, hi), prov = resolve_band(spec, fs, kurtogram=kg, frequencies=freqs)
        bands.append({
            "name": spec["name"], "strategy": spec["strategy"],
            "low_hz": float(lo), "high_hz": float(hi),
            "clamped": bool(prov.get("clamped", False)),
            "provenance": _jsonable(prov),
        })
    doc = {
        "case": case_name(case.load_kN, case.depth_um),
        "load_kN": float(case.load_kN), "depth_um": float(case.depth_um),
        "fs": fs, "signal": analysis.get("signal", "p_max"),
        "kurtogram": None if kg is None else {
            "level": float(kg.level), "fc": float(kg.fc), "bandwidth": float(kg.bandwidth),
            "kurtosis": float(kg.kurtosis)},
        "bands": bands,
    }
    return doc, kg


def case_harmonics(case, analysis: Mapping[str, Any], bands_doc: Mapping[str, Any],
                   *, full_output: bool = False):
    """Tidy harmonic table of one case for the bands of ``bands_doc`` (see :func:`case_bands`).

    The bands are applied as fixed limits, so the kurtogram is computed once (in
    :func:`case_bands`) and the envelope rule can rerun alone.
    """
    from .config import case_name
    from .signal import analyze_signal

    signal = analysis.get("signal", "p_max")
    x = case_signal(case, signal)
    fs = float(case.fs)
    specs = [{"name": b["name"], "strategy": "fixed", "low_hz": b["low_hz"], "high_hz": b["high_hz"]}
             for b in bands_doc["bands"]]
    kind = {b["name"]: b["strategy"] for b in bands_doc["bands"]}
    clamped = {b["name"]: b["clamped"] for b in bands_doc["bands"]}
    res = analyze_signal(
        x, fs, fr=float(case.fr), bpfi=float(case.bpfi), bands=specs,
        n_harmonics=int(analysis.get("harmonics", 3)),
        n_sidebands=int(analysis.get("sidebands", 2)),
        n_raw_harmonics=int(analysis.get("raw_orders_fr", 3)),
        nlevel=None, filter_order=int(analysis.get("filter_order", 4)),
        squared=bool(analysis.get("squared_envelope", False)),
        full_output=full_output,
    )
    df, extra = (res if full_output else (res, None))
    df = df.copy()
    base = df["base"].where(df["base"].notna(), None)
    df["quantity"] = [
        QUANTITY_NAMES.get((q, b if q in ("raw_spectrum", "envelope_spectrum") else None),
                           f"{q}_{b}" if b else q)
        for q, b in zip(df["quantity"], base)
    ]
    df = df[df["quantity"] != "kurtogram_kurtosis"]
    df["band"] = df["band_strategy"]
    df["band_strategy"] = [kind.get(n, "raw") for n in df["band"]]
    df["clamped"] = [clamped.get(n, False) for n in df["band"]]
    df["case"] = case_name(case.load_kN, case.depth_um)
    df["load_kN"] = float(case.load_kN)
    df["depth_um"] = float(case.depth_um)
    df["signal"] = signal
    if bands_doc.get("kurtogram"):
        kgd = bands_doc["kurtogram"]
        lo = next(b for b in bands_doc["bands"] if b["strategy"] == "kurtogram")
        df = pd.concat([df, pd.DataFrame([{
            "case": df["case"].iloc[0], "load_kN": float(case.load_kN),
            "depth_um": float(case.depth_um), "band": lo["name"], "band_strategy": "kurtogram",
            "band_low_hz": lo["low_hz"], "band_high_hz": lo["high_hz"],
            "quantity": "kurtogram_kurtosis", "order": kgd["level"], "sideband": 0,
            "frequency_hz": kgd["fc"], "amplitude": kgd["kurtosis"], "clamped": lo["clamped"],
            "scaling": "kurtosis of the best kurtogram cell (order = level)",
            "signal": signal}])],
            ignore_index=True)
    keep = TIDY_COLUMNS + [c for c in ("base", "target_hz", "clamped", "scaling", "signal") if c in df]
    df = df[keep].reset_index(drop=True)
    return (df, extra) if full_output else df


def case_summary(case) -> dict[str, Any]:
    """One summary row of a case: peak pressures, loads, frequencies and simulation diagnostics."""
    from .config import case_name

    stats = json.loads(case.attrs.get("stats_json", "{}"))
    tinfo = case.table or {}
    attrs = tinfo.get("attrs", tinfo) if isinstance(tinfo, Mapping) else {}

    def tget(key):
        v = attrs.get(key) if isinstance(attrs, Mapping) else None
        return float(v) if v is not None and np.ndim(v) == 0 else np.nan

    p = np.asarray(case.p_max)
    pd_ = np.asarray(case.p_max_defect)
    return {
        "case": case_name(case.load_kN, case.depth_um),
        "load_kN": float(case.load_kN), "depth_um": float(case.depth_um),
        "p_max_peak_Pa": float(p.max()), "p_max_mean_Pa": float(p.mean()),
        "p_max_defect_peak_Pa": float(pd_.max()),
        "roller_load_max_N": float(np.max(case.roller_load)),
        "bpfi_used_hz": float(case.bpfi), "bpfi_geometry_hz": float(case.bpfi_geometry),
        "fs_hz": float(case.fs), "n_samples": int(p.size),
        "n_solves": stats.get("n_solves", np.nan),
        "simulate_wall_s": stats.get("wall_seconds", np.nan),
        "interp_max_rel_error_p_max": tget("interp_max_rel_error_p_max"),
        "git_commit": case.attrs.get("git_commit", ""),
    }


def case_diagnosability(case, sensor: Mapping[str, Any], analysis: Mapping[str, Any],
                        snr_db, *, reference=None) -> pd.DataFrame:
    """Is BPFI detected in the synthetic acceleration of a case, per SNR and band strategy?

    The case's contact history goes through the transfer path of ``sensor`` (modes, noise at
    each SNR, tones: :mod:`bearing_envelope.transfer`); every band of ``analysis.bands`` is
    resolved on the acceleration (the kurtogram band from the acceleration's own kurtogram),
    demodulated, and the BPFI line of the envelope spectrum is tested with
    :func:`bearing_envelope.diagnosis.detection_statistic` (line-to-median ratio against a
    threshold at 1 % false-alarm probability).

    Parameters
    ----------
    case : bearing_envelope.io.Case
    sensor : mapping
        The config's ``sensor`` section (:meth:`TransferModel.from_mapping` keys).
    analysis : mapping
        The config's ``analysis`` section.
    snr_db : sequence of float
        SNR levels (dB); the noise seed is ``sensor.seed + index``.
    reference : Case, optional
        The healthy case of the same load. With it, the SNR is that of the defect-related part
        ``H e - H e_ref``; without it (and for the healthy case itself), of the whole response.

    Returns
    -------
    pandas.DataFrame
        One row per (snr_db, band): ``case, load_kN, depth_um, snr_db, snr_definition, band,
        band_strategy, band_low_hz, band_high_hz, statistic_db, threshold_db, detected,
        peak_hz, peak_amplitude``.
    """
    from .config import case_name
    from .diagnosis import detection_statistic
    from .signal import envelope_spectrum, resolve_band
    from .transfer import (TransferModel, excitation_from_history, select_excitation,
                           synthesize_acceleration)

    fs = float(case.fs)
    model = TransferModel.from_mapping(sensor, fs=fs)
    _, e = select_excitation(case.signals, model.excitation)
    exc = excitation_from_history(e, scale=model.excitation_scale)
    ref = None
    if reference is not None and float(case.depth_um) > 0:
        _, er = select_excitation(reference.signals, model.excitation)
        if er.size == e.size:
            ref = excitation_from_history(er, scale=model.excitation_scale)
    freqs = case_frequencies(case)
    rows = []
    for i, snr in enumerate(snr_db):
        acc, _info = synthesize_acceleration(exc, fs, model, reference=ref, seed=model.seed + i,
                                             fr=float(case.fr), snr_db=float(snr))
        need_kg = any(b["strategy"] == "kurtogram" for b in analysis["bands"])
        kg = _kurtogram(acc, fs, analysis) if need_kg else None
        for spec in analysis["bands"]:
            (lo, hi), _prov = resolve_band(spec, fs, kurtogram=kg, frequencies=freqs)
            f, a = envelope_spectrum(acc, fs, (lo, hi), order=int(analysis.get("filter_order", 4)),
                                     squared=bool(analysis.get("squared_envelope", False)))
            d = detection_statistic(f, a, float(case.bpfi), fr=float(case.fr))
            rows.append({
                "case": case_name(case.load_kN, case.depth_um), "load_kN": float(case.load_kN),
                "depth_um": float(case.depth_um), "snr_db": float(snr),
                "snr_definition": "defect part (H e - H e_ref)" if ref is not None else "whole response",
                "band": spec["name"], "band_strategy": spec["strategy"],
                "band_low_hz": float(lo), "band_high_hz": float(hi),
                "statistic_db": d.statistic_db, "threshold_db": d.threshold_db,
                "detected": bool(d.detected), "peak_hz": d.peak_hz,
                "peak_amplitude": d.peak_amplitude,
            })
    return pd.DataFrame(rows)


def _jsonable(obj):
    if isinstance(obj, Mapping):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    return obj


class log_to:
    """Context manager sending stderr (warnings, tracebacks) to a rule's log file.

    Used by the workflow scripts: ``with log_to(snakemake.log[0]): ...``. An exception is
    written to the log and re-raised so that the job fails.
    """

    def __init__(self, path):
        self.path = path

    def __enter__(self):
        import logging
        import sys

        self._fh = open(self.path, "w", encoding="utf-8")
        self._old = sys.stderr
        sys.stderr = self._fh
        logging.basicConfig(stream=self._fh, level=logging.INFO, force=True)
        return self._fh

    def __exit__(self, exc_type, exc, tb):
        import sys
        import traceback

        if exc_type is not None:
            traceback.print_exception(exc_type, exc, tb, file=self._fh)
        sys.stderr = self._old
        self._fh.close()
        return False
