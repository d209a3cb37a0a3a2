"""Measured vibration records: read one file safely, list many, name a bearing.

Everything here refuses what it cannot read faithfully, with one line that names the file (or
the option) and what is allowed, instead of guessing:

- CSV: the delimiter (``,`` ``;`` tab ``|`` or blanks) and the decimal mark (``.`` or ``,``) are
  detected from the first lines; a file where ``,`` may be either (``0,037719`` on every line)
  is refused unless ``delimiter``/``decimal`` settle it, so a decimal fraction never becomes a
  number of its own.
- ``.npy``: the header's shape and dtype are checked against the file size (a truncated file
  or a lying header never allocates what it claims) and the memory the analysis will need
  against the memory available, before any sample is read (the samples are memory-mapped and
  only the chosen channel is copied). Never unpickled (``allow_pickle=False``).
- ``.npz``: the members' headers are read first (no array is loaded to find the signal);
  empty, truncated and corrupt archives are refused.
- MATLAB ``.mat`` (v4-v7): CWRU's layout ``X###_DE_time`` / ``_FE_time`` / ``_BA_time`` with
  ``X###RPM`` (channel chosen by ``channel``, default DE; the shaft rate from the RPM), or any
  variable named with ``column``.
- ``.wav`` (``scipy.io.wavfile``): the sampling rate from the file, integer PCM as counts.
- a case file ``.h5`` of ``bearing-envelope simulate``.

Complex, boolean and object data are refused (an imaginary part is never dropped silently).

Bearings named by designation or alias come from the bearing catalogue
(:func:`bearing_envelope.physics.catalogue.bearing_geometry`, ``data/bearings.yaml``): ``6205``
is ``SKF 6205-2RS``, ``6203`` is ``SKF 6203``. Analysing what is read: :mod:`bearing_envelope.io.analysis`.
"""

# pandas (CSV) and scipy.io (.mat, .wav) are imported by the reader that needs them: reading an
# .npy or .npz needs neither, and they cost ~0.5-1 s of start-up.
from __future__ import annotations

import csv
import json
import math
import os
import re
import stat
import tokenize
import zipfile
import zlib

import numpy as np
from numpy.lib import format as npf

from .. import io as _io  # read_case looked up at call time (callers may substitute it)
from ..physics.catalogue import bearing_geometry  # the one resolver of bearing names
from .records_csv import _TIME_NAMES, _column_index, _csv_lines, _fs_from_time, _guess_sep, _pick, _read_csv, sniff_csv

#: The channel read from a record holding several when none is named: the drive end (CWRU's
#: ``X###_DE_time``), and the signal read from a simulated case file: the peak pressure.
DEFAULT_CHANNEL = "DE"
DEFAULT_SIGNAL = "p_max"

__all__ = ["DEFAULT_CHANNEL", "DEFAULT_SIGNAL", "SUFFIXES", "MEMORY_FACTOR", "MAX_MAGNITUDE",
           "RATE_AGREEMENT", "read_record", "sniff_csv", "read_manifest", "collect_records",
           "check_memory"]

#: File types :func:`read_record` reads.
SUFFIXES = (".csv", ".npy", ".npz", ".mat", ".wav", ".h5", ".hdf5")

#: Peak memory of one analysis per byte of float64 samples: issue 22's tester measured 5.1 GB
#: RSS for a 268 MB ``.npy`` (19x); 4 M samples (32 MB) took 1.0 GB peak RSS here, 0.7 GB above
#: a short record's (22x). The check uses 24x.
MEMORY_FACTOR = 24.0

_FS_NAMES = ("fs", "Fs", "FS", "sampling_rate", "sample_rate", "sampling_frequency")
_FR_NAMES = ("fr", "shaft_hz", "shaft_rate_hz")
_RPM_NAMES = ("rpm", "RPM")
_MM_PER_INCH = 25.4


# ------------------------------------------------------------------------------ values
def _human_bytes(n: float) -> str:
    for unit in ("B", "kB", "MB", "GB", "TB"):
        if n < 1000 or unit == "TB":
            return f"{n:.3g} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1000.0
    return f"{n:.3g} TB"  # pragma: no cover


