"""More false-alarm trials on a finished default sweep's healthy cases (issue 16).

    nice -n 5 python benchmarks/false_alarms_more_trials.py FIRST END

Trials FIRST..END-1 of the map's test on the healthy cases, the loop of
``pipeline.case_false_alarms`` (same bands, noise definition and per-trial seeds: trial 0
reproduces the rule's trial 0 to the bit), so trials 20.. are independent of the rule's 0-19
without rerunning them. Writes false_alarms_FIRST_END.csv (one row per test; pool with
``diagnosis.false_alarm_rates``). Run from the worktree (reads config.yaml and results/cases).
"""
import sys

import pandas as pd
import yaml

from bearing_envelope.io import read_case
from bearing_envelope.study.pipeline import (MAP_BACKGROUND, _case_id, _sensor_setup, _trial_seed,
                                       diagnosability_bands)
from bearing_envelope.diagnosis.detection import detection_statistic
from bearing_envelope.signal import envelope_spectrum
from bearing_envelope.physics.transfer import synthesize_acceleration
from bearing_envelope.study.settings import workflow_settings
cfg = workflow_settings(yaml.safe_load(open("config.yaml")), ["config.yaml"]).config
K0, K1 = int(sys.argv[1]), int(sys.argv[2])
rows = []
for load, peer in ((250, 15), (500, 15), (750, 15)):
    case = read_case(f"results/cases/F{load}kN_h0um.h5")
    ref_case = read_case(f"results/cases/F{load}kN_h{peer}um.h5")  # the healthy case's peer
    model, exc, ref = _sensor_setup(case, cfg["sensor"], ref_case)
    bands = diagnosability_bands(case, cfg["sensor"], cfg["analysis"], reference=ref_case)
    for trial in range(K0, K1):
        for snr in cfg["diagnosability"]["snr_db"]:
            acc, _ = synthesize_acceleration(exc, float(case.fs), model, reference=ref,
                                             seed=_trial_seed(model.seed, case, trial, snr),
                                             fr=float(case.fr), snr_db=float(snr))
            for spec, lo, hi in bands:
                f, a = envelope_spectrum(acc, float(case.fs), (lo, hi),
                                         order=int(cfg["analysis"].get("filter_order", 4)),
                                         squared=bool(cfg["analysis"].get("squared_envelope", False)))
                d = detection_statistic(f, a, float(case.bpfi), fr=float(case.fr),
                                        background=MAP_BACKGROUND, level="two_sided")
                rows.append({"case": _case_id(case), "snr_db": float(snr), "band": spec["name"],
                             "trial": trial, "statistic_db": d.statistic_db,
                             "threshold_db": d.threshold_db, "detected": bool(d.detected),
                             "peak_hz": d.peak_hz})
        pd.DataFrame(rows).to_csv(f"false_alarms_{K0}_{K1}.csv", index=False)
        print(load, trial, flush=True)
