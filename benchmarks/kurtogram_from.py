"""The kurtogram band of the detection map chosen once per case or from each noisy record (issue 16).

    nice -n 5 python benchmarks/kurtogram_from.py [--config config.yaml] [--loads 250 750]
        [--results results] [-o kurtogram_from.csv]

For the sweep's simulated cases (``results/cases/*.h5`` of a finished default sweep), runs the
map's test (``pipeline.case_diagnosability``) in the kurtogram band only, with
``kurtogram_from: clean`` (the band once per case, from the noise-free acceleration: the map's
default) and ``record`` (the kurtogram of each noisy record, as an analyst would), and prints per
mode and SNR: the band(s) picked, the mean statistic over the defect cases and the number of
defect cells detected, and the healthy cells detected.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd

from bearing_envelope.io import read_case
from bearing_envelope.study.pipeline import case_diagnosability
from bearing_envelope.study.settings import workflow_settings


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", default="config.yaml")
    ap.add_argument("--results", default="results")
    ap.add_argument("--loads", nargs="*", type=float, default=None)
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args(argv)
    import yaml

    with open(args.config) as fh:
        raw = yaml.safe_load(fh)
    settings = workflow_settings(raw, [args.config])
    cfg = settings.config
    analysis = dict(cfg["analysis"])
    analysis["bands"] = [b for b in analysis["bands"] if b["strategy"] == "kurtogram"]
    snr = cfg["diagnosability"]["snr_db"]
    cases = [c for c in settings.cases if args.loads is None or c.load_kN in args.loads]
    path = lambda c: Path(args.results) / "cases" / f"{c.name}.h5"  # noqa: E731
    rows = []
    for c in cases:
        peers = [p for p in settings.cases if p.load_kN == c.load_kN and p.depth_um > 0]
        if c.depth_um > 0:
            ref = next(p for p in settings.cases if p.load_kN == c.load_kN and p.depth_um == 0)
        else:
            ref = min(peers, key=lambda p: (p.depth_um, p.width_um or 0.0))
        case, reference = read_case(path(c)), read_case(path(ref))
        for mode in ("clean", "record"):
            rows.append(case_diagnosability(case, cfg["sensor"], analysis, snr,
                                            reference=reference, kurtogram_from=mode))
        print(c.name, flush=True)
    df = pd.concat(rows, ignore_index=True)
    if args.output:
        df.to_csv(args.output, index=False)
    df["band_khz"] = (df.band_low_hz / 1e3).round(2).astype(str) + "-" + \
        (df.band_high_hz / 1e3).round(2).astype(str)
    defect = df[df.depth_um > 0]
    summary = defect.groupby(["kurtogram_from", "snr_db"]).agg(
        mean_statistic_db=("statistic_db", "mean"), detected=("detected", "sum"),
        cells=("detected", "size"),
        bands=("band_khz", lambda s: "; ".join(f"{k} ({v})" for k, v in s.value_counts().items())))
    healthy = df[df.depth_um == 0].groupby(["kurtogram_from", "snr_db"]).agg(
        healthy_detected=("detected", "sum"), healthy_cells=("detected", "size"))
    print(summary.join(healthy).to_markdown())


if __name__ == "__main__":
    main()
