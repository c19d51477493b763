"""Accelerator of ``sphere2r.py``: the 2R spherical chain's inverse by hand (the report's eqs 5-13,
corrected: v from its angles to u and w, two branches sigma) and its drawing on the unit sphere.
Derivation: ``docs/derivations/sphere2r.md``.

The chain comes from ``sphere2r.py``: the fixed axis u, the angle reference k, the link angles
alpha1, alpha2 and the joint angles theta1, theta2.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator.model import POSE_ROTATION, Drawing, InverseSolution


def inverse(
    U: sp.Matrix, K: sp.Matrix, alphas: tuple[sp.Symbol, sp.Symbol], thetas: tuple[sp.Symbol, sp.Symbol]
) -> InverseSolution:
    """v = p u + q w + sigma r (u x w), then m, n and theta1, theta2; validity ``reachable`` and
    ``w_off_the_base_axis``."""
    alpha1, alpha2 = alphas
    theta1, theta2 = thetas
    sigma = sp.Symbol("sigma", real=True)
    w = POSE_ROTATION[:, 2]
    c, p, q, r2, gram = sp.symbols("c_uw p q r_squared gram", real=True)
    v = sp.Matrix(sp.symbols("v_x v_y v_z", real=True))
    m = sp.Matrix(sp.symbols("m_x m_y m_z", real=True))
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    cross_uw = U.cross(w)
    safe = sp.Max(gram, 1e-300)  # w = +-u is flagged by validity; keep the values finite there
    steps = [
        (c, U.dot(w)),
        (gram, 1 - c**2),
        (p, (sp.cos(alpha1) - c * sp.cos(alpha2)) / safe),
        (q, (sp.cos(alpha2) - c * sp.cos(alpha1)) / safe),
        (r2, (1 - p**2 - q**2 - 2 * p * q * c) / safe),
    ]
    root = sigma * sp.sqrt(sp.Max(0, r2))
    steps += [(v[k], p * U[k] + q * w[k] + root * cross_uw[k]) for k in range(3)]
    steps += [(m[k], U.cross(v)[k] / sp.sin(alpha1)) for k in range(3)]
    steps += [(n[k], v.cross(w)[k] / sp.sin(alpha2)) for k in range(3)]
    steps += [
        (theta1, sp.atan2(K.cross(m).dot(U), K.dot(m))),
        (theta2, sp.atan2(m.cross(n).dot(v), m.dot(n))),
    ]
    return InverseSolution(steps, [sigma], {"reachable": r2, "w_off_the_base_axis": gram})


def drawing(U: sp.Matrix, K: sp.Matrix, v: sp.Matrix, w: sp.Matrix) -> Drawing:
    """The joint axes as points on the unit sphere: the fixed layer (axis u and the angle
    reference k, theta1 = 0) and the moving layer (intermediate axis v, end axis w); the arm is the
    path u -> v -> w (link 1 spans alpha1, link 2 alpha2)."""
    return Drawing(
        points={"base_axes": sp.Matrix.hstack(U, K), "moving_axes": sp.Matrix.hstack(v, w)},
        polylines={
            "arm": [("base_axes", 0), ("moving_axes", 0), ("moving_axes", 1)],
            "reference": [("base_axes", 0), ("base_axes", 1)],
        },
    )
