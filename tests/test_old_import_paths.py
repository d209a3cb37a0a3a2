"""Modules that moved into the layers keep their old import paths (``MOVED_MODULES``)."""
import importlib
import subprocess
import sys

import pytest

import bearing_envelope
from bearing_envelope import MOVED_MODULES


@pytest.mark.parametrize("old, new", sorted(MOVED_MODULES.items()))
def test_old_path_is_the_module_at_its_new_home(old, new):
    moved = importlib.import_module(f"bearing_envelope.{old}")
    home = importlib.import_module(f"bearing_envelope.{new}")
    assert moved is home
    assert home.__spec__.name == f"bearing_envelope.{new}"  # the alias leaves the spec alone


def test_the_forms_code_written_before_the_layers_used():
    from bearing_envelope import kinematics
    from bearing_envelope.history import simulate
    from bearing_envelope.signal import analysis
    from bearing_envelope.physics.history import simulate as simulate_today
    import bearing_envelope.scene as scene

    assert kinematics.__name__ == "bearing_envelope.physics.kinematics"
    assert simulate is simulate_today
    assert analysis.__name__ == "bearing_envelope.diagnosis.analysis"
    assert scene is bearing_envelope.physics.scene
    assert bearing_envelope.tables.__name__ == "bearing_envelope.study.tables"


def test_an_unknown_name_still_fails():
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("bearing_envelope.no_such_module")
    with pytest.raises(AttributeError, match="no_such_name"):
        bearing_envelope.no_such_name


def test_importing_the_root_imports_no_layer():
    code = ("import sys, bearing_envelope; "
            "print(sorted(m for m in sys.modules if m.startswith('bearing_envelope')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "['bearing_envelope']"
