"""Fault locations: one object per location, registered once in one table (issue 44).

:mod:`.base` holds :class:`FaultLocation` and the table :data:`LOCATIONS`
(:func:`get_location`, :func:`register_location`); one module per location holds its class,
its kinematics and its one registration: :mod:`.inner_race` (the study's), :mod:`.outer_race`,
:mod:`.rolling_element`. Nothing outside this package switches on a location's name: the scene
(:attr:`bearing_envelope.physics.scene.Defect.fault_location`), the exposure, the history, the
solves and the study read the object's attributes and methods.

Adding a location: a module here with a :class:`FaultLocation` subclass and its
:func:`register_location` call, its import line below, and its tests.

Examples
--------
>>> from bearing_envelope.physics.locations import get_location
>>> loc = get_location("outer_race")
>>> loc.code, loc.family, loc.races
('or', 'bpfo', ('outer',))
>>> get_location("cage")
Traceback (most recent call last):
...
ValueError: defect.location: got 'cage'; allowed: inner_race | outer_race | rolling_element
"""

from __future__ import annotations

from collections.abc import Mapping

from .base import (LOCATIONS, TWO_PI, FaultLocation, cage_angle, contact_signals,
                   event_frequencies, get_location, location_names, register_location,
                   scene_event_frequencies, wrap)
from .inner_race import INNER_RACE, InnerRace
from .outer_race import OUTER_RACE, OuterRace, outer_race_kinematics
from .rolling_element import (OFF_TRACK_OFFSET_M, ROLLING_ELEMENT, RollingElement, on_track,
                              rolling_element_kinematics, spin_is_free)

__all__ = ["FaultLocation", "LOCATIONS", "get_location", "register_location", "location_names",
           "InnerRace", "OuterRace", "RollingElement", "INNER_RACE", "OUTER_RACE",
           "ROLLING_ELEMENT", "LOCATION_FAMILIES", "TWO_PI", "wrap", "cage_angle",
           "contact_signals", "event_frequencies", "scene_event_frequencies",
           "outer_race_kinematics", "rolling_element_kinematics", "on_track",
           "OFF_TRACK_OFFSET_M", "spin_is_free"]


class _Families(Mapping):
    """``name -> (family, sideband)`` of every registered location, read live from
    :data:`LOCATIONS` (the mapping of before issue 44, for its readers)."""

    def __getitem__(self, name):
        loc = get_location(name)
        return loc.family, loc.sideband

    def __iter__(self):
        return iter(LOCATIONS)

    def __len__(self):
        return len(LOCATIONS)


#: The envelope line family each location makes and the spacing its sidebands are searched at
#: (``name -> (family, sideband)``), a live view of :data:`LOCATIONS`.
LOCATION_FAMILIES = _Families()
