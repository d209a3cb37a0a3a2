"""``bearing-envelope analyze``: envelope analysis of recordings or case files.

Reads one or many signals (.csv, .npy, .npz, MATLAB .mat, .wav, or a case file .h5 written by
bearing-envelope simulate; several files, a folder, or a CSV manifest) and runs the
envelope-analysis chain: raw spectrum, fast kurtogram, envelope spectra in every band, and for
every fault family (BPFO, BPFI, BSF, 2 x BSF, FTF, or lines given with --fault NAME=HZ) the
peak found within +-1 % (--search-percent) of its nominal frequency, its harmonics and its own
sidebands (fr for BPFI, FTF for BSF, none for BPFO), each with its height above the local
spectral floor. Ends with a verdict per family (detected or not, at a record-wise false-alarm
probability of 1 %, --pfa) and a one-line diagnosis. Fault frequencies come from --bpfi /
--fault, from the bearing (--bearing 6205, or the geometry in mm or inch), or from a case
file. Several records run in parallel with --jobs and give one table (--table, a row per
record x family) and one HTML page (--html). See docs/signal.md.

Examples::

    bearing-envelope analyze cwru_105.npz --fr 29.95 --bearing 6205 --plot figs/
    bearing-envelope analyze accel.csv --fs 12000 --fr 29.95 --fault bpfi=162.2 --column DE
    bearing-envelope analyze rec.npy --fs 12000 --fr 29.95 --bpfi 162.2 --fixed-band 0 6000 --json -
    bearing-envelope analyze results/cases/F500kN_h50um.h5 --csv out.csv --plot figs/
    bearing-envelope analyze records/ --fs 12000 --bearing 6205 --jobs 2 --table t.csv --html r.html
    bearing-envelope analyze --manifest records.csv --jobs 2 --table t.csv --html r.html --db
"""

# numpy, pandas, scipy and matplotlib are imported inside the functions that use them, on
# purpose: bearing_envelope.cli imports every command module to build its parser, and
# `bearing-envelope --help` (or any other command) must not pay their ~3 s of imports.
from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys

from ._analyze_batch import (figure_dir, figure_options, is_batch, record_json, run_batch,
                             single_threaded, tidy_lines, write_batch_outputs, write_text)



def plain_text(text: str) -> str:
    """Help text without reStructuredText markup: ``:func:`x``` -> ``x``, double back-quotes
    and ``::`` removed, escaped backslashes unescaped.

    Parameters
    ----------
    text : str
        reStructuredText (a module docstring's paragraphs).

    Returns
    -------
    str
        The plain text.
    """
    text = re.sub(r":[a-z]+:`~?([^`]+)`", r"\1", text)
    text = text.replace("``", "").replace("::", ":").replace("\\\\", "\\")
    return text


