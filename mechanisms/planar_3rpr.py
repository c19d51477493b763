"""Planar 3-RPR parallel manipulator: three legs, each a passive revolute joint on the base, an
actuated prismatic joint and a passive revolute joint on the platform. Forward pose after Gosselin,
Sefrioui & Richard (1992) (also Hunt 1983, Merlet's "Parallel Robots"): a polynomial of degree 6
in t = tan(phi / 2), so at most 6 assembly modes.

Frames and conventions (SI, radians):
* {B}: the plane of motion is z = 0; base joints A_i = (base_x<i>, base_y<i>, 0) in {B}.
* {P}: platform joints b_i = (platform_x<i>, platform_y<i>, 0) in {P}. The pose is planar
  (pose_kind 'planar'): ^B_P T = [Rot_z(phi), (x, y, 0)]; ``inverse_pose`` also takes (x, y, phi).
  It reads x = px, y = py, phi = atan2(r21, r11) and nothing else of ^B_P T.
* Leg i joins A_i to B_i = p + R b_i; d_i = B_i - A_i; the actuated variables are the leg lengths
  rho_i = |d_i| (rho1..rho3, metres). Passive variables (the Newton unknowns): x, y, phi.
* Residual: (|d_i|^2 - rho_i^2) / (2 rho_i) (metres; |d_i| - rho_i to first order), one per leg,
  a polynomial whose Jacobian stays finite where a leg has zero length (|d_i| - rho_i has a 0 / 0
  derivative there, e.g. at a trial pose with B1 = A1); no false closure (alignment 1).
* Inverse: rho_i = |d_i|, one branch (no signs); validity ``leg<i>_length`` = rho_i > 0.
* Rates: A (vx, vy, wz) = B rho_dot with (vx, vy) the velocity of the origin of {P} and wz the
  angular rate, in {B}; row i of A = (d_x, d_y, ((A_i - p) x d_i) . z) (the planar Pluecker
  coordinates of leg line i, moment about the origin of {P}), B = diag(rho_i). det B = 0: a leg
  of zero length (serial factors ``leg<i>_length``); det A = 0: the three leg lines meet in one
  point or are parallel (type II, ``leg_lines_concurrent_or_parallel``).
* Forward pose (the classical elimination): with q = B1 - A1 = p + R b1 - A1, u_i = b_i - b1,
  w_i = A_i - A1 and m_i = R u_i - w_i (i = 2, 3), legs 2 and 3 minus leg 1 give the linear system
  m_i . q = g_i = (rho_i^2 - rho1^2 - |m_i|^2) / 2 in q (q is (x, y) up to the known shift
  R b1 - A1). Cramer: q = adj(M) g / det M. Leg 1, |q| = rho1, becomes |adj(M) g|^2 - rho1^2
  det(M)^2 = 0, of degree 4 in (cos phi, sin phi); times (1 + t^2)^4 a polynomial of degree 8 in
  t = tan(phi / 2), from which ``remove_spurious_factors`` divides the factor (1 + t^2) (the
  trigonometric polynomial has harmonic degree 3 only): degree 6. Back-substitution: phi =
  2 atan(t), q by Cramer, p = A1 + q - R b1. Every real root is one mode (no branch signs).
  Blind spots: a mode with phi = pi exactly is at t = infinity (the degree drops and the mode is
  not found), and a mode where det M = 0 (a root at which Cramer's rule fails) gives no pose.
  An example of the latter: congruent base and platform (b_i = A_i) have M = 0 at phi = 0, so
  t = 0 is a root for every input; with equal legs the platform translates on a circle there (a
  self-motion, not reported by forward_pose_all: ``m.self_motion`` traces it), otherwise that
  root is no mode.
* Degeneracies: ``cramer_determinant_vanishes_for_every_phi`` (det M = 0 identically in phi) and
  ``polynomial_vanishes_identically`` (every coefficient zero: a self-motion along which phi
  varies), both normalised by the size of the geometry and the inputs.
* Defaults: the example attributed to Gosselin, Sefrioui & Richard (1992) in the literature on
  the 3-RPR (e.g. Merlet, "Parallel Robots"), numbers as recalled, no unit given (read as
  metres): A1 = (0, 0), A2 = (15.91, 0), A3 = (0, 10); b1 = (0, 0), b2 = (17.04, 0), b3 =
  20.84 (cos 0.8824, sin 0.8824); rho = (14.98, 15.38, 12). These inputs have 6 real assembly
  modes (example ``six_real_modes``), checked by an independent scan of the leg-1 equation over
  phi in tests/test_planar_3rpr.py.
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import (
    as_points,
    half_angle_forms,
    planar_pose,
    point_defaults,
    point_info,
    point_parameters,
    remove_spurious_factors,
)
from parakin.generator.model import (
    Citation,
    Example,
    ForwardElimination,
    Mechanism,
)

base = point_parameters("base", 3, dims=2)
platform = point_parameters("platform", 3, dims=2)
rho = sp.symbols("rho1:4", positive=True)
x, y, phi = sp.symbols("x y phi", real=True)
PLANAR_TWIST = ("vx", "vy", "wz")

#: the Gosselin-Sefrioui-Richard example (module docstring): base points, platform points, inputs
GSR_BASE = [(0.0, 0.0), (15.91, 0.0), (0.0, 10.0)]
GSR_PLATFORM = [(0.0, 0.0), (17.04, 0.0), (20.84 * math.cos(0.8824), 20.84 * math.sin(0.8824))]
GSR_LENGTHS = [14.98, 15.38, 12.0]
#: the home pose (x, y, phi): one of the example's assembly modes, rounded
HOME_POSE = (-14.9, 1.6, 0.245)


#: the model: three R-P-R legs on a planar platform; closure, rates, singularity factors,
#: inverse and drawing are derived from it (the forward elimination below is written by hand)
MODEL = joints.DistanceMechanism(
    joints.platform("planar"),
    [joints.prismatic_leg(as_points(base)[i], as_points(platform)[i], rho[i]) for i in range(3)],
    parallel_name="leg_lines_concurrent_or_parallel",
)


def _linear_form(expr: sp.Expr, c: sp.Symbol, s: sp.Symbol) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(a0, a1, a2) with expr = a0 + a1 c + a2 s, for expr affine in c, s after c^2 + s^2 = 1."""
    reduced = sp.expand(sp.expand(expr).subs(c**2, 1 - s**2))
    poly = sp.Poly(reduced, c, s)
    if poly.total_degree() > 1:
        raise ValueError(f"not affine in (cos, sin): {expr}")
    return tuple(sp.expand(poly.coeff_monomial(m)) for m in (1, c, s))  # type: ignore[return-value]


