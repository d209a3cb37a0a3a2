"""Does anything rank the pit sizes right? Pairs of records of one location, position, load
and fs, the smallest pit against the next larger one, compared feature by feature on the
measured records and on the model (docs/virtual_rig.md, "Size")."""

from __future__ import annotations

import numpy as np

__all__ = ["size_pairs", "size_ranking", "size_summary"]


def size_pairs(conditions) -> list:
    """The pairs compared: per location, outer-race position, load and fs, each record of the
    smallest pit (``length_um``) against the first record of the next larger one.

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records (:func:`~.manifest.record_conditions`).

    Returns
    -------
    list of (RigCondition, RigCondition)
        (smaller, larger), grouped by location in order of first appearance.
    """
    groups: dict = {}
    for c in conditions:
        groups.setdefault((c.location, c.position_deg, c.load, c.fs_hz), []).append(c)
    pairs = []
    for g in groups.values():
        sizes = sorted({c.length_um for c in g})
        if len(sizes) < 2:
            continue
        big = [d for d in g if d.length_um == sizes[1]][0]
        pairs += [(c, big) for c in g if c.length_um == sizes[0]]
    order = list(dict.fromkeys(c.location for c in conditions))
    return sorted(pairs, key=lambda p: order.index(p[0].location))


def _pulse_features(contact_path: str, fs: float) -> dict:
    """Removed-force pulses of a simulated record: median peak (N) and width above half the
    peak (s)."""
    with np.load(contact_path) as z:
        rf = np.asarray(z["removed_force"], dtype=float)
    top = float(np.max(rf))
    if top <= 0:
        return {"model_removed_N": 0.0, "model_width_s": 0.0}
    k = np.flatnonzero((rf[1:-1] > rf[:-2]) & (rf[1:-1] >= rf[2:]) & (rf[1:-1] > 0.5 * top)) + 1
    peaks = rf[k]
    return {"model_removed_N": float(np.median(peaks)),
            "model_width_s": float(np.count_nonzero(rf > 0.5 * top) / max(k.size, 1) / fs)}


def _features(card, name: str, cond, contact: dict, paths_json: dict) -> dict:
    """One record's size features: measured (identified event amplitude, line height, 2x/1x,
    3x/1x), simulated line height and the model's pulses."""
    r = card[card.record == name].iloc[0]
    p = paths_json.get(name, {})
    f = {"meas_amplitude": p.get("amplitude") if p.get("status") == "identified" else None,
         "meas_height_db": r.meas_height_db, "meas_h2_db": r.meas_h2_db,
         "meas_h3_db": r.meas_h3_db, "sim_height_db": r.sim_height_db}
    if name in contact:
        f.update(_pulse_features(contact[name], cond.fs_hz))
    return f


def size_ranking(card, conditions, contact: dict, paths_json: dict) -> list:
    """Does a feature rank the pit sizes right, record by record (:func:`size_pairs`)?

    Features of the measured record (identified event amplitude, line height, 2x/1x, 3x/1x)
    and of the model (median removed force per event, pulse width). A pair is ranked right
    when the larger pit has the larger value.

    Parameters
    ----------
    card : pandas.DataFrame
        The scorecard (:func:`~.scoring.scorecard`).
    conditions : sequence of RigCondition
        The rig's records (:func:`~.manifest.record_conditions`).
    contact : dict
        The contact histories (:func:`~.simulation.simulate_excitations`).
    paths_json : dict
        The run's ``paths.json``.

    Returns
    -------
    list of dict
        One row per pair and feature: values of the small and the large pit, ``right``.
    """
    rows = []
    for c, d in size_pairs(conditions):
        fc, fd = (_features(card, x.name, x, contact, paths_json) for x in (c, d))
        for key in fc:
            a, b = fc.get(key), fd.get(key)
            ok = None if a is None or b is None or not (np.isfinite(a) and np.isfinite(b)) \
                else bool(b > a)
            rows.append({"location": c.location, "load": c.load, "fs_hz": c.fs_hz,
                         "small": c.name, "large": d.name, "feature": key, "small_value": a,
                         "large_value": b, "right": ok})
    return rows


def size_summary(rows) -> str:
    """Markdown: per location, fs and feature, pairs ranked right / pairs compared.

    Parameters
    ----------
    rows : list of dict
        :func:`size_ranking`.

    Returns
    -------
    str
        A markdown table.
    """
    agg: dict = {}
    for r in rows:
        if r["right"] is None:
            continue
        key = (r["location"], int(r["fs_hz"]), r["feature"])
        n_ok, n = agg.get(key, (0, 0))
        agg[key] = (n_ok + int(r["right"]), n + 1)
    out = ["| location | fs Hz | feature | larger pit ranked larger |", "|---|---|---|---|"]
    out += [f"| {loc} | {fs} | {feat} | {ok}/{n} |" for (loc, fs, feat), (ok, n) in
            sorted(agg.items())]
    return "\n".join(out) + "\n"

