"""Estimated discretisation error of the reported amplitudes (error bars, issue 13 part 5).

``benchmarks/reference.py`` (issue 25 part 5, reusing ``benchmarks/accuracy.py``) measures, for
each fidelity point (the presets and the knob ladders between them) on cases of the default
scene, the relative error of every amplitude the analysis reports (peak and rms of each signal,
raw spectrum lines, envelope lines and sidebands in each band; interpolated amplitudes, the far
field ``responds``) against a reference that refines every knob (rim strips, global and window
axial spacing, window margin, tolerance, table load nodes and offsets). Its ``--write-model``
stores, per fidelity point, **load**, case kind (``defect`` / ``healthy``), signal and quantity
class (:func:`quantity_class`: ``peak``, ``rms``, each raw line family, envelope lines, their
sidebands, the band-passed peak), the worst relative error over the model's cases at that load
(three depths: 15, 60, 100 um), the analysis bands and the orders, in the package file
``data/discretisation_error.csv`` (a JSON provenance line, then the table).

**Which load's rows** (:func:`error_model`, ``load_rule``): by default every case reads the
worst over the model's loads (250, 500, 750 kN) of its point, kind, signal and class; with
``per_load`` (:func:`rows_at_load`) a case at a model load reads that load's rows, between two
model loads the larger of the two, outside them the nearest. On three held-out cases
(500 kN / 50 um, 250 kN / 40 um, 750 kN / 20 um) the bars read as the worst over the loads
covered every amplitude class at ``fast``, ``standard`` and ``accurate`` (100 %); read at the
case's own load, 67-78 % of the raw DC, BPFI and rms terms at ``standard``
(``docs/benchmarks.md``, "A preset within 2 % on every signal").

:func:`error_model` picks the rows that apply to a case: the fidelity must equal a measured
point in every numerical field (``name``, ``n_checks`` and ``n_snapshot_offsets`` do not change
the signals and are ignored), otherwise there is no estimate and the basis says why.
:func:`attach_errors` adds to a tidy table, row by row, the columns

``rel_error_est``
    Estimated relative discretisation error (a fraction; NaN where none was measured).
``error_est``
    The bound on ``|amplitude - converged value|`` that follows, in the amplitude's unit:
    ``e / (1 - e) * |amplitude|`` for ``e = rel_error_est`` (:func:`absolute_error`; ``inf`` for
    ``e >= 1``).
``error_basis``
    Where the estimate comes from, or why there is none (never empty).

A difference between two cases smaller than the sum of their ``error_est`` is not resolved
by the simulation at that fidelity. The estimate is an upper value over the measured cases
(250, 500 and 750 kN; 15, 60 and 100 um deep and healthy) of the default scene (flat defect, 20 um
rim, elastic) and its five analysis bands: it does not cover a scene whose rim radius, shape or
hardness differ.
"""

from __future__ import annotations

import dataclasses

import json
import math
from functools import lru_cache
from importlib import resources
from io import StringIO
from typing import Any

import numpy as np

from ..physics.fidelity import Fidelity, fidelity_from
from ..physics.scene import Scene
from ..io.case import ErrorModel   # the type a case file stores; re-exported here
from ..lazy import lazy_module

pd = lazy_module("pandas")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["ErrorModel", "error_model", "case_error_model", "attach_errors", "absolute_error", "measured_points",
           "measured_far_field", "quantity_class", "rows_at_load", "lookup_rel_error",
           "stored_error_model",
           "scene_differences", "ERROR_COLUMNS", "LOAD_RULES"]

#: Columns :func:`attach_errors` adds to a tidy table.
ERROR_COLUMNS = ["rel_error_est", "error_est", "error_basis"]

#: Fidelity fields that do not change the signals (not compared when matching a point).
_IGNORED = ("name", "n_checks", "n_snapshot_offsets", "far_field")

#: Signals whose values the far-field model changes (removed force and approach halve with the
#: coupled far field, issue 25); p_max and p_max_defect move by < 0.03 %, so their measured
#: errors stand whatever the far field. A case whose ``far_field`` is not the model's
#: (:func:`measured_far_field`) gets no bars for these.
FAR_FIELD_SIGNALS = ("removed_force", "contact_force", "approach", "approach_change",
                     "contact_area")


