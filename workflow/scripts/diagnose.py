"""Rule diagnose: BPFI detection in the synthetic acceleration of one case, per SNR and band."""
from bearing_envelope.io import read_case
from bearing_envelope.study.pipeline import case_diagnosability, log_to
from bearing_envelope.io import write_csv_atomic
from bearing_envelope.study.job_transport import job_settings

with log_to(snakemake.log[0]):  # noqa: F821
    inp, job = snakemake.input, job_settings(snakemake)  # noqa: F821
    ref = read_case(inp.reference) if inp.reference else None
    df = case_diagnosability(
        read_case(inp.case),
        job.sensor,
        job.analysis,
        snakemake.params.snr_db,  # noqa: F821
        reference=ref,
        kurtogram_from=snakemake.params.kurtogram_from,  # noqa: F821
    )
    write_csv_atomic(df, snakemake.output[0])  # noqa: F821
