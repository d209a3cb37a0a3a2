# bearing_envelope: contact-pressure histories of a damaged roller bearing and their envelope
# analysis over a load x defect-depth sweep. Everything lives in workflow/rules/*.smk; the
# physics and signal processing live in the package (src/bearing_envelope).
#
# No `configfile:` directive: ./config.yaml and the --configfile files are read once, each, by
# the project's loader in workflow/rules/common.smk (bearing_envelope.study.settings.
# workflow_settings: strict YAML with line numbers, merged so that a designation is a complete
# bearing, validated and typed once).
from snakemake.utils import min_version

min_version("8.10")


report: "workflow/report/workflow.rst"


include: "workflow/rules/jobenv.smk"
include: "workflow/rules/common.smk"
include: "workflow/rules/simulate.smk"
include: "workflow/rules/analysis.smk"
include: "workflow/rules/aggregate.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/diagnosability.smk"
include: "workflow/rules/sensor.smk"
include: "workflow/rules/tradeoff.smk"
include: "workflow/rules/report_pages.smk"


rule all:
    input:
        all_targets(),
    default_target: True
