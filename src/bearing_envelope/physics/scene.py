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

The scene lives in three modules, one concern each: :mod:`.scene_sections` (the defaults,
:data:`DEFAULT_SCENE`, and the frozen dataclass of each section), :mod:`.scene_build` (reading
a mapping: merge over the defaults, check every field, build the sections) and this module
(:class:`Scene`, which joins them; every name above is importable from here).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Mapping

from .dynamics_option import Dynamics, build_dynamics
from .kinematics import FaultFrequencies, bearing_rates, fault_frequencies
from .scene_build import (
    BEARING_KINDS, DEFAULT_GROOVE_CONFORMITY, DEFECT_LOCATIONS, DEFECT_SHAPES, MAX_BAND_ORDER,
    MAX_CONTACT_ANGLE_DEG, WIDTH_PER_DEPTH, _base_mapping, _build_bearing, _build_defect,
    _build_load, _build_material, _build_operation, _check_override_bearing, _merge,
    default_width_um,
)
from .scene_sections import (
    ACQUISITION_MODES, BEARING_STEEL_HARDNESS_GPA, DEFAULT_SCENE, ROLLER_LOAD_MODELS, STEEL_E_GPA,
    STEEL_NU, STUDY_DESIGNATION, Acquisition, Bearing, Defect, EndRelief, Load, Material,
    MaterialProps, Operation, default_scene_mapping,
)

__all__ = [
    "EndRelief", "Bearing", "MaterialProps", "Material", "Acquisition", "Operation", "Load",
    "Defect", "Scene", "ACQUISITION_MODES", "ROLLER_LOAD_MODELS", "BEARING_STEEL_HARDNESS_GPA",
    "DEFAULT_SCENE", "default_scene_mapping", "MAX_BAND_ORDER", "DEFECT_LOCATIONS", "DEFECT_SHAPES",
    "BEARING_KINDS", "DEFAULT_GROOVE_CONFORMITY", "STUDY_DESIGNATION", "STEEL_E_GPA", "STEEL_NU",
    "MAX_CONTACT_ANGLE_DEG", "WIDTH_PER_DEPTH", "default_width_um",
]


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
