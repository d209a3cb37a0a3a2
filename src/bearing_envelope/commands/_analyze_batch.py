"""Many records at once for ``bearing-envelope analyze``: the library's parallel batch
(:func:`bearing_envelope.diagnosis.batch.analyze_records`) with the command's options, its
printout, the verdict table, the lines, the JSON and the HTML page.
"""

# Only the standard library at module level: run() calls single_threaded() before numpy is
# imported (the thread-count variables are read when numpy/numba load). numpy, pandas and the
# package's modules are imported inside the functions for that reason.
from __future__ import annotations

import html
import json
import os
import sys

#: Exit code of a batch where at least one record failed (the others' results are written).
EXIT_SOME_FAILED = 1

#: Environment variables that make numpy's BLAS, OpenMP and numba use one thread.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                    "NUMEXPR_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMBA_NUM_THREADS")


def single_threaded() -> None:
    """One thread per process for BLAS, OpenMP and numba (inherited by forked workers)."""
    for k in THREAD_VARIABLES:
        os.environ[k] = "1"


def write_text(path: str, text: str) -> None:
    """Write ``text`` to ``path``, creating its folder."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)


def is_batch(args) -> bool:
    """Several records (or a folder, or a manifest): the batch mode."""
    return args.manifest is not None or len(args.files) != 1 or os.path.isdir(args.files[0])


def figure_dir(args) -> str | None:
    """Where the per-record analyst figures go: ``--plot`` in batch mode, else beside
    ``--html`` (``<stem>_figures/``); None without ``--html`` and batch ``--plot``."""
    if args.html:
        if args.plot and is_batch(args):
            return args.plot
        stem = os.path.splitext(os.path.abspath(args.html))[0]
        return f"{stem}_figures"
    return args.plot if is_batch(args) else None


def figure_options(args) -> dict:
    """``db``, ``fmax``, ``orders`` of the analyst figures."""
    return {"db": args.db, "fmax": args.fmax, "orders": args.orders}


def run_batch(tasks: list[dict], args, library: dict) -> int:
    """Analyse every task, print, write the outputs; exit code 0, or 1 if any record failed.

    ``library``: the keyword arguments of the library call (options, bearing, names, reader).
    """
    from tqdm import tqdm

    from bearing_envelope.diagnosis.batch import analyze_records

    jobs = args.jobs or os.cpu_count() or 1
    jobs = max(1, min(jobs, len(tasks)))
    bar = tqdm(total=len(tasks), file=sys.stderr, unit="record", desc="analyze",
               disable=args.quiet or not sys.stderr.isatty())
    with bar:
        results = analyze_records(tasks, args.fs, jobs=jobs, figure_dir=figure_dir(args),
                                  figure_options=figure_options(args), progress=bar.update,
                                  **library)
    json_only = args.json == "-"
    out = sys.stderr if json_only else sys.stdout
    for r in results:
        if not r.ok:
            where = "" if r.file in r.error else f"{r.file}: "
            print(f"bearing-envelope analyze: {where}{r.error}", file=sys.stderr)
    for r in results:
        print(f"{r.file}: {r.summary_lines()[0] if r.ok else 'FAILED: ' + r.error}", file=out)
        if r.ok and r.defect_size is not None:
            print(f"  defect length (entry-exit spacing): {r.defect_size['summary']}", file=out)
    n_bad = sum(not r.ok for r in results)
    print(f"# {len(results)} records: {len(results) - n_bad} analysed, {n_bad} failed "
          f"({jobs} job{'s' if jobs > 1 else ''})", file=out)
    write_batch_outputs(results, args, library["options"], out=out)
    return EXIT_SOME_FAILED if n_bad else 0


def tidy_lines(res):
    """A record's lines in the tidy vocabulary of the tables (``envelope_bpfi``, ...)."""
    from bearing_envelope.study.tables import tidy_from_analysis

    return tidy_from_analysis(res.lines)


def record_json(res) -> dict:
    """The ``--json`` document of one result (lines in the tidy vocabulary)."""
    return res.to_dict(lines=tidy_lines(res)) if res.ok else res.to_dict()