# ------------------------------------------------------------------------------- parser
def register(subparsers) -> None:
    """Add the ``analyze`` sub-command.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The sub-parsers of the top-level parser (:func:`bearing_envelope.cli.build_parser`).
    """
    doc = __doc__.split("\n\n")
    p = subparsers.add_parser(
        "analyze",
        help="envelope analysis of recordings or case files: every fault family, the real "
             "peaks, a verdict; many records in parallel",
        description=plain_text(doc[1]),
        epilog=plain_text("\n\n".join(doc[2:])),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    _add_input_args(p)
    _add_frequency_args(p)
    _add_analysis_args(p)
    _add_output_args(p)
    p.set_defaults(func=run)


def _add_input_args(p) -> None:
    p.add_argument("files", nargs="*", metavar="FILE",
                   help="signal files (.csv, .npy, .npz, .mat, .wav, case file .h5) or folders "
                        "(their files of these types, sorted; CSV manifests left out)")
    p.add_argument("--manifest", default=None, metavar="CSV",
                   help="CSV with a 'file' column (relative to the manifest) and optionally fs, "
                        "fr (or shaft_hz, rpm), bearing, column, channel per record")
    p.add_argument("--column", default=None,
                   help="CSV column (name or 0-based index), .npz key, .mat variable, or channel "
                        "index of a 2-D .npy or multi-channel .wav")
    p.add_argument("--channel", choices=("DE", "FE", "BA"), default="DE",
                   help="accelerometer of a CWRU .mat file (X###_DE_time, _FE_time, _BA_time; "
                        "default DE)")
    p.add_argument("--signal", default="p_max",
                   help="signal of a case file (default p_max; e.g. p_max_defect)")
    p.add_argument("--delimiter", choices=(",", ";", "tab", "|", "space"), default=None,
                   help="CSV field delimiter (default: detected; an ambiguous file is refused)")
    p.add_argument("--decimal", choices=(".", ","), default=None,
                   help="CSV decimal mark (default: detected)")


def _add_frequency_args(p) -> None:
    p.add_argument("--fs", type=float, default=None,
                   help="sampling frequency, Hz (else from the file: a case file, an 'fs' entry "
                        "of .npz/.mat, a .wav header, or a time column of a CSV)")
    p.add_argument("--fr", type=float, default=None,
                   help="shaft rate, Hz (else from the file: a case file, an fr/rpm entry, a "
                        "CWRU X###RPM variable)")
    p.add_argument("--bpfi", type=float, default=None,
                   help="inner-race fault frequency, Hz (same as --fault bpfi=HZ)")
    p.add_argument("--fault", action="append", default=None, metavar="NAME=HZ",
                   help="a fault frequency, Hz; repeatable. Names bpfo, bpfi, bsf, bsf2 (2 x "
                        "BSF), ftf get their sidebands (fr for bpfi, ftf for bsf/bsf2, none for "
                        "bpfo/ftf; bsf brings bsf2); other names none. Overrides the geometry's "
                        "value of the same name")
    g = p.add_argument_group("bearing (fault frequencies BPFO, BPFI, FTF, BSF, 2 x BSF)")
    g.add_argument("--bearing", default=None, metavar="DESIGNATION",
                   help="a bearing by designation: 6205 (SKF 6205-2RS, CWRU drive end) or 6203 "
                        "(SKF 6203-2RS, CWRU fan end); instead of the geometry below")
    g.add_argument("--n-rollers", type=int, default=None, help="rolling elements per row")
    g.add_argument("--roller-diameter-mm", type=float, default=None, help="roller diameter, mm")
    g.add_argument("--pitch-diameter-mm", type=float, default=None, help="pitch diameter, mm")
    g.add_argument("--roller-diameter-in", type=float, default=None,
                   help="roller diameter, inch (instead of mm)")
    g.add_argument("--pitch-diameter-in", type=float, default=None,
                   help="pitch diameter, inch (instead of mm)")
    g.add_argument("--contact-angle-deg", type=float, default=None,
                   help="contact angle, degrees (default 0)")


def _add_analysis_args(p) -> None:
    p.add_argument("--bands", default=None,
                   help="band list: a YAML/JSON file (a list, or a mapping with a 'bands' key) "
                        "or an inline JSON list; default: kurtogram, fs/4-3fs/8, 3-6 and 10-13 x "
                        "BPFI")
    p.add_argument("--fixed-band", nargs=2, type=float, metavar=("LOW_HZ", "HIGH_HZ"),
                   default=None,
                   help="add a fixed band (Hz); LOW_HZ 0 gives a low-pass, HIGH_HZ = fs/2 means "
                        "up to Nyquist (clamped to 0.98 fs/2, recorded), e.g. --fixed-band 0 "
                        "6000 at fs = 12 kHz is the full band")
    p.add_argument("--clamp", action="store_true",
                   help="clamp a fixed band's upper edge above Nyquist to 0.98 fs/2 instead of "
                        "refusing it")
    p.add_argument("--speed", choices=("measured", "nominal"), default=None,
                   help="measured (default for a recording, RECORD_OPTIONS): the shaft rate is "
                        "read from the record's shaft harmonics (diagnosis.speed) and every "
                        "fault frequency is scaled to it, "
                        "fundamentals then searched within 0.5 %%; nominal: the given --fr / rpm "
                        "as is, fundamentals searched within --search-percent (the rates of "
                        "README 'What the confidence means' are with measured)")
    p.add_argument("--search-percent", type=float, default=None,
                   help="half-width of the search for each fault fundamental, percent of its "
                        "nominal frequency (default: the library's, AnalysisOptions; real lines "
                        "sit 0.2-0.7 %% off when the nominal speed is not the actual one); "
                        "harmonics are searched around k x the frequency found")
    p.add_argument("--routes", default=None, metavar="ROUTE[,ROUTE...]",
                   help="evidence routes of the verdict besides the envelope bands "
                        "(diagnosis.routes): cpw (cepstrum pre-whitened squared envelope "
                        "spectrum), drs_sk (discrete/random separation, kurtogram band, squared "
                        "envelope spectrum), ees (enhanced envelope spectrum); not by default: "
                        "drs_info, info (the spectral infogram's band of the random part or of "
                        "the record, docs/diagnosis_routes.md); 'envelope' for the envelope "
                        "bands alone; default: the library's for a recording (RECORD_OPTIONS: "
                        "envelope,cpw,drs_sk,ees)")
    p.add_argument("--pfa", type=float, default=None,
                   help="record-wise false-alarm probability of the verdict (default: the "
                        "library's, AnalysisOptions); each family x band test runs at pfa / "
                        "number of tests")
    p.add_argument("--harmonics", type=int, default=None,
                   help="harmonics K per family (default: the library's, AnalysisOptions, as "
                        "the sweep; refused when K x the highest fault frequency does not fit "
                        "below fs/2)")
    p.add_argument("--sidebands", type=int, default=None,
                   help="sidebands M per side of each harmonic (default: the library's, as the "
                        "sweep)")
    p.add_argument("--raw-harmonics", type=int, default=None,
                   help="orders of fr and of each fault frequency in the raw spectrum "
                        "(default: the library's, as the sweep)")
    p.add_argument("--nlevel", type=int, default=None,
                   help="kurtogram levels (default: the library's, or as deep as a short "
                        "signal allows)")
    p.add_argument("--max-level", type=float, default=None, help="kurtogram guard: max level")
    p.add_argument("--min-bandwidth", type=float, default=None,
                   help="kurtogram guard: minimum bandwidth, Hz")
    p.add_argument("--level0", choices=("analytic", "real"), default=None,
                   help="kurtosis of the kurtogram's level 0 (whole band): analytic signal "
                        "or the real signal as in Antoni's code (E x^4/(E x^2)^2 - 3); "
                        "default: the library's")
    p.add_argument("--filter-order", type=int, default=None,
                   help="Butterworth order (default: the library's)")
    p.add_argument("--window", default=None, help="spectrum window (default: the library's)")
    p.add_argument("--squared", action="store_true", help="squared envelope")
    p.add_argument("--interpolate", action="store_true",
                   help="interpolated, scalloping-corrected peak amplitudes")


def _add_output_args(p) -> None:
    p.add_argument("--csv", default=None, metavar="OUT",
                   help="write every line of every record as CSV (several records: a 'file' "
                        "column first)")
    p.add_argument("--json", default=None, metavar="OUT", nargs="?", const="-",
                   help="machine-readable result (frequencies, bands, every line, verdict) as "
                        "JSON to OUT, or alone on stdout with '--json' or '--json -'")
    p.add_argument("--table", default=None, metavar="OUT",
                   help="write the verdict table as CSV: a row per record x family (verdict, "
                        "line frequencies and amplitudes, band, margin, fault-band metrics); a "
                        "failed record gets one row with its reason")
    p.add_argument("--html", default=None, metavar="OUT",
                   help="write an HTML page with every record's verdict and figure (raw "
                        "spectrum, envelope waveform, envelope spectrum with the fault lines); "
                        "the PNGs go to --plot DIR or to OUT's folder")
    p.add_argument("--plot", default=None, metavar="DIR",
                   help="one record: write the kurtogram and envelope-spectrum figures (PNG) to "
                        "DIR; several: each record's figure")
    g = p.add_argument_group("figures of --html and of several records' --plot")
    g.add_argument("--db", action="store_true", help="amplitudes in dB (re the largest line)")
    g.add_argument("--fmax", type=float, default=None, metavar="HZ",
                   help="upper frequency of the envelope spectrum (default (K + 0.5) x the "
                        "family shown)")
    g.add_argument("--orders", action="store_true",
                   help="frequency axes in orders of the shaft rate (x fr)")
    b = p.add_argument_group("several records")
    b.add_argument("--jobs", type=int, default=1,
                   help="records analysed in parallel, one single-threaded process each "
                        "(default 1; 0: one per CPU)")
    b.add_argument("--quiet", action="store_true",
                   help="no progress bar (it is shown on stderr only when that is a terminal)")


# --------------------------------------------------------------------------- validation
def _positive(opt: str, v) -> None:
    if v is not None and (not math.isfinite(v) or v <= 0):
        raise ValueError(f"{opt}: {opt.lstrip('-').replace('-', '_')} must be a finite "
                         f"number > 0, got {v!r}")


def check_args(args) -> None:
    """Refuse bad arguments before any file is read; ``ValueError`` naming the option.

    Numbers must be finite and in range; the analysis options' ranges (``--nlevel``,
    ``--harmonics``, ``--search-percent``, ...) are AnalysisOptions' own, checked when
    :func:`build_options` makes them, also before any file is read (``--harmonics`` is checked
    again against each record's Nyquist frequency); every output must be writable;
    ``--bands`` is read here. Sets ``args.faults``, ``args.band_specs``, ``args.geometry`` and
    ``args.options`` (:func:`build_options`).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments; modified in place (also ``args.routes``).

    Raises
    ------
    ValueError
        No file, manifest or folder given, or an empty folder.
    """
    for opt in ("--fs", "--fr", "--bpfi", "--fmax"):
        _positive(opt, getattr(args, opt[2:].replace("-", "_")))
    args.routes = parse_routes(args.routes)
    args.faults = parse_faults(args.fault)
    args.geometry = geometry_args(args)
    _check_counts(args)
    if args.fixed_band is not None:
        from bearing_envelope.diagnosis.records import check_fixed_band  # start-up time

        check_fixed_band(args.fixed_band, OPTION_NAMES)
    if not args.files and args.manifest is None:
        raise ValueError("file: give a signal file, several, a folder, or --manifest CSV")
    if len(args.files) == 1 and args.manifest is None and os.path.isdir(args.files[0]) \
            and not os.listdir(args.files[0]):
        raise ValueError(f"file: {args.files[0]!r} is an empty directory; allowed: a signal "
                         f"file or a folder of them")
    check_outputs(args)
    args.band_specs = load_bands(args.bands)
    args.options = build_options(args)   # every option's range and rule: AnalysisOptions'


def parse_routes(text: str | None) -> tuple[str, ...] | None:
    """``--routes``: the comma-separated route names (checked against diagnosis.routes.ROUTES
    where the chain runs), None for the default.

    Parameters
    ----------
    text : str or None
        The ``--routes`` value.

    Returns
    -------
    tuple of str or None
        The route names, ``envelope`` left out (it always runs); ``None`` when not given.

    Raises
    ------
    ValueError
        A name that is not a route (the message lists the routes).
    """
    if text is None:
        return None
    # the layers load here, before any record is read (the chain needs them next anyway)
    from bearing_envelope.diagnosis.routes import ROUTES

    names = tuple(r.strip() for r in str(text).split(",") if r.strip())
    if not names or any(r not in ROUTES for r in names):
        raise ValueError(f"--routes: got {text!r}; allowed: a comma-separated list of "
                         f"{', '.join(ROUTES)}")
    return tuple(r for r in names if r != "envelope")


def _check_counts(args) -> None:
    if args.jobs is not None and not 0 <= args.jobs <= 1024:
        raise ValueError(f"--jobs: got {args.jobs}; allowed: an integer 0 .. 1024")


#: ``bearing_geometry`` parameter -> the option that gives it (the rules of a bearing given by
#: designation or geometry, mm or inch, are the library's: physics.catalogue.bearing_geometry).
_BEARING_OPTIONS = {"designation": "bearing", "n_rollers": "n_rollers",
                    "roller_diameter_mm": "roller_diameter_mm",
                    "pitch_diameter_mm": "pitch_diameter_mm",
                    "roller_diameter_in": "roller_diameter_in",
                    "pitch_diameter_in": "pitch_diameter_in",
                    "contact_angle_deg": "contact_angle_deg"}


def geometry_args(args) -> dict | None:
    """The bearing of ``--bearing`` or of the geometry options, or None
    (:func:`bearing_envelope.physics.catalogue.bearing_geometry` with the options' values).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments (``bearing``, ``n_rollers``, ``roller_diameter_mm``/``_in``, ``pitch_diameter_mm``/``_in``, ``contact_angle_deg``).

    Returns
    -------
    dict or None
        ``designation``, ``n_rollers``, ``roller_diameter_mm``, ``pitch_diameter_mm``,
        ``contact_angle_deg`` (inch options converted to mm); ``None`` when no bearing is given.
    """
    from bearing_envelope.physics.catalogue import bearing_geometry  # start-up time

    return bearing_geometry(**{p: getattr(args, a) for p, a in _BEARING_OPTIONS.items()},
                            names={p: "--" + a.replace("_", "-")
                                   for p, a in _BEARING_OPTIONS.items()})


def _writable(opt: str, path: str | None, *, directory: bool = False) -> None:
    """Refuse an output that cannot be written, before any analysis."""
    if path is None or (path == "-" and opt == "--json"):
        return
    target = os.path.abspath(path)
    real = os.path.realpath(target)
    if real.startswith(("/dev/", "/proc/", "/sys/")) or real in ("/dev", "/proc", "/sys"):
        raise ValueError(f"{opt}: {path!r} is a system path ({real}); allowed: a "
                         f"{'directory' if directory else 'regular file'} of your own")
    if os.path.exists(target) and not (os.path.isdir(target) or os.path.isfile(target)):
        raise ValueError(f"{opt}: {path!r} is a device, FIFO or socket; allowed: a "
                         f"{'directory' if directory else 'regular file'}")
    if directory and os.path.exists(target) and not os.path.isdir(target):
        raise ValueError(f"--plot: {path!r} is a file; allowed: a directory")
    if not directory and (os.path.isdir(target) or path.endswith(os.sep)):
        raise ValueError(f"{opt}: {path!r} is a directory; allowed: a file path")
    if os.path.exists(target) and not os.access(target, os.W_OK):
        raise ValueError(f"{opt}: {path!r} is not writable")
    d = target if directory else os.path.dirname(target)
    while not os.path.exists(d):
        d = os.path.dirname(d)
    if not os.path.isdir(d):
        raise ValueError(f"{opt}: cannot create {path!r}: {d!r} is a file")
    if not os.access(d, os.W_OK | os.X_OK):
        raise ValueError(f"{opt}: cannot write {path!r}: the folder {d!r} is not writable")


def check_outputs(args) -> None:
    """Every output (``--csv``, ``--json``, ``--table``, ``--html``, ``--plot``) writable.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments.
    """
    for opt in ("--csv", "--json", "--table", "--html"):
        _writable(opt, getattr(args, opt[2:]))
    _writable("--plot", args.plot, directory=True)


def parse_faults(items) -> dict[str, float]:
    """``["bpfi=162.2", "gear=87"]`` -> ``{"bpfi": 162.2, "gear": 87.0}`` (``--fault``).

    Parameters
    ----------
    items : iterable of str or None
        ``NAME=HZ`` items.

    Returns
    -------
    dict of str to float
        Lower-cased name -> frequency, Hz; a malformed item raises ``ValueError``.

    Raises
    ------
    ValueError
        An item that is not ``NAME=HZ``, a value that is not a number, or a frequency <= 0 Hz.
    """
    from bearing_envelope.diagnosis.analysis import check_fault_name  # start-up time

    out: dict[str, float] = {}
    for item in items or []:
        name, sep, value = str(item).partition("=")
        name = name.strip().lower()
        if not sep or not re.fullmatch(r"[a-z][a-z0-9_]*", name):
            raise ValueError(f"--fault: expected NAME=HZ with a name of letters, digits and _ "
                             f"(e.g. bpfo=107.4), got {item!r}")
        try:
            hz = float(value)
        except ValueError:
            raise ValueError(f"--fault {name}: {value!r} is not a number (Hz)") from None
        if not math.isfinite(hz) or hz <= 0:
            raise ValueError(f"--fault {name}: got {hz!r}; allowed: a frequency > 0 Hz")
        check_fault_name(name, f"--fault {name}")   # the library's rule (fr, dc reserved)
        out[name] = hz
    return out


def load_bands(text: str | None):
    """Band list from a YAML/JSON file or an inline JSON list (None: the defaults).

    Parameters
    ----------
    text : str or None
        The ``--bands`` value: a file path or inline JSON.

    Returns
    -------
    list of dict or None
        The band mappings (a mapping's ``bands`` entry); ``None`` when not given.

    Raises
    ------
    ValueError
        Not valid YAML, not UTF-8 text, neither a file nor a JSON list, or not a list of band
        mappings.
    """
    if text is None:
        return None
    if os.path.isdir(text):
        raise ValueError(f"--bands: {text!r} is a directory; allowed: a YAML/JSON file or an "
                         f"inline JSON list")
    if os.path.exists(text):
        import yaml  # only for a --bands file

        try:
            with open(text, encoding="utf-8") as fh:
                data = yaml.safe_load(fh)
        except yaml.YAMLError as exc:
            where = getattr(exc, "problem_mark", None)
            at = f" at line {where.line + 1}, column {where.column + 1}" if where else ""
            raise ValueError(f"--bands: {text} is not valid YAML{at} "
                             f"({getattr(exc, 'problem', None) or 'syntax error'})") from None
        except UnicodeDecodeError:
            raise ValueError(f"--bands: {text} is not a UTF-8 text file") from None
    else:
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(f"--bands: neither a file nor a JSON list ({exc})") from None
    if isinstance(data, dict):
        data = data.get("bands")
    if not isinstance(data, list) or not all(isinstance(b, dict) for b in data):
        raise ValueError("--bands: expected a list of band mappings (or a mapping with 'bands'); "
                         "e.g. [{\"name\": \"f\", \"strategy\": \"fixed\", \"low_hz\": 5000, "
                         "\"high_hz\": 7000}]")
    return data


# ---------------------------------------------------------------------------------- run
def record_tasks(args) -> list[dict]:
    """The records to analyse: the manifest's rows, then the files (folders expanded).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments (``manifest``, ``files``).

    Returns
    -------
    list of dict
        One task per record: ``file``, ``fs``, ``shaft_hz``, ``bearing``, ``column``,
        ``channel`` (``None`` for plain files) and a unique ``name`` (the file's stem).
    """
    from bearing_envelope.io.records import collect_records, read_manifest  # numpy: start-up

    tasks = read_manifest(args.manifest) if args.manifest is not None else []
    for t in tasks:  # the library's name of the shaft rate
        t["shaft_hz"] = t.pop("fr")
    for f in collect_records(args.files):
        tasks.append({"file": f, "fs": None, "shaft_hz": None, "bearing": None, "column": None,
                      "channel": None})
    seen: dict[str, int] = {}
    for t in tasks:  # figure names: the file's stem, numbered when two records share it
        stem = os.path.splitext(os.path.basename(t["file"]))[0]
        seen[stem] = seen.get(stem, 0) + 1
        t["name"] = stem if seen[stem] == 1 else f"{stem}_{seen[stem]}"
    return tasks


#: The library's parameters as this command names them (its messages name the options).
OPTION_NAMES = {"fs": "--fs", "shaft_hz": "--fr", "bpfi": "--bpfi", "faults": "--fault",
                "bearing": "--bearing", "n_harmonics": "--harmonics",
                "n_raw_harmonics": "--raw-harmonics", "n_sidebands": "--sidebands",
                "nlevel": "--nlevel", "fixed_band": "--fixed-band", "clamp": "--clamp",
                "bands": "--bands", "record": "the case file",
                "min_bandwidth": "--min-bandwidth", "n_rollers": "--n-rollers",
                "roller_diameter_mm": "--roller-diameter-mm/-in",
                "pitch_diameter_mm": "--pitch-diameter-mm/-in"}

#: ``AnalysisOptions`` field -> the option that sets it (None: not given, the library's); the
#: options' ranges are AnalysisOptions' own (``options_with`` names the option in its errors).
_OPTION_FIELDS = {"n_harmonics": "harmonics", "n_sidebands": "sidebands",
                  "n_raw_harmonics": "raw_harmonics", "nlevel": "nlevel",
                  "max_level": "max_level", "min_bandwidth": "min_bandwidth",
                  "filter_order": "filter_order", "window": "window", "level0": "level0",
                  "search_percent": "search_percent", "pfa": "pfa"}


def build_options(args):
    """The library's options of a recording (``RECORD_OPTIONS``) with the options given.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments (after :func:`check_args`).

    Returns
    -------
    AnalysisOptions
        ``RECORD_OPTIONS`` with every option given on the command line replaced.

    Raises
    ------
    ValueError
        A value AnalysisOptions refuses, in one line naming the option (``--harmonics``).
    """
    from bearing_envelope.diagnosis import options_with
    from bearing_envelope.diagnosis.records import RECORD_OPTIONS

    given = {f: getattr(args, a) for f, a in _OPTION_FIELDS.items()
             if getattr(args, a) is not None}
    if args.band_specs is not None:
        given["bands"] = args.band_specs
    if args.squared:
        given["squared"] = True
    if args.interpolate:
        given["interpolate"] = True
    if args.speed is not None:
        given["measure_speed"] = args.speed == "measured"
    if args.routes is not None:
        given["routes"] = args.routes
    names = {f: "--" + a.replace("_", "-") for f, a in _OPTION_FIELDS.items()}
    names.update(routes="--routes", bands="--bands")
    return options_with(RECORD_OPTIONS, names=names, **given)


def library_arguments(args) -> dict:
    """The keyword arguments of the library call, the same for every record.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments (after :func:`check_args`).

    Returns
    -------
    dict
        ``shaft_hz``, ``bearing``, ``bpfi``, ``faults``, ``options``, ``fixed_band``, ``clamp``,
        ``names`` and ``reader`` (a ``read_task`` partial with the reading options).
    """
    from functools import partial

    from bearing_envelope.io.analysis import read_task

    delim = {"tab": "\t"}.get(args.delimiter, args.delimiter)
    return {"shaft_hz": args.fr, "bearing": args.geometry, "bpfi": args.bpfi,
            "faults": args.faults, "options": args.options,
            "fixed_band": args.fixed_band, "clamp": args.clamp, "names": OPTION_NAMES,
            "reader": partial(read_task, column=args.column, channel=args.channel,
                              signal=args.signal, delimiter=delim, decimal=args.decimal,
                              fs=args.fs)}


def analyze_task(task: dict, args, library: dict):
    """One record through the library (:func:`bearing_envelope.diagnosis.batch.analyze_item`:
    the task's own fs, shaft rate and bearing win over the options).

    Parameters
    ----------
    task : dict
        One task of :func:`record_tasks`.
    args : argparse.Namespace
        Parsed ``analyze`` arguments (``args.fs``, Hz).
    library : dict
        :func:`library_arguments`.

    Returns
    -------
    RecordAnalysis
        The record's full analysis.
    """
    from bearing_envelope.diagnosis.batch import analyze_item

    return analyze_item(task, fs=args.fs, **library)


def run(args) -> int:
    """Execute ``bearing-envelope analyze``.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments.

    Returns
    -------
    int
        0 for one record; for a batch, 0, or 1 if any record failed.

    Raises
    ------
    ValueError
        A single path that is a directory where a signal file is expected.
    """
    if (args.files or args.manifest) and is_batch(args) and args.jobs != 1:
        single_threaded()  # before numpy is imported: every worker one thread
    check_args(args)
    library = library_arguments(args)
    if is_batch(args):
        return run_batch(record_tasks(args), args, library)
    if os.path.isdir(args.files[0]):
        raise ValueError(f"file: {args.files[0]!r} is a directory; allowed: a signal file")
    res = analyze_task(record_tasks(args)[0], args, library)
    from bearing_envelope.diagnosis.defect_size import size_document

    size = size_document(res)
    print_record(args, res, size)
    write_record_outputs(args, res, size)
    return 0


def _record_doc(res, size) -> dict:
    doc = record_json(res)
    if size is not None:
        doc["defect_size"] = size
    return doc


def print_record(args, res, size: dict | None = None) -> None:
    """The header, the full line table and the verdict of one record (stdout; stderr when
    ``--json -`` takes stdout).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments.
    res : RecordAnalysis
        The record's analysis.
    size : dict, optional
        :func:`~bearing_envelope.diagnosis.defect_size.size_document`, printed last (and put
        in the JSON).
    """
    import pandas as pd

    opt = res.options
    json_only = args.json == "-"
    if json_only:
        print(json.dumps(_record_doc(res, size), indent=1, allow_nan=False))
    out = sys.stderr if json_only else sys.stdout
    print(f"# {res.file} ({res.source}): {res.n_samples} samples, fs = {res.fs:g} Hz, "
          f"fr = {res.shaft_hz:g} Hz, " + ", ".join(f"{k} = {v:g} Hz" for k, v in
                                                   res.frequencies.items() if k != "fr"),
          file=out)
    kg = res.kurtogram
    if kg is not None:
        print(f"# kurtogram: level {kg.level:.3f}, fc = {kg.fc:g} Hz, bandwidth = "
              f"{kg.bandwidth:g} Hz, kurtosis = {kg.kurtosis:.3f} (level 0: {opt.level0} "
              f"signal)", file=out)
    for name, b in res.bands.items():
        lo, hi = b["band"]
        print(f"# band {name}: {lo:g} - {hi:g} Hz ({b['provenance']['strategy']}"
              f"{', clamped' if b['provenance'].get('clamped') else ''})", file=out)
    if not json_only:
        show = tidy_lines(res)[["band", "quantity", "base", "order", "sideband", "target_hz",
                                "frequency_hz", "amplitude", "floor_ratio_db", "threshold_db",
                                "detected"]]
        with pd.option_context("display.max_rows", None, "display.width", 200,
                               "display.float_format", "{:.6g}".format):
            print(show.to_string(index=False), file=out)
    verdict = res.verdict
    print(f"# search: fundamentals within +-{opt.search_percent:g} % of nominal, harmonics "
          f"around k x the line found; verdict at a record-wise false-alarm probability of "
          f"{verdict.pfa:g} ({verdict.n_tests} family x band tests at {verdict.pfa_test:.2g} "
          f"each; a family needs its fundamental and 2nd harmonic)", file=out)
    for fv in verdict.families:
        print(f"#   {fv.summary()}", file=out)
    for i, line in enumerate(verdict.summary_lines()):
        print(f"{'verdict: ' if i == 0 else '         '}{line}", file=out)
    if size is not None:
        print(f"defect length (entry-exit spacing, docs/analysis.md): {size['summary']}",
              file=out)


def write_record_outputs(args, res, size: dict | None = None) -> None:
    """``--csv``, ``--json OUT``, ``--table``, ``--plot`` and ``--html`` of one record.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``analyze`` arguments.
    res : RecordAnalysis
        The record's analysis.
    size : dict, optional
        :func:`~bearing_envelope.diagnosis.defect_size.size_document`, written into
        ``--json OUT``.
    """
    out = sys.stderr if args.json == "-" else sys.stdout
    if args.csv:
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        tidy_lines(res).to_csv(args.csv, index=False)
        print(f"# table written to {args.csv}", file=out)
    if args.json is not None and args.json != "-":
        write_text(args.json, json.dumps(_record_doc(res, size), indent=1, allow_nan=False)
                   + "\n")
        print(f"# JSON written to {args.json}", file=out)
    if args.plot:
        from bearing_envelope.diagnosis.plots import save_analysis_figures

        stem = os.path.splitext(os.path.basename(res.file))[0]
        paths = save_analysis_figures(res.details, args.plot, prefix=f"{stem}_",
                                      n_harmonics=max(res.options.n_harmonics, 3),
                                      n_sidebands=res.options.n_sidebands)
        print(f"# figures: {', '.join(paths)}", file=out)
    if args.table or args.html:
        from dataclasses import replace

        from bearing_envelope.diagnosis.batch import record_figure

        fig_dir = figure_dir(args)
        if fig_dir is not None:
            res = replace(res, figure=record_figure(res, fig_dir, figure_options(args)))
        write_batch_outputs([res], args, res.options, out=out, lines_and_json=False)
