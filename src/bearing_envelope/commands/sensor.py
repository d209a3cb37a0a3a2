"""``bearing-envelope sensor``: synthetic accelerometer signal of a simulated case.

Reads a case file (:func:`bearing_envelope.io.read_case`), takes the contact signal named by the
``sensor:`` section of the config (``excitation``: ``pressure`` = p_max, ``pressure_defect`` =
p_max_defect, ``force`` = contact_force, the roller load minus the force the defect removes at
fixed approach: the blocked force, docs/sensor.md), passes it through the structural modes,
adds noise at the target SNR and the interfering tones (:mod:`bearing_envelope.physics.transfer`), and
writes the acceleration with its provenance: ``.h5`` = a copy of the case file with the
acceleration added as ``signals/acceleration`` (readable by ``read_case`` like any case), ``.npz`` =
the acceleration, time, frequencies and provenance alone. See ``docs/sensor.md``.

Example::

    bearing-envelope sensor results/cases/F500kN_h50um.h5 --config config.yaml \\
        --snr-db 0 --reference results/cases/F500kN_h0um.h5 -o results/sensor/F500kN_h50um_snr0.h5
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from bearing_envelope.physics.transfer import TransferModel


def register(subparsers) -> None:
    """Add the ``sensor`` sub-command.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The sub-parsers of the top-level parser (:func:`bearing_envelope.cli.build_parser`).
    """
    p = subparsers.add_parser(
        "sensor",
        help="synthetic accelerometer signal (modes + noise at an SNR + tones) of a case",
        description=__doc__.split("\n\n")[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("case", help="case file (HDF5) written by `bearing-envelope simulate`")
    p.add_argument("--config", required=True, help="YAML config with a `sensor:` section")
    p.add_argument("--snr-db", type=float, default=None,
                   help="target SNR in dB = 10 log10(P_defect/P_noise); overrides the config")
    p.add_argument("--no-noise", action="store_true", help="add no noise (ignores --snr-db)")
    p.add_argument("--seed", type=int, default=None, help="seed of the noise (overrides the config)")
    p.add_argument("--excitation", default=None, choices=("pressure", "pressure_defect", "force"),
                   help="contact signal used as excitation (overrides the config)")
    p.add_argument("--reference", default=None,
                   help="no-defect case file of the same load: P_defect = var(H e - H e_ref)")
    p.add_argument("-o", "--output", required=True, help="output file, .npz or .h5")
    p.set_defaults(func=run)


def _read_case(path: str):
    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba, pandas: ~4 s)
    from bearing_envelope.io import read_case

    return read_case(path)


def load_sensor_config(path: str) -> TransferModel:
    """The typed ``sensor:`` section of a config file, validated by the one loader
    (:func:`bearing_envelope.study.settings.load_settings`, partial); ValueError if absent.

    Parameters
    ----------
    path : str
        YAML config file.

    Returns
    -------
    TransferModel
        The validated ``sensor:`` section.

    Raises
    ------
    ValueError
        The config has no ``sensor:`` section.
    """
    from bearing_envelope.study.settings import load_settings  # lazy: CLI start-up time

    settings = load_settings(path, partial=True)
    if settings.sensor is None:
        raise ValueError(f"{path}: no `sensor:` section (see docs/sensor.md)")
    return settings.sensor


def synthesize_sensor_case(case_path, model: TransferModel, output, *, snr_db="model", seed=None,
                           excitation=None, reference=None, config_label=None) -> dict[str, Any]:
    """Synthesise the acceleration of a case file and write it with its provenance.

    Reads the case(s), calls :func:`bearing_envelope.study.pipeline.case_acceleration` and writes with
    :func:`bearing_envelope.io.write_sensor_case` (``.h5``: a copy of the case with
    ``signals/acceleration``; ``.npz``: the signal alone; atomic). ``config_label`` (where the
    section came from) is recorded in the provenance. Returns the provenance (achieved SNR in
    ``snr_db_achieved``).

    Parameters
    ----------
    case_path : str or path-like
        Case file (.h5) to read.
    model : TransferModel
        The ``sensor:`` section (:func:`load_sensor_config`).
    output : str or path-like
        Output file, ``.h5`` or ``.npz``.
    snr_db : float, "model" or None, optional
        Target SNR in dB; ``"model"``: the model's own; ``None``: no noise.
    seed : int or None, optional
        Noise seed.
    excitation : str or None, optional
        Contact signal to use (``pressure``, ``pressure_defect``, ``force``); ``None``: the
        model's.
    reference : str or path-like or None, optional
        Case file passed to ``case_acceleration`` as the reference case.
    config_label : str or None, optional
        Where the section came from, recorded in the provenance.

    Returns
    -------
    dict
        The provenance written with the signal (``n_samples``, ``excitation_signal``,
        ``snr_db_achieved``, source and reference case, config, command, ...).
    """
    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba, pandas: ~4 s)
    from bearing_envelope.io import check_sensor_output, write_sensor_case as write
    from bearing_envelope.study.pipeline import case_acceleration

    check_sensor_output(output)
    case = _read_case(str(case_path))
    ref = _read_case(str(reference)) if reference else None
    acc, info = case_acceleration(case, model, reference=ref, snr_db=snr_db, seed=seed,
                                  excitation=excitation)
    info.update(source_case=str(case_path), reference_case=str(reference) if reference else None,
                config=config_label, command="bearing-envelope sensor")
    write(output, acc, case=case, source=str(case_path), provenance=info)
    return info


def run(args: argparse.Namespace) -> int:
    """Entry point of ``bearing-envelope sensor``.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments (``case``, ``config``, ``output``, ``snr_db``, ``no_noise``, ``seed``,
        ...; see :func:`register`).

    Returns
    -------
    int
        0.
    """
    model = load_sensor_config(args.config)
    snr = None if args.no_noise else ("model" if args.snr_db is None else args.snr_db)
    info = synthesize_sensor_case(args.case, model, args.output, snr_db=snr, seed=args.seed,
                                  excitation=args.excitation, reference=args.reference,
                                  config_label=str(args.config))
    print(f"sensor: {args.case} -> {args.output} ({info['n_samples']} samples, "
          f"excitation {info['excitation_signal']}, SNR {info['snr_db_achieved']:.2f} dB)")
    return 0
