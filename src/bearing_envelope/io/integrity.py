"""Integrity of HDF5 case files: checksums written with the data, verified before use.

Every dataset of a case file (and of a sensor case) that HDF5 can checksum is written with the
Fletcher-32 filter (:data:`CHECKSUM_OPTIONS`): a flipped bit in a chunk makes the read fail.
What the filter cannot cover -- attributes, scalar and empty datasets, variable-length strings --
goes into one SHA-256 digest stored as the root attribute :data:`DIGEST_ATTR`
(:func:`content_digest`). :func:`verify_file` reads every chunk and recomputes the digest: a
file that passes it is the file that was written.

HDF5 files are built in memory and written to disk as bytes (:func:`write_image`): HDF5
itself never meets a full disk (it crashed with SIGSEGV in h5py 3.16 when a flush failed), free
space is checked against the exact size first, and a full disk gives one line naming the path
and the space needed (:class:`DiskFullError`).
"""

from __future__ import annotations

import errno
import hashlib
import os
import shutil

import h5py
import numpy as np

__all__ = ["DIGEST_ATTR", "CHECKSUM_OPTIONS", "DiskFullError", "content_digest", "seal",
           "verify_file", "require_free_space", "free_bytes", "estimate_h5_bytes", "is_disk_full",
           "file_sha256", "write_image", "TEXT_DIGEST_PREFIX", "seal_text", "unseal_text",
           "sealed_text_problem"]

#: Root attribute holding the SHA-256 digest (hex) of :func:`content_digest`.
DIGEST_ATTR = "content_sha256"

#: Dataset-creation options of a checksummed dataset (h5py chooses the chunk shape).
CHECKSUM_OPTIONS = {"fletcher32": True}

#: Bytes of HDF5 overhead per dataset (object header, chunk index, attributes) assumed by
#: :func:`estimate_h5_bytes`; measured: 2-4 KiB per dataset in a case file.
_OVERHEAD_BYTES_PER_DATASET = 8192

#: Free space kept on top of the estimate, bytes (the file system's own bookkeeping).
_FREE_SPACE_MARGIN_BYTES = 1 << 20

_MIB = float(1 << 20)


class DiskFullError(OSError):
    """Not enough free space for a file: one line naming the path, the space needed and free.

    Parameters
    ----------
    path : str
        The file that would not fit; kept as :attr:`path`.
    needed : int
        Bytes the file needs; kept as :attr:`needed`.
    free : int
        Bytes free on its file system; kept as :attr:`free`.
    """

    def __init__(self, path: str, needed: int, free: int):
        super().__init__(errno.ENOSPC, f"{path}: not enough free disk space: needs about "
                         f"{needed / _MIB:.1f} MiB, {free / _MIB:.1f} MiB free on "
                         f"{os.path.dirname(os.path.abspath(path))}")
        self.path, self.needed, self.free = path, needed, free

    def __str__(self) -> str:
        return self.strerror


def _canonical(value) -> bytes:
    """Bytes of an attribute or small dataset value, the same for the written and the read-back
    value (type tag, dtype, shape, data)."""
    if isinstance(value, bytes):
        return b"b:" + value
    if isinstance(value, str):
        return b"s:" + value.encode("utf-8", "surrogatepass")
    arr = np.asarray(value)
    if arr.dtype.kind in "OUS":
        items = [_canonical(v) for v in arr.ravel().tolist()]
        return b"o:" + repr(arr.shape).encode() + b"".join(
            len(i).to_bytes(8, "little") + i for i in items)
    arr = np.ascontiguousarray(arr)
    return b"a:" + arr.dtype.str.encode() + repr(arr.shape).encode() + arr.tobytes()


def _checksummed(ds: h5py.Dataset) -> bool:
    """Whether HDF5 verifies this dataset's data on read (Fletcher-32 on a numeric dtype)."""
    return bool(ds.fletcher32) and ds.dtype.kind not in "OSUV"


def content_digest(f: h5py.File) -> str:
    """SHA-256 (hex) of everything in ``f`` that no Fletcher-32 checksum covers.

    Covers every attribute of every group and dataset (but :data:`DIGEST_ATTR` itself), the
    names and shapes of all datasets, and the values of datasets without a checksum (scalar,
    empty, strings). Objects are visited in sorted order, so the digest does not depend on the
    order of writing.

    Parameters
    ----------
    f : h5py.File
        An open HDF5 file.

    Returns
    -------
    str
        The SHA-256 digest (hex).
    """
    h = hashlib.sha256()
    names: list[str] = []
    f.visit(names.append)
    for name in [""] + sorted(names):
        obj = f[name] if name else f
        h.update(b"\0path:" + name.encode())
        for key in sorted(obj.attrs.keys()):
            if not name and key == DIGEST_ATTR:
                continue
            h.update(b"\0attr:" + key.encode() + b"=" + _canonical(obj.attrs[key]))
        if isinstance(obj, h5py.Dataset):
            h.update(b"\0shape:" + repr(obj.shape).encode() + obj.dtype.str.encode())
            if not _checksummed(obj):
                h.update(b"\0data:" + _canonical(obj[()]))
    return h.hexdigest()


