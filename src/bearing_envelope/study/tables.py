"""Aggregate tables of the sweep and the one tidy vocabulary every table uses.

The tidy table has one row per amplitude with the columns :data:`TIDY_COLUMNS` (then the extra
columns :data:`TIDY_EXTRA_COLUMNS` where present). The same column and quantity names are used
by the sweep's ``harmonics.csv`` and by ``bearing-envelope analyze``: :func:`tidy_from_analysis`
maps the long form returned by :func:`bearing_envelope.diagnosis.analyze_signal` onto them, and
both sides call it. The vocabulary is documented once, in ``docs/file-format.md`` ("Tidy
tables"). Pivots turn one (band, quantity, order, sideband) slice into a load x depth grid,
like the study's Figs 8, 12 and 14-20. Files are written and read by :mod:`bearing_envelope.io`.
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Mapping

import numpy as np
import pandas as pd

__all__ = [
    "TIDY_COLUMNS",
    "TIDY_EXTRA_COLUMNS",
    "TIDY_SORT",
    "RAW_BAND",
    "BAND_STRATEGIES",
    "QUANTITIES",
    "quantity_name",
    "tidy_from_analysis",
    "concat_tidy",
    "band_table",
    "add_location",
    "pivot_tables",
    "table_html",
]

from ..io.vocabulary import (BAND_STRATEGIES, QUANTITIES, RAW_BAND, TIDY_COLUMNS,  # noqa: F401
                         TIDY_EXTRA_COLUMNS, TIDY_SORT, quantity_name)
from .case_id import CaseId, format_number


def tidy_from_analysis(table: pd.DataFrame, strategies: Mapping[str, str] | None = None
                       ) -> pd.DataFrame:
    """The long table of :func:`bearing_envelope.diagnosis.analyze_signal` in the tidy vocabulary:
    its columns already are (``band`` = name, ``band_strategy`` = how it was chosen); its
    measure names ``quantity`` + ``base`` become one :data:`QUANTITIES` name (``raw_spectrum``
    + ``bpfi`` -> ``raw_bpfi``, ``envelope_spectrum`` + ``bpfi`` -> ``envelope_bpfi``).

    Parameters
    ----------
    table : DataFrame
        As returned by ``analyze_signal`` (columns ``bearing_envelope.diagnosis.COLUMNS``).
    strategies : mapping, optional
        Band name -> strategy, overriding ``band_strategy`` (the sweep applies its bands as fixed
        limits, so the strategy that chose them comes from the bands file).

    Returns
    -------
    DataFrame
        A copy; the other columns are kept, in their order.

    Raises
    ------
    ValueError
        The table lacks ``analyze_signal``'s ``band`` and ``band_strategy`` columns.
    """
    if "band" not in table.columns or "band_strategy" not in table.columns:
        raise ValueError("tidy_from_analysis expects analyze_signal's columns band (name) and "
                         f"band_strategy; got {list(table.columns)}")
    df = table.copy()
    base = df["base"].where(df["base"].notna(), None) if "base" in df else [None] * len(df)
    df["quantity"] = [quantity_name(q, b) for q, b in zip(df["quantity"], base)]
    if strategies is not None:
        df["band_strategy"] = [strategies.get(n, RAW_BAND) for n in df["band"]]
    return df


def concat_tidy(frames: Iterable[pd.DataFrame], cases: Iterable[CaseId] | None = None
                ) -> pd.DataFrame:
    """Concatenate per-case tidy frames, check the columns and sort deterministically.

    Parameters
    ----------
    frames : iterable of pandas.DataFrame
        Per-case tidy tables.
    cases : iterable of CaseId, optional
        The sweep's typed cases (each names its rows' ``case``): the ``location`` and
        ``width_um`` columns come from them (:func:`add_location`, :func:`add_width`); None:
        the frames' own columns only.

    Returns
    -------
    pandas.DataFrame
        Every frame's rows in one table (:data:`TIDY_COLUMNS` first), sorted by
        :data:`TIDY_SORT`, with the cases' ``location`` / ``width_um`` columns where they vary.

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
    lead, sort = list(TIDY_COLUMNS), list(TIDY_SORT)
    if cases is not None:
        cases = list(cases)
        df = add_width(add_location(df, cases), cases)
    if "location" in df.columns:
        # a key like load and depth, the first of the sort
        lead.insert(lead.index("depth_um") + 1, "location")
        sort.insert(0, "location")
    if "width_um" in df.columns:
        # a sweep over widths: a key like load and depth (empty: the healthy race)
        lead.insert(lead.index("depth_um") + 1, "width_um")
        sort.insert(sort.index("depth_um") + 1, "width_um")
    extra = [c for c in df.columns if c not in lead]
    df = df[lead + extra]
    dup = df.duplicated(["case", "band", "quantity", "order", "sideband"], keep=False)
    if dup.any():
        rows = df.loc[dup, ["case", "band", "quantity", "order", "sideband"]].head(4)
        raise ValueError(f"{int(dup.sum())} tidy rows share case, band, quantity, order and "
                         f"sideband, e.g. {rows.to_dict('records')}")
    return df.sort_values(sort, kind="stable").reset_index(drop=True)


