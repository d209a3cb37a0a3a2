"""Hostile configurations: every one refused before any job, or run to the end.

Regenerates the hostile-tester set of issue 34 (wrong types, absurd and extreme values of every
scene, operation, analysis and sensor field, YAML oddities, huge sweeps, device and empty files,
and the issue's failures-inside-a-job) on the draft test config
(``config.yaml`` + ``tests/data/config_draft.yaml`` with the ``sensor:`` section of
``config.yaml``), and for each one:

1. runs the pre-run check in this process exactly as ``bearing-envelope check-config FILE``
   and the workflow's main process do (:func:`bearing_envelope.study.limits.checked_settings`:
   the file merged over ``./config.yaml``, validated, then every case's and job's cost
   estimated), and records refused/accepted, the CPU seconds it took and whether a refusal is
   one line naming a field;
2. with ``--run``, runs every *accepted* config through the jobs of its first and last case
   (simulation, bands, envelope, and with a sensor the sensor and detection-map jobs: the
   :mod:`bearing_envelope.study.pipeline` calls of ``workflow/scripts/*.py``) in a child
   process limited to :data:`MAX_JOB_CPU_S` CPU seconds, and records whether it ran to the
   end, failed inside a job (the defect this benchmark exists to find) or ran past the limit
   (accepted and expensive).

Each special config says what it must give (``refuse`` or ``either``); one that must be refused
and is accepted is counted as silently wrong (or, for the ``cost`` class, as accepted and
expensive).

Usage::

    python -m benchmarks hostile_configs [--run] [--limit N] [--out results.csv]
    python benchmarks/hostile_configs.py --run

Figures (date, machine, CPU seconds) go to ``docs/validation.md``.
"""

from __future__ import annotations

import argparse
import copy
import os
import random
import sys
import tempfile
import time
import traceback
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]

#: Target size of the generated set (the issue's 260).
N_CONFIGS = 260

#: CPU seconds ``check-config`` may take on any config (the issue's target).
MAX_CHECK_CPU_S = 10.0

#: CPU seconds the jobs of an accepted config may take (``--run``; the issue's 10 CPU minutes):
#: the child running them is stopped there (RLIMIT_CPU) and the config counted as expensive.
MAX_JOB_CPU_S = 600.0

#: Special configs the pre-run check must refuse (their class and name): accepted, each is
#: silently wrong (or, class ``cost``, an accepted resource bomb). The others may run.
MUST_REFUSE_CLASSES = ("cost", "file", "plausibility", "yaml")


def base_config() -> dict:
    """The draft test config with the default ``sensor:`` and ``diagnosability:`` sections."""
    from bearing_envelope.study.config_read import read_configs, read_yaml

    base = read_configs([ROOT / "config.yaml", ROOT / "tests" / "data" / "config_draft.yaml"])
    full = read_yaml(ROOT / "config.yaml")
    for key in ("sensor", "diagnosability"):
        if key in full:
            base[key] = copy.deepcopy(full[key])
    return base


def _leaves(m, prefix=()):
    """Dotted paths of the scalar leaves of ``m`` (lists of scalars count as leaves)."""
    if isinstance(m, dict):
        for k, v in m.items():
            yield from _leaves(v, prefix + (k,))
    elif isinstance(m, list) and m and isinstance(m[0], dict):
        for i, v in enumerate(m):
            yield from _leaves(v, prefix + (i,))
    else:
        yield prefix


def _set(cfg: dict, path: tuple, value) -> dict:
    out = copy.deepcopy(cfg)
    node = out
    for k in path[:-1]:
        if isinstance(node, dict):
            node = node.setdefault(k, {})
        else:
            node = node[k]
    node[path[-1]] = value
    return out


def _dotted(path: tuple) -> str:
    return ".".join(f"[{p}]" if isinstance(p, int) else str(p) for p in path).replace(".[", "[")


#: Values tried on every numeric leaf (extremes) and on every leaf (wrong types).
EXTREMES = (0, -1, 1e-300, 1e300, 10 ** 70, 0.5000001)
WRONG_TYPES = ("abc", [1, 2], True, {"a": 1}, None)


