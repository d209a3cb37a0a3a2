"""Modules imported on first use: what a ``simulate`` job never calls, it does not import.

This module sits below the layers (docs/architecture.md): it imports nothing of the package.
A module that names a heavy dependency only inside its functions (``scipy.signal``, 1.0 CPU s to
import with ``scipy.stats``; ``pandas``, 0.3 s) binds it with :func:`lazy_module` instead of
``import``: the name reads like the module, and the import happens at the first attribute
access. The import chain of ``bearing-envelope simulate`` reaches the diagnosis layer (the
settings loader fills the ``analysis:`` defaults from ``AnalysisOptions``), whose modules need
these packages only when they analyse a signal.
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["LazyModule", "lazy_module"]


class LazyModule:
    """A stand-in for a module, imported (:func:`importlib.import_module`) at the first
    attribute read; every read then goes to the module itself.

    Parameters
    ----------
    name : str
        The module's absolute dotted name (``"scipy.signal"``).
    """

    __slots__ = ("_name", "_module")

    def __init__(self, name: str):
        self._name = name
        self._module: ModuleType | None = None

    def __getattr__(self, attr: str):
        mod = self._module
        if mod is None:
            mod = self._module = importlib.import_module(self._name)
        return getattr(mod, attr)

    def __repr__(self) -> str:
        state = "imported" if self._module is not None else "not imported yet"
        return f"<lazy module {self._name!r} ({state})>"


def lazy_module(name: str) -> LazyModule:
    """``name``, imported when one of its attributes is first read.

    Parameters
    ----------
    name : str
        Absolute dotted module name.

    Returns
    -------
    LazyModule
        Reads ``lazy.attr`` as ``importlib.import_module(name).attr``.
    """
    return LazyModule(name)