def seal(f: h5py.File) -> str:
    """Store :func:`content_digest` of the open, writable file ``f`` as :data:`DIGEST_ATTR`
    (the last write before closing); returns it.

    Parameters
    ----------
    f : h5py.File
        An open, writable HDF5 file.

    Returns
    -------
    str
        The digest stored.
    """
    f.flush()
    digest = content_digest(f)
    f.attrs[DIGEST_ATTR] = digest
    return digest


def _read_all(ds: h5py.Dataset) -> None:
    """Read every chunk of ``ds`` (HDF5 checks each chunk's Fletcher-32 sum as it reads)."""
    if ds.shape is None or ds.size == 0:
        return
    if ds.chunks is None:
        ds[()]
        return
    for sl in ds.iter_chunks():
        ds[sl]


def verify_file(path: str | os.PathLike, *, require_digest: bool = True) -> str | None:
    """Why the HDF5 file ``path`` is not intact (``None`` when it is).

    Reads every chunk of every dataset (a flipped bit in checksummed data fails the read) and
    recomputes :func:`content_digest` (a changed attribute, name, shape or unchecksummed value
    fails the comparison). Without a stored digest the file is reported unless
    ``require_digest`` is false (files written before checksums existed).

    Parameters
    ----------
    path : str or os.PathLike
        An HDF5 file.
    require_digest : bool
        Report a file without a stored digest.

    Returns
    -------
    str or None
        One line saying what is wrong, or None.
    """
    path = os.fspath(path)
    try:
        with h5py.File(path, "r") as f:
            names: list[str] = []
            f.visit(names.append)
            for name in names:
                obj = f[name]
                if isinstance(obj, h5py.Dataset):
                    try:
                        _read_all(obj)
                    except (OSError, ValueError, RuntimeError) as exc:
                        return (f"dataset '/{name}' fails its checksum or does not read "
                                f"({' '.join(str(exc).split())[:120]})")
            stored = f.attrs.get(DIGEST_ATTR)
            if stored is None:
                return f"no '{DIGEST_ATTR}' attribute (written without checksums)" \
                    if require_digest else None
            stored = stored.decode() if isinstance(stored, bytes) else str(stored)
            actual = content_digest(f)
    except (OSError, KeyError, ValueError, RuntimeError) as exc:
        return f"unreadable HDF5 ({' '.join(str(exc).split())[:160]})"
    if actual != stored:
        return (f"attribute/metadata digest mismatch (stored {stored[:12]}..., computed "
                f"{actual[:12]}...): an attribute or small dataset changed after writing")
    return None


def estimate_h5_bytes(arrays) -> int:
    """Upper estimate of the bytes of an HDF5 file holding ``arrays`` uncompressed, plus
    per-dataset overhead (compression only makes the file smaller).

    Parameters
    ----------
    arrays : iterable of numpy.ndarray
        The datasets the file will hold.

    Returns
    -------
    int
        Bytes.
    """
    arrays = list(arrays)
    return int(sum(np.asarray(a).nbytes for a in arrays)
               + _OVERHEAD_BYTES_PER_DATASET * (len(arrays) + 1))


def require_free_space(path: str | os.PathLike, needed: int) -> None:
    """Raise :class:`DiskFullError` when the file system of ``path``'s folder has less than
    ``needed`` bytes (plus a 1 MiB margin) free.

    Parameters
    ----------
    path : str or os.PathLike
        The file about to be written.
    needed : int
        Bytes it needs.

    Raises
    ------
    DiskFullError
        Fewer bytes free than ``needed`` plus a safety margin.
    """
    path = os.fspath(path)
    free = free_bytes(path)
    if free < needed + _FREE_SPACE_MARGIN_BYTES:
        raise DiskFullError(path, needed + _FREE_SPACE_MARGIN_BYTES, free)


def is_disk_full(exc: BaseException, path: str | os.PathLike) -> bool:
    """Whether ``exc`` (raised while writing next to ``path``) means the disk is full: errno
    ENOSPC/EDQUOT, or an HDF5 write error while the file system has < 1 MiB left.

    Parameters
    ----------
    exc : BaseException
        The exception raised while writing.
    path : str or os.PathLike
        The file being written.

    Returns
    -------
    bool
        True when the disk (or the quota) is full.
    """
    if isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT):
        return True
    if not isinstance(exc, (OSError, RuntimeError)):
        return False
    return free_bytes(path) < _FREE_SPACE_MARGIN_BYTES


