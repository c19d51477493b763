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
* The model (``MODEL``) is three crank legs of the joint language on the unit sphere: w_i turns
  on the cone of half-angle alpha1 about u_i (a crank of radius sin(alpha1) about the axis u_i
  through cos(alpha1) u_i), and |v_i - w_i| = 2 sin(alpha2 / 2) is w_i . v_i = cos(alpha2). The
  passive variables are the unit quaternion q0..q3 of R (scalar first); closure, rates (A rows
  (w_i x v_i)^T, B = diag((u_i x w_i) . v_i): ``leg<i>_axes_coplanar``, zero where the distal link
  lies in the proximal plane), the parallel factor det A (``distal_plane_normals_coplanar``),
  the inverse and the drawing are derived from it; the Agile Eye's folded poses (a zero
  ``leg<i>_axes_coplanar`` at every input) are flagged input-independent.
* Distal angles phi_i (the elimination's unknowns): v_i = cos(alpha2) w_i + sin(alpha2)
  (cos(phi_i) n1_i + sin(phi_i) n2_i), n1_i = (u_i x w_i) / sin(alpha1), n2_i = w_i x n1_i.
  phi_i = +-90 deg puts the distal link in the proximal plane (a serial singularity).
* Inverse branches: sigma_i = +-1 in theta_i = atan2(B, A) + sigma_i acos(-C / sqrt(A^2 + B^2)),
  8 combinations numbered as in ``parakin.Mechanism`` (branch 0 = all +).
* Defaults: the report's example (section 3.2.3) read with alpha1 and alpha2 swapped, the only
  reading that reproduces its "8 independent solutions": alpha1 = 45 deg (proximal), alpha2 =
  90 deg (distal), beta = 60 deg, gamma = 45 deg (see tests/test_spm.py). Home: R = I on inverse
  branch 0 (theta_i = -74.46 deg, phi_i = 158.53 deg), a regular, symmetric configuration.
* Forward pose (an accelerator; the generator also derives the polynomial form from the closure,
  method "automatic"): x = tan((phi1 - 1/2) / 2). Two equations in (x, y = tan(phi2 / 2)), E1 = v1.v2 - cos(psi)
  and E2 = w3 . v3(v1, v2) - cos(alpha2), with leg 3 imposed on the rigid platform (which fixes its
  handedness, so the report's mirror solutions never enter), are biquadratic; their resultant in y
  (formed over generic coefficients) has degree 8 in x, the bound of Gosselin et al. (1994).
"""

from __future__ import annotations

import math
from dataclasses import replace

import sympy as sp
from parakin.generator import joints
from parakin.generator.elimination import biquadratic_resultant, half_angle_grid
from parakin.generator.frames import homogeneous, rot_z, sign_or_plus
from parakin.generator.model import Citation, Example, ForwardElimination, Mechanism, ParameterInfo

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


#: the model: three R-R-R legs whose axes meet at the centre, written as crank legs on the unit
#: sphere (the intermediate axis w_i turns on the cone of half-angle alpha1 about u_i: a crank of
#: radius sin(alpha1) about the axis u_i through cos(alpha1) u_i; the platform axis v_i = R v0_i
#: lies at the distal angle alpha2 from it, |v_i - w_i| = 2 sin(alpha2 / 2)) on a platform that
#: turns about the centre (unit quaternion); closure, rates, singularity factor, inverse (the
#: report's branch signs) and drawing are derived from it
MODEL = joints.DistanceMechanism(
    joints.platform("rotation"),
    [
        joints.crank_leg(
            sp.cos(alpha1) * base_axes(i)[0],
            base_axes(i)[0],
            base_axes(i)[1],
            sp.sin(alpha1),
            2 * sp.sin(alpha2 / 2),
            platform_axis(i),
            theta[i],
            serial_name="leg{k}_axes_coplanar",
            spherical=True,
        )  # fmt: skip
        for i in range(3)
    ],
    parallel_name="distal_plane_normals_coplanar",
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
    parameters = {alpha1: float(45 * deg), alpha2: float(90 * deg), beta: float(60 * deg), gamma: float(45 * deg)}
    fields = MODEL.fields()
    # the Agile Eye's folded poses (a leg's axes coplanar) do not depend on the inputs: flagged
    fields["rates"] = replace(fields["rates"], input_independent=[f"leg{i + 1}_axes_coplanar" for i in range(3)])
    # drawn on the unit sphere: each leg from its actuated axis u_i (not the centre of w_i's circle)
    axes = sp.Matrix.hstack(*(base_axes(i)[0] for i in range(3)))
    fields["drawing"] = replace(fields["drawing"], points={**fields["drawing"].points, "base": axes})
    # home: the platform at R = I on inverse branch 0 (all sigma_i = +1), symmetric and far from
    # both singularity kinds
    home = MODEL.home_at(sp.eye(3), None, 0, parameters)
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
        **fields,
        forward=forward(),
        home={
            symbol: math.remainder(value, 2 * math.pi) if symbol in theta else value for symbol, value in home.items()
        },
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
    )
