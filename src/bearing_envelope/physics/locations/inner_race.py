"""The inner race: the defect turns with the shaft (the study's location).

**Kinematics.** The inner ring (and the defect on it) turns at the shaft rate ``f_r``; the
defect's angle from the load direction is ``theta_d = 2 pi f_r t``. The cage turns at ``f_c``;
roller ``j`` sits at ``theta_c + 2 pi j / Z``. The defect meets a roller whenever the relative
angle ``theta_d - theta_c`` crosses a multiple of ``2 pi / Z``, i.e. at ``Z (f_r - f_c) = BPFI``.
The **BPFI override** is realised through the implied cage rate ``f_c = f_r - BPFI / Z``: event
spacing is exactly ``1/BPFI`` and the load-zone modulation of the defect stays at ``f_r``.
Offset of the defect from the nearest roller's contact centre: ``x = R_i wrap(theta_d -
theta_c)`` (``wrap`` into ``[-pi/Z, pi/Z)``, ``R_i`` the raceway radius at the contact).

**Roller load** at the defect: the load-zone law ``Q(psi)`` at the defect's angle ``psi =
theta_d`` (``smooth``: the roller centred on the defect has this load at the event; the
no-defect signal stays free of a spurious BPFI-rate step) or at the angle of the roller over the
defect (``discrete``). **Exposure**: the defect passes elements at every angle (uniformly over
whole revolutions). **Table**: up to the largest element load ``Q_max`` from the default first
node (loads below it scaled); every window row solved.
"""

from __future__ import annotations

import math

import numpy as np

from ..kernels import HAVE_NUMBA, synth_kernel
from .base import FaultLocation, TWO_PI, cage_angle, register_location

__all__ = ["InnerRace", "INNER_RACE", "kinematics", "synthesize", "synthesize_numpy"]


def kinematics(scene, t: np.ndarray, *, t_end: float | None = None) -> dict[str, np.ndarray]:
    """Shaft and cage angles, defect offset and roller index at times ``t`` (s).

    Parameters
    ----------
    scene : Scene
        The case's scene.
    t : ndarray
        Times, s, shape ``(n,)``.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it (the slip process).

    Returns
    -------
    dict of str to ndarray
        ``theta_shaft`` (rad, the defect's angle from the load direction), ``theta_cage``
        (rad), ``offset`` (m), ``roller`` (int64, the nearest roller) and ``theta_roller``
        (rad, that roller's angle); each of shape ``(n,)``.
    """
    b = scene.bearing
    z = b.rollers_per_row
    theta_d = 2.0 * np.pi * scene.operation.shaft_rate_hz * t
    theta_c = cage_angle(scene, t, t_end=t_end)
    pitch = 2.0 * np.pi / z
    rel = theta_d - theta_c
    k = np.floor((rel + 0.5 * pitch) / pitch)
    wrapped = rel - k * pitch
    return {"theta_shaft": theta_d, "theta_cage": theta_c,
            "offset": b.inner_race_radius_m * wrapped, "roller": np.mod(k, z).astype(np.int64),
            "theta_roller": theta_d - wrapped}


def _law_params(ld):
    return (ld.stiffness, ld.delta_r, ld.clearance, math.cos(ld.contact_angle_rad), ld.exponent)


def synthesize_numpy(scene, table, ld, t: np.ndarray, *, t_end: float | None = None):
    """Per-sample synthesis, numpy version: ``(p_max, p_max_defect, roller_load, offset)``.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    table : PressureTable
        The inner-race contact table.
    ld : LoadDistribution
        The load-zone law.
    t : ndarray
        Times, s, shape ``(n,)``.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it.

    Returns
    -------
    tuple of ndarray
        ``p_max`` (Pa), ``p_max_defect`` (Pa), ``roller_load`` (N), ``offset`` (m); each of
        shape ``(n,)``.
    """
    kin = kinematics(scene, t, t_end=t_end)
    psi = kin["theta_roller"] if scene.load.roller_load == "discrete" else kin["theta_shaft"]
    Q = ld.load_at(psi)
    P, Pd = table.evaluate(Q, kin["offset"])
    return P, Pd, Q, kin["offset"]


def synthesize(scene, table, ld, t: np.ndarray, *, t_end: float | None = None):
    """Per-sample synthesis with the numba kernel (falls back to numpy without numba); the
    pressures capped at ``table.p_cap`` when set.

    Parameters
    ----------
    scene : Scene
        The case's scene.
    table : PressureTable
        The inner-race contact table.
    ld : LoadDistribution
        The load-zone law.
    t : ndarray
        Times, s, shape ``(n,)``.
    t_end : float, optional
        End of the whole record, s, when ``t`` is one block of it.

    Returns
    -------
    tuple of ndarray
        ``p_max`` (Pa), ``p_max_defect`` (Pa), ``roller_load`` (N), ``offset`` (m); each of
        shape ``(n,)``.
    """
    if not HAVE_NUMBA:  # pragma: no cover
        return synthesize_numpy(scene, table, ld, t, t_end=t_end)
    t = np.ascontiguousarray(t, dtype=float)
    theta_c = np.ascontiguousarray(cage_angle(scene, t, t_end=t_end))
    n = t.size
    P, Pd, Q, X = (np.empty(n) for _ in range(4))
    K, dr, c, ca, ex = _law_params(ld)
    synth_kernel(t, theta_c, scene.operation.shaft_rate_hz, scene.bearing.rollers_per_row,
                  scene.bearing.inner_race_radius_m, K, dr, c, ca, ex,
                  scene.load.roller_load == "discrete", *table.args(), P, Pd, Q, X)
    if table.p_cap is not None:
        np.minimum(P, table.p_cap, out=P)
        np.minimum(Pd, table.p_cap, out=Pd)
    return P, Pd, Q, X


