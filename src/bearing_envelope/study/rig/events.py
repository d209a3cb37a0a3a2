"""The shape of a race fault's events in a record, measured and simulated alike.

The rig's harmonic ratios (2x/1x, 3x/1x) are set by how the events spread in time: a squared
envelope's synchronous average at the fault's rate is the coherent part of its harmonic series
(:mod:`bearing_envelope.signal.cycles`). Read on the measured record and on its simulated twin
in one band (analyze's fixed band fs/4-3fs/8), it says *why* the ratios differ:

- ``contrast_db``: the average's peak over its floor (its lower quartile), dB: how clearly the
  events stand out;
- ``width_ms``: the r.m.s. width of the event in the average at the fault's rate (BPFO or
  BPFI), ms;
- ``element_spread_db`` (outer race): the average at the cage's rate (BPFO / Z) holds each
  rolling element's own event; the strongest over the weakest element's event energy, dB
  (``inf``: an element without an event). A fault met equally by every element gives about
  0 dB;
- ``secondary_events`` (outer race): per element, further events in its window of that average
  (each element's passage one event: 0).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy import fft as sp_fft
from scipy import signal as sps

from ...physics.locations import get_location
from ...signal.cycles import (FLOOR_PERCENTILE, RATE_SEARCH, burst_width, cycle_rate,
                              element_windows, synchronous_average)
from ...signal.envelope import bandpass, envelope, settling_samples
from ...signal.validation import check_band, check_fs
from .records import read_samples

__all__ = ["event_shape", "event_shapes", "squared_envelope", "record_pairs", "MIN_CONTRAST_DB",
           "ELEMENT_BINS"]

#: Phase bins of the averages at the fault's rate and, per element, at the cage's rate.
FAULT_BINS = 100
ELEMENT_BINS = 40
#: Below this contrast (the average's peak over its floor, the lower quartile) a record holds no
#: events in the band (the average of noise alone stays within about 1 dB of its floor): its
#: widths and spreads are not read (NaN).
MIN_CONTRAST_DB = 3.0
#: A secondary event: a peak of an element's window of the average at the cage's rate, at least
#: this fraction of the window's highest ...
SECONDARY_LEVEL = 0.25
#: ... and at least this far (s) from any higher one; counted only where the average at the
#: fault's rate stands this far over its floor (its peak 4x the floor): below, the floor's own
#: wiggles reach a quarter of a weak burst (a simulated record at 3.8 dB read 5.6 per element).
SECONDARY_SEPARATION_S = 0.4e-3
SECONDARY_MIN_CONTRAST_DB = 6.0


def squared_envelope(x, fs: float, rate_hz: float, band=None, search: float = RATE_SEARCH):
    """Squared envelope in ``band`` (default fs/4-3fs/8), the filter's edge transients cut at
    both ends, and the event rate refined on it within ``search`` (relative).

    Parameters
    ----------
    x : array_like, 1-D
        The record.
    fs : float
        Sampling rate, Hz.
    rate_hz : float
        Nominal event rate, Hz.
    band : (float, float), optional
        Demodulation band, Hz.
    search : float
        Relative half-width of the rate's refinement.

    Returns
    -------
    (numpy.ndarray, float)
        The squared envelope and the refined rate, Hz.
    """
    fs = check_fs(fs)
    band = check_band((fs / 4, 3 * fs / 8) if band is None else band, fs)
    edge = settling_samples(fs, band)
    e = envelope(bandpass(x, fs, band), squared=True)[edge:-edge]
    return e, cycle_rate(e, fs, rate_hz, search=search)


def event_shape(x, fs: float, rate_hz: float, *, n_elements: int | None = None,
                band=None, search: float = RATE_SEARCH) -> dict:
    """Width of a fault's events and the spread of the elements' events, from a record.

    Parameters
    ----------
    x : array_like, 1-D
        The record (acceleration), sampled at ``fs``.
    fs : float
        Sampling rate, Hz.
    rate_hz : float
        Nominal event rate (BPFO, BPFI), Hz; refined on the record within ``search``.
    n_elements : int, optional
        Elements passing a fixed defect once each per cage turn (outer race: Z); with it the
        element spread is measured at ``rate / n_elements``.
    band : (float, float), optional
        Demodulation band, Hz; default ``(fs/4, 3 fs/8)``.
    search : float, default 0.01
        Relative half-width of the rate's refinement
        (:func:`~bearing_envelope.signal.cycles.cycle_rate`; a rolling element slips: 0.015).

    Returns
    -------
    dict
        ``rate_hz`` (refined), ``contrast_db`` (the average's peak over its floor, the lower
        quartile: how clearly the record holds the event; near 0 dB the rest would read noise),
        ``width_ms``, ``h2_db`` and ``h3_db`` (the average's harmonics
        over its fundamental: the coherent part of the squared envelope spectrum's ratios), and
        with ``n_elements`` ``element_spread_db`` and ``secondary_events`` (per element, the
        mean count of further events in its window: peaks at least :data:`SECONDARY_LEVEL`
        of its highest, :data:`SECONDARY_SEPARATION_S` apart; NaN below
        :data:`SECONDARY_MIN_CONTRAST_DB`); all but the rate and the contrast NaN when the
        contrast is below :data:`MIN_CONTRAST_DB`.
    """
    e, rate = squared_envelope(x, fs, rate_hz, band, search)
    out = {"rate_hz": rate, **_fault_fold(e, fs, rate)}
    if n_elements:
        if np.isfinite(out["width_ms"]):
            out.update(_element_fold(e, fs, rate, n_elements))
        else:
            out.update(element_spread_db=np.nan, secondary_events=np.nan)
        if out["contrast_db"] < SECONDARY_MIN_CONTRAST_DB:
            out["secondary_events"] = np.nan
    return out


def _fault_fold(e, fs: float, rate: float) -> dict:
    """Contrast, width and harmonic ratios of the squared envelope's average at the rate."""
    avg = synchronous_average(e, fs, rate, bins=min(FAULT_BINS, int(fs / rate)))
    contrast = 10 * np.log10(avg.max() / np.percentile(avg, FLOOR_PERCENTILE))
    if contrast < MIN_CONTRAST_DB:
        return {"contrast_db": contrast, "width_ms": np.nan, "h2_db": np.nan, "h3_db": np.nan}
    c = np.abs(sp_fft.rfft(avg - avg.mean())[1:4])
    return {"contrast_db": contrast, "width_ms": 1e3 * burst_width(avg) / rate,
            "h2_db": 20 * np.log10(c[1] / c[0]), "h3_db": 20 * np.log10(c[2] / c[0])}


def _element_fold(e, fs: float, rate: float, z: int) -> dict:
    """Element spread and secondary events from the average at the cage's rate (a bin per
    sample)."""
    n_bins = int(fs * z / rate) // z * z
    windows = element_windows(synchronous_average(e, fs, rate / z, bins=n_bins), z)
    lv = np.array([w.sum() for w in windows])
    sep = max(int(SECONDARY_SEPARATION_S * n_bins * rate / z), 1)   # bins of the cage's turn
    secondary = [sps.find_peaks(w, height=SECONDARY_LEVEL * w.max(), distance=sep)[0].size - 1
                 for w in windows]
    return {"element_spread_db": 10 * np.log10(lv.max() / lv.min()) if lv.min() > 0 else np.inf,
            "secondary_events": float(np.mean(secondary))}


def event_shapes(conditions, sim_dir) -> list:
    """:func:`event_shape` of every race record and its simulated twin (``sim_dir``).

    Parameters
    ----------
    conditions : sequence of RigCondition
        The rig's records; ball records are skipped (their events follow the ball's spin, not
        one rate the record holds at every load).
    sim_dir : path
        The simulated records (``<name>_sim.npz``).

    Returns
    -------
    list of dict
        Per record: name, location, position, load, fs and each feature measured (``meas_``)
        and simulated (``sim_``).
    """
    races = [c for c in conditions if not get_location(c.location).spins]
    rows = [{"record": c.name, "location": c.location, "position_deg": c.position_deg,
             "length_um": c.length_um, "load": c.load, "fs_hz": c.fs_hz}
            for c in races]
    for i, _, c, side, path in record_pairs(races, sim_dir):
        loc = get_location(c.location)  # a fixed defect: each element once per cage turn
        shape = event_shape(read_samples(path), c.fs_hz, c.rates[loc.family],
                            n_elements=c.bearing.n_rollers if loc.positioned else None)
        rows[i].update({f"{side}_{k}": v for k, v in shape.items()})
    return rows


def record_pairs(conditions, sim_dir):
    """Each record and its simulated twin, in the order of a two-column figure.

    Parameters
    ----------
    conditions : sequence of RigCondition
        The records.
    sim_dir : path
        The simulated records (``<name>_sim.npz``).

    Yields
    ------
    (int, int, RigCondition, str, str)
        Row (the condition's index), column (0 measured, 1 simulated), the condition, side
        (``"meas"`` | ``"sim"``) and the record's path.
    """
    for i, c in enumerate(conditions):
        for j, (side, path) in enumerate((("meas", c.path),
                                          ("sim", Path(sim_dir) / f"{c.name}_sim.npz"))):
            yield i, j, c, side, str(path)