def quantity_class(quantity: str, sideband: int = 0) -> str:
    """The class an amplitude's error is estimated for: ``peak`` and ``rms`` of the signal, the
    tidy quantity (``raw_dc``, ``raw_fr``, ``raw_bpfi``, ``envelope_bpfi``, ``bandpass_peak``,
    ...) for lines at their harmonics, and ``<quantity>_sideband`` for shaft-rate sidebands.

    Parameters
    ----------
    quantity : str
        The tidy table's ``quantity`` (``peak``, ``rms``, ``raw_bpfi``, ``envelope_bpfi``, ...).
    sideband : int, default 0
        The row's sideband order (multiples of the shaft rate; 0 = the line itself).

    Returns
    -------
    str
        ``quantity`` itself, or ``"<quantity>_sideband"`` for a non-zero ``sideband``.
    """
    return f"{quantity}_sideband" if int(sideband) != 0 else str(quantity)


@lru_cache(maxsize=1)
def stored_error_model() -> tuple[dict[str, Any], pd.DataFrame]:
    """The discretisation-error model the package ships (``data/discretisation_error.csv``).

    Returns
    -------
    header : dict
        The file's JSON provenance line (source, date, reference, far_field, ...).
    table : pandas.DataFrame
        One row per measured point (``load_kN`` NaN for a model pooled over loads).

    Raises
    ------
    ValueError
        The packaged table's first line is not its JSON header.
    """
    text = resources.files("bearing_envelope").joinpath("data/discretisation_error.csv").read_text()
    first, _, rest = text.partition("\n")
    if not first.startswith("# "):
        raise ValueError("data/discretisation_error.csv: the first line must be '# {json header}'")
    header = json.loads(first[2:])
    table = pd.read_csv(StringIO(rest), keep_default_na=False, na_values=["nan", "NaN"])
    if "load_kN" not in table:                   # a model pooled over loads (before issue 25)
        table.insert(1, "load_kN", np.nan)
    return header, table


def measured_far_field() -> str:
    """The far-field model every measured point was run with (the header's ``far_field``; a
    model written before issue 25 has none and was measured ``frozen``).

    Returns
    -------
    str
        ``"responds"`` or ``"frozen"`` (:attr:`Fidelity.far_field`'s values).
    """
    return str(stored_error_model()[0].get("far_field", "frozen"))


def rows_at_load(rows: pd.DataFrame, load_kN: float | None) -> tuple[pd.DataFrame, str]:
    """The errors of one point and case kind at a load: ``(table, rule)``, the table with columns
    ``signal, quantity_class, rel_error, n_values``. At a model load its rows; between two model
    loads the larger of the two; outside them the nearest; ``None``: the worst over all.

    Parameters
    ----------
    rows : pandas.DataFrame
        The model's rows of one fidelity point and case kind (columns ``load_kN, signal,
        quantity_class, rel_error, n_values``; ``load_kN`` all NaN for a model pooled over
        loads, whose rows are then used whatever ``load_kN``).
    load_kN : float or None
        The case's load, kN; None reads the worst over every model load.

    Returns
    -------
    table : pandas.DataFrame
        One row per ``(signal, quantity_class)``, sorted: ``rel_error`` the largest over the
        loads used (a fraction), ``n_values`` the sum of theirs.
    rule : str
        Which load's rows were read, in words (for the error basis).
    """
    loads = np.sort(rows["load_kN"].dropna().unique())
    if loads.size == 0:
        use, rule = rows["load_kN"].unique(), "pooled over the model's loads"
    elif load_kN is None:
        use = loads
        rule = f"the worst over the model's loads ({', '.join(f'{x:g}' for x in loads)} kN)"
    elif np.isclose(loads, load_kN, rtol=1e-9).any():
        use = loads[np.isclose(loads, load_kN, rtol=1e-9)]
        rule = f"the model's {use[0]:g} kN rows"
    elif load_kN < loads[0] or load_kN > loads[-1]:
        use = loads[[int(np.argmin(np.abs(loads - load_kN)))]]
        rule = f"the nearest model load's rows ({use[0]:g} kN; {load_kN:g} kN is outside)"
    else:
        i = int(np.searchsorted(loads, load_kN))
        use = loads[i - 1:i + 1]
        rule = (f"the larger of the model's {use[0]:g} and {use[1]:g} kN rows ({load_kN:g} kN "
                f"lies between)")
    sub = rows[rows["load_kN"].isin(use)]
    g = sub.groupby(["signal", "quantity_class"], sort=True)
    out = pd.DataFrame({"rel_error": g["rel_error"].max(), "n_values": g["n_values"].sum()})
    return out.reset_index(), rule


