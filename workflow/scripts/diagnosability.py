"""Rule diagnosability: the detection table of the sweep and one heat map per band strategy."""
import pandas as pd

from bearing_envelope.figures import fig_diagnosability_maps
from bearing_envelope.pipeline import log_to
from bearing_envelope.tables import write_csv_atomic

with log_to(snakemake.log[0]):  # noqa: F821
    df = pd.concat([pd.read_csv(p) for p in snakemake.input], ignore_index=True)  # noqa: F821
    df = df.sort_values(["band", "load_kN", "depth_um", "snr_db"], kind="stable")
    write_csv_atomic(df, snakemake.output.table)  # noqa: F821
    fig_diagnosability_maps(df, snakemake.output.maps)  # noqa: F821