def field_configs(base: dict) -> list[tuple[str, str, object]]:
    """(name, class, mapping) for every leaf: extremes of the numeric ones, wrong types."""
    out = []
    for path in _leaves(base):
        if not path or path[0] in ("paper_run", "limits", "tradeoff"):
            continue
        node = base
        for k in path:
            node = node[k]
        name = _dotted(path)
        if isinstance(node, (int, float)) and not isinstance(node, bool):
            for v in EXTREMES:
                out.append((f"{name}={v!r}", "extreme", _set(base, path, v)))
        if isinstance(node, list) and node and isinstance(node[0], (int, float)):
            for v in ([1e300], [-5], [0.5] * 3, list(range(1, 400)), []):
                out.append((f"{name}={str(v)[:20]}", "extreme", _set(base, path, v)))
        for v in WRONG_TYPES:
            if v is None and node is None:
                continue
            out.append((f"{name}={v!r}", "type", _set(base, path, v)))
    return out


def _tmpfile(directory: Path, name: str, text: str | bytes) -> str:
    p = directory / name
    p.write_bytes(text if isinstance(text, bytes) else text.encode())
    return str(p)


def special_configs(base: dict, work: Path) -> list[tuple[str, str, object]]:
    """The issue's failures inside a job, its silently wrong values, files and huge sweeps."""
    s = lambda *kv: _multi(base, kv)  # noqa: E731
    empty = _tmpfile(work, "empty.csv", "")
    huge_profile = _tmpfile(work, "huge_profile.csv",
                            "".join(f"{y},{1e300 if y == 0 else 0.0}\n" for y in range(-17, 18)))
    ball = {"designation": "SKF 6205-2RS", "inner_groove_conformity": 0.5000001}
    cwru = (("scene", "operation", "bpfi_override_hz"), None, ("sweep", "loads_kN"), [1.0],
            ("sweep", "depths_um"), [0, 177.8], ("scene", "defect", "length_um"), 177.8)
    edge_case = (("scene", "operation"), {"shaft_rate_hz": 29.95, "fs_hz": 48000.0,
                                          "revolutions": 10, "bpfi_override_hz": None},
                 ("sweep", "loads_kN"), [1.0], ("sweep", "depths_um"), [279.4],
                 ("scene", "defect"), {"location": "outer_race", "shape": "cylinder",
                                       "width_um": 177.8})
    out = [
        ("long case name", "issue", s(("sweep", "loads_kN"), [250.00000000000001234567891])),
        ("long band name", "issue", s(("analysis", "bands"), [{"name": "b" * 300,
                                                               "strategy": "kurtogram"}])),
        ("nlevel 12, 1 revolution", "issue", s(("analysis", "nlevel"), 12,
                                               ("scene", "operation", "revolutions"), 1)),
        ("groove conformity 0.5000001", "issue", s(("scene", "bearing"), ball, *cwru)),
        ("rolling element at position_deg", "issue",
         s(("scene", "bearing"), {"designation": "SKF 6205-2RS"}, *cwru,
           ("scene", "defect", "location"), "rolling_element",
           ("scene", "defect", "position_deg"), 90)),
        ("rolling element (CWRU ball)", "issue",
         s(("scene", "bearing"), {"designation": "SKF 6205-2RS"}, *cwru,
           ("scene", "defect", "location"), "rolling_element")),
        ("tone 1e300 dB", "issue", s(("sensor", "tones"), [{"order": 1, "level_db": 1e300}])),
        ("noise_snr_db -1e300", "issue", s(("scene", "operation", "noise_snr_db"), -1e300)),
        ("excitation_scale 1e308", "issue", s(("sensor", "excitation_scale"), 1e308)),
        ("huge profile value", "issue", s(("scene", "bearing", "profile_file"), huge_profile)),
        ("profile /dev/zero", "file", s(("scene", "bearing", "profile_file"), "/dev/zero")),
        ("profile empty", "file", s(("scene", "bearing", "profile_file"), empty)),
        ("profile directory", "file", s(("scene", "bearing", "profile_file"), str(work))),
        ("profile /proc", "file", s(("scene", "bearing", "profile_file"), "/proc/self/status")),
        ("edge_radius_um 1e6", "silent", s(("scene", "defect", "edge_radius_um"), 1e6)),
        ("position_deg on inner race", "silent", s(("scene", "defect", "position_deg"), 90)),
        ("band below resolution", "silent",
         s(("analysis", "bands"), [{"name": "tiny", "strategy": "fixed", "low_hz": 0.007,
                                    "high_hz": 0.014}])),
        ("harmonics 3.0", "silent", s(("analysis", "harmonics"), 3.0)),
        ("5000 kN on the 6205", "plausibility",
         s(("scene", "bearing"), {"designation": "SKF 6205-2RS"}, *cwru,
           ("sweep", "loads_kN"), [5000])),
        ("seed 1e70", "plausibility", s(("scene", "operation", "noise_seed"), 10 ** 70)),
        ("sensor seed 2^63", "plausibility", s(("sensor", "seed"), 2 ** 63)),
        ("clearance larger than the roller", "plausibility",
         s(("scene", "bearing", "radial_clearance_um"), 20000.0)),
        ("sweep 1000 x 1000", "size", s(("sweep", "loads_kN"), list(range(1, 1001)),
                                        ("sweep", "depths_um"), [0] + [1 + i * 0.5
                                                                       for i in range(999)])),
        ("sweep 100 x 100", "size", s(("sweep", "loads_kN"), list(range(1, 101)),
                                      ("sweep", "depths_um"), [0] + [1 + i * 0.5
                                                                     for i in range(99)])),
        ("sweep 40 x 25 (1000 cases)", "size",
         s(("sweep", "loads_kN"), list(range(100, 140)),
           ("sweep", "depths_um"), [0] + [10 + i for i in range(24)])),
        ("max_cases 0", "size", s(("limits", "max_cases"), 0)),
        ("width sweep x locations", "size",
         s(("sweep", "widths_um"), [20.0 + i for i in range(30)],
           ("sweep", "locations"), ["inner_race", "outer_race", "rolling_element"],
           ("sweep", "depths_um"), [0] + [10 + i for i in range(20)])),
        # issue 43's stress test: resource bombs the estimate must refuse, a silently ignored path
        ("global_dx_um 0.01 (draft)", "cost",
         s(("fidelity",), {"preset": "draft", "global_dx_um": 0.01})),
        ("false_alarm_trials 1e6", "cost",
         s(("diagnosability", "false_alarm_trials"), 10 ** 6)),
        ("false_alarm_trials 1e9", "cost",
         s(("diagnosability", "false_alarm_trials"), 10 ** 9)),
        ("10,000 SNR levels", "cost",
         s(("diagnosability", "snr_db"), [round(-80 + 0.028 * i, 3) for i in range(10000)])),
        ("1,000 bands", "cost",
         s(("analysis", "bands"), [{"name": f"b{i}", "strategy": "fixed",
                                    "low_hz": 1000.0 + i, "high_hz": 2000.0 + i}
                                   for i in range(1000)])),
        ("1,000 bands, 100 revolutions", "cost",
         s(("analysis", "bands"), [{"name": f"b{i}", "strategy": "fixed",
                                    "low_hz": 1000.0 + i, "high_hz": 2000.0 + i}
                                   for i in range(1000)],
           ("scene", "operation", "revolutions"), 100)),
        # issue 43 leftovers: the load zone's edge (simulate's own check of each case), a
        # global grid the solver cannot converge on, a light contact's refined table
        ("OR pit at 90 deg, zero clearance (never loaded)", "issue",
         s(("scene", "bearing"), {"designation": "SKF 6205-2RS", "radial_clearance_um": 0.0},
           *edge_case, ("scene", "defect", "position_deg"), 90)),
        ("OR pit at 90 deg, zero clearance, no detection map", "issue",
         s(("scene", "bearing"), {"designation": "SKF 6205-2RS", "radial_clearance_um": 0.0},
           *edge_case, ("scene", "defect", "position_deg"), 90,
           ("diagnosability", "enabled"), False)),
        ("OR pit at 75.36 deg, +10 um (2.8e-4 N contact)", "plausibility",
         s(("scene", "bearing"), {"designation": "SKF 6205-2RS", "radial_clearance_um": 10.0},
           *edge_case, ("scene", "defect", "position_deg"), 75.36)),
        ("global_dx_um 0.1 (draft)", "cost",
         s(("fidelity",), {"preset": "draft", "global_dx_um": 0.1})),
        ("OR pit at 90 deg, centrifugal (refined table)", "issue",
         s(("scene", "bearing"), {"designation": "SKF 6205-2RS"}, *edge_case,
           ("scene", "defect", "position_deg"), 90, ("scene", "load", "centrifugal"), True)),
        ("paper_run /nonexistent/run", "silent", s(("paper_run",), "/nonexistent/run")),
        ("paper_run without tables", "silent", s(("paper_run",), str(work))),
    ]
    return out


