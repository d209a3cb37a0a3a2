"""``bearing-envelope rig``: the virtual CWRU rig and its scorecard, record by record.

For each measured fault record (.npz with x, fs and meta_json: fault, fault_diameter_in,
outer_race_position, shaft_hz, load_hp, as in /work/shared/data/real) simulates the contact
history of its scene (config_rig.yaml with the record's defect, shaft rate, fs and length),
identifies the record's transfer path (identify-path), makes the simulated record (the contact
force through that path at the rig's one gain, plus the record's background), then runs
`analyze` on the measured and the simulated records alike and writes the scorecard
(docs/virtual_rig.md: the pass rules).

Example::

    bearing-envelope rig /work/shared/data/real/cwru_de12 --config config_rig.yaml -o runs/rig
"""

from __future__ import annotations

import argparse


def register(subparsers) -> None:
    """Add the ``rig`` sub-command.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The sub-parsers of the top-level parser (:func:`bearing_envelope.cli.build_parser`).
    """
    p = subparsers.add_parser(
        "rig",
        help="virtual CWRU rig: simulated records beside the measured ones, and the scorecard",
        description=__doc__.split("\n\n")[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("records", nargs="+", help="measured records (.npz) or folders of them")
    p.add_argument("--config", default="config_rig.yaml", help="rig config (default "
                                                               "config_rig.yaml)")
    p.add_argument("-o", "--output", default="runs/rig", help="output folder")
    p.add_argument("--gain-reference", default="OR007at6",
                   help="records (name contains) the rig's gain is identified on")
    p.add_argument("--simulate-only", action="store_true",
                   help="stop after the contact histories")
    p.add_argument("--score-only", action="store_true",
                   help="simulate nothing: score the records whose contact history exists")
    p.add_argument("--identify", action="store_true",
                   help="after scoring: identify the clearance and the sensor's cross-axis "
                        "gain from the run (load_zone.json)")
    p.set_defaults(func=run)


def _collect(paths) -> list[str]:
    import glob
    import os

    out = []
    for p in paths:
        out += sorted(glob.glob(os.path.join(p, "*.npz"))) if os.path.isdir(p) else [p]
    return out


def run(args) -> int:
    """Simulate the contact histories of the records' scenes and write the rig scorecard.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments: ``records``, ``config``, ``output``, ``gain_reference``,
        ``simulate_only``, ``score_only``, ``identify`` (see :func:`register`).

    Returns
    -------
    int
        0; no fault record among the files raises ``ValueError``.

    Raises
    ------
    ValueError
        No fault record among the files given.
    """
    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba, pandas: ~4 s)
    from pathlib import Path

    from bearing_envelope.study import rig

    out = Path(args.output)
    settings = rig.read_rig_config(args.config)
    conds = rig.record_conditions(_collect(args.records), settings)
    if not conds:
        raise ValueError("records: no fault record (meta_json fault inner_race / outer_race / "
                         "ball) among the files given")
    if args.score_only:
        contact = {c.name: str(out / "contact" / f"{c.name}_contact.npz") for c in conds
                   if (out / "contact" / f"{c.name}_contact.npz").exists()}
    else:
        contact = rig.simulate_excitations(conds, settings, out / "contact")
    if args.simulate_only:
        return 0
    rig.run_scorecard(conds, contact, out, args.gain_reference, settings=settings)
    if args.identify:
        import json

        fit = rig.identify_from_run(out, conds, settings)
        (out / "load_zone.json").write_text(json.dumps(fit, indent=1), encoding="utf-8")
        print(f"rig: at {fit['load_kN']:g} kN: clearance {fit['clearance_um']:.2f} um, sensor "
              f"cross-axis gain {fit['sensor_cross_axis']:.3f} (measured fr sideband "
              f"{fit['measured']['sb1_db']:.1f} dB, 3:00/6:00 {fit['measured']['ratio_3_6_db']:.1f}"
              " dB)")
    return 0
