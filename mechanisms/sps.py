"""The 3(SPS)-S spherical platform of Knapczyk and Tora (``shared/papers/002_91f1e7509f31240b.txt``):
an orienting platform on a central spherical joint Q, driven by three linear actuators A_i B_i.

Frames and conventions (SI, radians), as in section 2 of the paper:
* {B} and {P} both have their origin at Q (pose_kind 'rotation': ^B_P T has zero translation).
  x_b points from Q to A1 and y_b lies in the plane Q A1 A2 (A2 on the +y side); x_p points from Q
  to B1 and y_p lies in the plane Q B1 B2 (B2 on the +y side). So a1 = (a1x, 0, 0),
  a2 = (a2x, a2y, 0) with a2y > 0, a3 = (a3x, a3y, a3z), and the platform points are fixed by
  |QB_i| = b_i and |B_i B_j| = b_ij: b1p = b1 (1, 0, 0), b2p = b2 (q12, sqrt(1 - q12^2), 0),
  b3p = b3 (q13, (q23 - q12 q13) / s, chi sqrt(D3) / s) with s = sqrt(1 - q12^2), q_ij the cosines
  of eq (1c) and D3 their Gram determinant (eq 5). The distances do not fix the handedness chi of
  the platform (the sign of det[b1p b2p b3p]); chi = -1 reproduces the paper's printed b_3.
* Orientation: b_i = R b_ip (eq 8) with the Euler set of eq (9), R = Rx(alpha) Ry(beta) Rx(gamma)
  (Craig's X'-Y'-X' set; the paper's text calls it "R_{y',y',y'}", a typo). The passive
  variables are (alpha, beta, gamma). Inverse branch sigma = sign(sin beta): the two Euler triples
  of one rotation; both give the same leg lengths. sin beta = 0 is a singularity of the Euler set
  only (validity ``euler_angles_regular``).
* Actuated: the leg lengths d_i = |a_i - R b_ip| (eq 7). Their strokes d_i_min <= d_i <= d_i_max
  (section 5, ``STROKES``) are the actuated ranges (``limits``): every solver refuses lengths
  outside them (BadInputError) and the inverse pose flags the branches whose lengths leave them
  (failure ``actuator_range``), one check in one place for forward_pose, forward_pose_all, the
  tracker and the inverse. k1..k3 (N/m, section 5) are the actuator stiffnesses, delta f_i = k_i delta d_i with f_i > 0
  a compression (the leg pushes the platform along u_i = (B_i - A_i) / d_i), declared as the
  mechanism's ``actuator_stiffness``; the kinematics do not use them (statics, section 4:
  ``examples/sps_section5.py``).
* Model: three S-P-S legs (``parakin.generator.joints``) on a platform with this Euler set as
  coordinates: rates, the singularity factor, the inverse (with validity ``leg<i>_length`` and
  ``euler_angles_regular``) and the drawing are derived; the closure below is the paper's.
* Loop closure: g_i = a_i^2 + b_i^2 - 2 a_i . R b_ip - d_i^2 = 0 (eq 7), square in (alpha, beta,
  gamma). Its passive Jacobian is U_omega (eq 11a) and its actuated Jacobian W = -2 diag(d) (eq
  12), so the closure's passive rates are J_omega^-1 = -U_omega^-1 W (eq 17 lacks the minus sign).
  R(alpha, beta, gamma) is always a proper rotation, so every zero of g is a true closure: the
  alignment output is the constant 1 (there is no mirror or half-turn to reject).
* Rates (A omega = B d_dot, omega in {B}): d_i d_i_dot = (a_i x b_i) . omega, so A has rows
  (a_i x b_i)^T and B = diag(d_i). det A = det[a_i x b_i] vanishes at the type II singularities
  (the three leg moment vectors about Q coplanar); det U_omega = 8 sin(beta) det[b_i x a_i].
* Forward pose (eqs 2-6): the paper's unknown is v = a2o . b1o (eq 2); eq (3) gives b1o and eq
  (4) b2o with the roots r1 = s1 sqrt(D1), r2 = s2 sqrt(D2) (the printed "1/2 sqrt(D1)", "1/2
  sqrt(D2)" read +-sqrt); the sign in eq (5) is not a branch: sqrt(D3) enters as chi sqrt(D3), a
  platform constant. Rationalising F(v) (squaring out r1, r2) gives a degree-12 polynomial with
  the spurious factor (v^2 - 1)^2, and v folds the two configurations s1 = +-1 onto one value, so
  that at D1 ~ 0 or near v = 1 distinct configurations make clustered, ill-conditioned roots in v.
  The generated code therefore eliminates in angles instead: b1o = p1 a1o + rho1 (cos phi y_b +
  sin phi z_b) on the cone of leg 1 and b2o = p2 a2o + rho2 (cos psi (z_b x a2o) + sin psi z_b)
  on that of leg 2 (rho_i = sqrt(1 - p_i^2)); eq (4)'s condition E1 = b1o . b2o - q12 = 0 and
  eq (6)'s E2 = a3o . b3o - p3 = 0 with b3o = k1 b1o + k2 b2o + k3 b1o x b2o (eq 5) are bilinear
  in (1, cos, sin) of phi and psi, so biquadratic in x = tan(phi / 2), y = tan(psi / 2); their
  resultant in y (generator.elimination) is the degree-8 forward polynomial in t = x, without
  square roots or spurious factors (8 = the Bezout number of the quaternion formulation; at the
  real roots, v = c12 p1 + s12 rho1 cos phi gives the paper's roots). Distinct real roots t are
  distinct b1o, so D1's fold and v = 1 are gone. For each root t and branch tau = +-1 the back
  substitution takes a zero psi of E = |E1| E1 + |E2| E2 (each E_n = alpha_n + beta_n cos psi +
  gamma_n sin psi at that t, |E_n| its coefficient norm, so that neither degenerate case, E1 = 0
  at b1o = +-a2o or E2 = 0, loses the root), builds b1o, b2o and R, then takes six gated
  Cayley-Newton steps on the leg equations. At a (near-)double root t (two configurations with
  nearly the same b1o), rounding may split the pair into a complex pair close to the real axis:
  the root isolation reports it as a near-real root (a local minimum of |p| within the near-real
  tolerance), and the two branches tau give the two configurations. Candidates that do not close are dropped by the runtime, and
  duplicates merged, so a mode's (root, branch) slot does not label it:
  ``paper_labels`` of ``examples/sps_section5.py`` computes (v, s1, s2) from the configuration (paper order
  v1..v4 = branches (s1, s2) = (+, +), (+, -), (-, +), (-, -)), and
  ``polynomial_roots`` of ``examples/sps_section5.py`` maps the roots t to v.
* Defaults: section 5 (Baukema SHM4-120A), with a3x = +2.720 m (printed -2.720: with it no
  configuration exists, and the printed b_3 is 5.07 m from A3 instead of d3 = 1.32 m; see
  tests/test_sps.py), chi = -1, strokes and stiffnesses as printed.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator import joints
from parakin.generator.elimination import biquadratic_resultant, half_angle_grid
from parakin.generator.frames import homogeneous, rot_x, rot_y
from parakin.generator.model import (
    POSE_ROTATION,
    Citation,
    ClosureModel,
    Drawing,
    Example,
    ForwardElimination,
    Mechanism,
    ParameterInfo,
)

# parameters (section 5)
a1x, a2x, a2y, a3x, a3y, a3z = sp.symbols("a1x a2x a2y a3x a3y a3z", real=True)
b1, b2, b3, b12, b23, b13 = sp.symbols("b1 b2 b3 b12 b23 b13", positive=True)
chi = sp.Symbol("chi", real=True)
stiffness = sp.symbols("k1:4", real=True)
# variables
d = sp.symbols("d1:4", positive=True)
alpha, beta, gamma = sp.symbols("alpha beta gamma", real=True)
#: section 5 (Baukema SHM4-120A): (d_i_min, d_i_max) of legs 1..3, metres; the actuated ranges
STROKES = ((0.530, 1.780), (0.530, 1.780), (0.810, 2.060))
NEWTON_STEPS = 6  # Cayley-Newton steps of the back substitution
NEWTON_REACH = sp.Rational(1, 5)  # rad: how far from a closure those steps reach (see _cayley_newton)


def base_points() -> list[sp.Matrix]:
    return [sp.Matrix([a1x, 0, 0]), sp.Matrix([a2x, a2y, 0]), sp.Matrix([a3x, a3y, a3z])]


def platform_cosines() -> tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]:
    """q12, q13, q23 (eq 1c) and D3 (eq 5), from the distances."""
    q12 = (b1**2 + b2**2 - b12**2) / (2 * b1 * b2)
    q13 = (b1**2 + b3**2 - b13**2) / (2 * b1 * b3)
    q23 = (b2**2 + b3**2 - b23**2) / (2 * b2 * b3)
    return q12, q13, q23, 1 - q12**2 - q13**2 - q23**2 + 2 * q12 * q13 * q23


def platform_points() -> list[sp.Matrix]:
    """b_ip in {P} (module docstring)."""
    q12, q13, q23, d3 = platform_cosines()
    s = sp.sqrt(1 - q12**2)
    return [
        sp.Matrix([b1, 0, 0]),
        b2 * sp.Matrix([q12, s, 0]),
        b3 * sp.Matrix([q13, (q23 - q12 * q13) / s, chi * sp.sqrt(sp.Max(0, d3)) / s]),
    ]


def euler_rotation(a: sp.Expr, b: sp.Expr, c: sp.Expr) -> sp.Matrix:
    """Eq (9): R = Rx(alpha) Ry(beta) Rx(gamma)."""
    return rot_x(a) * rot_y(b) * rot_x(c)


def leg_equations(rotation: sp.Matrix) -> sp.Matrix:
    """g_i of eq (7)."""
    rows = []
    for i, (a, bp) in enumerate(zip(base_points(), platform_points(), strict=True)):
        rows.append(a.dot(a) + bp.dot(bp) - 2 * a.dot(rotation * bp) - d[i] ** 2)
    return sp.Matrix(rows)


#: the model: three S-P-S legs from a_i to b_ip on a platform turning about Q, with the Euler set
#: of eq (9) as coordinates (branch sigma = sign(sin beta)); rates, the singularity factor, the
#: inverse (d_i = |a_i - R b_ip|, eq 7) and the drawing are derived from it; the closure is the
#: paper's eq (7), kept as written (its Jacobians are eqs 11a and 12)
SIGMA = sp.Symbol("sigma", real=True)
SIN_BETA = sp.Symbol("sin_beta", real=True)
MOTION = joints.Platform(
    "rotation",
    (alpha, beta, gamma),
    euler_rotation(alpha, beta, gamma),
    sp.zeros(3, 1),
    read=(
        (SIN_BETA, sp.sqrt(POSE_ROTATION[0, 1] ** 2 + POSE_ROTATION[0, 2] ** 2)),
        (beta, sp.atan2(SIGMA * SIN_BETA, POSE_ROTATION[0, 0])),
        (alpha, sp.atan2(SIGMA * POSE_ROTATION[1, 0], -SIGMA * POSE_ROTATION[2, 0])),
        (gamma, sp.atan2(SIGMA * POSE_ROTATION[0, 1], SIGMA * POSE_ROTATION[0, 2])),
    ),
    pose=(POSE_ROTATION, sp.zeros(3, 1)),
    angular=(alpha, beta, gamma),
    branches=(SIGMA,),
    validity=(("euler_angles_regular", SIN_BETA**2),),
)


def model() -> joints.DistanceMechanism:
    legs = [
        joints.prismatic_leg(a, bp, d[i])
        for i, (a, bp) in enumerate(zip(base_points(), platform_points(), strict=True))
    ]
    return joints.DistanceMechanism(MOTION, [*legs, joints.central_joint()], parallel_name="leg_moments_coplanar")


# ---------------------------------------------------------------------------- forward pose
T_HALF = sp.Symbol("t", real=True)
Q12 = sp.Symbol("q12", real=True)
COSINES = sp.symbols("c12 s12 p1 p2 p3 rho1 rho2 e1 e2 e3 k1 k2 k3", real=True)


def cone_grids() -> tuple[sp.Matrix, sp.Matrix]:
    """The closure as two equations bilinear in f(phi) = (1, cos phi, sin phi) and f(psi), in the
    canonical base frame a1o = (1, 0, 0), a2o = (c12, s12, 0), a3o = (e1, e2, e3): b1o = p1 a1o +
    rho1 (cos phi y_b + sin phi z_b) on the cone of leg 1 (eq 1b), b2o = p2 a2o + rho2 (cos psi n2 +
    sin psi z_b) on the cone of leg 2 (n2 = z_b x a2o), rho_i = sqrt(1 - p_i^2); E1 = b1o . b2o -
    q12 (eq 4) and E2 = a3o . b3o - p3 (eq 6) with b3o = k1 b1o + k2 b2o + k3 b1o x b2o (eq 5; k1,
    k2, k3 are platform constants). Entry [j, k] multiplies f_j(phi) f_k(psi)."""
    c12, s12, p1, p2, p3, rho1, rho2, e1, e2, e3, k1, k2, k3 = COSINES
    a1o, a2o, a3o = sp.Matrix([1, 0, 0]), sp.Matrix([c12, s12, 0]), sp.Matrix([e1, e2, e3])
    z = sp.Matrix([0, 0, 1])
    leg1 = [p1 * a1o, rho1 * sp.Matrix([0, 1, 0]), rho1 * z]
    leg2 = [p2 * a2o, rho2 * z.cross(a2o), rho2 * z]
    first, second = sp.zeros(3, 3), sp.zeros(3, 3)
    for j in range(3):
        for k in range(3):
            first[j, k] = leg1[j].dot(leg2[k])
            second[j, k] = k3 * a3o.dot(leg1[j].cross(leg2[k]))
            if k == 0:
                second[j, k] += k1 * a3o.dot(leg1[j])
            if j == 0:
                second[j, k] += k2 * a3o.dot(leg2[k])
    first[0, 0] -= Q12
    second[0, 0] -= p3
    return first.applyfunc(sp.expand), second.applyfunc(sp.expand)


def _cayley_newton(rotation: sp.Matrix, step: int) -> tuple[list[tuple[sp.Symbol, sp.Expr]], sp.Matrix]:
    """One Newton step on a_i . R b_ip = |a_i| b_i p_i (the leg equations), R <- Cay(w) R.

    The step is gated, w / (1 + (|w| / NEWTON_REACH)^4): a candidate within a few hundredths of
    a radian of a closure (a root near a branch point) converges, one further away (the wrong
    branch tau) stays put and is rejected by the runtime, instead of drifting into another mode.
    It is regularised where the Jacobian (rows R b_ip x a_i) is singular. Platform points come
    from the symbols ``PLATFORM`` (assigned in the auxiliaries)."""
    assignments: list[tuple[sp.Symbol, sp.Expr]] = []
    c12, s12, p1, p2, p3, *_ = COSINES
    targets = [p1, p2, p3]
    jacobian = sp.Matrix(3, 3, sp.symbols(f"newton{step}_J1:10", real=True))
    residual = sp.Matrix(sp.symbols(f"newton{step}_g1:4", real=True))
    for i, (a, bp) in enumerate(zip(base_points(), PLATFORM, strict=True)):
        point = rotation * bp
        value = a.dot(point) - sp.sqrt(a.dot(a)) * [b1, b2, b3][i] * targets[i]
        row = point.cross(a)
        assignments.append((residual[i], value))
        assignments += [(jacobian[i, k], row[k]) for k in range(3)]
    det = sp.Symbol(f"newton{step}_det", real=True)
    w = sp.Matrix(sp.symbols(f"newton{step}_w1:4", real=True))
    gate = sp.Symbol(f"newton{step}_gate", real=True)
    raw = -(jacobian.adjugate() * residual)
    assignments.append((det, jacobian.det()))
    assignments += [(w[k], raw[k] * det / (det**2 + sp.Float(1e-24))) for k in range(3)]
    assignments.append((gate, 1 / (1 + (w.dot(w) / NEWTON_REACH**2) ** 2)))
    u = w * gate / 2
    skew = sp.Matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    cayley = sp.eye(3) + 2 / (1 + u.dot(u)) * (skew + skew * skew)
    names = " ".join(f"R{step}_{j}{k}" for j in (1, 2, 3) for k in (1, 2, 3))
    updated = sp.Matrix(3, 3, sp.symbols(names, real=True))
    product = cayley * rotation
    assignments += [(updated[j, k], product[j, k]) for j in range(3) for k in range(3)]
    return assignments, updated


PLATFORM = [sp.Matrix(sp.symbols(f"b{i}p_x b{i}p_y b{i}p_z", real=True)) for i in (1, 2, 3)]


def forward() -> ForwardElimination:
    c12, s12, p1, p2, p3, rho1, rho2, e1, e2, e3, k1, k2, k3 = COSINES
    a = base_points()
    q12e, q13e, q23e, d3e = platform_cosines()
    a2n, a3n = sp.sqrt(a[1].dot(a[1])), sp.sqrt(a[2].dot(a[2]))
    q13, q23, s3 = sp.symbols("q13 q23 s3", real=True)
    auxiliary: list[tuple[sp.Symbol, sp.Expr]] = [
        (c12, a2x / a2n),
        (s12, a2y / a2n),
        (e1, a3x / a3n),
        (e2, a3y / a3n),
        (e3, a3z / a3n),
        (Q12, q12e),
        (q13, q13e),
        (q23, q23e),
        (s3, chi * sp.sqrt(sp.Max(0, d3e))),
        # b3o = k1 b1o + k2 b2o + k3 b1o x b2o (eq 5)
        (k1, (q13 - Q12 * q23) / (1 - Q12**2)),
        (k2, (q23 - Q12 * q13) / (1 - Q12**2)),
        (k3, s3 / (1 - Q12**2)),
    ]
    for symbols, point in zip(PLATFORM, platform_points(), strict=True):
        auxiliary += [(symbols[k], point[k]) for k in range(3)]
    for i, (p, bi) in enumerate(zip((p1, p2, p3), (b1, b2, b3), strict=True)):
        norm = sp.sqrt(a[i].dot(a[i]))
        auxiliary.append((p, (norm**2 + bi**2 - d[i] ** 2) / (2 * norm * bi)))  # eq (1b)
    # |p_i| > 1: leg i cannot reach; rho_i = 0 then, and the roots found do not close
    auxiliary += [(rho1, sp.sqrt(sp.Max(0, 1 - p1**2))), (rho2, sp.sqrt(sp.Max(0, 1 - p2**2)))]
    # E1, E2 biquadratic in the tangent half angles x = tan(phi / 2), y = tan(psi / 2);
    # the resultant in y is the degree-8 forward polynomial in x = t
    first, second = cone_grids()
    elimination = biquadratic_resultant(T_HALF)
    for symbols, grid in zip((elimination.first, elimination.second), (first, second), strict=True):
        full = half_angle_grid(grid)  # [p, q]: coefficient of x^p y^q
        auxiliary += [(symbols[k][j], sp.expand(full[j, k])) for k in range(3) for j in range(3)]
    # the grids themselves, for the back substitution on the unit circle
    grid_symbols = [sp.Matrix(3, 3, sp.symbols(f"E{n}_0:3(0:3)", real=True)) for n in (1, 2)]
    for symbols, grid in zip(grid_symbols, (first, second), strict=True):
        auxiliary += [(symbols[j, k], grid[j, k]) for j in range(3) for k in range(3)]

    # back substitution: phi from t; at a root, E1 and E2 are alpha + beta cos psi + gamma sin psi
    # with a common zero psi; it is taken from E = |E1| E1 + |E2| E2 (|.| the coefficient norm:
    # E1 alone vanishes identically where b1o = +-a2o, E2 alone where a3o is normal to b3o's
    # circle), on branch tau (its other zero is not a configuration and does not close, except at
    # a double root t, where both are configurations); then b1o, b2o, R and Newton polish
    tau = sp.Symbol("tau", real=True)
    cos_phi, sin_phi = sp.symbols("cos_phi sin_phi", real=True)
    f_phi = sp.Matrix([1, cos_phi, sin_phi])
    back: list[tuple[sp.Symbol, sp.Expr]] = [
        (cos_phi, (1 - T_HALF**2) / (1 + T_HALF**2)),
        (sin_phi, 2 * T_HALF / (1 + T_HALF**2)),
    ]
    lines, weights = [], []
    for n, symbols in enumerate(grid_symbols, start=1):
        line = sp.Matrix(sp.symbols(f"E{n}_alpha E{n}_beta E{n}_gamma", real=True))
        weight = sp.Symbol(f"E{n}_weight", real=True)
        row = f_phi.T * symbols
        back += [*((line[k], row[k]) for k in range(3)), (weight, sp.sqrt(line.dot(line)))]
        lines.append(line)
        weights.append(weight)
    lin = sp.Matrix(sp.symbols("E_alpha E_beta E_gamma", real=True))
    norm2, disc, root = sp.symbols("E_norm2 E_discriminant E_root", real=True)
    cos_psi, sin_psi = sp.symbols("cos_psi sin_psi", real=True)
    combined = weights[0] * lines[0] + weights[1] * lines[1]
    back += [
        *((lin[k], combined[k]) for k in range(3)),
        (norm2, lin[1] ** 2 + lin[2] ** 2),
        (disc, norm2 - lin[0] ** 2),
        # a slightly negative discriminant (where the two zeros meet) is clamped
        (root, tau * sp.sqrt(sp.Max(0, disc))),
        (cos_psi, (-lin[0] * lin[1] - root * lin[2]) / norm2),
        (sin_psi, (-lin[0] * lin[2] + root * lin[1]) / norm2),
    ]
    b1o = sp.Matrix(sp.symbols("b1o_x b1o_y b1o_z", real=True))
    b2o = sp.Matrix(sp.symbols("b2o_x b2o_y b2o_z", real=True))
    a2o = sp.Matrix([c12, s12, 0])
    z = sp.Matrix([0, 0, 1])
    b1_value = sp.Matrix([p1, rho1 * cos_phi, rho1 * sin_phi])
    b2_value = p2 * a2o + rho2 * (cos_psi * z.cross(a2o) + sin_psi * z)
    back += [*((b1o[k], b1_value[k]) for k in range(3)), *((b2o[k], b2_value[k]) for k in range(3))]
    # R = [x y z]: x along b1o, y along the part of b2o normal to it, z = x cross y (the platform
    # frame is canonical); normalised, so that R is a rotation for every real root, even one that
    # is not a configuration; such roots do not close
    x_axis = sp.Matrix(sp.symbols("x_axis1:4", real=True))
    y_axis = sp.Matrix(sp.symbols("y_axis1:4", real=True))
    x_norm, y_norm = sp.symbols("x_axis_norm y_axis_norm", real=True)
    back += [(x_norm, sp.sqrt(b1o.dot(b1o)))]
    back += [(x_axis[k], b1o[k] / x_norm) for k in range(3)]
    y_raw = b2o - x_axis.dot(b2o) * x_axis
    back += [(y_norm, sp.sqrt(y_raw.dot(y_raw)))]
    back += [(y_axis[k], y_raw[k] / y_norm) for k in range(3)]
    rotation = sp.Matrix.hstack(x_axis, y_axis, x_axis.cross(y_axis))
    start = sp.Matrix(3, 3, sp.symbols("R0_11 R0_12 R0_13 R0_21 R0_22 R0_23 R0_31 R0_32 R0_33", real=True))
    back += [(start[j, k], rotation[j, k]) for j in range(3) for k in range(3)]
    current = start
    for step in range(1, NEWTON_STEPS + 1):
        assignments, current = _cayley_newton(current, step)
        back += assignments
    return ForwardElimination(
        unknown=T_HALF,
        coefficients=elimination.coefficients,
        branches=[tau],
        auxiliary=auxiliary,
        back_substitution=back,
        pose=homogeneous(current, [0, 0, 0]),
        degeneracies={},
    )


# ---------------------------------------------------------------------------- closure and rates
def closure() -> ClosureModel:
    rotation = euler_rotation(alpha, beta, gamma)
    return ClosureModel(leg_equations(rotation), sp.Matrix([sp.Integer(1)]), homogeneous(rotation, [0, 0, 0]))


# section 5: the machine's configuration (root v3, branch (s1, s2) = (-, +)), XYX Euler angles,
# to full precision so that the home closes the loop (residual 4e-16; 8 digits left 7e-9)
HOME_EULER = (0.38623430068232256, 0.32043813812493704, -0.2199222510816914)


def drawing(parts: Drawing) -> Drawing:
    """The model's parts (base points A_i, platform points B_i = R b_ip, the legs A_i -> B_i, the
    base and platform triangles) with the centre Q on both bodies and the spokes from Q to the
    points of each body (the central spherical joint)."""
    centre = sp.zeros(3, 1)
    spokes = [0, 3, 1, 3, 2]  # A1 (B1) -> Q -> A2 (B2) -> Q -> A3 (B3)
    points = {name: sp.Matrix.hstack(parts.points[name], centre) for name in ("base", "platform")}
    polylines = parts.polylines | {
        "base_spokes": [("base", i) for i in spokes],
        "platform_spokes": [("platform", i) for i in spokes],
    }
    return Drawing(points=points, polylines=polylines)


def platform_frame(b1_printed: list[float], b2_printed: list[float]) -> list[list[float]]:
    """^B_P T from the printed b_1, b_2 (in {B}): x_p points from Q to B1 and y_p lies in the
    plane Q B1 B2 on B2's side (module docstring), so R = [x y z] is their Gram-Schmidt frame."""
    x_axis = sp.Matrix(b1_printed).normalized()
    y_raw = sp.Matrix(b2_printed) - x_axis.dot(sp.Matrix(b2_printed)) * x_axis
    y_axis = y_raw.normalized()
    pose = homogeneous(sp.Matrix.hstack(x_axis, y_axis, x_axis.cross(y_axis)), [0, 0, 0])
    return [[float(pose[i, j]) for j in range(4)] for i in range(4)]


