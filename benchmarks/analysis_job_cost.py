"""Where the CPU of the analysis jobs goes (issue 25 part 7): stages of the bands, envelope,
diagnose and false_alarms jobs on one load's cases of a default sweep, in CPU seconds
(``time.process_time``), and the cost of one envelope spectrum split into its transforms.

``python benchmarks/analysis_job_cost.py RESULTS_DIR [LOAD_kN]`` (a default sweep's
``results/``; the healthy case and the shallowest defect of the load). The false-alarm stage
runs 2 of the configured trials and is scaled to all of them (its cost is linear in trials).
"""

from __future__ import annotations

import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
IMPORTS = {  # what each workflow script imports (workflow/scripts/*.py)
    "python alone": "pass",
    "numpy": "import numpy",
    "numpy + scipy.signal": "import numpy, scipy.signal",
    "analysis job (bands/envelope/diagnose/false_alarms)":
        "import bearing_envelope.io, bearing_envelope.study.pipeline, bearing_envelope.study.tables",
    "simulate job": "import bearing_envelope.physics.history, bearing_envelope.io, "
                    "bearing_envelope.study.accuracy",
}


def import_cost(code: str, repeat: int = 3) -> float:
    """Median CPU seconds (user + system) of a fresh interpreter running ``code``."""
    out = []
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([sys.executable, "-c", code], check=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        out.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    return sorted(out)[len(out) // 2]


def _cpu(fn, *args, **kw):
    t = time.process_time()
    out = fn(*args, **kw)
    return time.process_time() - t, out


def stage_costs(results: Path, load: int) -> list[tuple[str, float]]:
    import yaml
    from bearing_envelope.io import read_case
    from bearing_envelope.study import pipeline as pl
    from bearing_envelope.study.settings import workflow_settings

    cfg = ROOT / "config.yaml"
    s = workflow_settings(yaml.safe_load(cfg.read_text()), [cfg])
    a, sensor, dg = s.analysis, s.sensor, s.diagnosability
    peer = min((d for d in s.sweep.depths_um if d > 0))
    rows = []
    t, healthy = _cpu(read_case, results / "cases" / f"F{load}kN_h0um.h5")
    rows.append(("read_case (one case file)", t))
    _, defect = _cpu(read_case, results / "cases" / f"F{load}kN_h{peer:g}um.h5")
    t, (bands, _kg) = _cpu(pl.case_bands, defect, a)
    rows.append(("bands: kurtogram + band limits", t))
    t, _ = _cpu(pl.case_envelope, defect, a, bands)
    rows.append((f"envelope: raw spectrum + {len(a.bands)} bands' lines", t))
    t, _ = _cpu(pl.diagnosability_bands, defect, sensor, a, reference=healthy)
    rows.append(("diagnose/false_alarms: bands on the clean acceleration", t))
    t, _ = _cpu(pl.case_diagnosability, defect, sensor, a, dg.snr_db, reference=healthy)
    rows.append((f"diagnose: whole map of a case ({len(dg.snr_db)} SNR x {len(a.bands)} bands)", t))
    t, _ = _cpu(pl.case_false_alarms, healthy, sensor, a, dg.snr_db, 2, reference=defect)
    rows.append((f"false_alarms: {dg.false_alarm_trials} trials (2 measured, scaled)",
                 t * dg.false_alarm_trials / 2))
    return rows


def envelope_spectrum_parts(n: int, fs: float = 65000.0) -> list[tuple[str, float]]:
    """CPU of one envelope spectrum of n samples, by part, and at the next fast FFT length."""
    import numpy as np
    from scipy import fft, signal

    from bearing_envelope.signal import envelope_spectrum
    from bearing_envelope.signal.envelope import bandpass

    x = np.random.default_rng(0).standard_normal(n)
    reps = 10
    parts = [("envelope_spectrum (band-pass, Hilbert, |.|, rfft)",
              lambda: envelope_spectrum(x, fs, (8125.0, 16250.0))),
             ("  band-pass (sosfiltfilt, order 4)", lambda: bandpass(x, fs, (8125.0, 16250.0))),
             ("  Hilbert: fft of the real record", lambda: fft.fft(x)),
             ("  Hilbert: ifft of the one-sided spectrum", lambda: fft.ifft(x.astype(complex))),
             ("  amplitude spectrum: rfft of the envelope", lambda: fft.rfft(x)),
             (f"  scipy.signal.hilbert at {n} samples", lambda: signal.hilbert(x)),
             (f"  scipy.signal.hilbert at the next fast length {fft.next_fast_len(n)}",
              lambda: signal.hilbert(x, fft.next_fast_len(n)))]
    out = []
    for name, fn in parts:
        fn()
        t = time.process_time()
        for _ in range(reps):
            fn()
        out.append((name, (time.process_time() - t) / reps))
    return out


def main(argv: list[str]) -> int:
    results = Path(argv[0])
    load = int(argv[1]) if len(argv) > 1 else 500
    print(f"load average at start: {open('/proc/loadavg').read().split()[:3]}")
    print("| start-up of a fresh interpreter | CPU s |\n|---|---:|")
    for name, code in IMPORTS.items():
        print(f"| {name} | {import_cost(code):.2f} |")
    print(f"\n| stage ({load} kN cases) | CPU s |\n|---|---:|")
    for name, t in stage_costs(results, load):
        print(f"| {name} | {t:.2f} |")
    import h5py
    with h5py.File(results / "cases" / f"F{load}kN_h0um.h5", "r") as f:
        n = int(f["time"].shape[0])
    print(f"\n| one envelope spectrum, {n} samples | CPU s |\n|---|---:|")
    for name, t in envelope_spectrum_parts(n):
        print(f"| {name} | {t:.3f} |")
    print(f"\nload average at end: {open('/proc/loadavg').read().split()[:3]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
