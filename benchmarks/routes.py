"""What each route sees (issue 32): the envelope route and the benchmark's methods on the CWRU
12 kHz drive-end development records, one verdict from several routes, leave one fault set
out, and the false-alarm rate on shaped noise with every route.

    nice -n 10 python -m benchmarks routes --data DATA [--trials 400] [--no-mc] [--only-mc]

``DATA``: laid out like the project's real-data folder (``benchmarks.real_records``).
Records: the 32 of ``cwru_de12/`` (truth and Smith & Randall's grade in its ``index.csv``) and
the normal record, through ``analyze_signal`` with the ``analyze`` command's defaults
(``diagnosis.records.RECORD_OPTIONS`` without its routes, :data:`OPTIONS`) and then every
route of ``diagnosis.routes.run_routes``, one at a time (CPU of each).
Variants of the combination (:data:`VARIANTS`: which faults the routes may raise, how many
routes) are scored on all records and in leave-one-fault-set-out: the variant with no wrong
verdict at medium or high on the other sets and the most right ones there (ties: the first
of :data:`VARIANTS`, the most conservative) is judged on the held-out set. The Monte Carlo
draws shaped noise as ``cwru_dev.noise_mc`` does and counts any verdict (or "cannot tell")
of the combined verdict as a false alarm (95 % Clopper-Pearson interval). CPU seconds:
``time.process_time`` per record and route.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bearing_envelope.diagnosis import analyze_signal
from bearing_envelope.diagnosis.detection import clopper_pearson
from bearing_envelope.diagnosis.records import RECORD_OPTIONS
from bearing_envelope.diagnosis.routes import DEFAULT_ROUTES, ROUTES, combine_routes, run_routes
from bearing_envelope.physics.kinematics import fault_frequencies

from .real_records import INCH, load_records, outcome, shaped_noise

#: Combination variants: (name, faults the routes may raise, routes needed), most
#: conservative first.
VARIANTS = (("envelope only", (), 99), ("ball, 2 routes", ("ball",), 2),
            ("ball, 3 routes", ("ball",), 3), ("any, 3 routes", ("ball", "bpfo", "bpfi"), 3),
            ("any, 2 routes", ("ball", "bpfo", "bpfi"), 2))
FAMS = ("bpfo", "bpfi", "bsf", "bsf2", "ftf")
#: Sets of routes compared (the default first): the infogram as the DRS route's band selector,
#: and as a route of its own.
ROUTE_SETS = {"default": DEFAULT_ROUTES,
              "drs_info for drs_sk": tuple("drs_info" if r == "drs_sk" else r
                                           for r in DEFAULT_ROUTES),
              "default + drs_info": (*DEFAULT_ROUTES, "drs_info"),
              "default + info": (*DEFAULT_ROUTES, "info"),
              "default + drs_info + info": (*DEFAULT_ROUTES, "drs_info", "info")}
#: The options of ``bearing-envelope analyze`` on a recording, the routes run one by one here
#: (to time each).
OPTIONS = dataclasses.replace(RECORD_OPTIONS, routes=())


def run(records):
    """Per record: the route results and the CPU of each route."""
    out = []
    for rec in records:
        t0 = time.process_time()
        _, det = analyze_signal(rec["x"], rec["fs"], fr=rec["fr"], fault_frequencies=rec["ff"],
                                options=OPTIONS, full_output=True)
        cpu = {"envelope": time.process_time() - t0}
        res = {"envelope": run_routes(rec["x"], rec["fs"], det, ("envelope",))["envelope"]}
        for r in ROUTES[1:]:
            t1 = time.process_time()
            res[r] = run_routes(rec["x"], rec["fs"], det, (r,))[r]
            cpu[r] = time.process_time() - t1
        out.append((rec, res, cpu))
    return out


def route_table(runs, grades) -> pd.DataFrame:
    """Route x family x margin per record (the margin of each detected, unexplained family;
    the named ones marked *)."""
    rows = []
    for rec, res, cpu in runs:
        row = {"record": rec["record"], "set": rec["set"], "grade": grades.get(rec["record"], "-")}
        for r, rr in res.items():
            found = rr.finds
            row[r] = ", ".join(f"{f}{'*' if f in rr.named else ''} {rr.margin(f):.1f}"
                               for f in found) or "-"
        row["cpu_s"] = round(sum(cpu.values()), 2)
        rows.append(row)
    return pd.DataFrame(rows)


def own_family_table(runs, grades) -> pd.DataFrame:
    """Per fault record, the margin over its threshold (dB) of the fault's own fundamental in
    each default route, found or not (a ball: the better of BSF and 2 x BSF); ``+``: the route
    finds it, ``*``: it names it."""
    rows = []
    for rec, res, _ in runs:
        if rec["truth"] is None:
            continue
        fams = ("bsf", "bsf2") if rec["truth"] == "bsf" else (rec["truth"],)
        row = {"record": rec["record"], "set": rec["set"],
               "grade": grades.get(rec["record"], "-")}
        for r in DEFAULT_ROUTES:
            rr = res[r]
            fam = max(fams, key=lambda f: np.nan_to_num(rr.margin(f), nan=-np.inf))
            mark = "*" if fam in rr.named else "+" if fam in rr.finds else ""
            row[r] = f"{rr.margin(fam):.1f}{mark}"
        rows.append(row)
    return pd.DataFrame(rows)


def score(runs, raises, min_routes, routes=DEFAULT_ROUTES) -> pd.DataFrame:
    rows = []
    for rec, res, _ in runs:
        v = combine_routes({r: res[r] for r in routes}, raises=raises, min_routes=min_routes)
        rows.append({"record": rec["record"], "set": rec["set"], "diagnosis": v.diagnosis,
                     "confidence": v.confidence, "decided_by": v.decided_by,
                     "outcome": outcome(v.diagnosis, rec["truth"])})
    return pd.DataFrame(rows)


def summary(df, grades) -> dict:
    conf = df.confidence.isin(["high", "medium"])
    y = df.record.map(lambda r: str(grades.get(r, "")).startswith("Y"))
    return {"Y right at medium/high": f"{int((y & conf & (df.outcome == 'right')).sum())}/"
                                      f"{int(y.sum())}",
            "right at medium/high": int((conf & (df.outcome == "right")).sum()),
            "wrong at medium/high": int((conf & (df.outcome == "wrong")).sum()),
            "high right/wrong": f"{int(((df.confidence == 'high') & (df.outcome == 'right')).sum())}/"
                                f"{int(((df.confidence == 'high') & (df.outcome == 'wrong')).sum())}",
            "medium right/wrong": f"{int(((df.confidence == 'medium') & (df.outcome == 'right')).sum())}/"
                                  f"{int(((df.confidence == 'medium') & (df.outcome == 'wrong')).sum())}",
            "low right/wrong": f"{int(((df.confidence == 'low') & (df.outcome == 'right')).sum())}/"
                               f"{int(((df.confidence == 'low') & (df.outcome == 'wrong')).sum())}",
            "cannot tell": int((df.confidence == "cannot tell").sum()),
            "none": int(df.confidence.isna().sum())}


def lofo(scored: dict) -> pd.DataFrame:
    sets = [s for s in dict.fromkeys(scored[VARIANTS[0][0]].set) if s != "normal"]
    out = []
    for held in sets:
        def key(name):
            r = scored[name][scored[name].set != held]
            conf = r.confidence.isin(["high", "medium"])
            return (int((conf & (r.outcome == "wrong")).sum()) == 0,
                    int((conf & (r.outcome == "right")).sum()))
        names = [v[0] for v in VARIANTS]
        best = max(names, key=lambda n: (key(n), -names.index(n)))
        r = scored[best][scored[best].set == held]
        conf = r.confidence.isin(["high", "medium"])
        out.append({"held_out": held, "variant chosen": best,
                    "verdicts": ", ".join(f"{x.record}:{x.diagnosis or '-'}/{x.confidence or 'none'}"
                                          for x in r.itertuples()),
                    "right at medium/high": int((conf & (r.outcome == "right")).sum()),
                    "wrong at medium/high": int((conf & (r.outcome == "wrong")).sum()),
                    "n": len(r)})
    return pd.DataFrame(out)


def noise_mc(normal, trials, n, raises, min_routes, seed=24) -> dict:
    ff = fault_frequencies(29.95, 9, 0.3126 * INCH, 1.537 * INCH, 0.0)
    alarms = any_named = 0
    per_route: dict[str, int] = {}
    t0 = time.process_time()
    for t, y in enumerate(shaped_noise(normal, trials, n, seed)):
        _, det = analyze_signal(y, 12000.0, fr=29.95, fault_frequencies=ff, options=OPTIONS,
                                full_output=True)
        res = run_routes(y, 12000.0, det)
        v = combine_routes(res, raises=raises, min_routes=min_routes)
        alarms += v.confidence is not None
        any_named += any(r.named for r in res.values())
        for r, rr in res.items():
            per_route[r] = per_route.get(r, 0) + bool(rr.named)
        if (t + 1) % 25 == 0:  # progress: a partial count survives an interrupted run
            print(f"# {t + 1} trials: {alarms} alarms, per route {per_route}, CPU "
                  f"{time.process_time() - t0:.0f} s", flush=True)
    lo, hi = clopper_pearson(alarms, trials)
    return {"trials": trials, "alarms": alarms, "ci": (lo, hi), "any_named": any_named,
            "per_route": per_route, "cpu_s": time.process_time() - t0}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--data", type=Path, required=True,
                   help="folder with cwru_de12/index.csv and cwru_097_normal_0hp.npz")
    p.add_argument("--trials", type=int, default=300)
    p.add_argument("--no-mc", action="store_true")
    p.add_argument("--only-mc", action="store_true")
    args = p.parse_args(argv)
    records = load_records(args.data)
    if args.only_mc:
        _print_mc(records, args.trials)
        return 0
    idx = pd.read_csv(args.data / "cwru_de12" / "index.csv")
    grades = (dict(zip(idx.cwru_record, idx.sr2015_grade)) if "sr2015_grade" in idx else {})
    runs = run(records)
    print("## what each route sees (margin over threshold, dB; * named)\n")
    print(route_table(runs, grades).to_markdown(index=False))
    cpu = pd.DataFrame([c for _, _, c in runs])
    print("\nCPU s per record, mean by route: " + ", ".join(
        f"{r} {cpu[r].mean():.2f}" for r in cpu.columns) + f"; total per record "
        f"{cpu.sum(axis=1).mean():.2f} (max {cpu.sum(axis=1).max():.2f})")
    print("\n## the fault's own fundamental in each route (margin over threshold, dB; "
          "+ found, * named)\n")
    print(own_family_table(runs, grades).to_markdown(index=False))
    scored = {name: score(runs, raises, k) for name, raises, k in VARIANTS}
    print("\n## variants\n")
    print(pd.DataFrame([{"variant": n, **summary(scored[n], grades)} for n in scored])
          .to_markdown(index=False))
    chosen = "ball, 2 routes"
    print(f"\n## verdicts ({chosen})\n")
    print(scored[chosen].to_markdown(index=False))
    print("\n## leave one fault set out\n")
    print(lofo(scored).to_markdown(index=False))
    _print_route_sets(runs, grades, chosen)
    if not args.no_mc:
        _print_mc(records, args.trials)
    return 0


def _print_route_sets(runs, grades, chosen):
    """The shipped rule and leave-one-fault-set-out with each set of :data:`ROUTE_SETS`, and
    the records whose verdict a set changes against the default."""
    rows, changed = [], []
    base = None
    for name, routes in ROUTE_SETS.items():
        scored = {v: score(runs, raises, k, routes) for v, raises, k in VARIANTS}
        lo = lofo(scored)
        rows.append({"routes": name, **summary(scored[chosen], grades),
                     "LOFO right/wrong at medium/high": f"{lo['right at medium/high'].sum()}/"
                                                        f"{lo['wrong at medium/high'].sum()}"})
        cur = scored[chosen]
        if base is None:
            base = cur
            continue
        diff = (cur.diagnosis.fillna("-") != base.diagnosis.fillna("-")) | (
            cur.confidence.fillna("-") != base.confidence.fillna("-"))
        changed.extend(f"{name}: {r.record} {b.diagnosis or '-'}/{b.confidence or 'none'} -> "
                       f"{r.diagnosis or '-'}/{r.confidence or 'none'} ({r.outcome})"
                       for (_, r), (_, b) in zip(cur[diff].iterrows(), base[diff].iterrows()))
    print(f"\n## sets of routes ({chosen}; LOFO over the variants)\n")
    print(pd.DataFrame(rows).to_markdown(index=False))
    print("\nverdicts changed against the default: " + ("; ".join(changed) or "none"))


def _print_mc(records, trials):
    n = int(np.median([r["x"].size for r in records if r["truth"] is not None]))
    mc = noise_mc(records[-1], trials, n, ("ball",), 2)
    print(f"\n## shaped noise ({mc['trials']} records of {n} samples, every route)\n\n"
          f"verdict with a finding: {mc['alarms']}/{mc['trials']} (95 % CI "
          f"{100 * mc['ci'][0]:.2f}-{100 * mc['ci'][1]:.2f} %); any route naming a family: "
          f"{mc['any_named']}/{mc['trials']}; CPU {mc['cpu_s']:.0f} s")
    for r, k in mc["per_route"].items():
        lo, hi = clopper_pearson(k, mc["trials"])
        print(f"- route {r} names a family: {k}/{mc['trials']} (95 % CI {100 * lo:.2f}-"
              f"{100 * hi:.2f} %)")


def smoke() -> None:
    """``real_records``' synthetic data folder (one inner-race record, one normal record), every
    route, and a 2-trial Monte Carlo."""
    from unittest import mock

    from . import real_records

    # real_records.smoke builds the folder and calls its main: run this one's instead
    with mock.patch.object(real_records, "main", lambda argv: main([*argv])):
        real_records.smoke()
