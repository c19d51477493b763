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
* Passive variables (the Newton unknowns): x, y. Residual: |P - C_i| - b_i (metres), two rows;
  no false closure (alignment 1).
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
from parakin.generator.blocks import half_angle_solution, laplace_det
from parakin.generator.frames import homogeneous, translation
from parakin.generator.model import (
    POSE_POSITION,
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


def distal(i: int) -> sp.Matrix:
    """d_i = P - C_i(theta_i), in the plane."""
    return sp.Matrix([x, y]) - elbow(i, theta[i])


def inverse() -> InverseSolution:
    sigma = list(sp.symbols("sigma1 sigma2", real=True))
    steps: list[tuple[sp.Symbol, sp.Expr]] = [(x, POSE_POSITION[0]), (y, POSE_POSITION[1])]
    validity = {}
    for i in range(2):
        e, f, g = sp.symbols(f"E{i + 1} F{i + 1} G{i + 1}", real=True)
        v = sp.Matrix([x, y]) - base_point(i)
        steps += [(e, -2 * a[i] * v[0]), (f, -2 * a[i] * v[1]), (g, v.dot(v) + a[i] ** 2 - b[i] ** 2)]
        # half_angle_solution's sign +1 turns the arm counter-clockwise from A_i -> P
        angle, discriminant = half_angle_solution(e, f, g, OUTSIDE[i] * sigma[i])
        steps.append((theta[i], angle))
        # relative to E^2 + F^2 + G^2 (a length^4, as the discriminant): a measure without unit, so
        # that the validity tolerance means the same for a five-bar of millimetres or of metres
        validity[f"leg{i + 1}_reachable"] = discriminant / (e**2 + f**2 + g**2)
    return InverseSolution(steps, sigma, validity)


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


def rates() -> tuple[RateModel, dict[str, sp.Expr]]:
    """d_i . P_dot = a_i (d_i . (-sin theta_i, cos theta_i)) theta_dot_i."""
    distals = [distal(i) for i in range(2)]
    diagonal = [a[i] * distals[i].dot(sp.diff(direction(theta[i]), theta[i])) for i in range(2)]
    matrix = sp.Matrix.vstack(*(v.T for v in distals))
    model = RateModel(
        twist=["vx", "vy"],
        a=matrix,
        b=sp.diag(*diagonal),
        serial_factors={f"leg{i + 1}_links_aligned": diagonal[i] for i in range(2)},
    )
    return model, {"distal_links_aligned": laplace_det(matrix)}


def closure() -> ClosureModel:
    residual = sp.Matrix([sp.sqrt(v.dot(v)) - b[i] for i, v in enumerate(distal(i) for i in range(2))])
    return ClosureModel(residual, sp.Matrix([sp.Integer(1)]), translation(x, y, 0))


def drawing() -> Drawing:
    """Base joints A_i, and the moving joints C1, C2 and P (in {B}, z = 0): each leg A_i -> C_i
    -> P and the base A1 -> A2. (A point set of one column would come out one-dimensional.)"""

    def lift(vector: sp.Matrix) -> sp.Matrix:
        return sp.Matrix([vector[0], vector[1], 0])

    return Drawing(
        points={
            "base": sp.Matrix.hstack(*(lift(base_point(i)) for i in range(2))),
            "moving": sp.Matrix.hstack(*(lift(elbow(i, theta[i])) for i in range(2)), sp.Matrix([x, y, 0])),
        },
        polylines={
            "base": [("base", 0), ("base", 1)],
            **{f"leg{i + 1}": [("base", i), ("moving", i), ("moving", 2)] for i in range(2)},
        },
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
    rate_model, parallel = rates()
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
        actuated=list(theta),
        passive=[x, y],
        legs=[],
        inverse=inverse(),
        forward=forward(),
        home=home(),
        angular=list(theta),
        parallel_factors=parallel,
        closure=closure(),
        rates=rate_model,
        pose_kind="planar_translation",
        parameter_info={
            d: ParameterInfo("m", "half the base length: the base joints are A1 = (-d, 0), A2 = (d, 0)", "positive"),
            a[0]: ParameterInfo("m", "proximal (actuated) link 1 length |C1 - A1|", "positive"),
            a[1]: ParameterInfo("m", "proximal (actuated) link 2 length |C2 - A2|", "positive"),
            b[0]: ParameterInfo("m", "distal link 1 length |P - C1|", "positive"),
            b[1]: ParameterInfo("m", "distal link 2 length |P - C2|", "positive"),
        },
        examples=EXAMPLES,
        drawing=drawing(),
    )
