"""Every public function and method of the library documents its parameters and its return
value in numpydoc sections (``Parameters``, ``Returns`` / ``Yields``), read with ``ast``.

Public: a module not named ``_*``, a function or class in the module's ``__all__`` (or, without
one, not named ``_*``), and the methods of such a class not named ``_*`` (properties and dunder
methods aside). A function "takes parameters" when it has any besides ``self``/``cls``, and
"returns" when a ``return`` carries a value (``Yields`` for a generator).
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "bearing_envelope"

#: Modules whose gaps are still open (listed so the list only shrinks); empty: every public
#: function of the library is checked.
PENDING: set[str] = set()


def _section(doc: str, name: str) -> bool:
    return re.search(rf"^\s*{name}\s*\n\s*-{{3,}}", doc, re.M) is not None


def _returns_value(fn: ast.AST) -> tuple[bool, bool]:
    """(returns a value, is a generator), nested functions and classes not counted."""
    value = gen = False
    todo = list(ast.iter_child_nodes(fn))
    while todo:
        node = todo.pop()
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            continue
        if isinstance(node, ast.Return) and node.value is not None and not (
                isinstance(node.value, ast.Constant) and node.value.value is None):
            value = True
        if isinstance(node, (ast.Yield, ast.YieldFrom)):
            gen = True
        todo.extend(ast.iter_child_nodes(node))
    return value, gen


def _takes_parameters(fn: ast.FunctionDef) -> bool:
    a = fn.args
    names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
    names += [x.arg for x in (a.vararg, a.kwarg) if x is not None]
    return any(n not in ("self", "cls") for n in names)


def _public_names(tree: ast.Module) -> set[str] | None:
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            try:
                return set(ast.literal_eval(node.value))
            except ValueError:
                return None
    return None


def _is_property(fn: ast.FunctionDef) -> bool:
    return any(isinstance(d, ast.Name) and d.id in ("property", "cached_property")
               or isinstance(d, ast.Attribute) and d.attr in ("setter", "getter", "deleter")
               for d in fn.decorator_list)


def public_functions():
    """(module path, qualified name, node) of every public function and method."""
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC).as_posix()
        if any(part.startswith("_") and part != "__init__.py" for part in rel.split("/")):
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        names = _public_names(tree)
        for node in tree.body:
            public = (node.name in names) if names is not None and hasattr(node, "name") \
                else not getattr(node, "name", "_").startswith("_")
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and public:
                yield rel, node.name, node
            elif isinstance(node, ast.ClassDef) and public:
                for item in node.body:
                    if (isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef))
                            and not item.name.startswith("_") and not _is_property(item)):
                        yield rel, f"{node.name}.{item.name}", item


def gaps(fn) -> list[str]:
    """The numpydoc sections ``fn`` lacks."""
    doc = ast.get_docstring(fn) or ""
    out = []
    if _takes_parameters(fn) and not _section(doc, "Parameters"):
        out.append("Parameters")
    value, gen = _returns_value(fn)
    if gen and not _section(doc, "Yields"):
        out.append("Yields")
    elif value and not gen and not _section(doc, "Returns"):
        out.append("Returns")
    return out


def _under(rel: str, p: str) -> bool:
    return rel == p or rel.startswith(p + "/")


def _pending(rel: str) -> bool:
    return any(_under(rel, p) for p in PENDING)


def test_public_functions_document_parameters_and_returns():
    missing = [f"{rel}: {name} lacks {', '.join(g)}"
               for rel, name, fn in public_functions()
               if not _pending(rel) and (g := gaps(fn))]
    assert missing == []


def test_pending_modules_are_still_pending():
    """A module of :data:`PENDING` with no gap left must leave the list."""
    done = {p for p in PENDING
            if not any(_under(rel, p) and gaps(fn)
                       for rel, _, fn in public_functions())}
    assert done == set()


if __name__ == "__main__":  # a count: python tests/test_numpydoc.py
    rows = list(public_functions())
    ok = sum(not gaps(fn) for _, _, fn in rows)
    print(f"{ok} of {len(rows)} public functions and methods document Parameters/Returns")
    for rel, name, fn in rows:
        if gaps(fn):
            print(f"  {rel}: {name}: {', '.join(gaps(fn))}")
