"""Accelerator of ``delta.py`` (optional): the Delta's forward pose as the intersection of three
spheres, a quadratic in mu along the normal of the plane of the shifted elbows, and the drawing's
tool point. Without it the generator derives the polynomial form from the closure. Derivation:
``docs/derivations/delta.md``.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp
from parakin.generator.frames import translation
from parakin.generator.model import Drawing, ForwardElimination

Z = sp.Matrix([0, 0, 1])


def arm(radial: sp.Matrix, angle: sp.Expr) -> sp.Matrix:
    """u_i(theta) = cos(theta) e_i - sin(theta) z, the upper arm's direction."""
    return sp.cos(angle) * radial - sp.sin(angle) * Z


def forward(
    radial: Sequence[sp.Matrix],
    big_r: sp.Symbol,
    r: sp.Symbol,
    big_l: sp.Symbol,
    ell: sp.Symbol,
    theta: tuple[sp.Symbol, ...],
) -> ForwardElimination:
    """The three-sphere intersection as a quadratic in mu: the platform at distance ``ell`` from the
    shifted elbows (R - r) e_i + L u_i(theta_i), e_i = ``radial[i]``."""
    mu = sp.Symbol("mu", real=True)
    centres = [sp.Matrix(sp.symbols(f"c{i + 1}_x c{i + 1}_y c{i + 1}_z", real=True)) for i in range(3)]
    n_a = sp.Matrix(sp.symbols("na_x na_y na_z", real=True))
    n_b = sp.Matrix(sp.symbols("nb_x nb_y nb_z", real=True))
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    v0 = sp.Matrix(sp.symbols("v0_x v0_y v0_z", real=True))
    n2, n_norm, v0_sq = sp.symbols("n_squared n_norm v0_squared", real=True)
    auxiliary: list[tuple[sp.Symbol, sp.Expr]] = []
    for i in range(3):
        shifted = (big_r - r) * radial[i] + big_l * arm(radial[i], theta[i])
        auxiliary += [(centres[i][k], shifted[k]) for k in range(3)]
    auxiliary += [(n_a[k], centres[1][k] - centres[0][k]) for k in range(3)]
    auxiliary += [(n_b[k], centres[2][k] - centres[0][k]) for k in range(3)]
    auxiliary += [(n[k], n_a.cross(n_b)[k]) for k in range(3)]
    auxiliary += [(n2, n.dot(n)), (n_norm, sp.sqrt(n2))]
    circumcentre = (n_a.dot(n_a) * n_b.cross(n) + n_b.dot(n_b) * n.cross(n_a)) / (2 * sp.Max(n2, 1e-300))
    auxiliary += [(v0[k], circumcentre[k]) for k in range(3)]
    auxiliary.append((v0_sq, v0.dot(v0)))
    position = centres[0] + v0 + mu * n / sp.Max(n_norm, 1e-300)
    return ForwardElimination(
        unknown=mu,
        coefficients=[v0_sq - ell**2, sp.Integer(0), sp.Integer(1)],
        branches=[],
        auxiliary=auxiliary,
        back_substitution=[],
        pose=translation(*position),
        degeneracies={"elbow_centres_collinear": n_norm / ell**2},
    )


def drawing(parts: Drawing, position: sp.Matrix) -> Drawing:
    """The model's parts (motor joints b_i, elbows c_i, platform joints P_i; each leg b_i -> c_i
    -> P_i, the base and platform triangles) with the tool point p (``position``) and the platform spokes."""
    points = parts.points | {"platform": sp.Matrix.hstack(parts.points["platform"], position)}
    spokes = [("platform", 0), ("platform", 3), ("platform", 1), ("platform", 3), ("platform", 2)]
    return Drawing(points=points, polylines=parts.polylines | {"tool": spokes})
