"""The analysis of recordings *from files*: :func:`analyze_file` and :func:`analyze_files` are
:func:`~bearing_envelope.diagnosis.records.analyze_record` and
:func:`~bearing_envelope.diagnosis.batch.analyze_records` that also accept a path and read it
with :func:`read_task` (:func:`bearing_envelope.io.records.read_record`).

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

__all__ = ["read_task", "analyze_file", "analyze_files"]


def read_task(item, *, column=None, channel: str = DEFAULT_CHANNEL, signal: str = DEFAULT_SIGNAL,
              delimiter: str | None = None, decimal: str | None = None,
              fs: float | None = None) -> dict:
    """Read one record: a path, or a task mapping ``{"file", "column", "channel"}`` whose
    non-None values override the keyword arguments.

    Parameters
    ----------
    item : str, path-like or mapping
        The file, or a task (a manifest row).
    column, channel, signal, delimiter, decimal
        As :func:`bearing_envelope.io.records.read_record`.
    fs : float, optional
        The caller's sampling rate, Hz (a task's own ``fs`` wins): the file's time column is
        then not read for one (:func:`~bearing_envelope.io.records.read_record`).

    Returns
    -------
    dict
        The record (:func:`~bearing_envelope.io.records.read_record`).
    """
    if isinstance(item, Mapping):
        path = os.fspath(item["file"])
        column = item.get("column") or column
        channel = item.get("channel") or channel
        fs = item.get("fs") or fs
    else:
        path = os.fspath(item)
    return read_record(path, column=column, channel=channel, signal=signal,
                       delimiter=delimiter, decimal=decimal, fs=fs)


def analyze_file(path_or_array, fs: float | None = None, **kwargs):
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
        The record's rates (Hz), bands, line table, verdict per fault family and spectra.

    Examples
    --------
    A CSV record with a time column (fs read from it): a synthetic inner-race fault of a
    6205 at 29.95 Hz, impacts at BPFI (162.19 Hz) ringing at 3 kHz in noise:

    >>> import os, tempfile
    >>> import numpy as np
    >>> from bearing_envelope.io.analysis import analyze_file
    >>> fs, fr, bpfi = 12000.0, 29.95, 162.19
    >>> t = np.arange(2**15) / fs
    >>> tau = t % (1 / bpfi)
    >>> x = ((1 + 0.5 * np.cos(2 * np.pi * fr * t)) * np.exp(-tau / 2e-3)
    ...      * np.sin(2 * np.pi * 3000 * tau)
    ...      + 0.3 * np.random.default_rng(0).standard_normal(t.size))
    >>> path = os.path.join(tempfile.mkdtemp(), "record.csv")
    >>> np.savetxt(path, np.column_stack([t, x]), delimiter=",", header="time_s,accel",
    ...            comments="")
    >>> res = analyze_file(path, shaft_hz=fr, bearing="6205")
    >>> round(res.fs), res.n_samples, res.verdict.diagnosis.family
    (12000, 32768, 'bpfi')
    """
    kwargs.setdefault("reader", read_task)
    return _records.analyze_record(path_or_array, fs, **kwargs)


def analyze_files(items, fs: float | None = None, **kwargs) -> list:
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
