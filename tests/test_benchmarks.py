"""Every registered benchmark runs on tiny inputs (``smoke()``): the benchmarks that regenerate
the figures of docs/benchmarks.md stay runnable. No timing is checked."""
import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import benchmarks  # noqa: E402


@pytest.mark.parametrize("name", sorted(benchmarks.REGISTRY))
def test_smoke(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    module = benchmarks.load(name)
    assert callable(module.main)
    module.smoke()


def test_every_module_of_the_folder_is_registered_or_a_helper():
    helpers = {"__init__", "__main__", "accuracy"}   # accuracy: the reference's tables/metrics
    modules = {p.stem for p in (ROOT / "benchmarks").glob("*.py")}
    assert modules - helpers == set(benchmarks.REGISTRY)


def test_entry_point_lists_the_registry():
    out = subprocess.run([sys.executable, "-m", "benchmarks"], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout
    assert all(name in out for name in benchmarks.REGISTRY)


def test_an_unknown_name_is_refused_with_the_allowed_ones():
    res = subprocess.run([sys.executable, "-m", "benchmarks", "nope"], cwd=ROOT,
                         capture_output=True, text=True)
    assert res.returncode != 0 and "contact_speed" in res.stderr


def test_nothing_outside_src_imports_a_private_name_of_the_library():
    """``from bearing_envelope.x import _name``, ``bearing_envelope._module`` or
    ``module._name`` on an imported library module, anywhere outside src/."""
    hits = []
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT)
        if rel.parts[0] in ("src", ".snakemake", "results") or rel.parts[0].startswith("."):
            continue
        hits += [(str(rel), name) for _, name in _private_uses(path)]
    assert sorted(set(hits)) == []


def _private(name: str) -> bool:
    return any(p.startswith("_") and not p.startswith("__") for p in name.split("."))


def _private_uses(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    modules = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("bearing_envelope"):
            for alias in node.names:
                full = f"{node.module}.{alias.name}"
                if _private(full):
                    yield node.lineno, full
                modules.add(alias.asname or alias.name)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("bearing_envelope"):
                    if _private(alias.name):
                        yield node.lineno, alias.name
                    modules.add(alias.asname or alias.name.split(".")[0])
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _private(node.attr):
            base = node.value
            while isinstance(base, ast.Attribute):
                base = base.value
            if isinstance(base, ast.Name) and base.id in modules:
                yield node.lineno, f"{base.id}...{node.attr}"
