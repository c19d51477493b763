"""Accelerator of ``spm.py`` (optional): the forward pose eliminated by hand, a degree-8 resultant
in x = tan((phi1 - 1/2) / 2) of two equations biquadratic in the distal angles of legs 1 and 2
(the bound of Gosselin et al. 1994). Without it the generator derives the polynomial form from
the closure. Derivation: ``docs/derivations/spm.md``.

The geometry comes from ``spm.py`` as ``Geometry``: the base axes u_i, e1_i, e2_i and platform
axes v0_i (functions of the leg index), the actuated angles theta_i and the link and platform
angles alpha1, alpha2, beta.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import sympy as sp
from parakin.generator.elimination import biquadratic_resultant, half_angle_grid
from parakin.generator.frames import homogeneous, sign_or_plus
from parakin.generator.model import ForwardElimination

phi = sp.symbols("phi1:4", real=True)
#: origin of the elimination's half-angle tangents (radians; any value away from 0 and pi)
OFFSET = sp.Rational(1, 2)


@dataclass(frozen=True)
class Geometry:
    base_axes: Callable[[int], tuple[sp.Matrix, sp.Matrix, sp.Matrix]]
    platform_axis: Callable[[int], sp.Matrix]
    theta: tuple[sp.Symbol, ...]
    alpha1: sp.Symbol
    alpha2: sp.Symbol
    beta: sp.Symbol


def leg_vectors(g: Geometry, i: int, angle: sp.Expr) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """w_i(theta_i) and the distal cone frame n1_i, n2_i."""
    u, e1, e2 = g.base_axes(i)
    w = sp.cos(g.alpha1) * u + sp.sin(g.alpha1) * (sp.cos(angle) * e1 + sp.sin(angle) * e2)
    n1 = sp.cos(angle) * e2 - sp.sin(angle) * e1
    return w, n1, w.cross(n1)


def distal_cone(g: Geometry, i: int) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """v_i = P + Q cos(phi_i) + S sin(phi_i)."""
    w, n1, n2 = leg_vectors(g, i, g.theta[i])
    return sp.cos(g.alpha2) * w, sp.sin(g.alpha2) * n1, sp.sin(g.alpha2) * n2


def distal_axis(g: Geometry, i: int) -> sp.Matrix:
    p, q, s = distal_cone(g, i)
    return p + q * sp.cos(phi[i]) + s * sp.sin(phi[i])


def platform_constants(beta: sp.Symbol) -> tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]:
    """cos(psi) = v0_1 . v0_2 (eq 15) and v0_3 = ka v0_1 + kb v0_2 + kc v0_1 x v0_2."""
    cb, sb = sp.cos(beta), sp.sin(beta)
    denominator = 4 * cb**2 + sb**2
    return (
        cb**2 - sb**2 / 2,
        (2 * cb**2 - sb**2) / denominator,
        (2 * cb**2 - sb**2) / denominator,
        2 * sp.sqrt(3) * cb / denominator,
    )


def rotation_from_axes(g: Geometry, v1: sp.Matrix, v2: sp.Matrix) -> sp.Matrix:
    """R with R v0_1 = v1, R v0_2 = v2 (and so R (v0_1 x v0_2) = v1 x v2)."""
    v0 = [g.platform_axis(0), g.platform_axis(1)]
    reference = sp.Matrix.hstack(v0[0], v0[1], v0[0].cross(v0[1]))
    return sp.Matrix.hstack(v1, v2, v1.cross(v2)) * sp.simplify(reference.inv())


def forward(g: Geometry) -> ForwardElimination:
    """The forward elimination (module docstring); branch tau picks the root y of E1."""
    x, y = sp.symbols("x y", real=True)
    cos_psi, ka, kb, kc = platform_constants(g.beta)
    k_syms = sp.symbols("cos_psi ka kb kc", real=True)
    # v_i = P_i + Q_i cos + S_i sin, as coefficient triples of f(phi) = (1, cos phi, sin phi)
    legs = [distal_cone(g, i) for i in range(3)]
    w3 = leg_vectors(g, 2, g.theta[2])[0]
    first = sp.zeros(3, 3)
    second = sp.zeros(3, 3)
    for j in range(3):
        for k in range(3):
            first[j, k] = legs[0][j].dot(legs[1][k])
            second[j, k] = k_syms[3] * w3.dot(legs[0][j].cross(legs[1][k]))
            if k == 0:
                second[j, k] += k_syms[1] * w3.dot(legs[0][j])
            if j == 0:
                second[j, k] += k_syms[2] * w3.dot(legs[1][k])
    first[0, 0] -= k_syms[0]
    second[0, 0] -= sp.cos(g.alpha2)
    # tangent half angles of phi_i - OFFSET: x = tan((phi1 - OFFSET) / 2). Without the offset a
    # mode with phi1 = pi (a natural pose) sits at x = infinity and the degree-8 polynomial loses
    # it; the offset moves that case to the unremarkable phi1 = pi + OFFSET.
    # f(OFFSET + p) = T f(p) with f = (1, cos, sin)
    c, s = sp.cos(OFFSET), sp.sin(OFFSET)
    turn = sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    grids = [half_angle_grid(turn.T * m * turn) for m in (first, second)]
    elimination = biquadratic_resultant(x)
    auxiliary = list(zip(k_syms, (cos_psi, ka, kb, kc), strict=True))
    for symbols, grid in zip((elimination.first, elimination.second), grids, strict=True):
        auxiliary += [(symbols[k][j], grid[j, k]) for k in range(3) for j in range(3)]
    # back substitution: y from E1 (both roots, branch tau; the Bezout kernel fails at the Agile
    # Eye's double roots), then phi1, phi2, v1, v2 and R. The roots of A2 y^2 + A1 y + A0 are
    # q / A2 and A0 / q with q = -(A1 + sign(A1) sqrt(D)) / 2 (no cancellation); as angles,
    # 2 atan2(numerator, denominator), so that y = infinity (A2 = 0) is just phi2 = OFFSET + pi.
    tau = sp.Symbol("tau", real=True)
    big_a = [sum(elimination.first[k][j] * x**j for j in range(3)) for k in range(3)]
    discriminant, stable = sp.symbols("discriminant_y q_y", real=True)
    phi1_sym, phi2_sym = sp.symbols("phi1_root phi2_root", real=True)
    sign_a1 = sign_or_plus(big_a[1])
    plus, minus = (1 + tau) / 2, (1 - tau) / 2  # tau = +-1 selects one root, with no division
    back = [
        (discriminant, big_a[1] ** 2 - 4 * big_a[2] * big_a[0]),
        (stable, -(big_a[1] + sign_a1 * sp.sqrt(sp.Max(0, discriminant))) / 2),
        (phi1_sym, OFFSET + 2 * sp.atan(x)),
        (phi2_sym, OFFSET + 2 * sp.atan2(plus * stable + minus * big_a[0], plus * big_a[2] + minus * stable)),
    ]
    v1 = distal_axis(g, 0).subs(phi[0], phi1_sym)
    v2 = distal_axis(g, 1).subs(phi[1], phi2_sym)
    pose = homogeneous(rotation_from_axes(g, v1, v2), [0, 0, 0])
    return ForwardElimination(
        unknown=x,
        coefficients=elimination.coefficients,
        branches=[tau],
        auxiliary=auxiliary,
        back_substitution=back,
        pose=pose,
        degeneracies={},
    )
