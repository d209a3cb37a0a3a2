"""The virtual rig: every measured fault record of a record set re-made as a simulated record of
that rig, set beside it and scored (docs/virtual_rig.md; ``bearing-envelope rig``).

The record set is described by a manifest (:mod:`.manifest`: per record the file, the bearing,
the fault's location and size in um, the outer race's position in degrees, the load, fs and the
shaft rate); the CWRU Bearing Data Center's drive-end records are one such set
(:mod:`.cwru`: the converted development records by the package's manifest, the data center's
``.mat`` files as downloaded by its catalogue). The rooms:

- :mod:`.records`: a record's bearing, defect and operation (:class:`RigCondition`), the rig's
  bearing look-up and rates;
- :mod:`.manifest`, :mod:`.cwru`: record sets;
- :mod:`.config`: the rig's config (its scene, load, sensor);
- :mod:`.simulation`: scenes, contact histories, transfer paths, simulated records;
- :mod:`.scoring`: the scorecard's features and pass rules;
- :mod:`.events`: how a race fault's events spread in a record;
- :mod:`.figures`: measured beside simulated;
- :mod:`.size`: does anything rank the pit sizes;
- :mod:`.load_zone`: the clearance and the sensor's cross-axis gain identified from a run;
- :mod:`.run`: one scored run and its files.

Why a study subpackage and not a Snakemake overlay: the sweep's dimensions are load x depth x
width of one scene; the rig varies the defect location, the outer-race position, the shaft
rate and the sampling rate per record and reads the measured records themselves, none of which
the sweep's case grid names.

Examples
--------
>>> from bearing_envelope.study import rig                       # doctest: +SKIP
>>> conds = rig.record_conditions(["my_records/manifest.csv"])   # doctest: +SKIP
>>> settings = rig.read_rig_config("config_rig.yaml")            # doctest: +SKIP
>>> contact = rig.simulate_excitations(conds, settings, "runs/rig/contact")  # doctest: +SKIP
>>> card = rig.run_scorecard(conds, contact, "runs/rig", "OR007at6",
...                          settings=settings)                  # doctest: +SKIP
"""

from __future__ import annotations

from .config import RigSettings, read_rig_config
from .cwru import DRIVE_END
from .load_zone import (directional_modulation, event_exponent, identify_from_run,
                        identify_load_zone, measured_sideband_db, removed_force_exponent,
                        structure_ratio_db)
from .manifest import (MANIFEST_NAME, fault_location, manifest_rows, read_rig_manifest,
                       record_conditions)
from .records import RigBearing, RigCondition, rig_event_rates, resolve_bearing
from .run import run_scorecard
from .scoring import (features_in_measured_band, load_trends, outer_race_ratios,
                      outer_race_ratios_in_band, pass_rates, scorecard)
from .dynamic import dynamic_supported, sensor_excitation
from .simulation import (anchor_gains, condition_scene, existing_excitations, path_modes,
                         record_paths, record_spin_seed, reference_mode, rig_gain, sensor_gain,
                         simulate_excitations, write_rig_record)
from .size import size_ranking, size_summary

__all__ = ["record_conditions", "manifest_rows", "RigCondition", "RigBearing", "RigSettings",
           "read_rig_config", "read_rig_manifest", "fault_location", "rig_event_rates",
           "resolve_bearing", "condition_scene", "simulate_excitations", "path_modes",
           "reference_mode", "anchor_gains", "record_spin_seed",
           "sensor_gain", "record_paths", "rig_gain", "write_rig_record", "run_scorecard",
           "scorecard", "pass_rates", "load_trends", "outer_race_ratios",
           "outer_race_ratios_in_band", "features_in_measured_band", "size_ranking",
           "size_summary", "removed_force_exponent", "event_exponent", "directional_modulation",
           "structure_ratio_db",
           "identify_load_zone", "measured_sideband_db", "identify_from_run", "DRIVE_END",
           "MANIFEST_NAME", "existing_excitations", "dynamic_supported", "sensor_excitation"]
