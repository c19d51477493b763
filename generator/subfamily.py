"""The relations a mechanism imposes on its polynomial family's values, and the subfamily they cut
out: where the root count is proven when the generic member's count is not the mechanism's.

The family F(z; q) of a polynomial form (``generator/polynomial_form.py``) has one value q_i per
free parameter (an actuated variable, a parameter, a derived expression) and per circle parameter u
of an angle (``generator/start_systems.py``'s ``Family``). Its generic count (at a random complex q)
bounds every member's; a mechanism whose own values always satisfy some relations lives on a
subfamily whose generic count can be smaller, the rest of the generic roots at infinity for every
input. A user's Hexaglide with two sliders on each of three shared rails (six rail parameters,
pairwise equal) keeps 72 of the family's 80 roots: no input could be certified complete against 80.

Relations found, all linear (so a straight segment between two members of the subfamily stays in
it: the runtime's homotopy from a start instance drawn there to any input of the mechanism):
* a constant value: an angle that is a number (u constant), a free expression with no symbols;
* identical values: values that depend on the parameters only and are equal at the mechanism's
  parameter values (relative ``COINCIDENT``): parameters sharing a value (the shared rails).
Inputs never enter a relation: the actuated variables stay generic. A relation between parameter
values holds for the mechanism as generated; parameters loaded with other values break it, and
the count proven on the subfamily does not hold for them (``holds`` says so; the manifest's
``subfamily`` names the relations for the runtime to check). So where the family is small
(``start_systems.GENERIC_MAX_PATHS``) the count for any parameter values is proven first and kept
where the subfamily loses none of it (``constants_only``: the relations no parameter changes).

The subfamily is q = lift(t): one coordinate t_j per group of identical values (and per value in
no relation), constants fixed.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mpmath
import numpy as np
import sympy as sp

#: two values depending on the parameters only are identical where they agree to this, relative
COINCIDENT = 1e-12


@dataclass(frozen=True)
class Relations:
    """The subfamily of a family with ``len(coordinate)`` values: value i is coordinate
    ``coordinate[i]`` of t, or the constant ``constant[i]`` where that is -1; ``names`` the values'
    symbols (for messages and the manifest)."""

    coordinate: tuple[int, ...]
    constant: tuple[complex, ...]
    names: tuple[str, ...]

    @property
    def size(self) -> int:
        """The subfamily's dimension (coordinates of t)."""
        return max(self.coordinate, default=-1) + 1

    @property
    def groups(self) -> list[list[int]]:
        """The values that are identical, as lists of indices (two or more each)."""
        members: dict[int, list[int]] = {}
        for index, c in enumerate(self.coordinate):
            if c >= 0:
                members.setdefault(c, []).append(index)
        return [group for group in members.values() if len(group) > 1]

    @property
    def constants(self) -> list[int]:
        """The indices of the constant values."""
        return [index for index, c in enumerate(self.coordinate) if c < 0]

    def matrix(self) -> np.ndarray:
        """d q / d t, (values, size): one 1 per row of a coordinate, none for a constant."""
        out = np.zeros((len(self.coordinate), self.size))
        for index, c in enumerate(self.coordinate):
            if c >= 0:
                out[index, c] = 1.0
        return out

    def full(self, t: np.ndarray) -> np.ndarray:
        """The family's values (..., values) of subfamily coordinates t (..., size)."""
        t = np.asarray(t, dtype=complex)
        index = np.array([max(c, 0) for c in self.coordinate], dtype=np.intp)
        picked = t[..., index] if self.size else np.zeros(t.shape[:-1] + (len(index),), complex)
        return np.where(np.array(self.coordinate) >= 0, picked, np.array(self.constant, dtype=complex))

    def full_mp(self, t: Sequence) -> list:
        """``full`` in mpmath: the constants as the doubles the start instances store."""
        return [
            t[c] if c >= 0 else mpmath.mpc(complex(value))
            for c, value in zip(self.coordinate, self.constant, strict=True)
        ]

    def coordinates(self, q: np.ndarray) -> np.ndarray:
        """t of family values q (..., values) on the subfamily: each coordinate's first value."""
        first = [self.coordinate.index(c) for c in range(self.size)]
        return np.asarray(q, dtype=complex)[..., first]

    def holds(self, q: np.ndarray, tolerance: float = COINCIDENT) -> bool:
        """Whether the family values q (values,) satisfy the relations (relative ``tolerance``)."""
        q = np.asarray(q, dtype=complex)
        if q.shape != (len(self.coordinate),) or not np.isfinite(q).all():
            return False
        back = self.full(self.coordinates(q))
        return bool(np.all(np.abs(q - back) <= tolerance * np.maximum(np.abs(q), np.abs(back))))

    def constants_only(self) -> Relations | None:
        """The relations without the identical values: the constants only (values no parameter
        can change), every other value a coordinate of its own; None when there is no constant."""
        if not self.constants:
            return None
        coordinate: list[int] = []
        for c in self.coordinate:
            coordinate.append(-1 if c < 0 else max(coordinate, default=-1) + 1)
        return Relations(tuple(coordinate), self.constant, self.names)

    def key(self) -> str:
        """The relations as text: part of a subfamily record's cache key."""
        constants = [(i, repr(complex(self.constant[i]))) for i in self.constants]
        return repr((self.groups, constants))

    def describe(self) -> str:
        """The relations in words, by the values' names."""
        parts = [" = ".join(self.names[i] for i in group) for group in self.groups]
        if self.constants:  # numbers of the design (fixed angles): no parameter changes them
            parts.append(f"{', '.join(self.names[i] for i in self.constants)} fixed by the design")
        return "; ".join(parts)

    def manifest(self) -> dict[str, object]:
        """The manifest's ``subfamily``: indices into the start instance (free values, then circles)."""
        return {
            "identical": self.groups,
            "constant": self.constants,
            "relations": self.describe(),
            "tolerance": COINCIDENT,
        }


