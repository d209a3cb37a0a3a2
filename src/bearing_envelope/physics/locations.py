"""Fault locations other than the inner race: outer race and rolling element (issue 23).

The inner-race history (:mod:`bearing_envelope.physics.history`) is unchanged; this module gives
the kinematics, the roller load and the contact tables of the two other locations and turns
them into the same signals (:data:`bearing_envelope.physics.history.CONTACT_SIGNALS`).

**Outer race** (``defect.location: outer_race``). The outer ring is fixed; the defect sits at
``phi_d`` = ``defect.position_deg`` from the load direction (0 = centre of the load zone). The
cage turns at ``f_c`` (the FTF, or ``f_r - BPFI/Z`` with the BPFI override); element ``j`` sits
at ``theta_c + 2 pi j / Z``, so an element passes the defect at ``Z f_c`` = BPFO. Offset of the
defect from the nearest element's contact centre along the outer raceway:
``x = R_o wrap(phi_d - theta_c)`` (``wrap`` into ``[-pi/Z, pi/Z)``,
``R_o = (D + d cos alpha)/2``). Load: the load-zone law at ``phi_d`` (``smooth``: constant under
a steady load, zero outside the load zone) or at the passing element's angle (``discrete``).
The contact table is that of the outer contact: the concave outer raceway in the gap
(``1/R_x = 2/d - 1/R_o``; the outer profile radius or groove conformity across rolling).

**Rolling element** (``defect.location: rolling_element``). The defect is on element 0, whose
centre is at the cage angle ``theta_c`` (in the load zone's centre at ``t = 0``); the element
carries ``Q(theta_c)``, modulated at the cage rate (FTF). Rolling without slip on the fixed
outer race, it turns relative to the cage by ``beta = theta_c (D + d cos alpha)/d`` (this is
``2 pi BSF t`` without slip: ``R_o f_c / (d/2) = BSF``). Its surface point at ``beta = 0``
touches the outer race, at ``beta = pi`` the inner race: the defect meets the two races
alternately, ``2 x BSF`` events per unit time, each in its own contact (its own table, the
race's curvature): ``x_o = (d/2) wrap(beta)``, ``x_i = (d/2) wrap(beta - pi)`` (``wrap`` into
``[-pi, pi)``). Signals: ``p_max`` the larger of the two contacts' maxima; ``p_max_defect`` and
the integral signals add the two contacts' (the element's approach is the sum of its two
approaches; the defect is in at most one contact at a time); ``defect_offset`` the offset in
the contact the defect is nearer to. With the centrifugal force (``load.centrifugal``) the
outer contact carries ``Q_o = Q_i + F_c``: the defect strikes the outer race all round
(``roller_load`` and ``contact_force`` then read the outer contact's ``Q_o``).

**Intermittent strikes** (``defect.spin_axis: wandering``). A ball rolls about an axis fixed in
the ball only while it is loaded; in the unloaded zone the cage and drag turn it freely. The
model: once per cage turn, at ``theta_c = pi`` (mod 2 pi, the middle of the unloaded zone), the
ball's orientation is redrawn uniformly on the sphere (seeded by ``defect.spin_seed`` and the
turn's index): the defect's latitude from the new rolling track (``sin(lat)`` uniform in
[-1, 1]) and its longitude along it (uniform). Through that turn the defect passes the contacts
at ``(d/2) sin(lat)`` from the track, and strikes a contact only while that is within the
contact's axial semi-axis ``b(Q)`` (Hertz; the pit's centre inside the ellipse). On-track
strikes are modelled as centred ones (the table's): an assumption that over-states the events of
a defect near the ellipse's axial end. With ``b ~ 1.06 mm`` at 534 N on the 6205's 3.97 mm
radius a turn strikes with probability ``b/(d/2) = 0.27`` at the most loaded position.
"""

from __future__ import annotations

import math

import numpy as np

