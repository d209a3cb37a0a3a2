"""The rolling element: the defect is on one ball/roller and meets both races (issue 23).

The defect is on element 0, whose centre is at the cage angle ``theta_c`` (in the load zone's
centre at ``t = 0``); the element carries ``Q(theta_c)``, modulated at the cage rate (FTF).
Rolling without slip on the fixed outer race, it turns relative to the cage by ``beta = theta_c
(D + d cos alpha)/d`` (this is ``2 pi BSF t`` without slip: ``R_o f_c / (d/2) = BSF``). Its
surface point at ``beta = 0`` touches the outer race, at ``beta = pi`` the inner race: the defect
meets the two races alternately, ``2 x BSF`` events per unit time, each in its own contact (its
own table, the race's curvature): ``x_o = (d/2) wrap(beta)``, ``x_i = (d/2) wrap(beta - pi)``
(``wrap`` into ``[-pi, pi)``). Signals: ``p_max`` the larger of the two contacts' maxima;
``p_max_defect`` and the integral signals add the two contacts' (the element's approach is the
sum of its two approaches; the defect is in at most one contact at a time); ``defect_offset``
the offset in the contact the defect is nearer to. With the centrifugal force
(``load.centrifugal``) the outer contact carries ``Q_o = Q_i + F_c``: the defect strikes the
outer race all round (``roller_load`` and ``contact_force`` then read the outer contact's
``Q_o``).

**Intermittent strikes** (``defect.spin_axis: wandering``). A ball rolls about an axis fixed in
the ball only while it is loaded between the two races; where its inner contact carries no load
the cage and drag turn it freely. The model: once per cage turn, where the ball is least loaded
(``theta_c = pi`` mod 2 pi: the minimum of the load law ``Q(psi)``, which falls monotonically
from the load direction), the ball's orientation is redrawn uniformly on the sphere (seeded by
``defect.spin_seed`` and the turn's index): the defect's latitude from the new rolling track
(``sin(lat)`` uniform in [-1, 1]) and its longitude along it (uniform). **Only when the ball is
free there**: when its inner contact is loaded even at ``psi = pi`` (a preload, or a light
clearance with the centrifugal force, loads every ball all round; issue 43: config_rig.yaml's
scene carries Q_i = 7 N at 12:00) the two contacts hold the spin axis, and the orientation
drawn at the start (turn 0) is kept through the record. Through a turn the defect passes the
contacts at ``(d/2) sin(lat)`` from the track, and strikes a contact only while that is within
the contact's axial semi-axis ``b(Q)`` (Hertz; the pit's centre inside the ellipse). On-track
strikes are modelled as centred ones (the table's): an assumption that over-states the events of
a defect near the ellipse's axial end. With ``b ~ 1.06 mm`` at 534 N on the 6205's 3.97 mm
radius a turn strikes with probability ``b/(d/2) = 0.27`` at the most loaded position.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import hertz_estimate
from .base import FaultLocation, TWO_PI, cage_angle, contact_signals, register_location, wrap

__all__ = ["RollingElement", "ROLLING_ELEMENT", "rolling_element_kinematics", "on_track",
           "OFF_TRACK_OFFSET_M", "spin_is_free"]

#: Offset (m) given to a defect that is off the contact's track: beyond every table's reach,
#: where the table reads the no-defect contact.
OFF_TRACK_OFFSET_M = 1.0


def spin_is_free(ld) -> bool:
    """Whether a ball is free to turn where it is least loaded (``psi = pi``): its inner
    contact unloaded there (within the rounding of the load law, :meth:`~.loads.
    LoadDistribution.loaded`).

    Parameters
    ----------
    ld : LoadDistribution
        The load law.

    Returns
    -------
    bool
        True when the inner contact carries no load at ``psi = pi``.
    """
    return not bool(ld.loaded(ld.load_at(np.full(1, math.pi), "inner"))[0])


def rolling_element_kinematics(scene, theta_c: np.ndarray, *,
                               redraw: bool = True) -> dict[str, np.ndarray]:
    """Offsets (m) of a rolling-element defect in the outer and inner contact, and the element's
    angle (rad) from the load direction (the load law's argument).

    ``beta = theta_c (D + d cos alpha)/d`` (the element's turn relative to the cage), offsets
    ``x_o = (d/2) wrap(beta)``, ``x_i = (d/2) wrap(beta - pi)``.

    Parameters
    ----------
    scene : Scene
        A rolling-element defect.
    theta_c : ndarray
        Cage angle (rad) at each instant.
    redraw : bool, default True
        ``wandering`` only: redraw the orientation once per cage turn (the ball is free where
        least loaded, :func:`spin_is_free`); False: the orientation of turn 0 throughout.

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
        sin_lat, lon = _orientations(scene.defect.spin_seed, theta_c, redraw)
        beta = beta + lon
        out["track_offset"] = 0.5 * d * sin_lat
    out.update(offset_outer=0.5 * d * wrap(beta, TWO_PI),
               offset_inner=0.5 * d * wrap(beta - math.pi, TWO_PI))
    return out


def _orientations(seed: int, theta_c: np.ndarray, redraw: bool) -> tuple[np.ndarray, np.ndarray]:
    """``(sin(latitude), longitude)`` of the defect relative to the element's rolling track
    during each cage turn, drawn uniformly on the sphere once per turn at ``theta_c = pi``
    (mod 2 pi: where the ball is least loaded) from the generator seeded ``(seed, turn)``:
    deterministic, and the same in every block of a record. ``redraw`` False: turn 0's draw
    throughout (the spin axis held by loaded contacts all round)."""
    theta_c = np.asarray(theta_c, dtype=float)
    turn = np.floor((theta_c + math.pi) / TWO_PI).astype(np.int64) if redraw else \
        np.zeros(theta_c.shape, dtype=np.int64)
    sin_lat, lon = np.empty(turn.shape), np.empty(turn.shape)
    for k in np.unique(turn):
        rng = np.random.default_rng([int(seed), int(k) + 2 ** 31])
        sel = turn == k
        sin_lat[sel] = rng.uniform(-1.0, 1.0)      # uniform on the sphere: sin(lat) uniform
        lon[sel] = rng.uniform(0.0, TWO_PI)
    return sin_lat, lon


def on_track(scene, race: str, q: np.ndarray, track_offset: np.ndarray) -> np.ndarray:
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


class RollingElement(FaultLocation):
    """The rolling element (module docstring): 2 x BSF events with FTF sidebands (the element
    crosses the load zone with the cage)."""

    name = "rolling_element"
    code = "re"
    body = "rolling element"
    races = ("inner", "outer")
    contact_race = "inner"
    family = "bsf2"
    sideband = "ftf"
    spins = True

    def thickness_m(self, bearing) -> float:
        """``d/2``, m.

        Parameters
        ----------
        bearing : Bearing
            The bearing.

        Returns
        -------
        float
            m.
        """
        return 1e-3 * 0.5 * bearing.roller_diameter_mm

    def room_m(self, bearing) -> tuple[float, str]:
        """Half the element's circumference.

        Parameters
        ----------
        bearing : Bearing
            The bearing.

        Returns
        -------
        tuple of (float, str)
            Room (m) and its description.
        """
        return 0.5e-3 * math.pi * bearing.roller_diameter_mm, "half the element's circumference"

    def speed_m_s(self, scene) -> float:
        """``2 pi f_c R_o`` (its surface rolls on the fixed outer race).

        Parameters
        ----------
        scene : Scene
            The case's scene.

        Returns
        -------
        float
            m/s.
        """
        return 2.0 * math.pi * scene.cage_rate_hz * scene.bearing.outer_race_radius_m

    def angle(self, scene, t, *, t_end=None):
        """The element centre's angle (the cage angle: it meets both races on that radius).

        Parameters
        ----------
        scene : Scene
            The case's scene.
        t : ndarray
            Times, s.
        t_end : float, optional
            End of the whole record, s (the slip process).

        Returns
        -------
        ndarray
            Angle, rad, shape of ``t``.
        """
        return cage_angle(scene, np.asarray(t, dtype=float), t_end=t_end)

    def passage_angles(self, scene, ld, n):
        """Every angle for both races (the element orbits with the cage).

        Parameters
        ----------
        scene : Scene
            The case's scene.
        ld : LoadDistribution
            The load law.
        n : int
            Samples per race.

        Returns
        -------
        dict
            ``{"inner": angles, "outer": angles}``.
        """
        psi = TWO_PI * np.arange(n) / n
        return {"inner": psi, "outer": psi}

    def signals(self, scene, tables, ld, t, *, t_end=None, use_numba=True):
        """Both contacts' tables combined (module docstring).

        Parameters
        ----------
        scene : Scene
            The case's scene.
        tables : mapping
            ``{"inner": PressureTable, "outer": PressureTable}``.
        ld : LoadDistribution
            The load law.
        t : ndarray
            Times, s.
        t_end : float, optional
            End of the whole record, s.
        use_numba : bool, default True
            Use the numba kernels.

        Returns
        -------
        dict of str to ndarray
            Every signal (``p_max`` the larger, the others summed).
        """
        wandering = scene.defect.spin_axis == "wandering"
        kin = rolling_element_kinematics(scene, cage_angle(scene, t, t_end=t_end),
                                         redraw=not wandering or spin_is_free(ld))
        Qi = ld.load_at(kin["psi"], "inner")
        # the outer contact carries the centrifugal force too (equal to Qi without it)
        Q = ld.load_at(kin["psi"], "outer") if ld.centrifugal > 0 else Qi
        xi_, xo_ = kin["offset_inner"], kin["offset_outer"]
        if wandering:
            xi_ = np.where(on_track(scene, "inner", Qi, kin["track_offset"]), xi_,
                           OFF_TRACK_OFFSET_M)
            xo_ = np.where(on_track(scene, "outer", Q, kin["track_offset"]), xo_,
                           OFF_TRACK_OFFSET_M)
        ci = contact_signals(tables["inner"], Qi, xi_, use_numba)
        co = contact_signals(tables["outer"], Q, xo_, use_numba)
        removed = ci["removed_force"] + co["removed_force"]
        xo, xi = kin["offset_outer"], kin["offset_inner"]
        return {"p_max": np.maximum(ci["p_max"], co["p_max"]),
                "p_max_defect": ci["p_max_defect"] + co["p_max_defect"],
                "removed_force": removed, "contact_force": Q - removed,
                "approach": ci["approach"] + co["approach"],
                "approach_change": ci["approach_change"] + co["approach_change"],
                "contact_area": ci["contact_area"] + co["contact_area"],
                "roller_load": Q, "defect_offset": np.where(np.abs(xo) <= np.abs(xi), xo, xi)}


ROLLING_ELEMENT = register_location(RollingElement())
