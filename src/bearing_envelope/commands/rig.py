"""``bearing-envelope rig``: the virtual rig and its scorecard, record by record.

For each measured fault record of a record set (a manifest CSV; a folder holding
manifest.csv; the CWRU data center's .mat files as downloaded; the converted CWRU development
records, .npz, by the package's manifest) simulates the contact history of its scene
(config_rig.yaml with the record's defect, shaft rate, fs and length), identifies the record's
transfer path (identify-path), makes the simulated record (the force the defect removes through
that path at the rig's one gain, plus the record's background), then runs `analyze` on the
measured and the simulated records alike and writes the scorecard (docs/virtual_rig.md: the
manifest's columns and the pass rules).

Example::

    bearing-envelope rig DATA/cwru_de12 DATA/cwru_de48 --config config_rig.yaml -o runs/rig
    bearing-envelope rig my_records/manifest.csv --config my_rig.yaml -o runs/my_rig
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
        help="virtual rig: simulated records beside the measured ones, and the scorecard",
        description=__doc__.split("\n\n")[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("records", nargs="+",
                   help="manifests (.csv), folders (with a manifest.csv, or of CWRU .mat or "
                        ".npz records) or record files")
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
                        "gain from the run (load_zone.json), with the exponents of the run's "
                        "excitations (rig.dynamics)")
    p.set_defaults(func=run)


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
        0 (success); a failure raises.

    Raises
    ------
    ValueError
        No fault record among the records given.
    """
    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba, pandas: ~4 s)
    from pathlib import Path

    from bearing_envelope.study import rig

    out = Path(args.output)
    settings = rig.read_rig_config(args.config)
    conds = rig.record_conditions(args.records)
    if not conds:
        raise ValueError("records: no fault record (location inner_race / outer_race / "
                         "rolling_element) among the records given")
    if args.score_only:
        contact = rig.existing_excitations(conds, settings, out / "contact")
    else:
        contact = rig.simulate_excitations(conds, settings, out / "contact",
                                           gain_reference=args.gain_reference)
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
