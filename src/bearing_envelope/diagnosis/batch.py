"""Many records at once: :func:`analyze_records`, in parallel, results in input order.

Each record runs through :func:`~bearing_envelope.diagnosis.records.analyze_record` (in this
process with ``jobs=1``, else in a pool of forked processes); a record that cannot be read or
analysed becomes a :class:`~bearing_envelope.diagnosis.records.RecordFailure` with its one-line
reason and the others still run. The results come back in input order, so a table made of them
does not depend on ``jobs``.

Threads: for ``jobs > 1`` each worker should run single-threaded. The thread-count variables
(``OMP_NUM_THREADS``, ``OPENBLAS_NUM_THREADS``, ``NUMBA_NUM_THREADS``, ...) are read when numpy
and numba load, so a program sets them to 1 before it imports numpy; ``bearing-envelope analyze
--jobs N`` does (``commands/_analyze_batch.py: single_threaded``).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping
from dataclasses import replace

import numpy as np

from .defect_size import size_document
from .records import RecordFailure, analyze_record
from ..lazy import lazy_module

pd = lazy_module("pandas")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["one_line", "analyze_item", "analyze_records", "record_figure", "verdict_table"]

#: Per-record keys of a mapping item that override the call's arguments.
_ITEM_KEYS = ("fs", "shaft_hz", "bearing", "name")


def one_line(exc: BaseException) -> str:
    """The first line of an exception's message (``OSError``: reason and file).

    Parameters
    ----------
    exc : BaseException
        The exception a record raised.

    Returns
    -------
    str
        ``strerror: filename`` for an ``OSError``, the key for a ``KeyError``, the first
        line of a ``ValueError``'s message, else ``TypeName: first line``.
    """
    if isinstance(exc, OSError) and exc.strerror:
        return f"{exc.strerror}: {exc.filename}" if exc.filename else exc.strerror
    if isinstance(exc, KeyError) and exc.args:
        return str(exc.args[0])
    text = str(exc).strip().splitlines()
    msg = text[0] if text else ""
    if isinstance(exc, (ValueError, OSError)):
        return msg or type(exc).__name__
    return f"{type(exc).__name__}: {msg}" if msg else type(exc).__name__


def _split(item, index: int) -> tuple[object, dict]:
    """``(what analyze_record reads, per-record arguments)`` of one item."""
    if isinstance(item, (str, os.PathLike)):
        path = os.fspath(item)
        return path, {"file": path}
    if isinstance(item, Mapping) and "x" not in item:  # a task: {"file", "fs", ...}
        if item.get("file") is None:
            raise ValueError(f"item {index}: a mapping needs 'x' (a record read) or 'file' "
                             f"(a task); got keys {sorted(item)}")
        path = os.fspath(item["file"])
        per = {k: item[k] for k in _ITEM_KEYS if item.get(k) is not None}
        return item, {"file": path, **per}
    if isinstance(item, Mapping):
        return item, {"file": item.get("file"), "name": item.get("name")}
    return item, {"name": f"record_{index}"}


def record_figure(res, fig_dir: str, figure_options: Mapping | None = None) -> str:
    """Write the analyst figure of one record (:func:`~bearing_envelope.diagnosis.plots.
    save_record_figure`), ``{name}_analysis.png`` in ``fig_dir``.

    Parameters
    ----------
    res : RecordAnalysis
        With its samples and spectra (not compact).
    fig_dir : str
        Folder of the figure.
    figure_options : mapping, optional
        ``db``, ``fmax``, ``orders``.

    Returns
    -------
    str
        The path written.
    """
    from .plots import save_record_figure  # matplotlib: only when figures are asked for

    stem = res.name or os.path.splitext(os.path.basename(res.file))[0]
    return save_record_figure(res.signal, res.details, os.path.join(
        fig_dir, f"{stem}_analysis.png"), n_harmonics=res.options.n_harmonics,
        title=res.file, **dict(figure_options or {}))


def analyze_item(item, *, reader: Callable | None = None, index: int = 0, **kwargs):
    """One item of :func:`analyze_records`, analysed in full (samples and spectra kept).

    Parameters
    ----------
    item : array_like, mapping or path
        As an item of :func:`analyze_records`: a task mapping's non-None ``fs``, ``shaft_hz``,
        ``bearing``, ``name`` win over ``kwargs``; ``reader`` reads a path or a task.
    reader : callable, optional
        ``reader(path_or_task) -> record mapping``.
    index : int, default 0
        Position of the item (the name ``record_{index}`` of an array).
    **kwargs
        The arguments of :func:`~bearing_envelope.diagnosis.records.analyze_record`.

    Returns
    -------
    RecordAnalysis
        The full analysis of the item, its samples and spectra kept (for plots).

    Raises
    ------
    ValueError
        A path item without a ``reader``.
    """
    signal, per = _split(item, index)
    if isinstance(signal, Mapping) and "x" not in signal:  # a task: the reader reads it
        if reader is None:
            raise ValueError(f"file: {per['file']}: a path needs a reader")
        signal = reader(signal)
    return analyze_record(signal, reader=reader, **{**kwargs, **per})


def _work(index: int, item, kwargs: dict, reader, fig_dir, figure_options):
    """One record: analysed (and drawn), compact; any error becomes a failure (one line)."""
    per: dict = {"name": f"item_{index}"}
    try:
        _, per = _split(item, index)
        res = analyze_item(item, reader=reader, index=index, **kwargs)
        res = replace(res, defect_size=size_document(res))   # needs the samples: before compact
        if fig_dir is not None:
            res = replace(res, figure=record_figure(res, fig_dir, figure_options))
        return res.compact()
    except (ValueError, KeyError, OSError, MemoryError) as exc:
        return RecordFailure(per.get("file"), per.get("name"), one_line(exc))
    except Exception as exc:  # noqa: BLE001 - one bad record must not stop the batch
        return RecordFailure(per.get("file"), per.get("name"),
                             f"internal error: {one_line(exc)}")


def _warm_up(fig_dir) -> None:
    """Load the kurtogram's compiled kernel (and matplotlib) once in the parent, so that the
    forked workers inherit them (~0.4 s of numba cache per process otherwise). Results do not
    change."""
    from ..signal.kurtogram import fast_kurtogram

    if fig_dir is not None:
        import matplotlib.backends.backend_agg  # noqa: F401
        import matplotlib.figure  # noqa: F401

        from . import plots  # noqa: F401
    fast_kurtogram(np.random.default_rng(0).standard_normal(4096), 1000.0, 2)


def _results(items, kwargs, reader, fig_dir, figure_options, jobs):
    """``(index, result)`` as the records finish."""
    if jobs <= 1:
        for i, item in enumerate(items):
            yield i, _work(i, item, kwargs, reader, fig_dir, figure_options)
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    _warm_up(fig_dir)
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else None)
    with ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
        futures = {pool.submit(_work, i, item, kwargs, reader, fig_dir, figure_options): i
                   for i, item in enumerate(items)}
        for fut in as_completed(futures):
            yield futures[fut], fut.result()


def analyze_records(items: Iterable, fs: float | None = None, *, jobs: int = 1,
                    reader: Callable | None = None, figure_dir: str | None = None,
                    figure_options: Mapping | None = None,
                    progress: Callable[[], None] | None = None, **kwargs) -> list:
    """Analyse many records, in parallel; one result per item, in input order.

    Parameters
    ----------
    items : iterable
        Each an array, a record already read (a mapping with ``"x"``), a path (needs
        ``reader``), or a task mapping ``{"file", "fs", "shaft_hz", "bearing", "name", ...}``
        whose non-None values override the call's for that record (``reader`` receives the
        whole task: a manifest row's column or channel is the reader's business).
    fs : float, optional
        Sampling frequency of every record (default each record's).
    jobs : int, default 1
        Records analysed in parallel, one process each (0: one per CPU).
    reader : callable, optional
        ``reader(path_or_task) -> record mapping``
        (:func:`bearing_envelope.io.records.read_record`, or a closure of it); picklable
        (a module-level function or a ``functools.partial``) when ``jobs > 1``.
    figure_dir : str, optional
        Write each record's analyst figure there (``{name}_analysis.png``).
    figure_options : mapping, optional
        ``db``, ``fmax``, ``orders`` of the figure.
    progress : callable, optional
        Called once per finished record (a progress bar's ``update``).
    **kwargs
        The arguments of :func:`~bearing_envelope.diagnosis.records.analyze_record`
        (``shaft_hz``, ``bearing``, ``bpfi``, ``faults``, ``options``, ``fixed_band``,
        ``clamp``, ``names``).

    Returns
    -------
    list
        :class:`~bearing_envelope.diagnosis.records.RecordAnalysis` (compact: no samples, no
        spectra) or :class:`~bearing_envelope.diagnosis.records.RecordFailure` per item.
    """
    items = list(items)
    jobs = max(1, min(jobs or os.cpu_count() or 1, len(items) or 1))
    kwargs = dict(kwargs, fs=fs)
    out: list = [None] * len(items)
    for i, res in _results(items, kwargs, reader, figure_dir, figure_options, jobs):
        out[i] = res
        if progress is not None:
            progress()
    return out


def verdict_table(results: Iterable) -> pd.DataFrame:
    """The verdict table of many results (each :meth:`RecordAnalysis.to_frame` or failure
    row), in order.

    Parameters
    ----------
    results : iterable of RecordAnalysis or RecordFailure
        The records analysed, in the order of the table.

    Returns
    -------
    pandas.DataFrame
        One row per record and fault family (the columns of
        :func:`~bearing_envelope.diagnosis.records.record_rows`), one row per failure
        (``status`` ``error`` and its reason).
    """
    return pd.DataFrame.from_records([row for r in results for row in r.rows])
