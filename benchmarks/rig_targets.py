"""Issue 42's rig targets read off scored rig runs, side by side (docs/virtual_rig.md, "With the
dynamics").

    python -m benchmarks rig_targets runs/rig_qs runs/rig_dyn     # folders of `bearing-envelope rig`

Per run (the same written pass rules, :mod:`bearing_envelope.study.rig.scoring`):

- line height and 3x/1x within tolerance (records where compared), OR 3:00 re 6:00 within 6 dB
  (``outer_race.csv``), the ball records' verdict class (``rule_class`` of the 2 x BSF records);
- secondary events per ball passage of the OR 3:00 records, measured and simulated
  (``event_shape.csv``, :func:`bearing_envelope.study.rig.events.event_shape`);
- line height (dB over the floor) against pit diameter per location and position, measured and
  simulated (median over the records), and the excitation model of each group.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pandas as pd


def _rate(card, rule: str, mask=None) -> tuple[int, int]:
    col = card[f"rule_{rule}"] if mask is None else card[mask][f"rule_{rule}"]
    col = col[col.isin(["PASS", "FAIL"])]
    return int((col == "PASS").sum()), int(col.size)


def targets(run: Path) -> dict:
    """The targets of one run folder."""
    card = pd.read_csv(run / "scorecard.csv", dtype={"record": str})
    ratios = pd.read_csv(run / "outer_race.csv")
    ev = pd.read_csv(run / "event_shape.csv", dtype={"record": str})
    at3 = ev[(ev.location == "outer_race") & (ev.position_deg == 90.0)]
    ok3 = ratios[ratios.rule.isin(["PASS", "FAIL"])]
    return {"height": _rate(card, "height_db"), "h3": _rate(card, "h3_db"),
            "h2": _rate(card, "h2_db"), "family": _rate(card, "family"),
            "ball_class": _rate(card, "class", card.family == "bsf2"),
            "or_3_6": (int((ok3.rule == "PASS").sum()), int(ok3.shape[0])),
            "or_3_6_db": list(zip(ratios.meas_db.round(1), ratios.sim_db.round(1))),
            "secondary": list(zip(at3.record, at3.meas_secondary_events.round(2),
                                  at3.sim_secondary_events.round(2)))}


def height_by_size(run: Path) -> pd.DataFrame:
    """Median measured and simulated line height per location, position, fs and pit."""
    card = pd.read_csv(run / "scorecard.csv", dtype={"record": str})
    g = card.groupby(["family", "position_deg", "fs_hz", "length_um"])
    return g[["meas_height_db", "sim_height_db"]].median().round(1).reset_index()


def models(run: Path) -> dict:
    """The excitation model of each simulated record (the simulated record's meta)."""
    out = {}
    for f in sorted((run / "sim").glob("*_sim.npz")):
        with np.load(f) as z:
            meta = json.loads(str(z["meta_json"]))
        out[meta["source_record"]] = meta.get("excitation", "quasi_static")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks rig_targets", description=__doc__)
    ap.add_argument("runs", nargs="+", help="scored rig run folders")
    args = ap.parse_args(argv)
    runs = [Path(r) for r in args.runs]
    res = [targets(r) for r in runs]
    print("| target | " + " | ".join(r.name for r in runs) + " |")
    print("|---|" + "---|" * len(runs))
    for key in ("height", "h3", "h2", "family", "ball_class", "or_3_6"):
        print(f"| {key} | " + " | ".join(f"{t[key][0]}/{t[key][1]}" for t in res) + " |")
    for r, t in zip(runs, res):
        print(f"\n{r.name}: OR 3:00 re 6:00 (measured, simulated dB): {t['or_3_6_db']}")
        print(f"{r.name}: secondary events per ball passage at 3:00 (record, measured, "
              f"simulated): {t['secondary']}")
        m = models(r)
        print(f"{r.name}: excitation models: "
              f"{ {k: sum(v == k for v in m.values()) for k in sorted(set(m.values()))} }")
    tabs = [height_by_size(r) for r in runs]
    merged = tabs[0]
    for r, t in zip(runs[1:], tabs[1:]):
        merged = merged.merge(t.drop(columns="meas_height_db"), on=list(t.columns[:4]),
                              suffixes=("", f"_{r.name}"))
    print("\nline height over the floor, dB (median over the records; sim columns per run in "
          "the order given)\n")
    print(merged.to_markdown(index=False))
    return 0


def smoke() -> None:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        run = Path(tmp)
        pd.DataFrame({"record": ["a", "b"], "family": ["bpfo", "bsf2"], "position_deg": [90.0, 0],
                      "fs_hz": [12e3, 12e3], "length_um": [177.8, 177.8],
                      "meas_height_db": [40.0, 10.0], "sim_height_db": [42.0, 30.0],
                      **{f"rule_{k}": ["PASS", "FAIL"] for k in
                         ("height_db", "h3_db", "h2_db", "family", "class")}}
                     ).to_csv(run / "scorecard.csv", index=False)
        pd.DataFrame({"record_3": ["a"], "record_6": ["c"], "meas_db": [-12.0],
                      "sim_db": [-10.0], "rule": ["PASS"]}).to_csv(run / "outer_race.csv",
                                                                   index=False)
        pd.DataFrame({"record": ["a"], "location": ["outer_race"], "position_deg": [90.0],
                      "meas_secondary_events": [1.5], "sim_secondary_events": [0.0]}
                     ).to_csv(run / "event_shape.csv", index=False)
        (run / "sim").mkdir()
        main([str(run)])


if __name__ == "__main__":
    raise SystemExit(main())
