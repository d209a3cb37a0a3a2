"""``bearing-envelope simulate``: pressure time history of one load x depth case to HDF5.

Reads the ``scene:`` section (and ``fidelity:``, a preset name or a mapping) of a YAML config
(``--config``, default ``./config.yaml`` when present; the whole file is validated by the same
loader as the workflow's, :func:`bearing_envelope.study.settings.load_settings`), says which file it read,
builds the scene (:meth:`bearing_envelope.physics.scene.Scene.from_mapping`, validated before any solve),
simulates the history (:func:`bearing_envelope.physics.history.simulate`) and writes the case file
(:func:`bearing_envelope.io.write_case`, layout in ``docs/file-format.md``).

Example::

    bearing-envelope simulate --config config.yaml --load-kn 500 --depth-um 50 \\
        -o results/cases/F500kN_h50um.h5
"""

from __future__ import annotations

import argparse
import os
import sys


def register(subparsers) -> None:
    """Add the ``simulate`` sub-command.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The sub-parsers of the top-level parser (:func:`bearing_envelope.cli.build_parser`).
    """
    p = subparsers.add_parser(
        "simulate",
        help="pressure time history of one load x depth case (HDF5)",
        description=__doc__.split("\n\n")[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--config", default=None,
                   help="YAML config (validated like the workflow's; only `scene:` and `fidelity:` "
                        "are used); default ./config.yaml when present, else the built-in scene")
    p.add_argument("--load-kn", type=float, required=True, help="load value, kN (see scene load.mode)")
    p.add_argument("--depth-um", type=float, required=True, help="defect depth, um (0 = no defect)")
    p.add_argument("--width-um", type=float, default=None,
                   help="defect width across rolling, um (default: the config's, null = 2 x depth)")
    p.add_argument("--fidelity", default=None,
                   help="preset draft | fast | standard | accurate | paper (overrides the config's `fidelity:`)")
    p.add_argument("--numpy", action="store_true", help="numpy synthesis instead of the numba kernel")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar and no summary")
    p.add_argument("-o", "--output", required=True, help="output case file (.h5)")
    p.set_defaults(func=run)


def check_output(path: str) -> None:
    """Refuse an output path that cannot become a case file, before any solve.

    Parameters
    ----------
    path : str
        The ``-o`` path.

    Raises
    ------
    ValueError
        ``-o`` is a directory, or its parent exists and is not a writable directory.
    """
    if os.path.isdir(path):
        raise ValueError(f"-o/--output: {path!r} is a directory; allowed: a file path ending in .h5")
    parent = os.path.dirname(os.path.abspath(path))
    probe = parent
    while not os.path.exists(probe):
        probe = os.path.dirname(probe)
    if not os.path.isdir(probe) or not os.access(probe, os.W_OK | os.X_OK):
        raise ValueError(f"-o/--output: {path!r}: {probe!r} is not a writable directory")


def resolve_config(path: str | None):
    """The config file simulate reads: ``--config``, else ``./config.yaml`` when present, else none.

    Parameters
    ----------
    path : str or None
        The ``--config`` value.

    Returns
    -------
    str or None
        The config path, or ``None`` (the built-in scene).
    """
    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba, pandas: ~4 s)
    from bearing_envelope.study.config_read import default_config_path

    if path is not None:
        return path
    p = default_config_path()
    return None if p is None else str(p)


def run(args) -> int:
    """Simulate one load x depth case and write its case file.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments: ``config``, ``load_kn`` (kN), ``depth_um`` (um), ``width_um`` (um or
        ``None``), ``fidelity``, ``numpy``, ``quiet``, ``output`` (.h5).

    Returns
    -------
    int
        0; an invalid config, case or output path raises ``ValueError``.
    """
    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba, pandas: ~4 s)
    from bearing_envelope.physics.fidelity import fidelity_from
    from bearing_envelope.physics.dynamics.case import simulate_case
    from bearing_envelope.physics.dynamics.criterion import model_choice
    from bearing_envelope.io import write_case
    from bearing_envelope.study.accuracy import case_error_model
    from bearing_envelope.study.limits import check_case
    from bearing_envelope.study.case_id import CaseId
    from bearing_envelope.study.settings import load_settings

    path = resolve_config(args.config)
    if path is None:
        scene_map, fid, cfg = {}, fidelity_from(None), {}
        source = "no config file (no --config and no ./config.yaml): the built-in scene"
    else:
        st = load_settings(path, partial=True)
        scene_map, fid, cfg = st.scene_mapping, st.fidelity, st.config
        source = f"config {path}"
    if not args.quiet:
        print(f"simulate: {source}", file=sys.stderr)
    if args.fidelity is not None:
        fid = fidelity_from(args.fidelity)
    case = CaseId(args.load_kn, args.depth_um, args.width_um)
    scene = case.scene(scene_map)
    check_output(args.output)
    check_case(case, scene, fid, cfg)  # memory and CPU estimate before any allocation
    if not args.quiet:   # which model and why, one line (docs/dynamics.md)
        print(f"simulate: {case.name}: model {model_choice(scene).reason}", file=sys.stderr)
    hist = simulate_case(scene, fid, progress=not args.quiet, use_numba=not args.numpy)
    if hist.stats.get("exposure_note"):
        # one line, also when quiet: the case's model is outside its validated range
        print(f"simulate: warning: {case.name}: {hist.stats['exposure_note']}", file=sys.stderr)
    write_case(args.output, hist, extra_attrs={"config_file": str(path or ""), **case.attrs()},
               error_model=case_error_model(hist))
    if not args.quiet and hasattr(hist, "element_load_n"):
        m = hist.model
        print(f"{args.output}: {case.name}, {hist.time.size} samples, dynamic model: "
              f"{m['steps']} steps of {m['step_s'] * 1e6:.3g} us, {m['cpu_s']:.1f} CPU s; "
              f"defect force peak {m['defect_force_peak_n']:.4g} N", file=sys.stderr)
    elif not args.quiet:
        s = hist.stats
        info = hist.table.info
        print(f"{args.output}: {case.name}, {hist.time.size} samples, {s['n_solves']} solves in "
              f"{s['wall_seconds']:.1f} s (solver {s['solver_seconds']:.1f} s); "
              f"p_max max {hist.p_max.max() / 1e9:.3f} GPa; table interp error "
              f"{info.get('interp_max_rel_error_p_max', 0.0):.2%}", file=sys.stderr)
    return 0
