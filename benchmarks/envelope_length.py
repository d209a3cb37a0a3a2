"""Envelope spectra at the sweep's record length, before and after issue 25's FFT change (run by
hand; results in docs/benchmarks.md, "Envelope spectra without Bluestein").

The default sweep's records have 411,392 = 2^8 x 1607 samples (100 revolutions at 15.8 Hz and
65 kHz): a length with a large prime factor, for which pocketfft runs Bluestein's algorithm.
Timed side by side in one process, interleaved, best of ``--repeat`` (CPU s per call):

* ``before``: the chain as it was: ``scipy.signal.hilbert`` over the record's own length and the
  full one-sided spectrum (``scipy.fft.rfft``);
* ``after, full``: :func:`bearing_envelope.signal.envelope_spectrum` (Hilbert zero-padded to a
  fast length, the mean removed first; the full spectrum): the envelope and bands rules;
* ``after, map``: the same up to 1.5 x BPFI (``fmax_hz``, a zoom transform): the detection map's
  and the false-alarm trials' spectra.

It also reports how far the new envelope spectrum is from the old one on the same signal (the
largest difference over the bins up to 3.5 x BPFI, relative to the 1 x BPFI line), and the
start-up of every row at the next fast length, for scale.

    python benchmarks/envelope_length.py [--repeat 7] [--n 411392]
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import time

import numpy as np
from scipy import fft as sp_fft
from scipy import signal as sp_signal

from bearing_envelope.signal import envelope_spectrum
from bearing_envelope.signal.envelope import bandpass
from bearing_envelope.signal.spectrum import _window
from signal_speed import synthetic_case

FS, BPFI, BAND = 65000.0, 231.9, (16250.0, 31850.0)


def before(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The former chain: band-pass, circular Hilbert at len(x), full windowed rfft."""
    y = bandpass(x, FS, BAND)
    e = np.abs(sp_signal.hilbert(y))
    e = e - e.mean()
    w = _window("hann", e.size)
    a = np.abs(sp_fft.rfft(e * w)) * (2.0 / w.sum())
    a[0] *= 0.5
    return np.arange(a.size) * FS / e.size, a


def after_full(x):
    return envelope_spectrum(x, FS, BAND)


def after_map(x):
    return envelope_spectrum(x, FS, BAND, fmax_hz=1.5 * BPFI)


def best_cpu(fn, x, repeat: int) -> float:
    out = []
    for _ in range(repeat):
        t0 = time.process_time()
        fn(x)
        out.append(time.process_time() - t0)
    return min(out)


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--n", type=int, default=411392)
    args = p.parse_args(argv)
    x = synthetic_case(args.n)
    print(f"# {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, {platform.node()}, "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}; n = {args.n} "
          f"(next fast length {sp_fft.next_fast_len(args.n)})")
    rows = {"before": before, "after, full": after_full, "after, map (<= 1.5 x BPFI)": after_map}
    t = {k: [] for k in rows}
    for _ in range(3):  # interleaved
        for k, fn in rows.items():
            t[k].append(best_cpu(fn, x, max(1, args.repeat // 3)))
    base = min(t["before"])
    print("| envelope spectrum | CPU s per call (best) | x before |\n|---|---:|---:|")
    for k in rows:
        print(f"| {k} | {min(t[k]):.4f} | {min(t[k]) / base:.2f} |")
    f0, a0 = before(x)
    f1, a1 = after_full(x)
    f2, a2 = after_map(x)
    sel = f0 <= 3.5 * BPFI
    line = a0[np.argmin(np.abs(f0 - BPFI))]
    print(f"\nlargest |after - before| up to 3.5 x BPFI: {np.max(np.abs(a1[sel] - a0[sel])) / line:.2e} "
          f"of the 1 x BPFI line; map vs full on its {a2.size} bins: "
          f"{np.max(np.abs(a2 - a1[:a2.size])) / line:.2e}")


if __name__ == "__main__":
    main()
