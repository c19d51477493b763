"""Accelerator of ``stewart.py`` (optional): the forward pose's system in Study coordinates (e, g),
seven homogeneous quadrics with 40 isolated solutions for a general 6-6 geometry (Wampler 1996;
Husty 1996), solved by a parameter homotopy from a generic complex instance at generation time.
Without it the generator finds the forward pose by its automatic homotopy on the closure.
Derivation: ``docs/derivations/stewart.md``.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator.frames import (
    pure_quaternion,
    quaternion_conjugate,
    quaternion_product,
    quaternion_rotation_unnormalised,
)
from parakin.generator.model import ForwardHomotopy

study_e = sp.symbols("e0:4")
study_g = sp.symbols("g0:4")


def study_leg_equation(base: sp.Matrix, platform: sp.Matrix, length: sp.Expr) -> sp.Expr:
    """Leg |R b + p - A|^2 = l^2 times e . e in Study coordinates: with R = R(e), p = 2 vec(g e*) / (e . e)
    and e . g = 0, (e.e)(|b|^2 + |A|^2 - l^2) + 4 g.g + 4 <g, e b> - 2 A . vec(e b e*) - 4 A . vec(g e*)."""
    e, g = sp.Matrix(study_e), sp.Matrix(study_g)
    norm = e.dot(e)
    e_b = quaternion_product(e, pure_quaternion(platform))
    rotated = quaternion_rotation_unnormalised(e) * platform  # vec(e b e*)
    translated = quaternion_product(g, quaternion_conjugate(e))[1:, 0]  # vec(g e*)
    constant = platform.dot(platform) + base.dot(base) - length**2
    return norm * constant + 4 * g.dot(g) + 4 * g.dot(e_b) - 2 * base.dot(rotated) - 4 * base.dot(translated)


def forward(base: sp.Matrix, platform: sp.Matrix, lengths: tuple[sp.Symbol, ...]) -> ForwardHomotopy:
    """The Study quadric and the six leg quadrics for base points ``base`` (6 x 3, in {B}) and
    platform points ``platform`` (6 x 3, in {P}); the passive values (p, q) from (e, g)."""
    e, g = sp.Matrix(study_e), sp.Matrix(study_g)
    rows = [base.row(k).T for k in range(6)], [platform.row(k).T for k in range(6)]
    equations = [e.dot(g)] + [study_leg_equation(a, b, n) for a, b, n in zip(*rows, lengths, strict=True)]
    norm = e.dot(e)
    position = 2 * quaternion_product(g, quaternion_conjugate(e))[1:, 0] / norm
    passive = list(position) + [c / sp.sqrt(norm) for c in e]
    return ForwardHomotopy(list(study_e) + list(study_g), equations, list(study_e), passive)
