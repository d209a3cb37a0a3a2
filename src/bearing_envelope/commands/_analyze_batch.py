"""Many records at once for ``bearing-envelope analyze``: parallel runs, the verdict table,
the HTML page.

Each record runs in :func:`work` (in this process with ``--jobs 1``, else in a pool of forked,
single-threaded processes); a record that cannot be read or analysed becomes a row with its
one-line reason and the others still run. The results are put back in input order, so the
tables do not depend on ``--jobs``.
"""

# Only the standard library (and ._analyze_record, itself standard library only) at module
# level: run() calls single_threaded() before numpy is imported (the thread-count variables are
# read when numpy/numba load). numpy, pandas and the package's modules are imported inside the
# functions for that reason.
from __future__ import annotations

import html
import json
import os
import sys

from ._analyze_record import analyze_record, figure_dir, finish_record, write_text

#: Exit code of a batch where at least one record failed (the others' results are written).
EXIT_SOME_FAILED = 1

#: Environment variables that make numpy's BLAS, OpenMP and numba use one thread.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                    "NUMEXPR_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMBA_NUM_THREADS")


def single_threaded() -> None:
    """One thread per process for BLAS, OpenMP and numba (inherited by forked workers)."""
    for k in THREAD_VARIABLES:
        os.environ[k] = "1"


def one_line(exc: BaseException) -> str:
    """The first line of an exception's message (``OSError``: reason and file)."""
    if isinstance(exc, OSError) and exc.strerror:
        return f"{exc.strerror}: {exc.filename}" if exc.filename else exc.strerror
    if isinstance(exc, KeyError) and exc.args:
        return str(exc.args[0])
    text = str(exc).strip().splitlines()
    msg = text[0] if text else ""
    if isinstance(exc, (ValueError, OSError)):
        return msg or type(exc).__name__
    return f"{type(exc).__name__}: {msg}" if msg else type(exc).__name__


def failed(task: dict, reason: str) -> dict:
    """The result of a record that failed: one table row with its reason."""
    f = task["file"]
    row = {"file": f, "record": os.path.splitext(os.path.basename(f))[0], "status": "error",
           "error": reason}
    return {"file": f, "ok": False, "error": reason, "rows": [row], "lines": None,
            "json": {"file": f, "error": reason}, "summary": [], "figure": None}


def work(task: dict, args, fig_dir: str | None) -> dict:
    """Analyse one record; any error becomes a failed result (one line)."""
    try:
        return finish_record(analyze_record(task, args), args, fig_dir)
    except (ValueError, KeyError, OSError, MemoryError) as exc:
        return failed(task, one_line(exc))
    except Exception as exc:  # noqa: BLE001 - one bad record must not stop the batch
        return failed(task, f"internal error: {one_line(exc)}")


def _warm_up(args, fig_dir) -> None:
    """Import the analysis modules and load the kurtogram's compiled kernel once in the parent,
    so that the forked workers inherit them (~3 s of imports and 0.4 s of numba cache per
    process otherwise). Results do not change."""
    import numpy as np

    import bearing_envelope.commands._analyze_record  # noqa: F401
    import bearing_envelope.diagnosis  # noqa: F401
    import bearing_envelope.io.records  # noqa: F401
    import bearing_envelope.study.tables  # noqa: F401
    from bearing_envelope.signal.kurtogram import fast_kurtogram

    if fig_dir is not None:
        import bearing_envelope.diagnosis.plots  # noqa: F401
        import matplotlib.backends.backend_agg  # noqa: F401
        import matplotlib.figure  # noqa: F401
    fast_kurtogram(np.random.default_rng(0).standard_normal(4096), 1000.0, 2)


def _results(tasks, args, fig_dir, jobs):
    """``(index, result)`` as the records finish."""
    if jobs <= 1:
        for i, task in enumerate(tasks):
            yield i, work(task, args, fig_dir)
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    _warm_up(args, fig_dir)
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else None)
    with ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
        futures = {pool.submit(work, task, args, fig_dir): i for i, task in enumerate(tasks)}
        for fut in as_completed(futures):
            yield futures[fut], fut.result()


def run_batch(tasks: list[dict], args) -> int:
    """Analyse every task, write the outputs; exit code 0, or 1 if any record failed."""
    from tqdm import tqdm

    jobs = args.jobs or os.cpu_count() or 1
    jobs = max(1, min(jobs, len(tasks)))
    fig_dir = figure_dir(args)
    results: list = [None] * len(tasks)
    bar = tqdm(total=len(tasks), file=sys.stderr, unit="record", desc="analyze",
               disable=args.quiet or not sys.stderr.isatty())
    with bar:
        for i, res in _results(tasks, args, fig_dir, jobs):
            results[i] = res
            bar.update()
    json_only = args.json == "-"
    out = sys.stderr if json_only else sys.stdout
    for r in results:
        if not r["ok"]:
            where = "" if r["file"] in r["error"] else f"{r['file']}: "
            print(f"bearing-envelope analyze: {where}{r['error']}", file=sys.stderr)
    for r in results:
        print(f"{r['file']}: {r['summary'][0] if r['ok'] else 'FAILED: ' + r['error']}",
              file=out)
    n_bad = sum(not r["ok"] for r in results)
    print(f"# {len(results)} records: {len(results) - n_bad} analysed, {n_bad} failed "
          f"({jobs} job{'s' if jobs > 1 else ''})", file=out)
    write_batch_outputs(results, args, out=out)
    return EXIT_SOME_FAILED if n_bad else 0


