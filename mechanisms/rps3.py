"""3-RPS parallel manipulator (Lee and Shah 1988): three legs, each a revolute joint on the base
whose axis is tangent to the base circle, an actuated prismatic joint and a spherical joint on
the platform. Three degrees of freedom, the height and two tilts, with parasitic motion (the
platform's centre moves sideways as it tilts); the forward pose has 16 complex solutions.

Frames and conventions (SI, radians):
* {B}: base joints A_i = r_b e_i, e_i = (cos eta_i, sin eta_i, 0), eta_i = 90, 210, 330 deg; the
  revolute axis of leg i is the tangent u_i = (-sin eta_i, cos eta_i, 0): leg i stays in the
  vertical plane through A_i normal to u_i.
* {P}: platform joints c_i = r_p e_i.
* Actuated: the leg lengths l1..l3 = |C_i - A_i| (metres). Passive: the platform position x, y,
  z and its unit quaternion q0..q3 (scalar first, q0 >= 0 from the inverse).
* Inverse pose: reads the height z and the tilt R^T k (the controlled coordinates) and returns
  the reachable pose with them, the given pose where it is reachable; a pose off the set is
  invalid, ``leg<i>_plane_reachable`` naming the legs whose joints leave their planes.
* Forward pose: the generator's automatic homotopy, 32 paths (16 poses, each with its two
  quaternion signs).
* Defaults (illustrative): r_b = 1 m, r_p = 0.5 m; home: the platform level at z = 1 m.
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import pose_values, radial_directions
from parakin.generator.model import Citation, Example, Mechanism, ParameterInfo

r_b, r_p = sp.symbols("r_b r_p", positive=True)
lengths = sp.symbols("l1:4", positive=True)
#: leg directions at 90, 210, 330 deg (exact) and their tangents z x e_i, the revolute axes
RADIAL = radial_directions(3, start=sp.pi / 2)
TANGENT = [sp.Matrix([0, 0, 1]).cross(e) for e in RADIAL]
DEFAULTS = {r_b: 1.0, r_p: 0.5}
HOME_HEIGHT = 1.0

MODEL = joints.DistanceMechanism(
    joints.platform("transform"),
    [
        joints.prismatic_leg(r_b * e, r_p * e, length, revolute_axis=u)
        for e, u, length in zip(RADIAL, TANGENT, lengths, strict=True)
    ],
    parallel_name="platform_moves_with_legs_locked",
)


def build() -> Mechanism:
    home = MODEL.home_at(sp.eye(3), sp.Matrix([0, 0, HOME_HEIGHT]), 0, DEFAULTS)
    return Mechanism(
        name="rps3",
        title="3-RPS parallel manipulator (Lee and Shah 1988): height and two tilts, parasitic motion",
        citation=Citation(
            ("K.-M. Lee", "D. K. Shah"),
            "Kinematic analysis of a three-degrees-of-freedom in-parallel actuated manipulator",
            1988,
            "IEEE Journal on Robotics and Automation 4(3), pp. 354-360",
            "10.1109/56.796",
        ),
        parameters=dict(DEFAULTS),
        **MODEL.fields(),
        forward=None,
        home=home,
        limits={length: (0.25, 3.0) for length in lengths},
        parameter_info={
            r_b: ParameterInfo("m", "radius of the circle of the base revolute joints A_i", "positive"),
            r_p: ParameterInfo("m", "radius of the circle of the platform spherical joints c_i", "positive"),
        },
        examples=EXAMPLES,
    )


# Examples
EXAMPLES = [
    Example(
        name="home",
        description="the platform level at p = (0, 0, 1): by hand every leg spans r_b - r_p = 0.5 m "
        "across and 1 m up, l = sqrt(1.25) = 1.1180339887 m",
        pose=pose_values(sp.eye(3), [0.0, 0.0, HOME_HEIGHT]),
        branch=0,
        expected={"actuated": [math.sqrt(1.25)] * 3},
        tolerance=1e-12,
    ),
]
