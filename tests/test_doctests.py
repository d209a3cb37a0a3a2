"""The examples in the library's docstrings run and print what they say.

Every module of ``src/bearing_envelope`` whose docstrings carry a ``>>>`` example is run (so an
example cannot rot unseen), and the functions a user calls first in each subpackage must carry
one (:data:`ENTRY_POINTS`, issue 44 part 7).
"""
import doctest
import importlib
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "bearing_envelope"

#: (module, qualified name) of the functions a user calls first, per subpackage: each carries
#: an example
ENTRY_POINTS = [
    # contact
    ("bearing_envelope.contact.solver", "solve_contact"),
    ("bearing_envelope.contact.hertz", "sphere"),
    ("bearing_envelope.contact.hertz", "elliptical"),
    # physics
    ("bearing_envelope.physics.scene", "Scene.from_mapping"),
    ("bearing_envelope.physics.history", "simulate"),
    ("bearing_envelope.physics.loads", "solve_row"),
    ("bearing_envelope.physics.kinematics", "fault_frequencies"),
    ("bearing_envelope.physics.kinematics", "bearing_rates"),
    ("bearing_envelope.physics.catalogue", "resolve_designation"),
    # signal
    ("bearing_envelope.signal.envelope", "envelope_spectrum"),
    ("bearing_envelope.signal.kurtogram", "fast_kurtogram"),
    ("bearing_envelope.signal.envelope", "envelope"),
    ("bearing_envelope.signal.sk", "spectral_kurtosis"),
    # diagnosis
    ("bearing_envelope.diagnosis.analysis", "analyze_signal"),
    ("bearing_envelope.diagnosis.faults", "fault_verdict"),
    ("bearing_envelope.diagnosis.speed", "estimate_shaft_rate"),
    ("bearing_envelope.diagnosis.records", "analyze_record"),
    # io
    ("bearing_envelope.io.case", "read_case"),
    ("bearing_envelope.io.analysis", "analyze_file"),
    # study
    ("bearing_envelope.study.settings", "load_settings"),
    ("bearing_envelope.study.pipeline", "case_summary"),
]


def _modules():
    """Importable names of the library's modules that contain a ``>>>`` line."""
    out = []
    for path in sorted(SRC.rglob("*.py")):
        if ">>>" not in path.read_text(encoding="utf-8"):
            continue
        parts = path.relative_to(SRC.parent).with_suffix("").parts
        out.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return out


def _run(tests) -> doctest.TestResults:
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for t in tests:
        runner.run(t)
    return runner.summarize(verbose=False)


def _lookup(module: str, qualname: str):
    obj = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    return obj


@pytest.mark.parametrize("module, name", ENTRY_POINTS)
def test_entry_point_has_an_example(module, name):
    fn = _lookup(module, name)
    tests = doctest.DocTestFinder(recurse=False).find(fn, name, globs={})
    assert any(t.examples for t in tests), f"{module}.{name} has no example"


@pytest.mark.parametrize("module", _modules())
def test_module_examples_run(module):
    mod = importlib.import_module(module)
    tests = [t for t in doctest.DocTestFinder().find(mod, module) if t.examples]
    assert tests, f"{module} has a '>>>' line but doctest finds no example"
    result = _run(tests)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {module} failed"
