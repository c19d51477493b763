"""The planar five-bar linkage (RRRRR) with its two base joints actuated, the example of Gosselin &
Angeles (1990) for the three kinds of singularity: the output point P is where the two distal
links meet.

Frames and conventions (SI, radians):
* {B}: the plane of motion is z = 0; base joints A1 = (-d, 0, 0) and A2 = (d, 0, 0) (d: half the
  base length), the y axis through their midpoint.
* Leg i: proximal (actuated) link of length a_i at the angle theta_i from the x axis (counter-
  clockwise, right-handed about z), elbow C_i = A_i + a_i (cos theta_i, sin theta_i, 0); distal
  link of length b_i from C_i to the output point P = (x, y, 0).
* {P}: origin at P, R = I (pose_kind 'planar_translation': ^B_P T = [I, (x, y, 0)]);
  ``inverse_pose`` also takes (x, y) and refuses a pose off the plane z = 0 or with a rotation.
* Passive variables (the Newton unknowns): x, y. Residual: (|P - C_i|^2 - b_i^2) / (2 b_i)
  (metres; |P - C_i| - b_i to first order), two rows; no false closure (alignment 1).
* Model: two R-R-R legs (``parakin.generator.joints.crank_leg``) meeting at P; closure, rates,
  factors, inverse and drawing (base joints, elbows C_i, P) are derived from them.
* Inverse: with v = P - A_i, leg i is E cos(theta_i) + F sin(theta_i) + G = 0, E = -2 a_i v_x,
  F = -2 a_i v_y, G = |v|^2 + a_i^2 - b_i^2, solved through its tan-half-angle quadratic:
  theta_i = angle(v) + s_i sigma_i gamma_i, gamma_i = acos((|v|^2 + a_i^2 - b_i^2) / (2 a_i |v|))
  the angle at A_i, with s_1 = +1 and s_2 = -1: sigma_i = +1 puts elbow i outside (leg 1 turned
  counter-clockwise from A1 -> P, leg 2 clockwise from A2 -> P). With P above the base line,
  branch 0 (+, +) is the usual '+-' working mode with both elbows out; branch k has the signs
  ``InversePose.branches[k]`` of (sigma1, sigma2). Validity ``leg<i>_reachable`` = (E^2 + F^2 -
  G^2) / (E^2 + F^2 + G^2), the discriminant (2 a_i |v|)^2 - G^2 made unitless (positive where
  |a_i - b_i| < |v| < a_i + b_i; the same tolerance at any size).
* Forward (two circles): with e = C2 - C1, w = |e|^2 and alpha = (w + b1^2 - b2^2) / (2 w),
  P = C1 + alpha e + mu J e / |e| (J: a quarter turn counter-clockwise) with mu^2 + alpha^2 w -
  b1^2 = 0: the forward polynomial is this quadratic in mu (degree 2; mu > 0: P to the left of
  C1 -> C2, the mode 'above' the elbows when C2 is right of C1). Degeneracy ``elbows_coincide``:
  |e| / (b1 + b2) (then the circles are concentric: no isolated solution, or a self-motion when
  b1 = b2).
* Rates: A (vx, vy) = B theta_dot from |P - C_i|^2 = b_i^2, with d_i = P - C_i: rows of A are
  d_i^T, B = diag(a_i d_i . (-sin theta_i, cos theta_i)). Type I (serial, det B = 0):
  ``leg<i>_links_aligned``, proximal and distal link i aligned (stretched or folded, the
  workspace boundary). Type II (det A = 0): ``distal_links_aligned``, d_1 x d_2 = 0.
* Defaults (illustrative): d = 0.15, a1 = a2 = 0.2, b1 = b2 = 0.25 m. At P = (0, 0.4) both
  proximal links are vertical (theta = pi/2): (d, 0.4 - a_i, b_i) = (0.15, 0.2, 0.25) is a 3-4-5
  triangle (the examples). The home configuration, P = (0, 0.33) with the elbows out, is better
  conditioned (at P = (0, 0.4), |P - A1| = 0.427 m is 0.023 m short of a1 + b1).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.frames import homogeneous, translation
from parakin.generator.model import (
    Citation,
    Example,
    ForwardElimination,
    Mechanism,
    ParameterInfo,
)

d = sp.Symbol("d", positive=True)
a = sp.symbols("a1 a2", positive=True)
b = sp.symbols("b1 b2", positive=True)
theta = sp.symbols("theta1 theta2", real=True)
x, y = sp.symbols("x y", real=True)
#: s_i of the module docstring: sigma_i = +1 is the elbow outside for both legs
OUTSIDE = (1, -1)


def base_point(i: int) -> sp.Matrix:
    return sp.Matrix([(-d, d)[i], 0])


def direction(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


def elbow(i: int, angle: sp.Expr) -> sp.Matrix:
    """C_i = A_i + a_i (cos theta_i, sin theta_i)."""
    return base_point(i) + a[i] * direction(angle)


#: the model: two R-R-R legs (cranks about z from the x axis, distal links) meeting at the output
#: point P, a platform that only translates in the plane; closure, rates, factors, inverse and
#: drawing are derived from it (the forward elimination below is written by hand)
MODEL = joints.DistanceMechanism(
    joints.platform("planar_translation"),
    [
        joints.crank_leg([(-d, d)[i], 0, 0], [0, 0, 1], [1, 0, 0], a[i], b[i], [0, 0, 0], theta[i], sign=OUTSIDE[i])
        for i in range(2)
    ],
    parallel_name="distal_links_aligned",
)


def forward() -> ForwardElimination:
    mu = sp.Symbol("mu", real=True)
    c1 = sp.Matrix(sp.symbols("C1_x C1_y", real=True))
    e = sp.Matrix(sp.symbols("e_x e_y", real=True))
    w, norm, alpha = sp.symbols("e_squared e_norm alpha", real=True)
    elbow2 = elbow(1, theta[1])
    auxiliary = [(c1[k], elbow(0, theta[0])[k]) for k in range(2)]
    auxiliary += [(e[k], elbow2[k] - c1[k]) for k in range(2)]
    auxiliary += [
        (w, e.dot(e)),
        (norm, sp.sqrt(w)),
        (alpha, (w + b[0] ** 2 - b[1] ** 2) / (2 * sp.Max(w, 1e-300))),
    ]
    quarter_turn = sp.Matrix([-e[1], e[0]])
    point = c1 + alpha * e + mu * quarter_turn / sp.Max(norm, 1e-300)
    return ForwardElimination(
        unknown=mu,
        coefficients=[alpha**2 * w - b[0] ** 2, sp.Integer(0), sp.Integer(1)],
        branches=[],
        auxiliary=auxiliary,
        back_substitution=[],
        pose=translation(point[0], point[1], 0),
        degeneracies={"elbows_coincide": norm / (b[0] + b[1])},
    )


HOME_Y = 0.4
#: the home configuration: P = (0, 0.33) m, elbows out, where proximal and distal links are
#: nearly perpendicular (det B near its largest) and the distal links meet at about 50 degrees
HOME_POINT = (0.0, 0.33)


def home() -> dict[sp.Symbol, float]:
    """theta_1 = angle(A1 -> P) + the angle at A1 (law of cosines); theta_2 = pi - theta_1 by
    the symmetry of the default geometry about the y axis."""
    values = {d: 0.15, a[0]: 0.2, b[0]: 0.25}
    px, py = HOME_POINT[0] + values[d], HOME_POINT[1]
    reach = math.hypot(px, py)
    inner = math.acos((reach**2 + values[a[0]] ** 2 - values[b[0]] ** 2) / (2 * values[a[0]] * reach))
    first = math.atan2(py, px) + inner
    return {theta[0]: first, theta[1]: math.pi - first, x: HOME_POINT[0], y: HOME_POINT[1]}


#: branch 3 at P = (0, 0.4), by reflecting the home elbows across the lines A_i -> P
ELBOW_IN = 2 * math.atan2(0.4, 0.15) - math.pi / 2


def pose_list(px: float, py: float) -> list[list[float]]:
    transform = homogeneous(sp.eye(3), [px, py, 0])
    return [[float(transform[i, j]) for j in range(4)] for i in range(4)]


EXAMPLES = [
    Example(
        name="home_elbows_out",
        description="P = (0, 0.4) m at the defaults, branch 0: both proximal links vertical, theta = "
        "(pi/2, pi/2) (by hand: C1 = (-0.15, 0.2), |P - C1| = |(0.15, 0.2)| = 0.25 = b1, a 3-4-5 "
        "triangle; leg 2 by symmetry)",
        pose=pose_list(0.0, HOME_Y),
        branch=0,
        expected={"actuated": [math.pi / 2, math.pi / 2], "passive": [0.0, HOME_Y]},
        tolerance=1e-12,
    ),
    Example(
        name="home_elbows_in",
        description="the same P, branch 3 (both elbows in): the elbows reflected across the lines "
        "A_i -> P, by hand theta1 = 2 atan2(0.4, 0.15) - pi/2 = 0.8532 rad and theta2 = pi - theta1",
        pose=pose_list(0.0, HOME_Y),
        branch=3,
        expected={"actuated": [ELBOW_IN, math.pi - ELBOW_IN], "passive": [0.0, HOME_Y]},
        tolerance=1e-12,
    ),
    Example(
        name="proximal_vertical",
        description="theta = (pi/2, pi/2): elbows (-0.15, 0.2) and (0.15, 0.2), circles of radius "
        "0.25 m meeting at P = (0, 0.4) and (0, 0) (by hand: 0.15^2 + 0.2^2 = 0.25^2); 2 modes",
        actuated=[math.pi / 2, math.pi / 2],
        expected={"mode_count": 2, "poses": [pose_list(0.0, HOME_Y), pose_list(0.0, 0.0)]},
        tolerance=1e-12,
    ),
]


def build() -> Mechanism:
    return Mechanism(
        name="five_bar",
        title="Planar five-bar linkage (RRRRR), two actuated base joints (Gosselin & Angeles 1990)",
        citation=Citation(
            ("C. Gosselin", "J. Angeles"),
            "Singularity analysis of closed-loop kinematic chains",
            1990,
            "IEEE Transactions on Robotics and Automation 6(3), pp. 281-290",
        ),
        parameters={d: 0.15, a[0]: 0.2, a[1]: 0.2, b[0]: 0.25, b[1]: 0.25},
        **MODEL.fields(),
        forward=forward(),
        home=home(),
        parameter_info={
            d: ParameterInfo("m", "half the base length: the base joints are A1 = (-d, 0), A2 = (d, 0)", "positive"),
            a[0]: ParameterInfo("m", "proximal (actuated) link 1 length |C1 - A1|", "positive"),
            a[1]: ParameterInfo("m", "proximal (actuated) link 2 length |C2 - A2|", "positive"),
            b[0]: ParameterInfo("m", "distal link 1 length |P - C1|", "positive"),
            b[1]: ParameterInfo("m", "distal link 2 length |P - C2|", "positive"),
        },
        examples=EXAMPLES,
    )
