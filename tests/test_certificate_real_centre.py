"""The C certificate's real centre (generator/runtime/krawczyk.h, ``kw_real_centre``; issue 33)
against roots computed exactly by SymPy.

For a system of real coefficients, a box B(x, r) about a REAL centre x is its own conjugate; where
Krawczyk's test passes on it, it holds exactly one root, and that root's conjugate (a root too) lies
in it, so the root is real: one test decides uniqueness and realness at once. A candidate within
the test's reach of the real space is tested there first. The argument must never call a root of
a conjugate pair near the real space real: a box about a real point holds both roots of the pair
or neither, never exactly one. The systems here are x^2 + y^2 = 5, x y = q: (x + y)^2 = 5 + 2 q
and (x - y)^2 = 5 - 2 q, four real roots for q = 2 and two conjugate pairs 2^-20.5 (~7e-7) from
the real space for q = 5/2 + 2^-40 (every coefficient exact in double)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import sympy

import parakin
from parakin.solvers.certify import certify_roots_compiled

EXPONENTS = np.array([[2, 0], [0, 2], [0, 0], [1, 1], [0, 0]])
EQUATION = np.array([0, 0, 0, 1, 1])


@pytest.fixture(scope="module")
def library() -> Any:
    return parakin.load("planar_3rrr", backend="compiled").backend


def exact_roots(q: sympy.Rational) -> np.ndarray:
    """The four roots of x^2 + y^2 - 5 = 0, x y - q = 0 by SymPy, as complex doubles (P, 2)."""
    x, y = sympy.symbols("x y")
    solutions = sympy.solve([x**2 + y**2 - 5, x * y - q], [x, y], dict=True)
    assert len(solutions) == 4
    return np.array([[complex(sympy.N(s[x], 40)), complex(sympy.N(s[y], 40))] for s in solutions])


def coefficients(q: float) -> np.ndarray:
    return np.array([1.0, 1.0, -5.0, 1.0, -q], dtype=complex)


def contains(centre: np.ndarray, radii: np.ndarray, root: np.ndarray) -> bool:
    """The polydisc holds the root (the root's double within 2^-52 of the exact one)."""
    return bool((np.abs(centre - root) <= radii + 4 * 2.0**-52 * np.abs(root)).all())


def test_real_roots_are_certified_real_at_a_real_centre(library: Any) -> None:
    roots = exact_roots(sympy.Integer(2))
    assert np.allclose(roots.imag, 0.0)  # (1, 2), (2, 1) and their negatives
    rng = np.random.default_rng(3)
    # candidates as a tracker leaves them: 1e-9 off, with imaginary parts 1e-9 (within reach)
    candidates = roots.real + 1e-9 * (rng.standard_normal(roots.shape) + 1j * rng.standard_normal(roots.shape))
    result = certify_roots_compiled(library, coefficients(2.0), EXPONENTS, EQUATION, candidates)
    assert result.unique.all() and (result.real == 1).all() and result.certified_distinct == 4
    assert (result.center.imag == 0.0).all()  # the real centre: one test decided both
    for p in range(4):
        assert contains(result.center[p], result.radii[p], roots[p])
        assert (result.radii[p] < 1e-12).all()


def test_a_conjugate_pair_near_the_real_space_is_not_called_real(library: Any) -> None:
    q = sympy.Rational(5, 2) + sympy.Rational(1, 2**40)
    roots = exact_roots(q)
    assert np.allclose(np.abs(roots.imag), 2.0**-20.5)  # within the reach (1e-6 of the size)
    candidates = roots + 1e-12
    result = certify_roots_compiled(library, coefficients(float(q)), EXPONENTS, EQUATION, candidates)
    # each root of the pair in a box of its own, which misses the real space; its conjugate's box
    # is the conjugate
    assert result.unique.all() and (result.real == -1).all() and result.certified_distinct == 4
    for p in range(4):
        assert contains(result.center[p], result.radii[p], roots[p])
        assert (result.radii[p] < np.abs(roots[p].imag)).all()
    # a candidate projected on the real space between the pair: never certified real
    between = np.vstack([roots.real, roots.real + 1e-9])
    result = certify_roots_compiled(library, coefficients(float(q)), EXPONENTS, EQUATION, between)
    assert (result.real != 1).all()
    # the pair is real for q = 5/2 - 2^-40, 2^-19.5 apart on the real space: the same
    # candidates' real boxes each hold one of them
    below = sympy.Rational(5, 2) - sympy.Rational(1, 2**40)
    real_roots = exact_roots(below)
    assert np.allclose(real_roots.imag, 0.0)
    result = certify_roots_compiled(library, coefficients(float(below)), EXPONENTS, EQUATION, real_roots.real + 1e-13)
    assert result.unique.all() and (result.real == 1).all() and result.certified_distinct == 4
    for p in range(4):
        assert contains(result.center[p], result.radii[p], real_roots[p].real)


def test_a_candidate_beyond_the_reach_takes_the_complex_sequence(library: Any) -> None:
    """Imaginary parts 1e-3 (far beyond KW_NEAR of the size): not projected; the complex
    sequence (the double-word attempt's Newton steps, then the second test at Re x) still
    certifies the real roots real, at centres that keep an imaginary part."""
    roots = exact_roots(sympy.Integer(2))
    candidates = roots.real + 1e-3j
    result = certify_roots_compiled(library, coefficients(2.0), EXPONENTS, EQUATION, candidates)
    assert result.unique.all() and (result.real == 1).all() and result.certified_distinct == 4
    assert (result.center.imag != 0.0).any()
    for p in range(4):
        assert contains(result.center[p], result.radii[p], roots[p].real)


#: x^2 + e x y + f y^2 = 0 in the projective group (x, y), patched by (1 + i) x + (2 - i) y = 1
HOMOGENEOUS_EXPONENTS = np.array([[2, 0], [1, 1], [0, 2], [1, 0], [0, 1], [0, 0]])
HOMOGENEOUS_EQUATION = np.array([0, 0, 0, 1, 1, 1])


def patched_roots(e: sympy.Rational, f: sympy.Rational) -> tuple[np.ndarray, list[bool]]:
    """The two roots in the patch by SymPy (P, 2) and whether each is a real projective point."""
    t = sympy.symbols("t")
    points, real = [], []
    for ratio in sympy.solve(t**2 + e * t + f, t):  # x = ratio y
        y = 1 / ((1 + sympy.I) * ratio + 2 - sympy.I)
        points.append([complex(sympy.N(ratio * y, 40)), complex(sympy.N(y, 40))])
        real.append(bool(sympy.im(ratio) == 0))
    return np.array(points), real


@pytest.mark.parametrize(
    "e, f, real",
    [
        (sympy.Integer(0), sympy.Integer(-4), 1),  # (2 : 1), (-2 : 1)
        (sympy.Integer(-2), 1 - sympy.Rational(1, 2**42), 1),  # (1 +- 2^-21 : 1): real, close
        (sympy.Integer(-2), 1 + sympy.Rational(1, 2**42), -1),  # (1 +- i 2^-21 : 1): a conjugate pair
    ],
)
def test_homogeneous_realness_by_the_patched_system_s_mirror(library: Any, e: Any, f: Any, real: int) -> None:
    """Real projective points certified real, a conjugate pair of points 2^-21 from the real ones
    never real (each in a box of its own, non-real), against SymPy's roots."""
    roots, exact_real = patched_roots(e, f)
    assert exact_real == [real == 1] * 2
    c = np.array([1.0, float(e), float(f), 1 + 1j, 2 - 1j, -1.0])
    result = certify_roots_compiled(
        library, c, HOMOGENEOUS_EXPONENTS, HOMOGENEOUS_EQUATION, roots * (1 + 1e-13), homogeneous=[0, 1],
        patch_equation=1,
    )  # fmt: skip
    assert result.unique.all() and (result.real == real).all() and result.certified_distinct == 2
    for p in range(2):
        assert contains(result.center[p], result.radii[p], roots[p])
