"""``bearing-envelope identify-path``: the transfer path a record's fault impulses excite.

Reads a measured record (the formats of ``analyze``), finds the resonance band (the fast
kurtogram's cell whose envelope spectrum holds the strongest line at the bearing's BPFO, BPFI,
BSF or 2 x BSF, or --event-hz), every period's event on that line's track, and fits the mode
they ring (natural frequency, damping from the decay of the averaged impulse envelope,
amplitude per event) and the background spectrum (the record with its events gated out, or,
where they ring through every period, the quiet end of each period; or --background, a
healthy record of the same machine; where it comes from is printed). What the record does not
identify is flagged (warning lines). Writes the result as JSON
(bearing_envelope.diagnosis.transfer_path). A record without periodic impulses, or too short,
is refused with one line. See docs/virtual_rig.md.

Examples::

    bearing-envelope identify-path cwru_130.npz --bearing 6205 --shaft-hz 29.95 -o path.json
    bearing-envelope identify-path rec.csv --fs 12000 --event-hz 107.4 --json -
"""

from __future__ import annotations

import argparse
import sys


def register(subparsers) -> None:
    """Add the ``identify-path`` sub-command.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The sub-parsers of the top-level parser (:func:`bearing_envelope.cli.build_parser`).
    """
    p = subparsers.add_parser(
        "identify-path",
        help="identify the transfer path (resonance, damping, amplitude, background) from "
             "the fault impulses of a record",
        description=__doc__.split("\n\n")[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("record", help="signal file (.npz, .npy, .csv, .mat, .wav)")
    p.add_argument("--bearing", default=None, help="bearing designation (e.g. 6205)")
    p.add_argument("--shaft-hz", type=float, default=None,
                   help="shaft rate, Hz (else the file's)")
    p.add_argument("--fs", type=float, default=None, help="sampling rate, Hz (else the file's)")
    p.add_argument("--event-hz", type=float, action="append", default=None,
                   help="an event rate to search, Hz (repeatable; instead of --bearing)")
    p.add_argument("--column", default=None, help="CSV column / .npz key / .mat variable")
    p.add_argument("--background", default=None,
                   help="a healthy record of the same machine at the same fs")
    p.add_argument("-o", "--output", default="-", help="JSON output (default - : stdout)")
    p.set_defaults(func=run)


def event_rates(args, fr):
    """The event rates identify-path searches: ``--event-hz`` and, with ``--bearing``, the
    bearing's BPFO, BPFI, BSF and 2 x BSF from the project's one resolver and rates function.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments; reads ``event_hz`` (Hz, list or None) and ``bearing`` (a designation
        or alias, or None).
    fr : float or None
        Shaft rate, Hz (None: the file gives none).

    Returns
    -------
    dict of str to float
        Name -> rate, Hz.

    Raises
    ------
    ValueError
        A bearing without a shaft rate, or neither a bearing nor event rates (one line naming
        the option).
    """
    from bearing_envelope.physics.catalogue import bearing_geometry
    from bearing_envelope.physics.kinematics import bearing_rates

    rates = {f"event{i + 1}": hz for i, hz in enumerate(args.event_hz or [])}
    if args.bearing is not None:
        if fr is None:
            raise ValueError("--shaft-hz: the file gives no shaft rate; pass --shaft-hz (Hz)")
        g = bearing_geometry(args.bearing, names={"designation": "--bearing"})
        r = bearing_rates(fr, g["n_rollers"], g["roller_diameter_mm"], g["pitch_diameter_mm"],
                          g["contact_angle_deg"])
        rates.update({k: r[k] for k in ("bpfo", "bpfi", "bsf", "bsf2")})
    if not rates:
        raise ValueError("--bearing: give the bearing (with --shaft-hz) or --event-hz")
    return rates


def run(args) -> int:
    """Identify the transfer path of one record and write it as JSON.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments: ``record``, ``bearing``, ``shaft_hz`` (Hz), ``fs`` (Hz),
        ``event_hz`` (Hz, list), ``column``, ``background``, ``output`` (``-``: stdout).

    Returns
    -------
    int
        0; a missing sampling rate, shaft rate or event rate, or a background at another fs,
        raises ``ValueError``.

    Raises
    ------
    ValueError
        No sampling rate (the file gives none and no ``--fs``), or a background record sampled
        at another rate.
    """
    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba, pandas: ~4 s)
    from bearing_envelope.diagnosis.transfer_path import identify_path
    from bearing_envelope.io.records import read_record

    rec = read_record(args.record, column=args.column, fs=args.fs)
    fs = args.fs or rec.get("fs")
    if not fs:
        raise ValueError("--fs: the file gives no sampling rate; pass --fs (Hz)")
    fr = args.shaft_hz or rec.get("fr")
    rates = event_rates(args, fr)
    bg = None
    if args.background is not None:
        bg_rec = read_record(args.background, column=args.column, fs=args.fs)
        if bg_rec.get("fs") not in (None, fs):
            raise ValueError(f"--background: fs {bg_rec['fs']:g} Hz; allowed: the record's "
                             f"{fs:g} Hz")
        bg = bg_rec["x"]
    path = identify_path(rec["x"], float(fs), rates, background=bg,
                         background_name=args.background or "healthy record")
    text = path.to_json()
    if args.output == "-":
        sys.stdout.write(text + "\n")
    else:
        with open(args.output, "w", encoding="utf-8") as fh:
            fh.write(text + "\n")
    for flag in path.flags:
        print(f"bearing-envelope identify-path: warning: {flag}", file=sys.stderr)
    if path.not_identified:
        print(f"bearing-envelope identify-path: warning: not identified: "
              f"{', '.join(path.not_identified)}", file=sys.stderr)
    print(f"# {path.event_name} {path.event_hz:.2f} Hz, every one of {path.n_periods} periods' "
          f"events averaged ({path.n_events} stand out one by one); band "
          f"{path.band_hz[0]:.0f}-{path.band_hz[1]:.0f} Hz; f_n {path.f_n_hz:.0f} Hz, zeta "
          f"{path.zeta:.4f} ({path.zeta_range[0]:.4f}-{path.zeta_range[1]:.4f}); amplitude "
          f"{path.amplitude:.4g}; background rms {path.background_rms:.4g}", file=sys.stderr)
    print(f"# background from: {path.background_source}", file=sys.stderr)
    for m in path.modes[1:]:
        print(f"# further mode: f_n {m['f_n_hz']:.0f} Hz, zeta {m['zeta']:.4f}; amplitude "
              f"{m['amplitude']:.4g} ({m['excess_db']:.1f} dB of added power, prominence "
              f"{m['prominence_z']:.1f} standard errors)", file=sys.stderr)
    return 0
