# Config validation (before any job) and the small input helpers shared by every rule.
import json
import os
import sys
from pathlib import Path

from bearing_envelope.study.figures import example_pairs
from bearing_envelope.study.limits import precheck, profile_files
from bearing_envelope.study.recovery import is_dry_run, marker_if_present, recover_case_files
from bearing_envelope.study.provenance import code_dependencies
from bearing_envelope.study.case_id import CASE_NAME_REGEX
from bearing_envelope.study.settings import workflow_settings


def check_limits(settings):
    """bearing_envelope.study.limits.precheck (case names, lower bounds, tradeoff section,
    resource estimate per case): one line naming the field, no job runs."""
    try:
        return precheck(settings)
    except ValueError as exc:
        print(f"bearing_envelope: invalid configuration: {exc}", file=sys.stderr)
        raise SystemExit(1)


def load_workflow_settings():
    """The one validating loader (bearing_envelope.study.settings.workflow_settings): reads
    ./config.yaml and the --configfile files once each, merges them with --config (a designation
    is a complete bearing), validates and types once; on error one line naming the field, and
    no job runs. `config` becomes the validated mapping (schema defaults filled)."""
    try:
        settings = workflow_settings(workflow.overwrite_configfiles,
                                     dict(workflow.config_settings.config))
    except ValueError as exc:  # ConfigError, one line naming the field
        print(f"bearing_envelope: invalid configuration: {exc}", file=sys.stderr)
        raise SystemExit(1)
    config.clear()
    config.update(settings.config)
    return settings


SETTINGS = load_workflow_settings()
ESTIMATES = check_limits(SETTINGS)  # bearing_envelope.study.limits

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

LOADS = list(SETTINGS.sweep.loads_kN)
DEPTHS = list(SETTINGS.sweep.depths_um)
CASE_IDS = SETTINGS.cases
CASES = [c.name for c in CASE_IDS]
#: The typed case each name stands for: a case's identity names its files, never the reverse.
CASE_BY_NAME = {c.name: c for c in CASE_IDS}
BAND_NAMES = [b.name for b in SETTINGS.analysis.bands]

wildcard_constraints:
    case=CASE_NAME_REGEX,


def case_id(wildcards):
    """The typed case (CaseId) of a job: looked up by the name it gave its files."""
    return CASE_BY_NAME[wildcards.case]


# Typed values reach the jobs as params (bearing_envelope.study.job_transport.JobValue): the canonical
# JSON Snakemake compares to rerun a job when a value changes, carrying the value the loader
# built; each script reads them with study.job_transport.job_settings (nothing validated again).


def simulation_params(wildcards):
    """The scene section and the resolved fidelity (a change reruns the simulations only),
    carrying the job's case and its scene as the loader built it."""
    return SETTINGS.simulation_param(case_id(wildcards))


def sensor_params(wildcards):
    """The typed transfer model; "{}" (carrying None) without a `sensor:` section."""
    return SETTINGS.sensor_param()


def analysis_params(wildcards):
    """The typed analysis settings (a change reruns the analysis jobs only)."""
    return SETTINGS.analysis_param()


def example_cases(wildcards=None):
    """Cases drawn alone (Figs 7, 9, 11): the deepest defect and the healthy race (or the
    shallowest depth) at the highest load; and the pairs of Figs 4 and 5: the sweep's cases
    nearest the study's 250 kN / 15 um, 500 kN / 50 um and 750 kN / 100 um, each with the
    healthy race of its load (bearing_envelope.study.figures.example_pairs)."""
    load = max(LOADS)
    # with a location axis: the cases of its first location (the figures of one location)
    first = [c for c in CASE_IDS if c.location == CASE_IDS[0].location]
    at_load = [c for c in first if c.load_kN == load]
    return {
        "defect": max(at_load, key=lambda c: (c.depth_um, c.width_um or 0.0)).name,
        "healthy": min(at_load, key=lambda c: (c.depth_um, c.width_um or 0.0)).name,
        "pairs": example_pairs(first),
    }


def reference_case(wildcards):
    """The healthy case of the same load for a defect case (defines the defect part); for a
    healthy case, the shallowest defect case of its load (its noise defines the healthy cells'
    noise: bearing_envelope.study.pipeline.case_diagnosability). None where the sweep lacks it."""
    case = case_id(wildcards)
    if case.depth_um > 0:
        return f"results/cases/{case.healthy.name}.h5" if 0.0 in DEPTHS else []
    peers = [c for c in CASE_IDS if c.load_kN == case.load_kN and c.location == case.location
             and c.depth_um > 0]
    if not peers:
        return []
    return f"results/cases/{min(peers, key=lambda c: (c.depth_um, c.width_um or 0.0)).name}.h5"


#: Healthy cases (depth 0): their false alarms are measured (rule false_alarms).
HEALTHY = [c.name for c in CASE_IDS if c.depth_um == 0]


# The files the analysis reads: the simulated cases, or their copies with the synthetic
# acceleration (rule `sensor`) when `analysis.signal` is `acceleration`.
ANALYSIS_STAGE = "sensor" if SETTINGS.analysis.signal == "acceleration" else "cases"


def recovery_consumers(stage, case):
    """Files made from results/{stage}/{case}.h5 (bearing_envelope.study.recovery)."""
    return [f"results/bands/{case}.json"] + ([f"results/sensor/{case}.h5"] if stage == "cases" else [])


def analysis_case(wildcards):
    return f"results/{ANALYSIS_STAGE}/{wildcards.case}.h5"


def analysis_cases():
    return [f"results/{ANALYSIS_STAGE}/{case}.h5" for case in CASES]


def all_targets():
    return [
        "results/tables/harmonics.csv",
        "results/tables/cases.csv",
        "results/figures",
        "results/tables_html",
        "results/paper/paper.md",
    ] + (
        ["results/tables/diagnosability.csv", "results/figures_diagnosability"]
        if SETTINGS.sensor is not None and SETTINGS.diagnosability.enabled
        else []
    )


def paper_run_tables(wildcards=None):
    """Tables of a paper-conventions run (config key `paper_run`: its working directory), when
    that run exists: the page then shows both columns."""
    run = config.get("paper_run")
    if not run:
        return {}
    names = ("cases", "harmonics", "bands")
    paths = {n: os.path.join(run, "results", "tables", f"{n}.csv") for n in names}
    return paths if all(os.path.exists(p) for p in paths.values()) else {}


# Before the DAG: every case file verified in full (checksums, attribute digest); a bad one is
# moved aside, and a bad or deleted one is rebuilt with what is made from it, in this run
# (bearing_envelope.study.recovery; nothing changes on a dry run).
if workflow.is_main_process:
    recover_case_files({"cases": CASES, ANALYSIS_STAGE: CASES}, recovery_consumers,
                       dry_run=is_dry_run(workflow=workflow))
