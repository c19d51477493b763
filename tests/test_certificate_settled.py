"""The certificate's Newton steps stop after a settled one (krawczyk.h's KW_SETTLED, certify.py's
SETTLED; issue 33): a candidate as the tracker leaves it (~1e-12 relative from its root) takes one
step, whose quadratic convergence leaves the centre at rounding; a candidate farther off takes both.
Either way the centre must be the root to rounding, checked against roots computed exactly by
SymPy: x^2 + y^2 = 5, x y = q, four real roots for q = 2 and four non-real ones for q = 3
((x + y)^2 = 11, (x - y)^2 = -1)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import sympy

import parakin
from parakin.solvers.certify import SETTLED, certify_roots, certify_roots_compiled

EXPONENTS = np.array([[2, 0], [0, 2], [0, 0], [1, 1], [0, 0]])
EQUATION = np.array([0, 0, 0, 1, 1])


@pytest.fixture(scope="module")
def library() -> Any:
    return parakin.load("planar_3rrr", backend="compiled").backend


def exact_roots(q: int) -> np.ndarray:
    """The four roots of x^2 + y^2 - 5 = 0, x y - q = 0 by SymPy, as complex doubles (P, 2)."""
    x, y = sympy.symbols("x y")
    solutions = sympy.solve([x**2 + y**2 - 5, x * y - q], [x, y], dict=True)
    assert len(solutions) == 4
    return np.array([[complex(sympy.N(s[x], 40)), complex(sympy.N(s[y], 40))] for s in solutions])


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("offset", [1e-12, 1e-7])  # one settled step; two steps (the first above SETTLED)
def test_the_centre_is_the_root_to_rounding_after_the_steps(library: Any, q: int, offset: float) -> None:
    assert (offset < SETTLED) == (offset == 1e-12)  # 1e-12: the first step settles; 1e-7: it does not
    roots = exact_roots(q)
    rng = np.random.default_rng(q)
    noise = rng.standard_normal(roots.shape) + 1j * rng.standard_normal(roots.shape)
    candidates = roots * (1 + offset * noise)
    c = np.array([1.0, 1.0, -5.0, 1.0, -q], dtype=complex)
    for certify in (lambda *a: certify_roots_compiled(library, *a), certify_roots):
        result = certify(c, EXPONENTS, EQUATION, candidates)
        assert result.unique.all() and result.certified_distinct == 4
        assert (result.real == (1 if q == 2 else -1)).all()
        # the centre within a few units of rounding of the exact root (the candidate was offset off)
        error = np.abs(result.center - roots).max(-1) / np.abs(roots).max(-1)
        assert (error <= 8 * 2.0**-52).all(), error
