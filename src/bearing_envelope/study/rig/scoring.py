"""The rig's scorecard: each record's features read by ``analyze`` on the measured record and
on its simulated twin alike, and the written pass rules (docs/virtual_rig.md, "Pass rules").

Every function here reads ``analyze``'s tables (the verdict table and the lines CSV, as
pandas DataFrames); none simulates or reads a record.
"""

from __future__ import annotations

import math
import os

import numpy as np

from ...physics.locations import get_location

__all__ = ["TOL_DB", "TOL_LINE", "RATIO_BANDS", "record_features", "scorecard",
           "load_trends", "outer_race_ratios", "features_in_measured_band",
           "outer_race_ratios_in_band", "band_ratios", "pass_rates", "scorecard_markdown",
           "of_record"]


def of_record(lines, name: str):
    """The rows of ``analyze``'s lines table that belong to the record ``name`` (its file's
    name without suffix).

    Parameters
    ----------
    lines : pandas.DataFrame
        ``analyze --csv`` (a ``file`` column).
    name : str
        The record's name (``<name>_sim`` for a simulated one).

    Returns
    -------
    pandas.Series of bool
        The mask.
    """
    return lines.file.map(lambda f: os.path.splitext(os.path.basename(str(f)))[0]) == name


#: Tolerances of the pass rules (docs/virtual_rig.md), dB or fraction.
TOL_DB, TOL_LINE = 6.0, 0.005


def _class(diag, conf, family) -> str:
    if diag != family:
        return "nothing" if not isinstance(diag, str) or not diag else f"other:{diag}"
    return "named" if conf in ("medium", "high") else "low"


def record_features(table, lines, name: str, family: str) -> dict:
    """The scorecard's features of one record from analyze's verdict table and lines CSV.

    Parameters
    ----------
    table, lines : pandas.DataFrame
        ``analyze --table`` and ``analyze --csv``.
    name : str
        The record's name.
    family : str
        The family it is judged on (the location's ``family``).

    Returns
    -------
    dict
        ``diagnosis``, ``confidence``, ``class``, ``detected``, the best band and fr, and where
        the family's line is detected ``line_orders``, ``height_db``, ``h1``, ``h2_db``,
        ``h3_db``, ``sideband_db``.
    """
    rows = table[(table.record == name) & (table.family == family)]
    if rows.empty:
        return {"diagnosis": None, "confidence": None}
    r = rows.iloc[0]
    diag = r.record_diagnosis if isinstance(r.record_diagnosis, str) else ""
    out = {"diagnosis": diag, "confidence": r.record_confidence,
           "class": _class(diag, r.record_confidence, family), "detected": bool(r.detected),
           "band_low_hz": float(r.band_low_hz), "band_high_hz": float(r.band_high_hz),
           "fr_hz": float(r.fr_hz)}
    if not r.detected:
        return out
    fr = float(r.fr_hz)
    out.update(line_orders=float(r.h1_hz) / fr, height_db=float(r.h1_db),
               h1=float(r.h1_amplitude),
               h2_db=20 * math.log10(max(r.h2_amplitude, 1e-300) / r.h1_amplitude),
               h3_db=20 * math.log10(max(r.h3_amplitude, 1e-300) / r.h1_amplitude))
    ln = lines[of_record(lines, name) & (lines.band == r.band) &
               (lines.base == family) & (lines.order == 1)]
    sb = ln[ln.sideband.abs() == 1].amplitude  # the +-1 sidebands (the written rule)
    if family != "bpfo" and len(sb):
        out["sideband_db"] = 20 * math.log10(max(sb.mean(), 1e-300) / r.h1_amplitude)
    return out


def _pass(key, m, s) -> str:
    if m.get(key) is None or s.get(key) is None:
        return "n/a"
    tol = TOL_LINE * m[key] if key == "line_orders" else TOL_DB
    return "PASS" if abs(m[key] - s[key]) <= tol else "FAIL"


