"""Tricept (Neumann 1988; Siciliano 1999): three actuated U-P-S legs and a passive U-P leg that
constrains the platform.

Frames and conventions (SI, radians):
* {B}: origin at the passive leg's universal joint, z toward the platform. The actuated legs'
  universal joints A_i = r_b (cos eta_i, sin eta_i, 0), eta_i = 0, 120, 240 deg.
* {P}: origin at the platform's centre, where the passive leg is fixed, its line along z_P. The
  platform's spherical joints c_i = r_p (cos eta_i, sin eta_i, 0).
* The passive leg: a universal joint at the origin, first axis x_B, second axis on the leg
  (-y_P at the platform's zero orientation), a passive prismatic joint, the leg fixed to the
  platform: p = s R z_P, s > 0, and R = Rot_x(a) Rot_y(b) (no turn about the leg). Three
  degrees of freedom: the leg's two angles and its length; the platform's position fixes them.
* Actuated: the leg lengths l1..l3 = |p + R c_i - A_i|. Passive: the passive leg's joints a, b
  (radians) and s (metres), read from a pose as a = atan2(r32, r22), b = atan2(r13, r11),
  s = p . R z_P: the closure is the three lengths, the passive leg closed by construction.
* Inverse pose: each length; a pose the passive leg cannot take (p off the line along R z_P, or
  the platform turned about its leg) is invalid, ``leg4_line_reachable`` /
  ``leg4_u_joint_reachable`` naming it, and ``leg4_extension_reachable`` a leg pointing away.
* Defaults (illustrative): r_b = 0.3 m, r_p = 0.1 m; home: the platform level at s = 0.5 m.
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import radial_directions, universal_prismatic_platform
from parakin.generator.model import Citation, Example, Mechanism, ParameterInfo

r_b, r_p = sp.symbols("r_b r_p", positive=True)
lengths = sp.symbols("l1:4", positive=True)
RADIAL = radial_directions(3)  # (cos eta_i, sin eta_i, 0), eta_i = 0, 120, 240 deg, exactly
DEFAULTS = {r_b: 0.3, r_p: 0.1}
HOME_HEIGHT = 0.5

#: the platform's coordinates: the passive leg's universal joint's angles a (about x_B) and b
#: (about the leg's second axis) and its length s: R = Rot_x(a) Rot_y(b), p = s R z_P
a, b, s = sp.symbols("a b s", real=True)
MOTION = universal_prismatic_platform((a, b), s)

MODEL = joints.DistanceMechanism(
    MOTION,
    [
        *(
            joints.prismatic_leg(r_b * e, r_p * e, length, universal_axis=[0, 0, 1])
            for e, length in zip(RADIAL, lengths, strict=True)
        ),
        joints.passive_leg([0, 0, 0], [1, 0, 0], [0, 0, 0], [0, 0, 1]),
    ],
    parallel_name="platform_moves_with_legs_locked",
)


def build() -> Mechanism:
    home = MODEL.home_at(sp.eye(3), sp.Matrix([0, 0, HOME_HEIGHT]), 0, DEFAULTS)
    return Mechanism(
        name="tricept",
        title="Tricept: three U-P-S legs and a passive U-P leg fixed to the platform",
        citation=Citation(
            ("B. Siciliano",),
            "The Tricept robot: inverse kinematics, manipulability analysis and closed-loop direct kinematics "
            "algorithm",
            1999,
            "Robotica 17(4), pp. 437-445",
            "10.1017/S0263574799001678",
        ),
        parameters=dict(DEFAULTS),
        **MODEL.fields(),
        forward=None,
        home=home,
        limits={length: (0.2, 1.2) for length in lengths},
        parameter_info={
            r_b: ParameterInfo("m", "radius of the circle of the base universal joints A_i", "positive"),
            r_p: ParameterInfo("m", "radius of the circle of the platform spherical joints c_i", "positive"),
        },
        examples=EXAMPLES,
    )


# Examples
def tilted(a: float, b: float, s: float) -> list[list[float]]:
    """The pose of the passive leg's angles a (about x_B), b (about the leg's second axis) and its
    length s: R = Rot_x(a) Rot_y(b), p = s R z_P."""
    ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
    rotation = [[cb, 0.0, sb], [sa * sb, ca, -sa * cb], [-ca * sb, sa, ca * cb]]
    return [[*row, s * row[2]] for row in rotation] + [[0.0, 0.0, 0.0, 1.0]]


EXAMPLES = [
    Example(
        name="home",
        description="the platform level at p = (0, 0, 0.5): by hand every leg spans r_b - r_p = 0.2 m "
        "across and 0.5 m up, l = sqrt(0.29) = 0.5385164807 m",
        pose=tilted(0.0, 0.0, HOME_HEIGHT),
        branch=0,
        expected={"actuated": [math.sqrt(0.29)] * 3},
        tolerance=1e-12,
    ),
]
