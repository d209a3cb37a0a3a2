"""``bearing-envelope contact-demo``: solve a Hertz sphere and compare with the closed form."""

from __future__ import annotations

import math
import time


def register(subparsers) -> None:
    """Add the ``contact-demo`` sub-command.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The sub-parsers of the top-level parser (:func:`bearing_envelope.cli.build_parser`).
    """
    p = subparsers.add_parser(
        "contact-demo",
        help="solve a Hertz sphere-on-flat contact and print p0 and a against Hertz",
        description="Smoke demo of the contact solver: sphere on flat, grid n x n over a box of side 6a.",
    )
    p.add_argument("--n", type=int, default=128, help="grid points per side (default 128)")
    p.add_argument("--force", type=float, default=100.0, help="normal force, N (default 100)")
    p.add_argument("--radius", type=float, default=0.01, help="equivalent sphere radius, m (default 0.01)")
    p.add_argument("--e-star", type=float, default=115.4e9, help="composite modulus, Pa (default 115.4e9)")
    p.add_argument("--tol", type=float, default=1e-8, help="solver tolerance (default 1e-8)")
    p.set_defaults(func=_run)


def _run(args) -> int:
    import numpy as np

    # lazy: keeps `bearing-envelope --help` ~0.4 s (numba: ~3 s)
    from ..contact import hertz, solve_contact

    if args.n < 8:
        raise ValueError(f"--n must be >= 8, got {args.n}")
    ref = hertz.sphere(args.force, args.radius, args.e_star)
    n = args.n
    d = 6.0 * ref.a / n
    x = (np.arange(n) - n // 2) * d  # node n // 2 at the centre
    gap = (x[:, None] ** 2 + x[None, :] ** 2) / (2.0 * args.radius)
    t = time.perf_counter()
    sol = solve_contact(gap, d, d, args.force, args.e_star, tol=args.tol)
    el = time.perf_counter() - t
    a_num = math.sqrt(sol.contact_area / math.pi)
    print(f"Hertz sphere R = {args.radius:g} m, F = {args.force:g} N, E* = {args.e_star:g} Pa, grid {n} x {n}, dx = {d:.4g} m")
    print(f"solver: {sol.iterations} iterations, residual {sol.residual:.2e}, {el:.3f} s")
    print(f"{'':14s}{'numerical':>14s}{'Hertz':>14s}{'rel. error':>12s}")
    for name, num, ex in (
        ("p0 (Pa)", sol.p_max, ref.p0),
        ("a (m)", a_num, ref.a),
        ("approach (m)", sol.approach, ref.approach),
        ("force (N)", sol.force, ref.force),
    ):
        print(f"{name:14s}{num:14.6g}{ex:14.6g}{num / ex - 1:+12.2e}")
    return 0
