# Before Snakemake reads ./config.yaml (the `configfile:` directive): read it with the project's
# strict loader, so a YAML syntax error or a duplicate key stops the run with its line number.
# Files given with --configfile are read by Snakemake's command line before any workflow code
# runs; for those, `bearing-envelope check-config FILE` names the line (README).
import sys as _sys
from pathlib import Path as _Path

from bearing_envelope.study.limits import refuse_config_code as _refuse_config_code
from bearing_envelope.study.settings import ConfigError as _ConfigError

if not workflow.overwrite_configfiles and _Path("config.yaml").is_file():
    try:
        _refuse_config_code(["config.yaml"])  # before Snakemake's YTE could run it
    except _ConfigError as _exc:
        print(f"bearing_envelope: invalid configuration: {_exc}", file=_sys.stderr)
        raise SystemExit(1)
