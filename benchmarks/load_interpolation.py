"""Load interpolation of the table (issue 25, fourth session), by hand.

    nice -n 5 python benchmarks/load_interpolation.py build --out results_bench/load_interp
    python benchmarks/load_interpolation.py nodes --out results_bench/load_interp
    nice -n 5 python benchmarks/load_interpolation.py metrics --out results_bench/load_interp
    python benchmarks/load_interpolation.py report --out results_bench/load_interp \
        [--rules old dF+nodes dF]

``build``: tables of the held-out cases (``benchmarks/reference.py`` HELDOUT) at ``standard``
with 5, 9 and 17 load nodes (checks and snapshots off; cached by ``benchmarks/accuracy.py``,
CPU per table stored). ``nodes`` (a): the ratios of the 5- and 9-node tables read at the
17-node table's own nodes between theirs (the 17-node rows are direct solves there), per rule
(``node_errors.csv``). ``metrics`` (b): the analysis chain's metrics (``accuracy.metrics``, 10
revolutions, each table's own acquisition, numpy reading) of every table and rule
(``metrics.csv``); ``report``: their errors against the 17-node table
(``load_interpolation.md``). Rules (:data:`RULES`): ``old`` = the package before 2026-11-26's
fourth session (ratios dF/Q, dA/A0 blended; delta0, A0 on the load nodes), ``dF`` = the package
after (dF, dA blended; delta0, A0 on ``q_out`` when the table has them), ``dF+nodes`` = dF with
delta0 on the nodes, and the candidates not adopted (``cubic``, ``edge``, ``dF+spline``,
``dF+hold``, ``dF@dense``: delta0 from the 17-node table). docs/benchmarks.md's table (b) is
``report --rules old dF+nodes dF`` on tables built with ``approach_out``; its "rules tried" rows
come from ``metrics --rules cubic dF+cubic dF+edge dF+spline dF@dense`` (delta0 on the nodes:
they were first run on tables built before ``approach_out`` existed).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
import accuracy as acc  # noqa: E402
from reference import HELDOUT, line_group  # noqa: E402

from bearing_envelope.physics.acquisition import acquisition_settings  # noqa: E402
from bearing_envelope.physics.history import synthesize_case  # noqa: E402

LOADS = (5, 9, 17)


def run_name(n: int) -> str:
    return f"n{n}"


def spec(n: int) -> dict:
    return {"preset": "standard", "n_loads": n, **acc.OFF}


def cmd_build(args) -> None:
    cases = HELDOUT if args.cases is None else [tuple(c) for c in eval(args.cases)]
    for load, depth in cases:
        for n in args.loads:
            rec = acc.build(args.out, load, depth, run_name(n), spec(n))
            print(f"F{load:g}kN h{depth:g}um n_loads={n}: {rec['cpu_s']:.1f} s CPU, "
                  f"{rec['n_solves']} solves", flush=True)


# ---------------------------------------------------------------------------------------------
# rules (numpy): a rule reads a node table T (nq, nx) at loads Q (N) and offsets x (m)

#: name -> rule: ``edge`` (``cbrt``: kappa a_coef Q^(1/3); ``measured``: each node's solved
#: half-width, linear in q between nodes), ``extensive`` (blend ``dF = Q_i ratio_force`` and
#: ``dA = A0(Q_i) ratio_area`` and divide by ``Q``, ``A0(Q)``: the rule adopted; W/W0 and P_d/W0
#: stay ratios), ``approach`` (delta0(Q): ``nodes`` = c(q) q^2 on the load nodes only, as before
#: 2026-11-26; default = the table's rule, on ``q_out`` when it has ``approach_out``;
#: ``spline`` = c a natural cubic spline through the nodes), ``below`` (``hold``: dF and dA
#: held below the first node instead of their ratios, capped at Q and A0), ``cubic``
#: (monotone cubic Hermite, Fritsch-Carlson, in q through four nodes instead of linear)
RULES = {
    "old": {"edge": "cbrt", "extensive": False, "cubic": False, "approach": "nodes"},
    "edge": {"edge": "measured", "extensive": False, "cubic": False, "approach": "nodes"},
    "cubic": {"edge": "cbrt", "extensive": False, "cubic": True, "approach": "nodes"},
    "dF": {"edge": "cbrt", "extensive": True, "cubic": False},
    "dF+edge": {"edge": "measured", "extensive": True, "cubic": False, "approach": "nodes"},
    "dF+cubic": {"edge": "cbrt", "extensive": True, "cubic": True, "approach": "nodes"},
    "dF+edge+cubic": {"edge": "measured", "extensive": True, "cubic": True, "approach": "nodes"},
    "dF+spline": {"edge": "cbrt", "extensive": True, "cubic": False, "approach": "spline"},
    "dF+nodes": {"edge": "cbrt", "extensive": True, "cubic": False, "approach": "nodes"},
    "dF+hold": {"edge": "cbrt", "extensive": True, "cubic": False, "below": "hold",
                "approach": "nodes"},
}

def node_edges(tab, rule) -> np.ndarray:
    """The contact edge of each load node (m; only differences matter)."""
    if rule["edge"] == "measured":
        return np.asarray(tab.info["half_width"], float)
    return tab.kappa * tab.a_coef * np.cbrt(tab.q_nodes)


def node_weights(tab, rule):
    """Node weights of (ratio_force, ratio_area): ``(Q_i, A0(Q_i))`` for an extensive rule."""
    one = np.ones(tab.q_nodes.size)
    return (tab.q_nodes, tab.area0) if rule["extensive"] else (one, one)


def _row(tab, T, k, xr, fill):
    xn = tab.offsets()
    j = np.clip(np.searchsorted(xn, xr, side="right") - 1, 0, xn.size - 2)
    tx = np.clip((xr - xn[j]) / (xn[j + 1] - xn[j]), 0.0, 1.0)
    v = (1 - tx) * T[k, j] + tx * T[k, j + 1]
    return np.where(xr >= xn[-1], fill, v)


def _pchip_slopes(h, d):
    """Fritsch-Carlson slopes at the inner point of two intervals (h, d: widths, secants)."""
    w1, w2 = 2 * h[1] + h[0], h[1] + 2 * h[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        m = (w1 + w2) / (w1 / d[0] + w2 / d[1])
    return np.where(d[0] * d[1] > 0, m, 0.0)


def read(tab, T, Q, x, fill, rule, w=None):
    """Table ``T`` read at ``(Q, x)`` under ``rule`` (linear or cubic in q between nodes); with
    node weights ``w`` (``Q_i``, ``A0(Q_i)``) ``w T`` is blended instead (the caller divides)."""
    w = np.ones(np.shape(T)[0]) if w is None else np.asarray(w, float)
    Q = np.asarray(Q, float)
    ax = np.abs(np.asarray(x, float))
    qn = np.cbrt(tab.q_nodes)
    nq = qn.size
    E = node_edges(tab, rule)
    q = np.cbrt(np.clip(Q, 0.0, None))
    qc = np.clip(q, qn[0], qn[-1])
    i = np.clip(np.searchsorted(qn, qc, side="right") - 1, 0, nq - 2)
    tq = (qc - qn[i]) / (qn[i + 1] - qn[i])
    e_q = np.where(q < qn[0], E[0] * q / qn[0], (1 - tq) * E[i] + tq * E[i + 1])

    def val(k):
        k = np.clip(k, 0, nq - 1)
        xr = np.where(q >= qn[0], np.maximum(ax + E[k] - e_q, 0.0),
                      ax * (E[k] + tab.s_const) / (e_q + tab.s_const))
        return _row(tab, T, k, xr, fill) * w[k]

    v0, v1 = val(i), val(i + 1)
    if rule["cubic"] and nq > 2:
        h = qn[i + 1] - qn[i]
        hm = np.where(i > 0, qn[i] - qn[np.maximum(i - 1, 0)], h)
        hp = np.where(i < nq - 2, qn[np.minimum(i + 2, nq - 1)] - qn[i + 1], h)
        vm, vp = val(i - 1), val(i + 2)
        d0, d1, dm, dp = (v1 - v0) / h, (v1 - v0) / h, (v0 - vm) / hm, (vp - v1) / hp
        m0 = np.where(i > 0, _pchip_slopes((hm, h), (dm, d0)), d0)
        m1 = np.where(i < nq - 2, _pchip_slopes((h, hp), (d1, dp)), d1)
        t = tq
        h00, h10, h01, h11 = (2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2,
                              t**3 - t**2)
        v = h00 * v0 + h10 * h * m0 + h01 * v1 + h11 * h * m1
    else:
        v = (1 - tq) * v0 + tq * v1
    return v


class RuleTable:
    """A table read under a rule (duck-types what ``synthesize_case`` calls, numpy path)."""

    def __init__(self, tab, rule, dense=None):
        self.t, self.rule = tab, rule
        self.p_cap = tab.p_cap
        self.dense = dense          # a denser table whose delta0(Q) nodes replace tab's

    def _approach0(self, Q):
        """delta0(Q): the table's c(q) q^2 rule, or on a denser table's nodes (``dense``), or
        with c a natural cubic spline in q (``rule["approach"] == "spline"``)."""
        t = self.dense if self.dense is not None else self.t
        if self.rule.get("approach") == "nodes" or self.dense is not None:   # nodes only
            return t._q2_rule(t.approach0, None, Q)
        if self.rule.get("approach") != "spline":
            return t.approach_no_defect(Q)
        from scipy.interpolate import CubicSpline
        qn = np.cbrt(t.q_nodes)
        q = np.cbrt(np.clip(Q, 0.0, None))
        c = CubicSpline(qn, t.approach0 / qn ** 2, bc_type="natural")(np.clip(q, qn[0], qn[-1]))
        return c * q ** 2

    def __getattr__(self, name):
        return getattr(self.t, name)

    def evaluate(self, Q, x):
        t, r = self.t, self.rule
        Q, x = np.asarray(Q, float), np.asarray(x, float)
        q = np.cbrt(np.clip(Q, 0.0, None))
        qn = np.cbrt(t.q_nodes)
        p0q = np.where(q < qn[0], t.w0[0] * q / qn[0], np.interp(q, qn, t.w0))
        qo = np.cbrt(t.q_out)
        pout = np.where(q < qo[0], t.p_out[0] * q / qo[0], np.interp(q, qo, t.p_out))
        P = np.maximum(p0q * read(t, t.ratio, Q, x, 1.0, r), pout)
        Pd = p0q * read(t, t.ratio_defect, Q, x, 0.0, r)
        if t.p_cap is not None:
            P, Pd = np.minimum(P, t.p_cap), np.minimum(Pd, t.p_cap)
        return P, Pd

    def evaluate_integrals(self, Q, x, *, use_numba=False):
        t, r = self.t, self.rule
        Q, x = np.asarray(Q, float), np.asarray(x, float)
        wf, wa = node_weights(t, r)
        qlo = np.clip(Q, t.q_nodes[0], None)
        a0 = t.area_no_defect(Q)
        if r.get("below") == "hold":       # dF, dA held below the first node, |dF| <= Q, |dA| <= A0
            dF = np.clip(read(t, t.ratio_force, Q, x, 0.0, r, wf), -Q, Q)
            dA = np.clip(read(t, t.ratio_area, Q, x, 0.0, r, wa), -a0, a0)
        else:
            dF = read(t, t.ratio_force, Q, x, 0.0, r, wf) * Q / (qlo if r["extensive"] else 1.0)
            dA = read(t, t.ratio_area, Q, x, 0.0, r, wa) * a0 / \
                (t.area_no_defect(qlo) if r["extensive"] else 1.0)
        d0, d = self._approach0(Q), self._approach0(Q + dF)
        area = t.area_no_defect(Q + dF) + dA
        return {"removed_force": dF, "contact_force": Q - dF, "approach": d,
                "approach_change": d - d0, "contact_area": area}


#: the node tables compared in (a): name -> (attribute, fill beyond the offsets, normaliser)
RATIOS = {"W/W0": ("ratio", 1.0), "P_d/W0": ("ratio_defect", 0.0),
          "ratio_force": ("ratio_force", 0.0), "ratio_area": ("ratio_area", 0.0)}


def load_rec(out, load, depth, n):
    return acc.build(out, load, depth, run_name(n), spec(n))


def node_errors(coarse, fine, rule) -> pd.DataFrame:
    """(a): the coarse table read at the fine table's nodes between its own (the fine rows are
    direct solves there), per ratio: the error of each row, max and rms over the offsets where
    the defect touches the contact, relative to the row's largest |value| (W/W0: to 1)."""
    qc = coarse.q_nodes
    rows = []
    xs = fine.offsets()
    for k, Qk in enumerate(fine.q_nodes):
        if np.min(np.abs(qc / Qk - 1.0)) < 1e-9:
            continue                                   # a node of both: not interpolated
        for name, (attr, fill) in RATIOS.items():
            Tf = getattr(fine, attr)[k]
            wf, wa = node_weights(coarse, rule)
            w = {"ratio_force": wf, "ratio_area": wa}.get(attr)
            v = read(coarse, getattr(coarse, attr), np.full(xs.size, Qk), xs, fill, rule, w)
            if w is not None and rule["extensive"]:
                v = v / {"ratio_force": Qk, "ratio_area": float(coarse.area_no_defect(Qk))}[attr]
            dev = Tf - fill
            scale = 1.0 if attr == "ratio" else max(float(np.max(np.abs(dev))), 1e-300)
            touch = np.abs(dev) > 1e-12 * max(scale, 1.0) if attr != "ratio" else \
                np.ones_like(dev, bool)
            e = (v - Tf)[touch] / scale
            if not e.size:
                continue
            rows.append({"Q_over_qmax": Qk / fine.q_nodes[-1], "ratio": name,
                         "max_err": float(np.max(np.abs(e))),
                         "rms_err": float(np.sqrt(np.mean(e ** 2))),
                         "sum_err": float(np.sum(v[touch] - Tf[touch]) /
                                          max(abs(float(np.sum(dev))), 1e-300))})
    return pd.DataFrame(rows)


