"""``bearing-envelope check-config``: validate a config file exactly as the workflow does.

Reads ``./config.yaml`` (when present) and the file with the project's strict loader (duplicate
keys refused, YAML errors with their line), merges them as ``snakemake --configfile FILE`` from
this directory would (:func:`bearing_envelope.study.settings.workflow_settings`: a partial file is
an overlay, and a designation is a complete bearing), validates and runs every cross-field
check (:func:`bearing_envelope.study.limits.checked_settings`, the workflow's own pre-run
check: the estimated cost of every job included); prints the cases it defines, or one line
naming the field that is wrong, and for each case ``simulate`` would warn about (a defect that
never meets a loaded contact, a pit beyond the bridging limit) the same line. No simulation
runs. Use it before passing a file to Snakemake: Snakemake evaluates a ``--configfile`` as a
YTE template before any workflow code runs (this command reads it as data and refuses the
template), and it rejects some files without a line ("Config file is not valid JSON or YAML").

Example::

    bearing-envelope check-config my_config.yaml
"""

from __future__ import annotations

import argparse
import sys


def register(subparsers) -> None:
    """Add the ``check-config`` sub-command.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The sub-parsers of the top-level parser (:func:`bearing_envelope.cli.build_parser`).
    """
    p = subparsers.add_parser(
        "check-config",
        help="validate a config file as the workflow does (no simulation)",
        description=__doc__.split("\n\n")[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("config", nargs="?", default=None,
                   help="YAML config, merged over ./config.yaml as the workflow merges a "
                        "--configfile (default: ./config.yaml alone)")
    p.set_defaults(func=run)


def run(args) -> int:
    """Validate the config as the workflow would and print the cases it defines.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments; ``args.config`` is the YAML file (``None``: ``./config.yaml`` alone).

    Returns
    -------
    int
        0 when the config is valid; an invalid one raises ``ValueError`` (exit 2 via
        :func:`bearing_envelope.cli.main`).
    """
    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba, pandas: ~4 s)
    from bearing_envelope.study.limits import checked_settings

    st, estimates = checked_settings([] if args.config is None else [args.config])
    cases = st.cases
    heaviest = max(estimates, key=lambda e: e.cpu_seconds, default=None)
    cost = "" if heaviest is None else (f"; heaviest simulation about "
                                        f"{heaviest.cpu_seconds:.3g} CPU s ({heaviest.case})")
    print(f"{st.source}: valid; fidelity {st.fidelity.name}; {len(cases)} cases: "
          f"{', '.join(c.name for c in cases[:6])}{' ...' if len(cases) > 6 else ''}{cost}",
          file=sys.stdout)
    for e in estimates:     # what `simulate` will say about the case, one line each
        if e.note:
            print(f"check-config: warning: case {e.case}: {e.note}", file=sys.stderr)
    from bearing_envelope.physics.dynamics.criterion import model_choice
    for c in cases:   # which model simulates each case, and why (docs/dynamics.md)
        print(f"  {c.name}: model {model_choice(st.scene(c)).reason}", file=sys.stdout)
    return 0
