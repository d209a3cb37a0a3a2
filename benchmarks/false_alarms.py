"""False-alarm rate of the detection test by construction: pure Gaussian noise.

    nice -n 5 python -m benchmarks false_alarms [--trials 1000] [--revolutions 100]
        [--bands kurtogram fixed ...] [--save out.npz]

White Gaussian noise at fs = 65 kHz (the sweep's record: 100 revolutions of fr = 15.8 Hz,
411,392 samples) goes through exactly the chain of the rule ``false_alarms``
(``signal.envelope_spectrum``: 4th-order Butterworth band-pass, zero phase, Hilbert envelope,
mean removed, Hann window; then ``diagnosis.detection_statistic`` at BPFI = 231.9 Hz with the
shaft rate 15.8 Hz), in each of the sweep's five bands. The answer is known: there is no line,
so every detection is a false alarm and the rate must be ``pfa`` (1 %). This separates "the
threshold is wrong" from "the healthy signal has lines".

Each trial draws one noise record (seed ``[seed, trial]``) and demodulates it in every band (the
bands overlap little, so their rates are nearly independent). Prints per band: trials, false
alarms, rate and its 95 % Clopper-Pearson interval, and the 99 % quantile of the statistic
against the threshold. ``--save`` keeps the envelope-spectrum amplitudes below 1.6 x BPFI of
every trial and band (to evaluate other backgrounds or thresholds without re-running the chain).

    nice -n 5 python -m benchmarks false_alarms --model SAVED.npz [--model-trials 50000]

evaluates, from a saved run, a model of the same spectra with many more trials: complex Gaussian
bins with the measured mean spectral shape (E[a^2] per bin, averaged over the saved records and
smoothed over 101 bins) and the Hann window's correlation of neighbouring bins; per band the
false-alarm rate of the statistic before issue 16 (one median over 0.5-1.5 x BPFI, asymptotic
threshold), with the exact threshold only, and of the map's statistic after it (mean of the
medians either side over 0.8-1.2 x BPFI, exact threshold), vectorised (the same formulas as
``diagnosis.detection_statistic``, whose local-maximum rule is omitted: it removes < 0.01 %).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bearing_envelope.diagnosis.detection import clopper_pearson, detection_statistic
from bearing_envelope.signal import envelope_spectrum

FS = 65000.0
FR = 15.8
BPFI = 231.9
#: The default sweep's bands (config.yaml; the kurtogram band of the healthy and defect cases is
#: the clamped top cell of level 1.5, 16.25-31.85 kHz).
BANDS = {
    "kurtogram": (16250.0, 31850.0),
    "fs4_3fs8": (16250.0, 24375.0),
    "bpfi_3_6": (3 * BPFI, 6 * BPFI),
    "bpfi_10_13": (10 * BPFI, 13 * BPFI),
    "fixed": (8125.0, 16250.0),
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--trials", type=int, default=1000)
    ap.add_argument("--revolutions", type=float, default=100.0)
    ap.add_argument("--bands", nargs="*", default=list(BANDS))
    ap.add_argument("--seed", type=int, default=16)
    ap.add_argument("--save", default=None)
    ap.add_argument("--model", default=None)
    ap.add_argument("--model-trials", type=int, default=50_000)
    args = ap.parse_args(argv)
    if args.model:
        model(args.model, args.model_trials, args.seed)
        return 0
    n = int(round(args.revolutions / FR * FS))
    n = 411392 if args.revolutions == 100.0 else n  # the sweep's record length
    keep = None
    det = {b: [] for b in args.bands}
    stat = {b: [] for b in args.bands}
    slices = {b: [] for b in args.bands}
    thr = {}
    t0 = time.process_time()
    for trial in range(args.trials):
        x = np.random.default_rng([args.seed, trial]).standard_normal(n)
        for b in args.bands:
            f, a = envelope_spectrum(x, FS, BANDS[b], order=4)
            d = detection_statistic(f, a, BPFI, fr=FR)
            det[b].append(d.detected)
            stat[b].append(d.statistic_db)
            thr[b] = d.threshold_db
            if args.save:
                if keep is None:
                    keep = f <= 1.6 * BPFI
                    f_keep = f[keep]
                slices[b].append(a[keep].astype(np.float32))
    cpu = time.process_time() - t0
    print(f"{args.trials} trials x {len(args.bands)} bands, N = {n} samples, "
          f"{cpu:.0f} s CPU ({cpu / args.trials / len(args.bands):.3f} s per record and band)\n")
    print("| band | trials | false alarms | rate | 95 % CI | threshold (dB) | 99 % quantile of S (dB) |")
    print("|---|---|---|---|---|---|---|")
    for b in args.bands:
        k, m = int(np.sum(det[b])), len(det[b])
        lo, hi = clopper_pearson(k, m)
        print(f"| {b} | {m} | {k} | {100 * k / m:.2f} % | {100 * lo:.2f}-{100 * hi:.2f} % | "
              f"{thr[b]:.2f} | {np.quantile(stat[b], 0.99):.2f} |")
    if args.save:
        np.savez_compressed(args.save, f=f_keep, **{b: np.array(slices[b]) for b in args.bands})
    return 0


def smoke() -> None:
    """Two trials of ten revolutions in two bands, saved, then the model from the saved run."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        saved = str(Path(d, "saved.npz"))
        main(["--trials", "2", "--revolutions", "10", "--bands", "fixed", "bpfi_3_6",
              "--save", saved])
        main(["--model", saved, "--model-trials", "20"])