def free_bytes(path: str | os.PathLike) -> int:
    """Free bytes on the file system that will hold ``path`` (its nearest existing folder);
    0 when that cannot be told.

    Parameters
    ----------
    path : str or os.PathLike
        A path that may not exist yet.

    Returns
    -------
    int
        Free bytes available to this (unprivileged) writer, 0 when unknown.
    """
    folder = os.path.dirname(os.path.abspath(os.fspath(path)))
    while folder and not os.path.isdir(folder):
        parent = os.path.dirname(folder)
        if parent == folder:
            break
        folder = parent
    try:
        return shutil.disk_usage(folder).free
    except OSError:
        return 0


def file_sha256(path: str | os.PathLike) -> str:
    """SHA-256 (hex) of a file's bytes (e.g. a measured profile a case depends on).

    Parameters
    ----------
    path : str or os.PathLike
        Any file.

    Returns
    -------
    str
        The SHA-256 digest (hex).
    """
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def write_image(tmp: str | os.PathLike, path: str | os.PathLike, data: bytes) -> None:
    """Write the finished file ``data`` to ``tmp``, sync it, and rename it to ``path``.

    Free space is checked against ``len(data)`` first; ENOSPC while writing raises
    :class:`DiskFullError` as well. ``tmp`` is removed on any failure.

    Parameters
    ----------
    tmp : str or os.PathLike
        The temporary file to write (next to ``path``).
    path : str or os.PathLike
        The final file.
    data : bytes
        The file's whole content.

    Raises
    ------
    DiskFullError
        Not enough free space (ENOSPC while writing); nothing is left behind.
    """
    tmp, path = os.fspath(tmp), os.fspath(path)
    try:
        require_free_space(path, len(data))
        with open(tmp, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, DiskFullError):
            raise
        if is_disk_full(exc, path):
            raise DiskFullError(path, len(data), free_bytes(path)) from None
        raise


#: First line of a sealed text file (a per-case table): the SHA-256 of every line after it.
TEXT_DIGEST_PREFIX = "# content_sha256="


def seal_text(body: str) -> str:
    """``body`` preceded by the line ``# content_sha256=<hex>`` (SHA-256 of ``body``'s UTF-8
    bytes), so that an edit of the file after writing is found (:func:`unseal_text`).

    Parameters
    ----------
    body : str
        The text to seal (e.g. a CSV table).

    Returns
    -------
    str
        The sealed text.
    """
    return f"{TEXT_DIGEST_PREFIX}{hashlib.sha256(body.encode('utf-8')).hexdigest()}\n{body}"


def unseal_text(text: str, path: str | os.PathLike) -> str:
    """The body of a text sealed by :func:`seal_text`, after checking its digest.

    Parameters
    ----------
    text : str
        The file's content.
    path : str or os.PathLike
        The file (named in the error).

    Returns
    -------
    str
        The text after the digest line.

    Raises
    ------
    ValueError
        One line naming the file: no digest line, or the content no longer matches it (the
        file was edited after it was written).
    """
    problem, body = _seal_problem(text)
    if problem is not None:
        raise ValueError(f"{os.fspath(path)}: {problem}; delete it so the workflow remakes it")
    return body


def _seal_problem(text: str) -> tuple[str | None, str]:
    """(what is wrong with a sealed text or None, its body)."""
    first, _, body = text.partition("\n")
    if not first.startswith(TEXT_DIGEST_PREFIX):
        return (f"no '{TEXT_DIGEST_PREFIX}' first line (not written by this package, or "
                f"edited)"), body
    stored = first[len(TEXT_DIGEST_PREFIX):].strip()
    actual = hashlib.sha256(body.encode("utf-8")).hexdigest()
    if actual != stored:
        return (f"edited after it was written (digest {stored[:12]}... stored, "
                f"{actual[:12]}... now)"), body
    return None, body


def sealed_text_problem(path: str | os.PathLike) -> str | None:
    """Why an existing sealed text file (:func:`seal_text`) cannot be used (None when intact).

    Reads the whole file and checks its content against its digest line (:func:`unseal_text`),
    whatever its modification time: an edit that keeps the mtime is found too.

    Parameters
    ----------
    path : str or os.PathLike
        An existing sealed file (a per-case table).

    Returns
    -------
    str or None
        One line saying what is wrong (no digest line, content edited, unreadable), or None.
    """
    try:
        with open(path, encoding="utf-8", newline="") as fh:
            text = fh.read()
    except (OSError, UnicodeDecodeError) as exc:
        return f"unreadable ({exc})"
    return _seal_problem(text)[0]
