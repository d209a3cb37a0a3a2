"""Every default is written once: its home against every other place that could hold one.

Homes (docs/architecture.md, "Where defaults live"): the scene in ``physics/scene_sections.py``
(``DEFAULT_SCENE``) with the study bearing's values in its catalogue entry
(``data/bearings.yaml``); the fidelity preset in ``physics/fidelity.py``; the analysis options in
``diagnosis.AnalysisOptions`` (the filter order in ``signal/envelope.py``); the trade-off study
in ``study/tradeoff_settings.py``; the pre-run limits in ``study/limits.py``; the sensor in
``physics/transfer_model.py`` (``TransferModel``, ``NoiseSpec``). The schema file holds defaults only
for sections whose home it is (diagnosability, paper_run), and the loader fills the others in
from their homes. Below: every default of the same quantity across the library.
"""

from __future__ import annotations

import inspect
from pathlib import Path

import pytest
import yaml

from bearing_envelope.diagnosis.options import AnalysisOptions
from bearing_envelope.physics import catalogue
from bearing_envelope.physics.fidelity import DEFAULT_PRESET, fidelity_from
from bearing_envelope.physics.scene import DEFAULT_SCENE, STUDY_DESIGNATION, Scene
from bearing_envelope.signal.envelope import DEFAULT_FILTER_ORDER, bandpass, envelope_spectrum
from bearing_envelope.study.limits import DEFAULT_LIMITS
from bearing_envelope.study.schema import full_schema
from bearing_envelope.study.settings import settings_from_mapping
from bearing_envelope.study.schema import SCHEMA_PATH
from bearing_envelope.study.tradeoff import TRADEOFF_DEFAULTS, tradeoff_study

ROOT = Path(__file__).resolve().parents[1]
RAW_SCHEMA = yaml.safe_load(SCHEMA_PATH.read_text())

#: Schema sections whose defaults live in code (none may be written in the schema file).
CODE_HOMED = ("fidelity", "scene", "limits", "tradeoff", "sensor")


def _defaults(node, path=""):
    """Every ``default:`` under a schema node: dotted path -> value."""
    out = {}
    if isinstance(node, dict):
        if "default" in node:
            out[path] = node["default"]
        for key, sub in node.items():
            if key != "default":
                out.update(_defaults(sub, f"{path}.{key}" if path else key))
    elif isinstance(node, list):
        for i, sub in enumerate(node):
            out.update(_defaults(sub, f"{path}[{i}]"))
    return out


def _leaves(m, path=()):
    if isinstance(m, dict) and m:
        for k, v in m.items():
            yield from _leaves(v, path + (k,))
    else:
        yield path, m


@pytest.mark.parametrize("section", CODE_HOMED)
def test_schema_file_writes_no_default_whose_home_is_code(section):
    assert _defaults(RAW_SCHEMA["properties"][section]) == {}
    assert _defaults(RAW_SCHEMA["$defs"]) == {}   # the material: physics/scene.py


def test_schema_file_writes_no_analysis_option_default():
    """Only ``signal`` (which simulated signal: no analysis option) has its default in the file."""
    raw = _defaults(RAW_SCHEMA["properties"]["analysis"])
    assert set(raw) == {"properties.signal"}


def test_loaded_schema_takes_analysis_and_fidelity_defaults_from_their_homes():
    opt = AnalysisOptions()
    props = full_schema()["properties"]
    an = {k: v["default"] for k, v in props["analysis"]["properties"].items() if "default" in v}
    assert an["harmonics"] == opt.n_harmonics and an["sidebands"] == opt.n_sidebands
    assert an["raw_orders_fr"] == opt.n_raw_harmonics and an["nlevel"] == opt.nlevel
    assert an["filter_order"] == opt.filter_order == DEFAULT_FILTER_ORDER
    assert an["squared_envelope"] is opt.squared
    assert an["max_level"] == opt.max_level and an["min_bandwidth_hz"] == opt.min_bandwidth
    assert an["amplitude"] == ("interpolated" if opt.interpolate else "peak_bin")
    assert props["fidelity"]["default"] == DEFAULT_PRESET
    assert fidelity_from(None) == fidelity_from(DEFAULT_PRESET)