from .fidelity import Fidelity
from .geometry import hertz_estimate
from .kinematics import bearing_rates
from .loads import LoadDistribution
from .scene import Scene
from .solves import SolveStats
from .table import PressureTable, build_table

__all__ = ["location_tables", "location_signals", "outer_race_kinematics", "OFF_TRACK_OFFSET_M",
           "on_track",
           "rolling_element_kinematics", "TWO_PI", "LOCATION_FAMILIES", "event_frequencies",
           "scene_event_frequencies"]

TWO_PI = 2.0 * math.pi

#: The envelope line family each defect location makes and the spacing its sidebands are
#: searched at: inner race BPFI with fr sidebands (the defect crosses the load zone once per
#: shaft turn); outer race BPFO, events of equal load under a steady load, so no sidebands are
#: expected (fr sidebands are searched as a check); rolling element 2 x BSF (the defect meets both
#: races once per spin turn) with FTF sidebands (the element crosses the load zone with the cage).
LOCATION_FAMILIES = {"inner_race": ("bpfi", "fr"), "outer_race": ("bpfo", "fr"),
                     "rolling_element": ("bsf2", "ftf")}


def event_frequencies(fr: float, bpfi: float, z: int, d_mm: float, pitch_mm: float,
                      alpha_deg: float) -> dict[str, float]:
    """Rates (Hz) at which the history's events repeat, from the cage rate it uses.

    ``f_c = f_r - BPFI/Z`` (the FTF; with a BPFI override, the implied cage rate), BPFO =
    ``Z f_c``, BSF = ``f_c (D + d cos alpha)/d`` (the element's spin relative to the cage,
    :func:`rolling_element_kinematics`), ``bsf2 = 2 BSF``. Without an override these are the
    geometric frequencies (:func:`bearing_envelope.physics.kinematics.fault_frequencies`) to
    rounding.

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


def scene_event_frequencies(scene: Scene) -> dict[str, float]:
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


def _wrap(angle: np.ndarray, period: float) -> np.ndarray:
    """``angle`` wrapped into ``[-period/2, period/2)`` (rad)."""
    return angle - period * np.floor(angle / period + 0.5)


def outer_race_kinematics(scene: Scene, theta_c: np.ndarray) -> dict[str, np.ndarray]:
    """Offset (m) of an outer-race defect from the nearest element, and the angle (rad) of the
    load law: the defect's (``smooth``) or the passing element's (``discrete``).

    Parameters
    ----------
    scene : Scene
        ``defect.location == "outer_race"``.
    theta_c : ndarray
        Cage angle (rad) at each instant (:func:`bearing_envelope.physics.history.cage_angle`).

    Returns
    -------
    dict of str to ndarray
        ``offset`` (m) and ``psi`` (rad), shape of ``theta_c``.
    """
    b = scene.bearing
    phi_d = math.radians(scene.defect.position_deg)
    wrapped = _wrap(phi_d - theta_c, TWO_PI / b.rollers_per_row)
    psi = phi_d - wrapped if scene.load.roller_load == "discrete" else np.full(theta_c.shape, phi_d)
    return {"offset": b.outer_race_radius_m * wrapped, "psi": psi}


def rolling_element_kinematics(scene: Scene, theta_c: np.ndarray) -> dict[str, np.ndarray]:
    """Offsets (m) of a rolling-element defect in the outer and inner contact, and the element's
    angle (rad) from the load direction (the load law's argument).

    ``beta = theta_c (D + d cos alpha)/d`` (the element's turn relative to the cage), offsets
    ``x_o = (d/2) wrap(beta)``, ``x_i = (d/2) wrap(beta - pi)``.

    Parameters
    ----------
    scene : Scene
        ``defect.location == "rolling_element"``.
    theta_c : ndarray
        Cage angle (rad) at each instant.

    Returns
    -------
    dict of str to ndarray
        ``psi`` (rad, = ``theta_c``), ``offset_outer``, ``offset_inner`` and ``track_offset``
        (m; zero unless ``defect.spin_axis == "wandering"``), shape of ``theta_c``.
    """
    b = scene.bearing
    d = 1e-3 * b.roller_diameter_mm
    beta = theta_c * (b.pitch_diameter_m + d * math.cos(b.contact_angle_rad)) / d
    out = {"psi": theta_c, "track_offset": np.zeros(np.shape(theta_c))}
    if scene.defect.spin_axis == "wandering":
        sin_lat, lon = _orientations(scene.defect.spin_seed, theta_c)
        beta = beta + lon
        out["track_offset"] = 0.5 * d * sin_lat
    out.update(offset_outer=0.5 * d * _wrap(beta, TWO_PI),
               offset_inner=0.5 * d * _wrap(beta - math.pi, TWO_PI))
    return out


def _orientations(seed: int, theta_c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(sin(latitude), longitude)`` of the defect relative to the element's rolling track
    during each cage turn, drawn uniformly on the sphere once per turn at ``theta_c = pi``
    (mod 2 pi: the unloaded zone) from the generator seeded ``(seed, turn)``: deterministic,
    and the same in every block of a record."""
    turn = np.floor((np.asarray(theta_c, dtype=float) + math.pi) / TWO_PI).astype(np.int64)
    sin_lat, lon = np.empty(turn.shape), np.empty(turn.shape)
    for k in np.unique(turn):
        rng = np.random.default_rng([int(seed), int(k) + 2 ** 31])
        sel = turn == k
        sin_lat[sel] = rng.uniform(-1.0, 1.0)      # uniform on the sphere: sin(lat) uniform
        lon[sel] = rng.uniform(0.0, TWO_PI)
    return sin_lat, lon


#: Offset (m) given to a defect that is off the contact's track: beyond every table's reach,
#: where the table reads the no-defect contact.
OFF_TRACK_OFFSET_M = 1.0


def on_track(scene: Scene, race: str, q: np.ndarray, track_offset: np.ndarray) -> np.ndarray:
    """Whether a rolling-element defect (its centre) lies within the ``race`` contact's axial
    semi-axis ``b(Q)`` (Hertz, ``b ~ Q^(1/3)``) of the rolling track.

    Parameters
    ----------
    scene : Scene
        The scene (the contact's curvatures and materials).
    race : {"inner", "outer"}
        The contact.
    q : ndarray
        Its load (N) at each instant.
    track_offset : ndarray
        The defect's axial distance from the track (m), :func:`rolling_element_kinematics`.

    Returns
    -------
    ndarray of bool
        True where the defect can strike that contact.
    """
    b1 = hertz_estimate(scene.for_race(race), 1.0).b
    return np.abs(track_offset) <= b1 * np.cbrt(np.clip(q, 0.0, None))


def location_tables(scene: Scene, fid: Fidelity, exposure: dict, stats: SolveStats,
                    progress: bool = False) -> tuple[dict[str, PressureTable], list, dict]:
    """The contact tables a location needs: ``{"outer": ...}`` for an outer-race defect (the
    scene's contact is already the outer one), ``{"inner": ..., "outer": ...}`` for a rolling
    element, each over the loads its defect meets (``exposure``,
    :func:`~.exposure.exposure`): up to the largest; from the smallest when every passage is
    loaded (a fixed outer-race defect, or the outer race with the centrifugal force), else from
    the default first node. Returns ``(tables, nodes, snapshots)`` (nodes and snapshots of the
    first table).

    Parameters
    ----------
    scene : Scene
        An outer-race or rolling-element defect.
    fid : Fidelity
        The fidelity of the solves.
    exposure : dict
        :func:`~.exposure.exposure` of the scene (``races`` -> ``q_min_N``, ``q_max_N``,
        ``loaded_fraction``).
    stats : SolveStats
        Accumulates the solve statistics.
    progress : bool, default False
        Show progress.

    Returns
    -------
    tables : dict of str to PressureTable
        ``"outer"`` (and ``"inner"`` for a rolling element).
    nodes : list of LoadNode
        The first table's per-load solutions (:func:`~.table.build_table`).
    snapshots : dict
        The first table's pressure fields at a few offsets per load.
    """
    races = ("outer",) if scene.defect.location == "outer_race" else ("inner", "outer")
    tables, nodes, snaps = {}, None, None
    for race in races:
        r = exposure["races"][race]
        q_min = r["q_min_N"] if r["loaded_fraction"] == 1.0 else None
        tab, nd, sn = build_table(scene.for_race(race), fid, q_max=r["q_max_N"], stats=stats,
                                  progress=progress, q_min=q_min)
        tables[race] = tab
        if nodes is None:
            nodes, snaps = nd, sn
    return tables, nodes, snaps


def _contact(table: PressureTable, Q: np.ndarray, x: np.ndarray, use_numba: bool) -> dict:
    P, Pd = table.evaluate(Q, x)
    out = {"p_max": P, "p_max_defect": Pd}
    out.update(table.evaluate_integrals(Q, x, use_numba=use_numba))
    return out


def location_signals(scene: Scene, tables: dict[str, PressureTable], ld: LoadDistribution,
                     theta_c: np.ndarray, *, use_numba: bool = True) -> dict[str, np.ndarray]:
    """Every contact and state signal at the instants of ``theta_c`` (cage angle, rad) for an
    outer-race or rolling-element defect (module docstring).

    Parameters
    ----------
    scene : Scene
        An outer-race or rolling-element defect.
    tables : dict of str to PressureTable
        :func:`location_tables`.
    ld : LoadDistribution
        The load-zone law.
    theta_c : ndarray
        Cage angle, rad, shape ``(n,)``.
    use_numba : bool, default True
        Use the numba kernels for the integrals.

    Returns
    -------
    dict of str to ndarray
        Every contact and state signal (SI units), each of shape ``(n,)``; for a rolling
        element the two contacts combined (``p_max`` the larger, the others summed).
    """
    if scene.defect.location == "outer_race":
        kin = outer_race_kinematics(scene, theta_c)
        Q = ld.load_at(kin["psi"], "outer")
        out = _contact(tables["outer"], Q, kin["offset"], use_numba)
        out.update(roller_load=Q, defect_offset=kin["offset"])
        return out
    kin = rolling_element_kinematics(scene, theta_c)
    Qi = ld.load_at(kin["psi"], "inner")
    # the outer contact carries the centrifugal force too (equal to Qi without it)
    Q = ld.load_at(kin["psi"], "outer") if ld.centrifugal > 0 else Qi
    xi_, xo_ = kin["offset_inner"], kin["offset_outer"]
    if scene.defect.spin_axis == "wandering":
        xi_ = np.where(on_track(scene, "inner", Qi, kin["track_offset"]), xi_, OFF_TRACK_OFFSET_M)
        xo_ = np.where(on_track(scene, "outer", Q, kin["track_offset"]), xo_, OFF_TRACK_OFFSET_M)
    ci = _contact(tables["inner"], Qi, xi_, use_numba)
    co = _contact(tables["outer"], Q, xo_, use_numba)
    removed = ci["removed_force"] + co["removed_force"]
    xo, xi = kin["offset_outer"], kin["offset_inner"]
    return {"p_max": np.maximum(ci["p_max"], co["p_max"]),
            "p_max_defect": ci["p_max_defect"] + co["p_max_defect"],
            "removed_force": removed, "contact_force": Q - removed,
            "approach": ci["approach"] + co["approach"],
            "approach_change": ci["approach_change"] + co["approach_change"],
            "contact_area": ci["contact_area"] + co["contact_area"],
            "roller_load": Q, "defect_offset": np.where(np.abs(xo) <= np.abs(xi), xo, xi)}
