"""The analysis of recordings *from files*: :func:`analyze_record` and :func:`analyze_records`
accept a path (or an array) and read it with :func:`read_task`
(:func:`bearing_envelope.io.records.read_record`).

No decision is taken here: every one is :mod:`bearing_envelope.diagnosis.records`' (this module
only binds the reader, which the diagnosis layer may not import). Importing this module imports
the analysis chain (numpy, scipy, numba, pandas); ``import bearing_envelope.io`` does not.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

from ..diagnosis import batch as _batch
from ..diagnosis import records as _records
from .records import DEFAULT_CHANNEL, DEFAULT_SIGNAL, read_record

__all__ = ["read_task", "analyze_record", "analyze_records"]


def read_task(item, *, column=None, channel: str = DEFAULT_CHANNEL, signal: str = DEFAULT_SIGNAL,
              delimiter: str | None = None, decimal: str | None = None) -> dict:
    """Read one record: a path, or a task mapping ``{"file", "column", "channel"}`` whose
    non-None values override the keyword arguments.

    Parameters
    ----------
    item : str, path-like or mapping
        The file, or a task (a manifest row).
    column, channel, signal, delimiter, decimal
        As :func:`bearing_envelope.io.records.read_record`.

    Returns
    -------
    dict
        The record (:func:`~bearing_envelope.io.records.read_record`).
    """
    if isinstance(item, Mapping):
        path = os.fspath(item["file"])
        column = item.get("column") or column
        channel = item.get("channel") or channel
    else:
        path = os.fspath(item)
    return read_record(path, column=column, channel=channel, signal=signal,
                       delimiter=delimiter, decimal=decimal)


def analyze_record(path_or_array, fs: float | None = None, **kwargs):
    """Analyse one record given as a file or as samples.

    Parameters
    ----------
    path_or_array : str, path-like, array_like or mapping
        A file (``.csv``, ``.npy``, ``.npz``, ``.mat``, ``.wav``, case file ``.h5``), the
        samples, or a record already read.
    fs : float, optional
        Sampling frequency, Hz (default the file's).
    **kwargs
        As :func:`bearing_envelope.diagnosis.records.analyze_record` (``shaft_hz``,
        ``bearing``, ``bpfi``, ``faults``, ``options``, ``fixed_band``, ``clamp``, ``name``,
        ``names``); ``reader`` defaults to :func:`read_task`.

    Returns
    -------
    RecordAnalysis
    """
    kwargs.setdefault("reader", read_task)
    return _records.analyze_record(path_or_array, fs, **kwargs)


def analyze_records(items, fs: float | None = None, **kwargs) -> list:
    """Analyse many records (files, arrays or tasks), in parallel, in input order.

    Parameters
    ----------
    items : iterable
        Paths, arrays, records already read, or task mappings (:func:`read_task`).
    fs : float, optional
        Sampling frequency, Hz (default each file's).
    **kwargs
        As :func:`bearing_envelope.diagnosis.batch.analyze_records` (``jobs``, ``shaft_hz``,
        ``bearing``, ``options``, ``figure_dir``, ...); ``reader`` defaults to
        :func:`read_task`.

    Returns
    -------
    list
        ``RecordAnalysis`` or ``RecordFailure`` per item.
    """
    kwargs.setdefault("reader", read_task)
    return _batch.analyze_records(items, fs, **kwargs)
