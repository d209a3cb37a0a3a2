"""Is there an event train to find? The synchronous average of each development record's
squared envelope at its fault's rate, in every band of a scan (issue 32).

    nice -n 10 python -m benchmarks coherent_events --data DATA [--records 121,197,...]

``DATA``: laid out like the project's real-data folder (``benchmarks.real_records``). For each
CWRU 12 kHz drive-end development record (truth and Smith & Randall's grade in
``cwru_de12/index.csv``) and its fault's event rate (BPFO, BPFI at the nominal speed; a ball:
2 x BSF, its defect striking both races once per spin turn), the record's squared envelope in
every band of a scan (:data:`WIDTHS` Hz wide, half overlapping, from :data:`LOW_HZ` to
:data:`HIGH_HZ`) is folded at the rate refined on it within :data:`SEARCH`
(``study.rig.events.event_shape``): the **contrast** is the fold's peak over its floor (its
lower quartile), dB. A train of events the record holds stands out in some band (the clearly
diagnosed outer-race records: 10-20 dB); a record without one reads what a fold of its
squared envelope at an unrelated rate reads, the **control**: the same scan at the rate within
:data:`CONTROL_SPAN` x the fault's farthest from every multiple of the shaft's, the cage's and
the fault rates (:func:`control_rate`), whose best band is the scan's own chance level.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bearing_envelope.study.rig.events import event_shape

from .real_records import load_records

#: Band widths of the scan (Hz), each band half overlapping the next.
WIDTHS = (375.0, 750.0, 1500.0)
#: The scan's span (Hz): above the shaft's tones, below the 12 kHz records' anti-alias edge.
LOW_HZ, HIGH_HZ = 250.0, 5750.0
#: Relative half-width of the rate's refinement (a ball's spin rate slips up to 1.3 % on
#: CWRU 222 and 223; the races' rates sit within 0.5 % of nominal).
SEARCH = 0.015
#: The control's rate is sought between these multiples of the fault's rate ...
CONTROL_SPAN = (1.1, 1.4)


def bands(low: float = LOW_HZ, high: float = HIGH_HZ, widths=WIDTHS) -> list[tuple]:
    """The scan's bands (Hz): each width, half overlapping, within ``[low, high]``."""
    return [(lo, lo + w) for w in widths for lo in np.arange(low, high - w + 1.0, w / 2.0)]


def event_rate(rec) -> tuple[str, float]:
    """The fault's event family and its nominal rate (Hz) for a record of ``load_records``."""
    fam = {"bpfi": "bpfi", "bpfo": "bpfo", "bsf": "bsf2"}[rec["truth"]]
    ff = rec["ff"]
    return fam, (2.0 * ff.bsf if fam == "bsf2" else getattr(ff, fam))


def control_rate(rate_hz: float, rates) -> tuple[float, float]:
    """The rate in :data:`CONTROL_SPAN` x ``rate_hz`` farthest (relative) from every multiple
    of ``rates`` (the shaft's, the cage's and the fault rates), and that distance."""
    cand = rate_hz * np.linspace(*CONTROL_SPAN, 601)
    lines = np.array([k * f for f in rates for k in range(1, int(2 * rate_hz / f) + 2)])
    dist = np.min(np.abs(cand[:, None] - lines[None, :]) / lines[None, :], axis=1)
    i = int(np.argmax(dist))
    return float(cand[i]), float(dist[i])


def scan(x, fs: float, rate_hz: float, control_hz: float, band_list) -> dict:
    """The best contrast (dB) at the rate and at the control's over the bands, and where."""
    best, control = (-np.inf, None, np.nan), -np.inf
    for band in band_list:
        s = event_shape(x, fs, rate_hz, band=band, search=SEARCH)
        if s["contrast_db"] > best[0]:
            best = (s["contrast_db"], band, s["rate_hz"] / rate_hz - 1.0)
        c = event_shape(x, fs, control_hz, band=band, search=SEARCH)
        control = max(control, c["contrast_db"])
    return {"contrast_db": best[0], "band_hz": f"{best[1][0]:.0f}-{best[1][1]:.0f}",
            "rate_offset_percent": 100.0 * best[2], "control_db": control,
            "excess_db": best[0] - control}


def run(records, grades) -> pd.DataFrame:
    """One row per fault record: its grade, family, best contrast, control and CPU."""
    rows = []
    band_list = bands()
    for rec in records:
        if rec["truth"] is None:
            continue
        fam, rate = event_rate(rec)
        ff = rec["ff"]
        ctrl, gap = control_rate(rate, (rec["fr"], ff.ftf, ff.bpfo, ff.bpfi, ff.bsf))
        t0 = time.process_time()
        row = {"record": rec["record"], "set": rec["set"],
               "grade": grades.get(rec["record"], "-"), "family": fam,
               "control_hz": ctrl, "control_gap_percent": 100.0 * gap,
               **scan(rec["x"], rec["fs"], rate, ctrl, band_list)}
        row["cpu_s"] = time.process_time() - t0
        rows.append(row)
    return pd.DataFrame(rows)


def main(argv=None) -> int:
    """Print the table (markdown) and the contrast per grade."""
    p = argparse.ArgumentParser(prog="python -m benchmarks coherent_events",
                                description=__doc__.split("\n\n")[0])
    p.add_argument("--data", type=Path, required=True,
                   help="folder with cwru_de12/ (index.csv) and the normal record")
    p.add_argument("--records", default="",
                   help="comma-separated CWRU record numbers (default: every fault record)")
    a = p.parse_args(argv)
    idx = pd.read_csv(a.data / "cwru_de12" / "index.csv")
    grades = (dict(zip(idx.cwru_record, idx.sr2015_grade)) if "sr2015_grade" in idx else {})
    records = load_records(a.data)
    if a.records:
        keep = {int(r) for r in a.records.split(",")}
        records = [r for r in records if r["record"] in keep]
    df = run(records, grades)
    print(f"## coherent events ({len(bands())} bands, rates refined within "
          f"{100 * SEARCH:g} %)\n")
    print(df.to_markdown(index=False, floatfmt=".2f"))
    print(f"\nCPU s per record: {df.cpu_s.mean():.2f} (total {df.cpu_s.sum():.1f})")
    return 0


def smoke() -> None:
    """A synthetic 2 s record of bursts at 107 Hz in noise: the scan finds them above the
    control (two bands)."""
    fs, rate = 12000.0, 107.0
    rng = np.random.default_rng(0)
    t = np.arange(24000) / fs
    x = 0.2 * rng.standard_normal(t.size)
    for t0 in np.arange(0.01, 2.0, 1.0 / rate):
        ring = t >= t0
        x[ring] += np.exp(-800.0 * (t[ring] - t0)) * np.sin(2 * np.pi * 3000.0 * (t[ring] - t0))
    ctrl, gap = control_rate(rate, (29.95, 11.9))
    assert gap > 0.02 and CONTROL_SPAN[0] * rate <= ctrl <= CONTROL_SPAN[1] * rate
    out = scan(x, fs, rate, ctrl, [(2500.0, 3500.0), (4000.0, 5000.0)])
    assert out["excess_db"] > 3.0, out