# ------------------------------------------------------------------------- verdict table
def verdict_table(results: list[dict]):
    """The verdict table (a DataFrame) of every result, in input order."""
    import pandas as pd

    rows = [row for r in results for row in r["rows"]]
    return pd.DataFrame.from_records(rows)


# ------------------------------------------------------------------------------ outputs
def write_batch_outputs(results: list[dict], args, *, out, lines_and_json: bool = True) -> None:
    """``--table``, ``--html`` and (``lines_and_json``) ``--csv`` and ``--json``."""
    if args.table:
        os.makedirs(os.path.dirname(os.path.abspath(args.table)), exist_ok=True)
        verdict_table(results).to_csv(args.table, index=False)
        print(f"# verdict table written to {args.table}", file=out)
    if lines_and_json and args.csv:
        import pandas as pd

        parts = [r["lines"].assign(file=r["file"]) for r in results if r["lines"] is not None]
        lines = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()
        cols = ["file"] + [c for c in lines.columns if c != "file"]
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        lines[cols].to_csv(args.csv, index=False)
        print(f"# lines written to {args.csv}", file=out)
    if lines_and_json and args.json is not None:
        doc = json.dumps({"records": [r["json"] for r in results]}, indent=1, allow_nan=False)
        if args.json == "-":
            print(doc)
        else:
            write_text(args.json, doc + "\n")
            print(f"# JSON written to {args.json}", file=out)
    if args.html:
        write_text(args.html, html_page(results, args))
        print(f"# page written to {args.html}", file=out)


_CSS = ("body{font-family:sans-serif;margin:1.5em;max-width:75em}"
        "table{border-collapse:collapse;font-size:90%}td,th{border:1px solid #bbb;"
        "padding:2px 6px;text-align:left}tr.error td{background:#fdd}"
        "img{max-width:100%;border:1px solid #ddd}h2{font-size:110%;margin-top:2em}"
        "pre{white-space:pre-wrap;font-size:90%}")


def html_page(results: list[dict], args) -> str:
    """A static HTML page: the verdict of every record, then each record's figure."""
    base = os.path.dirname(os.path.abspath(args.html))
    e = html.escape
    conf = any("confidence" in row or "record_confidence" in row
               for r in results for row in r["rows"])
    head = ["record", "status", "diagnosis"] + (["confidence"] if conf else []) + ["verdict"]
    rows = []
    for i, r in enumerate(results):
        diag = next((row for row in r["rows"] if row.get("diagnosis")), {})
        first = r["rows"][0]
        label = diag.get("family") or first.get("record_diagnosis_label") or "no fault"
        cells = [f'<a href="#r{i}">{e(r["file"])}</a>', "ok" if r["ok"] else "failed",
                 e(str(label if r["ok"] else "-"))]
        if conf:
            cells.append(e(str(diag.get("confidence", first.get("record_confidence", "")))))
        cells.append(e(r["summary"][0] if r["ok"] else r["error"]))
        rows.append(f'<tr class="{"ok" if r["ok"] else "error"}">'
                    + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>bearing-envelope "
             f"analyze: {len(results)} records</title><style>{_CSS}</style></head><body>",
             f"<h1>Envelope analysis of {len(results)} records</h1>",
             f"<p>{sum(r['ok'] for r in results)} analysed, "
             f"{sum(not r['ok'] for r in results)} failed; search +-{args.search_percent:g} %, "
             f"record-wise false-alarm probability {args.pfa:g}, {args.harmonics} harmonics. "
             f"Fault lines of the family diagnosed (or the closest) are labelled; the other "
             f"families searched are in grey.</p>",
             "<table><tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>",
             *rows, "</table>"]
    for i, r in enumerate(results):
        parts.append(f'<h2 id="r{i}">{e(r["file"])}</h2>')
        if not r["ok"]:
            parts.append(f"<p>failed: {e(r['error'])}</p>")
            continue
        parts.append("<pre>" + e("\n".join(r["summary"])) + "</pre>")
        if r["figure"]:
            src = os.path.relpath(r["figure"], base).replace(os.sep, "/")
            parts.append(f'<img src="{e(src)}" alt="{e(r["file"])}" loading="lazy">')
    parts.append("</body></html>\n")
    return "\n".join(parts)
