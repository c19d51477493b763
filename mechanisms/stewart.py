"""General 6-6 Gough-Stewart platform (6-SPS / 6-UPS): six base points, six platform points, any
3-D geometry. Defaults: Dietmaier's geometry with 40 real assembly modes (P. Dietmaier, "The
Stewart-Gough platform of general geometry can have 40 real postures", Advances in Robot
Kinematics, 1998), as quoted with its pose by the issue that added this file.

Frames and conventions (SI, radians):
* {B}: base frame, base points A_i (parameter group ``base``, 6 x 3, in {B}); {P}: platform frame,
  platform points b_i (group ``platform``, 6 x 3, in {P}). Pose ^B_P T = (R, p); leg vector
  d_i = R b_i + p - A_i (Dietmaier's R x_i + t - X_i), actuated leg lengths l_i = |d_i|.
* Passive variables (the Newton unknowns): the position p = (x, y, z) of the origin of {P} and the
  unit quaternion q = (q0, q1, q2, q3) of R (scalar first, R(q) v = q v q* / |q|^2). The closure
  is square: six leg residuals (d_i . d_i - l_i^2) / (2 l_i) (metres; |d_i| - l_i to first order)
  and the normalisation (q . q - 1) / 2. Newton steps in (p, q) have no parametrisation
  singularity (Euler angles have one at beta = +-pi/2): the closure Jacobian is singular only at
  type II singularities. q and -q are the same pose; the inverse returns q0 >= 0.
* Rates: A twist = diag(l) l_dot with row i of A the Pluecker coordinates (d_i ; (A_i - p) x d_i)
  of leg line i (twist = (v of the origin of {P}, w), both in {B}); det A = 0 is the type II
  singularity (``leg_lines_dependent``), l_i = 0 the serial one.
* Forward pose (every assembly mode): the Study coordinates (e, g) of the pose, R = R(e) and
  p = 2 vec(g e*) / (e . e), with the Study quadric e . g = 0 turn each leg equation times
  e . e into a quadric in (e, g) (Wampler 1996; Husty 1996):
  (e.e)(|b_i|^2 + |A_i|^2 - l_i^2) + 4 g.g + 4 <g, e b_i> - 2 A_i . vec(e b_i e*) - 4 A_i . vec(g e*) = 0
  (<,> the 4-D inner product, products of quaternions). Seven homogeneous quadrics in the eight
  (e, g) have 40 isolated solutions for a general geometry (Raghavan; Ronga and Vust; Lazard;
  Mourrain), found by a parameter homotopy from a generic complex instance solved at generation
  time (``ForwardHomotopy``).
"""

from __future__ import annotations

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import point_defaults, point_info, point_parameters
from parakin.generator.frames import (
    pure_quaternion,
    quaternion_conjugate,
    quaternion_from_rotation,
    quaternion_product,
    quaternion_rotation_unnormalised,
)
from parakin.generator.model import (
    Citation,
    Example,
    ForwardHomotopy,
    Mechanism,
)

BASE = point_parameters("base", 6)
PLATFORM = point_parameters("platform", 6)
lengths = sp.symbols("l1:7", positive=True)
x, y, z = sp.symbols("x y z", real=True)
quaternion = sp.symbols("q0:4", real=True)
study_e = sp.symbols("e0:4")
study_g = sp.symbols("g0:4")

#: Dietmaier (1998): base points X_i, platform points x_i, leg lengths with 40 real modes
DIETMAIER_BASE = [
    [0.0, 0.0, 0.0],
    [1.107915, 0.0, 0.0],
    [0.549094, 0.756063, 0.0],
    [0.735077, -0.223935, 0.525991],
    [0.514188, -0.526063, -0.368418],
    [0.590473, 0.094733, -0.205018],
]
DIETMAIER_PLATFORM = [
    [0.0, 0.0, 0.0],
    [0.542805, 0.0, 0.0],
    [0.956919, -0.528915, 0.0],
    [0.665885, -0.353482, 1.402538],
    [0.478359, 1.158742, 0.107672],
    [-0.137087, -0.235121, 0.353913],
]
DIETMAIER_LENGTHS = [1.0, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071]
#: one of the 40 modes, as quoted (15 digits)
DIETMAIER_ROTATION = [
    [-0.040450357031281, -0.932229494397471, 0.359599691867884],
    [0.983337493748685, 0.026695523074364, 0.179818582009314],
    [-0.177231887661606, 0.360881585597300, 0.915616371179918],
]
DIETMAIER_POSITION = [0.955868038233880, -0.046995628998516, -0.290013283037649]


