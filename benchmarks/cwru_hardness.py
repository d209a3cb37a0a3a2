"""What the hardness bound changes in the CWRU scenes (docs/scene.md, "The hardness bound in the
CWRU scenes").

    nice -n 10 python -m benchmarks cwru_hardness --fidelity standard --revolutions 20

config_cwru.yaml (SKF 6205, assumed 1 kN, 0.011 in deep EDM pits) per location (inner race,
outer race at 6:00, ball) and pit (0.007 / 0.021 in), elastic (``hardness_GPa: null``) and
elastic-perfectly-plastic at 7.36 GPa (52100 at ~61 HRC, docs/plasticity.md): the largest
``p_max``, the largest removed force and the envelope line of the location's family (band
fs/4 - 3 fs/8, Hann; BPFI, BPFO or 2 x BSF) of ``p_max``.
"""

from __future__ import annotations

import argparse
import copy
import os

import numpy as np
import yaml

from bearing_envelope.physics.history import simulate
from bearing_envelope.physics.locations import scene_event_frequencies
from bearing_envelope.physics.scene import BEARING_STEEL_HARDNESS_GPA, Scene
from bearing_envelope.signal.envelope import envelope_spectrum
from bearing_envelope.signal.spectrum import amplitude_at

HERE = os.path.dirname(os.path.abspath(__file__))


def main(argv=None) -> int:
    """Run the measurement (module docstring); ``argv`` as on the command line."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks cwru_hardness",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--fidelity", default="standard")
    ap.add_argument("--revolutions", type=float, default=20)
    ap.add_argument("--locations", nargs="*", default=["inner_race", "outer_race", "rolling_element"])
    ap.add_argument("--pits-um", type=float, nargs="*", default=[177.8, 533.4])
    args = ap.parse_args(argv)
    with open(os.path.join(HERE, "..", "config_cwru.yaml")) as fh:
        base = yaml.safe_load(fh)["scene"]
    base.setdefault("operation", {})["revolutions"] = args.revolutions
    for loc in args.locations:
        for pit in args.pits_um:
            out = {}
            for h in (None, BEARING_STEEL_HARDNESS_GPA):
                m = copy.deepcopy(base)
                m.setdefault("defect", {}).update(location=loc, width_um=pit)
                m.setdefault("material", {})["hardness_GPa"] = h
                sc = Scene.from_mapping(m, load_kN=1.0, depth_um=279.4)
                hist = simulate(sc, args.fidelity)
                p, fs = hist.signals["p_max"], sc.operation.fs_hz
                line = sc.defect.fault_location.event_rate(scene_event_frequencies(sc))
                f, a = envelope_spectrum(p - p.mean(), fs, (0.25 * fs, 0.375 * fs))
                out[h] = (p.max() / 1e9, hist.signals["removed_force"].max(),
                          amplitude_at(f, a, line, 0.01 * line)[1] / 1e6)
            (p0, f0, e0), (p1, f1, e1) = out[None], out[BEARING_STEEL_HARDNESS_GPA]
            print(f"{loc:15s} {pit:6.1f} um: p_max {p0:.2f} -> {p1:.2f} GPa, removed force "
                  f"{f0:.3g} -> {f1:.3g} N ({100 * (f1 / f0 - 1):+.1f} %), envelope line "
                  f"{e0:.3g} -> {e1:.3g} MPa ({20 * np.log10(e1 / e0):+.2f} dB)", flush=True)
    return 0


def smoke() -> None:
    """The same path on a tiny case: draft, a tenth of a revolution, the inner race."""
    main(["--fidelity", "draft", "--revolutions", "0.1", "--locations", "inner_race",
          "--pits-um", "177.8"])


if __name__ == "__main__":
    raise SystemExit(main())
