"""Storage: reads and writes what it is given, computes nothing.

- :mod:`.case`: the HDF5 case file (:func:`write_case`, :func:`read_case`);
- :mod:`.artefacts`: bands, kurtogram, spectra, sensor case and tables (a ``write_*`` /
  ``read_*`` pair each, with a format version);
- :mod:`.atomic`: atomic file and folder writes, stale temporary files;
- :mod:`.integrity`: checksums and attribute digest of case files, free-space checks;
- :mod:`.vocabulary`: the column names of the tidy tables.

Everything public is re-exported here: ``from bearing_envelope.io import read_case``.
"""

from .artefacts import *  # noqa: F401,F403
from .artefacts import __all__ as _artefacts_all
from .atomic import *  # noqa: F401,F403
from .atomic import __all__ as _atomic_all
from .case import *  # noqa: F401,F403
from .case import __all__ as _case_all
from .integrity import *  # noqa: F401,F403
from .integrity import __all__ as _integrity_all

__all__ = [*_case_all, *_artefacts_all, *_atomic_all, *_integrity_all]
