"""Aggregate tables of the sweep: the tidy harmonic table and load x depth pivots.

The tidy table has one row per amplitude with the columns :data:`TIDY_COLUMNS`. Pivots turn
one (band, quantity, order, sideband) slice into a load x depth grid, like the study's
Figs 8, 12 and 14-20.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = [
    "TIDY_COLUMNS",
    "concat_tidy",
    "pivot_tables",
    "write_csv_atomic",
    "parse_case_name",
]

TIDY_COLUMNS = [
    "case",
    "load_kN",
    "depth_um",
    "band",
    "band_strategy",
    "band_low_hz",
    "band_high_hz",
    "quantity",
    "order",
    "sideband",
    "frequency_hz",
    "amplitude",
]

def parse_case_name(name: str) -> tuple[float, float]:
    """Return ``(load_kN, depth_um)`` of a case name (:meth:`bearing_envelope.settings.CaseId.parse`).

    Kept for callers of the former helper; new code uses ``CaseId.parse`` (which also gives the
    width of a ``..._w{width}um`` name).
    """
    from .settings import CaseId

    c = CaseId.parse(name)
    return c.load_kN, c.depth_um


def _public_mode(path) -> None:
    """Give a file made by ``mkstemp`` (mode 0600) the mode a plain ``open`` would give."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, 0o666 & ~umask)


def write_csv_atomic(df: pd.DataFrame, path: str | os.PathLike, **kwargs) -> None:
    """Write ``df`` to CSV through a temporary file in the same directory, then rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        df.to_csv(tmp, index=kwargs.pop("index", False), **kwargs)
        _public_mode(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def concat_tidy(frames: Iterable[pd.DataFrame]) -> pd.DataFrame:
    """Concatenate per-case tidy frames, check the columns and sort deterministically.

    Raises
    ------
    ValueError
        If a frame lacks a tidy column, or an amplitude is not finite.
    """
    frames = list(frames)
    if not frames:
        raise ValueError("no per-case tables to aggregate")
    for i, f in enumerate(frames):
        missing = [c for c in TIDY_COLUMNS if c not in f.columns]
        if missing:
            raise ValueError(f"per-case table {i} lacks columns {missing}")
    df = pd.concat(frames, ignore_index=True)
    bad = ~np.isfinite(df["amplitude"].to_numpy(dtype=float))
    if bad.any():
        rows = df.loc[bad, ["case", "band", "quantity", "order", "sideband"]].head(5)
        raise ValueError(f"non-finite amplitudes in {int(bad.sum())} rows, e.g.\n{rows}")
    extra = [c for c in df.columns if c not in TIDY_COLUMNS]
    df = df[TIDY_COLUMNS + extra]
    return df.sort_values(
        ["load_kN", "depth_um", "band", "quantity", "order", "sideband"], kind="stable"
    ).reset_index(drop=True)


def pivot_tables(tidy: pd.DataFrame, *, sideband: int = 0) -> dict[str, pd.DataFrame]:
    """Load x depth pivot of every (band, quantity, order) at one sideband index.

    Returns
    -------
    dict
        ``"{band}__{quantity}__{order}"`` -> DataFrame indexed by load (kN), columns depth (um).
    """
    sel = tidy[tidy["sideband"] == sideband]
    out: dict[str, pd.DataFrame] = {}
    for (band, quantity, order), g in sel.groupby(["band", "quantity", "order"], sort=True):
        p = g.pivot_table(index="load_kN", columns="depth_um", values="amplitude", aggfunc="first")
        p.index.name = "load_kN"
        p.columns.name = "depth_um"
        out[f"{band}__{quantity}__{order:g}"] = p
    return out
