"""Sub-commands of the ``bearing-envelope`` CLI, one module each (see :mod:`bearing_envelope.cli`)."""