# ------------------------------------------------------------------------------ outputs
def write_batch_outputs(results: list, args, options, *, out,
                        lines_and_json: bool = True) -> None:
    """``--table``, ``--html`` and (``lines_and_json``) ``--csv`` and ``--json``."""
    if args.table:
        from bearing_envelope.diagnosis.batch import verdict_table

        os.makedirs(os.path.dirname(os.path.abspath(args.table)), exist_ok=True)
        verdict_table(results).to_csv(args.table, index=False)
        print(f"# verdict table written to {args.table}", file=out)
    if lines_and_json and args.csv:
        import pandas as pd

        parts = [tidy_lines(r).assign(file=r.file) for r in results if r.ok]
        lines = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()
        cols = ["file"] + [c for c in lines.columns if c != "file"]
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        lines[cols].to_csv(args.csv, index=False)
        print(f"# lines written to {args.csv}", file=out)
    if lines_and_json and args.json is not None:
        doc = json.dumps({"records": [record_json(r) for r in results]}, indent=1,
                         allow_nan=False)
        if args.json == "-":
            print(doc)
        else:
            write_text(args.json, doc + "\n")
            print(f"# JSON written to {args.json}", file=out)
    if args.html:
        write_text(args.html, html_page(results, args, options))
        print(f"# page written to {args.html}", file=out)


_CSS = ("body{font-family:sans-serif;margin:1.5em;max-width:75em}"
        "table{border-collapse:collapse;font-size:90%}td,th{border:1px solid #bbb;"
        "padding:2px 6px;text-align:left}tr.error td{background:#fdd}"
        "img{max-width:100%;border:1px solid #ddd}h2{font-size:110%;margin-top:2em}"
        "pre{white-space:pre-wrap;font-size:90%}")


def html_page(results: list, args, options) -> str:
    """A static HTML page: the verdict of every record, then each record's figure."""
    base = os.path.dirname(os.path.abspath(args.html))
    e = html.escape
    conf = any("confidence" in row or "record_confidence" in row
               for r in results for row in r.rows)
    head = ["record", "status", "diagnosis"] + (["confidence"] if conf else []) + ["verdict"]
    rows = []
    for i, r in enumerate(results):
        diag = next((row for row in r.rows if row.get("diagnosis")), {})
        first = r.rows[0]
        label = diag.get("family") or first.get("record_diagnosis_label") or "no fault"
        cells = [f'<a href="#r{i}">{e(r.file)}</a>', "ok" if r.ok else "failed",
                 e(str(label if r.ok else "-"))]
        if conf:
            cells.append(e(str(diag.get("confidence", first.get("record_confidence", "")))))
        cells.append(e(r.summary_lines()[0] if r.ok else r.error))
        rows.append(f'<tr class="{"ok" if r.ok else "error"}">'
                    + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>bearing-envelope "
             f"analyze: {len(results)} records</title><style>{_CSS}</style></head><body>",
             f"<h1>Envelope analysis of {len(results)} records</h1>",
             f"<p>{sum(r.ok for r in results)} analysed, "
             f"{sum(not r.ok for r in results)} failed; search +-{options.search_percent:g} "
             f"%, record-wise false-alarm probability {options.pfa:g}, "
             f"{options.n_harmonics} harmonics. "
             f"Fault lines of the family diagnosed (or the closest) are labelled; the other "
             f"families searched are in grey.</p>",
             "<table><tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>",
             *rows, "</table>"]
    for i, r in enumerate(results):
        parts.append(f'<h2 id="r{i}">{e(r.file)}</h2>')
        if not r.ok:
            parts.append(f"<p>failed: {e(r.error)}</p>")
            continue
        parts.append("<pre>" + e("\n".join(r.summary_lines())) + "</pre>")
        if r.figure:
            src = os.path.relpath(r.figure, base).replace(os.sep, "/")
            parts.append(f'<img src="{e(src)}" alt="{e(r.file)}" loading="lazy">')
    parts.append("</body></html>\n")
    return "\n".join(parts)