def test_loaded_schema_takes_sensor_defaults_from_the_transfer_model():
    from bearing_envelope.physics.transfer import Mode, NoiseSpec, TransferModel

    props = full_schema()["properties"]["sensor"]["properties"]
    model = TransferModel(modes=(Mode(3000.0, 0.02),))
    for key in ("excitation", "excitation_scale", "discretization", "seed"):
        assert props[key]["default"] == getattr(model, key), key
    assert props["noise"]["properties"]["exact"]["default"] is NoiseSpec().exact is True
    # a config giving only the modes builds the model the dataclass defaults build
    st = settings_from_mapping({"sweep": {"loads_kN": [500], "depths_um": [0]},
                                "sensor": {"modes": [{"f_n_hz": 3000.0, "zeta": 0.02}]}})
    assert st.sensor == model


def test_filter_order_has_one_home():
    for fn in (bandpass, envelope_spectrum):
        assert inspect.signature(fn).parameters["order"].default == DEFAULT_FILTER_ORDER


def test_study_bearing_is_its_catalogue_entry_with_its_override():
    values = catalogue.bearing_values(STUDY_DESIGNATION)
    for key, value in values.items():
        assert DEFAULT_SCENE["bearing"][key] == value, key
    assert DEFAULT_SCENE["operation"]["bpfi_override_hz"] == \
        catalogue.entry(STUDY_DESIGNATION)["bpfi_override_hz"]["value"] == 231.9
    # naming the entry or not gives the same scene (the designation field aside)
    named = Scene.from_mapping({"bearing": {"designation": STUDY_DESIGNATION}}, load_kN=500,
                               depth_um=50)
    assert named.bpfi_hz == Scene.default().bpfi_hz == 231.9
    assert named.bearing.roller_diameter_mm == Scene.default().bearing.roller_diameter_mm


def test_config_yaml_restates_no_default():
    """config.yaml states what the default sweep chooses: no scene value (every one is the
    study's default), no analysis, limits, tradeoff, sensor or diagnosability value equal to its
    home's
    (``fidelity: standard`` is stated as the sweep's choice of preset)."""
    cfg = yaml.safe_load((ROOT / "config.yaml").read_text())
    assert cfg["scene"] == {}
    assert "limits" not in cfg
    for key, value in cfg.get("tradeoff", {}).items():
        default = TRADEOFF_DEFAULTS[key]
        assert value != (list(default) if isinstance(default, tuple) else default), key
    loaded = full_schema()["properties"]["analysis"]["properties"]
    for key, value in cfg["analysis"].items():
        assert "default" not in loaded[key] or loaded[key]["default"] != value, key
    schema_defaults = _defaults(full_schema()["properties"])
    for path, value in _leaves({k: cfg[k] for k in ("sensor", "diagnosability")}):
        dotted = ".properties.".join(path)
        assert dotted not in schema_defaults or schema_defaults[dotted] != value, path


def test_catalogue_and_config_agree_on_nothing_twice():
    """bearings.yaml is the only file with the study bearing's numbers: config.yaml and the
    CWRU overlays name a designation instead of repeating an entry's values."""
    for name in ("config.yaml", "config_cwru.yaml", "config_cwru_or.yaml", "config_cwru_ball.yaml",
                 "config_cwru_locations.yaml"):
        scene = (yaml.safe_load((ROOT / name).read_text()) or {}).get("scene") or {}
        bearing = scene.get("bearing") or {}
        assert set(bearing) <= {"designation"}, name
        assert "bpfi_override_hz" not in (scene.get("operation") or {}), name


def test_tradeoff_and_limits_defaults_have_one_home():
    sig = inspect.signature(tradeoff_study).parameters
    for key in ("base", "reference", "reference_element", "element_series", "revolutions"):
        assert sig[key].default is TRADEOFF_DEFAULTS[key], key
    assert sig["cases"].default is TRADEOFF_DEFAULTS["cases"]
    st = settings_from_mapping({"sweep": {"loads_kN": [500], "depths_um": [0]}})
    assert "limits" not in st.config and "tradeoff" not in st.config
    assert DEFAULT_LIMITS["max_case_cpu_s"] > 0


