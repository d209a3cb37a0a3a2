"""Reading a record's columns: the sampling rate from a time column (its printed precision
the quantum), the column picked by name or index, and the CSV reader with its sniffed dialect
(:func:`sniff_csv`); read by :mod:`.records` for every format that has columns or variables."""

from __future__ import annotations

import re

import numpy as np

__all__ = ["sniff_csv"]

_TIME_NAMES = ("time", "t", "time_s", "times", "seconds")
_SNIFF_BYTES = 65536
_SNIFF_LINES = 200


def _fs_from_time(t, path: str, quantum: float = 0.0) -> float:
    """The sampling rate of a time column: uniform within 0.1 % of its step, or within the
    precision it is written to (``quantum``, s: a column printed to 6 decimals is uniform
    within 1e-6 s, and its rate is then read end to end, ``(n - 1) / (t[-1] - t[0])``)."""
    t = np.asarray(t, dtype=float)
    dt = np.diff(t)
    if t.size < 3 or not np.all(dt > 0):
        raise ValueError(f"file: {path}: the time column is not increasing; give --fs")
    step = float(np.median(dt))
    dev = float(np.max(np.abs(dt - step)))
    if dev > 1e-3 * step + 1.001 * quantum:
        printed = f" (written to {quantum:.3g} s)" if quantum > 0 else ""
        raise ValueError(f"file: {path}: the time column is not uniformly sampled: steps "
                         f"{dt.min():.6g}-{dt.max():.6g} s{printed}, allowed: within 0.1 % "
                         f"of the step or the column's printed precision; give --fs")
    if quantum > 0:
        return float((t.size - 1) / (t[-1] - t[0]))
    return 1.0 / step


#: A number as written in a CSV field: its digits after the decimal mark and its exponent.
_DECIMALS = r"^[+-]?\d*(?:\.(?P<frac>\d*))?(?:[eE](?P<exp>[+-]?\d+))?$"


def _printed_quantum(series, dec: str) -> float:
    """The last written digit of a column of numbers, its median over the column (s for a
    time column): 1e-6 for ``0.000083``, 1e-9 for ``8.3333e-05``; 0 when the texts are not
    plain numbers."""
    text = series.str.strip()
    if dec == ",":
        text = text.str.replace(",", ".", regex=False)
    parts = text.str.extract(_DECIMALS)
    if not text.str.fullmatch(_DECIMALS).all():
        return 0.0
    frac = parts["frac"].fillna("").str.len().to_numpy(dtype=float)
    exp = parts["exp"].fillna("0").astype(int).to_numpy(dtype=float)
    # the median, not the coarsest: "%g" writes 0 s as "0" and 0.5 s as "0.5", values exact
    # as written, and the largest quantum (1 s for "0") would let any step through
    return float(np.median(10.0 ** (exp - frac)))


def _pick(names, column, what: str, path: str) -> str:
    names = list(names)
    if column is not None:
        if column in names:
            return column
        raise ValueError(f"--column: {path} has no {what} {column!r} (available: "
                         f"{', '.join(map(str, names)) or 'none'})")
    if len(names) == 1:
        return names[0]
    if not names:
        raise ValueError(f"file: {path} holds no numeric signal; allowed: a {what} with a "
                         f"real vector")
    raise ValueError(f"--column: {path} holds several {what}s ({', '.join(map(str, names))}); "
                     f"choose one with --column")


def _column_index(column, n: int, path: str, what: str) -> int:
    try:
        idx = int(str(column))
    except ValueError:
        raise ValueError(f"--column: {column!r} is not an index; {path} holds {n} {what}s, "
                         f"allowed: an integer 0 .. {n - 1}") from None
    if not -n <= idx < n:
        raise ValueError(f"--column: index {idx} is out of range; {path} has {n} {what}s "
                         f"(0-based)")
    return idx


# --------------------------------------------------------------------------------- CSV
_DOT_NUM = re.compile(r"^[+-]?(\d+\.\d*|\.\d+|\d+)([eE][+-]?\d+)?$")
_COMMA_NUM = re.compile(r"^[+-]?\d+,\d+([eE][+-]?\d+)?$")
_INT = re.compile(r"^[+-]?\d+$")
_NAMES = {",": "commas", ";": "semicolons", "\t": "tabs", "|": "bars", r"\s+": "blanks"}


def _is_number(tok: str) -> bool:
    try:
        float(tok)
    except ValueError:
        return False
    return True


def _split(line: str, sep: str) -> list[str]:
    if sep == r"\s+":
        return line.split()
    return [t.strip().strip('"').strip("'") for t in line.split(sep)]


def _csv_lines(path: str) -> list[str]:
    try:
        with open(path, "rb") as fh:
            head = fh.read(_SNIFF_BYTES)
            more = fh.read(1) != b""
    except OSError:
        raise
    try:
        text = head.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        if not (more and exc.start >= len(head) - 4):  # a character cut at the block's end
            raise ValueError(f"file: {path} is not a UTF-8 text CSV (byte {exc.start}); "
                             f"allowed: text with numbers") from None
        text = head[:exc.start].decode("utf-8-sig")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if more and lines:
        lines = lines[:-1]  # possibly cut
    return lines[:_SNIFF_LINES]