#: the model: six S-P-S legs on a spatial platform (x, y, z, unit quaternion q0..q3); closure,
#: rates, singularity factor, inverse and drawing are derived from it
MODEL = joints.DistanceMechanism(
    joints.platform("transform"),
    [joints.prismatic_leg(BASE.row(k).T, PLATFORM.row(k).T, lengths[k]) for k in range(6)],
)


def study_leg_equation(base: sp.Matrix, platform: sp.Matrix, length: sp.Expr) -> sp.Expr:
    """Leg |R b + p - A|^2 = l^2 times e . e in Study coordinates (module docstring)."""
    e, g = sp.Matrix(study_e), sp.Matrix(study_g)
    norm = e.dot(e)
    e_b = quaternion_product(e, pure_quaternion(platform))
    rotated = quaternion_rotation_unnormalised(e) * platform  # vec(e b e*)
    translated = quaternion_product(g, quaternion_conjugate(e))[1:, 0]  # vec(g e*)
    constant = platform.dot(platform) + base.dot(base) - length**2
    return norm * constant + 4 * g.dot(g) + 4 * g.dot(e_b) - 2 * base.dot(rotated) - 4 * base.dot(translated)


def forward() -> ForwardHomotopy:
    e, g = sp.Matrix(study_e), sp.Matrix(study_g)
    rows = [BASE.row(k).T for k in range(6)], [PLATFORM.row(k).T for k in range(6)]
    equations = [e.dot(g)] + [study_leg_equation(a, b, n) for a, b, n in zip(*rows, lengths, strict=True)]
    norm = e.dot(e)
    position = 2 * quaternion_product(g, quaternion_conjugate(e))[1:, 0] / norm
    passive = list(position) + [c / sp.sqrt(norm) for c in e]
    return ForwardHomotopy(list(study_e) + list(study_g), equations, list(study_e), passive)


def examples() -> list[Example]:
    pose = [row + [t] for row, t in zip(DIETMAIER_ROTATION, DIETMAIER_POSITION, strict=True)] + [[0, 0, 0, 1]]
    return [
        Example(
            "dietmaier_40",
            "Dietmaier (1998): leg lengths with 40 real assembly modes, among them the quoted pose",
            actuated=DIETMAIER_LENGTHS,
            expected={"mode_count": 40, "poses": [pose]},
            tolerance=5e-6,  # the lengths are printed to 6 decimals
        ),
        Example(
            "dietmaier_pose",
            "The quoted pose of Dietmaier's example: its leg lengths are the printed ones",
            pose=pose,
            expected={"actuated": DIETMAIER_LENGTHS},
            tolerance=5e-7,
        ),
    ]


def build() -> Mechanism:
    home_quaternion = quaternion_from_rotation(sp.Matrix(DIETMAIER_ROTATION))
    return Mechanism(
        name="stewart",
        title="General 6-6 Gough-Stewart platform (6-SPS), every assembly mode by homotopy",
        citation=Citation(
            ("P. Dietmaier",),
            "The Stewart-Gough platform of general geometry can have 40 real postures",
            1998,
            "Advances in Robot Kinematics: Analysis and Control",
        ),
        parameters={**point_defaults(BASE, DIETMAIER_BASE), **point_defaults(PLATFORM, DIETMAIER_PLATFORM)},
        **MODEL.fields(),
        forward=forward(),
        home={
            **dict(zip(lengths, DIETMAIER_LENGTHS, strict=True)),
            **dict(zip((x, y, z), DIETMAIER_POSITION, strict=True)),
            **{q: float(v) for q, v in zip(quaternion, home_quaternion.evalf(17), strict=True)},
        },
        limits={length: (0.0, float("inf")) for length in lengths},
        parameter_info={
            **point_info(BASE, "base joint A{k}, in {B}"),
            **point_info(PLATFORM, "platform joint b{k}, in {P}"),
        },
        parameter_groups={"base": BASE, "platform": PLATFORM},
        examples=examples(),
    )