def lookup_rel_error(table: pd.DataFrame, point: str, load_kN: float | None, kind: str,
                     signal: str, qclass: str) -> float:
    """The estimated relative error of one amplitude (NaN where none was measured): the rows of
    ``table`` (the model's columns) for ``point`` and ``kind`` read at ``load_kN`` by
    :func:`rows_at_load`.

    Parameters
    ----------
    table : pandas.DataFrame
        The error model's table (columns ``point, load_kN, kind, signal, quantity_class,
        rel_error, n_values``).
    point : str
        The measured fidelity point's name.
    load_kN : float or None
        The case's load, kN (None: the worst over the model's loads).
    kind : {"defect", "healthy"}
        The case kind.
    signal : str
        The signal's name (``p_max``, ``removed_force``, ...).
    qclass : str
        The amplitude's class (:func:`quantity_class`).

    Returns
    -------
    float
        The relative error (a fraction), NaN where the class was not measured.
    """
    rows = table[(table["point"] == point) & (table["kind"] == kind)]
    t, _ = rows_at_load(rows, load_kN)
    hit = t[(t["signal"] == signal) & (t["quantity_class"] == qclass)]
    return float(hit["rel_error"].iloc[0]) if len(hit) else math.nan


def measured_points() -> dict[str, Fidelity]:
    """The measured fidelity points of the error model, by name.

    Returns
    -------
    dict of str to Fidelity
        Each point of the model file's header, built with :func:`fidelity_from` and named by
        its key.
    """
    header, _ = stored_error_model()
    return {name: fidelity_from({**{k: v for k, v in spec.items() if k != "name"},
                                 "name": name})
            for name, spec in header["fidelities"].items()}


def _same(a: Fidelity, b: Fidelity) -> bool:
    da, db = a.to_dict(), b.to_dict()
    for k in da:
        if k in _IGNORED:
            continue
        x, y = da[k], db[k]
        if isinstance(x, float) or isinstance(y, float):
            if x is None or y is None:
                if x is not y:
                    return False
            elif not math.isclose(float(x), float(y), rel_tol=1e-9):
                return False
        elif x != y:
            return False
    return True


#: Scene keys that may differ from the default scene without voiding the estimate: the sweep
#: values and what does not change the discretisation (duration, noise, seeds).
_SCENE_FREE = ("operation.revolutions", "operation.noise_snr_db", "operation.noise_seed",
               "operation.slip_seed", "load.value_kN", "defect.depth_um")


def _flat(d: Any, prefix: str = "") -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in dict(d).items():
        if isinstance(v, dict):
            out.update(_flat(v, f"{prefix}{k}."))
        else:
            out[f"{prefix}{k}"] = v
    return out


def scene_differences(scene: Any, depth_um: float) -> list[str]:
    """The keys (``section.key: value vs default``) in which a scene mapping differs from the
    default scene the error model was measured on, with the same depth (and so the default width
    ``w = 2 h``); the sweep values, duration, noise and seeds are not compared.

    Parameters
    ----------
    scene : mapping
        The case's nested scene mapping (:meth:`Scene.to_mapping` sections and keys).
    depth_um : float
        The case's defect depth, um (the default scene is built at it).

    Returns
    -------
    list of str
        ``"section.key: value vs default"`` for each differing key (a key missing on one side
        reads ``None``), sorted by key; empty when the scene is the default one.
    """
    flat = _flat(scene)
    ref = _flat(Scene.from_mapping({}, load_kN=float(flat.get("load.value_kN", 500.0)),
                                   depth_um=float(depth_um)).to_mapping())
    diff = []
    for k in sorted(set(flat) | set(ref)):
        if k in _SCENE_FREE:
            continue
        x, y = flat.get(k), ref.get(k)
        same = (math.isclose(float(x), float(y), rel_tol=1e-9)
                if isinstance(x, (int, float)) and isinstance(y, (int, float))
                and not isinstance(x, bool) else x == y)
        if not same:
            diff.append(f"{k}: {x!r} vs {y!r}")
    return diff


