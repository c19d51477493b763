"""The NumPy reference certificate (``parakin.solvers.certify.certify_roots``) decides realness as
the C one does (issue 33): from the one test's own bounds (a real centre; the complex centre's box
widened to hold the conjugate; a homogeneous system's mirror), against SymPy's exact roots of the
systems of tests/test_certificate_real_centre.py (x^2 + y^2 = 5, x y = q; a patched projective
pair). A passing box holds exactly one root, so where it also holds that root's conjugate the root
is real; a box never holds exactly one root of a conjugate pair and the pair's other root. The
second tests (at Re x, in the real chart) are made to fail here wherever they are asked: the
decisions below are the one test's."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import sympy
from test_certificate_real_centre import (
    EQUATION,
    EXPONENTS,
    HOMOGENEOUS_EQUATION,
    HOMOGENEOUS_EXPONENTS,
    coefficients,
    contains,
    exact_roots,
    patched_roots,
)

import parakin.solvers.certify as certify


@pytest.fixture
def one_test(monkeypatch: pytest.MonkeyPatch) -> None:
    """No second test: ``_contains_where`` asked for any candidate fails the test."""

    def refuse(*args: Any) -> np.ndarray:
        mask = args[-1]
        assert not mask.any(), "a second realness test was needed"
        return np.zeros(mask.shape, bool)

    monkeypatch.setattr(certify, "_contains_where", refuse)


def test_real_roots_are_certified_real_at_a_real_centre(one_test: None) -> None:
    roots = exact_roots(sympy.Integer(2))
    assert np.allclose(roots.imag, 0.0)  # (1, 2), (2, 1) and their negatives
    rng = np.random.default_rng(3)
    candidates = roots.real + 1e-9 * (rng.standard_normal(roots.shape) + 1j * rng.standard_normal(roots.shape))
    result = certify.certify_roots(coefficients(2.0), EXPONENTS, EQUATION, candidates)
    assert result.unique.all() and (result.real == 1).all() and result.certified_distinct == 4
    assert (result.center.imag == 0.0).all()  # the real centre: one test decided both
    for p in range(4):
        assert contains(result.center[p], result.radii[p], roots[p])


def test_a_conjugate_pair_near_the_real_space_is_never_real() -> None:
    q = sympy.Rational(5, 2) + sympy.Rational(1, 2**40)
    roots = exact_roots(q)
    assert np.allclose(np.abs(roots.imag), 2.0**-20.5)  # within the reach (1e-6 of the size)
    result = certify.certify_roots(coefficients(float(q)), EXPONENTS, EQUATION, roots + 1e-12)
    assert result.unique.all() and (result.real == -1).all() and result.certified_distinct == 4
    for p in range(4):
        assert contains(result.center[p], result.radii[p], roots[p])
    # projected on the real space between the pair: never certified real
    between = np.vstack([roots.real, roots.real + 1e-9])
    assert (certify.certify_roots(coefficients(float(q)), EXPONENTS, EQUATION, between).real != 1).all()


@pytest.mark.parametrize(
    "q, real", [(sympy.Integer(2), True), (sympy.Rational(5, 2) + sympy.Rational(1, 2**40), False)]
)
def test_the_complex_centre_s_widened_box(q: Any, real: bool) -> None:
    """The complex sequence alone (no real centre): the bounds at x pass on B(x, r + 2 max |Im x|)
    for the real roots (candidates 1e-8 off the real space: Newton leaves ~1e-16 imaginary
    parts), never for a root of the close conjugate pair (that box would hold both)."""
    roots = exact_roots(q)
    assert np.allclose(roots.imag, 0.0) == real
    candidates = (roots + 1e-8j * real + 1e-12)[:, None, :]
    size = np.abs(candidates).max(-1)
    mask = np.ones(size.shape, bool)
    unique, radius, x, _, wide = certify._attempt(
        coefficients(float(q)), EXPONENTS, EQUATION, candidates, 1e-6 * size, mask, False, None
    )  # fmt: skip
    assert unique.all() and (wide == real).all()
    for p in range(4):
        assert contains(x[p, 0], radius[p, 0], roots[p])


@pytest.mark.parametrize(
    "e, f, real",
    [
        (sympy.Integer(0), sympy.Integer(-4), 1),  # (2 : 1), (-2 : 1)
        (sympy.Integer(-2), 1 - sympy.Rational(1, 2**24), 1),  # (1 +- 2^-12 : 1): real, close
        (sympy.Integer(-2), 1 + sympy.Rational(1, 2**24), -1),  # (1 +- i 2^-12 : 1): a conjugate pair
    ],
)
def test_homogeneous_realness_by_the_patched_system_s_mirror(one_test: None, e: Any, f: Any, real: int) -> None:
    roots, exact_real = patched_roots(e, f)
    assert exact_real == [real == 1] * 2
    c = np.array([1.0, float(e), float(f), 1 + 1j, 2 - 1j, -1.0])
    result = certify.certify_roots(
        c, HOMOGENEOUS_EXPONENTS, HOMOGENEOUS_EQUATION, roots * (1 + 1e-13), homogeneous=[0, 1], patch_equation=1
    )
    assert result.unique.all() and (result.real == real).all() and result.certified_distinct == 2
    for p in range(2):
        assert contains(result.center[p], result.radii[p], roots[p])


def test_the_mirror_radius_holds_the_conjugate_pair_s_other_root() -> None:
    """The patched mirror maps a root of the pair (1 +- i 2^-12 : 1) to the other (SymPy's): the
    mirror's radius about each holds the other, so no box of that radius passes (two roots)."""
    roots, _ = patched_roots(sympy.Integer(-2), 1 + sympy.Rational(1, 2**24))
    c = np.array([1.0, -2.0, float(1 + sympy.Rational(1, 2**24)), 1 + 1j, 2 - 1j, -1.0])
    x, r = roots[:, None, :], np.full((2, 1), 1e-12)
    patch = HOMOGENEOUS_EQUATION == 1
    wide = certify._mirror_radius(np.tile(c, (2, 1)), HOMOGENEOUS_EXPONENTS, x, r, (1, np.ones(2, bool), patch), 1e-13)
    gap = np.abs(roots[::-1] - roots).max(-1)  # each root's distance to the other
    assert (wide[:, 0] >= gap).all() and (wide[:, 0] <= 2 * gap).all()


def test_an_overflowing_mirror_bound_proves_nothing() -> None:
    """z0 - z1 = 0 with the patch z0 = 1e300, at a centre whose first coordinate is visibly
    non-real: the group's bound |c0 x_i| ~ 1e600 overflows to inf - inf (NaN); the mirror must
    give no radius (0), where dropping the NaN gave r and called the root real without proof."""
    c = np.array([[1.0, -1.0, 1.0, -1e300]], complex)
    exponents, equation = np.array([[1, 0], [0, 1], [1, 0], [0, 0]]), np.array([0, 0, 1, 1])
    x, r = np.array([[[1e300 + 1e-3j, 1e300]]]), np.array([[1e285]])
    wide = certify._mirror_radius(c, exponents, x, r, (1, np.ones(2, bool), equation == 1), 1e-13)
    assert wide.shape == (1, 1) and wide[0, 0] == 0.0