def examples() -> list[Example]:
    """Section 5: the starting point d = (0.780, 0.570, 1.320) m, with 'four real roots' v1..v4 =
    0.98004, 0.83904, 0.91463, 0.96707 of eq (6), and the machine's configuration (v3) printed as
    b_1 = (2.278, 0.290, -0.698), b_2 = (2.000, 1.250, -0.454) m. Corrections (tests/test_sps.py):
    a3x = +2.720 (the printed -2.720 admits no configuration). The printed points agree with the
    configurations to 5.2e-3 m only: the paper's roots are off at the 1e-3 level (F(v3) = -1.2e-3
    on the printed data), so the pose built from b_1, b_2 holds to 5e-3, not to the 1e-3 digits."""
    return [
        Example(
            name="section5_starting_point",
            description="section 5 starting point d = (0.780, 0.570, 1.320) m (a3x = +2.720, the "
            "printed -2.720 is a typo): four real roots v1..v4 = 0.98004, 0.83904, 0.91463, 0.96707 "
            "(four assembly modes); the machine's configuration (v3) as the frame of the printed "
            "b_1 = (2.278, 0.290, -0.698), b_2 = (2.000, 1.250, -0.454) m, to 5e-3: the printed "
            "points are 5e-3 m off the data's configuration (the printed roots are off at 1e-3)",
            actuated=[0.780, 0.570, 1.320],
            expected={
                "mode_count": 4,
                "poses": [platform_frame([2.278, 0.290, -0.698], [2.000, 1.250, -0.454])],
            },
            tolerance=5e-3,
        )
    ]


