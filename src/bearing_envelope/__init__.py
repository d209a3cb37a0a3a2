"""bearing_envelope: non-Hertzian contact of a damaged roller bearing and envelope analysis.

Layers, bottom up (each importable alone): :mod:`.contact`, :mod:`.physics`, :mod:`.signal`,
:mod:`.diagnosis`, :mod:`.io`, :mod:`.study`, :mod:`.cli` (``docs/architecture.md``).
SI units inside the library; names carry units only at the edges (``depth_um``, ``load_kN``).

Modules that moved into the layers keep their old import path (:data:`MOVED_MODULES`):
``from bearing_envelope import kinematics`` and ``import bearing_envelope.history`` give the
module at its new home. The alias is resolved on first use (PEP 562 ``__getattr__`` and an
import finder), so importing the package root imports nothing of the package.
"""

import importlib
import importlib.abc
import importlib.machinery
import sys

__version__ = "0.1.0"

#: Old module path (relative to the package) -> the module's home today.
MOVED_MODULES = {
    "accuracy": "study.accuracy",
    "catalogue": "physics.catalogue",
    "config": "study.schema",
    "fidelity": "physics.fidelity",
    "figures": "study.figures",
    "geometry": "physics.geometry",
    "history": "physics.history",
    "kinematics": "physics.kinematics",
    "loads": "physics.loads",
    "paper": "study.paper",
    "pipeline": "study.pipeline",
    "pit": "physics.pit",
    "provenance": "study.provenance",
    "records": "io.records",
    "scene": "physics.scene",
    "settings": "study.settings",
    "tables": "study.tables",
    "tradeoff": "study.tradeoff",
    "transfer": "physics.transfer",
    "vocabulary": "io.vocabulary",
    "signal.analysis": "diagnosis.analysis",
    "signal.faults": "diagnosis.faults",
    "signal.plots": "diagnosis.plots",
}

__all__ = ["__version__", "MOVED_MODULES"]


class _MovedModuleFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Import ``bearing_envelope.<old path>`` as the module of :data:`MOVED_MODULES`.

    The module object is the one at the new path (``bearing_envelope.kinematics is
    bearing_envelope.physics.kinematics``); its ``__spec__`` stays the new path's.
    """

    def find_spec(self, fullname, path=None, target=None):
        """The alias spec of an old path, None for every other name."""
        old = fullname.partition(f"{__name__}.")[2]
        if not fullname.startswith(f"{__name__}.") or old not in MOVED_MODULES:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec):
        """The module at its new path (imported now, on first use of the old path)."""
        new = importlib.import_module(f"{__name__}.{MOVED_MODULES[spec.name.partition('.')[2]]}")
        spec.loader_state = new.__spec__
        return new

    def exec_module(self, module):
        """Nothing to run: the module is imported already; restore its own spec."""
        module.__spec__ = module.__spec__.loader_state


if not any(isinstance(f, _MovedModuleFinder) for f in sys.meta_path):
    sys.meta_path.append(_MovedModuleFinder())


def __getattr__(name):
    """``bearing_envelope.<old name>`` for the modules of :data:`MOVED_MODULES`."""
    if name in MOVED_MODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
