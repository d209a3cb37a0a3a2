"""YAML documents of bounded size: an alias bomb is refused before any object is built.

YAML aliases share nodes, so a few hundred bytes (``a1: [*a0, *a0, ...]`` over 8 levels) stand
for 10^8 values: reading them is fast, but every later walk over the object (validation,
hashing, printing) expands them and runs for minutes. :func:`load_bounded` composes the node
graph, counts the nodes the document *expands* to without expanding it (each shared node
counted once per use, memoised), and refuses more than :data:`MAX_EXPANDED_NODES`; a file over
:data:`MAX_DOCUMENT_BYTES` is refused before parsing.
"""

from __future__ import annotations

import os

import yaml

__all__ = ["MAX_EXPANDED_NODES", "MAX_DOCUMENT_BYTES", "MAX_NESTING", "YamlLimitError", "expanded_size",
           "load_bounded", "check_document_size"]

#: Nodes a config may expand to (scalars, lists, mappings, each alias use counted in full):
#: the default config has about 700, a large hand-written sweep a few thousand.
MAX_EXPANDED_NODES = 100_000

#: Largest config file read, bytes (the default config is 12 kB).
MAX_DOCUMENT_BYTES = 1 << 20

#: Deepest nesting of lists and mappings accepted (the schema's deepest field is 6 levels
#: down; a 20,000-deep list would exhaust Python's recursion in the parser).
MAX_NESTING = 32


class YamlLimitError(ValueError):
    """The document is larger than the limits of this module (message: one line)."""


def expanded_size(node: yaml.Node, limit: int = MAX_EXPANDED_NODES) -> int:
    """Number of nodes ``node`` expands to (aliases counted in full), stopping past ``limit``.

    Parameters
    ----------
    node : yaml.Node
        The composed document (or part of it).
    limit : int
        Stop counting past this many nodes.

    Returns
    -------
    int
        Nodes counted (more than ``limit`` means: too many).
    """
    memo: dict[int, int] = {}

    def size(n: yaml.Node, depth: int) -> int:
        if depth > MAX_NESTING:
            raise YamlLimitError(f"lists or mappings nested more than {MAX_NESTING} deep "
                                 f"(line {n.start_mark.line + 1}); allowed: at most "
                                 f"{MAX_NESTING} levels")
        key = id(n)
        if key in memo:
            return memo[key]
        memo[key] = limit + 1  # a cycle (recursive alias) counts as too large
        if isinstance(n, yaml.SequenceNode):
            total = 1 + sum(size(c, depth + 1) for c in n.value)
        elif isinstance(n, yaml.MappingNode):
            total = 1 + sum(size(k, depth + 1) + size(v, depth + 1) for k, v in n.value)
        else:
            total = 1
        memo[key] = min(total, limit + 1)
        return memo[key]

    return size(node, 0)


def check_document_size(path: str | os.PathLike) -> None:
    """Refuse a file larger than :data:`MAX_DOCUMENT_BYTES` (before reading it).

    Parameters
    ----------
    path : str or os.PathLike
        The YAML file.

    Raises
    ------
    YamlLimitError
        A document larger than :data:`MAX_DOCUMENT_BYTES`.
    """
    n = os.path.getsize(path)
    if n > MAX_DOCUMENT_BYTES:
        raise YamlLimitError(f"{n:,} bytes; allowed: a config of at most "
                             f"{MAX_DOCUMENT_BYTES:,} bytes")


def load_bounded(stream, loader_cls, limit: int = MAX_EXPANDED_NODES):
    """``yaml.load(stream, loader_cls)`` after checking the expanded size of the document.

    Parameters
    ----------
    stream : str or file
        The YAML text or an open file.
    loader_cls : type
        A PyYAML loader class (e.g. ``yaml.SafeLoader``).
    limit : int
        Most nodes the document may expand to.

    Returns
    -------
    object
        The loaded document.

    Raises
    ------
    YamlLimitError
        The document expands to more than ``limit`` nodes (an alias bomb or a recursive alias)
        or nests lists and mappings more than :data:`MAX_NESTING` deep.
    """
    loader = loader_cls(stream)
    try:
        try:
            node = loader.get_single_node()
        except RecursionError:  # the composer recurses once per level of nesting
            raise YamlLimitError(f"lists or mappings nested too deep for the parser; allowed: "
                                 f"at most {MAX_NESTING} levels") from None
        if node is None:
            return None
        n = expanded_size(node, limit)
        if n > limit:
            raise YamlLimitError(f"the document expands to more than {limit:,} values through "
                                 f"YAML aliases (&anchor/*alias); allowed: at most {limit:,}")
        return loader.construct_document(node)
    finally:
        loader.dispose()
