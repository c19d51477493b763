"""Accelerator of ``gough.py`` (optional): the forward pose of a 6-SPS with linearly related planar
platforms by the paper's procedure (sections 3 and 5.1-5.3: the linear system (8), the quartic
(23), eqs 24-27), and its architecture measure, det M of system (8) (eq 14). Without it the
generator finds the forward pose by its automatic homotopy. Derivation: ``docs/derivations/gough.md``.

The base joints are A_1 = O and A_k = (xa[k - 2], ya[k - 2], 0), k = 2..6; ``t`` = (t11, t12, t22)
the platform map of eq (1).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp
from parakin.generator.frames import homogeneous
from parakin.generator.model import ForwardElimination

u = sp.symbols("u1:6", real=True)


def system8_matrix(xa: Sequence[sp.Symbol], ya: Sequence[sp.Symbol]) -> sp.Matrix:
    """The 5x5 coefficient matrix of eq (8): rows [x, y, x^2, y^2, x y] of A_2..A_6."""
    return sp.Matrix([[xa[k], ya[k], xa[k] ** 2, ya[k] ** 2, xa[k] * ya[k]] for k in range(5)])


def system8_rhs(
    xa: Sequence[sp.Symbol], ya: Sequence[sp.Symbol], platform: list[sp.Matrix], lengths: Sequence[sp.Symbol]
) -> sp.Matrix:
    """L_i of eq (7), i = 2..6."""
    rows = []
    for k, b in enumerate(platform[1:]):
        rows.append((lengths[k + 1] ** 2 - b[0] ** 2 - b[1] ** 2 - xa[k] ** 2 - ya[k] ** 2 - lengths[0] ** 2) / 2)
    return sp.Matrix(rows)


def conic_matrix(xa: Sequence[sp.Symbol], ya: Sequence[sp.Symbol]) -> sp.Matrix:
    """Rows [1, x, y, x^2, y^2, x y] of A_1..A_6: det = 0 iff the six base points lie on a conic."""
    points = [(0, 0)] + list(zip(xa, ya, strict=True))
    return sp.Matrix([[1, px, py, px**2, py**2, px * py] for px, py in points])


def base_scale2(xa: Sequence[sp.Symbol], ya: Sequence[sp.Symbol]) -> sp.Expr:
    """The mean square distance of A2..A6 from A1 = O (m^2), the scale of the base (kept positive
    when every point sits at O)."""
    return sp.Max(sum(xa[k] ** 2 + ya[k] ** 2 for k in range(5)) / 5, 1e-300)


def normalised_conic_determinant(
    det_m: sp.Expr, scale2: sp.Expr, xa: Sequence[sp.Symbol], ya: Sequence[sp.Symbol]
) -> sp.Expr:
    """det M (eq 14) made scale-free: with the base coordinates divided by s = sqrt(scale2) (the
    columns x, y of M scale by 1/s, x^2, y^2, xy by 1/s^2: det by 1/s^8 = 1/scale2^4), divided by
    an upper bound of its row norms, sqrt(r^2 / s^2 + r^4 / s^4) >= |row| (r^2 = x^2 + y^2), so that
    |measure| <= 1 (Hadamard), invariant under scaling and rotating the base. Coincident points
    (a zero row) give 0, not 0 / 0."""
    rows = [(xa[k] ** 2 + ya[k] ** 2) / scale2 + (xa[k] ** 2 + ya[k] ** 2) ** 2 / scale2**2 for k in range(5)]
    return det_m / sp.Max(scale2**4 * sp.sqrt(sp.Mul(*rows)), 1e-300)


def architecture(xa: Sequence[sp.Symbol], ya: Sequence[sp.Symbol]) -> dict[str, sp.Expr]:
    """Eq (14): det M of system (8). It is checked here to be, term by term, the six-point conic
    determinant det[1, x, y, x^2, y^2, x y] of A1..A6 (A1 = O): it vanishes exactly when the base
    points lie on a conic, eq (15). The measure is det M normalised (``normalised_conic_
    determinant``: scale-free, |measure| <= 1), so that ``architecture_tolerance`` decides."""
    det_m = sp.expand(system8_matrix(xa, ya).det(method="berkowitz"))
    if sp.expand(det_m - conic_matrix(xa, ya).det(method="berkowitz")) != 0:
        raise ValueError("det M of system (8) is not the six-point conic determinant")
    return {"normalised_six_point_conic_determinant": normalised_conic_determinant(det_m, base_scale2(xa, ya), xa, ya)}


def forward(
    xa: Sequence[sp.Symbol],
    ya: Sequence[sp.Symbol],
    t: tuple[sp.Symbol, sp.Symbol, sp.Symbol],
    platform: list[sp.Matrix],
    lengths: Sequence[sp.Symbol],
) -> ForwardElimination:
    """The forward elimination: u from the linear system (8) by Cramer's rule, the quartic (23) in
    i_y, branches sigma (the sign of i_z, eq 24) and tau (the line-sphere intersection, eqs 5, 9,
    10)."""
    t11, t12, t22 = t
    matrix, rhs = system8_matrix(xa, ya), system8_rhs(xa, ya, platform, lengths)
    det_m, scale2 = sp.symbols("det_M scale2", real=True)
    big_l = sp.symbols("L2:7", real=True)
    ix, iy, e1, e2, a1, a2 = sp.symbols("i_x i_y e1 e2 a1 a2", real=True)
    adjugate = matrix.adjugate()
    auxiliary: list[tuple[sp.Symbol, sp.Expr]] = [(big_l[k], rhs[k]) for k in range(5)]
    auxiliary.append((det_m, sp.expand(matrix.det(method="berkowitz"))))
    # eq (8) by Cramer's rule
    auxiliary += [(u[j], sum(sp.expand(adjugate[j, k]) * big_l[k] for k in range(5)) / det_m) for j in range(5)]
    auxiliary += [
        (ix, -u[2] / t11),  # eq (11)
        (e1, -t11 / t22),
        (e2, -t12 / t22),
        (a1, -(u[4] + t12 * ix) / t22),  # eq (20): j_x = e1 i_y + a1
        (a2, -u[3] / t22),  # eq (19): j_y = e2 i_y + a2
    ]
    jx, jy = e1 * iy + a1, e2 * iy + a2
    quartic = sp.Poly(sp.expand((1 - ix**2 - iy**2) * (1 - jx**2 - jy**2) - (ix * jx + iy * jy) ** 2), iy)
    coefficients = [quartic.coeff_monomial(iy**k) for k in range(5)]  # eq (23), ascending

    sigma, tau = sp.symbols("sigma tau", real=True)
    names = "j_x j_y w_i w_j i_dot_j s_dot i_z j_z g11 g12 g22 det_G c1 c2 h2"
    jx_s, jy_s, wi, wj, dot, sdot, iz, jz, g11, g12, g22, det_g, c1, c2, h2 = sp.symbols(names, real=True)
    i_p = sp.Matrix([ix, iy, iz])
    j_p = sp.Matrix([jx_s, jy_s, jz])
    n1 = t11 * i_p - sp.Matrix([1, 0, 0])  # eq (9): n1 . p = u1
    n2 = t12 * i_p + t22 * j_p - sp.Matrix([0, 1, 0])  # eq (10): n2 . p = u2
    back = [
        (jx_s, jx),
        (jy_s, jy),
        (wi, 1 - ix**2 - iy**2),
        (wj, 1 - jx_s**2 - jy_s**2),
        (dot, ix * jx_s + iy * jy_s),
        (sdot, dot / sp.Max(sp.Abs(dot), 1e-300)),  # sign(dot); exactly 0 only at i_z = 0 = i.j
        (iz, sigma * sp.sqrt(sp.Max(0, wi))),  # eq (24)
        (jz, -sigma * sdot * sp.sqrt(sp.Max(0, wj))),  # eq (25): i_z j_z = -(i_x j_x + i_y j_y)
        (g11, n1.dot(n1)),
        (g12, n1.dot(n2)),
        (g22, n2.dot(n2)),
        (det_g, sp.Max(g11 * g22 - g12**2, 1e-300)),  # |n1 x n2|^2
        (c1, (g22 * u[0] - g12 * u[1]) / det_g),
        (c2, (g11 * u[1] - g12 * u[0]) / det_g),
    ]
    p0 = c1 * n1 + c2 * n2
    back.append((h2, lengths[0] ** 2 - p0.dot(p0)))  # eq (5) on the line p0 + s (n1 x n2)
    position = p0 + tau * sp.sqrt(sp.Max(0, h2) / det_g) * n1.cross(n2)
    # at a root i_P, j_P are orthonormal; Gram-Schmidt keeps the pose of a near-double root (or of
    # a candidate that is no mode, rejected downstream by its leg residual) a rigid transform
    i_n, j_t, j_n = sp.symbols("i_norm j_tangent j_norm", real=True)
    back += [(i_n, sp.sqrt(sp.Max(i_p.dot(i_p), 1e-300))), (j_t, j_p.dot(i_p) / i_n)]
    j_perp = j_p - j_t * i_p / i_n
    back.append((j_n, sp.sqrt(sp.Max(j_perp.dot(j_perp), 1e-300))))
    i_unit, j_unit = i_p / i_n, j_perp / j_n
    pose = homogeneous(sp.Matrix.hstack(i_unit, j_unit, i_unit.cross(j_unit)), position)
    # normalised det M (the architecture measure, here on the auxiliaries): 0 on a conic
    auxiliary.insert(0, (scale2, base_scale2(xa, ya)))
    degeneracies = {
        "base_points_on_a_conic": normalised_conic_determinant(det_m, scale2, xa, ya),
        "platform_map_singular": t11 * t22,
    }
    return ForwardElimination(iy, coefficients, [sigma, tau], auxiliary, back, pose, degeneracies)