def _case_ids(df: pd.DataFrame, cases: Iterable[CaseId]) -> list[CaseId]:
    """The typed case of each row (its ``case`` column names one of ``cases``)."""
    by_name = {c.name: c for c in cases}
    missing = sorted(set(df["case"]) - set(by_name))
    if missing:
        raise ValueError(f"rows of case(s) {missing[:3]} that are not cases of the sweep")
    return [by_name[c] for c in df["case"]]


def add_location(df: pd.DataFrame, cases: Iterable[CaseId]) -> pd.DataFrame:
    """``df`` with a ``location`` column after ``depth_um`` (``inner_race``, ``outer_race``,
    ``rolling_element``) from the typed cases its ``case`` column names, when a case has one (a
    sweep over locations, or a scene's location other than the inner race); else ``df``
    unchanged, so the default sweep's tables stay as they were.

    Parameters
    ----------
    df : pandas.DataFrame
        With a ``case`` column.
    cases : iterable of CaseId
        The sweep's cases.

    Returns
    -------
    pandas.DataFrame
        A new table with the ``location`` column, or ``df`` itself when no case has one.
    """
    locations = [c.location for c in _case_ids(df, cases)]
    if all(loc is None for loc in locations):
        return df
    df = df.drop(columns=["location"], errors="ignore")
    df.insert(list(df.columns).index("depth_um") + 1, "location", locations)
    return df


def add_width(df: pd.DataFrame, cases: Iterable[CaseId]) -> pd.DataFrame:
    """``df`` with a ``width_um`` column after ``depth_um`` (the defect width of a sweep over
    widths, NaN for the healthy race) from the typed cases its ``case`` column names, when one
    has a width; else ``df`` unchanged.

    Parameters
    ----------
    df : pandas.DataFrame
        With a ``case`` column.
    cases : iterable of CaseId
        The sweep's cases.

    Returns
    -------
    pandas.DataFrame
        A new table with the ``width_um`` column (um), or ``df`` itself when no case has a
        width.
    """
    widths = [c.width_um for c in _case_ids(df, cases)]
    if all(w is None for w in widths):
        return df
    df = df.drop(columns=["width_um"], errors="ignore")
    df.insert(list(df.columns).index("depth_um") + 1, "width_um",
              [np.nan if w is None else w for w in widths])
    return df


def band_table(bands: Iterable) -> pd.DataFrame:
    """One row per case and band from :class:`bearing_envelope.io.CaseBands` objects.

    Columns :data:`bearing_envelope.io.BAND_TABLE_COLUMNS`: ``case, load_kN, depth_um, band,
    strategy, low_hz, high_hz, clamped``, in the order given.

    Parameters
    ----------
    bands : iterable of bearing_envelope.io.CaseBands
        Each case's chosen bands (``case``, ``load_kN``, ``depth_um`` and ``bands``, whose
        items have ``name``, ``strategy``, ``low_hz``, ``high_hz`` in Hz and ``clamped``).

    Returns
    -------
    pandas.DataFrame
        One row per case and band, cases and bands in the order given (no columns when
        ``bands`` is empty).
    """
    rows = []
    for doc in bands:
        for b in doc.bands:
            rows.append({"case": doc.case, "load_kN": doc.load_kN, "depth_um": doc.depth_um,
                         "band": b.name, "strategy": b.strategy, "low_hz": b.low_hz,
                         "high_hz": b.high_hz, "clamped": b.clamped})
    return pd.DataFrame(rows)


