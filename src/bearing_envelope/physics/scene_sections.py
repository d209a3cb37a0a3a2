"""The scene's sections: the defaults of a scene and one frozen dataclass per section.

:data:`DEFAULT_SCENE` (the source study's scene) is the one home of every scene default; each
dataclass's field defaults read it. The dataclasses keep the mapping's units (the names carry
them); properties ending in ``_m``/``_pa``/``_n`` give SI values. They are built and checked by
:mod:`bearing_envelope.physics.scene_build` and joined by :class:`bearing_envelope.physics.scene.Scene`
(the mapping layout is documented there and in ``docs/scene.md``).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from typing import Any

from .catalogue import bearing_values, operation_values
from .locations import FaultLocation, get_location

__all__ = [
    "EndRelief", "Bearing", "MaterialProps", "Material", "Acquisition", "Operation", "Load",
    "Defect", "ACQUISITION_MODES", "ROLLER_LOAD_MODELS", "BEARING_STEEL_HARDNESS_GPA",
    "DEFAULT_SCENE", "default_scene_mapping", "STUDY_DESIGNATION", "STEEL_E_GPA", "STEEL_NU",
]


#: The bearing of the source study (Brusa et al. 2021): its catalogue entry
#: (``data/bearings.yaml``) is the default scene's bearing and carries the study's stated BPFI
#: (``operation.bpfi_override_hz``, 231.9 Hz; geometry alone gives 194.2 Hz).
STUDY_DESIGNATION = "FAG 534176"

#: ``scene.bearing`` keys a catalogue entry need not give (their default when it does not).
_BEARING_EXTRA = {
    "pitch_diameter_mm": None,
    "profile_file": None,
    "designation": None,
    "kind": "roller",
    "outer_raceway_profile_radius_mm": None,
    "inner_groove_conformity": None,
    "outer_groove_conformity": None,
}

#: Young's modulus (GPa) and Poisson ratio of through-hardened bearing steel (AISI 52100 /
#: 100Cr6): both bodies' material when a config names none.
STEEL_E_GPA = 210.0
STEEL_NU = 0.3

#: The default scene: the study's bearing from its catalogue entry (``designation`` null means
#: this bearing) and the defaults of every other section, written here only (the config schema
#: holds no scene default; ``tests/test_defaults.py``).
DEFAULT_SCENE: dict[str, Any] = {
    "bearing": {**_BEARING_EXTRA, **bearing_values(STUDY_DESIGNATION), "designation": None},
    "material": {
        "roller": {"E_GPa": STEEL_E_GPA, "nu": STEEL_NU},
        "race": {"E_GPa": STEEL_E_GPA, "nu": STEEL_NU},
        "hardness_GPa": None,
    },
    "operation": {
        "shaft_rate_hz": 15.8,
        **operation_values(STUDY_DESIGNATION),
        "fs_hz": 65000.0,
        "revolutions": 100.0,
        "cage_slip_percent": 0.0,
        "slip_seed": 0,
        "noise_snr_db": None,
        "noise_seed": 0,
        "acquisition": {"mode": "antialiased", "oversample": "auto"},
    },
    "load": {"mode": "bearing", "roller_load": "smooth", "centrifugal": False},
    "defect": {
        "length_um": 500.0,
        "width_um": None,
        "shape": "flat",
        "edge_radius_um": 20.0,
        "axial_position_mm": 0.0,
        "orientation": "axial",
        "location": "inner_race",
        "position_deg": 0.0,
        "profile_file": None,
        "spin_axis": "fixed",
        "spin_seed": 0,
    },
    # physics/dynamics_option.py; structure null: its STRUCTURE_DEFAULTS
    "dynamics": {"model": "quasi_static", "structure": None},
}


def default_scene_mapping() -> dict[str, Any]:
    """A deep copy of :data:`DEFAULT_SCENE` (the source study's scene).

    Returns
    -------
    dict
        The ``scene:`` layout (``bearing``, ``material``, ``operation``, ``load``, ``defect``).
    """
    return copy.deepcopy(DEFAULT_SCENE)


@dataclass(frozen=True)
class EndRelief:
    """Roller end relief (how the roller profile drops near its ends).

    Attributes
    ----------
    kind : {"radius", "log"}
        ``radius``: a circular corner of radius ``radius_mm`` tangent to the crown at
        ``|y| = L/2 - radius_mm``; the drop grows as ``r - sqrt(r^2 - u^2)`` with ``u`` the
        distance into the corner and reaches ``r`` at the end ``|y| = L/2``.
        ``log``: a logarithmic drop over the last ``length_mm`` of each end,
        ``drop = -drop_um * ln(1 - (1 - 1/e) s^2)`` with ``s`` in [0, 1] the relative position in the
        relief zone, reaching ``drop_um`` at the end.
    radius_mm : float
        Corner radius (``kind = radius``), mm, 0 < r < L/2.
    drop_um : float
        Drop at the roller end (``kind = log``), um, > 0.
    length_mm : float
        Length of the logarithmic relief zone at each end (``kind = log``), mm, 0 < l < L/2.
    """

    kind: str
    radius_mm: float | None
    drop_um: float | None = None
    length_mm: float | None = None


@dataclass(frozen=True)
class Bearing:
    """Geometry of the bearing and of the modelled roller / inner-race contact.

    Attributes (mapping keys and units)
    -----------------------------------
    bore_mm, outside_diameter_mm : float
        Bore ``d_i`` and outside diameter ``D_o``, mm.
    roller_diameter_mm : float
        Roller (maximum) diameter ``d``, mm.
    rollers_per_row : int
        Rollers per row ``Z`` (>= 1).
    rows : int
        Number of rows (>= 1). In ``bearing`` load mode the radial load is shared equally.
    pitch_diameter_mm : float
        Pitch diameter ``D``, mm; ``None`` in the mapping means ``(bore + OD)/2``.
    contact_angle_deg : float
        Contact angle ``alpha``, degrees, in [0, 45] (:data:`MAX_CONTACT_ANGLE_DEG`).
    roller_crown_radius_mm : float
        Roller profile (crown) radius ``c_r`` (convex), mm.
    raceway_profile_radius_mm : float
        Inner-raceway profile radius ``c_i`` (concave), mm; must exceed ``c_r`` (the profiles
        must not cross). Axial equivalent radius ``R_y = 1/(1/c_r - 1/c_i)``.
    roller_length_mm : float
        Effective roller length ``L`` (contacting length including the end relief), mm.
    end_relief : EndRelief
        End relief of the roller.
    radial_clearance_um : float
        Radial internal (operating) clearance ``P_d``, um, >= 0 (load distribution).
    profile_file : str or None
        Two-column text/CSV file ``y_mm, deviation_um`` of the measured roller profile (drop from
        the roller's generatrix at its centre, positive = material removed), replacing the
        analytic crown and end relief; the raceway keeps its analytic radius ``c_i``.
    designation : str or None
        Catalogue entry the values came from (:mod:`bearing_envelope.physics.catalogue`), or None.
    kind : {"roller", "ball"}
        ``roller``: line contact with crown and end relief, load exponent 10/9; ``ball``: point
        contact in a groove of conformity ``f`` (``R_y`` from ``f``, no end relief; the axial
        extent ``roller_length_mm`` is the width of the groove the ball can touch), load exponent
        3/2.
    outer_raceway_profile_radius_mm : float or None
        Rollers: concave outer-raceway profile radius ``c_o`` (mm), > ``c_r``; None = ``c_i``
        (for the FAG 534176 the outer sphere radius from geometry, ``(D + d cos a)/(2 cos a)`` =
        83.08 mm, equals ``c_i`` = 83.1 mm to 0.03 %).
    inner_groove_conformity, outer_groove_conformity : float or None
        Balls: groove radius / ball diameter ``f_i``, ``f_o`` (> 0.5); None for rollers.
    """

    bore_mm: float
    outside_diameter_mm: float
    roller_diameter_mm: float
    rollers_per_row: int
    rows: int
    pitch_diameter_mm: float
    contact_angle_deg: float
    roller_crown_radius_mm: float
    raceway_profile_radius_mm: float
    roller_length_mm: float
    end_relief: EndRelief
    radial_clearance_um: float
    profile_file: str | None
    designation: str | None = None
    kind: str = _BEARING_EXTRA["kind"]
    outer_raceway_profile_radius_mm: float | None = None
    inner_groove_conformity: float | None = None
    outer_groove_conformity: float | None = None
    #: The race of the modelled contact (``inner`` | ``outer``): which curvature :attr:`rx_m`
    #: and :attr:`ry_m` give. Not a config key: set from ``defect.location`` (outer race) or
    #: per contact for a rolling-element defect (:meth:`Scene.for_race`).
    contact_race: str = "inner"

    # SI helpers -------------------------------------------------------------------------
    @property
    def roller_radius_m(self) -> float:
        """Roller radius ``d/2`` (m)."""
        return 0.5e-3 * self.roller_diameter_mm

    @property
    def pitch_diameter_m(self) -> float:
        """Pitch diameter ``D`` (m)."""
        return 1e-3 * self.pitch_diameter_mm

    @property
    def contact_angle_rad(self) -> float:
        """Contact angle (rad): ``contact_angle_deg``."""
        return math.radians(self.contact_angle_deg)

    @property
    def inner_race_radius_m(self) -> float:
        """Inner-raceway radius at the contact in the rolling plane, ``(D - d cos(alpha))/2`` (m).

        Harris & Kotzalas (2007), section 2: the inner-raceway contact radius of an angular
        contact roller; 64.0 mm for the default scene (design.md hand numbers).
        """
        return 0.5e-3 * (self.pitch_diameter_mm
                         - self.roller_diameter_mm * math.cos(self.contact_angle_rad))

    @property
    def outer_race_radius_m(self) -> float:
        """Outer-raceway radius at the contact in the rolling plane, ``(D + d cos(alpha))/2`` (m)."""
        return 0.5e-3 * (self.pitch_diameter_mm
                         + self.roller_diameter_mm * math.cos(self.contact_angle_rad))

    def race_radius_m(self, race: str) -> float:
        """Kinematic raceway radius (m) of ``race`` (``inner`` | ``outer``): arc length per radian
        of the contact point along the race.

        Parameters
        ----------
        race : {"inner", "outer"}
            The raceway.

        Returns
        -------
        float
            ``inner_race_radius_m`` or ``outer_race_radius_m`` (anything but ``inner``: outer).
        """
        return self.inner_race_radius_m if race == "inner" else self.outer_race_radius_m

    def rx_for(self, race: str) -> float:
        """Equivalent radius across rolling of the ``race`` contact (m).

        ``1/R_x = 2/d + 1/R_i`` (inner, convex race) or ``2/d - 1/R_o`` (outer, concave race).
        Rollers: ``R_i, R_o`` = :meth:`race_radius_m` (Harris & Kotzalas 2007, ch. 2; unchanged
        for the inner race). Balls: the race radius along the contact normal,
        ``(D -+ d cos(alpha)) / (2 cos(alpha))`` (Harris & Kotzalas 2007, eqs. 2.27-2.33;
        design.md section 5).

        Parameters
        ----------
        race : {"inner", "outer"}
            The raceway.

        Returns
        -------
        float
            ``R_x``, m.
        """
        r = self.roller_radius_m
        rr = self.race_radius_m(race)
        if self.kind == "ball":
            rr = rr / math.cos(self.contact_angle_rad)
        return 1.0 / (1.0 / r + (1.0 if race == "inner" else -1.0) / rr)

    def ry_for(self, race: str) -> float:
        """Axial equivalent radius of the ``race`` contact (m); inf for equal profiles.

        Rollers: ``1/R_y = 1/c_r - 1/c_race`` (crown against the concave raceway generatrix;
        ``c_o`` = ``outer_raceway_profile_radius_mm``, null = ``c_i``). Balls:
        ``1/R_y = 1/r - 1/(f d)`` with the groove conformity ``f`` of that race.

        Parameters
        ----------
        race : {"inner", "outer"}
            The raceway.

        Returns
        -------
        float
            ``R_y``, m; ``math.inf`` when the curvature sum is <= 0.
        """
        if self.kind == "ball":
            f = self.inner_groove_conformity if race == "inner" else self.outer_groove_conformity
            k = 1.0 / self.roller_radius_m - 1.0 / (1e-3 * f * self.roller_diameter_mm)
        else:
            c = self.raceway_profile_radius_mm if race == "inner" or \
                self.outer_raceway_profile_radius_mm is None else self.outer_raceway_profile_radius_mm
            k = 1.0 / (1e-3 * self.roller_crown_radius_mm) - 1.0 / (1e-3 * c)
        return math.inf if k <= 0 else 1.0 / k

    @property
    def rx_m(self) -> float:
        """Equivalent radius in the rolling direction of the modelled contact (m):
        :meth:`rx_for` of :attr:`contact_race` (inner race: ``1/R_x = 2/d + 1/R_i``)."""
        return self.rx_for(self.contact_race)

    @property
    def ry_m(self) -> float:
        """Axial equivalent radius of the modelled contact (m): :meth:`ry_for` of
        :attr:`contact_race` (inner roller race: ``1/R_y = 1/c_r - 1/c_i``)."""
        return self.ry_for(self.contact_race)

    def race_thickness_m(self, location: str) -> float:
        """Material under a raceway (m): the deepest a pit can be.

        ``inner_race``: ``(D - d)/2 - bore/2`` (groove bottom to bore), ``outer_race``:
        ``OD/2 - (D + d)/2``, ``rolling_element``: ``d/2``. A simple bound (the groove bottom
        of a ball race; the roller raceway of a roller bearing).

        Parameters
        ----------
        location : str or FaultLocation
            The defect location (:func:`~bearing_envelope.physics.locations.get_location`).

        Returns
        -------
        float
            Thickness, m (:meth:`FaultLocation.thickness_m`).
        """
        return get_location(location).thickness_m(self)

    @property
    def half_length_m(self) -> float:
        """``L/2`` (m)."""
        return 0.5e-3 * self.roller_length_mm


@dataclass(frozen=True)
class MaterialProps:
    """Young's modulus ``E_GPa`` (GPa) and Poisson ratio ``nu`` of one body."""

    E_GPa: float = STEEL_E_GPA
    nu: float = STEEL_NU


#: Indentation hardness of through-hardened bearing steel (AISI 52100 / 100Cr6, ~62 HRC): the
#: Vickers hardness HV 10 = 750 kgf/mm^2 (ASTM E140: 61 HRC ~ 720 HV, 62 HRC ~ 746 HV) is
#: HV * g = 7.36 GPa, the mean pressure under a Vickers indenter. An elastic-perfectly-plastic
#: surface caps the contact pressure at it (``material.hardness_GPa``). ISO 76's 4.0 GPa (the
#: static load rating's contact stress) is a design limit, not a hardness. See docs/plasticity.md.
BEARING_STEEL_HARDNESS_GPA = 7.36


@dataclass(frozen=True)
class Material:
    """Materials of the roller and the (inner) race, and the surface hardness.

    ``hardness_GPa`` (GPa, > 0, or None = elastic): indentation hardness ``H`` of the
    elastic-perfectly-plastic surface, the bound ``p <= H`` of every contact solve
    (:func:`bearing_envelope.contact.solve_contact`, ``hardness``);
    :data:`BEARING_STEEL_HARDNESS_GPA` for through-hardened bearing steel.
    """

    roller: MaterialProps
    race: MaterialProps
    hardness_GPa: float | None = None

    @property
    def hardness_pa(self) -> float | None:
        """The pressure bound ``H`` (Pa), or None (elastic)."""
        return None if self.hardness_GPa is None else self.hardness_GPa * 1e9

    @property
    def e_star_pa(self) -> float:
        """Composite modulus ``1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2`` (Pa); 115.4 GPa for steel."""
        r, s = self.roller, self.race
        return 1.0 / ((1 - r.nu ** 2) / (r.E_GPa * 1e9) + (1 - s.nu ** 2) / (s.E_GPa * 1e9))


#: ``operation.acquisition.mode`` values (see :class:`Acquisition`).
ACQUISITION_MODES = ("antialiased", "point")

#: ``load.roller_load`` values (see :class:`Load`).
ROLLER_LOAD_MODELS = ("smooth", "discrete")


@dataclass(frozen=True)
class Acquisition:
    """How the history is sampled at ``fs`` (:func:`bearing_envelope.physics.history.acquire`).

    Attributes
    ----------
    mode : str
        ``antialiased`` (default): the history is evaluated at ``oversample * fs``, low-pass
        filtered (linear-phase FIR, pass band to 0.40 fs, >= 80 dB stop band from 0.50 fs =
        Nyquist) and decimated to ``fs`` with zero delay, as an acquisition chain with an
        anti-alias filter would. ``point``: the history is evaluated at the sample instants
        only (the source study's point sampling; features narrower than a sample alias).
    oversample : int or "auto"
        Internal rate factor ``N >= 1`` for ``antialiased``. ``auto``: the smallest ``N`` for
        which the defect moves no more than the table's offset-node spacing per internal sample
        (``N = ceil(v / (fs dx_node))``, ``v`` the defect's speed relative to the cage; 6-9 at
        ``standard``, 17-18 at ``paper``; :func:`bearing_envelope.physics.acquisition.auto_oversample`).
        Ignored for ``point``.
    """

    mode: str = DEFAULT_SCENE["operation"]["acquisition"]["mode"]
    oversample: int | str = DEFAULT_SCENE["operation"]["acquisition"]["oversample"]


@dataclass(frozen=True)
class Operation:
    """Operating and sampling conditions.

    Attributes
    ----------
    shaft_rate_hz : float
        Shaft (inner-ring) rotation rate ``f_r``, Hz.
    bpfi_override_hz : float or None
        BPFI to reproduce, Hz; ``None`` uses the geometric BPFI. The override is realised through
        the implied cage rate ``f_c = f_r - BPFI/Z`` (see :mod:`bearing_envelope.physics.history`).
    fs_hz : float
        Sampling rate, Hz; must be at least ``2 * 13 * BPFI`` (the analysis band 10-13 x BPFI
        below Nyquist).
    revolutions : float
        Duration in shaft revolutions (> 0); samples = ``round(revolutions / f_r * fs)``.
    cage_slip_percent : float
        Mean cage slip, percent of the cage rate, in [0, 50). 0 = pure rolling.
    slip_seed : int
        Seed of the random slip process.
    noise_snr_db : float or None
        Additive white Gaussian noise at this SNR (signal power = variance of the clean signal),
        dB; ``None`` = no noise.
    noise_seed : int
        Seed of the noise.
    acquisition : Acquisition
        Sampling of the history at ``fs``: anti-aliased (default) or point samples.
    """

    shaft_rate_hz: float
    bpfi_override_hz: float | None
    fs_hz: float
    revolutions: float
    cage_slip_percent: float
    slip_seed: int
    noise_snr_db: float | None
    noise_seed: int
    acquisition: Acquisition = Acquisition()


@dataclass(frozen=True)
class Load:
    """The load: ``value_N`` and ``mode``.

    ``bearing``: ``value_N`` is the radial load on the whole bearing, shared by the rows and the
    rollers (:mod:`bearing_envelope.physics.loads`). ``contact``: ``value_N`` is the force on the modelled
    contact when it sits at the centre of the load zone; the roller load elsewhere follows the same
    load-zone shape as in ``bearing`` mode.

    ``roller_load`` says which load the modelled contact carries at each instant: ``smooth``
    (default) the load-zone law at the defect's angle (continuous; no step at BPFI in a healthy
    race), ``discrete`` the load of the roller actually over the defect, at that roller's angle
    (steps as the defect passes from one roller to the next, half-way between them).

    ``centrifugal`` (default False): each element also presses on the outer race with its
    centrifugal force ``m omega_c^2 D/2`` (:func:`bearing_envelope.physics.loads.centrifugal_force`),
    so elements outside the radial load zone still load the outer race.
    """

    value_N: float
    mode: str = DEFAULT_SCENE["load"]["mode"]
    roller_load: str = DEFAULT_SCENE["load"]["roller_load"]
    centrifugal: bool = DEFAULT_SCENE["load"]["centrifugal"]

    @property
    def load_kN(self) -> float:
        """The load value (kN): ``value_N / 1000``."""
        return self.value_N / 1e3


@dataclass(frozen=True)
class Defect:
    """Defect on the inner raceway.

    Attributes
    ----------
    depth_um : float
        Depth ``h``, um; 0 means no defect.
    length_um : float
        Length ``l`` (500 um in the study), um: along the axis for ``orientation = axial``.
    width_um : float
        Width ``w`` (default ``2 h``), um: across the rolling direction's normal, i.e. along the
        rolling direction for ``orientation = axial``.
    shape : {"flat", "dent"}
        ``flat``: flat bottom at depth ``h`` with rims rounded to ``edge_radius_um``; ``dent``: a
        smooth cos^2 x cos^2 bump of depth ``h`` over the footprint.
    edge_radius_um : float
        Rim radius of the flat defect, um (>= 0; 0 = sharp, a pressure singularity).
    axial_position_mm : float
        Axial position of the defect centre from the roller centre, mm.
    orientation : {"axial", "circumferential"}
        ``axial``: ``l`` along the roller axis (y), ``w`` along rolling (x); ``circumferential``:
        swapped.
    location : {"inner_race", "outer_race", "rolling_element"}
        Where the defect is (:data:`DEFECT_LOCATIONS`; :mod:`bearing_envelope.physics.locations`).
    position_deg : float
        ``outer_race``: the defect's angle from the load direction (deg, in [0, 360); 0 = the
        centre of the load zone, CWRU's 6:00 under a downward load; 90 = 3:00, 180 = 12:00).
    profile_file : str or None
        Measured defect profile, two columns ``x_um, depth_um`` (depth across the defect along
        rolling, extruded over the length): replaces the analytic shape (``shape: profile``).
    spin_axis : {"fixed", "wandering"}
        ``rolling_element`` only. ``fixed``: the defect lies on the element's rolling track and
        meets a race every half spin turn. ``wandering``: the element's orientation about its
        centre is redrawn (uniform on the sphere, seeded) once per cage turn where it is least
        loaded (180 deg from the load direction) when its inner contact is unloaded there; an
        element loaded all round (a preload) keeps its first orientation, its spin axis held by
        the contacts; the defect meets a contact only while its
        axial distance from the track, ``(d/2) sin(latitude)``, is within the contact's axial
        semi-axis ``b(Q)`` (:func:`bearing_envelope.physics.locations.rolling_element_kinematics`).
    spin_seed : int
        Seed of the ``wandering`` orientations (>= 0).
    """

    depth_um: float
    length_um: float
    width_um: float
    shape: str
    edge_radius_um: float
    axial_position_mm: float
    orientation: str
    location: str = DEFAULT_SCENE["defect"]["location"]
    position_deg: float = DEFAULT_SCENE["defect"]["position_deg"]
    profile_file: str | None = None
    spin_axis: str = DEFAULT_SCENE["defect"]["spin_axis"]
    spin_seed: int = DEFAULT_SCENE["defect"]["spin_seed"]

    @property
    def extent_x_m(self) -> float:
        """Footprint size along the rolling direction ``x`` (m)."""
        return 1e-6 * (self.width_um if self.orientation == "axial" else self.length_um)

    @property
    def extent_y_m(self) -> float:
        """Footprint size along the axis ``y`` (m)."""
        return 1e-6 * (self.length_um if self.orientation == "axial" else self.width_um)

    @property
    def active(self) -> bool:
        """Whether there is a defect (depth > 0)."""
        return self.depth_um > 0.0

    @property
    def fault_location(self) -> FaultLocation:
        """The location object of :attr:`location` (:mod:`bearing_envelope.physics.locations`)."""
        return get_location(self.location)
