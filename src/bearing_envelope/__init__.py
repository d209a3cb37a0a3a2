"""bearing_envelope: non-Hertzian contact of a damaged roller bearing and envelope analysis.

Layers (each importable alone): :mod:`kinematics`, :mod:`geometry`, :mod:`contact`,
:mod:`loads`, :mod:`scene`, :mod:`history`, :mod:`signal`, :mod:`io`, :mod:`cli`.
SI units inside the library; names carry units only at the edges (``depth_um``, ``load_kN``).
"""

__version__ = "0.1.0"
__all__ = ["__version__"]
