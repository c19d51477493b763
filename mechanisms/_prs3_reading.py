"""Accelerator of ``prs3.py`` (optional): the 3-PRS's reachable set by hand, the tilt R0 about a
horizontal axis with the parasitic centre (x0, y0) it forces (Carretero et al.'s form, rationally).
The generator derives the inverse's reading of a pose onto that set from the legs' planes
(``generator/readings.py``); this hand form is kept as the independent check tests/test_prs3.py
compares it with. Derivation: ``docs/derivations/prs3.md``.
"""

from __future__ import annotations

import sympy as sp

K = sp.Matrix([0, 0, 1])


def tilt(r_p: sp.Expr, n: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """For a unit n = R^T k: the tilt R0 about a horizontal axis with R0^T k = n, its unit
    quaternion (q0 > 0) and the platform centre (x0, y0, 0) that the plane constraints give it
    (platform joints on the circle of radius ``r_p``). R0 = I + [v]x + [v]x^2 / (1 + n_z),
    v = n x k; q = (1 + n_z, n x k) / sqrt(2 (1 + n_z))."""
    v = n.cross(K)
    skew = sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    rotation = sp.eye(3) + skew + (v * v.T - v.dot(v) * sp.eye(3)) / (1 + n[2])
    root = sp.sqrt(2 * (1 + n[2]))
    q = sp.Matrix([(1 + n[2]) / root, v[0] / root, v[1] / root, 0])
    centre = sp.Matrix([-r_p * (n[0] ** 2 - n[1] ** 2) / (2 * (1 + n[2])), r_p * n[0] * n[1] / (1 + n[2]), 0])
    return rotation, q, centre
