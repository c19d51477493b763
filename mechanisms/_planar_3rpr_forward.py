"""Accelerator of ``planar_3rpr.py`` (optional): the classical forward elimination of a planar
3-RPR (Gosselin, Sefrioui and Richard 1992), a polynomial of degree 6 in t = tan(phi / 2) after the
spurious factor (1 + t^2); back substitution by Cramer's rule. Without it the generator derives the
polynomial form from the closure. Derivation: ``docs/derivations/planar_3rpr.md``.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator.blocks import as_points, half_angle_forms, planar_pose, remove_spurious_factors
from parakin.generator.model import ForwardElimination


def _linear_form(expr: sp.Expr, c: sp.Symbol, s: sp.Symbol) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(a0, a1, a2) with expr = a0 + a1 c + a2 s, for expr affine in c, s after c^2 + s^2 = 1."""
    reduced = sp.expand(sp.expand(expr).subs(c**2, 1 - s**2))
    poly = sp.Poly(reduced, c, s)
    if poly.total_degree() > 1:
        raise ValueError(f"not affine in (cos, sin): {expr}")
    return tuple(sp.expand(poly.coeff_monomial(m)) for m in (1, c, s))  # type: ignore[return-value]


def forward(base: sp.Matrix, platform: sp.Matrix, rho: tuple[sp.Symbol, ...]) -> ForwardElimination:
    """The elimination for base joints ``base`` (3 x 2, in {B}), platform joints ``platform`` (3 x 2,
    in {P}) and leg lengths ``rho``: every real root t is one mode (no branch signs)."""
    t = sp.Symbol("t", real=True)
    c, s = sp.symbols("cos_phi sin_phi", real=True)
    a = as_points(base)
    b = as_points(platform)
    rotation = sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    # m_i = R u_i - w_i and g_i = (rho_i^2 - rho1^2 - |m_i|^2) / 2, written with plain symbols:
    # u_i, w_i by coordinates (the rotation structure must stay visible for (1 + t^2) to divide),
    # g_i by its three coefficients of (1, cos phi, sin phi)
    u = {i: sp.Matrix(sp.symbols(f"u{i + 1}_x u{i + 1}_y", real=True)) for i in (1, 2)}
    w = {i: sp.Matrix(sp.symbols(f"w{i + 1}_x w{i + 1}_y", real=True)) for i in (1, 2)}
    g = {i: sp.symbols(f"g{i + 1}_0 g{i + 1}_c g{i + 1}_s", real=True) for i in (1, 2)}
    auxiliary: list[tuple[sp.Symbol, sp.Expr]] = []
    for i in (1, 2):
        auxiliary += [(u[i][k], b[i][k] - b[0][k]) for k in range(2)]
        auxiliary += [(w[i][k], a[i][k] - a[0][k]) for k in range(2)]
    for i in (1, 2):
        m_i = rotation[:2, :2] * u[i] - w[i]
        g_expr = (rho[i] ** 2 - rho[0] ** 2 - m_i.dot(m_i)) / 2
        auxiliary += list(zip(g[i], _linear_form(g_expr, c, s), strict=True))

    # the same in t: a form a0 + a1 cos + a2 sin becomes a0 W + a1 C + a2 S = (1 + t^2) * form
    generators = (*u[1], *u[2], *w[1], *w[2], *g[1], *g[2], rho[0])
    big_c, big_s, big_w = half_angle_forms(t, sp.QQ[generators])

    def scaled(vector: sp.Matrix) -> list[sp.Poly]:
        return [
            big_c * vector[0] - big_s * vector[1],
            big_s * vector[0] + big_c * vector[1],
        ]

    m = {i: [r - big_w * w[i][k] for k, r in enumerate(scaled(u[i]))] for i in (1, 2)}
    gt = {i: big_w * g[i][0] + big_c * g[i][1] + big_s * g[i][2] for i in (1, 2)}
    det_m = m[1][0] * m[2][1] - m[1][1] * m[2][0]
    numerator_x = gt[1] * m[2][1] - gt[2] * m[1][1]
    numerator_y = m[1][0] * gt[2] - m[2][0] * gt[1]
    # (1 + t^2)^4 (|adj(M) g|^2 - rho1^2 det(M)^2): degree 8 in t
    octic = numerator_x**2 + numerator_y**2 - rho[0] ** 2 * det_m**2
    clean = remove_spurious_factors(octic, t, spurious=[1 + t**2])
    if clean.degree != 6 or clean.removed != [(1 + t**2, 1)] or clean.content != 1:
        raise ValueError(f"3-RPR elimination: expected degree 6 after one (1 + t^2), got {clean}")

    # degeneracy measures, normalised by the size of the geometry and the inputs
    scale2 = sp.Symbol("length_scale2", positive=True)
    size = sum(v.dot(v) for v in (*u.values(), *w.values())) + sum(r**2 for r in rho)
    auxiliary.append((scale2, sp.Max(size / 7, 1e-300)))
    m_trig = {i: rotation[:2, :2] * u[i] - w[i] for i in (1, 2)}
    det_trig = m_trig[1][0] * m_trig[2][1] - m_trig[1][1] * m_trig[2][0]
    det_form = _linear_form(det_trig, c, s)
    degeneracies = {
        "cramer_determinant_vanishes_for_every_phi": sp.sqrt(sum(f**2 for f in det_form)) / scale2,
        "polynomial_vanishes_identically": sp.sqrt(sum(k**2 for k in clean.coefficients)) / scale2**3,
    }

    # back-substitution: phi, then q by Cramer, then p = A1 + q - R b1
    phi_root, det_sym = sp.symbols("phi_root det_M", real=True)
    q = sp.Matrix(sp.symbols("q_x q_y", real=True))
    g_num = {i: g[i][0] + g[i][1] * c + g[i][2] * s for i in (1, 2)}
    back = [
        (phi_root, 2 * sp.atan(t)),
        (c, (1 - t**2) / (1 + t**2)),
        (s, 2 * t / (1 + t**2)),
        (det_sym, det_trig),
        (q[0], (g_num[1] * m_trig[2][1] - g_num[2] * m_trig[1][1]) / det_sym),
        (q[1], (m_trig[1][0] * g_num[2] - m_trig[2][0] * g_num[1]) / det_sym),
    ]
    position = a[0][:2, 0] + q - rotation[:2, :2] * b[0][:2, 0]
    return ForwardElimination(
        unknown=t,
        coefficients=clean.coefficients,
        branches=[],
        auxiliary=auxiliary,
        back_substitution=back,
        pose=planar_pose(position[0], position[1], phi_root),
        degeneracies=degeneracies,
    )