def _check_dtype(dtype, path: str, what: str) -> None:
    """Refuse complex, boolean, object and non-numeric data (one line naming the file)."""
    dtype = np.dtype(dtype)
    if dtype.hasobject:
        raise ValueError(f"file: {path}: {what} holds Python objects (reading them would need "
                         f"unpickling, which is refused); allowed: real numbers")
    if dtype.kind == "c":
        raise ValueError(f"file: {path}: {what} holds complex values ({dtype}); allowed: real "
                         f"numbers (pass the real part or the magnitude explicitly)")
    if dtype.kind == "b":
        raise ValueError(f"file: {path}: {what} holds booleans; allowed: real numbers")
    if dtype.kind not in "iuf":
        raise ValueError(f"file: {path}: {what} holds {dtype} data; allowed: real numbers")


def available_memory() -> int | None:
    """Bytes of memory available now (``MemAvailable`` of ``/proc/meminfo``), or None.

    Returns
    -------
    int or None
        Available memory (bytes); None where ``/proc/meminfo`` is missing or unreadable (not
        Linux).
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def check_memory(n_samples: int, path: str, *, available: int | None = None) -> None:
    """Refuse a record whose analysis would need more memory than is available.

    Parameters
    ----------
    n_samples : int
        Samples of the signal to analyse.
    path : str
        The file, for the message.
    available : int, optional
        Bytes available (default :func:`available_memory`; unknown: no check).

    Raises
    ------
    ValueError
        The analysis would need more memory than is available (the message says how much).
    """
    need = MEMORY_FACTOR * 8.0 * n_samples
    avail = available_memory() if available is None else available
    if avail is not None and need > avail:
        raise ValueError(f"file: {path}: analysing its {n_samples} samples needs about "
                         f"{_human_bytes(need)} of memory ({MEMORY_FACTOR:g} x the "
                         f"{_human_bytes(8.0 * n_samples)} of float64 samples), "
                         f"{_human_bytes(avail)} available; cut the record into shorter pieces")


def _real_vector(a, path: str, what: str) -> np.ndarray:
    """A 1-D float64 copy of a (dtype checked first)."""
    a = np.asarray(a)
    _check_dtype(a.dtype, path, what)
    return np.array(a, dtype=np.float64).ravel()


# --------------------------------------------------------------------------------- .npy
def _npy_header(fh, path: str, what: str):
    """(shape, fortran_order, dtype) of an open ``.npy`` stream (left after the header)."""
    try:
        version = npf.read_magic(fh)
        if version == (1, 0):
            shape, fortran, dtype = npf.read_array_header_1_0(fh)
        elif version == (2, 0):
            shape, fortran, dtype = npf.read_array_header_2_0(fh)
        elif version == (3, 0):   # 2.0's layout with a UTF-8 header: no public reader
            shape, fortran, dtype = npf.read_array_header_2_0(fh)
        else:
            raise ValueError(f"format version {version[0]}.{version[1]}; allowed: 1.0, 2.0, "
                             f"3.0")
    except (ValueError, EOFError, OSError, SyntaxError, tokenize.TokenError) as exc:
        raise ValueError(f"file: {path}: {what} has no valid .npy header "
                         f"({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})"
                         ) from None
    _check_dtype(dtype, path, what)
    return tuple(int(d) for d in shape), bool(fortran), np.dtype(dtype)


def _check_size(shape, dtype, have: int, path: str, what: str) -> None:
    """The data after a ``.npy`` header must be exactly what the header claims: fewer bytes
    is a truncated file, more a header that hides samples (both refused)."""
    need = math.prod(shape) * dtype.itemsize
    if need > have:
        raise ValueError(f"file: {path}: {what} has a header that claims shape {shape} of "
                         f"{dtype} ({_human_bytes(need)}) but only {_human_bytes(have)} of data "
                         f"follow; the file is truncated or its header is wrong")
    if need < have:
        raise ValueError(f"file: {path}: {what} has a header that claims shape {shape} of "
                         f"{dtype} ({_human_bytes(need)}) but {_human_bytes(have)} of data "
                         f"follow; the header is wrong (samples would be left out)")


def _channel_of(shape, column, path: str) -> tuple[int | None, int]:
    """(channel index or None, samples) of an array of ``shape`` (1-D, or 2-D channels)."""
    if len(shape) > 2 or (len(shape) == 1 and column is not None) or len(shape) == 0:
        opt = "--column" if column is not None else "file"
        raise ValueError(f"{opt}: {path} holds a {len(shape)}-D array of shape {shape}; "
                         f"allowed: a 1-D signal (without --column) or a 2-D array of "
                         f"channels (--column = channel index)")
    if len(shape) == 1:
        return None, shape[0]
    n_ch = min(shape)
    if column is None and n_ch > 1:
        raise ValueError(f"--column: {path} holds a 2-D array of shape {shape} "
                         f"({n_ch} channels); choose one with --column INDEX")
    idx = 0 if column is None else _column_index(column, n_ch, path, "channel")
    return idx, max(shape)


def _take(a, idx):
    if idx is None:
        return a
    return a[:, idx] if a.shape[0] >= a.shape[1] else a[idx]


def _read_npy(path, column) -> dict:
    with open(path, "rb") as fh:
        shape, fortran, dtype = _npy_header(fh, path, "the array")
        offset = fh.tell()
    _check_size(shape, dtype, os.path.getsize(path) - offset, path, "the array")
    idx, n = _channel_of(shape, column, path)
    check_memory(n, path)
    a = np.load(path, mmap_mode="r", allow_pickle=False) if math.prod(shape) else \
        np.load(path, allow_pickle=False)
    return {"x": _real_vector(_take(a, idx), path, "the array"), "source": "npy"}


# --------------------------------------------------------------------------------- .npz
def _npz_members(zf: zipfile.ZipFile, path: str) -> dict:
    """``name -> (shape, dtype)`` of every ``.npy`` member, from the headers only."""
    out = {}
    for info in zf.infolist():
        if not info.filename.endswith(".npy"):
            continue
        name = info.filename[:-4]
        with zf.open(info) as fh:
            try:
                version = npf.read_magic(fh)
                shape, _, dtype = (npf.read_array_header_1_0(fh) if version == (1, 0)
                                   else npf.read_array_header_2_0(fh))
            except (ValueError, EOFError, SyntaxError, tokenize.TokenError) as exc:
                raise ValueError(f"file: {path}: member {name!r} has no valid .npy header "
                                 f"({exc})") from None
            if not np.dtype(dtype).hasobject:
                _check_size(tuple(shape), np.dtype(dtype), info.file_size - fh.tell(), path,
                            f"member {name!r}")
        out[name] = (tuple(int(d) for d in shape), np.dtype(dtype))
    return out


def _read_npz(path, column, fs=None) -> dict:
    try:
        with zipfile.ZipFile(path) as zf:
            members = _npz_members(zf, path)
        if not members:
            raise ValueError(f"file: {path} holds no arrays; allowed: an .npz with a real "
                             f"signal vector (and optionally fs)")
        with np.load(path, allow_pickle=False) as z:
            return _from_npz(z, members, column, path, fs)
    except (zipfile.BadZipFile, zipfile.LargeZipFile, EOFError, OSError, zlib.error) as exc:
        raise ValueError(f"file: {path} is not a readable .npz (truncated or corrupt: "
                         f"{exc})") from None


def _from_npz(z, members: dict, column, path: str, fs=None) -> dict:
    _check_rate_shapes(members, path)
    small = {k: z[k] for k, (shape, dt) in members.items()
             if math.prod(shape) <= 1 and dt.kind in "iuf"}
    out = _scalars(small, path)
    meta = members.get("meta_json")
    if meta is not None:
        if meta[1].kind != "U" or math.prod(meta[0]) != 1:
            raise ValueError(f"file: {path}: 'meta_json' holds {meta[1]} of shape {meta[0]}; "
                             f"allowed: one JSON text (or no meta_json)")
        out.update(_meta(z["meta_json"], out, path))
    name = _choose(members, column, path)
    shape, dt = members[name]
    _check_dtype(dt, path, f"variable {name!r}")
    if sum(d > 1 for d in shape) > 1:
        raise ValueError(f"file: {path}: variable {name!r} has shape {shape}; allowed: one "
                         f"signal (a vector; save one channel per variable)")
    check_memory(math.prod(shape), path)
    out["x"] = _real_vector(z[name], path, f"variable {name!r}")
    if out["fs"] is None and fs is None:
        for k, (shape, _) in members.items():
            if k.lower() in _TIME_NAMES and math.prod(shape) == out["x"].size:
                out["fs"] = _fs_from_time(np.ravel(z[k]), path)
    out["source"] = f"npz:{name}"
    return out


def _check_rate_shapes(members: dict, path: str) -> None:
    """Refuse an entry named as a rate (``fs``, ``shaft_hz``, ``rpm``...) that is not one
    number: it names the entry and its shape instead of taking it for a signal."""
    for k, (shape, dt) in members.items():
        if k in _FS_NAMES + _FR_NAMES + _RPM_NAMES and (math.prod(shape) != 1
                                                        or dt.kind not in "iuf"):
            raise ValueError(f"file: {path}: {k!r} holds {dt} of shape {shape}; allowed: one "
                             f"real number (a rate, {'rpm' if k in _RPM_NAMES else 'Hz'})")


def _choose(members: dict, column, path: str) -> str:
    cands = [k for k, (shape, dt) in members.items()
             if dt.kind in "iufcb" and math.prod(shape) > 1 and k.lower() not in _TIME_NAMES]
    return _pick(cands if column is None else list(members), column, "variable", path)


#: Relative difference above which two entries of one file that give the same rate (``fs``
#: and ``sampling_rate``; ``fr``, ``shaft_hz`` and ``rpm`` / 60; ``meta_json``'s ``shaft_hz``)
#: contradict each other: the file is refused instead of one being picked. 1e-3 lets an rpm
#: written to the unit (1797 rpm for 29.95 Hz) agree with its rate in Hz.
RATE_AGREEMENT = 1e-3


def _scalars(arrays: dict, path: str) -> dict:
    """fs and fr (Hz) from scalar entries (``fs``, ``fr``/``shaft_hz``, ``rpm``); entries that
    give the same rate must agree (:data:`RATE_AGREEMENT`), else the file is refused naming
    both."""
    out: dict = {"fs": None, "fr": None}
    seen: dict = {"fs": None, "fr": None}   # key -> (entry, value as written)
    for names, key, scale in ((_FS_NAMES, "fs", 1.0), (_FR_NAMES, "fr", 1.0),
                              (_RPM_NAMES, "fr", 1.0 / 60.0)):
        for k in names:
            if k in arrays and np.size(arrays[k]) == 1:
                v = np.asarray(arrays[k])
                if v.dtype.kind in "iuf":
                    value = float(v.ravel()[0])
                    if out[key] is None:
                        out[key], seen[key] = value * scale, (k, value)
                    else:
                        _agree(seen[key], out[key], (k, value), value * scale, path)
    return out


def _agree(first: tuple, first_hz: float, other: tuple, other_hz: float, path: str) -> None:
    """Refuse two entries of one file that give the same rate differently (one line, both
    named with their values)."""
    same = first_hz == other_hz or (math.isfinite(first_hz) and math.isfinite(other_hz) and
                                    abs(first_hz - other_hz) <= RATE_AGREEMENT
                                    * max(abs(first_hz), abs(other_hz)))
    if not same:
        raise ValueError(f"file: {path}: {first[0]!r} = {first[1]!r} and {other[0]!r} = "
                         f"{other[1]!r} contradict each other ({first_hz:g} vs {other_hz:g} "
                         f"Hz); allowed: entries that agree within {RATE_AGREEMENT:g}, or one "
                         f"of them")


def _meta(raw, out: dict, path: str) -> dict:
    """The shaft rate of a ``meta_json`` entry (``shaft_hz``) when no scalar gave one; a
    ``meta_json`` that is not a JSON object is refused (one line), never ignored."""
    try:
        meta = json.loads(str(np.asarray(raw).ravel()[0]))
    except RecursionError:
        raise ValueError(f"file: {path}: 'meta_json' is nested too deeply to read; allowed: a "
                         f"JSON object (or no meta_json)") from None
    except (ValueError, TypeError) as exc:
        raise ValueError(f"file: {path}: 'meta_json' is not valid JSON ({exc}); allowed: a JSON "
                         f"object (or no meta_json)") from None
    if not isinstance(meta, dict):
        raise ValueError(f"file: {path}: 'meta_json' holds a JSON {type(meta).__name__}; "
                         f"allowed: a JSON object (or no meta_json)")
    fr = meta.get("shaft_hz")
    if fr is None:
        return {}
    if isinstance(fr, bool) or not isinstance(fr, (int, float)):
        raise ValueError(f"file: {path}: 'meta_json' shaft_hz = {fr!r}; allowed: a shaft rate "
                         f"> 0 (Hz, a number) or no shaft_hz")
    if out.get("fr") is not None:   # a scalar gave one: they must agree
        _agree(("fr (Hz)", out["fr"]), out["fr"], ("meta_json shaft_hz", fr), float(fr), path)
        return {}
    # a non-positive or non-finite rate is returned as the file gives it: the consumer names
    # it and its allowed range ("the file gives fr = -29.95; pass a shaft rate > 0 ...")
    return {"fr": float(fr)}


# --------------------------------------------------------------------------------- .mat
_CWRU_VAR = re.compile(r"^X(\d+)_(DE|FE|BA)_time$")
_CWRU_RPM = re.compile(r"^X(\d+)RPM$")


def _read_mat(path, column, channel, fs=None) -> dict:
    from scipy.io import loadmat

    try:
        m = {k: v for k, v in loadmat(path).items() if not k.startswith("__")}
    except NotImplementedError:
        raise ValueError(f"file: {path} is a MATLAB v7.3 (HDF5) file; allowed: v4-v7 .mat "
                         f"(save with -v7)") from None
    except Exception as exc:  # scipy raises ValueError, TypeError, MatReadError, ... on junk
        raise ValueError(f"file: {path} is not a readable MATLAB .mat file "
                         f"({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
                         ) from None
    out = _scalars(m, path)
    cwru = {k: _CWRU_VAR.match(k) for k in m}
    cwru = {k: mt for k, mt in cwru.items() if mt}
    if column is None and cwru:
        name = _cwru_pick(cwru, channel, path)
        number = cwru[name].group(1)
        rpm = [v for k, v in m.items() if (mt := _CWRU_RPM.match(k)) and mt.group(1) == number]
        if rpm and np.size(rpm[0]) == 1 and out["fr"] is None:
            if np.asarray(rpm[0]).dtype.kind not in "iuf":
                raise ValueError(f"file: {path}: variable 'X{number}RPM' holds "
                                 f"{np.asarray(rpm[0]).dtype} data; allowed: one number (rpm)")
            out["fr"] = float(np.asarray(rpm[0]).ravel()[0]) / 60.0
    else:
        cands = [k for k, v in m.items() if isinstance(v, np.ndarray) and v.dtype.kind in "iufcb"
                 and v.size > 1 and k.lower() not in _TIME_NAMES]
        name = _pick(cands if column is None else list(m), column, "variable", path)
    shape = np.shape(m[name])
    if sum(d > 1 for d in shape) > 1:
        raise ValueError(f"file: {path}: variable {name!r} has shape {shape}; allowed: one "
                         f"signal (a vector; save one channel per variable)")
    out["x"] = _real_vector(m[name], path, f"variable {name!r}")
    if out["fs"] is None and fs is None:   # the caller's rate: no time vector read
        for k in m:
            if k.lower() in _TIME_NAMES and np.size(m[k]) == out["x"].size:
                out["fs"] = _fs_from_time(np.ravel(m[k]), path)
    out["source"] = f"mat:{name}"
    return out


def _cwru_pick(cwru: dict, channel: str, path: str) -> str:
    names = [k for k, mt in cwru.items() if mt.group(2) == channel]
    if not names:
        have = sorted({mt.group(2) for mt in cwru.values()})
        raise ValueError(f"--channel: {path} has no {channel} channel (X###_{channel}_time); "
                         f"it has {', '.join(have)}")
    if len(names) > 1:  # a few CWRU files hold two records: prefer the file's own number
        digits = re.findall(r"\d+", os.path.basename(path))
        own = [k for k in names if cwru[k].group(1).lstrip("0") in
               {d.lstrip("0") for d in digits}]
        if len(own) == 1:
            return own[0]
        raise ValueError(f"--column: {path} holds several {channel} records "
                         f"({', '.join(sorted(names))}); choose one with --column")
    return names[0]


# --------------------------------------------------------------------------------- .wav
def _wav_truncation(path: str) -> str | None:
    """Why a WAV file is shorter than its chunks say (None when every chunk is whole): the
    RIFF walk scipy does, without reading the samples."""
    size = os.path.getsize(path)
    with open(path, "rb") as fh:
        head = fh.read(12)
        if len(head) < 12 or head[:4] not in (b"RIFF", b"RIFX") or head[8:12] != b"WAVE":
            return None  # not a plain RIFF WAVE: scipy's reader reports it
        order = "little" if head[:4] == b"RIFF" else "big"
        pos = 12
        while pos + 8 <= size:
            fh.seek(pos)
            chunk = fh.read(8)
            n = int.from_bytes(chunk[4:8], order)
            if pos + 8 + n > size:
                return (f"its '{chunk[:4].decode('latin-1')}' chunk declares {n:,} bytes but "
                        f"{size - pos - 8:,} follow")
            pos += 8 + n + (n & 1)
    return None


def _read_wav(path, column) -> dict:
    from scipy.io import wavfile

    short = _wav_truncation(path)
    if short is not None:
        raise ValueError(f"file: {path} is a truncated WAV file ({short}); allowed: a whole "
                         f"recording")
    try:
        fs, a = wavfile.read(path, mmap=False)
    except Exception as exc:  # scipy raises ValueError, EOFError, struct.error, ... on junk
        raise ValueError(f"file: {path} is not a readable WAV file "
                         f"({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})"
                         ) from None
    idx = None
    if a.ndim > 1 or column is not None:
        idx, _ = _channel_of(a.shape, column, path)
    return {"x": _real_vector(_take(a, idx), path, "the audio"), "fs": float(fs),
            "source": "wav" if idx is None else f"wav:{idx}"}


# --------------------------------------------------------------------------------- case
def _read_case(path, signal) -> dict:
    case = _io.read_case(path)
    signals = dict(getattr(case, "signals", {}) or {})
    if signal not in signals and getattr(case, signal, None) is not None:
        signals[signal] = getattr(case, signal)
    if signal not in signals:
        raise ValueError(f"--signal: {path} has no signal {signal!r} (available: "
                         f"{', '.join(sorted(signals))})")
    return {"x": _real_vector(signals[signal], path, f"signal {signal!r}"), "fs": float(case.fs),
            "fr": float(case.fr), "bpfi": float(case.bpfi), "source": f"case:{signal}"}


# --------------------------------------------------------------------------------- entry
def read_record(path: str, *, column=None, channel: str = DEFAULT_CHANNEL,
                signal: str = DEFAULT_SIGNAL,
                delimiter: str | None = None, decimal: str | None = None,
                fs: float | None = None) -> dict:
    """Read one record and what the file says about it.

    Parameters
    ----------
    path : str
        ``.csv``, ``.npy``, ``.npz``, ``.mat``, ``.wav`` or a case file ``.h5``.
    column : str or int, optional
        CSV column (name or 0-based index), ``.npz``/``.mat`` variable, channel index of a
        2-D ``.npy`` or a multi-channel ``.wav``.
    channel : {"DE", "FE", "BA"}
        Accelerometer of a CWRU ``.mat`` file (drive end, fan end, base).
    signal : str
        Signal of a case file.
    delimiter, decimal : str, optional
        Force the CSV dialect (see :func:`sniff_csv`).
    fs : float, optional
        The caller's sampling rate (Hz, ``--fs``): a time column is then not read for one (nor
        refused when not uniform). The returned ``fs`` stays the file's (None here).

    Returns
    -------
    dict
        ``{"x": float64 ndarray, "fs": float | None, "fr": float | None, "bpfi": float |
        None, "source": str}``.

    Raises
    ------
    ValueError
        One line naming the file (``file: PATH ...``) or the option, and what is allowed.
    FileNotFoundError
        No such file.
    """
    if not os.path.exists(path):
        raise FileNotFoundError(f"no such file: {path}")
    if os.path.isdir(path):
        raise ValueError(f"file: {path!r} is a directory; allowed: a signal file")
    _check_regular(path)
    ext = os.path.splitext(path)[1].lower()
    if ext in (".h5", ".hdf5"):
        return _read_case(path, signal)
    readers = {".csv": lambda: _read_csv(path, column, delimiter, decimal, fs),
               ".npy": lambda: _read_npy(path, column),
               ".npz": lambda: _read_npz(path, column, fs),
               ".mat": lambda: _read_mat(path, column, channel, fs),
               ".wav": lambda: _read_wav(path, column)}
    if ext not in readers:
        raise ValueError(f"file: {path}: unsupported file type {ext!r}; allowed: "
                         f"{', '.join(SUFFIXES)}")
    out = {"fs": None, "fr": None, "bpfi": None}
    out.update(readers[ext]())
    _check_magnitude(out["x"], path)
    return out


def _check_regular(path: str) -> None:
    """Refuse what is not a regular file (after its symlinks): a FIFO blocks the reader
    forever, a device (``/dev/zero``) never ends; one line naming the file and what it is."""
    mode = os.stat(path).st_mode
    if not stat.S_ISREG(mode):
        kind = ("a FIFO" if stat.S_ISFIFO(mode) else "a character device" if stat.S_ISCHR(mode)
                else "a block device" if stat.S_ISBLK(mode) else "a socket"
                if stat.S_ISSOCK(mode) else "not a regular file")
        raise ValueError(f"file: {path} is {kind}; allowed: a regular signal file")


#: Largest |sample| a record may hold (and 1/MAX_MAGNITUDE the smallest peak): the analysis
#: squares the samples and takes fourth powers (kurtosis), which overflow above ~1e77 and lose
#: their digits in the subnormals; 1e50 keeps the fourth powers of 1e8 samples finite and
#: normal, and holds any physical unit (m to nm, g, Pa).
MAX_MAGNITUDE = 1e50


def _check_magnitude(x: np.ndarray, path: str) -> None:
    """Refuse, before any work, finite samples whose scale the analysis cannot carry (their
    squares overflow or underflow): one line with the peak and the allowed range."""
    finite = x[np.isfinite(x)]
    peak = float(np.max(np.abs(finite))) if finite.size else 0.0
    if peak > MAX_MAGNITUDE or 0.0 < peak < 1.0 / MAX_MAGNITUDE:
        raise ValueError(f"file: {path}: samples peak at |x| = {peak:.3g}; allowed: a peak "
                         f"within {1 / MAX_MAGNITUDE:g}-{MAX_MAGNITUDE:g} (rescale the record: "
                         f"its squares over- or underflow)")


# ------------------------------------------------------------------------------ batches
def _is_manifest(path: str) -> bool:
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as fh:
            first = fh.readline()
    except OSError:
        return False
    return "file" in [t.strip().strip('"').lower() for t in re.split(r"[,;\t|]", first)]


def collect_records(paths) -> list[str]:
    """Files of ``paths``: files as given, folders expanded (sorted, non-recursive) to the
    files of :data:`SUFFIXES`, leaving out a folder's CSV manifests (a header with a ``file``
    column).

    Parameters
    ----------
    paths : iterable of str or os.PathLike
        Files and folders.

    Returns
    -------
    list of str
        The record files, in the order given (a folder's sorted).

    Raises
    ------
    ValueError
        A folder that holds no record file.
    """
    out: list[str] = []
    for p in paths:
        if os.path.isdir(p):
            found = sorted(os.path.join(p, f) for f in os.listdir(p)
                           if os.path.splitext(f)[1].lower() in SUFFIXES
                           and os.path.isfile(os.path.join(p, f)))
            found = [f for f in found if not (f.lower().endswith(".csv") and _is_manifest(f))]
            if not found:
                raise ValueError(f"file: folder {p} holds no record; allowed: "
                                 f"{', '.join(SUFFIXES)} files")
            out.extend(found)
        else:
            out.append(p)
    return out


_MANIFEST_NUM = {"fs": ("fs", "fs_hz", "sampling_rate"),
                 "fr": ("fr", "fr_hz", "shaft_hz", "shaft_rate_hz"),
                 "rpm": ("rpm", "rpm_nominal", "shaft_rpm")}


def read_manifest(path: str) -> list[dict]:
    """Rows of a CSV manifest: ``file`` (relative to the manifest's folder) and optionally
    ``fs`` (Hz), ``fr`` / ``shaft_hz`` (Hz) or ``rpm`` / ``rpm_nominal``, ``bearing``
    (designation, :func:`bearing_geometry`), ``column``, ``channel``.

    Returns
    -------
    list of dict
        ``{"file", "fs", "fr", "bearing", "column", "channel"}`` (None where not given).

    Parameters
    ----------
    path : str
        The manifest (CSV with a ``file`` column).

    Raises
    ------
    ValueError
        No such manifest, an empty one, one without a ``file`` column, or a row with an empty
        ``file``.
    """
    if not os.path.isfile(path):
        raise ValueError(f"--manifest: no such file: {path}")
    try:
        lines = _csv_lines(path)
    except ValueError as exc:   # not UTF-8 text: the manifest is named, not a record
        raise ValueError(f"--manifest: {str(exc).replace('file: ', '', 1)}") from None
    if not lines:
        raise ValueError(f"--manifest: {path} is empty; allowed: a CSV with a 'file' column")
    sep = _guess_sep(lines)
    sep = "," if sep == r"\s+" else sep
    with open(path, encoding="utf-8-sig", newline="") as fh:
        rows = list(csv.DictReader(fh, delimiter=sep))
    if not rows or "file" not in [(k or "").strip().lower() for k in rows[0]]:
        raise ValueError(f"--manifest: {path} has no 'file' column; allowed columns: file, fs, "
                         f"fr (or shaft_hz, rpm), bearing, column, channel")
    base = os.path.dirname(os.path.abspath(path))
    return [_manifest_row(row, i + 2, path, base) for i, row in enumerate(rows)]


def _manifest_row(row: dict, line: int, path: str, base: str) -> dict:
    row = {(k or "").strip().lower(): (v or "").strip() for k, v in row.items()}
    if not row.get("file"):
        raise ValueError(f"--manifest: {path} line {line}: empty 'file'")
    out = {"file": os.path.join(base, row["file"]), "fs": None, "fr": None,
           "bearing": row.get("bearing") or None, "column": row.get("column") or None,
           "channel": (row.get("channel") or None)}
    for key, names in _MANIFEST_NUM.items():
        for n in names:
            if row.get(n):
                try:
                    v = float(row[n])
                except ValueError:
                    v = math.nan
                if not (math.isfinite(v) and v > 0):
                    raise ValueError(f"--manifest: {path} line {line}: {n} = {row[n]!r}; "
                                     f"allowed: a number > 0")
                out[key] = v
                break
    rpm = out.pop("rpm", None)
    if out["fr"] is None and rpm is not None:
        out["fr"] = rpm / 60.0
    if out["channel"] is not None and out["channel"].upper() not in ("DE", "FE", "BA"):
        raise ValueError(f"--manifest: {path} line {line}: channel = {out['channel']!r}; "
                         f"allowed: DE, FE, BA")
    if out["channel"] is not None:
        out["channel"] = out["channel"].upper()
    if out["bearing"] is not None:
        try:
            bearing_geometry(out["bearing"])
        except ValueError as exc:
            raise ValueError(f"--manifest: {path} line {line}: "
                             f"{str(exc).replace('bearing: ', '', 1)}") from None
    return out
