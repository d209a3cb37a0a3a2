"""Sweep artefacts other than the case file: bands + kurtogram, spectra, sensor case, tables.

Every artefact has a write_*/read_* pair, a format version (:data:`ARTEFACT_FORMATS`) and is
written through a temporary file in the target directory, then renamed (:mod:`.atomic`).
Layouts: ``docs/file-format.md``. Nothing here knows where the workflow puts the files.
"""

from __future__ import annotations

import io as _io
import json
import os
import shutil as _shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path as _Path

import numpy as np

from .. import __version__
from .atomic import atomic_path, write_csv_atomic
from .case import git_commit, jsonable, read_case
from .integrity import (CHECKSUM_OPTIONS, DiskFullError, estimate_h5_bytes, is_disk_full,
                        require_free_space, seal, free_bytes, write_image, seal_text,
                        unseal_text)
from .vocabulary import BAND_TABLE_COLUMNS, CASE_TABLE_COLUMNS, TIDY_COLUMNS

__all__ = [
    "ARTEFACT_FORMATS", "ArtefactFormatError",
    "BandLimits", "CaseBands", "write_bands", "read_bands",
    "KurtogramMap", "write_kurtogram", "read_kurtogram",
    "CaseSpectra", "write_spectra", "read_spectra",
    "SensorSignal", "SENSOR_SUFFIXES", "check_sensor_output", "write_sensor_case", "read_sensor",
    "write_tidy", "read_tidy", "write_case_table", "read_case_table",
    "write_band_table", "read_band_table", "write_pivots", "read_pivots",
]

#: Format version of each artefact layout; a reader accepts only its own version.
ARTEFACT_FORMATS = {
    "bands": 1,       # JSON: band limits of one case (+ best kurtogram cell)
    "kurtogram": 1,   # NPZ: kurtogram matrix of one case
    "spectra": 1,     # NPZ: raw and envelope spectra of one case
    "sensor": 1,      # HDF5 case file + signals/acceleration, or NPZ
    "tables": 1,      # CSV: tidy harmonics, cases, bands, pivots (version = the column set)
}


class ArtefactFormatError(ValueError):
    """A file is not the artefact its reader expects (format name, version or content)."""


def _check_format(path, doc_format, doc_version, artefact: str) -> None:
    want = f"bearing_envelope.{artefact}"
    if doc_format != want:
        raise ArtefactFormatError(f"{path}: not a {artefact} file (format {doc_format!r}, "
                                  f"expected {want!r})")
    if doc_version != ARTEFACT_FORMATS[artefact]:
        raise ArtefactFormatError(f"{path}: {artefact} format_version {doc_version!r} is not "
                                  f"supported (this reader: {ARTEFACT_FORMATS[artefact]})")


def _exists(path) -> str:
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"file not found: {path}")
    return path