def cmd_nodes(args) -> pd.DataFrame:
    out = []
    for load, depth in HELDOUT:
        fine = load_rec(args.out, load, depth, 17)["table"]
        for n in (5, 9):
            coarse = load_rec(args.out, load, depth, n)["table"]
            for rn, rule in RULES.items():
                df = node_errors(coarse, fine, rule)
                df["case"], df["n_loads"], df["rule"] = f"{load:g}kN/{depth:g}um", n, rn
                out.append(df)
    df = pd.concat(out, ignore_index=True)
    df.to_csv(args.out / "node_errors.csv", index=False)
    g = df.groupby(["n_loads", "ratio", "rule"]).agg(
        max_err=("max_err", "max"), rms_err=("rms_err", lambda v: float(np.sqrt(np.mean(v ** 2)))),
        sum_err=("sum_err", lambda v: float(np.max(np.abs(v)))))
    print((100 * g).round(2).unstack("rule").to_string())
    return df


#: rules of the metrics (b)
METRIC_RULES = ("old", "dF", "cubic", "dF+cubic", "dF+edge")


def case_metrics(out, load, depth, n, rule_name, revolutions, analysis) -> list[dict]:
    """(b): the analysis chain's metrics of one table read under one rule (numpy path, the
    case's own acquisition), with the CPU of the table and of the synthesis. A rule name ending
    in ``@dense`` takes delta0(Q) from the 17-node table (a stand-in for a denser grid)."""
    rec = load_rec(out, load, depth, n)
    sc = acc.scene(load, depth, revolutions)
    acq = acquisition_settings(sc, rec["fidelity"])
    base, _, dense = rule_name.partition("@")
    dtab = load_rec(out, load, depth, 17)["table"] if dense else None
    c0 = time.process_time()
    _, sig, _ = synthesize_case(sc, RuleTable(rec["table"], RULES[base], dtab), rec["ld"],
                                rec["fidelity"], use_numba=False, acquisition=acq)
    cpu = time.process_time() - c0
    return [{"load_kN": load, "depth_um": depth, "n_loads": n, "rule": rule_name, **r,
             "table_cpu_s": rec["cpu_s"], "synth_numpy_cpu_s": cpu, "oversample": acq["oversample"]}
            for r in acc.metrics(sc, sig, analysis)]


