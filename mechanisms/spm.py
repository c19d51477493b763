"""The 3-RRR spherical parallel manipulator (SPM), with the parametrisation of Bai, Hansen and
Angeles (2009), as analysed in the ED5314 report (``shared/papers/001_cec8c69b51cbfe6d.txt``).

Frames and conventions (SI, radians):
* {B} and {P} have their origin at the centre of rotation; the pose is a pure rotation R = ^B_P R
  (pose_kind 'rotation': ^B_P T has zero translation).
* eta_i = 2 pi (i - 1) / 3. Actuated axes u_i = Rz(eta_i) (0, sin gamma, -cos gamma) (gamma: base
  pyramid half-angle). Intermediate axes w_i = cos(alpha1) u_i + sin(alpha1) (cos(theta_i) e1_i +
  sin(theta_i) e2_i) with e1_i = Rz(eta_i) (0, -cos gamma, -sin gamma), e2_i = u_i x e1_i: theta_i
  is a right-handed rotation about u_i. Platform axes v_i = R v0_i, v0_i = Rz(eta_i) (0, sin beta,
  cos beta) (beta: platform half-angle). Leg closure: w_i . v_i = cos(alpha2).
  alpha1 is the proximal link angle (u to w), alpha2 the distal one (w to v).
* Passive angles phi_i: v_i = cos(alpha2) w_i + sin(alpha2) (cos(phi_i) n1_i + sin(phi_i) n2_i),
  n1_i = (u_i x w_i) / sin(alpha1), n2_i = w_i x n1_i. phi_i = +-90 deg puts the distal link in
  the proximal plane (a serial singularity).
* Inverse branches: sigma_i = +-1 in theta_i = atan2(B, A) + sigma_i acos(-C / sqrt(A^2 + B^2)),
  8 combinations numbered as in ``parakin.Mechanism`` (branch 0 = all +).
* Defaults: the report's example (section 3.2.3) read with alpha1 and alpha2 swapped, the only
  reading that reproduces its "8 independent solutions": alpha1 = 45 deg (proximal), alpha2 =
  90 deg (distal), beta = 60 deg, gamma = 45 deg (see tests/test_spm.py). Home: R = I on inverse
  branch 0 (theta_i = -74.46 deg, phi_i = 158.53 deg), a regular, symmetric configuration.
* Forward pose: x = tan(phi1 / 2). Two equations in (x, y = tan(phi2 / 2)), E1 = v1.v2 - cos(psi)
  and E2 = w3 . v3(v1, v2) - cos(alpha2) with leg 3 imposed on the rigid platform (which fixes its
  handedness, so the report's mirror solutions never enter), are biquadratic; their resultant in y
  (formed over generic coefficients) has degree 8 in x, the bound of Gosselin et al. (1994).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator.elimination import biquadratic_resultant, half_angle_grid
from parakin.generator.frames import homogeneous, rot_z, sign_or_plus
from parakin.generator.model import (
    POSE_ROTATION,
    Citation,
    ClosureModel,
    Drawing,
    Example,
    ForwardElimination,
    InverseSolution,
    Mechanism,
    ParameterInfo,
    RateModel,
)

alpha1, alpha2, beta, gamma = sp.symbols("alpha1 alpha2 beta gamma", positive=True)
theta = sp.symbols("theta1:4", real=True)
phi = sp.symbols("phi1:4", real=True)
ETA = [2 * sp.pi * i / 3 for i in range(3)]
#: origin of the elimination's half-angle tangents (radians; any value away from 0 and pi)
OFFSET = sp.Rational(1, 2)


def base_axes(i: int) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """u_i, e1_i, e2_i (module docstring)."""
    turn = rot_z(ETA[i])
    u = turn * sp.Matrix([0, sp.sin(gamma), -sp.cos(gamma)])
    e1 = turn * sp.Matrix([0, -sp.cos(gamma), -sp.sin(gamma)])
    e2 = turn * sp.Matrix([-1, 0, 0])  # u x e1
    return u, e1, e2


def platform_axis(i: int) -> sp.Matrix:
    return rot_z(ETA[i]) * sp.Matrix([0, sp.sin(beta), sp.cos(beta)])


def leg_vectors(i: int, angle: sp.Expr) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """w_i(theta_i) and the distal cone frame n1_i, n2_i."""
    u, e1, e2 = base_axes(i)
    w = sp.cos(alpha1) * u + sp.sin(alpha1) * (sp.cos(angle) * e1 + sp.sin(angle) * e2)
    n1 = sp.cos(angle) * e2 - sp.sin(angle) * e1
    return w, n1, w.cross(n1)


def distal_cone(i: int) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """v_i = P + Q cos(phi_i) + S sin(phi_i)."""
    w, n1, n2 = leg_vectors(i, theta[i])
    return sp.cos(alpha2) * w, sp.sin(alpha2) * n1, sp.sin(alpha2) * n2


def distal_axis(i: int) -> sp.Matrix:
    p, q, s = distal_cone(i)
    return p + q * sp.cos(phi[i]) + s * sp.sin(phi[i])


def platform_constants() -> tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]:
    """cos(psi) = v0_1 . v0_2 (eq 15) and v0_3 = ka v0_1 + kb v0_2 + kc v0_1 x v0_2."""
    cb, sb = sp.cos(beta), sp.sin(beta)
    denominator = 4 * cb**2 + sb**2
    return (
        cb**2 - sb**2 / 2,
        (2 * cb**2 - sb**2) / denominator,
        (2 * cb**2 - sb**2) / denominator,
        2 * sp.sqrt(3) * cb / denominator,
    )


def rotation_from_axes(v1: sp.Matrix, v2: sp.Matrix) -> sp.Matrix:
    """R with R v0_1 = v1, R v0_2 = v2 (and so R (v0_1 x v0_2) = v1 x v2)."""
    reference = sp.Matrix.hstack(platform_axis(0), platform_axis(1), platform_axis(0).cross(platform_axis(1)))
    return sp.Matrix.hstack(v1, v2, v1.cross(v2)) * sp.simplify(reference.inv())


def inverse() -> InverseSolution:
    """Per leg: w_i . v_i = cos(alpha2) is A cos(theta) + B sin(theta) + C = 0 with v_i = R v0_i."""
    branches = list(sp.symbols("sigma1:4", real=True))
    steps: list[tuple[sp.Symbol, sp.Expr]] = []
    validity = {}
    for i in range(3):
        u, e1, e2 = base_axes(i)
        v = POSE_ROTATION * platform_axis(i)
        a, b, c, reach = sp.symbols(f"A{i + 1} B{i + 1} C{i + 1} reach{i + 1}", real=True)
        cos_p, sin_p = sp.symbols(f"cos_phi{i + 1} sin_phi{i + 1}", real=True)
        v_sym = sp.Matrix(sp.symbols(f"v{i + 1}_x v{i + 1}_y v{i + 1}_z", real=True))
        steps += [(v_sym[k], v[k]) for k in range(3)]
        steps += [
            (a, sp.sin(alpha1) * e1.dot(v_sym)),
            (b, sp.sin(alpha1) * e2.dot(v_sym)),
            (c, sp.cos(alpha1) * u.dot(v_sym) - sp.cos(alpha2)),
            (reach, a**2 + b**2 - c**2),
            # the clamp keeps unreachable branches finite; their validity (reach) is negative
            (theta[i], sp.atan2(b, a) + branches[i] * sp.acos(sp.Max(-1, sp.Min(1, -c / sp.sqrt(a**2 + b**2))))),
        ]
        w, n1, n2 = leg_vectors(i, theta[i])
        steps += [(cos_p, n1.dot(v_sym)), (sin_p, n2.dot(v_sym)), (phi[i], sp.atan2(sin_p, cos_p))]
        validity[f"leg{i + 1}_reachable"] = reach
    return InverseSolution(steps, branches, validity)


def forward() -> ForwardElimination:
    x, y = sp.symbols("x y", real=True)
    cos_psi, ka, kb, kc = platform_constants()
    k_syms = sp.symbols("cos_psi ka kb kc", real=True)
    # v_i = P_i + Q_i cos + S_i sin, as coefficient triples of f(phi) = (1, cos phi, sin phi)
    legs = [distal_cone(i) for i in range(3)]
    w3 = leg_vectors(2, theta[2])[0]
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
    second[0, 0] -= sp.cos(alpha2)
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
    v1 = distal_axis(0).subs(phi[0], phi1_sym)
    v2 = distal_axis(1).subs(phi[1], phi2_sym)
    pose = homogeneous(rotation_from_axes(v1, v2), [0, 0, 0])
    return ForwardElimination(
        unknown=x,
        coefficients=elimination.coefficients,
        branches=[tau],
        auxiliary=auxiliary,
        back_substitution=back,
        pose=pose,
        degeneracies={},
    )


def closure() -> ClosureModel:
    """The report's eq (15) in the passive angles, v_i . v_j = cos(psi), plus the handedness
    det[v1 v2 v3] / det[v0_1 v0_2 v0_3] (+1 for the platform, -1 for its mirror image)."""
    cos_psi = platform_constants()[0]
    v = [distal_axis(i) for i in range(3)]
    residual = sp.Matrix([v[0].dot(v[1]) - cos_psi, v[1].dot(v[2]) - cos_psi, v[2].dot(v[0]) - cos_psi])
    reference = sp.Matrix.hstack(*(platform_axis(i) for i in range(3))).det()
    handedness = sp.Matrix([v[0].dot(v[1].cross(v[2])) / sp.simplify(reference)])
    return ClosureModel(residual, handedness, homogeneous(rotation_from_axes(v[0], v[1]), [0, 0, 0]))


def rates() -> tuple[RateModel, dict[str, sp.Expr]]:
    """Differentiating w_i . v_i = cos(alpha2): (w_i x v_i) . omega = ((u_i x w_i) . v_i) theta_dot_i,
    so A has rows (w_i x v_i)^T and B = diag((u_i x w_i) . v_i); omega is in {B}."""
    rows, diagonal, normals = [], [], []
    for i in range(3):
        u = base_axes(i)[0]
        w = leg_vectors(i, theta[i])[0]
        v = distal_axis(i)
        rows.append((w.cross(v)).T)
        diagonal.append(u.cross(w).dot(v))
        normals.append(w.cross(v) / sp.sin(alpha2))
    serial = {f"leg{i + 1}_axes_coplanar": sp.cos(phi[i]) for i in range(3)}
    serial |= {"proximal_links_folded": sp.sin(alpha1) ** 3, "distal_links_folded_b": sp.sin(alpha2) ** 3}
    triple = normals[0].dot(normals[1].cross(normals[2]))
    parallel = {"distal_plane_normals_coplanar": triple, "distal_links_folded_a": sp.sin(alpha2) ** 3}
    model = RateModel(
        twist=["wx", "wy", "wz"],
        a=sp.Matrix.vstack(*rows),
        b=sp.diag(*diagonal),
        serial_factors=serial,
        input_independent=[f"leg{i + 1}_axes_coplanar" for i in range(3)],
    )
    return model, parallel


def drawing() -> Drawing:
    """The joint axes as points on the unit sphere, one set per layer: actuated axes u_i (base),
    intermediate axes w_i (theta_i) and platform axes v_i (theta_i, phi_i) as each leg reaches
    them (at a closure, v_i = R v0_i); each leg is the path u_i -> w_i -> v_i (proximal, then
    distal link), the base and the platform are the triangles of their axes."""
    return Drawing(
        points={
            "base_axes": sp.Matrix.hstack(*(base_axes(i)[0] for i in range(3))),
            "intermediate_axes": sp.Matrix.hstack(*(leg_vectors(i, theta[i])[0] for i in range(3))),
            "platform_axes": sp.Matrix.hstack(*(distal_axis(i) for i in range(3))),
        },
        polylines={
            "base": [("base_axes", i % 3) for i in range(4)],
            "platform": [("platform_axes", i % 3) for i in range(4)],
            **{f"leg{i + 1}": [("base_axes", i), ("intermediate_axes", i), ("platform_axes", i)] for i in range(3)},
        },
    )


#: The report prints no numbers for the Agile Eye (alpha1 = alpha2 = 90 deg, beta = gamma =
#: atan(sqrt 2)); its input-independent modes are checked in tests/test_spm.py, not as an example.
EXAMPLES = [
    Example(
        name="section323",
        description="section 3.2.3: theta = (105, 60, 105) deg, the report's 'eight independent "
        "solutions' (section 3.2.1, Fig. 3); with the printed link labels swapped (alpha1 = 45 "
        "proximal, alpha2 = 90 deg distal, the defaults), the only reading with 8 real modes",
        actuated=[math.radians(105.0), math.radians(60.0), math.radians(105.0)],
        expected={"mode_count": 8},
        tolerance=0.0,
    )
]


def build() -> Mechanism:
    deg = sp.pi / 180
    rate_model, parallel = rates()
    parameters = {alpha1: float(45 * deg), alpha2: float(90 * deg), beta: float(60 * deg), gamma: float(45 * deg)}
    solution = inverse()
    # home: the platform at R = I on inverse branch 0 (all sigma_i = +1), symmetric and far from
    # both singularity kinds (|det A| = 0.999, |det B| = 0.285 with the defaults)
    at_identity = solution.at(sp.eye(3), None, 0, parameters)
    return Mechanism(
        name="spm",
        title="3-RRR spherical parallel manipulator (Bai, Hansen & Angeles 2009 parametrisation)",
        citation=Citation(
            ("V. R. Ashtekar",),
            "Forward and inverse kinematics of three degrees of freedom spherical parallel manipulators",
            None,
            "ED5314 course project report",
        ),
        parameters=parameters,
        actuated=list(theta),
        passive=list(phi),
        legs=[],
        inverse=solution,
        forward=forward(),
        home={symbol: math.remainder(at_identity[symbol], 2 * math.pi) for symbol in (*theta, *phi)},
        angular=[*theta, *phi],
        parallel_factors=parallel,
        closure=closure(),
        rates=rate_model,
        pose_kind="rotation",
        parameter_info={
            alpha1: ParameterInfo(
                "rad", "proximal link angle, between the actuated axis u_i and the intermediate axis w_i", "positive"
            ),
            alpha2: ParameterInfo(
                "rad", "distal link angle, between the intermediate axis w_i and the platform axis v_i", "positive"
            ),
            beta: ParameterInfo(
                "rad", "platform pyramid half-angle, between Z_P and each platform axis v0_i", "nonnegative"
            ),
            gamma: ParameterInfo(
                "rad", "base pyramid half-angle, between -Z_B and each actuated axis u_i", "nonnegative"
            ),
        },
        examples=EXAMPLES,
        drawing=drawing(),
    )
