"""The sweep configuration's schema: where it lives (a leaf of :mod:`bearing_envelope.study`).

The structure of ``config.yaml`` is described by ``bearing_envelope/data/config.schema.yaml`` (JSON
Schema, package data). Loading, validation and the cross-field checks a schema cannot express
(every case's scene builds, every fixed or order band and sensor mode below Nyquist, unique band
names, finite numbers) live in :mod:`bearing_envelope.study.settings`, the one loader used by the CLI and
the workflow. All of it runs before any job, so a bad value stops the sweep at once with the field named.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["SCHEMA_PATH"]

#: The JSON schema of ``config.yaml``, shipped as package data (the workflow validates against it too).
SCHEMA_PATH = Path(__file__).resolve().parent.parent / "data" / "config.schema.yaml"