def cmd_metrics(args) -> pd.DataFrame:
    analysis = acc.analysis_config()
    path = args.out / "metrics.csv"
    old = pd.read_csv(path) if path.exists() else pd.DataFrame(columns=["rule"])
    rules = [r for r in (args.rules or METRIC_RULES) if r not in set(old["rule"])]
    rows = []
    for load, depth in HELDOUT:
        for n in LOADS:
            for rn in rules:
                rows += case_metrics(args.out, load, depth, n, rn, args.revolutions, analysis)
                print(f"F{load:g}kN h{depth:g}um n{n} {rn}", flush=True)
    df = pd.concat([old, pd.DataFrame(rows)], ignore_index=True) if rows else old
    df.to_csv(path, index=False)
    return df


def metric_errors(df: pd.DataFrame, ref_rule: str | None = None) -> pd.DataFrame:
    """Relative error of every metric against the 17-node table under the same rule (or under
    ``ref_rule``), with its class (:func:`reference.line_group`)."""
    keys = acc.KEYS
    ref = df[df.n_loads == 17]
    if ref_rule is not None:
        ref = ref[ref.rule == ref_rule].drop(columns="rule")
        e = df[df.n_loads < 17].merge(ref[keys + ["value"]].rename(columns={"value": "ref"}),
                                      on=keys)
    else:
        e = df[df.n_loads < 17].merge(
            ref[keys + ["rule", "value"]].rename(columns={"value": "ref"}), on=keys + ["rule"])
    e["error"] = (e["value"] - e["ref"]).abs() / e["ref"].abs()
    e["group"] = [line_group(q, sb, b) for q, sb, b in
                  zip(e["quantity"], e["sideband"], e["band_strategy"].fillna(""))]
    return e[np.isfinite(e["error"]) & e["group"].notna()]


