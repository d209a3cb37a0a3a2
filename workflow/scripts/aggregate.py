"""Rule aggregate: tidy harmonic table, per-case summary, band table and load x depth pivots."""
import pandas as pd

from bearing_envelope.io import (read_bands, read_case, read_tidy, write_band_table,
                                 write_case_table, write_pivots, write_tidy)
from bearing_envelope.study.pipeline import case_summary
from bearing_envelope.study.provenance import log_to
from bearing_envelope.study.tables import add_location, band_table, concat_tidy, pivot_tables

with log_to(snakemake.log[0]):  # noqa: F821
    inp, out = snakemake.input, snakemake.output  # noqa: F821
    cases = snakemake.params.cases  # noqa: F821  (the sweep's typed cases: CaseId)
    tidy = concat_tidy((read_tidy(p, sealed=True) for p in inp.harmonics), cases)
    write_tidy(out.harmonics, tidy)
    write_case_table(out.cases, add_location(
        pd.DataFrame([case_summary(read_case(p)) for p in inp.cases]), cases))
    write_band_table(out.bands, add_location(band_table(read_bands(p) for p in inp.bands), cases))
    write_pivots(out.pivots, pivot_tables(tidy))