def test_cli_simulate_has_no_scene_or_fidelity_default():
    """``bearing-envelope simulate``: a scene or fidelity option left out is None (the config's
    or the home's default), never a second default."""
    import argparse

    from bearing_envelope.commands import simulate

    parser = argparse.ArgumentParser()
    simulate.register(parser.add_subparsers())
    sub = parser._subparsers._group_actions[0].choices["simulate"]
    for action in sub._actions:
        if action.dest in ("fidelity", "width_um", "config"):
            assert action.default is None, action.dest


# ---------------------------------------------------------------------------------------------
# Every default of the same quantity across the library (issue 44, part 4)
#
# A *definition* is a default written as a literal: a default of a public function's or method's
# parameter, a public class's (dataclass) field, or a fallback in a body
# (``m.get("key", 8)``, ``.pop``, ``.setdefault``, ``getattr(x, "key", 8)``, ``x.key or 8``
# outside an f-string). A default written as a name (``nlevel: int = DEFAULT_NLEVEL``) *reads* a
# home. Defaults that are no quantity's value are neutral and not counted: None and the
# sentinels of ``SENTINELS`` ("absent": the callee reads the home), booleans (switches), empty
# strings/containers or containers of None, and dataclass factories (a fresh empty container).
# The quantity is the parameter name (the body fallback's key), except where ``QUANTITY_OF``
# names it or ``NOT_ONE_QUANTITY`` says the name means something different in each callable.
# Each quantity: at most one definition, and every default of it (literal or read) equal.
# The DEFAULT_SCENE / dataclass pairs and the schema file have their own tests (above, below).

import ast  # noqa: E402
import dataclasses  # noqa: E402
import importlib  # noqa: E402
import pkgutil  # noqa: E402
from typing import NamedTuple  # noqa: E402

import bearing_envelope  # noqa: E402

#: Names that are a different quantity in each callable that has them (each its own quantity).
NOT_ONE_QUANTITY = {
    "name": "the name of what the callable builds or checks (a preset, a signal, a field)",
    "where": "the field prefix of an error message",
    "field": "the field name an error message gives",
    "base": "a base folder (manifest paths), a base preset (trade-off study), a base frequency",
    "kind": "which kind of thing (end relief, bearing, excitation, information measure)",
    "axis": "an array axis",
    "n": "a count of whatever the callable samples",
    "level": "a threshold statistic (detection) or a burst level (cycles)",
    "mode": "load mode, acquisition mode, structural mode: unrelated settings",
    "seed": "the seed of the callable's own random stream",
    "n_solves": "a counter's start (0): each object counts its own solves",
    "background": "a background band (multiples of a line) or where a background came from",
    "sideband": "a row selector: the sideband index (0 = the harmonic itself), not a setting",
    "x_d": "a row selector: the defect's offset in the contact (0 = centred), not a setting",
}

#: ``(callable or module, parameter) -> quantity`` where the parameter name alone would join
#: different quantities.
QUANTITY_OF: dict[tuple[str, str], str] = {
    # a preset's value against the solver's own default (fidelity.py documents the preset's)
    ("bearing_envelope.physics.fidelity.Fidelity", "tol"): "standard preset: solver tolerance",
    ("bearing_envelope.physics.fidelity.Fidelity", "max_iter"): "standard preset: iterations",
    ("bearing_envelope.signal.envelope.settling_samples", "tol"): "filter settling tolerance",
    # sidebands counted around a line (metrics) against those kept out of its background
    ("bearing_envelope.diagnosis.detection.detection_statistic", "sidebands"): "excluded sidebands",
    # what a figure marks for orientation against what an analysis searches
    ("bearing_envelope.diagnosis.plots.plot_envelope_spectrum", "n_harmonics"): "harmonics marked",
    ("bearing_envelope.diagnosis.plots.plot_envelope_spectrum", "n_sidebands"): "sidebands marked",
    ("bearing_envelope.diagnosis.plots.save_analysis_figures", "n_harmonics"): "harmonics marked",
    ("bearing_envelope.diagnosis.plots.save_analysis_figures", "n_sidebands"): "sidebands marked",
    ("bearing_envelope.diagnosis.plots.save_record_figure", "dpi"): "record figure dpi",
    ("bearing_envelope.diagnosis.plots.plot_envelope_waveform", "periods"): "waveform periods",
    ("bearing_envelope.study.figures.spectra.fig_harmonics_vs_depth", "orders"): "harmonic orders drawn",
    # the shaft-rate search (speed.py) against a fault line's search
    ("bearing_envelope.diagnosis.speed.estimate_shaft_rate", "search_percent"): "shaft-rate search",
    ("bearing_envelope.diagnosis.speed.estimate_shaft_rate", "orders"): "shaft orders searched",
    # acquire's resolved integer factor against the scene's setting ("auto" or an integer)
    ("bearing_envelope.physics.acquisition.acquire", "oversample"): "resolved oversample factor",
    # what an error model written before issue 25 was measured with (a stored file's meaning)
    ("bearing_envelope.study.accuracy", "far_field"): "far field of a pre-issue-25 error model",
    # the origin of an analysed record (its reader's word) against a config's in a message
    ("bearing_envelope.diagnosis.records", "source"): "a record's origin",
    # a missing rig.load_kN read as nan, then refused (no default)
    ("bearing_envelope.study.rig.config", "load_kN"): "missing-value marker",
}

