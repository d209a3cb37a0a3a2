"""sha256 of every array of every case file and of every table of a sweep's ``results/``.

For refactors that must not change a number: run the same sweep before and after, then
``python -m benchmarks result_digests results_before results_after``; prints one line per item
and the items that differ; for a differing numeric HDF5 dataset or CSV table of the same shape,
also the largest difference relative to the item's largest magnitude. HDF5 datasets are hashed
by their bytes (dtype and shape included); attributes holding provenance (creation time, host,
git commit, package version, paths, wall times) are skipped, the others are hashed. CSV tables
are hashed as text with columns named like wall or CPU times dropped.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import h5py
import numpy as np
import pandas as pd

#: Attributes and columns that record provenance or timing, not results.
VOLATILE = ("created_utc", "host", "git_commit", "package_version", "version", "config_file",
            "wall", "seconds", "cpu", "time_s", "python", "numpy", "scipy", "numba", "h5py",
            "workflow", "source_file", "code_",
            # execution statistics: with the shared no-defect store (issue 25) how many solves a
            # case ran and how many it read from the store depend on the job order; the
            # file's content digest covers them (its arrays are compared one by one here)
            "n_solves", "n_iterations", "nodefect_cache", "content_sha256")


def _volatile(name: str) -> bool:
    return any(v in name.lower() for v in VOLATILE)


def _h(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()[:16]


def _array_digest(a: np.ndarray) -> str:
    """Bytes of a numeric array; the values of a string (object) array."""
    if a.dtype.kind == "O":
        return _h(repr((a.shape, [x.decode() if isinstance(x, bytes) else x
                                   for x in a.ravel().tolist()])).encode())
    return _h(repr((a.dtype.str, a.shape)).encode() + a.tobytes())


def _drop_volatile(obj):
    if isinstance(obj, dict):
        return {k: _drop_volatile(v) for k, v in obj.items() if not _volatile(k)}
    return obj


def case_digests(path: Path) -> dict[str, str]:
    """``{item: digest}`` for every dataset and non-volatile attribute of an HDF5 file."""
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                out[f"{name}"] = _array_digest(np.asarray(obj[()]))
            for k, v in obj.attrs.items():
                if k.endswith("_json"):
                    v = _drop_volatile(json.loads(v))
                if not _volatile(k):
                    out[f"{name}@{k}"] = _h(repr(v).encode())
        visit("/", f)
        f.visititems(visit)
    return out


def table_digest(path: Path) -> str:
    """Digest of a CSV table's values (volatile columns dropped); a sealed table's first line
    (``# content_sha256=...``, :func:`bearing_envelope.io.write_tidy`) is not part of it."""
    return _h(table_digest_frame(path).to_csv(index=False).encode())


def table_digest_frame(path: Path) -> pd.DataFrame:
    """A CSV table without its seal line and its volatile columns."""
    with open(path, encoding="utf-8") as fh:
        sealed = fh.readline().startswith("# content_sha256=")
    df = pd.read_csv(path, skiprows=1 if sealed else 0)
    return df[[c for c in df.columns if not _volatile(c)]]


def digests(results: Path) -> dict[str, str]:
    out = {}
    for p in sorted(results.rglob("*.h5")):
        for k, v in case_digests(p).items():
            out[f"{p.relative_to(results)}:{k}"] = v
    for p in sorted(results.rglob("*.csv")):
        out[str(p.relative_to(results))] = table_digest(p)
    for p in sorted(results.rglob("*.npz")):
        with np.load(p, allow_pickle=False) as z:
            for k in sorted(z.files):
                out[f"{p.relative_to(results)}:{k}"] = _array_digest(z[k])
    return out


def main(argv: list[str]) -> int:
    runs = [digests(Path(a)) for a in argv]
    if len(runs) == 1:
        for k, v in runs[0].items():
            print(f"{v}  {k}")
        return 0
    a, b = runs
    keys = sorted(set(a) | set(b))
    diff = [k for k in keys if a.get(k) != b.get(k)]
    print(f"{len(keys)} items, {len(diff)} differ")
    for k in diff:
        rel = relative_difference(Path(argv[0]), Path(argv[1]), k)
        print(f"  {k}: {a.get(k)} -> {b.get(k)}" + ("" if rel is None else f" (max rel {rel:.2g})"))
    return 1 if diff else 0


def _numeric(path: Path, item: str):
    """The numeric values of one digest item (a dataset ``file.h5:name`` or a CSV table), or None."""
    if item.endswith(".csv"):
        p = path / item
        if not p.exists():
            return None
        return table_digest_frame(p).select_dtypes("number").to_numpy(dtype=float)
    file, _, name = item.partition(":")
    if not file.endswith(".h5") or "@" in name or not (path / file).exists():
        return None
    with h5py.File(path / file, "r") as f:
        a = np.asarray(f[name][()]) if name in f else None
    return a.astype(float) if a is not None and a.dtype.kind in "fiub" else None


def relative_difference(before: Path, after: Path, item: str) -> float | None:
    """``max |after - before| / max |before|`` of a numeric item of equal shape, else None."""
    x, y = _numeric(before, item), _numeric(after, item)
    if x is None or y is None or x.shape != y.shape or x.size == 0:
        return None
    with np.errstate(invalid="ignore"):  # inf - inf where both hold an infinity: skipped as NaN
        scale = float(np.nanmax(np.abs(x))) or 1.0
        return float(np.nanmax(np.abs(y - x))) / scale


def smoke() -> None:
    """Two tiny result folders (a case file and a table) that differ in one array."""
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        for name, value in (("a", 1.0), ("b", 2.0)):
            cases = Path(d, name, "cases")
            cases.mkdir(parents=True)
            with h5py.File(cases / "F1kN_h0um.h5", "w") as f:
                f["p_max"] = np.array([0.0, value])
                f.attrs["scene_json"] = "{}"
            tables = Path(d, name, "tables")
            tables.mkdir()
            pd.DataFrame({"case": ["F1kN_h0um"], "amplitude": [1.5]}).to_csv(
                tables / "harmonics.csv", index=False)
        assert main([str(Path(d, "a"))]) == 0
        assert main([str(Path(d, "a")), str(Path(d, "b"))]) == 1
        # [0, 1] -> [0, 2]: the largest difference is the largest value of before
        assert relative_difference(Path(d, "a"), Path(d, "b"), "cases/F1kN_h0um.h5:p_max") == 1.0
        assert relative_difference(Path(d, "a"), Path(d, "b"), "tables/harmonics.csv") == 0.0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
