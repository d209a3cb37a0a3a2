"""Speed of the signal chain (docs/benchmarks.md, "Signal chain").

1. Fast kurtogram of a 411,000-sample signal (100 revolutions at fs = 65 kHz) to nlevel 8:
   ``bearing_envelope.signal.fast_kurtogram`` against the straightforward port of Antoni's
   MATLAB code in the ``openconmo`` package (``pip install openconmo``; benchmark only), timed
   side by side in one process, interleaved, best of N. Also checks that both give the same
   kurtogram (rows 1.. ; row 0 differs by convention: analytic vs real signal).
2. The whole chain (``analyze_signal`` with the default bands: kurtogram, fs/4-3fs/8,
   3-6 x BPFI, 10-13 x BPFI; AnalysisOptions' defaults: K = 3 harmonics, M = 2 sidebands, 3
   raw orders) on the same signal.

The machine is shared: quote ratios measured side by side, not absolute times alone.

    python -m benchmarks signal_speed [--repeat 7] [--n 411000]
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import subprocess
import time

import numpy as np


def synthetic_case(n: int, fs: float = 65000.0, fr: float = 15.8, bpfi: float = 231.9,
                   fn: float = 12000.0, seed: int = 0) -> np.ndarray:
    """Impulses at BPFI (1 % jitter) ringing at fn, AM at fr, strong fr tone, noise at 0 dB."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    x = np.zeros(n)
    times = np.arange(0.5 / bpfi, t[-1] - 0.01, 1.0 / bpfi)
    times = times + rng.uniform(-0.01, 0.01, times.size) / bpfi
    L = int(0.004 * fs)
    tt = np.arange(L) / fs
    ring = np.exp(-2000.0 * tt) * np.sin(2 * np.pi * fn * tt)
    for t0 in times:
        i = int(round(t0 * fs))
        seg = x[i : i + L]
        seg += (1 + 0.5 * np.cos(2 * np.pi * fr * t0)) * ring[: seg.size]
    rms = np.sqrt(np.mean(x**2))
    return x + rms * rng.standard_normal(n) + 10 * rms * np.sqrt(2) * np.sin(2 * np.pi * fr * t)


def machine() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, timeout=5).stdout
        keep = ("Model name", "CPU(s):", "Thread(s) per core", "L2 cache", "L3 cache")
        lines = [ln.strip() for ln in out.splitlines() if ln.strip().startswith(keep)]
    except OSError:
        lines = [platform.processor()]
    return "; ".join(" ".join(ln.split()) for ln in lines)


def timeit(fn, repeat: int, clock=time.perf_counter) -> list[float]:
    """Seconds of ``repeat`` calls of ``fn`` on ``clock``."""
    out = []
    for _ in range(repeat):
        t0 = clock()
        fn()
        out.append(clock() - t0)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=411_000, help="samples (default 411000)")
    ap.add_argument("--nlevel", type=int, default=8)
    ap.add_argument("--repeat", type=int, default=7, help="best of N (default 7)")
    ap.add_argument("--clock", choices=("cpu", "wall"), default="cpu",
                    help="process CPU seconds (default; the machine is shared) or wall seconds")
    args = ap.parse_args(argv)
    clock = time.process_time if args.clock == "cpu" else time.perf_counter

    def timeit_(fn, repeat):
        return timeit(fn, repeat, clock)

    import numba
    import scipy

    from bearing_envelope.diagnosis import analyze_signal
    from bearing_envelope.signal import fast_kurtogram

    fs, fr, bpfi = 65000.0, 15.8, 231.9
    x = synthetic_case(args.n, fs, fr, bpfi)
    print(f"date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M UTC}")
    print(f"machine: {machine()}")
    print(f"load average at start: {os.getloadavg()}")
    print(f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}"
          f", numba {numba.__version__}, numba threads {numba.get_num_threads()}")
    print(f"signal: {args.n} samples at {fs:g} Hz, nlevel {args.nlevel}, best of {args.repeat}, "
          f"{'process CPU' if args.clock == 'cpu' else 'wall'} seconds")

    t0 = time.perf_counter()
    ours = fast_kurtogram(x, fs, args.nlevel)
    print(f"first call (JIT compile or cache load): {time.perf_counter() - t0:.2f} s")

    try:
        from openconmo.kurtogram import fast_kurtogram as oc_fast_kurtogram
    except ImportError:
        oc_fast_kurtogram = None
        print("openconmo not installed: no side-by-side comparison (pip install openconmo)")

    t_ours, t_oc = [], []
    for _ in range(args.repeat):  # interleaved, so both see the same machine load
        t_ours += timeit_(lambda: fast_kurtogram(x, fs, args.nlevel), 1)
        if oc_fast_kurtogram is not None:
            xc = x.copy()  # openconmo de-means its input in place
            t_oc += timeit_(lambda: oc_fast_kurtogram(xc, fs, args.nlevel), 1)
    print("\n## fast kurtogram")
    print(f"bearing_envelope: best {min(t_ours):.3f} s, median {np.median(t_ours):.3f} s")
    if t_oc:
        print(f"openconmo 0.0.6:  best {min(t_oc):.3f} s, median {np.median(t_oc):.3f} s")
        print(f"speed-up: {min(t_oc) / min(t_ours):.1f}x (best/best), "
              f"{np.median(t_oc) / np.median(t_ours):.1f}x (median/median)")
        kw, _, _, fc, bw = oc_fast_kurtogram(x.copy(), fs, args.nlevel)[:5]
        diff = np.abs(np.asarray(kw)[1:] - ours.matrix[1:])
        print(f"same map: max |dK| over rows 1.. = {diff.max():.3f} (relative to max K "
              f"{ours.kurtosis:.2f}); best cell ours fc = {ours.fc:g} Hz / B = "
              f"{ours.bandwidth:g} Hz, openconmo fc = {float(fc):g} Hz / B = {float(bw):g} Hz")

    analyze_signal(x, fs, fr=fr, bpfi=bpfi)  # warm-up
    t_chain = timeit_(lambda: analyze_signal(x, fs, fr=fr, bpfi=bpfi), args.repeat)
    print("\n## whole chain (analyze_signal, default bands)")
    print(f"best {min(t_chain):.3f} s, median {np.median(t_chain):.3f} s")
    # breakdown of one run
    from bearing_envelope.signal import amplitude_spectrum, envelope_spectrum

    t_raw = min(timeit_(lambda: amplitude_spectrum(x, fs), 3))
    t_env = min(timeit_(lambda: envelope_spectrum(x, fs, (16250.0, 24375.0)), 3))
    print(f"parts: raw spectrum {t_raw:.3f} s, kurtogram {min(t_ours):.3f} s, "
          f"one band (band-pass + Hilbert + spectrum) {t_env:.3f} s x 4 bands")
    print(f"load average at end: {os.getloadavg()}")
    return 0


def smoke() -> None:
    """The whole benchmark on a 20,000-sample signal, one repeat, nlevel 4."""
    main(["--n", "20000", "--nlevel", "4", "--repeat", "1"])


if __name__ == "__main__":
    main()
