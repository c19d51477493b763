"""A planar 3-RPR: three legs of actuated length l_i from base joints A_i to platform joints c_i.

Frames and conventions (SI, radians): {B} with the plane of motion z = 0; the platform pose is
planar, ^B_P T = [Rot_z(phi), (x, y, 0)]; A_i in {B} and c_i in {P} are parameters; actuated
l1..l3 (m), passive x, y (m) and phi (rad).
"""

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import home_from_pose, parameter_fields, planar_pose_values, point_group
from parakin.generator.model import Citation, Example, Mechanism

base = point_group("base", [(0, 0), (1, 0), (0.5, 0.9)], "base joint A{k}, in {B}")
platform = point_group("platform", [(-0.2, -0.1), (0.2, -0.1), (0.15, 0.25)], "platform joint c{k}, in {P}")
lengths = sp.symbols("l1:4", positive=True)
MODEL = joints.DistanceMechanism(
    joints.platform("planar"),
    [joints.prismatic_leg(a, c, length) for a, c, length in zip(base.points, platform.points, lengths, strict=True)],
)
#: parameters, their defaults and meaning; groups pass whole: load(..., base=[[x, y], ...])
PARAMETERS = parameter_fields(base, platform)


def build() -> Mechanism:
    return Mechanism(
        name="my_robot",
        title="My planar 3-RPR",
        citation=Citation(("A. User",), "A planar 3-RPR described by its joints", 2026),
        **PARAMETERS,
        **MODEL.fields(),
        home=home_from_pose(MODEL, planar_pose_values(0.5, 0.3, 0.0), 0, PARAMETERS["parameters"]),
        limits={length: (0.0, 2.0) for length in lengths},
        examples=EXAMPLES,  # defined below, read when build() runs
    )


# Examples
EXAMPLES = [
    Example(
        name="home",
        description="the home pose (0.5, 0.3, 0): by hand C1 = (0.3, 0.2), C2 = (0.7, 0.2), "
        "C3 = (0.65, 0.55), so l1 = l2 = sqrt(0.13) m and l3 = sqrt(0.145) m",
        pose=planar_pose_values(0.5, 0.3, 0.0),
        branch=0,
        expected={"actuated": [math.sqrt(0.13), math.sqrt(0.13), math.sqrt(0.145)]},
        tolerance=1e-12,
    ),
]
