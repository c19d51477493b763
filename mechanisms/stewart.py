"""General 6-6 Gough-Stewart platform (6-SPS / 6-UPS): six base points, six platform points, any
3-D geometry. Defaults: Dietmaier's geometry with 40 real assembly modes (P. Dietmaier, "The
Stewart-Gough platform of general geometry can have 40 real postures", Advances in Robot
Kinematics, 1998), as quoted with its pose by the issue that added this file.

Conventions (SI, radians; derivation: ``docs/derivations/stewart.md``):
* {B}: base points A_i (parameter group ``base``, 6 x 3); {P}: platform points b_i (group
  ``platform``, 6 x 3). Pose ^B_P T = (R, p); actuated leg lengths l_i = |R b_i + p - A_i|.
* Passive: p = (x, y, z) and the unit quaternion q0..q3 of R (scalar first; q0 >= 0 from the
  inverse). Type II singularity ``leg_lines_dependent``.
* Forward pose: every assembly mode by a parameter homotopy on the Study-coordinate quadrics
  (accelerator ``_stewart_forward.py``), 40 for a general geometry.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import parameter_fields, point_group
from parakin.generator.frames import quaternion_from_rotation
from parakin.generator.model import Citation, Example, Mechanism
from parakin.mechanisms._stewart_forward import forward

lengths = sp.symbols("l1:7", positive=True)
x, y, z = sp.symbols("x y z", real=True)
quaternion = sp.symbols("q0:4", real=True)

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
BASE_POINTS = point_group("base", DIETMAIER_BASE, "base joint A{k}, in {B}")
PLATFORM_POINTS = point_group("platform", DIETMAIER_PLATFORM, "platform joint b{k}, in {P}")
BASE, PLATFORM = BASE_POINTS.symbols, PLATFORM_POINTS.symbols
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
    [joints.prismatic_leg(BASE_POINTS.points[k], PLATFORM_POINTS.points[k], lengths[k]) for k in range(6)],
)


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
        **parameter_fields(BASE_POINTS, PLATFORM_POINTS),
        **MODEL.fields(),
        forward=forward(BASE, PLATFORM, lengths),
        home={
            **dict(zip(lengths, DIETMAIER_LENGTHS, strict=True)),
            **dict(zip((x, y, z), DIETMAIER_POSITION, strict=True)),
            **{q: float(v) for q, v in zip(quaternion, home_quaternion.evalf(17), strict=True)},
        },
        limits={length: (0.0, float("inf")) for length in lengths},
        examples=EXAMPLES,
    )


# Examples
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


EXAMPLES = examples()