def _multi(base: dict, kv) -> dict:
    cfg = base
    for i in range(0, len(kv), 2):
        cfg = _set(cfg, kv[i], kv[i + 1])
    return cfg


#: The file the "yte code writing a file" config would create if anything evaluated it as a
#: template (the check must not: it reads every config as data).
YTE_WITNESS = Path(tempfile.gettempdir()) / "bearing_envelope_hostile_yte_witness"


def yaml_texts(base: dict) -> list[tuple[str, str, str | bytes]]:
    """(name, class, file text) of YAML oddities (the text is written as is)."""
    good = yaml.safe_dump(base, sort_keys=False)
    rev = good.replace("revolutions: 4", "revolutions: 1:30")
    bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n" for i in range(1, 9))
    return [
        ("revolutions 1:30 (base 60)", "yaml", rev),
        ("octal load 0750", "yaml", good.replace("- 750", "- 0750", 1)),
        ("hex fs", "yaml", good.replace("fs_hz: 65000.0", "fs_hz: 0xFDE8")),
        ("deep list 20000", "yaml", "sweep: " + "[" * 20000 + "]" * 20000 + "\n"),
        ("deep block list 500", "yaml", "sweep:\n" + "".join(" " * i + "- \n"
                                                              for i in range(0, 1000, 2))),
        ("alias bomb", "yaml", bomb),
        ("duplicate key", "yaml", good + "sweep: {loads_kN: [1], depths_um: [0]}\n"),
        ("tabs", "yaml", good.replace("  ", "\t", 3)),
        ("binary junk", "yaml", bytes(range(256)) * 4),
        ("empty file", "yaml", ""),
        ("a list at top", "yaml", "- 1\n- 2\n"),
        ("nan load", "yaml", good.replace("- 750", "- .nan", 1)),
        ("inf depth", "yaml", good.replace("- 50", "- .inf", 1)),
        ("yte code", "yaml", "__use_yte__: true\n" + good),
        ("yte code writing a file", "yaml",
         f"__use_yte__: true\nfidelity: ?open({str(YTE_WITNESS)!r}, 'w').write('x') and "
         f"'draft'\n"),
        ("yte expression", "yaml", "__use_yte__: true\nfidelity: ?\"dr\" + \"aft\"\n"),
        ("only comments", "yaml", "# nothing here\n\n# still nothing\n"),
        ("1e6 as text", "yaml", good.replace("edge_radius_um: 20.0", "edge_radius_um: 1e6")),
        ("yes as location", "yaml", good.replace("orientation: axial", "orientation: yes")),
        ("2 MB file", "yaml", good + "#" + "x" * (2 << 20) + "\n"),
    ]