def parameter_info() -> dict[sp.Symbol, ParameterInfo]:
    info = {
        a1x: ParameterInfo("m", "x of the base point A1 (on the x_b axis), section 5"),
        a2x: ParameterInfo("m", "x of the base point A2 (in the x_b y_b plane)"),
        a2y: ParameterInfo("m", "y of the base point A2 (> 0)", "positive"),
        a3x: ParameterInfo("m", "x of the base point A3 (printed -2.720: a typo for +2.720)"),
        a3y: ParameterInfo("m", "y of the base point A3"),
        a3z: ParameterInfo("m", "z of the base point A3"),
        b12: ParameterInfo("m", "distance between the platform points B1 and B2", "positive"),
        b23: ParameterInfo("m", "distance between the platform points B2 and B3", "positive"),
        b13: ParameterInfo("m", "distance between the platform points B1 and B3", "positive"),
        chi: ParameterInfo("", "platform handedness, the sign of det[b1p b2p b3p] (+1 or -1)", "sign"),
    }
    for i in range(3):
        info[(b1, b2, b3)[i]] = ParameterInfo(
            "m", f"distance |Q B{i + 1}| from the centre Q to the platform point", "positive"
        )
        info[stiffness[i]] = ParameterInfo(
            "N/m", f"stiffness of actuator {i + 1}, delta f = k delta d (section 4; f > 0 compresses)", "nonzero"
        )
    return info


