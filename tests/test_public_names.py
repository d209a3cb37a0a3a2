"""Each public name of the library is defined once (issue 44: "public names defined twice: 0").

Every module of ``src/bearing_envelope`` is parsed with ``ast`` (nothing is imported); its
top-level public definitions (``def``, ``async def`` and ``class`` whose name does not start
with ``_``, also those under a top-level ``if`` / ``try``) are collected per module. A name
defined in two modules is one concept written twice, or two concepts under one name: either
way a reader cannot tell which one a call reaches. Re-exports (``from .x import name``) and
aliases by assignment are not definitions.

The one exemption, by package and name: the sub-command protocol of ``commands/`` (every
sub-command module defines ``register(subparsers)``, and ``run(args)`` which ``register`` binds;
``cli.py`` calls each module's ``register``).
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PACKAGE = "bearing_envelope"
SRC = Path(__file__).resolve().parents[1] / "src" / PACKAGE

#: (sub-package, name): a protocol each module of the sub-package implements.
PROTOCOL = {("commands", "register"), ("commands", "run")}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _top_level(body):
    """Statements at module level, those under a top-level ``if`` / ``try`` included."""
    for node in body:
        yield node
        if isinstance(node, ast.If):
            yield from _top_level(node.body + node.orelse)
        elif isinstance(node, ast.Try):
            yield from _top_level(node.body + node.orelse + node.finalbody
                                  + [s for h in node.handlers for s in h.body])


def public_definitions(tree: ast.Module) -> dict[str, int]:
    """``name -> line`` of the module's top-level public functions and classes."""
    return {n.name: n.lineno for n in _top_level(tree.body)
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
            and not n.name.startswith("_")}


def _exempt(module: str, name: str) -> bool:
    parts = module.split(".")
    return len(parts) > 2 and (parts[1], name) in PROTOCOL


def defined_twice(trees: dict[str, ast.Module]) -> dict[str, list[str]]:
    """``name -> ["module:line", ...]`` for every public name defined in two modules or more."""
    where = defaultdict(list)
    for mod, tree in sorted(trees.items()):
        for name, line in public_definitions(tree).items():
            if not _exempt(mod, name):
                where[name].append(f"{mod}:{line}")
    return {name: places for name, places in sorted(where.items()) if len(places) > 1}


def _library() -> dict[str, ast.Module]:
    return {module_name(p): ast.parse(p.read_text(encoding="utf-8"), str(p))
            for p in sorted(SRC.rglob("*.py"))}


def test_no_public_name_is_defined_twice():
    twice = defined_twice(_library())
    assert twice == {}, "public names defined in more than one module:\n" + "\n".join(
        f"{name}: {', '.join(places)}" for name, places in twice.items())


def test_the_library_has_public_definitions_to_check():
    """The walk reaches the library (a count of 0 would make the check above vacuous)."""
    trees = _library()
    n = sum(len(public_definitions(t)) for t in trees.values())
    assert len(trees) > 100 and n > 500
    assert "simulate" in public_definitions(trees[f"{PACKAGE}.physics.history"])


# ------------------------------------------------------------------------------------------
# the checker itself, on made-up modules


def _trees(**sources: str) -> dict[str, ast.Module]:
    return {f"{PACKAGE}.{m.replace('__', '.')}": ast.parse(s) for m, s in sources.items()}


def test_a_planted_duplicate_is_found_with_both_places():
    trees = _trees(physics__a="def rates(x):\n    return x\n",
                   study__b="import os\n\n\nclass Other:\n    pass\n\n\ndef rates(y):\n    return y\n")
    assert defined_twice(trees) == {"rates": [f"{PACKAGE}.physics.a:1", f"{PACKAGE}.study.b:8"]}


def test_a_planted_duplicate_in_the_real_library_is_found():
    """One more module defining an existing public name (``simulate``) fails the real check."""
    trees = _library()
    trees[f"{PACKAGE}.study.planted"] = ast.parse("def simulate(scene):\n    return scene\n")
    line = public_definitions(trees[f"{PACKAGE}.physics.history"])["simulate"]
    assert defined_twice(trees)["simulate"] == [f"{PACKAGE}.physics.history:{line}",
                                                f"{PACKAGE}.study.planted:1"]


def test_reexports_private_names_methods_and_the_protocol_are_not_duplicates():
    trees = _trees(
        physics__a="def rates(x):\n    return x\n\n\ndef _helper():\n    pass\n",
        physics__b=("from .a import rates\nfrom .a import rates as r2\nalias = rates\n\n\n"
                    "def _helper():\n    pass\n\n\nclass K:\n    def rates(self):\n        pass\n"),
        commands__one="def register(sub):\n    pass\n\n\ndef run(args):\n    pass\n",
        commands__two="def register(sub):\n    pass\n\n\ndef run(args):\n    pass\n")
    assert defined_twice(trees) == {}


def test_definitions_under_a_top_level_if_or_try_count():
    trees = _trees(signal__a="try:\n    import numba\nexcept ImportError:\n    def kernel():\n"
                             "        pass\n",
                   signal__b="if True:\n    def kernel():\n        pass\n")
    assert list(defined_twice(trees)) == ["kernel"]


def test_the_protocol_is_exempt_only_in_its_package():
    trees = _trees(commands__one="def run(args):\n    pass\n",
                   study__job="def run(args):\n    pass\n")
    assert defined_twice(trees) == {}          # one definition counted: the study's
    trees[f"{PACKAGE}.io.job"] = ast.parse("def run(args):\n    pass\n")
    assert list(defined_twice(trees)) == ["run"]
