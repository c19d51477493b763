"""The 2R spherical serial chain of section 2 of the ED5314 report
(``shared/papers/001_cec8c69b51cbfe6d.txt``): two revolute joints whose axes meet at the centre O.

Conventions (SI, radians): fixed axis u = Z_B, angle reference k = X_B (normal to u). Link 1 turns
by theta1 about u, link 2 by theta2 about the intermediate axis v; alpha1 = angle(u, v),
alpha2 = angle(v, w), w the end (pointing) axis. With Rot(a, t) a right-handed rotation about a:
    m = Rot(u, theta1) k            (eq 1)
    v = Rot(m, alpha1) u            (eq 2; printed as Rot(u, alpha1) u, which is u itself)
    n = Rot(v, theta2) m            (eq 3)
    w = Rot(n, alpha2) v            (eq 4)
The end frame is ^B_P R = [n, w x n, w] (pose_kind 'rotation'); inverse pose uses only its Z axis w.
Inverse (eqs 5-13, corrected): v . u = cos(alpha1), v . w = cos(alpha2) (eqs 5, 6 swap the two),
|v| = 1 give v = p u + q w + sigma r (u x w), two branches sigma = +-1; then m = u x v / sin(alpha1),
n = v x w / sin(alpha2) (eqs 8, 9 without the normalisation), theta1 = atan2((k x m) . u, k . m),
theta2 = atan2((m x n) . v, m . n) (eq 13 takes the sign about u, which is wrong: the rotation is
about v). Defaults: the report gives no numbers for the chain; alpha1 = 45, alpha2 = 90 deg are the
SPM example's link angles.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator.frames import homogeneous
from parakin.generator.model import (
    POSE_ROTATION,
    Citation,
    ClosureModel,
    Drawing,
    InverseSolution,
    Mechanism,
    ParameterInfo,
)
from parakin.generator.trigpoly import trig_factor

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


def inverse() -> InverseSolution:
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


def drawing(v: sp.Matrix, w: sp.Matrix) -> Drawing:
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
        inverse=inverse(),
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
        # section 2 prints no numbers (no link angles, no joint values): no named example
        drawing=drawing(v, w),
    )