def forward() -> ForwardElimination:
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


def home() -> dict[sp.Symbol, float]:
    """HOME_POSE and its leg lengths at the default geometry."""
    values = point_defaults(base, GSR_BASE) | point_defaults(platform, GSR_PLATFORM)
    pose = dict(zip((x, y, phi), HOME_POSE, strict=True))
    steps = dict(MODEL.inverse().steps)
    lengths = [float(steps[r].subs(values).subs(pose)) for r in rho]
    return dict(zip(rho, lengths, strict=True)) | pose


EXAMPLES = [
    Example(
        name="six_real_modes",
        description="Gosselin, Sefrioui & Richard (1992) as reproduced in the 3-RPR literature (the "
        "default geometry, numbers recalled, not re-read from the paper): rho = (14.98, 15.38, 12) "
        "has 6 real assembly modes, the most a 3-RPR can have; confirmed by an independent sign-change "
        "scan of the leg-1 equation over phi (tests/test_planar_3rpr.py)",
        actuated=GSR_LENGTHS,
        expected={"mode_count": 6},
        tolerance=0.0,
    )
]


def build() -> Mechanism:
    return Mechanism(
        name="planar_3rpr",
        title="Planar 3-RPR parallel manipulator (Gosselin, Sefrioui & Richard 1992: degree-6 forward polynomial)",
        citation=Citation(
            ("C. M. Gosselin", "J. Sefrioui", "M. J. Richard"),
            "Solutions polynomiales au probleme de la cinematique directe des manipulateurs paralleles plans "
            "a trois degres de liberte",
            1992,
            "Mechanism and Machine Theory 27(2)",
        ),
        parameters=point_defaults(base, GSR_BASE) | point_defaults(platform, GSR_PLATFORM),
        **MODEL.fields(),
        forward=forward(),
        home=home(),
        limits={r: (0.0, math.inf) for r in rho},
        parameter_info=point_info(base, "base joint A{k}, in {B}")
        | point_info(platform, "platform joint b{k}, in {P}"),
        parameter_groups={"base": base, "platform": platform},
        examples=EXAMPLES,
    )