def _number(expression: sp.Expr) -> complex | None:
    try:
        value = complex(sp.N(expression, 30))
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    return value if np.isfinite(value) else None


def family_relations(
    values: Sequence[sp.Symbol],
    expressions: Mapping[sp.Symbol, sp.Expr],
    circles: Mapping[sp.Symbol, sp.Expr],
    parameter_values: Mapping[sp.Symbol, float] | None = None,
) -> Relations | None:
    """The relations the mechanism imposes on the family's ``values`` (module docstring): each is a
    free value with its expression in ``expressions`` or a circle parameter u of the angle in
    ``circles`` (its value ``circle_parameter(angle)``); ``parameter_values`` the mechanism's
    parameters (None: constants only). None when there is no relation."""
    from .polynomial_form import circle_parameter

    known = {sp.sympify(k): v for k, v in (parameter_values or {}).items()}
    coordinate: list[int] = []
    constant: list[complex] = []
    seen: list[tuple[complex, int]] = []
    for symbol in values:
        expression = sp.sympify(circles[symbol] if symbol in circles else expressions[symbol])
        symbols = expression.free_symbols
        value = None
        if not symbols or (known and symbols <= set(known)):
            at = expression.xreplace({k: sp.Float(v, 30) for k, v in known.items()})
            value = _number(circle_parameter(at) if symbol in circles else at)
        if value is not None and not symbols:
            coordinate.append(-1)
            constant.append(value)
            continue
        if value is not None:
            match = next((c for v, c in seen if abs(v - value) <= COINCIDENT * max(abs(v), abs(value))), None)
            if match is not None:
                coordinate.append(match)
                constant.append(0j)
                continue
        index = max(coordinate, default=-1) + 1
        if value is not None:
            seen.append((value, index))
        coordinate.append(index)
        constant.append(0j)
    if all(c >= 0 for c in coordinate) and len(set(coordinate)) == len(coordinate):
        return None
    return Relations(tuple(coordinate), tuple(constant), tuple(str(v) for v in values))
