"""Rule sensor: the case file plus its synthetic acceleration (signals/acceleration)."""
from bearing_envelope.io import read_case, write_sensor_case
from bearing_envelope.study.pipeline import case_acceleration
from bearing_envelope.study.provenance import log_to
from bearing_envelope.study.job_transport import job_settings

with log_to(snakemake.log[0]):  # noqa: F821
    inp, out = snakemake.input, snakemake.output[0]  # noqa: F821
    case = read_case(inp.case)
    acc, info = case_acceleration(case, job_settings(snakemake).sensor,  # noqa: F821
                                  reference=read_case(inp.reference) if inp.reference else None)
    info.update(source_case=inp.case, reference_case=inp.reference or None,
                config="config.yaml: sensor", command="workflow rule sensor")
    write_sensor_case(out, acc, case=case, source=inp.case, provenance=info)
    print(f"sensor: {inp.case} -> {out}, SNR {info['snr_db_achieved']:.2f} dB")
