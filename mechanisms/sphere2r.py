"""The 2R spherical serial chain of section 2 of the ED5314 report
(``shared/papers/001_cec8c69b51cbfe6d.txt``): two revolute joints whose axes meet at the centre O.

Conventions (SI, radians; derivation: ``docs/derivations/sphere2r.md``): fixed axis u = Z_B, angle
reference k = X_B. Link 1 turns by theta1 about u, link 2 by theta2 about the intermediate axis v;
alpha1 = angle(u, v), alpha2 = angle(v, w), w the end (pointing) axis; with Rot(a, t) right-handed
about a: m = Rot(u, theta1) k, v = Rot(m, alpha1) u, n = Rot(v, theta2) m, w = Rot(n, alpha2) v
(eqs 1-4). The end frame is ^B_P R = [n, w x n, w] (pose_kind 'rotation'); the inverse uses only w,
two branches sigma = +-1 (accelerator ``_sphere2r_inverse.py``). Defaults: the report gives no
numbers for the chain; alpha1 = 45, alpha2 = 90 deg are the SPM example's link angles.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator.frames import homogeneous
from parakin.generator.model import Citation, ClosureModel, Mechanism, ParameterInfo
from parakin.generator.trigpoly import trig_factor
from parakin.mechanisms._sphere2r_inverse import drawing, inverse

alpha1, alpha2 = sp.symbols("alpha1 alpha2", positive=True)
theta1, theta2 = sp.symbols("theta1 theta2", real=True)
U = sp.Matrix([0, 0, 1])
K = sp.Matrix([1, 0, 0])


def rotate(axis: sp.Matrix, angle: sp.Expr, vector: sp.Matrix) -> sp.Matrix:
    """Rodrigues: Rot(axis, angle) vector, axis a unit vector."""
    return sp.cos(angle) * vector + sp.sin(angle) * axis.cross(vector) + (1 - sp.cos(angle)) * axis.dot(vector) * axis


def forward_chain() -> tuple[sp.Matrix, sp.Matrix, sp.Matrix, sp.Matrix]:
    """m, v, n, w of eqs (1)-(4)."""
    m = rotate(U, theta1, K)
    v = rotate(m, alpha1, U)
    n = rotate(v, theta2, m)
    w = rotate(n, alpha2, v)
    return m, v, n, w


def build() -> Mechanism:
    _, v, n, w = forward_chain()
    pose = homogeneous(sp.Matrix.hstack(n, w.cross(n), w), [0, 0, 0])
    deg = sp.pi / 180
    return Mechanism(
        name="sphere2r",
        title="2R spherical serial chain (ED5314 report, section 2)",
        citation=Citation(
            ("V. R. Ashtekar",),
            "Forward and inverse kinematics of three degrees of freedom spherical parallel manipulators",
            None,
            "ED5314 course project report",
        ),
        parameters={alpha1: float(45 * deg), alpha2: float(90 * deg)},
        actuated=[theta1, theta2],
        passive=[],
        legs=[],
        inverse=inverse(U, K, (alpha1, alpha2), (theta1, theta2)),
        home={theta1: 0.0, theta2: 0.0},
        angular=[theta1, theta2],
        # w leaves the plane of u and v unless theta2 = 0 or pi: there the pointing map loses rank
        factors={"links_coplanar": trig_factor(U.dot(v.cross(w)))},
        closure=ClosureModel(sp.zeros(0, 1), sp.Matrix([1]), pose),
        pose_kind="rotation",
        parameter_info={
            alpha1: ParameterInfo(
                "rad", "link 1 angle at O, between the fixed axis u and the intermediate axis v", "positive"
            ),
            alpha2: ParameterInfo(
                "rad", "link 2 angle at O, between the intermediate axis v and the end axis w", "positive"
            ),
        },
        drawing=drawing(U, K, v, w),
    )


# Examples
# none: section 2 prints no numbers (no link angles, no joint values)