class InnerRace(FaultLocation):
    """The inner race (module docstring): BPFI events with shaft-rate sidebands."""

    name = "inner_race"
    code = "ir"
    body = "inner ring"
    races = ("inner",)
    contact_race = "inner"
    family = "bpfi"
    sideband = "fr"
    solves_every_row = True

    def thickness_m(self, bearing) -> float:
        """``(D - d)/2 - bore/2`` (groove bottom to bore), m.

        Parameters
        ----------
        bearing : Bearing
            The bearing.

        Returns
        -------
        float
            Thickness, m.
        """
        return 1e-3 * (0.5 * (bearing.pitch_diameter_mm - bearing.roller_diameter_mm)
                       - 0.5 * bearing.bore_mm)

    def room_m(self, bearing) -> tuple[float, str]:
        """Half the element spacing on the inner raceway.

        Parameters
        ----------
        bearing : Bearing
            The bearing.

        Returns
        -------
        tuple of (float, str)
            Room (m) and its description.
        """
        return (0.5 * TWO_PI * bearing.race_radius_m("inner") / bearing.rollers_per_row,
                "half the element spacing on the inner raceway")

    def speed_m_s(self, scene) -> float:
        """``2 pi (f_r - f_c) R_i`` (4.24 m/s in the default scene).

        Parameters
        ----------
        scene : Scene
            The case's scene.

        Returns
        -------
        float
            m/s.
        """
        return 2.0 * math.pi * (scene.operation.shaft_rate_hz - scene.cage_rate_hz) * \
            scene.bearing.inner_race_radius_m

    def angle(self, scene, t, *, t_end=None):
        """The defect's own angle, ``2 pi f_r t`` (it turns with the shaft).

        Parameters
        ----------
        scene : Scene
            The case's scene.
        t : ndarray
            Times, s.
        t_end : float, optional
            End of the whole record, s.

        Returns
        -------
        ndarray
            Angle, rad, shape of ``t``.
        """
        theta = kinematics(scene, np.atleast_1d(t), t_end=t_end)["theta_shaft"]
        return theta.reshape(np.shape(t))

    def fault_lines(self, rates):
        """``{"bpfi": BPFI}`` with the analysis's default sideband spacing (the shaft rate:
        the study's analysis).

        Parameters
        ----------
        rates : mapping of str to float
            The case's rates, Hz.

        Returns
        -------
        tuple
            ``({"bpfi": Hz}, None)``.
        """
        return {self.family: float(rates[self.family])}, None

    def passage_angles(self, scene, ld, n):
        """Every angle (the defect passes elements all round), ``n`` uniform samples from 0.

        Parameters
        ----------
        scene : Scene
            The case's scene.
        ld : LoadDistribution
            The load law.
        n : int
            Samples.

        Returns
        -------
        dict
            ``{"inner": angles}``.
        """
        return {"inner": TWO_PI * np.arange(n) / n}

    def table_loads(self, scene, ld, exposure):
        """Up to ``Q_max`` (the most loaded element) from the default first node.

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
            ``{"inner": (Q_max, None)}``.
        """
        return {"inner": (ld.q_max, None)}

    def signals(self, scene, tables, ld, t, *, t_end=None, use_numba=True):
        """Synthesis from the inner table (numba kernel; numpy for a centrifugal load law).

        Parameters
        ----------
        scene : Scene
            The case's scene.
        tables : mapping
            ``{"inner": PressureTable}``.
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
            ``p_max``, ``p_max_defect`` (Pa), ``roller_load`` (N), ``defect_offset`` (m) and
            the integral signals of :meth:`~..table.PressureTable.evaluate_integrals`
            (``removed_force``, ``contact_force`` in N, ``approach``, ``approach_change`` in
            m, ``contact_area`` in m^2), each of shape ``(n,)``.
        """
        table = tables["inner"]
        # the numba kernel has the closed-form load law; the centrifugal law is read by numpy
        fn = synthesize if use_numba and ld.centrifugal == 0 else synthesize_numpy
        P, Pd, Q, X = fn(scene, table, ld, t, t_end=t_end)
        out = {"p_max": P, "p_max_defect": Pd, "roller_load": Q, "defect_offset": X}
        out.update(table.evaluate_integrals(Q, X, use_numba=use_numba))
        return out


INNER_RACE = register_location(InnerRace())
