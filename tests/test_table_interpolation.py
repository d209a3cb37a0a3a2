"""The table's load interpolation of the integral signals (issue 25, fourth session): a synthetic
table whose removed force and area change follow known laws in the load and the contact edge."""

import numpy as np
import pytest

from bearing_envelope.physics.kernels import HAVE_NUMBA
from bearing_envelope.physics.table import Q_MIN_FRACTION, PressureTable

Q_MAX = 5.0e4          # N
A_COEF = 1.1e-5        # m N^-1/3: edge a_coef Q^(1/3), 405 um at Q_MAX
C_AREA = 2.0e-9        # m^2 N^-2/3: A0 = C_AREA Q^(2/3) (Hertz)
STEP = 12e-6           # m, offset nodes
RAMP = 60e-6           # m: the removed force grows over this distance inside the edge
F0, DA0 = 2.2, -1.8e-9  # N, m^2: removed force and area change deep in the contact


def _g(d):
    """Fraction of the full removed force at a distance ``d`` (m) inside the contact edge."""
    return np.clip(d / RAMP, 0.0, 1.0)


def _table(n_loads=5):
    """dF(Q, x) = F0 g(e(Q) - |x|), dA = DA0 g(...), e = a_coef Q^(1/3): both independent of the
    load at a given distance from the edge, as measured (their ratios go as 1/Q, 1/A0)."""
    qn = np.linspace((Q_MIN_FRACTION * Q_MAX) ** (1 / 3), Q_MAX ** (1 / 3), n_loads)
    Q = qn ** 3
    e = A_COEF * qn
    s_max = e[-1] + 100e-6
    x = STEP * np.arange(int(np.ceil(s_max / STEP)) + 1)
    g = _g(e[:, None] - x[None, :])
    a0 = C_AREA * qn ** 2
    q_out = np.linspace(qn[0], qn[-1], 3 * (n_loads - 1) + 1) ** 3
    return PressureTable(
        Q, x / s_max, p0=1e9 * qn, w0=1e9 * qn, ratio=np.ones_like(g), ratio_defect=0 * g,
        a_coef=A_COEF, kappa=1.0, s_const=100e-6, s_max=s_max, q_out=q_out,
        p_out=np.zeros(q_out.size), ratio_force=F0 * g / Q[:, None],
        ratio_area=DA0 * g / a0[:, None], approach0=1e-5 * qn ** 2, area0=a0)


def _probe(tb):
    """Loads between every pair of nodes (and below the first) and offsets across the edge."""
    qn = np.cbrt(tb.q_nodes)
    q = np.concatenate([0.5 * (qn[:-1] + qn[1:]), qn[:-1] + 0.2 * np.diff(qn), [0.7 * qn[0]]])
    Q = np.repeat(q ** 3, 41)
    x = np.tile(np.linspace(-1.0, 1.0, 41), q.size) * A_COEF * np.repeat(q, 41)
    return Q, x


@pytest.mark.parametrize("use_numba", [False, True] if HAVE_NUMBA else [False])
def test_removed_force_and_area_change_read_between_load_nodes(use_numba):
    tb = _table()
    Q, x = _probe(tb)
    sig = tb.evaluate_integrals(Q, x, use_numba=use_numba)
    d = A_COEF * np.cbrt(Q) - np.abs(x)
    above = Q >= tb.q_nodes[0]
    # between the nodes: dF and dA read at the same distance from each row's edge, blended in q:
    # exact but for the offset interpolation across the ramp's two kinks (one cell each)
    tol = STEP / RAMP
    np.testing.assert_allclose(sig["removed_force"][above], F0 * _g(d[above]), rtol=0,
                               atol=tol * F0)
    flat = above & (d > RAMP + STEP)              # deep inside: no kink in either row's cell
    np.testing.assert_allclose(sig["removed_force"][flat], F0, rtol=1e-12)
    a0 = tb.area_no_defect(Q + sig["removed_force"])
    np.testing.assert_allclose(sig["contact_area"][flat] - a0[flat], DA0, rtol=1e-12)
    # below the first node the ratios are held: dF ~ Q, dA ~ A0 (as before)
    lo = ~above & (d > RAMP + STEP)
    np.testing.assert_allclose(sig["removed_force"][lo], F0 * Q[lo] / tb.q_nodes[0], rtol=1e-12)


def test_former_rule_missed_the_power_law():
    """The former rule (dF/Q linear in q) reads the same table 10-20 % off between the nodes."""
    tb = _table()
    Q, x = _probe(tb)
    d = A_COEF * np.cbrt(Q) - np.abs(x)
    flat = (Q >= tb.q_nodes[0]) & (d > RAMP + STEP)
    qn = np.cbrt(tb.q_nodes)
    q = np.cbrt(Q[flat])
    rf_old = np.interp(q, qn, F0 / tb.q_nodes)          # what the former rule read deep inside
    err = Q[flat] * rf_old / F0 - 1.0
    assert err.max() > 0.15                               # first interval, midpoint
    new = tb.evaluate_integrals(Q[flat], x[flat])["removed_force"] / F0 - 1.0
    assert np.abs(new).max() < 1e-12


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba not installed")
def test_integrals_numba_matches_numpy():
    tb = _table(n_loads=4)
    rng = np.random.default_rng(3)
    Q = rng.uniform(0.0, 1.05, 500) * Q_MAX
    x = rng.uniform(-1.2, 1.2, 500) * tb.s_max
    a = tb.evaluate_integrals(Q, x, use_numba=True)
    b = tb.evaluate_integrals(Q, x, use_numba=False)
    for k in a:
        np.testing.assert_allclose(a[k], b[k], rtol=1e-12, atol=1e-12 * np.abs(b[k]).max())


def test_no_defect_approach_read_on_the_dense_load_grid():
    """delta0 = c(q) q^2 with c bending between the load nodes (the end relief): read on q_out
    (the P_out solves' approach) it follows the bend; on the nodes alone it does not."""
    tb = _table()
    qo = np.cbrt(tb.q_out)
    qk = 0.8 * qo[-1]

    def law(q):
        return 1e-5 * q ** 2 * (1.0 + 0.5 * np.clip(q / qk - 1.0, 0.0, None) ** 2)

    tb.approach0 = law(np.cbrt(tb.q_nodes))
    tb.approach_out = law(qo)
    np.testing.assert_allclose(tb.approach_no_defect(tb.q_out), law(qo), rtol=1e-12)
    # the slope the approach change reads: dF = 1 N at the top of the range
    Q = np.linspace(0.85, 0.99, 8) * tb.q_out[-1]
    exact = law(np.cbrt(Q + 1.0)) - law(np.cbrt(Q))
    dense = tb.approach_no_defect(Q + 1.0) - tb.approach_no_defect(Q)
    tb.approach_out = None                                  # the load nodes only
    nodes = tb.approach_no_defect(Q + 1.0) - tb.approach_no_defect(Q)
    err_dense = np.abs(dense / exact - 1).max()
    err_nodes = np.abs(nodes / exact - 1).max()
    # the slope of a piecewise-linear c is first order in the spacing: 3x denser, ~1/3 the error
    assert err_dense < 0.4 * err_nodes and err_dense < 0.02


def test_dense_grids_must_match_q_out():
    tb = _table()
    with pytest.raises(ValueError, match="approach_out"):
        PressureTable(**{**tb.__dict__, "approach_out": np.ones(3)})
