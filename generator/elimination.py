"""Elimination over generic coefficient symbols.

Eliminating a variable from two polynomials whose coefficients are expanded trigonometric
expressions is slow and produces huge results. Instead the resultant is formed once over plain
symbols (the coefficients of a generic polynomial system) and the mechanism supplies those
coefficients as separate assignments; the generated code evaluates the coefficients first, then
the small generic resultant.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class BiquadraticResultant:
    """Two equations E_m(x, y) = sum_{k,j} c_m[k, j] x^j y^k, each quadratic in x and in y.

    ``first[k][j]`` and ``second[k][j]`` are the generic symbols (coefficient of y^k x^j);
    ``coefficients`` are those of Res_y(E_1, E_2)(x), ascending in x (degree 8); ``kernel``
    gives y at a simple root from the 2x2 Bezout matrix, ``y_numerator / y_denominator``.
    """

    x: sp.Symbol
    first: list[list[sp.Symbol]]
    second: list[list[sp.Symbol]]
    coefficients: list[sp.Expr]
    y_numerator: sp.Expr
    y_denominator: sp.Expr


def biquadratic_resultant(x: sp.Symbol, prefix: tuple[str, str] = ("a", "b")) -> BiquadraticResultant:
    """Res_y of two generic biquadratics by the Bezout (Cayley) formula:
    (A2 B0 - A0 B2)^2 - (A2 B1 - A1 B2)(A1 B0 - A0 B1) with A_k = sum_j a_kj x^j."""
    first = [[sp.Symbol(f"{prefix[0]}{k}{j}", real=True) for j in range(3)] for k in range(3)]
    second = [[sp.Symbol(f"{prefix[1]}{k}{j}", real=True) for j in range(3)] for k in range(3)]
    big_a = [sum(first[k][j] * x**j for j in range(3)) for k in range(3)]
    big_b = [sum(second[k][j] * x**j for j in range(3)) for k in range(3)]
    outer = big_a[2] * big_b[0] - big_a[0] * big_b[2]
    middle = big_a[2] * big_b[1] - big_a[1] * big_b[2]
    inner = big_a[1] * big_b[0] - big_a[0] * big_b[1]
    resultant = sp.Poly(sp.expand(outer**2 - middle * inner), x)
    coefficients = [resultant.coeff_monomial(x**d) for d in range(resultant.degree() + 1)]
    return BiquadraticResultant(x, first, second, coefficients, -outer, middle)


def coefficient_grid(expr: sp.Expr, x: sp.Symbol, y: sp.Symbol) -> list[list[sp.Expr]]:
    """c[k][j] = coefficient of y^k x^j of a polynomial of degree <= 2 in each of x and y."""
    polynomial = sp.Poly(sp.expand(expr), x, y)
    return [[polynomial.coeff_monomial(x**j * y**k) for j in range(3)] for k in range(3)]


#: (1 + x^2) (1, cos phi, sin phi) = (1 + x^2, 1 - x^2, 2 x) = HALF_ANGLE^T (1, x, x^2), x = tan(phi/2)
HALF_ANGLE = sp.Matrix([[1, 1, 0], [0, 0, 2], [1, -1, 0]])


def half_angle_grid(bilinear: sp.Matrix) -> sp.Matrix:
    """A bilinear form f(phi1)^T M f(phi2) in f = (1, cos, sin), times (1 + x^2)(1 + y^2), as the
    coefficient grid [p, q] of x^p y^q with x, y the half-angle tangents of phi1, phi2."""
    return HALF_ANGLE * bilinear * HALF_ANGLE.T
