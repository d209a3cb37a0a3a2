"""Rule paper: the study's findings next to this sweep's numbers (bearing_envelope.study.paper)."""
import pandas as pd

from bearing_envelope.study.paper import (STUDY_LOCATION, compare, flat_band, render_html,
                                          render_markdown, write_page)
from bearing_envelope.study.pipeline import log_to

inp, out = snakemake.input, snakemake.output  # noqa: F821
with log_to(snakemake.log[0]):  # noqa: F821
    paper = {k[len("paper_"):]: v for k, v in inp.items() if k.startswith("paper_")} or None
    rows = compare(inp.cases, inp.harmonics, inp.bands, paper=paper)
    bands = pd.read_csv(inp.bands)
    if "location" in bands.columns:  # a location sweep: the study's (inner-race) cases
        bands = bands[bands["location"] == STUDY_LOCATION]
    try:
        flat = flat_band(bands) if (bands["band"] == "kurtogram").any() else None
    except ValueError:  # no defect depths in the study's 15-50 um (another scene, e.g. CWRU)
        flat = None
    text = render_markdown(rows, flat=flat)
    write_page(text, out.md)
    write_page(render_html(text), out.html)
