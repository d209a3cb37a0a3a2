# Config validation (before any job) and the small input helpers shared by every rule.
import json
from pathlib import Path

from snakemake.utils import validate

from bearing_envelope.config import SCHEMA_PATH, case_name, check_config
from bearing_envelope.provenance import code_dependencies
from bearing_envelope.tables import parse_case_name


validate(config, str(SCHEMA_PATH))
check_config(config)

# Library code is an input of the rules that use it: editing a module reruns the stages whose
# script imports it (directly or through other package modules), derived from the imports.
SRC = Path(workflow.basedir) / "src" / "bearing_envelope"
SCRIPTS = Path(workflow.basedir) / "workflow" / "scripts"
ENV = "../envs/bearing_envelope.yaml"


def script_code(name):
    """The package sources the workflow script `name` depends on (its rule's `code` input)."""
    return code_dependencies(SCRIPTS / name)


SIM_CODE = script_code("simulate.py")
SENSOR_CODE = script_code("sensor.py")
SIGNAL_CODE = sorted(set(script_code("bands.py")) | set(script_code("envelope.py")))

LOADS = config["sweep"]["loads_kN"]
DEPTHS = config["sweep"]["depths_um"]
CASES = [case_name(f, h) for f in LOADS for h in DEPTHS]
BAND_NAMES = [b["name"] for b in config["analysis"]["bands"]]


wildcard_constraints:
    case=r"F[0-9.]+kN_h[0-9.]+um",
    load=r"[0-9.]+",
    depth=r"[0-9.]+",


def scene_params(wildcards):
    """The scene and fidelity as a canonical JSON string: a change reruns the simulations."""
    return json.dumps({"scene": config.get("scene", {}), "fidelity": config.get("fidelity", "standard")},
                      sort_keys=True)


def analysis_params(wildcards):
    return json.dumps(config["analysis"], sort_keys=True)


def example_cases(wildcards=None):
    """Cases drawn alone (Figs 4, 5, 7, 9, 11): the deepest defect and the healthy race
    (or the shallowest depth) at the highest load."""
    load = max(LOADS)
    return {
        "defect": case_name(load, max(DEPTHS)),
        "healthy": case_name(load, min(DEPTHS)),
    }


def reference_case(wildcards):
    """The healthy case of the same load, when the sweep has one (defines the defect part);
    none for a healthy case itself (its SNR is that of its whole response)."""
    load, depth = parse_case_name(wildcards.case)
    if float(depth) > 0 and 0 in [float(d) for d in DEPTHS]:
        return f"results/cases/{case_name(load, 0)}.h5"
    return []


# The files the analysis reads: the simulated cases, or their copies with the synthetic
# acceleration (rule `sensor`) when `analysis.signal` is `acceleration`.
ANALYSIS_STAGE = "sensor" if config["analysis"].get("signal", "p_max") == "acceleration" else "cases"


def analysis_case(wildcards):
    return f"results/{ANALYSIS_STAGE}/{wildcards.case}.h5"


def analysis_cases():
    return [f"results/{ANALYSIS_STAGE}/{case}.h5" for case in CASES]


def all_targets():
    return [
        "results/tables/harmonics.csv",
        "results/tables/cases.csv",
        "results/figures",
    ] + (
        ["results/tables/diagnosability.csv", "results/figures_diagnosability"]
        if config.get("sensor") and config.get("diagnosability", {}).get("enabled", True)
        else []
    )