# ------------------------------------------------------------------------------- bands (JSON)
@dataclass(frozen=True)
class BandLimits:
    """One demodulation band of one case.

    Attributes
    ----------
    name : str
        The band's name (``analysis.bands[].name``).
    strategy : str
        How it was chosen: ``kurtogram``, ``fraction``, ``orders`` or ``fixed``.
    low_hz, high_hz : float
        Band edges (Hz) after clamping.
    clamped : bool
        The upper edge was clamped below Nyquist.
    provenance : dict
        What :func:`bearing_envelope.signal.resolve_band` reported (JSON-able).
    """

    name: str
    strategy: str
    low_hz: float
    high_hz: float
    clamped: bool = False
    provenance: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The band as a JSON-ready mapping.

        Returns
        -------
        dict
            ``name, strategy, low_hz, high_hz, clamped, ...`` as JSON-ready values.
        """
        return {"name": self.name, "strategy": self.strategy, "low_hz": float(self.low_hz),
                "high_hz": float(self.high_hz), "clamped": bool(self.clamped),
                "provenance": jsonable(self.provenance)}


@dataclass(frozen=True)
class CaseBands:
    """Band limits of one case (the ``bands`` artefact; :func:`bearing_envelope.study.pipeline.case_bands`).

    Attributes
    ----------
    case : str
        Case name.
    load_kN, depth_um : float
        The case's sweep values.
    fs : float
        Sampling rate (Hz).
    signal : str
        The analysed signal (``p_max``, ``p_max_defect``, ``acceleration``).
    bands : tuple of BandLimits
        In the order of ``analysis.bands``.
    kurtogram : dict or None
        Best kurtogram cell (``level``, ``fc``, ``bandwidth``, ``kurtosis``; Hz), None when no
        band uses the kurtogram.
    """

    case: str
    load_kN: float
    depth_um: float
    fs: float
    signal: str
    bands: tuple
    kurtogram: dict | None = None

    def band(self, name: str) -> BandLimits:
        """The band called ``name`` (KeyError naming the bands held otherwise).

        Parameters
        ----------
        name : str
            A band's name (``kurtogram``, ``fs4_3fs8``, ...).

        Returns
        -------
        BandLimits
            That band's limits.

        Raises
        ------
        KeyError
            The case has no band ``name`` (the message lists its bands).
        """
        for b in self.bands:
            if b.name == name:
                return b
        raise KeyError(f"{self.case}: no band {name!r}; bands: {[b.name for b in self.bands]}")

    def to_dict(self) -> dict:
        """The JSON document of the case's bands.

        Returns
        -------
        dict
            The JSON document of :func:`write_bands` (format, version, case, bands).
        """
        return {"format": "bearing_envelope.bands", "format_version": ARTEFACT_FORMATS["bands"],
                "case": self.case, "load_kN": float(self.load_kN), "depth_um": float(self.depth_um),
                "fs": float(self.fs), "signal": self.signal,
                "kurtogram": None if self.kurtogram is None else
                {k: float(v) for k, v in self.kurtogram.items()},
                "bands": [b.to_dict() for b in self.bands]}

    @classmethod
    def from_dict(cls, doc) -> CaseBands:
        """The case's bands from a document made by :meth:`to_dict`.

        Parameters
        ----------
        doc : dict
            A document made by :meth:`to_dict` (read from JSON).

        Returns
        -------
        CaseBands
            The case's band limits.
        """
        return cls(case=str(doc["case"]), load_kN=float(doc["load_kN"]),
                   depth_um=float(doc["depth_um"]), fs=float(doc["fs"]), signal=str(doc["signal"]),
                   bands=tuple(BandLimits(name=b["name"], strategy=b["strategy"],
                                          low_hz=float(b["low_hz"]), high_hz=float(b["high_hz"]),
                                          clamped=bool(b.get("clamped", False)),
                                          provenance=dict(b.get("provenance", {})))
                               for b in doc["bands"]),
                   kurtogram=None if doc.get("kurtogram") is None else dict(doc["kurtogram"]))


def write_bands(path: str | os.PathLike, bands: CaseBands) -> str:
    """Write a case's band limits as JSON (atomic). Returns the path.

    Parameters
    ----------
    path : str or os.PathLike
        The JSON file to write.
    bands : CaseBands
        The case's band limits.

    Returns
    -------
    str
        ``path``.
    """
    with atomic_path(path, ".json") as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(bands.to_dict(), fh, indent=1)
    return os.fspath(path)


def read_bands(path: str | os.PathLike) -> CaseBands:
    """Read a file written by :func:`write_bands`.

    Parameters
    ----------
    path : str or os.PathLike
        A file written by :func:`write_bands`.

    Returns
    -------
    CaseBands
        The case's band limits.

    Raises
    ------
    FileNotFoundError, ArtefactFormatError
    """
    path = _exists(path)
    try:
        with open(path, encoding="utf-8") as fh:
            doc = json.load(fh)
    except json.JSONDecodeError as exc:
        raise ArtefactFormatError(f"{path}: not JSON ({exc})") from exc
    if not isinstance(doc, dict):
        raise ArtefactFormatError(f"{path}: not a bands file (a JSON object expected)")
    _check_format(path, doc.get("format"), doc.get("format_version"), "bands")
    try:
        return CaseBands.from_dict(doc)
    except (KeyError, TypeError, ValueError) as exc:
        raise ArtefactFormatError(f"{path}: bands file lacks or mistypes a field ({exc!r})") from exc


# --------------------------------------------------------------------------- kurtogram (NPZ)
@dataclass(frozen=True)
class KurtogramMap:
    """The kurtogram of one case as stored (enough to draw it).

    Attributes
    ----------
    matrix : ndarray, shape (n_levels, n_freqs)
        Kurtosis of every cell, repeated over the columns each band spans.
    levels : ndarray
        Level of each row.
    freqs : ndarray
        Centre frequency of each column (Hz).
    level, fc, bandwidth, kurtosis : float
        The best cell (Hz for ``fc`` and ``bandwidth``).
    """

    matrix: np.ndarray
    levels: np.ndarray
    freqs: np.ndarray
    level: float
    fc: float
    bandwidth: float
    kurtosis: float


def write_kurtogram(path: str | os.PathLike, kurtogram) -> str:
    """Write a kurtogram (:class:`bearing_envelope.signal.Kurtogram` or :class:`KurtogramMap`) as
    compressed NPZ (keys ``matrix``, ``levels``, ``freqs``, ``best`` = level, fc, bandwidth,
    kurtosis); ``None`` writes a file holding no kurtogram (no band uses one).

    Parameters
    ----------
    path : str or os.PathLike
        The NPZ file to write.
    kurtogram : Kurtogram, KurtogramMap or None
        The kurtogram (``None``: none was computed).

    Returns
    -------
    str
        ``path``.
    """
    arrays = {"format": np.array("bearing_envelope.kurtogram"),
              "format_version": np.array(ARTEFACT_FORMATS["kurtogram"])}
    if kurtogram is not None:
        arrays.update(matrix=np.asarray(kurtogram.matrix), levels=np.asarray(kurtogram.levels),
                      freqs=np.asarray(kurtogram.freqs),
                      best=np.array([kurtogram.level, kurtogram.fc, kurtogram.bandwidth,
                                     kurtogram.kurtosis], dtype=float))
    with atomic_path(path, ".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays)
    return os.fspath(path)


def _load_npz(path, artefact):
    path = _exists(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise ArtefactFormatError(f"{path}: not an NPZ file ({exc})") from exc
    fmt = str(arrays.pop("format")) if "format" in arrays else None
    ver = int(arrays.pop("format_version")) if "format_version" in arrays else None
    _check_format(path, fmt, ver, artefact)
    return path, arrays


def read_kurtogram(path: str | os.PathLike) -> KurtogramMap | None:
    """Read a file written by :func:`write_kurtogram` (None if it holds no kurtogram).

    Parameters
    ----------
    path : str or os.PathLike
        A file written by :func:`write_kurtogram`.

    Returns
    -------
    KurtogramMap or None
        The kurtogram's map and best cell, or None.

    Raises
    ------
    ArtefactFormatError
        The file lacks an array of the kurtogram.
    """
    path, a = _load_npz(path, "kurtogram")
    if "matrix" not in a:
        return None
    missing = [k for k in ("levels", "freqs", "best") if k not in a]
    if missing:
        raise ArtefactFormatError(f"{path}: kurtogram file lacks {missing}")
    best = a["best"]
    return KurtogramMap(matrix=a["matrix"], levels=a["levels"], freqs=a["freqs"],
                        level=float(best[0]), fc=float(best[1]), bandwidth=float(best[2]),
                        kurtosis=float(best[3]))


# ----------------------------------------------------------------------------- spectra (NPZ)
@dataclass(frozen=True)
class CaseSpectra:
    """Spectra of one case (what the figures draw).

    Attributes
    ----------
    raw_f, raw_a : ndarray (float32)
        Raw one-sided amplitude spectrum: frequencies (Hz) and amplitudes (signal units).
    envelope : dict
        Band name -> ``(f, amplitude)`` of its envelope spectrum (Hz, signal units; squared units
        for a squared envelope), kept up to a maximum frequency chosen by the writer.
    """

    raw_f: np.ndarray
    raw_a: np.ndarray
    envelope: dict = field(default_factory=dict)


def write_spectra(path: str | os.PathLike, spectra: CaseSpectra) -> str:
    """Write a case's spectra as compressed NPZ: keys ``raw_f``, ``raw_a`` and, per band,
    ``env_<band>_f``, ``env_<band>_a``; ``bands`` lists the band names in order.

    Parameters
    ----------
    path : str or os.PathLike
        The NPZ file to write.
    spectra : CaseSpectra
        The raw spectrum and the envelope spectrum of every band.

    Returns
    -------
    str
        ``path``.
    """
    arrays = {"format": np.array("bearing_envelope.spectra"),
              "format_version": np.array(ARTEFACT_FORMATS["spectra"]),
              "bands": np.array(list(spectra.envelope), dtype=str),
              "raw_f": np.asarray(spectra.raw_f), "raw_a": np.asarray(spectra.raw_a)}
    for name, (f, a) in spectra.envelope.items():
        arrays[f"env_{name}_f"] = np.asarray(f)
        arrays[f"env_{name}_a"] = np.asarray(a)
    with atomic_path(path, ".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays)
    return os.fspath(path)


def read_spectra(path: str | os.PathLike) -> CaseSpectra:
    """Read a file written by :func:`write_spectra`.

    Parameters
    ----------
    path : str or os.PathLike
        A file written by :func:`write_spectra`.

    Returns
    -------
    CaseSpectra
        The raw spectrum and the envelope spectrum of every band.

    Raises
    ------
    ArtefactFormatError
        The file lacks an array of the spectra.
    """
    path, a = _load_npz(path, "spectra")
    try:
        names = [str(n) for n in a["bands"]]
        env = {n: (a[f"env_{n}_f"], a[f"env_{n}_a"]) for n in names}
        return CaseSpectra(raw_f=a["raw_f"], raw_a=a["raw_a"], envelope=env)
    except KeyError as exc:
        raise ArtefactFormatError(f"{path}: spectra file lacks the array {exc}") from exc


# ------------------------------------------------------------------------ sensor (HDF5 / NPZ)
#: Output suffixes of :func:`write_sensor_case`.
SENSOR_SUFFIXES = (".h5", ".hdf5", ".npz")


@dataclass(frozen=True)
class SensorSignal:
    """A synthetic accelerometer signal as stored by :func:`write_sensor_case`.

    Attributes
    ----------
    acceleration : ndarray
        The signal (excitation units x mode gain; m/s^2 for gains in (m/s^2)/Pa).
    fs : float
        Sampling rate (Hz).
    provenance : dict
        Transfer model, SNR target and achieved, seed, source case, versions, commit.
    frequencies : dict
        ``fr``, ``bpfi``, ``bpfo``, ``ftf``, ``bsf`` (Hz) and ``load_kN``, ``depth_um`` of the
        source case, where known.
    """

    acceleration: np.ndarray
    fs: float
    provenance: dict
    frequencies: dict = field(default_factory=dict)

    @property
    def time(self) -> np.ndarray:
        """Sample times (s) from 0 at ``1 / fs``, one per sample of :attr:`acceleration`."""
        return np.arange(self.acceleration.size) / self.fs


def check_sensor_output(path: str | os.PathLike) -> str:
    """Return the lower-case suffix of a sensor output path, or raise ValueError naming it.

    Parameters
    ----------
    path : str or os.PathLike
        The output path of a sensor case.

    Returns
    -------
    str
        ``".h5"`` or ``".npz"``.

    Raises
    ------
    ValueError
        A path that ends neither in ``.npz`` nor in ``.h5``.
    """
    suffix = _Path(path).suffix.lower()
    if suffix not in SENSOR_SUFFIXES:
        raise ValueError(f"output must end in .npz or .h5, got {os.fspath(path)!r}")
    return suffix


def _json_default(o):
    if hasattr(o, "tolist"):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def write_sensor_case(path: str | os.PathLike, acceleration, *, case, source=None,
                      provenance: dict | None = None) -> str:
    """Write a synthetic acceleration with its provenance (atomic).

    Parameters
    ----------
    path : path-like
        ``.h5``/``.hdf5``: a copy of the case file ``source`` with the acceleration added as
        ``signals/acceleration`` (readable by :func:`read_case` like any case); ``.npz``: the
        acceleration, time, frequencies and provenance alone.
    acceleration : array_like
        1-D signal at the case's sampling rate.
    case : Case
        The source case (its ``fs``, frequencies and sweep values are recorded).
    source : path-like, optional
        The source case file; required for an HDF5 output.
    provenance : dict, optional
        JSON-able description of how the signal was made; ``package_version``, ``git_commit``
        and ``sensor_format_version`` are added.

    Returns
    -------
    str
        The path written.

    Raises
    ------
    DiskFullError
        Not enough free space (checked before writing, or ENOSPC while writing).
    """
    suffix = check_sensor_output(path)
    acc = np.asarray(acceleration)
    fs = float(case.fs)
    info = dict(provenance or {})
    info.setdefault("package_version", __version__)
    info.setdefault("git_commit", git_commit())
    info["sensor_format_version"] = ARTEFACT_FORMATS["sensor"]
    text = json.dumps(info, default=_json_default, allow_nan=True, sort_keys=True)
    meta = {"fs": fs}
    for key in ("fr", "bpfi", "bpfo", "ftf", "bsf", "load_kN", "depth_um"):
        v = getattr(case, key, None)
        if v is not None:
            meta[key] = float(v)
    needed = estimate_h5_bytes([acc, acc]) + (os.path.getsize(source) if source else 0)
    require_free_space(path, needed)
    try:
        if suffix == ".npz":
            with atomic_path(path, suffix) as tmp:
                with open(tmp, "wb") as fh:
                    np.savez(fh, acceleration=acc, time=np.arange(acc.size) / fs,
                             provenance=np.array(text), format=np.array("bearing_envelope.sensor"),
                             format_version=np.array(ARTEFACT_FORMATS["sensor"]),
                             **{k: np.array(v) for k, v in meta.items()})
            return os.fspath(path)
        image = _sensor_image(acc, fs, text, source)
        with atomic_path(path, suffix) as tmp:
            write_image(tmp, tmp, image)
    except OSError as exc:
        if isinstance(exc, DiskFullError) or not is_disk_full(exc, path):
            raise
        raise DiskFullError(os.fspath(path), needed, free_bytes(path)) from None
    return os.fspath(path)


def _sensor_image(acc, fs: float, text: str, source) -> bytes:
    """The sensor case file's bytes: the case file ``source`` with ``/signals/acceleration``
    added and the digest resealed, built in memory (HDF5 never meets a full disk)."""
    import h5py

    if source is None:
        raise ValueError("write_sensor_case: an .h5 output copies the case file; give source")
    buf = _io.BytesIO(_Path(source).read_bytes())
    with h5py.File(buf, "r+") as h5:
        sg = h5.require_group("signals")
        if "acceleration" in sg:
            del sg["acceleration"]
        d = sg.create_dataset("acceleration", data=acc, compression="gzip", compression_opts=4,
                              shuffle=True, **(CHECKSUM_OPTIONS if acc.size else {}))
        d.attrs["units"] = "excitation units x mode gain (m/s^2 for gains in (m/s^2)/Pa)"
        d.attrs["description"] = "synthetic accelerometer signal (bearing-envelope sensor)"
        d.attrs["provenance"] = text
        if "time" not in h5:
            h5.create_dataset("time", data=np.arange(acc.size) / fs,
                              **(CHECKSUM_OPTIONS if acc.size else {}))
        h5.attrs["sensor_json"] = text
        h5.attrs["sensor_format_version"] = ARTEFACT_FORMATS["sensor"]
        seal(h5)
    return buf.getvalue()


def read_sensor(path: str | os.PathLike) -> SensorSignal:
    """Read the acceleration written by :func:`write_sensor_case` (.h5 or .npz).

    Parameters
    ----------
    path : str or os.PathLike
        A file written by :func:`write_sensor_case`.

    Returns
    -------
    SensorSignal
        The acceleration, its sampling rate and the sensor settings.

    Raises
    ------
    FileNotFoundError, ArtefactFormatError
    """
    path = _exists(path)
    if _Path(path).suffix.lower() == ".npz":
        path, a = _load_npz(path, "sensor")
        if "acceleration" not in a or "fs" not in a:
            raise ArtefactFormatError(f"{path}: sensor file lacks 'acceleration' or 'fs'")
        freqs = {k: float(a[k]) for k in ("fr", "bpfi", "bpfo", "ftf", "bsf", "load_kN", "depth_um")
                 if k in a}
        return SensorSignal(acceleration=a["acceleration"], fs=float(a["fs"]),
                            provenance=json.loads(str(a.get("provenance", "{}"))),
                            frequencies=freqs)
    case = read_case(path)
    ver = case.attrs.get("sensor_format_version")
    _check_format(path, "bearing_envelope.sensor" if "acceleration" in case.signals else None,
                  ver, "sensor")
    freqs = {k: float(getattr(case, k)) for k in ("fr", "bpfi", "bpfo", "ftf", "bsf", "load_kN",
                                                   "depth_um")}
    return SensorSignal(acceleration=case.signals["acceleration"], fs=case.fs,
                        provenance=json.loads(case.attrs.get("sensor_json", "{}")),
                        frequencies=freqs)


# ---------------------------------------------------------------------------- tables (CSV)
def _read_csv(path, required, what, **kwargs):
    import pandas as pd  # lazy: importing io stays ~0.7 s (pandas +1.8 s)

    if isinstance(path, (str, os.PathLike)):   # else an open text buffer
        path = _exists(path)
    try:
        df = pd.read_csv(path, **kwargs)
    except (ValueError, pd.errors.ParserError) as exc:
        raise ArtefactFormatError(f"{path}: not a readable CSV {what} ({exc})") from exc
    missing = [c for c in required if c not in df.columns]
    if missing:
        raise ArtefactFormatError(f"{path}: {what} lacks the columns {missing}")
    return df


def _write_table(path, table, required, what: str) -> str:
    """Write ``table`` as CSV atomically after checking it holds the ``required`` columns."""
    missing = [c for c in required if c not in table.columns]
    if missing:
        raise ValueError(f"{what} lacks the columns {missing}")
    return write_csv_atomic(table, path)


def write_tidy(path: str | os.PathLike, table, *, sealed: bool = False) -> str:
    """Write a tidy harmonic table (per case or aggregated) as CSV, atomically.

    The columns must include :data:`bearing_envelope.study.tables.TIDY_COLUMNS` (ValueError naming the
    missing ones otherwise); extra columns follow them.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file.
    table : pandas.DataFrame
        The table.
    sealed : bool
        Precede the CSV by the line ``# content_sha256=...``
        (:func:`bearing_envelope.io.integrity.seal_text`): the per-case tables, so that an
        edit is found before they are aggregated (:func:`read_tidy` with ``sealed=True``).

    Returns
    -------
    str
        The path.

    Raises
    ------
    ValueError
        The table lacks a column of :data:`~.vocabulary.TIDY_COLUMNS`.
    """
    if not sealed:
        return _write_table(path, table, TIDY_COLUMNS, "tidy table")
    missing = [c for c in TIDY_COLUMNS if c not in table.columns]
    if missing:
        raise ValueError(f"tidy table lacks the columns {missing}")
    with atomic_path(path, ".csv") as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(seal_text(table.to_csv(index=False)))
    return os.fspath(path)


def read_tidy(path: str | os.PathLike, *, sealed: bool = False):
    """Read a tidy harmonic table written by :func:`write_tidy` (DataFrame).

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file.
    sealed : bool
        Require the digest line of ``write_tidy(..., sealed=True)`` and check it.

    Returns
    -------
    pandas.DataFrame
        One row per line (case, band, quantity, order, sideband, frequency in Hz, amplitude
        in the signal's unit, ...): the columns of :data:`~.vocabulary.TIDY_COLUMNS` and the
        optional ones present.

    Raises
    ------
    ArtefactFormatError
        Unreadable, columns missing, or (``sealed``) no digest or a digest that no longer
        matches: the file was edited after it was written.
    """
    if not sealed:
        return _read_csv(path, TIDY_COLUMNS, "tidy harmonic table")
    path = _exists(path)
    with open(path, encoding="utf-8", newline="") as fh:
        text = fh.read()
    try:
        body = unseal_text(text, path)
    except ValueError as exc:
        raise ArtefactFormatError(str(exc)) from None
    return _read_csv(_io.StringIO(body), TIDY_COLUMNS, f"tidy harmonic table {path}")


def write_case_table(path: str | os.PathLike, table) -> str:
    """Write the per-case summary table (one row per case) as CSV, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file to write.
    table : pandas.DataFrame
        One row per case.

    Returns
    -------
    str
        ``path``.
    """
    return _write_table(path, table, CASE_TABLE_COLUMNS, "case table")


def read_case_table(path: str | os.PathLike):
    """Read a table written by :func:`write_case_table` (DataFrame).

    Parameters
    ----------
    path : str or os.PathLike
        A file written by :func:`write_case_table`.

    Returns
    -------
    pandas.DataFrame
        One row per case.
    """
    return _read_csv(path, CASE_TABLE_COLUMNS, "case table")


def write_band_table(path: str | os.PathLike, table) -> str:
    """Write the band table (columns :data:`BAND_TABLE_COLUMNS`) as CSV, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file to write.
    table : pandas.DataFrame
        One row per case and band.

    Returns
    -------
    str
        ``path``.
    """
    return _write_table(path, table, BAND_TABLE_COLUMNS, "band table")


def read_band_table(path: str | os.PathLike):
    """Read a table written by :func:`write_band_table` (DataFrame).

    Parameters
    ----------
    path : str or os.PathLike
        A file written by :func:`write_band_table`.

    Returns
    -------
    pandas.DataFrame
        One row per case and band.
    """
    return _read_csv(path, BAND_TABLE_COLUMNS, "band table")


def write_pivots(directory: str | os.PathLike, pivots: dict) -> str:
    """Write load x depth pivots (``key -> DataFrame``) as ``<directory>/<key>.csv``.

    The files are written into a temporary sibling folder which then replaces ``directory``.

    Parameters
    ----------
    directory : str or os.PathLike
        The folder to (re)place.
    pivots : dict of str to pandas.DataFrame
        File stem -> load x depth pivot.

    Returns
    -------
    str
        ``directory``.
    """
    directory = _Path(directory)
    directory.parent.mkdir(parents=True, exist_ok=True)
    tmp = _Path(tempfile.mkdtemp(prefix=f".tmp-{directory.name}.", dir=directory.parent))
    try:
        for key, table in pivots.items():
            table.to_csv(tmp / f"{key}.csv")
        _public_mode_dir(tmp)
        _shutil.rmtree(directory, ignore_errors=True)
        os.replace(tmp, directory)
    except BaseException:
        _shutil.rmtree(tmp, ignore_errors=True)
        raise
    return os.fspath(directory)


def _public_mode_dir(path) -> None:
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, 0o777 & ~umask)
    for p in _Path(path).iterdir():
        os.chmod(p, 0o666 & ~umask)


def read_pivots(directory: str | os.PathLike) -> dict:
    """Read the pivots written by :func:`write_pivots`: ``key -> DataFrame`` indexed by
    ``load_kN`` with float ``depth_um`` columns.

    Parameters
    ----------
    directory : str or os.PathLike
        A folder written by :func:`write_pivots`.

    Returns
    -------
    dict of str to pandas.DataFrame
        File stem -> pivot.
    """
    import pandas as pd  # lazy: importing io stays ~0.7 s (pandas +1.8 s)

    directory = _exists(directory)
    out = {}
    for p in sorted(_Path(directory).glob("*.csv")):
        t = pd.read_csv(p, index_col="load_kN")
        t.columns = pd.Index([float(c) for c in t.columns], name="depth_um")
        out[p.stem] = t
    return out
