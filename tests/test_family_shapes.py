"""The numeric family of a polynomial form (``generator/start_systems.Family``) returns a value
vector and Jacobian matrices of the stated shapes whatever the number of unknowns or parameters:
with one unknown (or one parameter) the Jacobian was a vector, which broke every consumer."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import sympy as sp
from parakin.generator.start_systems import Family


def test_one_unknown_one_parameter_gives_matrices_equal_to_the_derivatives_by_hand():
    z, a = sp.symbols("z a")
    form = SimpleNamespace(unknowns=[z], family=[(a, 2.0)], circles=[])
    family = Family(form, [z**3 - a * z + 1])
    points = np.array([[0.5 + 0.1j], [-1.0 + 0.0j], [2.0 - 1.0j]])
    q = np.array([[3.0 + 0.0j]] * 3)
    value, jz, jq = family.value(points, q), family.jacobian(points, q), family.parameter_jacobian(points, q)
    assert value.shape == (3, 1) and jz.shape == (3, 1, 1) and jq.shape == (3, 1, 1)
    zz = points[:, 0]
    assert np.allclose(value[:, 0], zz**3 - 3 * zz + 1)
    assert np.allclose(jz[:, 0, 0], 3 * zz**2 - 3)
    assert np.allclose(jq[:, 0, 0], -zz)


def test_two_unknowns_keep_their_shapes():
    x, y, a = sp.symbols("x y a")
    form = SimpleNamespace(unknowns=[x, y], family=[(a, 1.0)], circles=[])
    family = Family(form, [x**2 + y**2 - a, x - y])
    point, q = np.array([1.0 + 0j, 2.0 + 0j]), np.array([5.0 + 0j])
    assert np.allclose(family.value(point, q), [0.0, -1.0])
    assert np.allclose(family.jacobian(point, q), [[2.0, 4.0], [1.0, -1.0]])
    assert np.allclose(family.parameter_jacobian(point, q), [[-1.0], [0.0]])