#: String defaults that name another home rather than give a value (like None).
SENTINELS = {"model": "the transfer model's own SNR (``snr_db='model'``)"}


class Default(NamedTuple):
    quantity: str
    where: str
    value: object
    literal: bool
    #: The expression a read default is written as (``DEFAULT_NLEVEL``, ``Cls.field``).
    expr: str = ""


def _neutral(value) -> bool:
    if value is None or isinstance(value, bool) or value is dataclasses._HAS_DEFAULT_FACTORY:
        return True
    if isinstance(value, str):
        return value == "" or value in SENTINELS
    return isinstance(value, (tuple, list, dict, frozenset, set)) and \
        all(v is None for v in value)


def _is_literal(node) -> bool:
    """A default written as a constant expression (no name, attribute or call in it)."""
    return not any(isinstance(n, (ast.Name, ast.Attribute, ast.Call)) for n in ast.walk(node))


def _arg_nodes(fn: ast.FunctionDef) -> dict:
    a = fn.args
    pos = a.posonlyargs + a.args
    out = dict(zip([x.arg for x in pos[len(pos) - len(a.defaults):]], a.defaults))
    out.update({x.arg: d for x, d in zip(a.kwonlyargs, a.kw_defaults) if d is not None})
    return out


def _class_nodes(cls_node: ast.ClassDef) -> tuple[dict, dict]:
    """Field default nodes (annotated class attributes) and method nodes of a class."""
    fields = {st.target.id: st.value for st in cls_node.body if isinstance(st, ast.AnnAssign)
              and st.value is not None and isinstance(st.target, ast.Name)}
    methods = {st.name: st for st in cls_node.body if isinstance(st, ast.FunctionDef)}
    return fields, methods


def _quantity(where: str, param: str) -> str:
    owner = where.split(":")[0]          # a body fallback: its module
    if (owner, param) in QUANTITY_OF:
        return QUANTITY_OF[(owner, param)]
    return f"{where}:{param}" if param in NOT_ONE_QUANTITY else param


def _signature_defaults(where: str, obj, nodes: dict) -> list[Default]:
    try:
        params = inspect.signature(obj).parameters.values()
    except (TypeError, ValueError):
        return []
    out = []
    for p in params:
        if p.default is inspect.Parameter.empty or _neutral(p.default):
            continue
        node = nodes.get(p.name)
        literal = node is not None and _is_literal(node)
        out.append(Default(_quantity(where, p.name), where, p.default, literal,
                           "" if literal or node is None else ast.unparse(node)))
    return out


def _body_fallbacks(tree, modname: str) -> list[Default]:
    out = []
    shown = {id(n) for fv in ast.walk(tree) if isinstance(fv, ast.FormattedValue)
             for n in ast.walk(fv)}                 # ``{x or 'none'}``: how a value is printed
    for node in ast.walk(tree):
        if id(node) in shown:
            continue
        key = dflt = None
        if isinstance(node, ast.Call) and len(node.args) in (2, 3):
            fn = node.func
            if isinstance(fn, ast.Attribute) and fn.attr in ("get", "pop", "setdefault") \
                    and len(node.args) == 2:
                key, dflt = node.args
            elif isinstance(fn, ast.Name) and fn.id == "getattr" and len(node.args) == 3:
                key, dflt = node.args[1:]
            if not (isinstance(key, ast.Constant) and isinstance(key.value, str)):
                continue
            key = key.value
        elif isinstance(node, ast.BoolOp) and isinstance(node.op, ast.Or) and \
                len(node.values) == 2 and isinstance(node.values[0], ast.Attribute):
            key, dflt = node.values[0].attr, node.values[1]
        else:
            continue
        if not _is_literal(dflt):
            continue
        value = ast.literal_eval(dflt)
        if not _neutral(value):
            where = f"{modname}:{node.lineno}"
            out.append(Default(_quantity(where, key), where, value, True))
    return out


