"""``bearing-envelope simulate``: pressure time history of one load x depth case to HDF5.

Reads the ``scene:`` section (and ``fidelity:``, a preset name or a mapping) of a YAML config,
builds the scene (:meth:`bearing_envelope.scene.Scene.from_mapping`, validated before any solve),
simulates the history (:func:`bearing_envelope.history.simulate`) and writes the case file
(:func:`bearing_envelope.io.write_case`, layout in ``docs/file-format.md``).

Example::

    bearing-envelope simulate --config config.yaml --load-kn 500 --depth-um 50 \\
        -o results/cases/F500kN_h50um.h5
"""

from __future__ import annotations

import argparse
import sys


def register(subparsers) -> None:
    """Add the ``simulate`` sub-command."""
    p = subparsers.add_parser(
        "simulate",
        help="pressure time history of one load x depth case (HDF5)",
        description=__doc__.split("\n\n")[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--config", default=None,
                   help="YAML config with `scene:` (and optionally `fidelity:`); default scene if omitted")
    p.add_argument("--load-kn", type=float, required=True, help="load value, kN (see scene load.mode)")
    p.add_argument("--depth-um", type=float, required=True, help="defect depth, um (0 = no defect)")
    p.add_argument("--fidelity", default=None,
                   help="preset draft | standard | paper (overrides the config's `fidelity:`)")
    p.add_argument("--numpy", action="store_true", help="numpy synthesis instead of the numba kernel")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar and no summary")
    p.add_argument("-o", "--output", required=True, help="output case file (.h5)")
    p.set_defaults(func=run)


def load_config(path: str | None) -> dict:
    """The YAML config as a dict (empty without a path)."""
    if path is None:
        return {}
    import yaml

    with open(path, encoding="utf-8") as fh:
        cfg = yaml.safe_load(fh) or {}
    if not isinstance(cfg, dict):
        raise ValueError(f"{path}: the config must be a mapping, got {type(cfg).__name__}")
    return cfg


def run(args) -> int:
    from bearing_envelope.fidelity import fidelity_from
    from bearing_envelope.history import simulate
    from bearing_envelope.io import write_case
    from bearing_envelope.scene import Scene

    cfg = load_config(args.config)
    scene = Scene.from_mapping(cfg.get("scene") or {}, load_kN=args.load_kn, depth_um=args.depth_um)
    fid = fidelity_from(args.fidelity if args.fidelity is not None else cfg.get("fidelity"))
    hist = simulate(scene, fid, progress=not args.quiet, use_numba=not args.numpy)
    write_case(args.output, hist, extra_attrs={"config_file": str(args.config or "")})
    if not args.quiet:
        s = hist.stats
        info = hist.table.info
        print(f"{args.output}: {hist.time.size} samples, {s['n_solves']} solves in "
              f"{s['wall_seconds']:.1f} s (solver {s['solver_seconds']:.1f} s); "
              f"p_max max {hist.p_max.max() / 1e9:.3f} GPa; table interp error "
              f"{info.get('interp_max_rel_error_p_max', 0.0):.2%}", file=sys.stderr)
    return 0
