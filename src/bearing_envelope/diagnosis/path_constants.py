"""The constants of the transfer path's identification (:mod:`.transfer_path`, :mod:`.path_background`):
thresholds, tolerances, segment lengths, each defined once here and read by both."""

from __future__ import annotations

__all__ = ['UNIT_IMPULSE_AREA', 'MIN_EVENTS', 'DEFAULT_PFA', 'EVENT_PFA', 'MAX_LEVEL', 'MIN_BAND_ORDER', 'F_MAX', 'MIN_DECAY_BAND', 'ZETA_MIN', 'ZETA_MAX', 'FILTER_ORDER', 'WELCH_SEGMENT', 'MIN_GAP', 'DECAY_FLOOR', 'DECAY_FROM', 'RISE_MARGIN', 'ONSETS', 'MODE_PFA', 'MODE_FLOOR', 'MAX_MODES', 'TRACK_SNR_DB', 'TRACK_PERIODS', 'SUBSETS', 'IDENT_TOL', 'MODE_SPAN', 'MIN_BACKGROUND', 'MAX_MODELLED', 'PRE_MARGIN', 'MIN_PRE']

#: Area of the excitation impulse a mode's gain refers to when none is given: a unit impulse.
UNIT_IMPULSE_AREA = 1.0

#: Fewest periods of the slowest event rate a record must hold (refused before any work).
MIN_EVENTS = 20
#: False-alarm probability of the event-rate line over all candidate rates.
DEFAULT_PFA = 0.001
#: False-alarm probability of one period's envelope maximum being called an event.
EVENT_PFA = 0.01
#: Deepest kurtogram level the band may come from: fs/16 wide at least (fs/2^(level+1)).
MAX_LEVEL = 3.0
#: The resonance band's lower edge is at least this many times the highest event rate (the
#: band must hold the ringing, not the event rate's own low harmonics).
MIN_BAND_ORDER = 5
#: f_n is searched below this fraction of fs (above it: the recorder's anti-alias filter).
F_MAX = 0.45
#: The decay is read in a band centred on f_n, the kurtogram's band's width or this
#: fraction of fs, whichever is wider.
MIN_DECAY_BAND = 1.0 / 12.0
#: Bounds of the damping fit.
ZETA_MIN, ZETA_MAX = 5e-4, 0.3
#: Butterworth order of the band-pass (applied forward and backward).
FILTER_ORDER = 4
#: Samples per Welch segment of the background spectrum (its transform length).
WELCH_SEGMENT = 1024
#: Shortest stretch between events the background spectrum is read from (samples).
MIN_GAP = 64
#: A further mode must add at least DECAY_FLOOR squared of the first's power (the decay fit's
#: floor when it was read from the peak down to this fraction of the peak's amplitude).
DECAY_FLOOR = 0.1
#: zeta is fitted on the decay from this many samples after the averaged events' peak (the
#: peak itself is rounded off by the events' timing scatter).
DECAY_FROM = 2
#: Samples before an event's modelled rise its energy is summed from (:func:`_rise`): the
#: events' timing scatter spreads it that far.
RISE_MARGIN = 2
#: Onsets per sample the events' modelled decay is averaged over (:func:`_model_power`): a
#: record's events start anywhere between two samples.
ONSETS = 16
#: False-alarm probability of a further mode: over the resolution cells searched (Bonferroni),
#: a peak of the power the events add whose prominence over its standard error (across the
#: events) exceeds the normal quantile is a mode, not the spread of noise.
MODE_PFA = 0.001
#: A further mode must add at least this fraction of the strongest mode's power (-20 dB: the
#: decay fit's own floor, ``DECAY_FLOOR`` squared); weaker ones change no feature read.
MODE_FLOOR = DECAY_FLOOR ** 2
#: Most modes identified from one record (the strongest first).
MAX_MODES = 4
#: The event track (:func:`_event_track`) averages the envelope's line at the event rate over
#: enough periods for the line to stand this far over its floor (dB, power) ...
TRACK_SNR_DB = 20.0
#: ... and over at least this many periods.
TRACK_PERIODS = 16
#: Interleaved subsets of the events whose fits give the standard errors of zeta and gain.
SUBSETS = 4
#: A quantity is identified when twice its standard error is within this (relative); else it
#: is flagged and listed in ``not_identified``.
IDENT_TOL = 0.10
#: Where the events dominate within this many half bandwidths (zeta f_n) of a mode, plus one
#: event rate, the background is interpolated across; a real ringing's far tails are no
#: damped cosine's (its force has a finite rise time): where the events' modelled spectrum
#: makes most of the record's farther off, half the record's power is the background (flagged).
MODE_SPAN = 5.0
#: Fewest samples between the events the background is read from (4 Welch segments); fewer,
#: and the background is the record's spectrum less the events' modelled one, and where the
#: events make most of that, the quiet end of every period's (flagged where neither holds).
MIN_BACKGROUND = 4 * WELCH_SEGMENT
#: The most of a spectrum the events' modelled part may make for the spectrum less it to be
#: read as the background (the model's power rests on the gain, identified within 10 %, so
#: on 20 %: at half the spectrum, that is 20 % of the background).
MAX_MODELLED = 0.5
#: Samples before the next event's modelled onset the quiet stretch before it ends: the
#: events' timing scatter around their track.
PRE_MARGIN = 4
#: Shortest quiet stretch before each event its spectrum is read from (samples; its
#: resolution fs / 16, 750 Hz at 12 kHz).
MIN_PRE = 16