def scorecard(conditions, measured_table, measured_lines, sim_table, sim_lines):
    """One row per record: measured and simulated features and each rule's outcome.

    Parameters
    ----------
    conditions : sequence of RigCondition
        The records scored (:func:`~.manifest.record_conditions`).
    measured_table, sim_table : pandas.DataFrame
        ``analyze --table`` of the measured and of the simulated records.
    measured_lines, sim_lines : pandas.DataFrame
        ``analyze --csv`` of the same.

    Returns
    -------
    pandas.DataFrame
        One row per record: its fault, the measured and simulated features (line heights
        in dB, frequencies in Hz) and the pass/fail of each rule.
    """
    import pandas as pd  # lazy: pandas ~1.8 s, only the scorecard needs it

    rows = []
    for c in conditions:
        fam = get_location(c.location).family  # the line family it is judged on
        m = record_features(measured_table, measured_lines, c.name, fam)
        s = record_features(sim_table, sim_lines, c.name + "_sim", fam)
        row = {"record": c.name, "family": fam, "load": c.load, "fs_hz": c.fs_hz,
               "position_deg": c.position_deg, "length_um": c.length_um}
        for k in ("diagnosis", "confidence", "class", "line_orders", "sideband_db", "h2_db",
                  "h3_db", "height_db", "h1", "band_low_hz", "band_high_hz", "fr_hz"):
            row[f"meas_{k}"], row[f"sim_{k}"] = m.get(k), s.get(k)
        row["rule_family"] = ("PASS" if m.get("diagnosis") == s.get("diagnosis") else "FAIL")
        row["rule_class"] = "PASS" if m.get("class") == s.get("class") else "FAIL"
        gate = m.get("detected", False)
        for k in ("line_orders", "sideband_db", "h2_db", "h3_db", "height_db"):
            row[f"rule_{k}"] = _pass(k, m, s) if gate else "n/a"
        rows.append(row)
    return pd.DataFrame(rows)


def _ratio_db(a, b):
    """20 log10(a / b), None where either is missing (no line detected)."""
    try:
        a, b = float(a), float(b)
    except (TypeError, ValueError):
        return None
    return 20 * math.log10(a / b) if np.isfinite(a) and np.isfinite(b) and a > 0 and b > 0 \
        else None


def load_trends(card, *, flat_db_per_load: float = 1.0) -> list:
    """Slope of the outer race's line height over the operating load (dB per unit of the
    manifest's ``load``: CWRU dB/hp; least squares over the
    records of one position, size and fs with a line on both sides) and the written rule:
    same sign, or both within +-``flat_db_per_load``.

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`.
    flat_db_per_load : float
        Slopes within this are flat, dB per unit of load.

    Returns
    -------
    list of dict
        Per position, size and fs: ``n``, ``meas_db_per_load``, ``sim_db_per_load``, ``rule``.
    """
    out = []
    or_ = card[card.family == "bpfo"]
    for (pos, dia, fs), g in or_.groupby(["position_deg", "length_um", "fs_hz"]):
        g = g[g.meas_height_db.notna() & g.sim_height_db.notna()]
        if g.load.nunique() < 2:
            continue
        hp = g.load.to_numpy(float)
        m, s = (float(np.polyfit(hp, g[k].to_numpy(float), 1)[0])
                for k in ("meas_height_db", "sim_height_db"))
        flat = abs(m) <= flat_db_per_load and abs(s) <= flat_db_per_load
        out.append({"position_deg": pos, "length_um": dia, "fs_hz": fs, "n": len(g),
                    "meas_db_per_load": m, "sim_db_per_load": s,
                    "rule": "PASS" if flat or m * s > 0 else "FAIL"})
    return out


def outer_race_ratios(card) -> list:
    """BPFO fundamental at 3:00 over 6:00 (90 over 0 deg; same size, load, fs), measured and
    simulated, dB.

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`.

    Returns
    -------
    list of dict
        Per pair: ``record_3``, ``record_6``, ``meas_db``, ``sim_db``, ``rule``.
    """
    out = []
    or_ = card[card.family == "bpfo"]
    for _, r3 in or_[or_.position_deg == 90.0].iterrows():
        r6 = or_[(or_.position_deg == 0.0) & (or_.load == r3.load) &
                 (or_.length_um == r3.length_um) & (or_.fs_hz == r3.fs_hz)]
        if r6.empty:
            continue
        r6 = r6.iloc[0]
        meas, sim = _ratio_db(r3.meas_h1, r6.meas_h1), _ratio_db(r3.sim_h1, r6.sim_h1)
        rule = "n/a" if meas is None else (
            "FAIL: no simulated line" if sim is None else
            "PASS" if abs(meas - sim) <= TOL_DB else "FAIL")
        out.append({"record_3": r3.record, "record_6": r6.record, "meas_db": meas,
                    "sim_db": sim, "rule": rule})
    return out


