"""Rule bands: kurtogram and band limits of one case (bearing_envelope.pipeline.case_bands)."""
import json
import os

import numpy as np

from bearing_envelope.io import read_case
from bearing_envelope.pipeline import case_bands, log_to

with log_to(snakemake.log[0]):  # noqa: F821
    analysis = json.loads(snakemake.params.analysis)  # noqa: F821
    doc, kg = case_bands(read_case(snakemake.input.case), analysis)  # noqa: F821
    out = snakemake.output  # noqa: F821
    arrays = {} if kg is None else {
        "matrix": kg.matrix, "levels": kg.levels, "freqs": kg.freqs,
        "best": np.array([kg.level, kg.fc, kg.bandwidth, kg.kurtosis]),
    }
    tmp = out.kurtogram + ".tmp.npz"
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, out.kurtogram)
    with open(out.bands + ".tmp", "w", encoding="utf-8") as fh:
        json.dump(doc, fh, indent=1)
    os.replace(out.bands + ".tmp", out.bands)
