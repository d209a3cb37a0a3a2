"""Shared fixtures: one draft sweep per test session (tests/test_workflow.py, tests/test_report.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DRAFT = ROOT / "tests" / "data" / "config_draft.yaml"


@pytest.fixture(scope="session")
def draft_run(tmp_path_factory):
    """A workdir holding the full draft sweep (2 loads x 2 depths, 4 revolutions)."""
    sys.path.insert(0, str(Path(__file__).parent))
    from test_workflow import smk

    wd = tmp_path_factory.mktemp("sweep")
    smk(wd)
    return wd
