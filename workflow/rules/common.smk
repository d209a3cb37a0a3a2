# Config validation (before any job) and the small input helpers shared by every rule.
import json
import os
import sys
from pathlib import Path

from bearing_envelope.study.figures import example_pairs
from bearing_envelope.study.handoff import ENV_VAR as HANDOFF_VAR, hand_off, take_over
from bearing_envelope.study.limits import checked_settings, paper_run_tables as run_tables, profile_files
from bearing_envelope.study.recovery import Artefact, is_dry_run, marker_if_present, recover_artefacts
from bearing_envelope.study.provenance import code_dependencies
from bearing_envelope.study.case_id import CASE_NAME_REGEX
from bearing_envelope.study.config_read import config_files
from bearing_envelope.study.settings import workflow_settings


def refuse(exc):
    """One line naming the field, and no job runs."""
    message = str(exc)
    if "__use_yte__" in message:
        message += YTE_NOTE
    print(f"bearing_envelope: invalid configuration: {message}", file=sys.stderr)
    raise SystemExit(1)


#: Snakemake evaluates every --configfile as a YTE template (snakemake.common.configfile, from
#: its command line, before this file is parsed): nothing of the workflow can run earlier.
YTE_NOTE = ("; Snakemake has already evaluated this file as a YTE template before the workflow "
            "started (its behaviour for every --configfile): check overlays with "
            "`bearing-envelope check-config FILE` before passing them to Snakemake")

#: Where the main process leaves the validated settings for its jobs (study.handoff).
HANDOFF_DIR = Path(".snakemake") / "bearing_envelope"


def load_workflow_settings():
    """The one validating loader, run once per run. The main process runs
    bearing_envelope.study.settings.workflow_settings (./config.yaml and the --configfile files
    read once each, merged with --config, validated and typed once) and the pre-run check
    (bearing_envelope.study.limits.precheck: case names, lower bounds, the cost of every job),
    then hands the settings to its jobs (study.handoff, through the environment). A job (a
    cluster job parses this file again) takes them over: no loader, no check. On error one
    line naming the field, and no job runs. `config` becomes the validated mapping."""
    files = config_files(workflow.overwrite_configfiles)
    overrides = dict(workflow.config_settings.config)
    address = os.environ.get(HANDOFF_VAR)
    try:
        if workflow.is_main_process:
            settings, estimates = checked_settings(workflow.overwrite_configfiles, overrides)
        elif address:
            settings, estimates = take_over(address, files, overrides), []
        else:  # an executor that passed no hand-off: the loader once more (no pre-run check)
            settings, estimates = workflow_settings(workflow.overwrite_configfiles, overrides), []
    except ValueError as exc:  # ConfigError / HandOffError, one line naming the field
        refuse(exc)
    for est in estimates:  # what each case's simulate job will warn about, said before any job
        if est.note:
            print(f"bearing_envelope: warning: case {est.case}: {est.note}", file=sys.stderr)
    if workflow.is_main_process and not is_dry_run(workflow=workflow):
        os.environ[HANDOFF_VAR] = hand_off(settings, HANDOFF_DIR, files, overrides)
        workflow.register_envvars(HANDOFF_VAR)  # executors that pass declared variables
    config.clear()
    config.update(settings.config)
    return settings, estimates


SETTINGS, ESTIMATES = load_workflow_settings()

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


#: Rebuild markers (bearing_envelope.study.recovery): results/.rebuild/{stage}/{case}.
MARKERS = "results/.rebuild"


def rebuild_marker(stage, case):
    """The rebuild marker of results/{stage}/{case}.* (an input of its first consumer)."""
    return f"{MARKERS}/{stage}/{case}"


def recovery_artefacts():
    """What is verified before the DAG: the case files (and their sensor copies) and the
    sealed per-case harmonic tables, each with its marker and the files made from it."""
    arts = []
    for stage in dict.fromkeys(("cases", ANALYSIS_STAGE)):
        for case in CASES:
            consumers = [f"results/bands/{case}.json"] + (
                [f"results/sensor/{case}.h5"] if stage == "cases" else [])
            arts.append(Artefact(f"results/{stage}/{case}.h5", rebuild_marker(stage, case),
                                 tuple(consumers)))
    arts += [Artefact(f"results/harmonics/{case}.csv", rebuild_marker("harmonics", case),
                      ("results/tables/harmonics.csv",), "sealed table") for case in CASES]
    return arts


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
    """Tables of a paper-conventions run (config key `paper_run`: its working directory; the
    pre-run check refused one that is not a finished run): the page then shows both columns."""
    return run_tables(config.get("paper_run"))


# Before the DAG: every case file verified in full (checksums, attribute digest) and every
# per-case harmonic table against its seal (its content, whatever its mtime); a bad one is moved
# aside, and a bad or deleted one is rebuilt with what is made from it, in this run
# (bearing_envelope.study.recovery; nothing changes on a dry run, one line says what would).
if workflow.is_main_process:
    recover_artefacts(recovery_artefacts(), dry_run=is_dry_run(workflow=workflow))
