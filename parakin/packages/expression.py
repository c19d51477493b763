"""Arithmetic expressions of a manifest's parameters, read and evaluated without SymPy.

A generated package writes some geometry as expression text (the joint graph's points, axes and
lengths, e.g. ``"-sqrt(3)*r_b/2"``, ``"2*sin(alpha2/2)"``). The runtime never imports SymPy: it
reads such text with Python's own parser and accepts only numbers, names, ``+ - * / **``, unary
minus (and plus), parentheses, the functions ``sin cos tan sqrt Abs`` of one argument and
``Max Min`` of two or more (SymPy's printed clamps), and the constant ``pi``. Anything else (attributes, calls of other names, comparisons, strings, a name
that is not a parameter) is a BrokenPackageError naming the text; nothing is ever passed to
``eval``.
"""

from __future__ import annotations

import ast
import functools
import math
from collections.abc import Callable, Collection, Mapping

from parakin.errors import BadInputError, BrokenPackageError

#: the functions an expression may call, of one argument (SymPy's printed names)
FUNCTIONS: dict[str, Callable[[float], float]] = {
    "sin": math.sin,
    "cos": math.cos,
    "tan": math.tan,
    "sqrt": math.sqrt,
    "Abs": abs,
}
#: the functions of two or more arguments (SymPy prints a clamp such as sqrt(Max(0, x)))
VARIADIC: dict[str, Callable[..., float]] = {"Max": max, "Min": min}
#: the constants an expression may name besides the parameters
CONSTANTS = {"pi": math.pi}
#: the longest expression text read (characters): far above any generated one
MAX_LENGTH = 10_000
_OPERATORS: dict[type, Callable[[float, float], float]] = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.Pow: lambda a, b: a**b,
}


@functools.lru_cache(maxsize=4096)
def _tree(text: str) -> ast.expr:
    """The checked syntax tree of ``text`` (names not yet checked)."""
    if len(text) > MAX_LENGTH:
        raise BrokenPackageError(f"expression of {len(text)} characters (at most {MAX_LENGTH}): {text[:60]!r}...")
    try:
        tree = ast.parse(text, mode="eval").body
    except (SyntaxError, ValueError, RecursionError, MemoryError) as error:
        raise BrokenPackageError(f"expression {text[:80]!r} is not arithmetic: {error}") from None
    for node in ast.walk(tree):
        allowed = isinstance(node, ast.BinOp) and type(node.op) in _OPERATORS
        allowed |= isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd)
        allowed |= isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)
        allowed |= (
            isinstance(node, ast.Constant)
            and isinstance(node.value, int | float)
            and not isinstance(node.value, bool)
            and math.isfinite(node.value)
        )
        allowed |= (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and not node.keywords
            and (
                (node.func.id in FUNCTIONS and len(node.args) == 1)
                or (node.func.id in VARIADIC and len(node.args) >= 2)
            )
            and not any(isinstance(a, ast.Starred) for a in node.args)
        )
        allowed |= isinstance(node, ast.operator | ast.unaryop | ast.expr_context)
        if not allowed:
            raise BrokenPackageError(
                f"expression {text[:80]!r}: {type(node).__name__} is not allowed (numbers, parameter names, "
                f"+ - * / **, unary minus, {', '.join([*FUNCTIONS, *VARIADIC])} and pi only)"
            )
    return tree


def names(text: str) -> set[str]:
    """The parameter names ``text`` uses (functions and constants left out).

    Raises
    ------
    BrokenPackageError
        ``text`` is not an allowed expression (module docstring).

    Example
    -------
    >>> sorted(names("-sqrt(3)*r_b/2 + pi*d"))
    ['d', 'r_b']
    """
    if not isinstance(text, str):
        raise BrokenPackageError(f"an expression is text, got {type(text).__name__}")
    tree = _tree(text)
    called = {id(node.func) for node in ast.walk(tree) if isinstance(node, ast.Call)}
    return {
        node.id
        for node in ast.walk(tree)
        if isinstance(node, ast.Name) and node.id not in CONSTANTS and id(node) not in called
    }


def check(text: object, known: Collection[str], where: str) -> str:
    """``text`` if it is an allowed expression of the names ``known`` (and pi).

    Parameters
    ----------
    text : object
        What the manifest holds.
    known : collection of str
        The names it may use (the manifest's parameters).
    where : str
        The field's path, for the message.

    Returns
    -------
    str
        ``text``.

    Raises
    ------
    BrokenPackageError
        Not a string, not an allowed expression, or a name that is not in ``known``.
    """
    if not isinstance(text, str):
        raise BrokenPackageError(f"field {where}: {text!r:.80} is not an expression (text)")
    try:
        used = names(text)
    except BrokenPackageError as error:
        raise BrokenPackageError(f"field {where}: {error}") from None
    unknown = sorted(used - set(known))
    if unknown:
        raise BrokenPackageError(f"field {where}: expression {text[:80]!r} names {unknown}, not parameters")
    return text


def evaluate(text: str, values: Mapping[str, float]) -> float:
    """The value of the expression ``text`` at the parameter ``values``.

    Parameters
    ----------
    text : str
        An allowed expression (module docstring).
    values : mapping of str to float
        Every name it uses (SI units).

    Returns
    -------
    float

    Raises
    ------
    BrokenPackageError
        ``text`` is not an allowed expression or names a value not given.
    BadInputError
        The value is undefined or not finite at these values (a division by zero, the square
        root of a negative number, an overflow).

    Example
    -------
    >>> evaluate("-sqrt(3)*r_b/2", {"r_b": 2.0})
    -1.7320508075688772
    """

    def value(node: ast.expr) -> float:
        if isinstance(node, ast.Constant):
            assert isinstance(node.value, int | float)  # checked by _tree
            return float(node.value)
        if isinstance(node, ast.Name):
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            if node.id not in values:
                raise BrokenPackageError(f"expression {text[:80]!r} names {node.id!r}, which has no value")
            return float(values[node.id])
        if isinstance(node, ast.UnaryOp):
            inner = value(node.operand)
            return -inner if isinstance(node.op, ast.USub) else inner
        if isinstance(node, ast.BinOp):
            return _OPERATORS[type(node.op)](value(node.left), value(node.right))
        assert isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
        if node.func.id in VARIADIC:
            return VARIADIC[node.func.id](*(value(a) for a in node.args))
        return FUNCTIONS[node.func.id](value(node.args[0]))

    tree = _tree(text)  # BrokenPackageError (a ValueError) before any arithmetic
    try:
        result = value(tree)
    except BrokenPackageError:
        raise
    except (ZeroDivisionError, OverflowError, ValueError) as error:
        raise BadInputError(f"expression {text[:80]!r} is undefined at these parameters ({error})") from None
    if isinstance(result, complex) or not math.isfinite(result):
        raise BadInputError(f"expression {text[:80]!r} is not a finite real number at these parameters ({result})")
    return float(result)


__all__ = ["CONSTANTS", "FUNCTIONS", "VARIADIC", "check", "evaluate", "names"]
