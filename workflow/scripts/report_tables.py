"""Rule report_tables: each sweep table as an HTML page the report shows in place."""
from pathlib import Path

import pandas as pd

from bearing_envelope.io import atomic_dir
from bearing_envelope.study.paper import write_page
from bearing_envelope.study.pipeline import log_to
from bearing_envelope.study.tables import table_html

inp, out = snakemake.input, Path(snakemake.output[0])  # noqa: F821
with log_to(snakemake.log[0]) as log, atomic_dir(out) as tmp:  # noqa: F821
    pages = {
        "cases": ({"cases": pd.read_csv(inp.cases)}, "One row per case: peak pressures, "
                  "end/centre pressure, roller load, BPFI, contact solves, simulation time."),
        "bands": ({"bands": pd.read_csv(inp.bands)}, "Demodulation band limits per case and "
                  "strategy (clamped = cut below Nyquist)."),
        "harmonics": ({"harmonics": pd.read_csv(inp.harmonics)}, "Tidy table of every amplitude "
                      "(docs/file-format.md, 'Tidy tables')."),
        "pivots": ({p.stem: pd.read_csv(p) for p in sorted(Path(inp.pivots).glob("*.csv"))},
                   "Load x depth pivots per (band, quantity, order), like the study's Figs 8 and 12-20."),
    }
    for name, (tables, caption) in pages.items():
        write_page(table_html(tables, f"{name}.csv", caption), tmp / f"{name}.html")
        print(name, sum(len(t) for t in tables.values()), "rows", file=log)