def generate(work: Path, n: int = N_CONFIGS, seed: int = 34) -> list[tuple[str, str, str]]:
    """Write the hostile set under ``work``: ``[(name, class, path)]`` (deterministic)."""
    base = base_config()
    mapped = special_configs(base, work)
    texts = yaml_texts(base)
    fields = field_configs(base)
    rng = random.Random(seed)
    room = max(0, n - len(mapped) - len(texts))
    fields = rng.sample(fields, min(room, len(fields)))
    out = []
    for i, (name, cls, cfg) in enumerate(mapped + fields):
        text = yaml.safe_dump(cfg, sort_keys=False, width=10 ** 6)
        out.append((name, cls, _tmpfile(work, f"c{i:03d}.yaml", text)))
    for j, (name, cls, text) in enumerate(texts):
        out.append((name, cls, _tmpfile(work, f"y{j:03d}.yaml", text)))
    return out


def check(path: str) -> dict:
    """The pre-run check of one config file, as ``check-config FILE`` runs it (in this process,
    from the repository's root: the file is an overlay over ``./config.yaml``)."""
    from bearing_envelope.study.limits import checked_settings

    t0 = time.process_time()
    here = os.getcwd()
    try:
        os.chdir(ROOT)
        st, estimates = checked_settings([path])
        notes = [f"case {e.case}: {e.note}" for e in estimates if e.note]
        status, msg = "accepted", f"{len(st.cases)} cases" + "".join(f"; {n}" for n in notes)
    except ValueError as exc:      # ConfigError: the refusal this benchmark expects
        st, status, msg = None, "refused", str(exc)
    except (Exception, RecursionError) as exc:  # noqa: BLE001 -- a crash is a finding
        st, status, msg = None, "crashed", f"{type(exc).__name__}: {exc}"
    finally:
        os.chdir(here)
    return {"status": status, "message": msg.replace(path, "FILE"), "settings": st,
            "check_cpu_s": time.process_time() - t0,
            "one_line": "\n" not in msg, "names_field": _names_field(msg)}


