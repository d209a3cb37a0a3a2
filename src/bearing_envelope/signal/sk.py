"""STFT-based spectral kurtosis."""

from __future__ import annotations

import numpy as np

from .kurtogram import fast_kurtogram
from .spectrum import DEFAULT_WINDOW
from .validation import check_fs, check_signal
from ..lazy import lazy_module

sp_signal = lazy_module("scipy.signal")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["spectral_kurtosis"]


def spectral_kurtosis(
    x,
    fs: float,
    nperseg: int | None = None,
    *,
    overlap: float = 0.8,
    window=DEFAULT_WINDOW,
    nlevel: int | None = None,
    return_frames: bool = False,
):
    r"""Spectral kurtosis from the short-time Fourier transform.

    Parameters
    ----------
    x : array_like, 1-D
        Real signal.
    fs : float
        Sampling frequency (Hz), > 0.
    nperseg : int, optional
        Window length (samples), >= 4. When omitted it is taken from the best cell of the fast
        kurtogram of ``x`` (:func:`fast_kurtogram` with ``nlevel``):
        ``nperseg = round(fs / bandwidth) = 2**(level + 1)``, so that the STFT resolution
        equals the kurtogram band, but at least 16.
    overlap : float, default 0.8
        Fraction of overlap of successive windows, in ``[0, 1)``; the hop is
        ``max(1, round(nperseg (1 - overlap)))``.
    window : str or tuple, default "hann"
        Window, see :func:`scipy.signal.get_window`.
    nlevel : int, optional
        Depth of the kurtogram used to pick ``nperseg`` (default as in :func:`fast_kurtogram`).
    return_frames : bool, default False
        Also return the number of frames used.

    Returns
    -------
    f : ndarray
        Frequencies (Hz), ``0 .. fs/2`` in steps of ``fs / nperseg``.
    sk : ndarray
        Spectral kurtosis at each frequency (dimensionless).
    n_frames : int
        Only with ``return_frames``.

    Raises
    ------
    ValueError
        Bad ``x``, ``fs``, ``nperseg`` or ``overlap``, or too few frames (< 2).

    Notes
    -----
    With :math:`X(t_j, f)` the STFT over frames fully inside the signal
    (``ShortTimeFFT.p_min`` .. ``p_max`` excluding the zero-padded edge frames),

    .. math:: SK(f) = \frac{\langle |X(t_j, f)|^4 \rangle_j}
                           {\langle |X(t_j, f)|^2 \rangle_j^2} - 2 .

    A stationary Gaussian signal gives :math:`SK \approx 0` with a bias of order
    :math:`1/K` (K independent frames; overlapping frames are correlated, so the effective K
    is smaller). At 0 Hz and fs/2 the STFT coefficients are real, so a Gaussian gives
    :math:`SK \approx 1` there (real fourth moment 3); ignore the edge bins. A pure tone
    gives -1 and impulsive content positive values.

    References
    ----------
    .. [1] J. Antoni, "The spectral kurtosis: a useful tool for characterising non-stationary
       signals", Mechanical Systems and Signal Processing 20 (2006) 282-307.
    """
    fs = check_fs(fs)
    x = check_signal(x, "x", min_length=4)
    overlap = float(overlap)
    if not (0.0 <= overlap < 1.0):
        raise ValueError(f"overlap must be in [0, 1), got {overlap!r}")
    if nperseg is None:
        kg = fast_kurtogram(x, fs, nlevel)
        nperseg = max(16, kg.window_length)
    if isinstance(nperseg, bool) or int(nperseg) != nperseg or int(nperseg) < 4:
        raise ValueError(f"nperseg must be an integer >= 4, got {nperseg!r}")
    nperseg = int(nperseg)
    if nperseg > x.size:
        raise ValueError(f"nperseg={nperseg} is longer than x ({x.size} samples)")
    hop = max(1, int(round(nperseg * (1.0 - overlap))))
    win = sp_signal.get_window(window, nperseg)
    stft = sp_signal.ShortTimeFFT(win, hop, fs, fft_mode="onesided", scale_to="magnitude")
    p0 = stft.lower_border_end[1]
    p1 = stft.upper_border_begin(x.size)[1]
    if p1 - p0 < 2:
        raise ValueError(
            f"x ({x.size} samples) gives fewer than 2 full frames with nperseg={nperseg}, "
            f"hop={hop}"
        )
    spec = stft.stft(x - x.mean(), p0=p0, p1=p1)
    p2 = spec.real**2 + spec.imag**2
    m2 = p2.mean(axis=1)
    m4 = (p2 * p2).mean(axis=1)
    sk = np.zeros_like(m2)
    ok = m2 > 0
    sk[ok] = m4[ok] / (m2[ok] ** 2) - 2.0
    f = stft.f
    if return_frames:
        return f, sk, int(p1 - p0)
    return f, sk
