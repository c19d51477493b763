"""Accelerator of ``five_bar.py`` (optional): the five-bar's forward pose as the intersection of
two circles, a quadratic in mu across the line of the elbows. Without it the generator derives
the polynomial form from the closure. Derivation: ``docs/derivations/five_bar.md``.

The geometry comes from ``five_bar.py``: the half base length d, the proximal and distal link
lengths a = (a1, a2), b = (b1, b2) and the actuated angles theta = (theta1, theta2).
"""

from __future__ import annotations

import sympy as sp
from parakin.generator.frames import translation
from parakin.generator.model import ForwardElimination


def base_point(d: sp.Symbol, i: int) -> sp.Matrix:
    return sp.Matrix([(-d, d)[i], 0])


def direction(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


def elbow(d: sp.Symbol, a: tuple[sp.Symbol, ...], i: int, angle: sp.Expr) -> sp.Matrix:
    """C_i = A_i + a_i (cos theta_i, sin theta_i)."""
    return base_point(d, i) + a[i] * direction(angle)


def forward(
    d: sp.Symbol, a: tuple[sp.Symbol, ...], b: tuple[sp.Symbol, ...], theta: tuple[sp.Symbol, ...]
) -> ForwardElimination:
    """P = C1 + alpha e + mu J e / |e| with mu^2 + alpha^2 |e|^2 - b1^2 = 0, e = C2 - C1."""
    mu = sp.Symbol("mu", real=True)
    c1 = sp.Matrix(sp.symbols("C1_x C1_y", real=True))
    e = sp.Matrix(sp.symbols("e_x e_y", real=True))
    w, norm, alpha = sp.symbols("e_squared e_norm alpha", real=True)
    elbow2 = elbow(d, a, 1, theta[1])
    auxiliary = [(c1[k], elbow(d, a, 0, theta[0])[k]) for k in range(2)]
    auxiliary += [(e[k], elbow2[k] - c1[k]) for k in range(2)]
    auxiliary += [
        (w, e.dot(e)),
        (norm, sp.sqrt(w)),
        (alpha, (w + b[0] ** 2 - b[1] ** 2) / (2 * sp.Max(w, 1e-300))),
    ]
    quarter_turn = sp.Matrix([-e[1], e[0]])
    point = c1 + alpha * e + mu * quarter_turn / sp.Max(norm, 1e-300)
    return ForwardElimination(
        unknown=mu,
        coefficients=[alpha**2 * w - b[0] ** 2, sp.Integer(0), sp.Integer(1)],
        branches=[],
        auxiliary=auxiliary,
        back_substitution=[],
        pose=translation(point[0], point[1], 0),
        degeneracies={"elbows_coincide": norm / (b[0] + b[1])},
    )