#: How a case reads the model's loads (:func:`error_model`): ``worst``, the worst over the
#: model's loads (the default since 2026-11-27: on the held-out cases it covered every amplitude
#: class at ``fast``, ``standard`` and ``accurate``, where the case's own load covered 67-78 % of
#: the raw DC, BPFI and rms terms; ``docs/benchmarks.md``, "A preset within 2 % on every
#: signal"), or ``per_load``, :func:`rows_at_load` at the case's load.
LOAD_RULES = ("worst", "per_load")


def error_model(fidelity: Fidelity, depth_um: float,
                scene: Any = None, load_kN: float | None = None,
                load_rule: str = "worst") -> ErrorModel:
    """The measured discretisation errors that apply to a case at ``fidelity``.

    Parameters
    ----------
    fidelity : Fidelity
        The case's numerical settings; its preset name selects the measured errors.
    depth_um : float
        The case's defect depth (0 = healthy race: the healthy case's errors apply).
    scene : mapping, optional
        The case's scene (:meth:`bearing_envelope.physics.scene.Scene.to_mapping`): if it differs from
        the default scene in anything but the sweep values, duration, noise and seeds
        (:func:`scene_differences`), there is no estimate and the basis names the keys.
    load_kN : float, optional
        The case's load (kN); default: the scene's ``load.value_kN``. Read with ``load_rule``
        ``per_load`` (:func:`rows_at_load`), and named in the basis when outside the model's
        loads.
    load_rule : {"worst", "per_load"}
        :data:`LOAD_RULES`: the worst over the model's loads (default), or the case's load.

    Returns
    -------
    ErrorModel
        ``point`` the matching measured fidelity point's name and ``table`` its rows for the
        case kind, read by ``load_rule`` (without the far-field signals, listed in
        ``withheld``, when the case's far field is not the model's); or ``point`` None and an
        empty table when the scene or the fidelity was not measured, ``basis`` saying why.

    Raises
    ------
    ValueError
        ``load_rule`` not in :data:`LOAD_RULES`.
    """
    if load_rule not in LOAD_RULES:
        raise ValueError(f"load_rule must be one of {LOAD_RULES}, got {load_rule!r}")
    fid = fidelity
    header, table = stored_error_model()
    kind = "healthy" if float(depth_um) <= 0 else "defect"
    if scene is not None:
        diff = scene_differences(scene, depth_um)
        if diff:
            return ErrorModel(None, kind, "not estimated: the scene differs from the measured "
                              "default scene in " + "; ".join(diff[:4])
                              + (f" (+{len(diff) - 4} more)" if len(diff) > 4 else ""),
                              table.iloc[0:0].copy())
    match = next((name for name, f in measured_points().items() if _same(fid, f)), None)
    if match is None:
        return ErrorModel(None, kind, f"not estimated: fidelity {fid.name!r} is not one of the "
                          f"measured points {sorted(header['fidelities'])} "
                          f"(benchmarks/accuracy.py)", table.iloc[0:0].copy())
    if load_kN is None and scene is not None:
        load_kN = _flat(scene).get("load.value_kN")
    load_kN = None if load_kN is None else float(load_kN)
    sub = table[(table["point"] == match) & (table["kind"] == kind)]
    rows, rule = rows_at_load(sub, load_kN if load_rule == "per_load" else None)
    if load_rule == "worst" and load_kN is not None and \
            not sub["load_kN"].min() <= load_kN <= sub["load_kN"].max():
        rule += f"; {load_kN:g} kN lies outside them"
    withheld = FAR_FIELD_SIGNALS if fid.far_field != measured_far_field() else ()
    rows = rows[~rows["signal"].isin(withheld)].reset_index(drop=True)
    cases = ", ".join(f"{c[0]:g} kN/{c[1]:g} um" for c in header["cases"]
                      if (c[1] > 0) == (kind == "defect"))
    basis = (f"{match}: {rule}, worst relative error over the model's cases ({cases}; default "
             f"scene) and the bands against a reference refining every knob, "
             f"{header['source']} {header['date']}")
    return ErrorModel(match, kind, basis, rows, tuple(withheld))


