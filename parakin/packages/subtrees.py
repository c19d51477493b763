"""The shared-subtree form of large expressions: one piece of code for the generator (which
stores ``symbolic.py`` in this form) and for ``parakin inspect`` (which prints it). Part of every
generated package's digest, so a change here regenerates them all."""

from __future__ import annotations

from typing import Any


def shared_subtrees(sympy: Any, expressions: list[Any]) -> tuple[list[tuple[Any, Any]], list[Any]]:
    """Every subtree that repeats, named once (``shared_k``, or a longer prefix where the
    expressions already use that name), and the expressions written with those names: a tree
    CSE that only names identical subtrees, so substituting back in order rebuilds them exactly.
    ``parakin inspect`` prints this form of a large expression; the generator stores it
    (``symbolic.py``)."""
    from sympy.simplify.cse_main import tree_cse

    taken = {str(symbol) for expression in expressions for symbol in getattr(expression, "free_symbols", ())}
    prefix = next(p for p in ("shared_", "shared__", "shared___") if not any(t.startswith(p) for t in taken))
    return tree_cse(expressions, sympy.numbered_symbols(prefix), opt_subs={}, order="none")


__all__ = ["shared_subtrees"]
