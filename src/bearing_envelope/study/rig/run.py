"""One scored run of the virtual rig: paths, gain, simulated records, ``analyze`` on the measured
and the simulated records alike, the scorecard and every file of the run's folder
(docs/virtual_rig.md, "Scorecard"), and the records the run's figures show."""

from __future__ import annotations

import csv
import json
from collections import Counter
from pathlib import Path

from ...physics.locations import get_location
from .config import RigSettings
from .events import event_shapes
from .figures import plot_element_folds, plot_side_by_side
from .scoring import (features_in_measured_band, load_trends, outer_race_ratios,
                      outer_race_ratios_in_band, pass_rates, scorecard, scorecard_markdown)
from .dynamic import excitation_model
from .simulation import anchor_gains, record_paths, rig_gain, write_rig_record
from .size import size_ranking, size_summary

__all__ = ["run_scorecard", "figure_records", "analyze_manifest"]


def figure_records(conditions) -> list:
    """The records a run's figures show: those at the lowest load and at the sampling rate most
    records have (ties: the lowest; CWRU: 0 hp, 12 kHz).

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records (:func:`~.manifest.record_conditions`).

    Returns
    -------
    list of RigCondition
        Those records, in the order given.
    """
    if not conditions:
        return []
    counts = Counter(c.fs_hz for c in conditions)
    fs = min(counts, key=lambda f: (-counts[f], f))
    low = min(c.load for c in conditions)
    return [c for c in conditions if c.load == low and c.fs_hz == fs]


def analyze_manifest(rows, path) -> str:
    """Write the manifest ``analyze --manifest`` reads: each record's file (absolute), fs and
    shaft rate (written to the bit: ``repr``).

    Parameters
    ----------
    rows : iterable of (str, RigCondition)
        The file and the condition it belongs to (the measured record or its twin).
    path : path
        The CSV written.

    Returns
    -------
    str
        ``path``.
    """
    with open(path, "w", encoding="utf-8", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["file", "fs", "shaft_hz"])
        for f, c in rows:
            w.writerow([str(Path(f).resolve()), repr(float(c.fs_hz)), repr(float(c.shaft_hz))])
    return str(path)


def _bearing_options(bearing) -> list[str]:
    if bearing.designation:
        return ["--bearing", bearing.designation]
    return ["--n-rollers", str(bearing.n_rollers),
            "--roller-diameter-mm", repr(bearing.roller_diameter_mm),
            "--pitch-diameter-mm", repr(bearing.pitch_diameter_mm),
            "--contact-angle-deg", repr(bearing.contact_angle_deg)]


def _analyze(files, conditions, out_prefix: Path):
    """``bearing-envelope analyze`` (defaults, the records' bearing) over the files, one
    process, their fs and shaft rates through a manifest: the verdict table and the lines, read
    back."""
    import subprocess
    import sys

    import pandas as pd  # lazy: pandas ~1.8 s

    table, lines = f"{out_prefix}_table.csv", f"{out_prefix}_lines.csv"
    manifest = analyze_manifest(zip(files, conditions), f"{out_prefix}_manifest.csv")
    cmd = [sys.executable, "-m", "bearing_envelope", "analyze", "--manifest", manifest,
           *_bearing_options(conditions[0].bearing), "--jobs", "1", "--table", table,
           "--csv", lines]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    sys.stderr.write(done.stderr)
    if done.returncode:
        last = (done.stderr.strip().splitlines() or ["no message"])[-1]
        raise RuntimeError(f"rig: analyze of {manifest} failed (exit {done.returncode}): {last}")
    # names as text: a record named "105" (a CWRU .mat file) is not the number 105
    return pd.read_csv(table, dtype={"record": str}), pd.read_csv(lines, dtype={"file": str})