def _names_field(msg: str) -> bool:
    """Whether a message names a config field or the file's line (``scene.bearing.x``,
    ``sweep.loads_kN[0]``, ``line 3``, a file-level problem)."""
    import re

    return bool(re.search(r"(^|: )[a-z_]+(\.[A-Za-z_0-9]+|\[[^\]]+\])*( x [a-z_]+| / [a-z_]+)?(:| must)|\bline \d+|"
                          r"config file|cannot read the config|nested|mapping|expands", msg))


def run_jobs(settings, work: Path) -> tuple[str, str]:
    """The jobs of the first and last case of an accepted config, as the workflow runs them.

    Returns
    -------
    (status, message)
        ``("ran", "")`` or ``("failed in a job", "<rule>: <error>")``.
    """
    from bearing_envelope.io import read_case, write_case
    from bearing_envelope.physics.history import simulate
    from bearing_envelope.study.pipeline import (case_acceleration, case_bands,
                                                 case_diagnosability, case_envelope)

    cases = settings.cases
    picks = [cases[0]] if len(cases) == 1 else [cases[0], cases[-1]]
    refs = {}
    for case in picks:
        rule = "simulate"
        try:
            hist = simulate(settings.scene(case), settings.fidelity, progress=False)
            path = work / f"{case.name}.h5"
            write_case(path, hist, extra_attrs={"case": case.name})
            c = read_case(path)
            rule = "bands"
            bands, _kg = case_bands(c, settings.analysis)
            rule = "envelope"
            case_envelope(c, settings.analysis, bands)
            if settings.sensor is not None:
                rule = "sensor"
                case_acceleration(c, settings.sensor, reference=refs.get(case.load_kN))
            if settings.sensor is not None and settings.diagnosability.enabled:
                rule = "diagnose"     # the detection map's job (workflow/rules/common.smk)
                case_diagnosability(c, settings.sensor, settings.analysis,
                                    settings.diagnosability.snr_db[:2],
                                    reference=refs.get(case.load_kN),
                                    kurtogram_from=settings.diagnosability.kurtogram_from)
            refs.setdefault(case.load_kN, c)
        except Exception as exc:  # noqa: BLE001 -- the finding
            last = traceback.format_exception_only(type(exc), exc)[-1].strip()
            return "failed in a job", f"{rule}: {last}"[:300]
    return "ran", ""


