"""Command-line entry point ``bearing-envelope``.

Each sub-command lives in its own module under :mod:`bearing_envelope.commands`, which defines
``register(subparsers)``; that function adds the sub-parser and sets ``func`` (called with the
parsed arguments, returns an exit code). Heavy imports happen inside ``func`` so that
``bearing-envelope --help`` stays fast.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

from . import __version__, commands


def build_parser() -> argparse.ArgumentParser:
    """Return the top-level parser with every sub-command registered.

    Returns
    -------
    argparse.ArgumentParser
        The ``bearing-envelope`` parser; each public module of :mod:`bearing_envelope.commands`
        has added its sub-parser through ``register``.
    """
    parser = argparse.ArgumentParser(
        prog="bearing-envelope",
        description="Contact simulation and envelope analysis of a damaged roller bearing.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{commands.__name__}.{info.name}")
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the process exit code.

    Parameters
    ----------
    argv : list of str or None, optional
        Arguments without the program name; ``None`` reads ``sys.argv[1:]``.

    Returns
    -------
    int
        The sub-command's exit code (``None`` from it counts as 0); 2 when no sub-command is
        given (help is printed) or when it raises ``ValueError``, ``KeyError`` or ``OSError``
        (one error line on stderr).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except (ValueError, KeyError) as exc:
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"bearing-envelope {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except OSError as exc:  # a path that is a directory, missing, unreadable or not writable
        what = exc.strerror or type(exc).__name__
        where = f": {exc.filename}" if exc.filename else ""
        print(f"bearing-envelope {args.command}: error: {what}{where}" if exc.strerror
              else f"bearing-envelope {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
