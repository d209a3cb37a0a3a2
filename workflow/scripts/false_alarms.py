"""Rule false_alarms: the detection map's test on many noise realisations of a healthy case."""
from bearing_envelope.io import read_case
from bearing_envelope.study.pipeline import case_false_alarms, log_to
from bearing_envelope.io import write_csv_atomic
from bearing_envelope.study.job_transport import job_settings

with log_to(snakemake.log[0]):  # noqa: F821
    inp, job = snakemake.input, job_settings(snakemake)  # noqa: F821
    df = case_false_alarms(
        read_case(inp.case),
        job.sensor,
        job.analysis,
        snakemake.params.snr_db,  # noqa: F821
        int(snakemake.params.n_trials),  # noqa: F821
        reference=read_case(inp.reference) if inp.reference else None,
        kurtogram_from=snakemake.params.kurtogram_from,  # noqa: F821
    )
    write_csv_atomic(df, snakemake.output[0])  # noqa: F821
