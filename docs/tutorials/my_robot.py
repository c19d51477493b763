"""A planar 3-RPR: three legs of actuated length l_i from base joints A_i to platform joints c_i.

Frames and conventions (SI, radians): {B} with the plane of motion z = 0; the platform pose is
planar, ^B_P T = [Rot_z(phi), (x, y, 0)]; A_i in {B} and c_i in {P} are parameters; actuated
l1..l3 (m), passive x, y (m) and phi (rad).
"""

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import as_points, point_defaults, point_parameters
from parakin.generator.model import Citation, Mechanism

base = point_parameters("base", 3, dims=2)
platform = point_parameters("platform", 3, dims=2)
lengths = sp.symbols("l1:4", positive=True)
MODEL = joints.DistanceMechanism(
    joints.platform("planar"),
    [joints.prismatic_leg(as_points(base)[i], as_points(platform)[i], lengths[i]) for i in range(3)],
)
DEFAULTS = point_defaults(base, [(0, 0), (1, 0), (0.5, 0.9)])
DEFAULTS |= point_defaults(platform, [(-0.2, -0.1), (0.2, -0.1), (0.15, 0.25)])


def build() -> Mechanism:
    return Mechanism(
        name="my_robot",
        title="My planar 3-RPR",
        citation=Citation(("A. User",), "A planar 3-RPR described by its joints", 2026),
        parameters=DEFAULTS,
        parameter_groups={"base": base, "platform": platform},  # load(..., base=[[x, y], ...])
        **MODEL.fields(),
        home=MODEL.home_at(sp.eye(3), sp.Matrix([0.5, 0.3, 0]), 0, DEFAULTS),
        limits={length: (0.0, 2.0) for length in lengths},
    )