#: The bands the 3:00 / 6:00 ratio is also read in with both records in one band (not the
#: rule: a second reading of the same lines): analyze's fixed fs/4-3fs/8 band and the raw
#: signal's envelope.
RATIO_BANDS = ("fs4_3fs8", "raw")


def _line_amplitude(lines, name: str, band: str):
    """The BPFO fundamental's amplitude in one of analyze's bands (None: no such row)."""
    ln = lines[of_record(lines, name) & (lines.band == band) &
               (lines.base == "bpfo") & (lines.order == 1) & (lines.sideband == 0)]
    return float(ln.amplitude.iloc[0]) if len(ln) else None


def band_ratios(lines, name: str, band: str, family: str) -> dict:
    """2x/1x, 3x/1x and (not BPFO) the +-1 sidebands over the line, dB, in one band.

    Parameters
    ----------
    lines : pandas.DataFrame
        ``analyze --csv``.
    name : str
        The record's name.
    band, family : str
        analyze's band and family names.

    Returns
    -------
    dict
        ``h2_db``, ``h3_db`` and ``sideband_db`` where the lines exist; empty without a line.
    """
    g = lines[of_record(lines, name) & (lines.band == band)
              & (lines.base == family)]
    a = {(int(o), int(sb)): float(v) for o, sb, v in zip(g.order, g.sideband, g.amplitude)}
    h1 = a.get((1, 0), 0.0)
    if h1 <= 0:
        return {}
    out = {k: 20 * math.log10(max(a.get((o, 0), 0.0), 1e-300) / h1)
           for k, o in (("h2_db", 2), ("h3_db", 3))}
    if family != "bpfo" and (1, -1) in a and (1, 1) in a:
        out["sideband_db"] = 20 * math.log10(max(0.5 * (a[(1, -1)] + a[(1, 1)]), 1e-300) / h1)
    return out


def features_in_measured_band(card, measured_lines, sim_lines) -> list:
    """The harmonic and sideband ratios of both records read in the measured record's best band
    (a second reading, not the rule: the rule reads each record in its own best band, and the
    simulated record's can differ). Only where that band is one of analyze's fixed bands (a
    kurtogram band is the record's own).

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`.
    measured_lines, sim_lines : pandas.DataFrame
        analyze's lines tables of the measured and the simulated records.

    Returns
    -------
    list of dict
        Per record and feature: band, measured and simulated dB, ``within_tol``.
    """
    out = []
    for _, r in card[card.meas_h1.notna()].iterrows():
        m = measured_lines[of_record(measured_lines, r.record)
                           & np.isclose(measured_lines.band_low_hz, r.meas_band_low_hz)
                           & np.isclose(measured_lines.band_high_hz, r.meas_band_high_hz)]
        bands = set(m.band) - {"kurtogram"}
        if not bands:
            continue
        band = sorted(bands)[0]
        fm = band_ratios(measured_lines, r.record, band, r.family)
        fs = band_ratios(sim_lines, f"{r.record}_sim", band, r.family)
        for k in ("sideband_db", "h2_db", "h3_db"):
            if k in fm and k in fs:
                out.append({"record": r.record, "band": band, "feature": k, "meas_db": fm[k],
                            "sim_db": fs[k], "within_tol": abs(fm[k] - fs[k]) <= TOL_DB})
    return out


