"""parakin.solvers.exact_certify: Krawczyk certificates in exact dyadic arithmetic, against systems with
known roots that double precision cannot separate (two roots 2^-25 apart) and against spoiled
candidates, which it must refuse."""

from __future__ import annotations

import numpy as np

from parakin.solvers.certify import certify_roots, distinct_clusters
from parakin.solvers.exact_certify import certify_root_exactly

D = 2.0**-26
# x^2 - 2 x + 1 - D^2 = 0 (roots 1 +- D, exactly; 1 - D^2 = 1 - 2^-52 is a double), y - x = 0
EXPONENTS = np.array([[2, 0], [1, 0], [0, 0], [0, 1], [1, 0]])
EQUATION = np.array([0, 0, 0, 1, 1])
COEFFICIENTS = np.array([1, -2, 1 - D * D, 1, -1], dtype=complex)
ROOTS = np.array([[1 + D, 1 + D], [1 - D, 1 - D]], dtype=complex)


def test_double_precision_cannot_separate_the_close_roots():
    cert = certify_roots(COEFFICIENTS, EXPONENTS, EQUATION, ROOTS)
    assert cert.certified_distinct < 2


def test_exact_arithmetic_certifies_each_close_root_in_its_own_box():
    boxes = [certify_root_exactly(COEFFICIENTS, EXPONENTS, EQUATION, root, True) for root in ROOTS]
    assert all(box.unique for box in boxes)
    assert all(box.radius < D / 4 for box in boxes)
    # each box holds its own exact root and not the other
    for box, root, other in zip(boxes, ROOTS, ROOTS[::-1], strict=True):
        assert np.abs(box.center - root).max() <= box.radius
        assert np.abs(box.center - other).max() > box.radius
    assert all(box.real == 1 for box in boxes)
    centres = np.array([box.center for box in boxes])
    radii = np.array([[box.radius] * 2 for box in boxes])
    distinct, count = distinct_clusters(centres, radii, np.ones(2, bool))
    assert distinct and count == 2


def test_a_candidate_near_the_roots_is_refined_to_one_of_them():
    box = certify_root_exactly(COEFFICIENTS, EXPONENTS, EQUATION, ROOTS[0] + 1e-14, True)
    assert box.unique and np.abs(box.center - ROOTS[0]).max() <= box.radius


def test_complex_roots_are_certified_non_real_and_a_spoiled_candidate_is_refused():
    # x^2 + 1 = 0, y - 2 x = 0: roots (+-i, +-2i)
    exponents = np.array([[2, 0], [0, 0], [0, 1], [1, 0]])
    equation = np.array([0, 0, 1, 1])
    coefficients = np.array([1, 1, 1, -2], dtype=complex)
    box = certify_root_exactly(coefficients, exponents, equation, np.array([1j, 2j]) * (1 + 1e-12), True)
    assert box.unique and box.real == -1 and np.abs(box.center - [1j, 2j]).max() <= box.radius
    # a point far from both roots: Newton may wander, but no box around the given point's limit
    # may claim a root that is not one: the certified centre, if any, is a root
    far = certify_root_exactly(coefficients, exponents, equation, np.array([0.0, 0.0]), True)
    assert not far.unique or min(np.abs(far.center - r).max() for r in ([1j, 2j], [-1j, -2j])) <= far.radius
