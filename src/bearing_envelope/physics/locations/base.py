"""The fault-location base class and the one table of locations (:data:`LOCATIONS`).

A fault location is one object (in the style of :mod:`scipy.stats` distributions: one class per
variant on a shared base, one instance registered once, callers never branching on its name).
It says everything the rest of the package asks about where a defect sits:

- its name (``defect.location``) and short code (case names);
- which body carries the defect (:attr:`FaultLocation.body`) and the contacts (races) the defect
  passes through (:attr:`FaultLocation.races`, one contact table each), the race of the scene's
  modelled contact (:attr:`FaultLocation.contact_race`);
- its kinematics: the angle of the contact where the defect is met (:meth:`FaultLocation.angle`),
  the speed at which it sweeps through a contact (:meth:`FaultLocation.speed_m_s`);
- its event rate and line family (:attr:`FaultLocation.family`, a key of
  :func:`event_frequencies`, with the sideband spacing :attr:`FaultLocation.sideband`;
  :meth:`FaultLocation.fault_lines` for the analysis);
- its exposure: the angles at which it meets each contact's element load
  (:meth:`FaultLocation.passage_angles`, read by :mod:`~bearing_envelope.physics.exposure`);
- its table and solve needs: the load range of each race's table
  (:meth:`FaultLocation.table_loads`), whether every window row is solved
  (:attr:`FaultLocation.solves_every_row`), and its signals from the tables
  (:meth:`FaultLocation.signals`);
- its scene rules: whether ``defect.position_deg`` and a wandering ``defect.spin_axis`` are
  settings, the room along rolling and the material under the defect.

Adding a location = one subclass with one :func:`register_location` call, and its tests.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..kinematics import bearing_rates

__all__ = ["FaultLocation", "LOCATIONS", "register_location", "get_location", "location_names",
           "TWO_PI", "wrap", "cage_angle", "event_frequencies", "scene_event_frequencies",
           "contact_signals"]

TWO_PI = 2.0 * math.pi


def wrap(angle: np.ndarray, period: float) -> np.ndarray:
    """``angle`` wrapped into ``[-period/2, period/2)``.

    Parameters
    ----------
    angle : ndarray
        Angles (rad).
    period : float
        The period (rad).

    Returns
    -------
    ndarray
        Wrapped angles, shape of ``angle``.
    """
    return angle - period * np.floor(angle / period + 0.5)


def cage_angle(scene, t: np.ndarray, *, t_end: float | None = None) -> np.ndarray:
    """Cage angle (rad) at times ``t``; with slip a seeded, piecewise-constant random slip.

    ``t_end`` (s): the record's end when ``t`` is a block of it (the slip draws depend only on
    the seed and ``t_end``, so blocks of one record agree). Times slightly before 0 (the
    anti-alias filter's lead-in) continue the first period's rate.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    t : ndarray
        Times, s.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it.

    Returns
    -------
    ndarray
        Cage angle, rad, shape of ``t``; ``2 pi f_c t`` without slip.
    """
    op = scene.operation
    fc = scene.cage_rate_hz
    if op.cage_slip_percent <= 0:
        return 2.0 * np.pi * fc * t
    rng = np.random.default_rng(op.slip_seed)
    period = 1.0 / scene.bpfi_hz
    last = max(float(t[-1]) if t.size else 0.0, 0.0 if t_end is None else float(t_end))
    n = int(np.ceil(last / period)) + 2
    s = rng.uniform(0.0, 2e-2 * op.cage_slip_percent, n)
    rate = 2.0 * np.pi * fc * (1.0 - s)
    edges = np.concatenate([[0.0], np.cumsum(rate * period)])   # angle at k * period
    k = np.clip((t / period).astype(np.int64), 0, n - 1)
    return edges[k] + rate[k] * (t - k * period)


def event_frequencies(fr: float, bpfi: float, z: int, d_mm: float, pitch_mm: float,
                      alpha_deg: float) -> dict[str, float]:
    """Rates (Hz) at which the history's events repeat, from the cage rate it uses.

    ``f_c = f_r - BPFI/Z`` (the FTF; with a BPFI override, the implied cage rate), BPFO =
    ``Z f_c``, BSF = ``f_c (D + d cos alpha)/d`` (the element's spin relative to the cage),
    ``bsf2 = 2 BSF``. Without an override these are the geometric frequencies
    (:func:`bearing_envelope.physics.kinematics.fault_frequencies`) to rounding.

    Parameters
    ----------
    fr, bpfi : float
        Shaft rate and the BPFI used (Hz).
    z : int
        Elements per row.
    d_mm, pitch_mm : float
        Element and pitch diameters (mm).
    alpha_deg : float
        Contact angle (deg).

    Returns
    -------
    dict
        ``{"fr", "bpfi", "bpfo", "ftf", "bsf", "bsf2"}`` in Hz.
    """
    return bearing_rates(fr, z, d_mm, pitch_mm, alpha_deg, bpfi=bpfi)


def scene_event_frequencies(scene) -> dict[str, float]:
    """:func:`event_frequencies` of a scene.

    Parameters
    ----------
    scene : Scene
        The scene (shaft rate, BPFI used, bearing geometry).

    Returns
    -------
    dict of str to float
        ``fr``, ``bpfi``, ``bpfo``, ``ftf``, ``bsf``, ``bsf2``, Hz.
    """
    b = scene.bearing
    return event_frequencies(scene.operation.shaft_rate_hz, scene.bpfi_hz, b.rollers_per_row,
                             b.roller_diameter_mm, b.pitch_diameter_mm, b.contact_angle_deg)


def contact_signals(table, Q: np.ndarray, x: np.ndarray, use_numba: bool) -> dict:
    """Every contact signal of one contact table read at loads ``Q`` and offsets ``x``.

    Parameters
    ----------
    table : PressureTable
        The contact's table.
    Q, x : ndarray
        Element load (N) and defect offset (m) per instant.
    use_numba : bool
        Use the numba kernels for the integrals.

    Returns
    -------
    dict of str to ndarray
        ``p_max``, ``p_max_defect`` and the integral signals of
        :meth:`~bearing_envelope.physics.table.PressureTable.evaluate_integrals`.
    """
    P, Pd = table.evaluate(Q, x)
    out = {"p_max": P, "p_max_defect": Pd}
    out.update(table.evaluate_integrals(Q, x, use_numba=use_numba))
    return out


class FaultLocation:
    """Where a defect sits: the base of every location (module docstring).

    A subclass sets the class attributes and implements the methods marked so; an instance is
    registered once (:func:`register_location`) and read through :func:`get_location`.

    Attributes
    ----------
    name : str
        The ``defect.location`` value.
    code : str
        Short code in case names (``ir``).
    body : str
        The body that carries the defect (words, for messages).
    races : tuple of str
        The contacts (``inner`` / ``outer``) the defect passes through, one table each.
    contact_race : str
        The race of the scene's modelled contact (:attr:`Bearing.contact_race`).
    family, sideband : str
        The line family of its events and the sideband spacing searched (keys of
        :func:`event_frequencies`).
    positioned : bool
        ``defect.position_deg`` is a setting (the defect is fixed in the load frame).
    spins : bool
        ``defect.spin_axis: wandering`` is allowed (the defect is on a rolling element).
    solves_every_row : bool
        Every row of the zoom window is solved with the defect (the inner race, whose default
        sweep and discretisation-error model were computed so), else only the contact's rows
        (:func:`~bearing_envelope.physics.solves.contact_rows`).
    """

    name: str = ""
    code: str = ""
    body: str = ""
    races: tuple[str, ...] = ()
    contact_race: str = "inner"
    family: str = ""
    sideband: str = ""
    positioned: bool = False
    spins: bool = False
    solves_every_row: bool = False

    def __repr__(self) -> str:
        return f"<FaultLocation {self.name!r} ({self.code}): {self.family} events>"

    # scene rules ---------------------------------------------------------------------------
    def thickness_m(self, bearing) -> float:
        """Material under the defect (m): the deepest a pit can be.

        Parameters
        ----------
        bearing : Bearing
            The bearing.

        Returns
        -------
        float
            Thickness, m.
        """
        raise NotImplementedError

    def room_m(self, bearing) -> tuple[float, str]:
        """Room along rolling a defect must stay under (m), and what it is (words).

        Parameters
        ----------
        bearing : Bearing
            The bearing.

        Returns
        -------
        tuple of (float, str)
            The room (m) and its description.
        """
        raise NotImplementedError

    def where(self, scene) -> str:
        """The location in words for a message (the outer race adds its angle).

        Parameters
        ----------
        scene : Scene
            The case's scene.

        Returns
        -------
        str
            E.g. ``inner_race`` or ``outer_race at 90 deg``.
        """
        return self.name

    # kinematics ----------------------------------------------------------------------------
    def speed_m_s(self, scene) -> float:
        """Speed (m/s) at which the defect sweeps through a contact.

        Parameters
        ----------
        scene : Scene
            The case's scene.

        Returns
        -------
        float
            m/s.
        """
        raise NotImplementedError

    def angle(self, scene, t: np.ndarray, *, t_end: float | None = None) -> np.ndarray:
        """Angle (rad, from the load direction) of the contact where the defect is met.

        Parameters
        ----------
        scene : Scene
            The case's scene.
        t : ndarray
            Times, s.
        t_end : float, optional
            End of the whole record, s, when ``t`` is one block of it.

        Returns
        -------
        ndarray
            Angle, rad, shape of ``t`` (not wrapped).
        """
        raise NotImplementedError

    def event_rate(self, rates: Mapping[str, float]) -> float:
        """The rate (Hz) of its events among ``rates`` (:func:`event_frequencies`).

        Parameters
        ----------
        rates : mapping of str to float
            Rates by family name.

        Returns
        -------
        float
            ``rates[self.family]``, Hz.
        """
        return float(rates[self.family])

    def fault_lines(self, rates: Mapping[str, float]):
        """The family the analysis searches and its sideband spacing.

        Parameters
        ----------
        rates : mapping of str to float
            The case's rates (:func:`event_frequencies` keys), Hz.

        Returns
        -------
        frequencies : dict
            ``{family: Hz}``.
        sideband_spacing : dict or None
            ``{family: (spacing name, Hz)}``; None: the analysis's default spacing.
        """
        return ({self.family: float(rates[self.family])},
                {self.family: (self.sideband, float(rates[self.sideband]))})

    # exposure and tables -------------------------------------------------------------------
    def passage_angles(self, scene, ld, n: int) -> dict[str, np.ndarray]:
        """Angles (rad, from the load direction) at which the defect meets each contact's
        element load, sampled uniformly over its passages.

        Parameters
        ----------
        scene : Scene
            The case's scene.
        ld : LoadDistribution
            The load law.
        n : int
            Samples per race over a range of angles.

        Returns
        -------
        dict of str to ndarray
            Race -> angles.
        """
        raise NotImplementedError

    def table_loads(self, scene, ld, exposure: dict) -> dict[str, tuple[float, float | None]]:
        """The load range of each race's contact table: ``(q_max, q_min)``, N (``q_min`` None:
        the table's default first node, loads below it scaled).

        Parameters
        ----------
        scene : Scene
            The case's scene.
        ld : LoadDistribution
            The load law.
        exposure : dict
            :func:`~bearing_envelope.physics.exposure.exposure` of the case.

        Returns
        -------
        dict
            Race -> ``(q_max, q_min)``.
        """
        out = {}
        for race in self.races:
            r = exposure["races"][race]
            out[race] = (r["q_max_N"], r["q_min_N"] if r["loaded_fraction"] == 1.0 else None)
        return out

    def signals(self, scene, tables: Mapping, ld, t: np.ndarray, *, t_end: float | None = None,
                use_numba: bool = True) -> dict[str, np.ndarray]:
        """Every contact and state signal at the instants ``t``.

        Parameters
        ----------
        scene : Scene
            The case's scene.
        tables : mapping of str to PressureTable
            The contact table of each race of :attr:`races`.
        ld : LoadDistribution
            The load law.
        t : ndarray
            Times, s, shape ``(n,)``.
        t_end : float, optional
            End of the whole record, s, when ``t`` is one block of it.
        use_numba : bool, default True
            Use the numba kernels.

        Returns
        -------
        dict of str to ndarray
            Signal name -> values (SI units), each of shape ``(n,)``.
        """
        raise NotImplementedError


#: The one table of fault locations: name -> the registered :class:`FaultLocation`.
LOCATIONS: dict[str, FaultLocation] = {}


def register_location(location: FaultLocation) -> FaultLocation:
    """Register a location under its name (once; a second one of the same name is refused).

    Parameters
    ----------
    location : FaultLocation
        The location (an instance).

    Returns
    -------
    FaultLocation
        ``location``.

    Raises
    ------
    ValueError
        Not a :class:`FaultLocation` with a name and a code, or its name or code already
        registered.
    """
    if not isinstance(location, FaultLocation) or not location.name or not location.code:
        raise ValueError(f"register_location: got {location!r}; allowed: a FaultLocation "
                         f"instance with a name and a code")
    codes = {loc.code: n for n, loc in LOCATIONS.items()}
    if location.name in LOCATIONS or location.code in codes:
        raise ValueError(f"register_location: {location.name!r} (code {location.code!r}) is "
                         f"already registered; allowed: a new name and code")
    LOCATIONS[location.name] = location
    return location


def location_names() -> tuple[str, ...]:
    """The registered location names, in registration order.

    Returns
    -------
    tuple of str
        The names (the first is the built-in default, the inner race).
    """
    return tuple(LOCATIONS)


def get_location(name) -> FaultLocation:
    """The registered location called ``name``.

    Parameters
    ----------
    name : str or FaultLocation
        A ``defect.location`` value (a location passes through).

    Returns
    -------
    FaultLocation
        The location.

    Raises
    ------
    ValueError
        One line naming the value and the allowed names.
    """
    if isinstance(name, FaultLocation):
        return name
    try:
        return LOCATIONS[name]
    except (KeyError, TypeError):
        raise ValueError(f"defect.location: got {name!r}; allowed: "
                         f"{' | '.join(LOCATIONS)}") from None