def sniff_csv(path: str, *, delimiter: str | None = None, decimal: str | None = None
              ) -> tuple[str, str, bool]:
    """Delimiter, decimal mark and header of a numeric CSV, from its first lines.

    Parameters
    ----------
    path : str
        The file.
    delimiter : str, optional
        Force the delimiter (``","``, ``";"``, ``"\\t"``, ``"|"``, or ``"space"`` for blanks).
    decimal : {".", ","}, optional
        Force the decimal mark.

    Returns
    -------
    (str, str, bool)
        Delimiter (``r"\\s+"`` for blanks), decimal mark and whether the first line is a
        header.

    Raises
    ------
    ValueError
        When the file holds no data line, or when ``,`` could be the delimiter or the
        decimal mark (every value an integer, the second field looking like a fraction):
        one line naming the file and ``--delimiter``/``--decimal``.
    """
    lines = _csv_lines(path)
    if not lines:
        raise ValueError(f"file: {path} holds no data line; allowed: a CSV of numbers")
    if delimiter == "space":
        delimiter = r"\s+"
    head_is_text = not all(_is_number(t) or _COMMA_NUM.match(t) for t in
                           _split(lines[0], delimiter or _guess_sep(lines)) if t)
    body = lines[1:] if head_is_text else lines
    if not body:
        raise ValueError(f"file: {path} holds a header and no data line")
    sep = delimiter or _guess_sep(body)
    dec = decimal or _guess_decimal(body, sep, path)
    if sep == "," and dec == ",":
        raise ValueError(f"--decimal: ',' cannot be the decimal mark of {path} when ',' also "
                         f"delimits its fields; give --delimiter")
    return sep, dec, head_is_text


def _guess_sep(lines: list[str]) -> str:
    for sep in (";", "\t", "|", ","):
        counts = {ln.count(sep) for ln in lines}
        if len(counts) == 1 and counts != {0}:
            return sep
    return r"\s+" if all(len(ln.split()) > 1 for ln in lines) else ","


def _guess_decimal(lines: list[str], sep: str, path: str) -> str:
    toks = [t for ln in lines for t in _split(ln, sep) if t]
    dots = any("." in t and _DOT_NUM.match(t) for t in toks)
    commas = any(_COMMA_NUM.match(t) for t in toks)
    if dots and commas:
        raise ValueError(f"file: {path} mixes '.' and ',' decimal marks; give --decimal")
    if commas:
        return ","
    if sep == "," and not dots and all(_INT.match(t) for t in toks):
        rows = [_split(ln, sep) for ln in lines]
        tails = [r[1] for r in rows if len(r) == 2]
        lead0 = any(len(t) > 1 and t.lstrip("+-").startswith("0") for r in rows for t in r[1:])
        same = len(tails) == len(rows) and len({len(t) for t in tails}) == 1
        if lead0 or same:
            raise ValueError(f"file: {path}: ',' may be the delimiter or the decimal mark "
                             f"(e.g. {lines[0].strip()!r}); refused as ambiguous, give "
                             f"--delimiter and --decimal")
    return "."


def _read_csv(path, column, delimiter, decimal, fs=None) -> dict:
    import pandas as pd

    sep, dec, header = sniff_csv(path, delimiter=delimiter, decimal=decimal)
    try:
        df = pd.read_csv(path, sep=sep, decimal=dec, header=0 if header else None,
                         engine="python" if sep == r"\s+" else "c", comment="#",
                         skip_blank_lines=True, dtype=str, keep_default_na=False,
                         encoding="utf-8-sig")
    except (pd.errors.ParserError, ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"file: {path} is not a regular CSV ({_NAMES.get(sep, sep)} between "
                         f"fields): {str(exc).splitlines()[0]}") from None
    cols = [str(c).strip() for c in df.columns]
    df.columns = cols
    tcols = [c for c in cols if c.lower() in _TIME_NAMES]
    data_cols = [c for c in cols if c not in tcols]
    if column is not None and column not in cols and str(column).lstrip("-").isdigit():
        column = cols[_column_index(column, len(cols), path, "column")]
    name = _pick(data_cols if column is None else cols, column, "column", path)
    out = {"x": _csv_numbers(df[name], path, name, sep, dec, header), "fs": None,
           "source": f"csv:{name}"}
    if tcols and fs is None:
        out["fs"] = _fs_from_time(_csv_numbers(df[tcols[0]], path, tcols[0], sep, dec, header),
                                  path, _printed_quantum(df[tcols[0]], dec))
    return out


def _csv_numbers(series, path, name, sep, dec, header) -> np.ndarray:
    import pandas as pd

    text = series.str.strip()
    if dec == ",":
        text = text.str.replace(",", ".", regex=False)
    values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=float)
    bad = np.isnan(values) & ~text.str.lower().isin(["nan"]).to_numpy()
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"file: {path}: column {name!r}, line {i + 1 + int(header)}: "
                         f"{series.iloc[i]!r} is not a number; allowed: real numbers with "
                         f"{dec!r} as decimal mark, fields separated by "
                         f"{_NAMES.get(sep, sep)} (else give --delimiter/--decimal)")
    return values