def outer_race_ratios_in_band(card, measured_lines, sim_lines, bands=RATIO_BANDS) -> list:
    """BPFO fundamental at 3:00 over 6:00 with both records read in the same band (each of
    ``bands``), measured and simulated, dB: the rule's ratio reads each record in its own
    best band, which mixes bands where the two records ring different resonances.

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`'s result.
    measured_lines, sim_lines : pandas.DataFrame
        ``analyze --csv`` of the measured and of the simulated records.
    bands : sequence of str
        analyze's band names.

    Returns
    -------
    list of dict
        Per pair and band: ``meas_db``, ``sim_db``, ``within_tol`` (the rule's 6 dB).
    """
    out = []
    for r in outer_race_ratios(card):
        for band in bands:
            a = [_line_amplitude(lines, rec + suffix, band)
                 for lines, suffix in ((measured_lines, ""), (sim_lines, "_sim"))
                 for rec in (r["record_3"], r["record_6"])]
            meas, sim = _ratio_db(a[0], a[1]), _ratio_db(a[2], a[3])
            ok = None if meas is None or sim is None else bool(abs(meas - sim) <= TOL_DB)
            out.append({"record_3": r["record_3"], "record_6": r["record_6"], "band": band,
                        "meas_db": meas, "sim_db": sim, "within_tol": ok})
    return out


def pass_rates(card) -> dict:
    """Per rule: records passed, records compared.

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`.

    Returns
    -------
    dict
        ``{rule: [passed, compared]}``.
    """
    out = {}
    for col in [c for c in card.columns if c.startswith("rule_")]:
        v = card[col]
        n = int((v != "n/a").sum())
        out[col[5:]] = [int((v == "PASS").sum()), n]
    return out


def scorecard_markdown(card, ratios, trends=()) -> str:
    """The scorecard as a markdown table (docs/virtual_rig.md), pass rates and OR ratios.

    Parameters
    ----------
    card : pandas.DataFrame
        :func:`scorecard`.
    ratios : pandas.DataFrame
        :func:`outer_race_ratios`.
    trends : pandas.DataFrame or sequence
        :func:`load_trends`.

    Returns
    -------
    str
        Markdown.
    """
    def num(v, fmt):
        return "-" if v is None or (isinstance(v, float) and not np.isfinite(v)) else fmt % v

    head = ("| record | measured | simulated | line (orders) m / s | sideband dB m / s | "
            "2x/1x dB m / s | 3x/1x dB m / s | height dB m / s | rules F C L S 2 3 H |\n"
            "|---|---|---|---|---|---|---|---|---|\n")
    rows = []
    for _, r in card.iterrows():
        rules = " ".join({"PASS": "P", "FAIL": "x", "n/a": "-"}[r[c]] for c in
                         ("rule_family", "rule_class", "rule_line_orders", "rule_sideband_db",
                          "rule_h2_db", "rule_h3_db", "rule_height_db"))
        cells = [r.record, f"{r.meas_diagnosis or 'nothing'} ({r.meas_confidence or '-'})",
                 f"{r.sim_diagnosis or 'nothing'} ({r.sim_confidence or '-'})"]
        for k, fmt in (("line_orders", "%.4f"), ("sideband_db", "%.1f"), ("h2_db", "%.1f"),
                       ("h3_db", "%.1f"), ("height_db", "%.1f")):
            cells.append(f"{num(r['meas_' + k], fmt)} / {num(r['sim_' + k], fmt)}")
        rows.append("| " + " | ".join(cells) + f" | {rules} |")
    rates = pass_rates(card)
    lines = [head + "\n".join(rows), "",
             "Pass rates (passed / compared): " + "; ".join(
                 f"{k} {v[0]}/{v[1]}" for k, v in rates.items())]
    if len(ratios):
        lines += ["", "| 3:00 record | 6:00 record | measured dB | simulated dB | rule |",
                  "|---|---|---|---|---|"]
        lines += [f"| {r.record_3} | {r.record_6} | {num(r.meas_db, '%.1f')} | "
                  f"{num(r.sim_db, '%.1f')} | {r.rule} |" for _, r in ratios.iterrows()]
    if len(trends):
        lines += ["", "| OR position deg | size um | fs Hz | records | measured dB/load | "
                  "simulated dB/load | rule |", "|---|---|---|---|---|---|---|"]
        lines += [f"| {r.position_deg:g} | {r.length_um:g} | {r.fs_hz:g} | {r.n} | "
                  f"{r.meas_db_per_load:.2f} | {r.sim_db_per_load:.2f} | {r.rule} |"
                  for _, r in trends.iterrows()]
    return "\n".join(lines) + "\n"


