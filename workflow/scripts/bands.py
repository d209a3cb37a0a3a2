"""Rule bands: kurtogram and band limits of one case (bearing_envelope.study.pipeline.case_bands)."""
from bearing_envelope.io import read_case, write_bands, write_kurtogram
from bearing_envelope.study.pipeline import case_bands
from bearing_envelope.study.provenance import log_to
from bearing_envelope.study.job_transport import job_settings

with log_to(snakemake.log[0]):  # noqa: F821
    bands, kurtogram = case_bands(read_case(snakemake.input.case),  # noqa: F821
                                  job_settings(snakemake).analysis)  # noqa: F821
    write_kurtogram(snakemake.output.kurtogram, kurtogram)  # noqa: F821
    write_bands(snakemake.output.bands, bands)  # noqa: F821