def build() -> Mechanism:
    derived = model().fields()
    parameters: dict[sp.Symbol, float] = {
        a1x: 2.470,
        a2x: 2.250,
        a2y: 1.020,
        a3x: 2.720,  # printed -2.720 (typo)
        a3y: 0.130,
        a3z: -0.460,
        b1: 2.400,
        b2: 2.400,
        b3: 2.635,
        b12: 1.030,
        b23: 0.240,
        b13: 1.070,
        chi: -1.0,
    }
    parameters.update(zip(stiffness, (-7.7292e6, -2.30083e8, -1.0165e7), strict=True))
    return Mechanism(
        name="sps",
        title="3(SPS)-S spherical platform with three linear actuators (Knapczyk & Tora)",
        citation=Citation(
            ("J. Knapczyk", "G. Tora"),
            "Displacement and force analysis of the spherical platform mechanism 3(SPS)-S with compliancies of linear actuators taken into account",
        ),
        parameters=parameters,
        **derived | {"closure": closure(), "drawing": drawing(derived["drawing"])},  # type: ignore[arg-type]
        forward=forward(),
        home={
            **dict(zip(d, (0.780, 0.570, 1.320), strict=True)),
            **dict(zip((alpha, beta, gamma), HOME_EULER, strict=True)),
        },
        limits=dict(zip(d, STROKES, strict=True)),  # the actuator strokes (section 5)
        parameter_info=parameter_info(),
        examples=examples(),
        actuator_stiffness=list(stiffness),
    )
