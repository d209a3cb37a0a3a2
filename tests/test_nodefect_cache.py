"""Issue 25 part B: the no-defect global solves shared through a content-addressed store. The
oracle is the same case simulated alone without the store (sha256 of its arrays)."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

from bearing_envelope.physics.history import CONTACT_SIGNALS, simulate
from bearing_envelope.physics.scene import Scene

#: A short draft record: the table (where the store acts) is the whole table of the case.
OP = {"operation": {"revolutions": 2}}


def _sha(hist) -> str:
    h = hashlib.sha256()
    for k in CONTACT_SIGNALS + ("roller_load", "defect_offset"):
        arr = hist.signals[k] if k in hist.signals else getattr(hist, k)
        h.update(np.ascontiguousarray(arr, dtype=np.float64).tobytes())
    for k in ("ratio", "ratio_defect", "ratio_force", "ratio_area", "p_out", "q_out", "approach0",
              "area0", "w0", "p0"):
        h.update(np.ascontiguousarray(getattr(hist.table, k), dtype=np.float64).tobytes())
    return h.hexdigest()


def _case(depth):
    return Scene.from_mapping(OP, load_kN=500.0, depth_um=depth)


@pytest.fixture(scope="module")
def alone():
    """The 50 um case solved alone, without the store."""
    return _sha(simulate(_case(50.0), "draft"))


def test_shared_solves_are_bit_identical_to_a_case_solved_alone(tmp_path, alone, capfd):
    store = tmp_path / "nodefect"
    first = simulate(_case(15.0), "draft", nodefect_cache=store)
    assert first.stats["nodefect_cache_misses"] > 0 and first.stats["nodefect_cache_hits"] == 0
    assert len(list(store.glob("*.npz"))) == first.stats["nodefect_cache_misses"]
    assert not list(store.glob(".tmp-*"))                     # written atomically
    second = simulate(_case(50.0), "draft", nodefect_cache=store)
    # every no-defect global solve of the 50 um case was made by the 15 um case
    assert second.stats["nodefect_cache_misses"] == 0
    assert second.stats["nodefect_cache_hits"] >= 5
    assert second.stats["n_solves"] < first.stats["n_solves"]
    assert _sha(second) == alone
    err = capfd.readouterr().err
    assert err.count("missing: solving and storing it") == first.stats["nodefect_cache_misses"]


def test_truncated_and_mismatched_entries_are_rebuilt_with_one_line(tmp_path, alone, capfd):
    store = tmp_path / "nodefect"
    simulate(_case(50.0), "draft", nodefect_cache=store)
    capfd.readouterr()
    entries = sorted(store.glob("*.npz"))
    assert len(entries) >= 3
    truncated, swapped, donor = entries[:3]
    truncated.write_bytes(truncated.read_bytes()[:200])
    swapped.write_bytes(donor.read_bytes())                   # another entry's content
    again = simulate(_case(50.0), "draft", nodefect_cache=store)
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 2, err
    assert sum("unreadable" in line for line in err) == 1
    assert sum("key mismatch" in line for line in err) == 1
    assert again.stats["nodefect_cache_misses"] == 2
    assert _sha(again) == alone
    # both rebuilt: a third run reads every entry
    third = simulate(_case(50.0), "draft", nodefect_cache=store)
    assert third.stats["nodefect_cache_misses"] == 0
    assert capfd.readouterr().err == ""


def test_the_key_holds_what_the_solve_depends_on(tmp_path):
    store = tmp_path / "nodefect"
    simulate(_case(50.0), "draft", nodefect_cache=store)
    n = len(list(store.glob("*.npz")))
    # another material: every global solve differs, none is reused
    other = Scene.from_mapping({**OP, "material": {"roller": {"E_GPa": 200.0, "nu": 0.3}}},
                               load_kN=500.0, depth_um=50.0)
    h = simulate(other, "draft", nodefect_cache=store)
    assert h.stats["nodefect_cache_hits"] == 0
    assert len(list(store.glob("*.npz"))) == n + h.stats["nodefect_cache_misses"]
