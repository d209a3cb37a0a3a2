"""The examples in the docstrings of the library's entry points run and print what they say."""
import doctest
import importlib

import pytest

#: (module, function) of every entry point that carries an example
ENTRY_POINTS = [
    ("bearing_envelope.contact.solver", "solve_contact"),
    ("bearing_envelope.physics.history", "simulate"),
    ("bearing_envelope.signal.envelope", "envelope_spectrum"),
    ("bearing_envelope.signal.kurtogram", "fast_kurtogram"),
    ("bearing_envelope.diagnosis.records", "analyze_record"),
]


@pytest.mark.parametrize("module, name", ENTRY_POINTS)
def test_example_runs(module, name):
    fn = getattr(importlib.import_module(module), name)
    tests = doctest.DocTestFinder(recurse=False).find(fn, name, globs={})
    examples = [ex for t in tests for ex in t.examples]
    assert examples, f"{module}.{name} has no example"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for t in tests:
        runner.run(t)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed"
