"""Rule envelope: raw spectrum and envelope harmonics of one case for every band."""
import json
import os

import numpy as np

from bearing_envelope.io import read_case
from bearing_envelope.pipeline import case_harmonics, log_to
from bearing_envelope.tables import write_csv_atomic

with log_to(snakemake.log[0]):  # noqa: F821
    analysis = json.loads(snakemake.params.analysis)  # noqa: F821
    with open(snakemake.input.bands, encoding="utf-8") as fh:  # noqa: F821
        bands = json.load(fh)
    case = read_case(snakemake.input.case)  # noqa: F821
    df, extra = case_harmonics(case, analysis, bands, full_output=True)
    write_csv_atomic(df, snakemake.output.harmonics)  # noqa: F821
    # Spectra for the figures: raw (float32) and each envelope spectrum up to (K + 1) x BPFI.
    fmax = (int(analysis.get("harmonics", 3)) + 1.5) * case.bpfi
    arrays = {"raw_f": extra["raw"][0].astype(np.float32), "raw_a": extra["raw"][1].astype(np.float32)}
    for name, b in extra["bands"].items():
        keep = b["f"] <= fmax
        arrays[f"env_{name}_f"] = b["f"][keep]
        arrays[f"env_{name}_a"] = b["amplitude"][keep]
    out = snakemake.output.spectra  # noqa: F821
    np.savez_compressed(out + ".tmp.npz", **arrays)
    os.replace(out + ".tmp.npz", out)