def _background(f, lo, hi, half):
    """The background mask of ``detection_statistic`` (fr harmonics and sidebands excluded)."""
    import math

    bg = (f >= lo * BPFI) & (f <= hi * BPFI) & (f > 0)
    centres = [k * BPFI + m * FR for k in range(1, int(math.ceil(hi)) + 2) for m in range(-3, 4)]
    centres += list(FR * np.arange(1, int(hi * BPFI / FR) + 2))
    for c in centres:
        bg &= np.abs(f - c) > half
    return bg


def model(path, trials, seed):
    from scipy.ndimage import uniform_filter1d

    from bearing_envelope.diagnosis.detection import threshold_db
    from bearing_envelope.study.pipeline import MAP_BACKGROUND

    saved = np.load(path)
    f = saved["f"].astype(float)
    half = 0.01 * BPFI
    tol = np.flatnonzero(np.abs(f - BPFI) <= half + 1e-9 * (f[1] - f[0]))
    n = tol.size
    wide = _background(f, 0.5, 1.5, half)
    near = _background(f, *MAP_BACKGROUND, half)
    below, above = near & (f < BPFI), near & (f > BPFI)
    thr = {"before": threshold_db(0.01, n), "exact": threshold_db(0.01, n, int(wide.sum())),
           "after": threshold_db(0.01, n, (int(below.sum()), int(above.sum())))}
    rng = np.random.default_rng([seed, 1])
    print(f"{trials} model spectra per band; n = {n} bins searched; thresholds (dB): before "
          f"{thr['before']:.2f}, exact threshold only {thr['exact']:.2f} ({int(wide.sum())} bins), "
          f"after {thr['after']:.2f} ({int(below.sum())} + {int(above.sum())} bins)\n")
    print("| band | amplitude at 0.5 / 1.5 x BPFI (re BPFI) | before | exact threshold only | after |")
    print("|---|---|---|---|---|")
    for b in [k for k in saved.files if k != "f"]:
        a2 = (saved[b].astype(float) ** 2).mean(axis=0)
        sigma = np.sqrt(uniform_filter1d(a2, 101, mode="nearest"))
        ref = sigma[tol].mean()
        k = dict.fromkeys(thr, 0)
        batch = min(5000, trials)
        for _ in range(trials // batch):
            z = rng.standard_normal((batch, f.size + 2)) + 1j * rng.standard_normal((batch, f.size + 2))
            a = np.abs((0.5 * z[:, 1:-1] - 0.25 * z[:, :-2] - 0.25 * z[:, 2:]) * sigma)
            peak = a[:, tol].max(axis=1)
            s_wide = 20 * np.log10(peak / np.median(a[:, wide], axis=1))
            s_near = 20 * np.log10(peak / (0.5 * (np.median(a[:, below], axis=1)
                                                   + np.median(a[:, above], axis=1))))
            k["before"] += int((s_wide > thr["before"]).sum())
            k["exact"] += int((s_wide > thr["exact"]).sum())
            k["after"] += int((s_near > thr["after"]).sum())
        m = batch * (trials // batch)
        cells = []
        for key in ("before", "exact", "after"):
            lo, hi = clopper_pearson(k[key], m)
            cells.append(f"{100 * k[key] / m:.2f} % ({100 * lo:.2f}-{100 * hi:.2f})")
        print(f"| {b} | {sigma[np.argmin(abs(f - 0.5 * BPFI))] / ref:.2f} / "
              f"{sigma[np.argmin(abs(f - 1.5 * BPFI))] / ref:.2f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