def _module_defaults(mod) -> list[Default]:
    """Every default a module writes or reads: its public callables' signatures (via inspect;
    literal or read decided on the source) and its body fallbacks."""
    tree = ast.parse(inspect.getsource(mod))
    top = {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    out = _body_fallbacks(tree, mod.__name__)
    for attr, obj in vars(mod).items():
        if attr.startswith("_") or getattr(obj, "__module__", None) != mod.__name__ \
                or attr not in top:
            continue
        where = f"{mod.__name__}.{attr}"
        if inspect.isfunction(obj):
            out += _signature_defaults(where, obj, _arg_nodes(top[attr]))
        elif inspect.isclass(obj):
            fields, methods = _class_nodes(top[attr])
            init = methods.get("__init__")
            out += _signature_defaults(where, obj, _arg_nodes(init) if init else fields)
            for name, fn in methods.items():
                if name.startswith("_"):
                    continue
                member = inspect.unwrap(getattr(getattr(obj, name), "__func__", getattr(obj, name)))
                out += _signature_defaults(f"{where}.{name}", member, _arg_nodes(fn))
    return out


def _library_defaults() -> list[Default]:
    out = []
    for info in pkgutil.walk_packages(bearing_envelope.__path__, "bearing_envelope."):
        if not info.name.endswith("__main__"):
            out += _module_defaults(importlib.import_module(info.name))
    return out


def _twice(defaults: list[Default]) -> dict[str, list[str]]:
    """Quantities defined more than once, or with unequal defaults: quantity -> the places.

    A default read from a name means the quantity has a home: a literal beside it is then a
    second definition, unless every read names the literal's own class (``AnalysisOptions.nlevel``
    reads ``AnalysisOptions``' field); a second literal is always one."""
    by: dict[str, list[Default]] = {}
    for d in defaults:
        by.setdefault(d.quantity, []).append(d)
    bad = {}
    for q, ds in by.items():
        values = {repr(d.value) for d in ds}
        lits = [d for d in ds if d.literal]
        reads = [d for d in ds if not d.literal]
        of_literal = len(lits) == 1 and all(
            d.expr.split(".")[0] == lits[0].where.rsplit(".", 1)[-1] for d in reads)
        homes = len(lits) + (bool(reads) and not of_literal)
        if homes > 1 or len(values) > 1:
            bad[q] = [f"{d.where}={d.value!r}{'' if d.literal else ' (read)'}" for d in ds]
    return bad


LIBRARY_DEFAULTS = _library_defaults()


def test_every_default_of_a_quantity_is_defined_once_and_agrees():
    twice = _twice(LIBRARY_DEFAULTS)
    assert not twice, "defaults defined twice or disagreeing:\n" + "\n".join(
        f"  {q}: {', '.join(w)}" for q, w in sorted(twice.items()))


def test_the_check_sees_signatures_fields_and_fallbacks():
    """The collection reaches every kind of place (so a clean result is not an empty one)."""
    where = {d.where for d in LIBRARY_DEFAULTS}
    assert "bearing_envelope.signal.kurtogram.fast_kurtogram" in where          # a function
    assert "bearing_envelope.diagnosis.options.AnalysisOptions" in where        # a dataclass
    assert any(w.startswith("bearing_envelope.physics.transfer_model.Mode.") for w in where)  # a method
    assert len(LIBRARY_DEFAULTS) > 200


def test_a_planted_duplicate_fails(tmp_path, monkeypatch):
    """A module writing ``nlevel = 8`` again (or a different filter order) is caught."""
    (tmp_path / "planted_defaults.py").write_text(
        "from bearing_envelope.signal.kurtogram import DEFAULT_NLEVEL\n\n"
        "def reads(x, nlevel=DEFAULT_NLEVEL):\n    return x\n\n\n"
        "def again(x, nlevel=8):\n    return x\n\n\n"
        "def other(x, *, order=2):\n    return x\n\n\n"
        "def fallback(m):\n    return m.get('nlevel', 8)\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    planted = _module_defaults(importlib.import_module("planted_defaults"))
    assert {d.where.split(".")[-1]: d.literal for d in planted if ":" not in d.where} == \
        {"reads": False, "again": True, "other": True}
    assert _twice([d for d in planted if d.where.endswith("reads")] + LIBRARY_DEFAULTS) == \
        _twice(LIBRARY_DEFAULTS)                                    # reading the home is fine
    twice = _twice(planted + LIBRARY_DEFAULTS)
    assert "nlevel" in twice and any("again" in w for w in twice["nlevel"])
    # one literal beside defaults that read the home is a second definition too
    alone = [d for d in planted if d.where.endswith("again")]
    assert "nlevel" in _twice(alone + LIBRARY_DEFAULTS)
    assert any(w.startswith("planted_defaults:") for w in twice["nlevel"])   # the fallback
    assert "order" in twice and any("other=2" in w for w in twice["order"])  # unequal default


#: ``DEFAULT_*`` constants of the same name in two modules that are different quantities.
SAME_NAME_OTHER_QUANTITY = {
    "DEFAULT_PFA": {"bearing_envelope.diagnosis.path_constants":
                    "identify-path's event detection (0.1 %), not the verdict's 1 %"},
    "DEFAULT_BANDS": {"bearing_envelope.study.tradeoff":
                      "the trade-off study's bands: the library's (read) and a fixed band"},
}


def test_a_default_constant_is_defined_in_one_module():
    """A module-level ``DEFAULT_*`` constant written as a literal in one module; the others
    import it (``diagnosis.analysis.DEFAULT_PFA`` is ``diagnosis.detection``'s)."""
    where: dict[str, list[str]] = {}
    for info in pkgutil.walk_packages(bearing_envelope.__path__, "bearing_envelope."):
        if info.name.endswith("__main__"):
            continue
        mod = importlib.import_module(info.name)
        for node in ast.parse(inspect.getsource(mod)).body:
            targets = node.targets if isinstance(node, ast.Assign) else \
                [node.target] if isinstance(node, ast.AnnAssign) and node.value else []
            for t in targets:
                if isinstance(t, ast.Name) and t.id.lstrip("_").startswith("DEFAULT_") and \
                        info.name not in SAME_NAME_OTHER_QUANTITY.get(t.id, {}):
                    where.setdefault(t.id, []).append(info.name)
    twice = {k: v for k, v in where.items() if len(v) > 1}
    assert not twice, twice
    assert len(where) > 10


def test_scene_dataclass_defaults_read_default_scene():
    """Each scene dataclass's field default is ``DEFAULT_SCENE``'s value at its key, read from
    it (no literal but None)."""
    from bearing_envelope.physics import scene_sections as sc

    tree = ast.parse(inspect.getsource(sc))
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    homes = {"Bearing": DEFAULT_SCENE["bearing"], "MaterialProps": DEFAULT_SCENE["material"]["race"],
             "Material": DEFAULT_SCENE["material"], "Load": DEFAULT_SCENE["load"],
             "Acquisition": DEFAULT_SCENE["operation"]["acquisition"],
             "Operation": DEFAULT_SCENE["operation"], "Defect": DEFAULT_SCENE["defect"],
             "EndRelief": {}}
    for name, home in homes.items():
        nodes, _ = _class_nodes(classes[name])
        for f in dataclasses.fields(getattr(sc, name)):
            if f.name not in nodes or f.name == "contact_race":
                continue
            value = f.default if f.default is not dataclasses.MISSING else f.default_factory()
            if dataclasses.is_dataclass(value):
                value = dataclasses.asdict(value)
            if value is None:
                continue                                    # absent: nothing to agree on
            assert f.name in home and value == home[f.name], (name, f.name)
            node = nodes[f.name]
            assert not _is_literal(node) or ast.literal_eval(node) is None, (name, f.name)
    assert DEFAULT_SCENE["material"]["roller"] == DEFAULT_SCENE["material"]["race"]
