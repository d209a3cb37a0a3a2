"""Modules imported on first use (``bearing_envelope.lazy``) and what a ``simulate`` job imports."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

from bearing_envelope.lazy import LazyModule, lazy_module


def test_lazy_module_imports_on_first_attribute_and_reads_through():
    lazy = lazy_module("json")
    assert isinstance(lazy, LazyModule) and "not imported yet" in repr(lazy)
    assert lazy.dumps([1, 2]) == json.dumps([1, 2])          # the real module's function
    assert lazy.JSONDecodeError is json.JSONDecodeError and "imported" in repr(lazy)


def test_lazily_bound_scipy_signal_still_filters():
    """A function of the signal layer whose scipy.signal is bound lazily: a 50 Hz tone through
    a 40-60 Hz band-pass keeps its amplitude (the analytic answer), a 400 Hz one is removed."""
    from bearing_envelope.signal.envelope import bandpass

    fs = 2000.0
    t = np.arange(8000) / fs
    y = bandpass(np.sin(2 * np.pi * 50 * t) + np.sin(2 * np.pi * 400 * t), fs, (40.0, 60.0))
    mid = slice(2000, 6000)
    assert abs(np.abs(y[mid]).max() - 1.0) < 0.02
    assert np.abs(y[mid] - np.sin(2 * np.pi * 50 * t[mid])).max() < 0.02


def test_simulate_job_imports_neither_scipy_signal_nor_stats():
    """What ``bearing-envelope simulate`` imports before it solves (commands/simulate.py's
    ``run``) leaves scipy.signal, scipy.stats and pandas out: 0.8 CPU s of a ball case's job."""
    code = ("import sys\n"
            "from bearing_envelope.physics.fidelity import fidelity_from\n"
            "from bearing_envelope.physics.history import simulate\n"
            "from bearing_envelope.io import write_case\n"
            "from bearing_envelope.study.accuracy import case_error_model\n"
            "from bearing_envelope.study.limits import check_case\n"
            "from bearing_envelope.study.case_id import CaseId\n"
            "from bearing_envelope.study.settings import load_settings\n"
            "print(sorted(m for m in ('scipy.signal', 'scipy.stats', 'pandas') if m in sys.modules))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