def run_scorecard(conditions, contact: dict, out_dir, gain_reference: str, *, log=print,
                  settings: RigSettings | None = None):
    """Paths, gain, simulated records, analyze on both sides, the scorecard and its files.

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records (:func:`~.manifest.record_conditions`).
    contact : dict
        :func:`~.simulation.simulate_excitations`'s result.
    out_dir : path
        ``paths.json``, ``sim/`` (the simulated records), ``scorecard.csv``,
        ``outer_race.csv``, ``summary.json``, ...
    gain_reference : str
        Records (name contains) the rig's gain is identified on.
    log : callable
        Progress lines.
    settings : RigSettings, optional
        The rig's sensor (:func:`~.simulation.sensor_gain`); None: a sensor blind to direction.

    Returns
    -------
    pandas.DataFrame
        The scorecard.
    """
    out_dir = Path(out_dir)
    conditions = [c for c in conditions if c.name in contact]
    paths = record_paths(conditions, log=log)
    gains = _gains(conditions, paths, contact, gain_reference, settings, log)
    gain = next(iter(gains.values()))
    anchors = anchor_gains(conditions, paths, gain[3], gain[4])
    sim = []
    for i, c in enumerate(conditions):
        g = gains.get(excitation_model(contact[c.name]), gain)
        sim.append(write_rig_record(c, contact[c.name], paths[c.name][0], g[0], out_dir / "sim",
                                    seed=i, first_gain=anchors[c.name][0], settings=settings))
    with open(out_dir / "paths.json", "w", encoding="utf-8") as fh:
        json.dump({n: {"status": s, "first_mode_gain_re_reference": anchors[n][0],
                       "group_records_with_reference_mode": anchors[n][1],
                       **{k: v for k, v in p.to_dict().items()
                                       if not k.startswith("background_")}}
                   for n, (p, s) in paths.items()}, fh, indent=1)
    mt, ml = _analyze([c.path for c in conditions], conditions, out_dir / "measured")
    st, sl = _analyze(sim, conditions, out_dir / "simulated")
    card = scorecard(conditions, mt, ml, st, sl)
    _write_tables(out_dir, card, ml, sl, gain, gains)
    with open(out_dir / "paths.json", encoding="utf-8") as fh:
        _write_size(out_dir, size_ranking(card, conditions, contact, json.load(fh)))
    zero = figure_records(conditions)
    if zero:
        plot_side_by_side(card, zero, out_dir / "sim", out_dir / "side_by_side.png")
    _write_events(conditions, out_dir)
    return card


def _gains(conditions, paths, contact: dict, reference: str, settings, log) -> dict:
    """The rig's gain per excitation model (:func:`~.dynamic.excitation_model`): on the
    reference records' excitations, and, where some record's excitation is of the other model,
    on their contact histories (``contact["_quasi_static"]``) too."""
    ref = [c for c in conditions if reference in c.name and c.name in contact]
    own = excitation_model(contact[ref[0].name]) if ref else "quasi_static"
    gains = {own: rig_gain(conditions, paths, contact, reference, settings)}
    others = {excitation_model(contact[c.name]) for c in conditions} - {own}
    qs = contact.get("_quasi_static", {})
    if "quasi_static" in others and any(c.name in qs for c in ref):
        gains["quasi_static"] = rig_gain(conditions, paths, qs, reference, settings)
    for model, g in gains.items():
        log(f"rig: gain ({model}) {g[0]:.4g} (m/s^2 or g)/N at resonance of the {g[3]:.0f} Hz "
            f"mode, {g[1]:.4g}-{g[2]:.4g} over the {reference} records")
    return gains


def _write_events(conditions, out_dir: Path) -> None:
    """``event_shape.csv`` (:func:`~.events.event_shapes` of every race record) and
    ``element_folds.png`` (:func:`~.figures.plot_element_folds` of the outer-race records of
    :func:`figure_records`)."""
    import pandas as pd  # lazy: pandas ~1.8 s

    pd.DataFrame(event_shapes(conditions, out_dir / "sim")).to_csv(
        out_dir / "event_shape.csv", index=False)
    outer = [c for c in figure_records(conditions) if get_location(c.location).positioned]
    if outer:
        plot_element_folds(outer, out_dir / "sim", out_dir / "element_folds.png")


def _write_tables(out_dir: Path, card, ml, sl, gain, gains: dict) -> None:
    """The scorecard's files: CSVs, ``summary.json``, ``scorecard.md``."""
    import pandas as pd  # lazy: pandas ~1.8 s

    ratios = pd.DataFrame(outer_race_ratios(card))
    card.to_csv(out_dir / "scorecard.csv", index=False)
    trends = pd.DataFrame(load_trends(card))
    trends.to_csv(out_dir / "outer_race_trend.csv", index=False)
    ratios.to_csv(out_dir / "outer_race.csv", index=False)
    pd.DataFrame(outer_race_ratios_in_band(card, ml, sl)).to_csv(
        out_dir / "outer_race_bands.csv", index=False)
    pd.DataFrame(features_in_measured_band(card, ml, sl)).to_csv(
        out_dir / "same_band.csv", index=False)
    with open(out_dir / "summary.json", "w", encoding="utf-8") as fh:
        json.dump({"gain": gain, "gains": gains, "pass_rates": pass_rates(card)}, fh, indent=1)
    (out_dir / "scorecard.md").write_text(scorecard_markdown(card, ratios, trends),
                                          encoding="utf-8")


def _write_size(out_dir: Path, sizes: list) -> None:
    import pandas as pd  # lazy: pandas ~1.8 s

    pd.DataFrame(sizes).to_csv(out_dir / "size.csv", index=False)
    (out_dir / "size.md").write_text(size_summary(sizes), encoding="utf-8")

