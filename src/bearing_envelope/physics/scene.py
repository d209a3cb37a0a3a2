"""The bearing scene: small validated, frozen dataclasses built from a plain mapping.

The mapping layout is the ``scene:`` section of the workflow's ``config.yaml`` (documented key by
key, with units, in ``docs/scene.md``)::

    bearing:
      bore_mm: 110.0                 # bore d_i
      outside_diameter_mm: 180.0     # outside diameter D_o
      roller_diameter_mm: 17.45      # roller (maximum) diameter d
      rollers_per_row: 22
      rows: 2
      pitch_diameter_mm: null        # null -> (bore + OD) / 2
      contact_angle_deg: 12.82
      roller_crown_radius_mm: 81.5   # c_r, convex roller profile radius
      raceway_profile_radius_mm: 83.1  # c_i, concave inner-raceway profile radius
      roller_length_mm: 34.0         # effective (contacting) roller length
      end_relief: {kind: radius, radius_mm: 1.0}   # or {kind: log, drop_um: 20, length_mm: 3}
      radial_clearance_um: 40.0      # radial internal (operating) clearance; < 0 = preload
      profile_file: null             # two-column file (y_mm, deviation_um) replacing the crown
    material:
      roller: {E_GPa: 210.0, nu: 0.3}
      race:   {E_GPa: 210.0, nu: 0.3}
      hardness_GPa: null             # null -> elastic; else the pressure bound H (GPa)
    operation:
      shaft_rate_hz: 15.8
      bpfi_override_hz: 231.9        # null -> geometric BPFI (194.2 Hz for the default)
      fs_hz: 65000.0
      revolutions: 100
      cage_slip_percent: 0.0
      slip_seed: 0
      noise_snr_db: null             # null -> no noise
      noise_seed: 0
      acquisition: {mode: antialiased, oversample: auto}   # or {mode: point}
    load:
      mode: bearing                  # bearing | contact
      roller_load: smooth            # smooth | discrete
      centrifugal: false             # true: each element pressed on the outer race by m w_c^2 D/2
    defect:
      length_um: 500.0
      width_um: null                 # null -> 2 x depth
      shape: flat                    # flat | dent
      edge_radius_um: 20.0
      axial_position_mm: 0.0
      orientation: axial             # axial | circumferential

Load value and defect depth are not part of the mapping: they are the sweep variables and come in
as ``Scene.from_mapping(mapping, load_kN=..., depth_um=...)``. Every check runs at construction,
so a bad scene fails before any contact solve with a :class:`ValueError` naming the dotted field,
the value and what is allowed. The dataclasses keep the mapping's units (the names carry them);
properties ending in ``_m``/``_pa``/``_n`` give SI values.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import os
from dataclasses import dataclass
from typing import Any, Mapping

from .dynamics_option import Dynamics, build_dynamics
from .catalogue import bearing_values, designations, operation_values, resolve_designation
from .geometry import defect_depth, read_defect_profile, read_profile
from .kinematics import FaultFrequencies, bearing_rates, fault_frequencies
from .locations import FaultLocation, get_location, location_names

__all__ = [
    "EndRelief", "Bearing", "MaterialProps", "Material", "Acquisition", "Operation", "Load",
    "Defect", "Scene", "ACQUISITION_MODES", "ROLLER_LOAD_MODELS", "BEARING_STEEL_HARDNESS_GPA",
    "DEFAULT_SCENE", "default_scene_mapping", "MAX_BAND_ORDER", "DEFECT_LOCATIONS", "DEFECT_SHAPES",
    "BEARING_KINDS", "DEFAULT_GROOVE_CONFORMITY", "STUDY_DESIGNATION", "STEEL_E_GPA", "STEEL_NU",
    "MAX_CONTACT_ANGLE_DEG", "WIDTH_PER_DEPTH", "default_width_um",
]

#: The analysis needs bands up to 13 x BPFI (the study's 10-13 x BPFI band); fs must exceed
#: twice that so the band lies below Nyquist.
MAX_BAND_ORDER = 13

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


# --------------------------------------------------------------------------------------------
# validation helpers


def _bad(field: str, value: Any, allowed: str) -> ValueError:
    return ValueError(f"scene.{field}: got {value!r}; allowed: {allowed}")


def _num(field: str, value: Any, *, lo: float | None = None, hi: float | None = None,
         lo_open: bool = False, hi_open: bool = False, allowed: str | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _bad(field, value, allowed or "a number")
    v = float(value)
    ok = math.isfinite(v)
    if ok and lo is not None:
        ok = v > lo if lo_open else v >= lo
    if ok and hi is not None:
        ok = v < hi if hi_open else v <= hi
    if not ok:
        if allowed is None:
            parts = []
            if lo is not None:
                parts.append(f"{'>' if lo_open else '>='} {lo:g}")
            if hi is not None:
                parts.append(f"{'<' if hi_open else '<='} {hi:g}")
            allowed = "a finite number " + " and ".join(parts)
        raise _bad(field, value, allowed)
    return v


def _int(field: str, value: Any, *, lo: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            (isinstance(value, float) and not value.is_integer()) or int(value) < lo:
        raise _bad(field, value, f"an integer >= {lo}")
    return int(value)


def _choice(field: str, value: Any, choices: tuple[str, ...]) -> str:
    if value not in choices:
        raise _bad(field, value, " | ".join(choices))
    return value


def _check_keys(prefix: str, mapping: Any, allowed: set[str], required: set[str] = frozenset()):
    if not isinstance(mapping, Mapping):
        raise ValueError(f"scene.{prefix}: got {mapping!r}; allowed: a mapping with keys "
                         f"{sorted(allowed)}")
    unknown = sorted(set(mapping) - allowed)
    if unknown:
        raise ValueError(f"scene.{prefix}.{unknown[0]}: unknown key (value {mapping[unknown[0]]!r});"
                         f" allowed keys of scene.{prefix}: {sorted(allowed)}")
    missing = sorted(required - set(mapping))
    if missing:
        raise ValueError(f"scene.{prefix}.{missing[0]}: missing; required keys of scene.{prefix}: "
                         f"{sorted(required)}")


# --------------------------------------------------------------------------------------------
# dataclasses


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
        ``standard``, 17-18 at ``paper``; :func:`bearing_envelope.physics.history.auto_oversample`).
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


@dataclass(frozen=True)
class Scene:
    """A complete scene: bearing, material, operation, load and defect."""

    bearing: Bearing
    material: Material
    operation: Operation
    load: Load
    defect: Defect
    dynamics: Dynamics      # which model simulates the case (physics/dynamics_option.py)

    # derived -----------------------------------------------------------------------------
    def frequencies(self) -> FaultFrequencies:
        """Geometric fault frequencies (:func:`bearing_envelope.physics.kinematics.fault_frequencies`).

        Returns
        -------
        FaultFrequencies
            At the scene's shaft rate, Hz (no BPFI override applied).
        """
        b = self.bearing
        return fault_frequencies(self.operation.shaft_rate_hz, b.rollers_per_row,
                                 b.roller_diameter_mm, b.pitch_diameter_mm, b.contact_angle_deg)

    @property
    def bpfi_hz(self) -> float:
        """The BPFI used by the time history: the override if given, else geometric (Hz)."""
        o = self.operation.bpfi_override_hz
        return float(o) if o is not None else self.frequencies().bpfi

    @property
    def cage_rate_hz(self) -> float:
        """Cage rate used by the time history: ``f_r - BPFI/Z`` (= FTF without override), Hz."""
        b = self.bearing   # the rates' one function (a stated BPFI sets the cage rate)
        return bearing_rates(self.operation.shaft_rate_hz, b.rollers_per_row, b.roller_diameter_mm,
                             b.pitch_diameter_mm, b.contact_angle_deg, bpfi=self.bpfi_hz)["ftf"]

    @property
    def defect_speed_m_s(self) -> float:
        """Speed (m/s) at which the defect sweeps through a contact: inner race
        ``2 pi (f_r - f_c) R_i`` (4.24 m/s in the default scene), outer race ``2 pi f_c R_o``,
        rolling element ``2 pi f_c R_o`` too (its surface rolls on the fixed outer race)."""
        return self.defect.fault_location.speed_m_s(self)

    @property
    def n_samples(self) -> int:
        """Samples of the record: ``revolutions / shaft_rate_hz x fs_hz``, rounded."""
        op = self.operation
        return int(round(op.revolutions / op.shaft_rate_hz * op.fs_hz))

    def to_mapping(self) -> dict[str, Any]:
        """The mapping layout (as in the config) plus ``load.value_kN`` and ``defect.depth_um``.

        Returns
        -------
        dict
            ``bearing``, ``material``, ``operation``, ``load``, ``defect``; ``defect.spin_*``
            only when wandering, ``load.centrifugal`` only when on.
        """
        b = dataclasses.asdict(self.bearing)
        b.pop("contact_race")
        b["end_relief"] = {k: v for k, v in b["end_relief"].items() if v is not None}
        d = dataclasses.asdict(self.defect)
        if d["spin_axis"] == "fixed":
            # only when wandering: the stored scene of every case without it is unchanged
            del d["spin_axis"], d["spin_seed"]
        return {
            "bearing": b,
            "material": dataclasses.asdict(self.material),
            "operation": dataclasses.asdict(self.operation),
            "load": {"mode": self.load.mode, "roller_load": self.load.roller_load,
                     "value_kN": self.load.load_kN,
                     # only when on: the stored scene of every case without it is unchanged
                     **({"centrifugal": True} if self.load.centrifugal else {})},
            "defect": d,
            # only when not the default: the stored scene of every quasi-static case is unchanged
            **({"dynamics": self.dynamics.to_mapping()} if self.dynamics.to_mapping()
               != DEFAULT_SCENE["dynamics"] else {}),
        }

    # construction ------------------------------------------------------------------------
    @classmethod
    def from_mapping(cls, mapping: Mapping[str, Any] | None = None, *, load_kN: float,
                     depth_um: float) -> "Scene":
        """Build and validate a scene.

        Parameters
        ----------
        mapping : mapping or None
            The ``scene:`` layout (module docstring / ``docs/scene.md``). Missing keys take the
            defaults of :data:`DEFAULT_SCENE` (the source study); unknown keys are errors.
            ``None`` = the default scene.
        load_kN : float
            Load value, kN (> 0): radial bearing load or contact force, see ``load.mode``.
        depth_um : float
            Defect depth, um (>= 0; 0 = no defect).

        Returns
        -------
        Scene
            The validated scene (SI units inside); an outer-race defect's contact is the outer
            race.

        Raises
        ------
        ValueError
            Naming the dotted field (``scene.defect.depth_um`` ...), the value and what is allowed.

        Examples
        --------
        The source study's scene at 250 kN with a 50 um deep defect, then another bearing from
        the catalogue:

        >>> from bearing_envelope.physics.scene import Scene
        >>> scene = Scene.from_mapping(None, load_kN=250.0, depth_um=50.0)
        >>> scene.operation.shaft_rate_hz, scene.operation.fs_hz, scene.defect.active
        (15.8, 65000.0, True)
        >>> ball = Scene.from_mapping({"bearing": {"designation": "SKF 6205-2RS"}},
        ...                           load_kN=2.0, depth_um=0.0)
        >>> ball.bearing.rollers_per_row, ball.defect.active
        (9, False)
        """
        m = _merge(_base_mapping(mapping), mapping or {}, "")
        bearing = _build_bearing(m["bearing"])
        material = _build_material(m["material"])
        load = _build_load(m["load"], load_kN)
        defect = _build_defect(m["defect"], depth_um, bearing)
        scene_freq = fault_frequencies(1.0, bearing.rollers_per_row, bearing.roller_diameter_mm,
                                       bearing.pitch_diameter_mm, bearing.contact_angle_deg)
        operation = _build_operation(m["operation"], scene_freq.bpfi, bearing.rollers_per_row)
        _check_override_bearing(operation, bearing)
        if defect.fault_location.contact_race != bearing.contact_race:
            bearing = dataclasses.replace(bearing, contact_race=defect.fault_location.contact_race)
        return cls(bearing, material, operation, load, defect, build_dynamics(m["dynamics"]))

    def for_race(self, race: str) -> "Scene":
        """This scene with the modelled contact on ``race`` (``inner`` | ``outer``): the
        curvature of that contact in the gap (:attr:`Bearing.rx_m`, :attr:`Bearing.ry_m`).

        Parameters
        ----------
        race : {"inner", "outer"}
            The contact to model.

        Returns
        -------
        Scene
            A copy with ``bearing.contact_race = race``.
        """
        return dataclasses.replace(self, bearing=dataclasses.replace(self.bearing, contact_race=race))

    @classmethod
    def default(cls, *, load_kN: float = 500.0, depth_um: float = 50.0) -> "Scene":
        """The source study's scene (:data:`DEFAULT_SCENE`).

        Parameters
        ----------
        load_kN : float, default 500
            Load value, kN.
        depth_um : float, default 50
            Defect depth, um.

        Returns
        -------
        Scene
            :meth:`from_mapping` of ``None``.
        """
        return cls.from_mapping(None, load_kN=load_kN, depth_um=depth_um)


def _check_override_bearing(operation: Operation, bearing: Bearing) -> None:
    """The BPFI override is the study's: refused on a scene naming another catalogue bearing
    (its fault frequencies then come from its geometry; ``designation: null`` is the study's)."""
    des = bearing.designation
    if operation.bpfi_override_hz is not None and des is not None and des != STUDY_DESIGNATION:
        raise _bad("operation.bpfi_override_hz", operation.bpfi_override_hz,
                   f"null for bearing.designation {des!r} (the override is the {STUDY_DESIGNATION}"
                   f" study's stated BPFI; other bearings take their fault frequencies from "
                   f"geometry)")


def _base_mapping(given: Mapping[str, Any] | None) -> dict[str, Any]:
    """The defaults a mapping is merged over: :data:`DEFAULT_SCENE`, with the bearing of the
    catalogue entry ``bearing.designation`` names (:mod:`bearing_envelope.physics.catalogue`)
    and the operation values travelling with it (the BPFI override: the study's 231.9 Hz for
    its entry, null, i.e. geometric, for an entry that states none)."""
    b = (given or {}).get("bearing") if isinstance(given, Mapping) else None
    des = b.get("designation") if isinstance(b, Mapping) else None
    if des is None:
        return DEFAULT_SCENE
    if not isinstance(des, str):
        raise _bad("bearing.designation", des, f"null or one of {list(designations())}")
    base = copy.deepcopy(DEFAULT_SCENE)
    base["bearing"].update(bearing_values(des))   # keys the entry lacks: the study's
    base["bearing"]["designation"] = des
    base["operation"].update(operation_values(des))
    return base


def _merge(default: Mapping[str, Any], given: Mapping[str, Any], prefix: str) -> dict[str, Any]:
    """Recursive merge of ``given`` over ``default``; unknown keys raise naming the dotted path."""
    name = prefix.rstrip(".") or "(root)"
    if not isinstance(given, Mapping):
        raise ValueError(f"scene.{name}: got {given!r}; allowed: a mapping with keys {sorted(default)}")
    out = copy.deepcopy(dict(default))
    for k, v in given.items():
        if k not in default:
            raise ValueError(f"scene.{prefix}{k}: unknown key (value {v!r}); allowed keys"
                             f"{' of scene.' + prefix.rstrip('.') if prefix else ''}: {sorted(default)}")
        if k == "end_relief":
            # the relief kind decides which keys exist: no merge with the default's keys
            out[k] = copy.deepcopy(v)
        elif isinstance(default[k], Mapping):
            out[k] = _merge(default[k], v, f"{prefix}{k}.")
        else:
            out[k] = v
    return out


def _build_bearing(m: Mapping[str, Any]) -> Bearing:
    p = "bearing."
    bore = _num(p + "bore_mm", m["bore_mm"], lo=0, lo_open=True)
    od = _num(p + "outside_diameter_mm", m["outside_diameter_mm"], lo=bore, lo_open=True,
              allowed=f"a number > bore_mm ({bore:g})")
    d = _num(p + "roller_diameter_mm", m["roller_diameter_mm"], lo=0, lo_open=True,
             hi=0.5 * (od - bore), hi_open=True,
             allowed=f"a number in (0, (OD - bore)/2 = {0.5 * (od - bore):g})")
    z = _int(p + "rollers_per_row", m["rollers_per_row"], lo=1)
    rows = _int(p + "rows", m["rows"], lo=1)
    pd = m["pitch_diameter_mm"]
    pd = 0.5 * (bore + od) if pd is None else _num(
        p + "pitch_diameter_mm", pd, lo=bore + d, hi=od - d,
        allowed=f"null or a number in [bore + d, OD - d] = [{bore + d:g}, {od - d:g}]")
    alpha = _num(p + "contact_angle_deg", m["contact_angle_deg"], lo=0, hi=MAX_CONTACT_ANGLE_DEG,
                 allowed=f"a finite angle in [0, {MAX_CONTACT_ANGLE_DEG:g}] deg (a radial bearing: "
                         f"the load distribution balances a radial load only)")
    if z * d >= math.pi * pd:
        raise _bad(p + "rollers_per_row", z,
                   f"rollers that fit on the pitch circle: Z * d < pi * D ({math.pi * pd / d:.1f})")
    cr = _num(p + "roller_crown_radius_mm", m["roller_crown_radius_mm"], lo=0, lo_open=True)
    ci = _num(p + "raceway_profile_radius_mm", m["raceway_profile_radius_mm"], lo=cr, lo_open=True,
              allowed=f"a number > roller_crown_radius_mm ({cr:g}) (profiles must not cross)")
    length = _num(p + "roller_length_mm", m["roller_length_mm"], lo=0, lo_open=True, hi=od,
                  allowed=f"a length > 0 and <= outside_diameter_mm ({od:g} mm)")
    relief = _build_relief(m["end_relief"], length)
    clearance = _num(p + "radial_clearance_um", m["radial_clearance_um"],
                     lo=-MAX_CLEARANCE_FRACTION * 1e3 * d, lo_open=True,
                     hi=MAX_CLEARANCE_FRACTION * 1e3 * d, hi_open=True,
                     allowed=f"an operating clearance within +-{MAX_CLEARANCE_FRACTION:.0%} of the "
                             f"rolling-element diameter (+-{MAX_CLEARANCE_FRACTION * 1e3 * d:g} um;"
                             f" negative = preload)")
    extra = _build_kind_fields(m, d, cr, length)
    pf = m["profile_file"]
    if pf is not None:
        if not isinstance(pf, (str, os.PathLike)):
            raise _bad(p + "profile_file", pf, "null or a path to a two-column file (y_mm, deviation_um)")
        pf = os.fspath(pf)
        try:
            _yp, dev = read_profile(pf)
        except (OSError, ValueError) as exc:
            raise _bad(p + "profile_file", pf, f"a readable two-column file (y_mm, deviation_um): {exc}")
        worst = max(abs(float(v)) for v in dev)
        if worst >= 0.5e-3 * d:
            raise _bad(p + "profile_file", pf, f"deviations smaller than the roller radius "
                       f"({500 * d:g} um; this file has {1e6 * worst:.4g} um)")
    return Bearing(bore, od, d, z, rows, pd, alpha, cr, ci, length, relief, clearance, pf, **extra)


#: Largest contact angle (deg) of the bearings the load distribution describes. It balances a
#: radial load alone (:func:`bearing_envelope.physics.loads.solve_row`), each element carrying
#: ``Q cos(alpha)`` of it: the ring's displacement grows as ``cos(alpha)^(-(n+1)/n)`` and has no
#: solution at 90 deg (at 89.99 deg the 6205 at 1 kN would need a displacement over 1 m). ISO 76 /
#: ISO 281 call a bearing radial up to 45 deg and a thrust bearing above, where the induced axial
#: load exceeds the radial one and a radial-only equilibrium no longer describes the bearing; up
#: to 45 deg the displacement is at most 2^((n+1)/(2n)) (1.8-1.9) times that at 0 deg.
MAX_CONTACT_ANGLE_DEG = 45.0


#: Largest radial clearance, as a fraction of the rolling-element diameter: ISO 5753 groups
#: reach about 1 % (C5 of a large bearing), 5 % is a loose bearing; a clearance near the ball
#: itself leaves one element carrying the load with no physical meaning.
MAX_CLEARANCE_FRACTION = 0.05


#: Groove conformity ``f = r_groove / d`` of a ball race when neither the config nor the
#: catalogue gives one: 0.52, typical of deep-groove ball bearings (0.515-0.53, Harris &
#: Kotzalas 2007, ch. 2) -- an assumption, stated in docs/scene.md.
DEFAULT_GROOVE_CONFORMITY = 0.52

#: ``scene.bearing.kind`` values.
BEARING_KINDS = ("roller", "ball")


def _build_kind_fields(m: Mapping[str, Any], d: float, cr: float, length: float) -> dict[str, Any]:
    """Designation, kind and the kind's own fields (roller: outer profile radius; ball: groove
    conformities, the groove width ``roller_length_mm < 2 f d``)."""
    p = "bearing."
    des = m["designation"]
    if des is not None and not isinstance(des, str):
        raise _bad(p + "designation", des, "null or a catalogue designation")
    if des is not None:   # an alias (6205, SKF 6205) names the entry as the catalogue writes it
        des = resolve_designation(des)
    kind = _choice(p + "kind", m["kind"], BEARING_KINDS)
    out: dict[str, Any] = {"designation": des, "kind": kind}
    co = m["outer_raceway_profile_radius_mm"]
    if kind == "roller":
        if co is not None:
            co = _num(p + "outer_raceway_profile_radius_mm", co, lo=cr, lo_open=True,
                      allowed=f"null or a number > roller_crown_radius_mm ({cr:g})")
        for k in ("inner_groove_conformity", "outer_groove_conformity"):
            if m[k] is not None:
                raise _bad(p + k, m[k], "null for kind 'roller' (groove conformity is a ball key)")
        out["outer_raceway_profile_radius_mm"] = co
        return out
    for k in ("inner_groove_conformity", "outer_groove_conformity"):
        f = m[k]
        f = DEFAULT_GROOVE_CONFORMITY if f is None else _num(
            p + k, f, lo=0.5, lo_open=True, hi=1.0, allowed="a number in (0.5, 1] (groove radius / ball "
            "diameter; 0.5 would be a groove of the ball's own radius: full conformity)")
        out[k] = f
        if length >= 2.0 * f * d:
            raise _bad(p + "roller_length_mm", length, f"for kind 'ball' the groove width, < 2 f d = "
                       f"{2.0 * f * d:g} mm ({k} = {f:g})")
    return out


def _build_relief(m: Any, length: float) -> EndRelief:
    p = "bearing.end_relief"
    if not isinstance(m, Mapping) or "kind" not in m:
        raise _bad(p, m, "{kind: radius, radius_mm: ...} or {kind: log, drop_um: ..., length_mm: ...}")
    kind = _choice(p + ".kind", m["kind"], ("radius", "log"))
    if kind == "radius":
        _check_keys("bearing.end_relief", m, {"kind", "radius_mm"}, {"radius_mm"})
        r = _num(p + ".radius_mm", m["radius_mm"], lo=0, lo_open=True, hi=length / 2, hi_open=True,
                 allowed=f"a number in (0, roller_length_mm/2 = {length / 2:g})")
        return EndRelief("radius", r, None, None)
    _check_keys("bearing.end_relief", m, {"kind", "drop_um", "length_mm"}, {"drop_um", "length_mm"})
    drop = _num(p + ".drop_um", m["drop_um"], lo=0, lo_open=True)
    ln = _num(p + ".length_mm", m["length_mm"], lo=0, lo_open=True, hi=length / 2, hi_open=True,
              allowed=f"a number in (0, roller_length_mm/2 = {length / 2:g})")
    return EndRelief("log", None, drop, ln)


def _build_material(m: Mapping[str, Any]) -> Material:
    out = []
    for body in ("roller", "race"):
        b = m[body]
        e = _num(f"material.{body}.E_GPa", b["E_GPa"], lo=0, lo_open=True)
        nu = _num(f"material.{body}.nu", b["nu"], lo=0, hi=0.5, hi_open=True)
        out.append(MaterialProps(e, nu))
    hv = m.get("hardness_GPa")
    if hv is not None:
        hv = _num("material.hardness_GPa", hv, lo=0, lo_open=True,
                  allowed="null (elastic) or a finite number > 0 (GPa)")
    return Material(*out, hardness_GPa=hv)


def _build_load(m: Mapping[str, Any], load_kN: float) -> Load:
    mode = _choice("load.mode", m["mode"], ("bearing", "contact"))
    v = _num("load.value_kN", load_kN, lo=0, lo_open=True)
    rl = _choice("load.roller_load", m["roller_load"], ROLLER_LOAD_MODELS)
    cf = m["centrifugal"]
    if not isinstance(cf, bool):
        raise _bad("load.centrifugal", cf, "true | false")
    return Load(v * 1e3, mode, rl, cf)


#: ``defect.location`` values built in (read at import, for the readers of before issue 44; the
#: live table is :data:`bearing_envelope.physics.locations.LOCATIONS`).
DEFECT_LOCATIONS = location_names()
#: ``defect.spin_axis`` values (see :class:`Defect`).
SPIN_AXES = ("fixed", "wandering")

#: ``defect.shape`` values: ``flat`` (rectangular footprint, flat bottom, rounded rims),
#: ``dent`` (smooth cos^2 bump), ``cylinder`` (circular footprint of diameter ``width_um``, flat
#: bottom, rounded rim: an EDM pit, CWRU), ``profile`` (measured profile from ``profile_file``).
DEFECT_SHAPES = ("flat", "dent", "cylinder", "profile")


#: A defect's width when ``defect.width_um`` is null, per unit of its depth (the source study's
#: defects are twice as wide as they are deep).
WIDTH_PER_DEPTH = 2.0


def default_width_um(depth_um: float) -> float:
    """The width of a defect whose ``width_um`` is null: :data:`WIDTH_PER_DEPTH` x depth.

    Parameters
    ----------
    depth_um : float
        Defect depth, um.

    Returns
    -------
    float
        Width, um.
    """
    return WIDTH_PER_DEPTH * depth_um


def _names_where(attribute: str) -> str:
    """The registered locations whose ``attribute`` is true, quoted, joined by ``or``."""
    return " or ".join(repr(n) for n in location_names() if getattr(get_location(n), attribute))


def _build_defect(m: Mapping[str, Any], depth_um: float, bearing: Bearing) -> Defect:
    p = "defect."
    depth = _num(p + "depth_um", depth_um, lo=0)
    shape = _choice(p + "shape", m["shape"], DEFECT_SHAPES)
    width = m["width_um"]
    width = default_width_um(depth) if width is None else _num(p + "width_um", width, lo=0,
                                                                  lo_open=True)
    # a cylindrical pit is round: its length is its diameter
    length = width if shape == "cylinder" else _num(p + "length_um", m["length_um"], lo=0,
                                                        lo_open=True)
    edge = _num(p + "edge_radius_um", m["edge_radius_um"], lo=0)
    ypos = _num(p + "axial_position_mm", m["axial_position_mm"])
    orient = _choice(p + "orientation", m["orientation"], ("axial", "circumferential"))
    loc = _choice(p + "location", m["location"], location_names())
    site = get_location(loc)
    pos = _num(p + "position_deg", m["position_deg"], lo=0, hi=360, hi_open=True,
               allowed="a finite angle in [0, 360) deg from the load direction (0 = centre of the "
                       "load zone)")
    if pos != 0 and not site.positioned:
        raise _bad(p + "position_deg", pos, f"0 unless defect.location is "
                   f"{_names_where('positioned')} (an {loc.replace('_', ' ')} defect turns through the load zone; its angle "
                   f"is not a setting)")
    pf = _defect_profile(m["profile_file"], shape)
    if depth > 0 and width <= 0:
        raise _bad(p + "width_um", width, "> 0 when depth_um > 0")
    spin = _choice(p + "spin_axis", m["spin_axis"], SPIN_AXES)
    if spin != "fixed" and not site.spins:
        raise _bad(p + "spin_axis", spin, f"'fixed' unless defect.location is "
                   f"{_names_where('spins')} (got location {loc!r})")
    d = Defect(depth, length, width, shape, edge, ypos, orient, loc, pos, pf, spin,
               _int(p + "spin_seed", m["spin_seed"], lo=0))
    if depth > 0:
        _check_defect_fits(d, bearing)
        _check_rim(d)
    return d


#: Least depth (fraction of ``depth_um``) the deepest point of a flat or cylindrical defect
#: keeps under its rim arcs: a rim radius much larger than the footprint flattens the defect
#: into nothing (``edge_radius_um: 1e6`` leaves 0.3 nm of a 50 um defect). A round trough whose
#: rims leave a few percent of the stated depth is a real shape (the pit-bottom study bisects
#: the depth of 20 um-rim troughs down to 0.5 um, which keep 1.25 %); below 1 % the stated
#: depth no longer describes the defect. The study's shallowest default case (15 um deep, 30 um
#: wide, 20 um rim) keeps 45 %.
MIN_RIM_DEPTH_FRACTION = 0.01


def _check_rim(d: Defect) -> None:
    """Refuse an ``edge_radius_um`` whose rim arcs leave less than
    :data:`MIN_RIM_DEPTH_FRACTION` of the depth at the defect's centre."""
    if d.shape not in ("flat", "cylinder") or d.edge_radius_um <= 0:
        return
    h = 1e-6 * d.depth_um
    deepest = float(defect_depth(d, 0.0, 0.0))
    if deepest >= MIN_RIM_DEPTH_FRACTION * h:
        return
    half = 0.5 * d.extent_x_m if d.shape == "cylinder" else \
        min(0.5 * d.extent_x_m, 0.5 * d.extent_y_m)
    keep = MIN_RIM_DEPTH_FRACTION * h      # r - sqrt(r^2 - half^2) = keep at the largest r
    r_max_um = 1e6 * (half * half + keep * keep) / (2.0 * keep)
    raise _bad("defect.edge_radius_um", d.edge_radius_um,
               f"a rim radius <= {r_max_um:.4g} um for this {d.depth_um:g} um deep defect (its "
               f"rims would leave {1e6 * deepest:.3g} um of depth, less than "
               f"{MIN_RIM_DEPTH_FRACTION:.0%})")


def _defect_profile(pf: Any, shape: str) -> str | None:
    """Validate ``defect.profile_file`` (required by, and only allowed with, ``shape: profile``)."""
    p = "defect.profile_file"
    if shape != "profile":
        if pf is not None:
            raise _bad(p, pf, "null unless defect.shape is 'profile'")
        return None
    if not isinstance(pf, (str, os.PathLike)):
        raise _bad(p, pf, "a path to a two-column file (x_um, depth_um) with defect.shape: profile")
    try:
        read_defect_profile(os.fspath(pf))
    except (OSError, ValueError) as exc:
        raise _bad(p, pf, f"a readable two-column file (x_um, depth_um): {exc}")
    return os.fspath(pf)


def _check_defect_fits(d: Defect, bearing: Bearing) -> None:
    """A defect the contact can host: axially within the roller (groove), along rolling less than
    half the element spacing on its race (half the element's circumference for a
    rolling-element defect), not deeper than the material under it."""
    p = "defect."
    half_l = 0.5 * bearing.roller_length_mm
    ey_mm = d.extent_y_m * 1e3
    if ey_mm >= bearing.roller_length_mm:
        field = "length_um" if d.orientation == "axial" else "width_um"
        raise _bad(p + field, getattr(d, field),
                   f"an axial extent < roller_length_mm ({bearing.roller_length_mm:g} mm): the "
                   f"defect must fit on the raceway under the roller")
    if abs(d.axial_position_mm) + 0.5 * ey_mm > half_l:
        raise _bad(p + "axial_position_mm", d.axial_position_mm,
                   f"|y| <= L/2 - axial extent/2 = {half_l - 0.5 * ey_mm:g} mm")
    room_m, what = d.fault_location.room_m(bearing)
    room_mm = 1e3 * room_m
    if d.extent_x_m * 1e3 >= room_mm:
        field = "width_um" if d.orientation == "axial" else "length_um"
        raise _bad(p + field, getattr(d, field), f"a rolling-direction extent < {what} "
                   f"({room_mm:g} mm)")
    t_um = 1e6 * d.fault_location.thickness_m(bearing)
    if d.depth_um >= t_um:
        raise _bad(p + "depth_um", d.depth_um, f"a depth < the material under the {d.location} "
                   f"({t_um:g} um)")


def _build_operation(m: Mapping[str, Any], bpfi_per_hz: float, z: int) -> Operation:
    p = "operation."
    fr = _num(p + "shaft_rate_hz", m["shaft_rate_hz"], lo=0, lo_open=True)
    ov = m["bpfi_override_hz"]
    if ov is not None:
        # the implied cage rate f_r - BPFI/Z must lie in (0, f_r): BPFI in (0, Z f_r)
        ov = _num(p + "bpfi_override_hz", ov, lo=0, lo_open=True, hi=z * fr, hi_open=True,
                  allowed=f"null or a number in (0, Z * shaft_rate_hz = {z * fr:g})")
    bpfi = ov if ov is not None else bpfi_per_hz * fr
    fs_min = 2.0 * MAX_BAND_ORDER * bpfi
    fs = _num(p + "fs_hz", m["fs_hz"], lo=fs_min,
              allowed=f">= 2 x {MAX_BAND_ORDER} x BPFI = {fs_min:.6g} Hz (the 10-13 x BPFI analysis "
                      f"band must lie below Nyquist)")
    rev = _num(p + "revolutions", m["revolutions"], lo=0, lo_open=True)
    if rev / fr * fs < 16:
        raise _bad(p + "revolutions", m["revolutions"], "a duration of at least 16 samples")
    slip = _num(p + "cage_slip_percent", m["cage_slip_percent"], lo=0, hi=50, hi_open=True)
    sseed = _int(p + "slip_seed", m["slip_seed"], lo=0)
    snr = m["noise_snr_db"]
    snr = None if snr is None else _num(p + "noise_snr_db", snr, allowed="null or a finite number (dB)")
    nseed = _int(p + "noise_seed", m["noise_seed"], lo=0)
    return Operation(fr, ov, fs, rev, slip, sseed, snr, nseed, _build_acquisition(m["acquisition"]))


def _build_acquisition(m: Mapping[str, Any]) -> Acquisition:
    p = "operation.acquisition."
    mode = _choice(p + "mode", m["mode"], ACQUISITION_MODES)
    n = m["oversample"]
    if n != "auto":
        if isinstance(n, float) and n.is_integer():
            n = int(n)
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise _bad(p + "oversample", n, "'auto' or an integer >= 1 (internal rate = "
                       "oversample x fs_hz)")
    return Acquisition(mode, n)
