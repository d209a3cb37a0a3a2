"""Rule sensor: the case file plus its synthetic acceleration (signals/acceleration)."""
import json

from bearing_envelope.commands.sensor import write_sensor_case
from bearing_envelope.pipeline import log_to

with log_to(snakemake.log[0]):  # noqa: F821
    inp = snakemake.input  # noqa: F821
    info = write_sensor_case(
        inp.case,
        json.loads(snakemake.params.sensor),  # noqa: F821
        snakemake.output[0],  # noqa: F821
        reference=inp.reference or None,
        config_label="config.yaml: sensor",
    )
    print(f"sensor: {inp.case} -> {snakemake.output[0]}, SNR {info['snr_db_achieved']:.2f} dB")  # noqa: F821
