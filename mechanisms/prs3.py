"""3-PRS parallel manipulator: three vertical rails, each carrying an actuated slider, a passive
revolute joint on the slider, a link of fixed length and a spherical joint on the platform. Three
degrees of freedom (the height and two tilts) with parasitic motion: the horizontal position and
the rotation about the vertical follow from them. The architecture of L.-W. Tsai, "Robot Analysis"
(1999), and of Carretero, Podhorodeski, Nahon & Gosselin (2000); the formulas are derived here
(``docs/derivations/prs3.md``, checked by tests/test_prs3.py), not copied from either text.

Conventions (SI, radians):
* {B}: z = k along the rails; rail i at A_i = r_b e_i, e_i = (cos theta_i, sin theta_i, 0),
  theta_i = 0, 120, 240 deg, tangent u_i = (-sin theta_i, cos theta_i, 0). {P}: c_i = r_p e_i.
* Actuated: the slider strokes d1..d3 (metres), S_i = A_i + d_i k, 0 <= d_i <= RAIL_LENGTH.
* Leg i: a revolute joint at S_i about u_i, a link of length L, a spherical joint at C_i = p + R c_i.
* Passive: p = (x, y, z) and the unit quaternion q0..q3 (scalar first); q and -q are one pose.
* Inverse pose (8 branches, sigma_i = +1: the link rises to the platform): it reads what the
  actuators control, the height z and the tilt n = R^T k (and the half-turn about the vertical
  nearer R), and returns the reachable pose with them (derived); x, y and the turn about the
  vertical are not read, off the set too (``unreachable="read"``). Validity ``leg<i>_reachable``.
* Forward pose: the generator's polynomial form, at most 16 assembly modes (``MODE_COUNTS``).
* Defaults (a compact design chosen here): r_b = 0.2 m, r_p = 0.1 m, L = 0.35 m, rails of 1 m;
  home: the platform level at z = 0.6 m, links rising (branch 0).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import home_from_pose, pose_values, radial_directions
from parakin.generator.frames import rot_y, rot_z
from parakin.generator.model import Citation, Example, Mechanism, ParameterInfo

r_b, r_p, L = sp.symbols("r_b r_p L", positive=True)
strokes = sp.symbols("d1:4", real=True)
DEFAULTS = {r_b: 0.2, r_p: 0.1, L: 0.35}
K = sp.Matrix([0, 0, 1])  # the rails' direction, the vertical of {B}
#: rail directions e_i at theta_i = 0, 120, 240 deg (exact) and their tangents u_i = k x e_i
RADIAL = radial_directions(3)
TANGENT = [K.cross(e) for e in RADIAL]
RAIL_LENGTH = 1.0  # the rails: 0 <= d_i <= RAIL_LENGTH (metres)
HOME_HEIGHT = 0.6  # the home: the platform level at this height (metres), links rising

#: three P-R-S legs; the inverse reads the reachable pose of the given height and tilt (derived)
MODEL = joints.DistanceMechanism(
    joints.platform("transform"),
    [
        joints.slider_leg(r_b * e, K, L, r_p * e, d, serial_name="leg{k}_link_horizontal", revolute_axis=u)
        for e, u, d in zip(RADIAL, TANGENT, strokes, strict=True)
    ],
    parallel_name="platform_moves_with_sliders_locked",
    unreachable="read",
)
LEVEL_POSE = pose_values(sp.eye(3), [0.0, 0.0, HOME_HEIGHT])


def build() -> Mechanism:
    return Mechanism(
        name="prs3",
        title="3-PRS parallel manipulator (vertical rails, 3 DOF with parasitic motion)",
        citation=Citation(
            ("M. Carretero", "R. P. Podhorodeski", "M. A. Nahon", "C. M. Gosselin"),
            "Kinematic analysis and optimization of a new three degree-of-freedom spatial parallel manipulator",
            2000,
            "Journal of Mechanical Design 122(1)",
        ),
        parameters=dict(DEFAULTS),
        **MODEL.fields(),
        forward=None,
        home=home_from_pose(MODEL, LEVEL_POSE, 0, DEFAULTS),
        limits={d: (0.0, RAIL_LENGTH) for d in strokes},
        parameter_info={
            r_b: ParameterInfo("m", "radius of the circle of the rails A_i (base)", "positive"),
            r_p: ParameterInfo("m", "radius of the circle of the spherical joints c_i (platform)", "positive"),
            L: ParameterInfo("m", "length of each link, revolute joint S_i to spherical joint C_i", "positive"),
        },
        examples=EXAMPLES,
    )


# Examples
#: a constructed input: the strokes of the reachable pose with Z-Y-Z Euler angles (30, 10, -30) deg
#: at z = 0.55 m, links rising (branch 0), computed by tests/test_prs3.py's own geometry
CONSTRUCTED_EULER = (math.radians(30.0), math.radians(10.0), 0.55)
CONSTRUCTED_STROKES = [0.20000812689943637, 0.214364266713217, 0.23008487353552343]
#: inputs and their number of real assembly modes (of 16 complex ones), counted by the independent
#: elimination of tests/test_prs3.py (a squarefree degree-16 polynomial, real roots isolated exactly)
MODE_COUNTS: dict[str, tuple[list[float], int]] = {
    "constructed_tilt": (CONSTRUCTED_STROKES, 16),  # every complex mode real
    "twelve_real_modes": ([0.25, 0.3, 0.35], 12),
    "six_real_modes": ([0.4, 0.2, 0.25], 6),
}
#: two other real modes of CONSTRUCTED_STROKES from that elimination (17 digits): the links hanging
#: below the sliders (branch 7), and the platform half-turned about the vertical (q0 = 0), links rising
LINKS_DOWN_MODE = [
    [0.9892231642773259, -0.0069971726555918155, 0.1462483190740409, -0.0003116859380161129],
    [-0.00699717265559172, 0.9954568830376479, 0.0949559560417258, 0.0006997172655592252],
    [-0.14624831907404087, -0.09495595604172606, 0.9846800473149738, -0.12035987059448745],
    [0.0, 0.0, 0.0, 1.0],
]
HALF_TURN_MODE = [
    [-0.9897143199003277, 0.008575136118405201, -0.14280067235409544, 0.00015683093072584955],
    [0.008575136118405054, -0.9928509385148458, -0.11905242933573329, -0.0008575136118402679],
    [-0.14280067235409538, -0.11905242933573337, 0.9825652584151744, 0.39652384979467187],
    [0.0, 0.0, 0.0, 1.0],
]
#: the level platform's strokes: its joints are r_b - r_p from the rails, d = z - sqrt(L^2 - (r_b - r_p)^2)
LEVEL_STROKE = HOME_HEIGHT - math.sqrt(DEFAULTS[L] ** 2 - (DEFAULTS[r_b] - DEFAULTS[r_p]) ** 2)


def euler_pose(alpha: float, beta: float, height: float) -> list[list[float]]:
    """The reachable pose with Z-Y-Z Euler angles (alpha, beta, -alpha) at ``height``, its centre
    x0 = r_p (cos beta - 1) cos(2 alpha) / 2, y0 = r_p (1 - cos beta) sin(2 alpha) / 2 (17 digits)."""
    x0 = DEFAULTS[r_p] * (math.cos(beta) - 1) * math.cos(2 * alpha) / 2
    y0 = DEFAULTS[r_p] * (1 - math.cos(beta)) * math.sin(2 * alpha) / 2
    return pose_values((rot_z(alpha) * rot_y(beta) * rot_z(-alpha)).evalf(17), [x0, y0, height])


EXAMPLES = [
    Example(
        "sixteen_real_modes",
        "The strokes of 'constructed_tilt': all 16 complex solutions real (counted by an exact "
        "elimination in tests/test_prs3.py), every one found from the polynomial form the generator "
        "derives from the closure",
        actuated=CONSTRUCTED_STROKES,
        expected={"mode_count": 16},
        tolerance=1e-9,
    ),
    Example(
        "level_home",
        "The platform level at z = 0.6 m: every stroke z - sqrt(L^2 - (r_b - r_p)^2) (its joints are "
        "r_b - r_p from the rails), links rising (branch 0); no parasitic motion",
        pose=LEVEL_POSE,
        branch=0,
        expected={"actuated": [LEVEL_STROKE] * 3, "passive": [0.0, 0.0, HOME_HEIGHT, 1.0, 0.0, 0.0, 0.0]},
        tolerance=1e-12,
    ),
    Example(
        "constructed_tilt",
        "Z-Y-Z Euler angles (30, 10, -30) deg at z = 0.55 m with its parasitic centre, links rising: "
        "the strokes of the test's own geometry (an input with 16 real modes, MODE_COUNTS)",
        pose=euler_pose(*CONSTRUCTED_EULER),
        branch=0,
        expected={"actuated": CONSTRUCTED_STROKES},
        tolerance=1e-12,
    ),
    Example(
        "constructed_links_down",
        "Another real mode of the constructed strokes (independent elimination): the links hang below "
        "the sliders (branch 7), the platform under the base plane",
        pose=LINKS_DOWN_MODE,
        expected={"actuated": CONSTRUCTED_STROKES},
        tolerance=1e-12,
    ),
    Example(
        "constructed_half_turn",
        "Another real mode of the constructed strokes (independent elimination): the platform "
        "half-turned about the vertical (q0 = 0), links rising; the inverse reads the half-turn from R",
        pose=HALF_TURN_MODE,
        expected={"actuated": CONSTRUCTED_STROKES},
        tolerance=1e-12,
    ),
]
