"""``bearing-envelope sensor``: synthetic accelerometer signal of a simulated case.

Reads a case file (:func:`bearing_envelope.io.read_case`), takes the contact signal named by the
``sensor:`` section of the config (``excitation``: ``pressure`` = p_max, ``pressure_defect`` =
p_max_defect, ``force`` = contact_force, the roller load minus the force the defect removes at
fixed approach: the blocked force, docs/sensor.md), passes it through the structural modes,
adds noise at the target SNR and the interfering tones (:mod:`bearing_envelope.transfer`), and
writes the acceleration with its provenance: ``.h5`` = a copy of the case file with the
acceleration added as ``signals/acceleration`` (readable by ``read_case`` like any case), ``.npz`` =
the acceleration, time, frequencies and provenance alone. See ``docs/sensor.md``.

Example::

    bearing-envelope sensor results/cases/F500kN_h50um.h5 --config config.yaml \\
        --snr-db 0 --reference results/cases/F500kN_h0um.h5 -o results/sensor/F500kN_h50um_snr0.h5
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Any


def register(subparsers) -> None:
    """Add the ``sensor`` sub-command."""
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
    from bearing_envelope.io import read_case  # lazy: io is a separate layer

    return read_case(path)


def _case_signals(case) -> dict:
    signals = dict(getattr(case, "signals", {}) or {})
    for name in ("p_max", "p_max_defect", "roller_load"):
        if name not in signals and getattr(case, name, None) is not None:
            signals[name] = getattr(case, name)
    return signals


def _git_commit() -> str | None:
    try:
        from bearing_envelope.io import git_commit

        return git_commit()
    except ImportError:
        pass
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=Path(__file__).resolve().parent,
                             capture_output=True, text=True, timeout=5, check=True)
        return out.stdout.strip() or None
    except (OSError, subprocess.SubprocessError):
        return None


def load_sensor_config(path: str) -> dict[str, Any]:
    """The ``sensor:`` section of a YAML config (ValueError if absent)."""
    import yaml

    with open(path, encoding="utf-8") as fh:
        cfg = yaml.safe_load(fh) or {}
    if not isinstance(cfg, dict) or not cfg.get("sensor"):
        raise ValueError(f"{path}: no `sensor:` section (see docs/sensor.md)")
    return cfg["sensor"]


def _json_default(o):
    if hasattr(o, "tolist"):
        return o.tolist()
    if isinstance(o, float) and not math.isfinite(o):
        return str(o)
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def _write(path: Path, acc, fs: float, case, info: dict[str, Any], source: str) -> None:
    import numpy as np

    provenance = json.dumps(info, default=_json_default, allow_nan=True, sort_keys=True)
    meta = {"fs": float(fs)}
    for key in ("fr", "bpfi", "bpfo", "ftf", "bsf", "load_kN", "depth_um"):
        v = getattr(case, key, None)
        if v is not None:
            meta[key] = float(v)
    path.parent.mkdir(parents=True, exist_ok=True)
    suffix = path.suffix.lower()
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp" + suffix, dir=path.parent)
    os.close(fd)
    try:
        if suffix == ".npz":
            with open(tmp, "wb") as fh:
                np.savez(fh, acceleration=acc, time=np.arange(acc.size) / fs,
                         provenance=np.array(provenance), **{k: np.array(v) for k, v in meta.items()})
        elif suffix in (".h5", ".hdf5"):
            import h5py

            # a copy of the case file plus the acceleration as a second signal, so that
            # read_case(OUT).signals["acceleration"] feeds every analysis like p_max does
            shutil.copyfile(source, tmp)
            with h5py.File(tmp, "a") as h5:
                sg = h5.require_group("signals")
                if "acceleration" in sg:
                    del sg["acceleration"]
                d = sg.create_dataset("acceleration", data=acc, compression="gzip",
                                      compression_opts=4, shuffle=True)
                d.attrs["units"] = "excitation units x mode gain (m/s^2 for gains in (m/s^2)/Pa)"
                d.attrs["description"] = "synthetic accelerometer signal (bearing-envelope sensor)"
                d.attrs["provenance"] = provenance
                if "time" not in h5:
                    h5.create_dataset("time", data=np.arange(acc.size) / fs)
                h5.attrs["sensor_json"] = provenance
        else:
            raise ValueError(f"output must end in .npz or .h5, got {str(path)!r}")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_sensor_case(case_path, section, output, *, snr_db="model", seed=None, excitation=None,
                      reference=None, config_label=None) -> dict[str, Any]:
    """Synthesise the acceleration of a case file and write it with its provenance.

    Parameters
    ----------
    case_path : str or Path
        Case file written by ``bearing-envelope simulate``.
    section : mapping
        The config's ``sensor:`` section (:meth:`bearing_envelope.transfer.TransferModel.from_mapping`).
    output : str or Path
        ``.h5`` (a copy of the case with ``signals/acceleration``) or ``.npz``; written atomically.
    snr_db : float, None or "model"
        Noise level: the section's own (``"model"``), none (``None``) or this SNR in dB.
    seed : int, optional
        Noise seed (default: the section's ``seed``).
    excitation : str, optional
        Overrides the section's ``excitation``.
    reference : str or Path, optional
        No-defect case of the same load: the defect part is ``H e - H e_ref``.
    config_label : str, optional
        Where the section came from (recorded in the provenance).

    Returns
    -------
    dict
        The provenance written with the signal (achieved SNR in ``snr_db_achieved``).
    """
    import numpy as np

    from bearing_envelope import __version__
    from bearing_envelope.transfer import (
        TransferModel,
        excitation_from_history,
        select_excitation,
        synthesize_acceleration,
    )

    out = Path(output)
    if out.suffix.lower() not in (".npz", ".h5", ".hdf5"):
        raise ValueError(f"output must end in .npz or .h5, got {str(output)!r}")
    section = dict(section)
    if excitation is not None:
        section["excitation"] = excitation
    case = _read_case(str(case_path))
    fs = float(case.fs)
    model = TransferModel.from_mapping(section, fs=fs)
    if snr_db != "model":
        model = model.with_snr(snr_db)

    name, x = select_excitation(_case_signals(case), model.excitation)
    e = excitation_from_history(x, scale=model.excitation_scale)
    ref = None
    if reference:
        rcase = _read_case(str(reference))
        if float(rcase.fs) != fs:
            raise ValueError(f"reference fs {rcase.fs} Hz differs from the case's {fs} Hz")
        _, xr = select_excitation(_case_signals(rcase), model.excitation)
        if np.shape(xr) != np.shape(x):
            raise ValueError(f"reference has {np.size(xr)} samples, the case {np.size(x)}")
        ref = excitation_from_history(xr, scale=model.excitation_scale)
    acc, info = synthesize_acceleration(e, fs, model, reference=ref, seed=seed,
                                        fr=getattr(case, "fr", None))
    info.update(
        source_case=str(case_path),
        reference_case=str(reference) if reference else None,
        excitation_signal=name,
        config=config_label,
        package_version=__version__,
        git_commit=_git_commit(),
        command="bearing-envelope sensor",
    )
    _write(out, acc, fs, case, info, str(case_path))
    return info


def run(args: argparse.Namespace) -> int:
    """Entry point of ``bearing-envelope sensor``."""
    section = load_sensor_config(args.config)
    snr = None if args.no_noise else ("model" if args.snr_db is None else args.snr_db)
    info = write_sensor_case(args.case, section, args.output, snr_db=snr, seed=args.seed,
                             excitation=args.excitation, reference=args.reference,
                             config_label=str(args.config))
    print(f"sensor: {args.case} -> {args.output} ({info['n_samples']} samples, "
          f"excitation {info['excitation_signal']}, SNR {info['snr_db_achieved']:.2f} dB)")
    return 0