def pivot_tables(tidy: pd.DataFrame, *, sideband: int = 0) -> dict[str, pd.DataFrame]:
    """Load x depth pivot of every (band, quantity, order) at one sideband index.

    With a ``location`` column (a sweep over defect locations) there is one pivot per location
    that has the quantity, named with ``__{location}`` (each location searches its own family:
    ``envelope_bpfi``, ``envelope_bpfo``, ``envelope_2bsf``). With a ``width_um`` column (a
    sweep over defect widths) there is one pivot per width, named with ``__w{width}``; the
    healthy race (no width) is depth 0 of each. Every cell holds exactly one amplitude: two
    rows for one cell raise ``ValueError`` (nothing is dropped).

    Parameters
    ----------
    tidy : pandas.DataFrame
        The sweep's tidy table (:func:`concat_tidy`): ``band``, ``quantity``, ``order``,
        ``sideband``, ``load_kN``, ``depth_um`` and ``amplitude``, and ``location`` or
        ``width_um`` where the sweep has them.
    sideband : int, keyword-only, default 0
        The sideband index pivoted (0 = the lines themselves).

    Returns
    -------
    dict
        ``"{band}__{quantity}__{order}[__{location}][__w{width}]"`` -> DataFrame indexed by
        load (kN), columns depth (um).
    """
    sel = tidy[tidy["sideband"] == sideband]
    out: dict[str, pd.DataFrame] = {}
    for (band, quantity, order), g in sel.groupby(["band", "quantity", "order"], sort=True):
        stem = f"{band}__{quantity}__{order:g}"
        groups = [(stem, g)]
        if "location" in g.columns:
            groups = [(f"{stem}__{loc}", gl) for loc, gl in g.groupby("location", sort=False)]
        for name, gg in groups:
            out.update(_width_pivots(gg, name))
    return out


def _width_pivots(g: pd.DataFrame, name: str) -> dict[str, pd.DataFrame]:
    """One pivot of ``g`` named ``name``, or one per width (``__w{width}``) when ``g`` has a
    ``width_um`` column; the healthy race (no width) is depth 0 of each."""
    if "width_um" not in g.columns:
        return {name: _pivot(g, name)}
    healthy = g[g["width_um"].isna()]
    return {f"{name}__w{format_number(w)}": _pivot(pd.concat([healthy, gw]),
                                                   f"{name}__w{format_number(w)}")
            for w, gw in g[g["width_um"].notna()].groupby("width_um", sort=True)}


def _pivot(g: pd.DataFrame, name: str) -> pd.DataFrame:
    """Load x depth pivot of ``g`` (one amplitude per cell, else ``ValueError``)."""
    dup = g.duplicated(["load_kN", "depth_um"], keep=False)
    if dup.any():
        cells = sorted(set(zip(g.loc[dup, "load_kN"], g.loc[dup, "depth_um"])))
        raise ValueError(f"pivot {name}: {len(cells)} load x depth cell(s) hold more than one "
                         f"amplitude, e.g. (load_kN, depth_um) = {cells[:3]}; a sweep axis is "
                         f"missing from the table")
    p = g.pivot(index="load_kN", columns="depth_um", values="amplitude")
    p.index.name = "load_kN"
    p.columns.name = "depth_um"
    return p


def table_html(tables, title: str, caption: str = "") -> str:
    """A self-contained HTML page showing tables (the report's viewable tables).

    Parameters
    ----------
    tables : mapping
        Section title -> DataFrame, shown in order.
    title, caption : str
        Page title and a paragraph under it (HTML-escaped; no paragraph for an empty caption).

    Returns
    -------
    str
        The page: one table per section (section headings only when there are several), no
        index column, floats to 6 significant digits, NaN as an empty cell.
    """
    style = ("body{font-family:sans-serif;font-size:12px;margin:1em}"
             "table{border-collapse:collapse;margin-bottom:1.5em}"
             "td,th{border:1px solid #bbb;padding:2px 5px;text-align:right}th{background:#eee}")
    parts = [f"<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{html.escape(title)}"
             f"</title><style>{style}</style></head><body><h1>{html.escape(title)}</h1>"]
    if caption:
        parts.append(f"<p>{html.escape(caption)}</p>")
    for name, df in tables.items():
        if len(tables) > 1:
            parts.append(f"<h2>{html.escape(str(name))}</h2>")
        parts.append(df.to_html(index=False, float_format=lambda v: f"{v:.6g}", na_rep="",
                                border=0))
    parts.append("</body></html>\n")
    return "\n".join(parts)
