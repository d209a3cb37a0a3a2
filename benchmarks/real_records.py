"""Diagnosis of real records: the verdict and its confidence on the CWRU 12 kHz drive-end
development set, per fault set and per confidence level, and the false-alarm rate on noise
shaped like the normal record.

    nice -n 10 python -m benchmarks real_records --data DATA [--trials 500]
        [--variants] [--lofo] [--no-mc] [--only-mc]

``DATA`` is a folder laid out like the project's real-data folder: ``cwru_de12/index.csv`` with
its records, and ``cwru_097_normal_0hp.npz``.

Records: the 28 of ``cwru_de12/`` (seven fault sets x four loads; truth in its ``index.csv``)
and the normal record ``cwru_097_normal_0hp.npz`` (48 kHz). Each goes through
``analyze_signal`` with the ``bearing-envelope analyze`` defaults (``RECORD_OPTIONS``: default
bands, 3 harmonics, 2 sidebands, 3 raw orders, pfa 1 %) and the fault frequencies of the SKF 6205 at the record's nominal speed,
twice: before (:data:`NOMINAL_OPTIONS`: nominal speed, fundamentals within +- 1 %) and after
(:data:`OPTIONS`: ``measure_speed=True``, the shaft rate read from the raw spectrum and the
fundamentals searched within 0.5 % of their kinematic value at it).
A verdict is ``right`` (the labelled family; 2 x BSF counts for a ball), ``wrong`` (another
family named) or ``abstain`` (no diagnosis: nothing detected, or "cannot tell").

``--variants`` repeats the evaluation without the band-count tie-break of the second pass
(``faults.BAND_TIE_BREAK = False``), with the kurtogram's former unlimited cell
(``kurtogram_min_orders=None``), with a fifth band, the full band of the cepstrum-pre-whitened
signal (Borghesani et al. 2013), and with the kurtogram band replaced by the infogram's (Antoni
2016) or the protrugram's (Barszcz & Jabłoński 2011) choice among bands at least as wide as
the kurtogram's limit (``bearing_envelope.signal.bandselect``). ``--lofo`` re-decides the stored tables with the tuned margins
(``HIGH_MIN_MARGIN_DB``, ``MEDIUM_MIN_MARGIN_DB``) chosen on six fault sets and judged on the
seventh (leave one fault set out), and the search window at the measured speed
(:data:`SPEED_WINDOW_GRID`) likewise, each window also with the former band count
(``faults.DISTINCT_BAND_OVERLAP = inf``: overlapping bands counted each; the third pass
counts distinct demodulation bands). The Monte Carlo draws ``--trials`` records of Gaussian noise
whose spectrum has the shape of the normal record's (Welch PSD, 1024-sample segments, after
decimation to 12 kHz), as long as a development record, and counts any diagnosis (or "cannot
tell") as a false alarm; 95 % Clopper-Pearson interval. CPU seconds: ``time.process_time``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import signal as sps

from bearing_envelope.diagnosis import (KURTOGRAM_MIN_ORDERS, RECORD_OPTIONS, AnalysisOptions,
                                        analyze_signal, faults)
from bearing_envelope.diagnosis.detection import clopper_pearson
from bearing_envelope.diagnosis.faults import evidence as faults_evidence
from bearing_envelope.diagnosis.faults import verdict as faults_verdict
from bearing_envelope.physics.kinematics import fault_frequencies
from bearing_envelope.signal import DEFAULT_BANDS
from bearing_envelope.signal.bandselect import infogram_band, protrugram_band

INCH = 25.4e-3
TRUTH = {"inner_race": "bpfi", "outer_race": "bpfo", "ball": "bsf", "normal": None}
#: Sets graded clearly diagnosable by envelope analysis (see docs/benchmarks.md, issue 24).
CLEAR_SETS = ("IR007", "OR007@6", "OR007@3")
#: Issue 24 (h24c): the shaft rate measured from the raw spectrum's shaft harmonics, the
#: fundamentals searched within the slip of the rolling elements around its kinematic values.
OPTIONS = RECORD_OPTIONS
#: The former settings (nominal speed, +- 1 % search), for the before/after table.
NOMINAL_OPTIONS = dataclasses.replace(RECORD_OPTIONS, measure_speed=False)
#: Fundamental search half-widths (%) at the measured speed for the leave-one-fault-set-out
#: choice (``--lofo``).
SPEED_WINDOW_GRID = (0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1.0, 1.5)
CPW_BAND = {"name": "cpw", "strategy": "fraction", "low": 0.0, "high": 0.5, "clamp": True,
            "prewhiten": True}


def load_records(data: Path) -> list[dict]:
    """The development records and the normal record, with their truth and fault set."""
    idx = pd.read_csv(data / "cwru_de12" / "index.csv")
    out = []
    for r in idx.itertuples():
        pos = "" if pd.isna(r.outer_race_position) else f"@{str(r.outer_race_position)[:-3]}"
        kind = {"inner_race": "IR", "outer_race": "OR", "ball": "B"}[r.fault]
        out.append(_record(data / "cwru_de12" / r.file, r.fault,
                           f"{kind}{int(r.fault_diameter_mils):03d}{pos}"))
    out.append(_record(data / "cwru_097_normal_0hp.npz", "normal", "normal"))
    return out


def _record(path: Path, fault: str, fault_set: str) -> dict:
    with np.load(path, allow_pickle=False) as z:
        x, fs, meta = z["x"], float(z["fs"]), json.loads(str(z["meta_json"]))
    g = meta["geometry"]
    ff = fault_frequencies(meta["shaft_hz"], g["n_balls"], g["ball_diameter_in"] * INCH,
                           g["pitch_diameter_in"] * INCH, g["contact_angle_deg"])
    return {"name": path.stem, "record": int(meta.get("cwru_record", path.stem.split("_")[1])), "set": fault_set,
            "truth": TRUTH[fault], "x": x, "fs": fs, "fr": float(meta["shaft_hz"]), "ff": ff}


def outcome(diagnosis: str | None, truth: str | None) -> str:
    """``right``, ``wrong`` or ``abstain`` (a ball is right as BSF or 2 x BSF)."""
    if diagnosis is None:
        return "right" if truth is None else "abstain"
    fam = "bsf" if diagnosis == "bsf2" else diagnosis
    return "right" if fam == truth else "wrong"


def hold_width(rec) -> float:
    """The narrowest band that can hold the lines searched (Hz): KURTOGRAM_MIN_ORDERS x
    n_harmonics x the highest fault frequency (2 x BSF included)."""
    ff = rec["ff"]
    top = max(ff.bpfo, ff.bpfi, ff.ftf, 2.0 * ff.bsf)
    return KURTOGRAM_MIN_ORDERS * OPTIONS.n_harmonics * top


def selected_band(name: str, band) -> AnalysisOptions:
    """The default bands with the kurtogram band replaced by a band chosen elsewhere."""
    spec = {"name": name, "strategy": "fixed", "low_hz": band[0], "high_hz": band[1],
            "clamp": True}
    return dataclasses.replace(OPTIONS, bands=(spec, *DEFAULT_BANDS[1:]))


def infogram_options(rec) -> AnalysisOptions:
    band, _ = infogram_band(rec["x"], rec["fs"], min_bandwidth=hold_width(rec))
    return selected_band("infogram", band)


def protrugram_options(rec) -> AnalysisOptions:
    w = hold_width(rec)
    band, _ = protrugram_band(rec["x"], rec["fs"], bandwidth=w, fmax_env=w)
    return selected_band("protrugram", band)


def evaluate(records, options) -> tuple[pd.DataFrame, dict]:
    """One row per record (verdict, confidence, outcome, evidence) and the stored tables;
    ``options`` is an AnalysisOptions or a function of the record giving one (its CPU time
    counts)."""
    rows, stored = [], {}
    for rec in records:
        t0 = time.process_time()
        opts = options(rec) if callable(options) else options
        table, det = analyze_signal(rec["x"], rec["fs"], fr=rec["fr"], fault_frequencies=rec["ff"],
                                    options=opts, full_output=True)
        v = det["verdict"]
        d = v.diagnosis
        kg = det["kurtogram"]
        rows.append({"record": rec["record"], "set": rec["set"], "truth": rec["truth"],
                     "diagnosis": None if d is None else d.family, "confidence": v.confidence,
                     "candidates": "/".join(v.candidates),
                     "truth_in_candidates": rec["truth"] is not None and any(
                         outcome(c, rec["truth"]) == "right" for c in v.candidates),
                     "outcome": outcome(None if d is None else d.family, rec["truth"]),
                     "bands": 0 if d is None else len(d.bands_agreeing),
                     "distinct": 0 if d is None else d.n_bands,
                     "margin_db": np.nan if d is None else round(d.margin_db, 1),
                     "second": "/".join(f.family for f in v.detected[1:] if d is not None),
                     "kurtogram_hz": np.nan if kg is None else round(kg.bandwidth),
                     "cpu_s": time.process_time() - t0})
        stored[rec["record"]] = (table, det["families"], v.n_tests, rec["fs"] / rec["x"].size,
                                 rec["fr"], rec["truth"], rec["set"])
    return pd.DataFrame(rows), stored


def per_set(df: pd.DataFrame) -> pd.DataFrame:
    """Right / wrong / abstain per fault set, with the confidence of each verdict."""
    out = []
    for s, g in df.groupby("set", sort=False):
        conf = ", ".join(f"{r.record}:{r.diagnosis or '-'}/{r.confidence or 'none'}"
                         for r in g.itertuples())
        out.append({"set": s, "n": len(g), "right": int((g.outcome == "right").sum()),
                    "wrong": int((g.outcome == "wrong").sum()),
                    "abstain": int((g.outcome == "abstain").sum()), "verdicts": conf})
    return pd.DataFrame(out)


def per_level(df: pd.DataFrame) -> pd.DataFrame:
    """What each confidence level meant on these records."""
    out = []
    for level in ("high", "medium", "low", faults.CANNOT_TELL, None):
        g = df[df.confidence.isna()] if level is None else df[df.confidence == level]
        out.append({"confidence": level or "none (nothing detected)", "verdicts": len(g),
                    "right": int((g.outcome == "right").sum()),
                    "wrong": int((g.outcome == "wrong").sum()),
                    "abstain": int((g.outcome == "abstain").sum()),
                    "truth among candidates": int(g.truth_in_candidates.sum())})
    return pd.DataFrame(out)


def redecide(stored, high_db: float, medium_db: float) -> pd.DataFrame:
    """The verdicts of the stored tables with other margins (module constants patched)."""
    keep = faults_evidence.HIGH_MIN_MARGIN_DB, faults_evidence.MEDIUM_MIN_MARGIN_DB
    faults_evidence.HIGH_MIN_MARGIN_DB, faults_evidence.MEDIUM_MIN_MARGIN_DB = high_db, medium_db
    try:
        rows = []
        for rec, (table, fams, n_tests, df_hz, fr, truth, s) in stored.items():
            v = faults.fault_verdict(table, fams, pfa=OPTIONS.pfa, n_tests=n_tests, fr=fr,
                                     df_hz=df_hz)
            d = v.diagnosis
            rows.append({"record": rec, "set": s, "confidence": v.confidence,
                         "outcome": outcome(None if d is None else d.family, truth)})
        return pd.DataFrame(rows)
    finally:
        faults_evidence.HIGH_MIN_MARGIN_DB, faults_evidence.MEDIUM_MIN_MARGIN_DB = keep


def lofo(stored) -> pd.DataFrame:
    """Leave one fault set out: on the other sets, the margins (grid) with no wrong verdict at
    high or medium and the most right ones there (ties: the larger margins); judged on the
    held-out set."""
    grid = [(h, m) for h in range(0, 22, 2) for m in range(0, 26, 2)]
    results = {g: redecide(stored, *g) for g in grid}
    sets = [s for s in dict.fromkeys(v[6] for v in stored.values()) if s != "normal"]
    out = []
    for held in sets:
        def score(g):
            r = results[g][results[g].set != held]
            conf = r.confidence.isin(["high", "medium"])
            wrong = int((conf & (r.outcome == "wrong")).sum())
            return (wrong == 0, int((conf & (r.outcome == "right")).sum()), g)
        best = max(grid, key=score)
        r = results[best][results[best].set == held]
        out.append({"held_out": held, "high_min_margin_db": best[0],
                    "medium_min_margin_db": best[1],
                    "high": f"{int(((r.confidence == 'high') & (r.outcome == 'right')).sum())}"
                            f" right / {int(((r.confidence == 'high') & (r.outcome == 'wrong')).sum())} wrong",
                    "medium": f"{int(((r.confidence == 'medium') & (r.outcome == 'right')).sum())}"
                              f" right / {int(((r.confidence == 'medium') & (r.outcome == 'wrong')).sum())} wrong",
                    "right": int((r.outcome == "right").sum()), "n": len(r)})
    return pd.DataFrame(out)


def lofo_speed_window(records) -> tuple[pd.DataFrame, dict]:
    """Leave one fault set out for ``measured_speed_search_percent``: on the other six sets the
    value of :data:`SPEED_WINDOW_GRID` with no wrong verdict at high or medium, then the most
    right verdicts, ties to the wider window; judged on the held-out set. The stored tables
    are also re-decided with the former band count (``former``: every agreeing band counted)."""
    runs, former = {}, {}
    for p in SPEED_WINDOW_GRID:
        runs[p], stored = evaluate(records, dataclasses.replace(
            OPTIONS, measured_speed_search_percent=p))
        former[p] = _former_band_count(stored)
    lofo_speed_window.former = former
    sets = [s for s in dict.fromkeys(r["set"] for r in records) if s != "normal"]
    out = []
    for held in sets:
        def score(p):
            r = runs[p][runs[p].set != held]
            conf = r.confidence.isin(["high", "medium"])
            return (int((conf & (r.outcome == "wrong")).sum()) == 0,
                    int((r.outcome == "right").sum()), p)
        best = max(SPEED_WINDOW_GRID, key=score)
        r = runs[best][runs[best].set == held]
        out.append({"held_out": held, "window_chosen_pct": best,
                    "verdicts": ", ".join(f"{x.record}:{x.diagnosis or '-'}/{x.confidence or 'none'}"
                                          for x in r.itertuples()),
                    "right": int((r.outcome == "right").sum()),
                    "wrong": int((r.outcome == "wrong").sum()),
                    "wrong_high_or_medium": int((r.confidence.isin(["high", "medium"])
                                                 & (r.outcome == "wrong")).sum()), "n": len(r)})
    return pd.DataFrame(out), runs


def shaped_noise(normal: dict, trials: int, n: int, seed: int):
    """Gaussian noise records of ``n`` samples at 12 kHz with the normal record's spectral
    shape (its Welch PSD after decimation 48 -> 12 kHz), unit variance."""
    x = sps.decimate(normal["x"], int(round(normal["fs"] / 12000.0)), ftype="fir")
    fw, pw = sps.welch(x - x.mean(), fs=12000.0, nperseg=1024)
    f = np.fft.rfftfreq(n, 1.0 / 12000.0)
    shape = np.sqrt(np.interp(f, fw, pw))
    for t in range(trials):
        rng = np.random.default_rng([seed, t])
        spec = shape * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
        y = np.fft.irfft(spec, n)
        yield y / y.std()


def noise_mc(normal: dict, trials: int, n: int, seed: int = 24) -> dict:
    """False alarms of the verdict on shaped noise (0 hp fault frequencies, fs 12 kHz)."""
    ff = fault_frequencies(29.95, 9, 0.3126 * INCH, 1.537 * INCH, 0.0)
    alarms = any_line = 0
    t0 = time.process_time()
    for y in shaped_noise(normal, trials, n, seed):
        v = analyze_signal(y, 12000.0, fr=29.95, fault_frequencies=ff, options=OPTIONS,
                           full_output=True)[1]["verdict"]
        alarms += v.confidence is not None
        any_line += any(f.detected for f in v.families)
    lo, hi = clopper_pearson(alarms, trials)
    lo2, hi2 = clopper_pearson(any_line, trials)
    return {"trials": trials, "false_alarms": alarms, "rate": alarms / trials, "ci": (lo, hi),
            "any_family_detected": any_line, "any_ci": (lo2, hi2),
            "cpu_s": time.process_time() - t0}


def _print_evaluation(title, df):
    print(f"\n## {title}\n")
    print(per_set(df).to_markdown(index=False))
    print()
    print(per_level(df).to_markdown(index=False))
    faults_only = df[df.truth.notna()]
    clear = df[df.set.isin(CLEAR_SETS)]
    print(f"\nright {int((df.outcome == 'right').sum())}/{len(df)} "
          f"({100 * (df.outcome == 'right').mean():.0f} %), wrong "
          f"{int((df.outcome == 'wrong').sum())}, abstain {int((df.outcome == 'abstain').sum())};"
          f" clearly diagnosable sets {int((clear.outcome == 'right').sum())}/{len(clear)} right;"
          f" wrong at high {int(((df.confidence == 'high') & (df.outcome == 'wrong')).sum())},"
          f" at medium {int(((df.confidence == 'medium') & (df.outcome == 'wrong')).sum())};"
          f" fault records {len(faults_only)}; CPU {df.cpu_s.sum():.1f} s")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--data", type=Path, required=True,
                   help="folder with cwru_de12/index.csv and cwru_097_normal_0hp.npz")
    p.add_argument("--trials", type=int, default=500)
    p.add_argument("--variants", action="store_true")
    p.add_argument("--lofo", action="store_true")
    p.add_argument("--no-mc", action="store_true")
    p.add_argument("--only-mc", action="store_true", help="only the noise Monte Carlo")
    args = p.parse_args(argv)
    records = load_records(args.data)
    if args.only_mc:
        _print_mc(records, args.trials)
        return 0
    before = evaluate(records, NOMINAL_OPTIONS)[0]
    _print_evaluation("before: nominal speed, +- 1 % (RECORD_OPTIONS, measure_speed=False)",
                      before)
    df, stored = evaluate(records, OPTIONS)
    _print_evaluation("measured speed, +- 0.5 % (RECORD_OPTIONS)", df)
    print("\n" + df.drop(columns=["cpu_s", "truth_in_candidates"]).to_markdown(index=False))
    if args.variants:
        _print_evaluation("without the band-count tie-break (faults.BAND_TIE_BREAK = False)",
                          _without_tie_break(records))
        former = dataclasses.replace(OPTIONS, kurtogram_min_orders=None)
        _print_evaluation("kurtogram cell unlimited (former)", evaluate(records, former)[0])
        cpw = dataclasses.replace(OPTIONS, bands=(*DEFAULT_BANDS, CPW_BAND))
        _print_evaluation("+ cepstrum-pre-whitened full band", evaluate(records, cpw)[0])
        _print_evaluation("infogram band instead of the kurtogram's",
                          evaluate(records, infogram_options)[0])
        _print_evaluation("protrugram band instead of the kurtogram's",
                          evaluate(records, protrugram_options)[0])
    if args.lofo:
        print("\n## leave one fault set out (margins chosen on the other six)\n")
        print(lofo(stored).to_markdown(index=False))
        table, runs = lofo_speed_window(records)
        print("\n## leave one fault set out (search window at the measured speed)\n")
        print(table.to_markdown(index=False))
        print("\n" + "\n".join(
            f"window {p} %: right {int((g.outcome == 'right').sum())}/{len(g)}, wrong "
            f"{int((g.outcome == 'wrong').sum())}, wrong at high/medium "
            f"{int((g.confidence.isin(['high', 'medium']) & (g.outcome == 'wrong')).sum())}"
            f" (high {int(((g.confidence == 'high') & (g.outcome == 'right')).sum())} right,"
            f" medium {int(((g.confidence == 'medium') & (g.outcome == 'right')).sum())} right);"
            f" former band count: right {int((h.outcome == 'right').sum())}, wrong "
            f"{int((h.outcome == 'wrong').sum())}, wrong at high/medium "
            f"{int((h.confidence.isin(['high', 'medium']) & (h.outcome == 'wrong')).sum())}"
            for (p, g), h in zip(runs.items(), lofo_speed_window.former.values())))
    if not args.no_mc:
        _print_mc(records, args.trials)
    print(f"\ntotal CPU {time.process_time():.0f} s (process)")
    return 0


def smoke() -> None:
    """A synthetic data folder: one inner-race record (2 s at 12 kHz, impulses at BPFI ringing
    at 3 kHz) and a 1 s normal record of noise; the evaluation and a 2-trial Monte Carlo."""
    import tempfile

    geometry = {"n_balls": 9, "ball_diameter_in": 0.3126, "pitch_diameter_in": 1.537,
                "contact_angle_deg": 0.0}
    fr = 29.95
    bpfi = fault_frequencies(fr, 9, 0.3126 * INCH, 1.537 * INCH, 0.0).bpfi
    rng = np.random.default_rng(0)
    t = np.arange(24000) / 12000.0
    x = 0.2 * rng.standard_normal(t.size)
    for t0 in np.arange(0.01, 2.0, 1.0 / bpfi):
        ring = t >= t0
        x[ring] += np.exp(-800.0 * (t[ring] - t0)) * np.sin(2 * np.pi * 3000.0 * (t[ring] - t0))
    with tempfile.TemporaryDirectory() as d:
        folder = Path(d, "cwru_de12")
        folder.mkdir()
        for path, xs, fs, rec in ((folder / "cwru_105_IR007_0hp_DE12.npz", x, 12000.0, 105),
                                  (Path(d, "cwru_097_normal_0hp.npz"),
                                   rng.standard_normal(48000), 48000.0, 97)):
            np.savez(path, x=xs, fs=fs, meta_json=json.dumps(
                {"shaft_hz": fr, "geometry": geometry, "cwru_record": rec}))
        pd.DataFrame([{"file": "cwru_105_IR007_0hp_DE12.npz", "cwru_record": 105,
                       "fault": "inner_race", "fault_diameter_mils": 7,
                       "outer_race_position": np.nan, "load_hp": 0, "rpm_nominal": 1797}]
                     ).to_csv(folder / "index.csv", index=False)
        main(["--data", d, "--trials", "2"])


def _former_band_count(stored) -> pd.DataFrame:
    """The stored tables re-decided with every agreeing band counted (before the third pass:
    ``faults.DISTINCT_BAND_OVERLAP = inf``)."""
    keep = faults_evidence.DISTINCT_BAND_OVERLAP
    faults_evidence.DISTINCT_BAND_OVERLAP = float("inf")
    try:
        return redecide(stored, faults_evidence.HIGH_MIN_MARGIN_DB,
                        faults_evidence.MEDIUM_MIN_MARGIN_DB)
    finally:
        faults_evidence.DISTINCT_BAND_OVERLAP = keep


def _without_tie_break(records) -> pd.DataFrame:
    """The evaluation with the second pass's band-count tie-break off."""
    keep = faults_verdict.BAND_TIE_BREAK
    faults_verdict.BAND_TIE_BREAK = False
    try:
        return evaluate(records, OPTIONS)[0]
    finally:
        faults_verdict.BAND_TIE_BREAK = keep


def _print_mc(records, trials):
    """The shaped-noise Monte Carlo with :data:`OPTIONS`, printed."""
    n = int(np.median([r["x"].size for r in records if r["truth"] is not None]))
    mc = noise_mc(records[-1], trials, n)
    print(f"\n## shaped noise ({mc['trials']} records of {n} samples)\n\nverdict with a "
          f"finding: {mc['false_alarms']}/{mc['trials']} = {100 * mc['rate']:.2f} % "
          f"(95 % CI {100 * mc['ci'][0]:.2f}-{100 * mc['ci'][1]:.2f} %); any family detected"
          f" (weak included): {mc['any_family_detected']}/{mc['trials']} (95 % CI "
          f"{100 * mc['any_ci'][0]:.2f}-{100 * mc['any_ci'][1]:.2f} %); CPU "
          f"{mc['cpu_s']:.0f} s")


if __name__ == "__main__":
    raise SystemExit(main())
