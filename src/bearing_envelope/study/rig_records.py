"""What the virtual rig reads from a CWRU record: its samples and meta, and the bearing's event
rates at its shaft rate (shared by :mod:`.rig` and :mod:`.rig_events`)."""

from __future__ import annotations

import json

import numpy as np

from ..physics.kinematics import fault_frequencies

__all__ = ["read_record", "rig_rates", "RIG_BEARING"]

#: The drive-end bearing of the CWRU rig (SKF 6205-2RS JEM, as in every record's meta
#: ``geometry``): rolling elements, ball and pitch diameters (mm), contact angle (deg).
RIG_BEARING = {"n_balls": 9, "ball_diameter_mm": 7.94, "pitch_diameter_mm": 39.04,
               "contact_angle_deg": 0.0}


def read_record(path: str) -> tuple[np.ndarray, dict]:
    """A record's samples and meta (``x`` and ``meta_json`` of its ``.npz``; never unpickled).

    Parameters
    ----------
    path : str
        The ``.npz`` record.

    Returns
    -------
    (numpy.ndarray, dict)
        The samples (float) and the parsed meta.
    """
    with np.load(path, allow_pickle=False) as z:
        return np.asarray(z["x"], dtype=float), json.loads(str(z["meta_json"]))


def rig_rates(fr: float) -> dict:
    """The rig bearing's event rates at a shaft rate.

    Parameters
    ----------
    fr : float
        Shaft rate, Hz.

    Returns
    -------
    dict
        ``bpfo``, ``bpfi``, ``bsf``, ``bsf2`` (2 x BSF), Hz.
    """
    b = RIG_BEARING
    ff = fault_frequencies(fr, b["n_balls"], b["ball_diameter_mm"], b["pitch_diameter_mm"],
                           b["contact_angle_deg"])
    return {"bpfo": ff.bpfo, "bpfi": ff.bpfi, "bsf": ff.bsf, "bsf2": 2 * ff.bsf}
