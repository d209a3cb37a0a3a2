"""A second look where the envelope is silent: the benchmark's own methods as routes of the
verdict, and one verdict from several routes.

**Routes.** Each route turns the record into one spectrum of the repetition of its impulses and
searches every fault family in it with the line search and the detection of
:mod:`~bearing_envelope.diagnosis.faults` (one "band" per route, each line tested at
``pfa / F`` for F families):

- ``envelope``: today's chain, the envelope spectra of the demodulation bands of
  :func:`~bearing_envelope.diagnosis.analysis.analyze_signal` (its verdict, unchanged);
- ``cpw`` (Smith & Randall 2015, method 2): cepstrum pre-whitening, squared envelope spectrum
  of the full band (:func:`~bearing_envelope.signal.separation.prewhitened_ses`);
- ``drs_sk`` (method 3): discrete/random separation (Antoni & Randall 2004, frequency-domain
  DRS, :func:`~bearing_envelope.signal.separation.discrete_random_separation`), the fast
  kurtogram's band of the random part (the cells limited as in ``analyze_signal``), squared
  envelope spectrum there;
- ``ees``: the enhanced envelope spectrum (the spectral coherence of the cyclic modulation
  spectrum averaged over the full band,
  :func:`~bearing_envelope.signal.cyclostationary.enhanced_envelope_spectrum`) of the
  record's random part (:func:`random_part`, computed once for it and the DRS routes): a
  periodic component whose power repeats, such as a pulsed carrier, is coherent at its rate
  and leaves with the discrete part.

Two more routes are measured but not run by default (:data:`DEFAULT_ROUTES`; the figures in
``docs/diagnosis_routes.md``, "Tried and not kept"):

- ``drs_info``: ``drs_sk`` with the band of the spectral infogram (Antoni 2016,
  :func:`~bearing_envelope.signal.infogram.infogram`: the cell whose squared envelope
  repeats most) of the random part instead of the kurtogram's, the same cells allowed;
- ``info``: the squared envelope spectrum of the record in its spectral-infogram band.

In each route the family verdict of :func:`~bearing_envelope.diagnosis.faults.fault_verdict`
decides which families the route **names** (its diagnosis, or its candidates when it cannot
tell) and which it **finds** (every detected family that no stronger one explains, weak ones
included). A rolling element is named by ``2xBSF`` or by ``BSF`` with its FTF sidebands, and
searched within :data:`BALL_SEARCH_PERCENT` of its kinematic value (a ball slips); the
envelope route also looks for it so in its own bands' spectra. The cage rate (FTF) is
supporting evidence only: reported, never a name.

**One verdict** (:func:`combine_routes`): the envelope route's verdict stands when it names a
family at ``medium`` or ``high``; its ``high`` needs a second route finding the same fault (one
route alone never makes ``high``: else ``medium``). Where the envelope route names nothing at
``medium`` or better (``low``, ``cannot tell``, nothing), a fault of :data:`RAISES` found by at
least :data:`MEDIUM_MIN_ROUTES` routes, named by one of them other than the envelope route,
and found by more routes than any other fault, is the diagnosis at ``medium``; otherwise the
envelope route's verdict stands. Only the rolling element may be raised so: on the 32 CWRU
development records, raising the races as well gives 4 (three routes needed) or 5 (two) wrong
verdicts at ``medium``, ball records whose race lines every route sees among them
(``python -m benchmarks routes``, ``docs/diagnosis_routes.md``). The evidence says which route
found what.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace


from ..signal.bands import band_from_kurtogram, clamp_band
from ..signal.cyclostationary import enhanced_envelope_spectrum
from ..signal.envelope import envelope_spectrum
from ..signal.kurtogram import DEFAULT_NLEVEL, fast_kurtogram, max_kurtogram_level
from ..signal.spectrum import DEFAULT_WINDOW
from ..signal.infogram import infogram, infogram_depth
from ..signal.separation import (DRS_NPERSEG, discrete_random_separation,
                                 prewhitened_ses)
from .detection import BACKGROUND_BAND
from .faults import CANNOT_TELL, Verdict, display_name, fault_verdict, search_lines
from ..lazy import lazy_module

pd = lazy_module("pandas")  # imported on first use (docs/architecture.md, lazy.py)

__all__ = ["BALL_SEARCH_PERCENT", "DEFAULT_ROUTES", "MEDIUM_MIN_ROUTES", "RAISES", "ROUTES",
           "RouteResult", "RoutedVerdict", "apply_routes", "combine_routes", "random_part",
           "route_found", "route_name", "route_spectrum", "route_verdict", "run_routes",
           "spectra_verdict"]

#: Every route (the envelope route is the verdict of ``analyze_signal``).
ROUTES = ("envelope", "cpw", "drs_sk", "ees", "drs_info", "info")
#: The routes run by default (the infogram's routes add no right verdict on the development
#: records: ``docs/diagnosis_routes.md``).
DEFAULT_ROUTES = ("envelope", "cpw", "drs_sk", "ees")
#: Routes naming one family that make it the diagnosis at ``medium`` where the envelope route
#: names nothing at ``medium`` or better.
MEDIUM_MIN_ROUTES = 2
#: Half-width (percent of the nominal frequency) of the search for a rolling element's
#: fundamental (BSF, 2 x BSF) in the routes other than ``envelope``: a ball rolls with slip and
#: its spin rate depends on its contact angle, so its lines sit further from the kinematic
#: value than the races' (CWRU 222 and 223: 2 x BSF 0.9 and 1.3 % below it at the measured
#: speed, where the races' lines are within 0.5 %).
BALL_SEARCH_PERCENT = 1.5
#: The faults the routes may raise to a diagnosis where the envelope route names nothing at
#: ``medium`` or better (see :func:`combine_routes`).
RAISES = ("ball",)
#: Records shorter than this (samples) get the envelope route only (the DRS needs Welch
#: segments of at least 16 samples three times over, the EES frames of 32).
MIN_ROUTE_SAMPLES = 1024
#: What each route is, for the evidence text.
ROUTE_LABELS = {
    "envelope": "envelope bands",
    "cpw": "pre-whitened SES (method 2)",
    "drs_sk": "DRS + SK band SES (method 3)",
    "ees": "enhanced envelope spectrum",
    "drs_info": "DRS + spectral-infogram band SES",
    "info": "spectral-infogram band SES",
}
#: The routes that read the record's random part (:func:`random_part`).
_READ_RANDOM = ("drs_sk", "drs_info", "ees")
#: The fault each family name stands for in a route's vote (2 x BSF and BSF: a rolling element).
_FAULT = {"bsf": "ball", "bsf2": "ball"}


@dataclass(frozen=True)
class RouteResult:
    """One route on one record.

    Attributes
    ----------
    route : str
        Its name (:data:`ROUTES`).
    verdict : Verdict
        The family verdict over the route's spectrum (one band).
    named : tuple of str
        Families the route names (:func:`route_name`).
    band : tuple of float
        The spectral band the route demodulated (Hz).
    found : tuple of str or None
        Families the route finds (:func:`route_found`); None: those of :attr:`verdict`. The
        envelope route adds the rolling element searched in its bands within
        :data:`BALL_SEARCH_PERCENT` (:func:`run_routes`).
    found_margins : tuple of (str, float)
        The margins (dB) of the families added to :attr:`found` that way.
    """

    route: str
    verdict: Verdict
    named: tuple[str, ...]
    band: tuple[float, float]
    found: tuple[str, ...] | None = None
    found_margins: tuple[tuple[str, float], ...] = ()

    @property
    def finds(self) -> tuple[str, ...]:
        """:attr:`found`, or the families :func:`route_found` reads in :attr:`verdict`."""
        return route_found(self.verdict) if self.found is None else self.found

    def margin(self, family: str) -> float:
        """The fundamental's margin over its threshold of one family in this route.

        Parameters
        ----------
        family : str
            Family name (``bpfo``, ``bsf2``, ...).

        Returns
        -------
        float
            ``floor_ratio_db - threshold_db`` (dB) in the route's best band; NaN when the
            family is not searched.
        """
        extra = dict(self.found_margins)
        if family in extra:
            return extra[family]
        for v in self.verdict.families:
            if v.family == family:
                return v.margin_db
        return math.nan


def route_name(verdict: Verdict) -> tuple[str, ...]:
    """The families a route's verdict names.

    Parameters
    ----------
    verdict : Verdict
        The route's family verdict.

    Returns
    -------
    tuple of str
        Its diagnosis, or its candidates when it cannot tell; ``bsf`` only with its FTF
        sidebands; never ``ftf`` (the cage rate supports, it does not name).
    """
    by = {v.family: v for v in verdict.families}
    fams = (verdict.diagnosis.family,) if verdict.diagnosis is not None else verdict.candidates
    out = []
    for f in fams:
        if f == "ftf" or (f == "bsf" and not by[f].modulation_ok):
            continue
        out.append(f)
    return tuple(out)


def random_part(x, fs: float):
    """The random part of a record (discrete/random separation), as the routes read it.

    Parameters
    ----------
    x : array_like, 1-D
        The record (at least 64 samples).
    fs : float
        Sampling frequency (Hz).

    Returns
    -------
    ndarray
        ``x`` less its discrete part
        (:func:`~bearing_envelope.signal.separation.discrete_random_separation`), the Welch
        segment :data:`~bearing_envelope.signal.separation.DRS_NPERSEG` or, on a shorter
        record, the largest power of two within a quarter of it (a coarser separation).
    """
    nper = min(DRS_NPERSEG, 2 ** int(math.log2(max(len(x) // 4, 1))))
    return discrete_random_separation(x, fs, nperseg=nper)[1]


def route_spectrum(route: str, x, fs: float, *, alpha_max_hz: float, min_bandwidth: float,
                   nlevel: int = DEFAULT_NLEVEL, window=DEFAULT_WINDOW, random=None):
    """The spectrum of one route other than ``envelope``.

    Parameters
    ----------
    route : {"cpw", "drs_sk", "ees", "drs_info", "info"}
    x : array_like, 1-D
        The record.
    fs : float
        Sampling frequency (Hz).
    alpha_max_hz : float
        Highest frequency the line search reads (Hz), for the EES's cyclic frequencies and
        the infogram's SES.
    min_bandwidth : float
        Narrowest kurtogram (infogram) cell the DRS (infogram) routes may demodulate (Hz).
    nlevel : int, default 8
        Kurtogram depth (reduced for short records).
    window : str or tuple, default "hann"
    random : ndarray, optional
        :func:`random_part` of ``x``, when already computed (the DRS routes and the EES read
        it); computed here otherwise.

    Returns
    -------
    f, amplitude : ndarray
        The spectrum (Hz, its own unit).
    band : tuple of float
        The spectral band used (Hz).
    """
    if route == "cpw":
        f, a = prewhitened_ses(x, fs, window=window)
        return f, a, (0.0, fs / 2.0)
    if route in _READ_RANDOM:
        rnd = random_part(x, fs) if random is None else random
    if route == "ees":
        f, a = enhanced_envelope_spectrum(rnd, fs, alpha_max_hz=alpha_max_hz)
        return f, a, (0.0, fs / 2.0)
    if route in ("drs_sk", "drs_info"):
        if route == "drs_info":
            band = _infogram_band(rnd, fs, alpha_max_hz, min_bandwidth, nlevel)
        else:
            nl = max(1, min(int(nlevel), max_kurtogram_level(rnd.size)))
            kg = fast_kurtogram(rnd, fs, nl, min_bandwidth=min(min_bandwidth, fs / 2.0))
            band, _ = band_from_kurtogram(kg)
        f, a = envelope_spectrum(rnd, fs, band, squared=True, window=window)
        return f, a, (float(band[0]), float(band[1]))
    if route == "info":
        band = _infogram_band(x, fs, alpha_max_hz, min_bandwidth, nlevel)
        f, a = envelope_spectrum(x, fs, band, squared=True, window=window)
        return f, a, band
    raise ValueError(f"route = {route!r}: allowed {ROUTES[1:]}")


def _infogram_band(x, fs: float, alpha_max_hz: float, min_bandwidth: float, nlevel: int):
    """The band (Hz, upper edge clamped below Nyquist) of the spectral infogram's best cell at
    least ``min_bandwidth`` wide and not starting at 0 Hz (where the shaft's tones beat with
    their mirror images), its SES read to ``alpha_max_hz`` (the lines searched)."""
    bw = min(min_bandwidth, fs / 4.0)
    nl = max(1, min(int(nlevel), infogram_depth(fs, bw, len(x))))
    ig = infogram(x, fs, nl, alpha_max_hz=min(alpha_max_hz, fs / 2.0))
    cell = ig.best("spectral", min_bandwidth=bw, above_dc=True)
    low, high, _ = clamp_band(*cell.band, fs)
    return float(low), float(high)


def route_verdict(route: str, f, amplitude, band, families, *, fr: float, search: Mapping,
                  n_harmonics: int, n_sidebands: int, pfa: float) -> Verdict:
    """The family verdict of :func:`~bearing_envelope.diagnosis.faults.fault_verdict` over one
    route's spectrum, each line tested at ``pfa / len(families)``.

    Parameters
    ----------
    route : str
    f, amplitude : ndarray
        The route's spectrum.
    band : (float, float)
        Its spectral band (Hz).
    families : sequence of FaultFamily
    fr : float
        Shaft rate (Hz).
    search : mapping
        ``search_percent``, ``min_search_bins`` (and optionally ``tolerance_hz``) of the
        envelope route's line search; a rolling element's fundamental is searched within at
        least :data:`BALL_SEARCH_PERCENT`.
    n_harmonics, n_sidebands : int
    pfa : float
        Record-wise false-alarm probability of the route.

    Returns
    -------
    Verdict
        The verdict over the route's one band (named after the route).
    """
    return spectra_verdict({route: (band, f, amplitude)}, families, fr=fr, search=search,
                           n_harmonics=n_harmonics, n_sidebands=n_sidebands, pfa=pfa)


def spectra_verdict(spectra: Mapping, families, *, fr, search, n_harmonics, n_sidebands,
                    pfa, known: Mapping | None = None) -> Verdict:
    """:func:`~bearing_envelope.diagnosis.faults.fault_verdict` over several spectra.

    Parameters
    ----------
    spectra : mapping
        ``{band name: ((low_hz, high_hz), f, amplitude)}``.
    families : sequence of FaultFamily
    fr : float
        Shaft rate (Hz).
    search : mapping
        ``search_percent``, ``tolerance_hz``, ``min_search_bins`` of the line search; a
        rolling element's fundamental is searched within at least :data:`BALL_SEARCH_PERCENT`.
    n_harmonics, n_sidebands : int
    pfa : float
        Record-wise false-alarm probability: each line is tested at ``pfa / (families x
        bands)``.
    known : mapping, optional
        ``{band name: {family: rows of search_lines}}`` already searched so (not searched
        again).

    Returns
    -------
    Verdict
    """
    n_tests = max(1, len(families) * len(spectra))
    rows = []
    for name, (band, f, amplitude) in spectra.items():
        for fam in families:
            done = (known or {}).get(name, {}).get(fam.name)
            if done is not None:
                rows.extend({"band": name, "band_low_hz": band[0], "band_high_hz": band[1],
                             "quantity": "envelope_spectrum", "base": fam.name, **r}
                            for r in done)
                continue
            kw = dict(search)
            if fam.name in _FAULT and kw.get("tolerance_hz") is None:
                kw["search_percent"] = max(kw["search_percent"], BALL_SEARCH_PERCENT)
            for r in search_lines(f, amplitude, fam, fr=fr, n_harmonics=n_harmonics,
                                  n_sidebands=n_sidebands, pfa=pfa / n_tests, **kw):
                rows.append({"band": name, "band_low_hz": band[0], "band_high_hz": band[1],
                             "quantity": "envelope_spectrum", "base": fam.name, **r})
    table = pd.DataFrame(rows)
    table["detected"] = table["detected"].astype("boolean")
    f0 = next(iter(spectra.values()))[1]
    return fault_verdict(table, families, pfa=pfa, n_tests=n_tests, fr=fr,
                         df_hz=float(f0[1] - f0[0]))


def _envelope_result(details: Mapping, search: Mapping) -> RouteResult:
    """The envelope route: ``analyze_signal``'s verdict names; it finds what that verdict
    finds plus a rolling element searched in the same bands' spectra within
    :data:`BALL_SEARCH_PERCENT` (the ball's slip), at the same per-test false-alarm rate."""
    v = details["verdict"]
    opt = details["options"]
    spectra = {name: (b["band"], b["f"], b["amplitude"]) for name, b in details["bands"].items()}
    # the other families' lines as analyze_signal found them (same search, same pfa per test)
    known = {name: {k: rows for k, rows in b["lines"].items() if k not in _FAULT}
             for name, b in details["bands"].items()}
    ball = spectra_verdict(spectra, details["families"], fr=details["fr"], search=search,
                           n_harmonics=opt.n_harmonics, n_sidebands=opt.n_sidebands,
                           pfa=opt.pfa, known=known)
    own = route_found(v)
    extra = tuple(f for f in route_found(ball) if f in _FAULT and f not in own)
    margins = tuple((w.family, w.margin_db) for w in ball.families if w.family in extra)
    return RouteResult("envelope", v, route_name(v), (0.0, details["fs"] / 2.0),
                       own + extra, margins)


def run_routes(x, fs: float, details: Mapping, routes: Sequence[str] = DEFAULT_ROUTES
               ) -> dict[str, RouteResult]:
    """Every route of ``routes`` on one record, after ``analyze_signal``.

    Parameters
    ----------
    x : array_like, 1-D
        The record given to ``analyze_signal``.
    fs : float
        Sampling frequency (Hz).
    details : mapping
        ``analyze_signal(..., full_output=True)[1]``: its verdict is the envelope route; its
        families, shaft rate (measured when asked) and options set the other routes' search.
    routes : sequence of str, default :data:`DEFAULT_ROUTES`

    Returns
    -------
    dict
        ``route -> RouteResult``; a record shorter than :data:`MIN_ROUTE_SAMPLES` gets the
        envelope route only.
    """
    bad = [r for r in routes if r not in ROUTES]
    if bad:
        raise ValueError(f"routes = {list(routes)!r}: allowed any of {ROUTES}")
    opt, fams, fr = details["options"], details["families"], details["fr"]
    speed = details.get("speed")
    measured = speed is not None and speed.measured
    search = {"search_percent": (opt.measured_speed_search_percent if measured
                                 else opt.search_percent),
              "tolerance_hz": opt.tolerance_hz,
              "min_search_bins": 2.0 if measured else 0.0}
    top = max(fam.frequency_hz for fam in fams)
    # the highest frequency the line search reads: the background band of the top harmonic
    span = BACKGROUND_BAND[1] * (top * opt.n_harmonics + 2.0 * fr)
    out = {}
    rnd = None  # the random part, computed once for the routes that read it
    for r in routes:
        if r != "envelope" and len(x) < MIN_ROUTE_SAMPLES:
            continue  # too short for the DRS's segments and the EES's frames: left out
        if r == "envelope":
            out[r] = _envelope_result(details, search)
            continue
        if r in _READ_RANDOM and rnd is None:
            rnd = random_part(x, fs)
        f, a, band = route_spectrum(r, x, fs, alpha_max_hz=span,
                                    min_bandwidth=2.0 * opt.n_harmonics * top,
                                    nlevel=opt.nlevel or DEFAULT_NLEVEL, window=opt.window,
                                    random=rnd)
        v = route_verdict(r, f, a, band, fams, fr=fr, search=search,
                          n_harmonics=opt.n_harmonics, n_sidebands=opt.n_sidebands,
                          pfa=opt.pfa)
        out[r] = RouteResult(r, v, route_name(v), band)
    return out


def _fault(family: str) -> str:
    """The fault a family stands for in the vote (``bsf``, ``bsf2`` -> ``ball``)."""
    return _FAULT.get(family, family)


def route_found(verdict: Verdict) -> tuple[str, ...]:
    """Families a route finds.

    Parameters
    ----------
    verdict : Verdict
        The route's family verdict.

    Returns
    -------
    tuple of str
        Every detected family that no stronger one explains (named, second findings and weak
        ones alike), without the cage rate (supporting evidence only).
    """
    return tuple(v.family for v in verdict.families
                 if v.detected and v.role not in (None, "explained") and v.family != "ftf")


@dataclass(frozen=True)
class RoutedVerdict:
    """One verdict from several routes (:func:`combine_routes`).

    Attributes
    ----------
    diagnosis : str or None
        The family diagnosed (``bpfo``, ``bpfi``, ``bsf``, ``bsf2``, ...), None when none.
    confidence : str or None
        ``high``, ``medium``, ``low``, ``cannot tell`` or None (nothing detected).
    candidates : tuple of str
        The envelope route's candidates when the verdict cannot tell.
    support : dict
        ``fault -> routes`` that find it (``ball`` for BSF and 2 x BSF).
    named : dict
        ``route -> families`` it names.
    decided_by : str
        ``"envelope"`` (its verdict stands), ``"envelope, high needs a second route"``
        (lowered to medium) or ``"routes"`` (raised by the routes).
    evidence : tuple of str
        Which route found what, one phrase per route.
    envelope : Verdict
        The envelope route's verdict.
    """

    diagnosis: str | None
    confidence: str | None
    candidates: tuple[str, ...]
    support: dict
    named: dict
    decided_by: str
    evidence: tuple[str, ...]
    envelope: Verdict

    def summary(self) -> str:
        """One line of the combined verdict.

        Returns
        -------
        str
            The diagnosis, its confidence, how it was decided and what each route found.
        """
        head = ("no fault" if self.confidence is None else
                f"{CANNOT_TELL}: {' or '.join(display_name(c) for c in self.candidates)}"
                if self.diagnosis is None else f"{display_name(self.diagnosis)}")
        return (f"{head} [{self.confidence or 'none'}; {self.decided_by}] routes: "
                + "; ".join(self.evidence))


def _evidence(results: Mapping[str, RouteResult]) -> tuple[str, ...]:
    out = []
    for r, res in results.items():
        found = res.finds
        named = ", ".join(f"{display_name(f)} {res.margin(f):+.1f} dB" for f in res.named)
        extra = [f for f in found if f not in res.named]
        txt = f"{ROUTE_LABELS[r]}: " + (f"names {named}" if named else "names nothing")
        if extra:
            txt += " (also " + ", ".join(f"{display_name(f)} {res.margin(f):+.1f} dB"
                                         for f in extra) + ")"
        cage = [v for v in res.verdict.families if v.family == "ftf" and v.detected]
        if cage:
            txt += f", cage rate {cage[0].margin_db:+.1f} dB (supporting only)"
        out.append(txt)
    return tuple(out)


def combine_routes(results: Mapping[str, RouteResult], *,
                   raises: Sequence[str] = RAISES,
                   min_routes: int = MEDIUM_MIN_ROUTES) -> RoutedVerdict:
    """One verdict from the routes' results (rule in the module's docstring).

    Parameters
    ----------
    results : mapping
        ``route -> RouteResult`` of :func:`run_routes`; must hold ``envelope``.
    raises : sequence of str, default :data:`RAISES`
        Faults (``ball``, ``bpfo``, ``bpfi``) the routes may raise where the envelope route
        names nothing at ``medium`` or better.
    min_routes : int, default :data:`MEDIUM_MIN_ROUTES`
        Routes finding a fault (at least one of them naming it) that raise it to ``medium``.

    Returns
    -------
    RoutedVerdict
    """
    if "envelope" not in results:
        raise ValueError(f"results hold {sorted(results)}: the envelope route is needed")
    env = results["envelope"].verdict
    support: dict[str, list[str]] = {}
    naming: dict[str, list[str]] = {}
    for r, res in results.items():
        for fam in res.finds:
            support.setdefault(_fault(fam), []).append(r)
        for fam in res.named:
            naming.setdefault(_fault(fam), []).append(r)
    support = {k: tuple(dict.fromkeys(v)) for k, v in support.items()}
    named = {r: res.named for r, res in results.items()}
    common = dict(support=support, named=named, evidence=_evidence(results), envelope=env)
    d = env.diagnosis
    if d is not None and env.confidence in ("high", "medium"):
        others = [r for r in support.get(_fault(d.family), ()) if r != "envelope"]
        if env.confidence == "high" and not others:
            return RoutedVerdict(d.family, "medium", (), decided_by="envelope, high needs a "
                                 "second route", **common)
        return RoutedVerdict(d.family, env.confidence, (), decided_by="envelope", **common)
    best = sorted(support.items(), key=lambda kv: len(kv[1]), reverse=True)
    if best:
        fault, routes = best[0]
        unique = len(best) == 1 or len(best[1][1]) < len(routes)
        outside = [r for r in naming.get(fault, ()) if r != "envelope"]
        if fault in raises and unique and len(routes) >= min_routes and outside:
            fam = _named_family(results, fault, outside)
            return RoutedVerdict(fam, "medium", (), decided_by="routes", **common)
    return RoutedVerdict(None if d is None else d.family, env.confidence, env.candidates,
                         decided_by="envelope", **common)


def _named_family(results, fault: str, routes: Sequence[str]) -> str:
    """The family name (``bsf2`` before ``bsf``) under which the routes name ``fault``."""
    names = [f for r in routes for f in results[r].named if _fault(f) == fault]
    return "bsf2" if "bsf2" in names else names[0]


def apply_routes(verdict: Verdict, routed: RoutedVerdict,
                 results: Mapping[str, RouteResult]) -> Verdict:
    """The envelope route's verdict carrying the combined decision.

    Where the routes raise a family, its family verdict is the naming route's (band = the
    route's name) with role ``diagnosis`` and level ``medium``, and the envelope's former
    diagnosis or candidates become ``weak``; where ``high`` is lowered, the confidence says
    ``medium``. The evidence of every route goes to ``Verdict.routes``.

    Parameters
    ----------
    verdict : Verdict
        The envelope route's verdict.
    routed : RoutedVerdict
        :func:`combine_routes` of ``results``.
    results : mapping
        ``route -> RouteResult``.

    Returns
    -------
    Verdict
    """
    fams = list(verdict.families)
    candidates = routed.candidates
    if routed.decided_by == "routes":
        src = next(r for r in results if r != "envelope" and routed.diagnosis in results[r].named)
        new = next(v for v in results[src].verdict.families if v.family == routed.diagnosis)
        new = replace(new, role="diagnosis", level="medium")
        fams = [new if v.family == routed.diagnosis else
                replace(v, role="weak") if v.role in ("diagnosis", "candidate") else v
                for v in fams]
        candidates = ()
    return replace(verdict, families=tuple(fams), confidence=routed.confidence,
                   candidates=candidates, routes=routed.evidence,
                   decided_by=routed.decided_by)