def metrics_table(e: pd.DataFrame) -> pd.DataFrame:
    """Median / 95th percentile / max error (%) per signal, class, node count and rule."""
    g = e.groupby(["signal", "group", "n_loads", "rule"])["error"]
    t = pd.DataFrame({"median": g.median(), "p95": g.quantile(0.95), "max": g.max()}) * 100
    return t


SIGNALS_SHOWN = ("p_max", "removed_force", "approach_change")
GROUPS_SHOWN = ("envelope_line", "envelope_sideband", "kurtogram_line", "kurtogram_sideband",
                "raw_dc", "raw_fr", "raw_bpfi", "peak", "rms")


def _fmt(v: float) -> str:
    return f"{v:.2g}" if v < 10 else f"{v:.0f}"


def report_markdown(df: pd.DataFrame, rules=("old", "dF"), ref_rule=None) -> str:
    """The tables of docs/benchmarks.md: error (%) against 17 nodes (under the same rule, or
    ``ref_rule``), median / 95th / max over the held-out cases, per signal and class, 5 and 9
    nodes, per rule."""
    t = metrics_table(metric_errors(df, ref_rule))
    lines = ["| signal | class | " + " | ".join(f"{n} nodes, {r}" for n in (5, 9) for r in rules)
             + " |", "|---|---|" + "---|" * (2 * len(rules))]
    for sig in SIGNALS_SHOWN:
        for grp in GROUPS_SHOWN:
            cells = []
            for n in (5, 9):
                for r in rules:
                    key = (sig, grp, n, r)
                    cells.append(" / ".join(_fmt(v) for v in t.loc[key]) if key in t.index else "-")
            lines.append(f"| {sig} | {grp} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def rule_sensitivity(df: pd.DataFrame, a="old", b="dF") -> pd.DataFrame:
    """Median / max relative change (%) of each metric between two rules on the same table."""
    keys = acc.KEYS + ["n_loads"]
    x = df[df.rule == a].merge(df[df.rule == b][keys + ["value"]], on=keys, suffixes=("", "_b"))
    x["change"] = (x["value_b"] - x["value"]).abs() / x["value"].abs()
    x["group"] = [line_group(q, sb, bs) for q, sb, bs in
                  zip(x["quantity"], x["sideband"], x["band_strategy"].fillna(""))]
    x = x[np.isfinite(x["change"]) & x["group"].notna()]
    g = x.groupby(["n_loads", "signal", "group"])["change"]
    return pd.DataFrame({"median": g.median(), "max": g.max()}) * 100


def cmd_report(args) -> None:
    df = pd.read_csv(args.out / "metrics.csv")
    rules = tuple(args.rules)
    md = ["Error against the 17-node table under the same rule, % (median / 95th pct / max over "
          "the three held-out cases' metrics of the class):", "", report_markdown(df, rules), ""]
    md += [f"The same against the 17-node table under rule {rules[-1]} (a common reference):",
           "", report_markdown(df, rules, rules[-1]), ""]
    new = rules[-1]
    sens = rule_sensitivity(df[df.n_loads == 17], "old", new)
    md += [f"Change of the 17-node table's metrics from rule old to {new}, % (median / max):",
           "", sens.round(3).to_markdown(), ""]
    one = df[(df.n_loads == 5) & (df.load_kN == 500.0) & (df.depth_um == 50.0)]
    md += [f"The default (5 nodes) at 500 kN / 50 um, rule old -> {new}, % (median / max):", "",
           rule_sensitivity(one, "old", new).round(3).to_markdown(), ""]
    cpu = df.groupby(["load_kN", "depth_um", "n_loads"])["table_cpu_s"].first().unstack()
    md += ["CPU per table, s (process time, checks and snapshots off):", "",
           cpu.round(1).to_markdown(), ""]
    text = "\n".join(md)
    (args.out / "load_interpolation.md").write_text(text)
    print(text)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    b = sub.add_parser("build")
    b.add_argument("--out", type=Path, required=True)
    b.add_argument("--cases", default=None)
    b.add_argument("--loads", type=int, nargs="+", default=list(LOADS))
    b.set_defaults(func=cmd_build)
    c = sub.add_parser("nodes")
    c.add_argument("--out", type=Path, required=True)
    c.set_defaults(func=cmd_nodes)
    m = sub.add_parser("metrics")
    m.add_argument("--out", type=Path, required=True)
    m.add_argument("--revolutions", type=float, default=10.0)
    m.add_argument("--rules", nargs="+", default=None, help="rules to add (default: all)")
    m.set_defaults(func=cmd_metrics)
    r = sub.add_parser("report")
    r.add_argument("--out", type=Path, required=True)
    r.add_argument("--rules", nargs="+", default=["old", "dF"])
    r.set_defaults(func=cmd_report)
    a = ap.parse_args(argv)
    a.func(a)


if __name__ == "__main__":
    main()
