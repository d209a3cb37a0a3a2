"""Rule tradeoff: the speed-accuracy study (bearing_envelope.study.tradeoff) -> CSV, Pareto CSV, PNG."""
from bearing_envelope.study.provenance import log_to
from bearing_envelope.io import write_csv_atomic
from bearing_envelope.study.job_transport import job_settings
from bearing_envelope.study.tradeoff import pareto_points, plot_tradeoff, study_from_config

with log_to(snakemake.log[0]) as log:  # noqa: F821
    setup = job_settings(snakemake).tradeoff  # noqa: F821
    df = study_from_config(setup.settings, scene=setup.scene_mapping,
                           analysis=setup.analysis.to_mapping(),
                           progress=lambda msg: print(msg, file=log, flush=True))
    write_csv_atomic(df, snakemake.output.table)  # noqa: F821
    write_csv_atomic(pareto_points(df), snakemake.output.pareto)  # noqa: F821
    plot_tradeoff(df, snakemake.output.plot)  # noqa: F821
