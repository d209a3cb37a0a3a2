"""The maintained benchmarks: one entry point, ``python -m benchmarks NAME [args]``.

Every figure of ``docs/benchmarks.md`` names the command of this registry that regenerates it.
A benchmark is a module of this package with

- ``main(argv) -> int``: the measurement (``argv`` as on the command line; ``--help`` lists the
  options), printing markdown tables;
- ``smoke() -> None``: the same code path on tiny inputs, seconds long, run by
  ``tests/test_benchmarks.py`` for every registered name (no timing is checked there).

To add one, write the module and add its name to :data:`REGISTRY`. ``python -m benchmarks``
alone lists them.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from types import ModuleType

#: name -> one line on what it measures (the module ``benchmarks.<name>``)
REGISTRY: dict[str, str] = {
    "contact_speed": "contact solver: time per solve and per CG iteration against the FFT bound "
                     "(and tamaas where installed), Hertz p0 error",
    "case_cost": "CPU of one simulated case per fault location and fidelity (CWRU 6205 scene), "
                 "and the table's no-defect contact against Hertz",
    "signal_speed": "fast kurtogram and the whole analysis chain on a sweep-length record",
    "false_alarms": "false-alarm rate of the detection test on pure Gaussian noise",
    "real_records": "verdicts on the CWRU 12 kHz drive-end records (right / wrong / abstain per "
                    "fault set and confidence) and false alarms on shaped noise",
    "reference": "the converged reference, the error model per load, its coverage on held-out "
                 "cases, the cost of the presets",
    "routes": "what each route of the verdict sees on the CWRU 12 kHz records (route x family x "
              "margin, CPU), combination variants, leave one fault set out, shaped-noise false "
              "alarms with every route",
    "coherent_events": "is there an event train to find: the synchronous average of each CWRU "
                       "12 kHz record's squared envelope at its fault's rate over a band scan, "
                       "against a control rate",
    "sweep_cost": "CPU per rule of a finished sweep, from Snakemake's benchmark files",
    "result_digests": "sha256 of every array and table of a sweep's results/ (bit-identity)",
    "job_validations": "validations of one value per run: the workflow's loader (a dry run) and "
                       "every job's loader, counted",
    "outside_zone": "outer-race pits at 3:00 / 12:00 against 6:00 per loading mechanism "
                    "(centrifugal force, preload): loads, events, BPFO level",
    "cwru_hardness": "what the hardness bound changes in the CWRU scenes (p_max, removed force, "
                     "envelope line)",
    "hostile_records": "hostile `analyze` inputs (every file type, rates, bearings, options, "
                       "broken files, pickles, devices): each refused in one line naming its "
                       "field or analysed right, none hanging",
    "hostile_configs": "bad and hostile configs: each refused before any job (or run to the "
                       "end with --run), and the check's cost",
    "defect_contact": "the defect contact law F(x, delta) of the dynamic model: cost and errors per "
                      "fidelity (CWRU 6205 pits), the defects' scales (CWRU pits, default sweep)",
    "dynamics_cost": "dynamic bearing model: RK4 numba against solve_ivp (accuracy, CPU), the "
                     "step rule's envelope-line convergence, CPU of a 12 kHz record",
    "identify_path_truth": "identify-path on synthetic records of known f_n, zeta, gain and "
                           "background at partial detection: within tolerance / flagged / wrong",
    "model_choice": "the criterion of scene.dynamics auto against where the quasi-static and the "
                    "dynamic model's answers differ (force line at the event rate, contact "
                    "opening over the pit)",
    "rig_cost": "virtual rig with the dynamics: CPU of a dynamic rig record per preset, and the "
                "whole rig quasi-static against dynamic (--whole)",
    "rig_clearance": "the dynamic rig's OR 3:00 events against the operating clearance: 3:00 "
                     "ball load, least load over the pit, secondary events, OR 3:00 re 6:00, the "
                     "IR fr sideband implied",
    "rig_targets": "issue 42's rig targets (line height, 3x/1x, OR 3:00 re 6:00, secondary "
                   "events at 3:00, ball class, height against pit size) read off scored runs",
    "defect_size": "defect length from the entry-exit spacing: records of known spacing, the "
                   "dynamic model's three CWRU pits, the CWRU 48 / 12 kHz records against the "
                   "pit diameter (rank correlation)",
}

#: Benchmarks of work in flight, registered as soon as their module is in this folder (each
#: with ``main(argv)`` and ``smoke()`` like the others); move an entry up once it has landed.
PENDING: dict[str, str] = {}
REGISTRY.update({name: what for name, what in PENDING.items()
                 if (Path(__file__).parent / f"{name}.py").exists()})


def load(name: str) -> ModuleType:
    """The module of a registered benchmark.

    Parameters
    ----------
    name : str
        A key of :data:`REGISTRY`.

    Returns
    -------
    module
        ``benchmarks.<name>``, with ``main(argv)`` and ``smoke()``.
    """
    if name not in REGISTRY:
        raise SystemExit(f"benchmark: got {name!r}; allowed: {', '.join(sorted(REGISTRY))}")
    return importlib.import_module(f"{__name__}.{name}")
