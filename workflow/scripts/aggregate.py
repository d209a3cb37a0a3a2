"""Rule aggregate: tidy harmonic table, per-case summary, band table and load x depth pivots."""
import json
import os
import shutil

import pandas as pd

from bearing_envelope.io import read_case
from bearing_envelope.pipeline import case_summary, log_to
from bearing_envelope.tables import concat_tidy, pivot_tables, write_csv_atomic

with log_to(snakemake.log[0]):  # noqa: F821
    inp, out = snakemake.input, snakemake.output  # noqa: F821
    tidy = concat_tidy(pd.read_csv(p) for p in inp.harmonics)
    write_csv_atomic(tidy, out.harmonics)
    write_csv_atomic(pd.DataFrame([case_summary(read_case(p)) for p in inp.cases]), out.cases)
    rows = []
    for p in inp.bands:
        with open(p, encoding="utf-8") as fh:
            doc = json.load(fh)
        for b in doc["bands"]:
            rows.append({"case": doc["case"], "load_kN": doc["load_kN"], "depth_um": doc["depth_um"],
                         "band": b["name"], "strategy": b["strategy"], "low_hz": b["low_hz"],
                         "high_hz": b["high_hz"], "clamped": b["clamped"]})
    write_csv_atomic(pd.DataFrame(rows), out.bands)
    tmp = out.pivots + ".tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    for key, table in pivot_tables(tidy).items():
        table.to_csv(os.path.join(tmp, f"{key}.csv"))
    shutil.rmtree(out.pivots, ignore_errors=True)
    os.replace(tmp, out.pivots)