def main(argv: list[str] | None = None) -> int:
    """Generate, check (and with ``--run`` run) the hostile set; print a summary.

    Parameters
    ----------
    argv : list of str, optional
        ``[--run] [--limit N] [--out CSV] [--n N]``.

    Returns
    -------
    int
        0 when every config was refused in one line naming a field or (with ``--run``) ran,
        and every check took at most :data:`MAX_CHECK_CPU_S`; else 1.
    """
    import pandas as pd

    ap = argparse.ArgumentParser(prog="python -m benchmarks hostile_configs",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--run", action="store_true", help="run the accepted configs' jobs")
    ap.add_argument("--n", type=int, default=N_CONFIGS, help="configs generated (default 260)")
    ap.add_argument("--limit", type=int, default=None, help="check only the first N")
    ap.add_argument("--out", default=None, help="write the per-config results as CSV")
    args = ap.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory(prefix="hostile-") as tmp:
        work = Path(tmp)
        configs = generate(work, args.n)[: args.limit]
        for name, cls, path in configs:
            r = check(path)
            r["job_cpu_s"] = float("nan")
            if r["status"] == "accepted" and args.run:
                jobdir = work / "jobs"
                jobdir.mkdir(exist_ok=True)
                r["status"], r["job_message"], r["job_cpu_s"] = run_limited(r["settings"], jobdir)
            r.pop("settings")
            rows.append({"name": name, "class": cls, "must_refuse": must_refuse(name, cls), **r})
            print(f"{r['status']:>16}  {r['check_cpu_s']:6.2f} s  {cls:<12} {name[:40]:<40} "
                  f"{(r.get('job_message') or r['message'])[:110]}", flush=True)
    df = pd.DataFrame(rows)
    if args.out:
        df.to_csv(args.out, index=False)
    return _summary(df)


def must_refuse(name: str, cls: str) -> bool:
    """Whether the pre-run check must refuse this config (:data:`MUST_REFUSE_CLASSES`, and the
    silently wrong values but ``harmonics 3.0``, an integral float read as 3)."""
    return cls in MUST_REFUSE_CLASSES or (cls == "silent" and name != "harmonics 3.0")


def run_limited(settings, work: Path) -> tuple[str, str, float]:
    """:func:`run_jobs` in a forked child limited to :data:`MAX_JOB_CPU_S` CPU seconds.

    Returns
    -------
    (status, message, cpu_s)
        ``run_jobs``'s status and message, or ``("ran past the CPU limit", ...)`` when the
        child was stopped at the limit; the child's CPU seconds.
    """
    import multiprocessing as mp
    import resource

    ctx = mp.get_context("fork")
    queue = ctx.SimpleQueue()

    def child():
        limit = int(MAX_JOB_CPU_S)
        resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + 5))
        queue.put(run_jobs(settings, work))

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = ctx.Process(target=child)
    proc.start()
    proc.join()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.exitcode == 0 and not queue.empty():
        status, msg = queue.get()
        return status, msg, cpu
    if cpu >= MAX_JOB_CPU_S - 1:
        return "ran past the CPU limit", f"stopped at {cpu:.0f} CPU s", cpu
    return "failed in a job", f"the jobs' process died (exit code {proc.exitcode})", cpu


def _summary(df) -> int:
    refused = df["status"] == "refused"
    bad_refusal = refused & ~(df["one_line"] & df["names_field"])
    tracebacks = df["status"] == "crashed"
    accepted = ~refused & ~tracebacks
    expensive = accepted & ((df["class"] == "cost") | (df["status"] == "ran past the CPU limit"))
    silent = accepted & df["must_refuse"] & ~expensive
    bad = tracebacks | (df["status"] == "failed in a job") | bad_refusal | expensive | silent | \
        (df["check_cpu_s"] > MAX_CHECK_CPU_S)
    print(f"\n{len(df)} configs: " + ", ".join(f"{k} {v}" for k, v in
                                                  df["status"].value_counts().items()))
    print(f"tracebacks {int(tracebacks.sum())}, silently wrong {int(silent.sum())}, accepted "
          f"and expensive {int(expensive.sum())}, refusals naming the field "
          f"{int((refused & ~bad_refusal).sum())} of {int(refused.sum())}")
    print(f"refusals not one line naming a field: {int(bad_refusal.sum())}; check CPU s: "
          f"max {df['check_cpu_s'].max():.2f}, median {df['check_cpu_s'].median():.3f}, "
          f"total {df['check_cpu_s'].sum():.1f}")
    if df["job_cpu_s"].notna().any():
        print(f"jobs of the accepted configs: CPU s max {df['job_cpu_s'].max():.1f}, total "
              f"{df['job_cpu_s'].sum():.1f} (limit {MAX_JOB_CPU_S:g} per config)")
    for _, r in df[bad].iterrows():
        print(f"  FINDING {r['status']}: {r['name']}: {r.get('job_message') or r['message']}")
    return 1 if bad.any() else 0


def smoke() -> None:
    """Tiny run for the test suite: the first 12 configs checked, none crashing."""
    with tempfile.TemporaryDirectory(prefix="hostile-smoke-") as tmp:
        configs = generate(Path(tmp), N_CONFIGS)[:12]
        for _name, _cls, path in configs:
            r = check(path)
            assert r["status"] in ("refused", "accepted"), r["message"]
            assert r["status"] == "accepted" or r["one_line"], r["message"]


if __name__ == "__main__":
    sys.path.insert(0, os.fspath(ROOT / "src"))
    sys.exit(main(sys.argv[1:]))