def case_error_model(history) -> ErrorModel:
    """The error model of a simulated case (:class:`~bearing_envelope.physics.history.History`):
    :func:`error_model` at its fidelity, defect depth and scene; what
    :func:`bearing_envelope.io.write_case` stores as the ``discretisation_error`` group.

    Parameters
    ----------
    history : bearing_envelope.physics.history.History
        The simulated case (its ``fidelity`` and ``scene`` are read).

    Returns
    -------
    ErrorModel
        As :func:`error_model` with the default load rule (``worst``).
    """
    em = error_model(history.fidelity, history.scene.defect.depth_um, history.scene.to_mapping())
    if hasattr(history, "element_load_n"):   # a dynamic case: the estimates are the contact's
        return dataclasses.replace(em, point=None, table=em.table.iloc[0:0].copy(), withheld=(),
                                   basis="not estimated: a dynamic case (docs/dynamics.md states "
                                         "the step rule's convergence of its envelope lines)")
    return em


def attach_errors(table: pd.DataFrame, model: ErrorModel, signal: str) -> pd.DataFrame:
    """``table`` (a tidy harmonic table of one case and signal) with :data:`ERROR_COLUMNS`.

    A row gets the measured error of the same signal and :func:`quantity_class`; a class that
    was not measured gets none, and says so.

    Parameters
    ----------
    table : pandas.DataFrame
        Tidy harmonic table with at least ``quantity``, ``sideband`` and ``amplitude``.
    model : ErrorModel
        The case's error model (:func:`error_model`, :func:`case_error_model`).
    signal : str
        The signal the table's rows belong to.

    Returns
    -------
    pandas.DataFrame
        A copy of ``table`` plus ``rel_error_est`` (fraction, NaN where none), ``error_est``
        (:func:`absolute_error`, in the amplitude's unit) and ``error_basis`` (str, never empty).
    """
    out = table.copy()
    rel = np.full(len(out), np.nan)
    basis = np.full(len(out), model.basis, dtype=object)
    if model.point is not None:
        est = {(r.signal, r.quantity_class): float(r.rel_error)
               for r in model.table.itertuples(index=False)}
        for i, (q, sb) in enumerate(zip(out["quantity"], out["sideband"])):
            key = (signal, quantity_class(q, sb))
            if key in est:
                rel[i] = est[key]
            elif signal in model.withheld:
                basis[i] = (f"not estimated: the errors of {signal} were measured with the "
                            f"{measured_far_field()} far field, not the case's")
            else:
                basis[i] = f"not estimated: {key[1]} of {signal} was not measured"
    out["rel_error_est"] = rel
    out["error_est"] = absolute_error(rel, out["amplitude"].to_numpy(dtype=float))
    out["error_basis"] = basis
    return out


def absolute_error(rel_error, amplitude):
    """The absolute error bound of an amplitude ``a`` whose relative error against the converged
    value ``a*`` is at most ``e``: ``|a - a*| <= e |a*| <= e / (1 - e) |a|`` (``|a*| <= |a| / (1 -
    e)``); ``inf`` for ``e >= 1`` (no bound), NaN where ``e`` is NaN.

    Parameters
    ----------
    rel_error : float or array_like
        Relative error bounds ``e`` (fractions).
    amplitude : float or array_like
        Amplitudes ``a`` (any unit), broadcast against ``rel_error``.

    Returns
    -------
    ndarray
        ``e / (1 - e) * |a|``, in the amplitude's unit (0-d for scalar inputs).
    """
    e = np.asarray(rel_error, dtype=float)
    a = np.abs(np.asarray(amplitude, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(e < 1, e / (1 - e) * a, np.where(np.isnan(e), np.nan, np.inf))
