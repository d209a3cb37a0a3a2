"""The outer race: the defect is fixed in the load frame (issue 23).

The outer ring is fixed; the defect sits at ``phi_d`` = ``defect.position_deg`` from the load
direction (0 = centre of the load zone). The cage turns at ``f_c`` (the FTF, or ``f_r -
BPFI/Z`` with the BPFI override); element ``j`` sits at ``theta_c + 2 pi j / Z``, so an element
passes the defect at ``Z f_c`` = BPFO. Offset of the defect from the nearest element's contact
centre along the outer raceway: ``x = R_o wrap(phi_d - theta_c)`` (``wrap`` into ``[-pi/Z,
pi/Z)``, ``R_o = (D + d cos alpha)/2``). Load: the load-zone law at ``phi_d`` (``smooth``:
constant under a steady load, zero outside the load zone) or at the passing element's angle
(``discrete``). The contact table is that of the outer contact: the concave outer raceway in
the gap (``1/R_x = 2/d - 1/R_o``; the outer profile radius or groove conformity across rolling).

**Exposure.** The pit meets an element's load only while the element is over it: at
``phi_d`` (``smooth``), or (``discrete``) while the pit lies inside the passing element's
contact, ``|x| <= a_H(Q_max) + w_x/2``: angles ``phi_d +- (a_H + w_x/2)/R_o``, not the whole
``phi_d +- pi/Z`` (issue 43: elements away from the pit carry loads the pit never meets). The
table still reaches the largest load read over ``phi_d +- pi/Z`` (the healthy contacts between
passages).
"""

from __future__ import annotations

import math

import numpy as np

from ..exposure import PASSAGE_SAMPLES
from ..geometry import hertz_estimate
from .base import FaultLocation, TWO_PI, cage_angle, contact_signals, register_location, wrap

__all__ = ["OuterRace", "OUTER_RACE", "outer_race_kinematics"]


def outer_race_kinematics(scene, theta_c: np.ndarray) -> dict[str, np.ndarray]:
    """Offset (m) of an outer-race defect from the nearest element, and the angle (rad) of the
    load law: the defect's (``smooth``) or the passing element's (``discrete``).

    Parameters
    ----------
    scene : Scene
        An outer-race defect.
    theta_c : ndarray
        Cage angle (rad) at each instant (:func:`~.base.cage_angle`).

    Returns
    -------
    dict of str to ndarray
        ``offset`` (m) and ``psi`` (rad), shape of ``theta_c``.
    """
    b = scene.bearing
    phi_d = math.radians(scene.defect.position_deg)
    wrapped = wrap(phi_d - theta_c, TWO_PI / b.rollers_per_row)
    psi = phi_d - wrapped if scene.load.roller_load == "discrete" else np.full(theta_c.shape, phi_d)
    return {"offset": b.outer_race_radius_m * wrapped, "psi": psi}


class OuterRace(FaultLocation):
    """The outer race (module docstring): BPFO events; fr sidebands searched as a check."""

    name = "outer_race"
    code = "or"
    body = "outer ring"
    races = ("outer",)
    contact_race = "outer"
    family = "bpfo"
    sideband = "fr"
    positioned = True

    def thickness_m(self, bearing) -> float:
        """``OD/2 - (D + d)/2``, m.

        Parameters
        ----------
        bearing : Bearing
            The bearing.

        Returns
        -------
        float
            Thickness, m.
        """
        return 1e-3 * (0.5 * bearing.outside_diameter_mm
                       - 0.5 * (bearing.pitch_diameter_mm + bearing.roller_diameter_mm))

    def room_m(self, bearing) -> tuple[float, str]:
        """Half the element spacing on the outer raceway.

        Parameters
        ----------
        bearing : Bearing
            The bearing.

        Returns
        -------
        tuple of (float, str)
            Room (m) and its description.
        """
        return (0.5 * TWO_PI * bearing.race_radius_m("outer") / bearing.rollers_per_row,
                "half the element spacing on the outer raceway")

    def where(self, scene) -> str:
        """``outer_race at <position_deg> deg``.

        Parameters
        ----------
        scene : Scene
            The case's scene.

        Returns
        -------
        str
            The location and its angle.
        """
        return f"{self.name} at {scene.defect.position_deg:g} deg"

    def speed_m_s(self, scene) -> float:
        """``2 pi f_c R_o``.

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
        """The defect's fixed position.

        Parameters
        ----------
        scene : Scene
            The case's scene.
        t : ndarray
            Times, s.
        t_end : float, optional
            Unused (no slip process enters).

        Returns
        -------
        ndarray
            ``position_deg`` in rad, shape of ``t``.
        """
        return np.full(np.shape(t), math.radians(scene.defect.position_deg))

    def _reach(self, scene, ld) -> float:
        """Half-angle (rad) about ``phi_d`` over which the pit lies inside a passing element's
        contact: ``(a_H(Q_max outer) + w_x/2) / R_o``."""
        q = ld.q_max_outer
        a = hertz_estimate(scene.for_race("outer"), q).a if q > 0 else 0.0
        ex = scene.defect.extent_x_m if scene.defect.active else 0.0
        return min((a + 0.5 * ex) / scene.bearing.outer_race_radius_m,
                   math.pi / scene.bearing.rollers_per_row)

    def passage_angles(self, scene, ld, n):
        """``phi_d`` (``smooth``) or ``phi_d +- reach`` (``discrete``; module docstring).

        Parameters
        ----------
        scene : Scene
            The case's scene.
        ld : LoadDistribution
            The load law.
        n : int
            Samples over the discrete range.

        Returns
        -------
        dict
            ``{"outer": angles}``.
        """
        phi = math.radians(scene.defect.position_deg)
        if scene.load.roller_load == "discrete":
            half = self._reach(scene, ld)
            return {"outer": phi + np.linspace(-half, half, n)}
        return {"outer": np.full(1, phi)}

    def table_loads(self, scene, ld, exposure):
        """From the loads the pit meets; ``discrete``: up to the largest element load read
        between passages (over ``phi_d +- pi/Z``).

        Parameters
        ----------
        scene : Scene
            The case's scene.
        ld : LoadDistribution
            The load law.
        exposure : dict
            The case's exposure.

        Returns
        -------
        dict
            ``{"outer": (q_max, q_min)}``.
        """
        q_max, q_min = super().table_loads(scene, ld, exposure)["outer"]
        if scene.load.roller_load == "discrete":
            half = math.pi / scene.bearing.rollers_per_row
            phi = math.radians(scene.defect.position_deg)
            q_max = max(q_max, float(np.max(ld.load_at(
                phi + np.linspace(-half, half, PASSAGE_SAMPLES), "outer"))))
        return {"outer": (q_max, q_min)}

    def signals(self, scene, tables, ld, t, *, t_end=None, use_numba=True):
        """The outer table read at the load law's angle and the nearest element's offset.

        Parameters
        ----------
        scene : Scene
            The case's scene.
        tables : mapping
            ``{"outer": PressureTable}``.
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
            Signal name -> values (SI units: pressures in Pa, loads in N, offsets in m), each
            of shape ``(n,)``: the contact signals of the outer-race table
            (:func:`~.base.contact_signals`).
        """
        kin = outer_race_kinematics(scene, cage_angle(scene, t, t_end=t_end))
        Q = ld.load_at(kin["psi"], "outer")
        out = contact_signals(tables["outer"], Q, kin["offset"], use_numba)
        out.update(roller_load=Q, defect_offset=kin["offset"])
        return out


OUTER_RACE = register_location(OuterRace())
