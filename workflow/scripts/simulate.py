"""Rule simulate: one load x depth case -> HDF5 (bearing_envelope.physics.history.simulate)."""
import json

from bearing_envelope.physics.dynamics.case import simulate_case
from bearing_envelope.physics.dynamics.criterion import model_choice
from bearing_envelope.io import write_case
from bearing_envelope.study.accuracy import case_error_model
from bearing_envelope.study.provenance import log_to
from bearing_envelope.study.job_transport import job_settings

#: The content-addressed store of the no-defect global solves (bearing_envelope.physics.nodefect_cache).
NODEFECT_CACHE = "results/cache/nodefect"

with log_to(snakemake.log[0]) as log:  # noqa: F821
    setup = job_settings(snakemake).simulation  # noqa: F821  (case, scene, fidelity: typed)
    case = setup.case
    # the no-defect solves of a load are shared by its depth cases (issue 25; bit-identical)
    # the model the scene needs (scene.dynamics; docs/dynamics.md), one line in the log
    print(f"simulate: {case.name}: model {model_choice(setup.scene).reason}", file=log)
    hist = simulate_case(setup.scene, setup.fidelity, progress=False,
                         nodefect_cache=NODEFECT_CACHE)
    if hist.stats.get("exposure_note"):
        # one line: a defect that never meets a loaded contact, or passages beyond the
        # validated pit bridging (physics/exposure.py); also in the case's stats
        print(f"simulate: warning: {case.name}: {hist.stats['exposure_note']}", file=log)
    write_case(snakemake.output[0], hist,  # noqa: F821
               extra_attrs={"workflow_rule": "simulate", **case.attrs()},
               error_model=case_error_model(hist))
    print(json.dumps(hist.stats, default=float), file=log)
