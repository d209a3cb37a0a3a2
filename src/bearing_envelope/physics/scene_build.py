"""Reading a scene mapping: merge it over the defaults, check every field, build the sections.

:meth:`bearing_envelope.physics.scene.Scene.from_mapping` calls these builders; each check runs
before any contact solve and fails with a :class:`ValueError` naming the dotted field
(``scene.defect.depth_um`` ...), the value and what is allowed. The limits and the allowed
values of the checks are defined here.
"""

from __future__ import annotations

import copy
import math
import os
from typing import Any, Mapping

from .catalogue import bearing_values, designations, operation_values, resolve_designation
from .geometry import defect_depth, read_defect_profile, read_profile
from .locations import get_location, location_names
from .scene_sections import (
    ACQUISITION_MODES, DEFAULT_SCENE, ROLLER_LOAD_MODELS, STUDY_DESIGNATION, Acquisition, Bearing,
    Defect, EndRelief, Load, Material, MaterialProps, Operation,
)

__all__ = [
    "MAX_BAND_ORDER", "DEFECT_LOCATIONS", "DEFECT_SHAPES", "BEARING_KINDS",
    "DEFAULT_GROOVE_CONFORMITY", "MAX_CONTACT_ANGLE_DEG", "WIDTH_PER_DEPTH", "default_width_um",
]


#: The analysis needs bands up to 13 x BPFI (the study's 10-13 x BPFI band); fs must exceed
#: twice that so the band lies below Nyquist.
MAX_BAND_ORDER = 13


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
