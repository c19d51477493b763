"""Planar 3-RRR parallel manipulator: three legs, each an actuated revolute joint on the base
driving a crank, a passive revolute elbow, a link and a passive revolute joint on the platform
(Gosselin & Angeles 1988; Merlet, "Parallel Robots", 2006). With the cranks locked the forward pose
is that of a 3-RPR on the elbows: at most 6 assembly modes.

Conventions (SI, radians; derivation: ``docs/derivations/planar_3rrr.md``):
* {B}: the plane of motion z = 0; base joints A_i = (base_x<i>, base_y<i>, 0). Crank a_i at the
  angle theta_i from the x axis (counter-clockwise), elbow E_i = A_i + a_i (cos theta_i,
  sin theta_i, 0); link b_i from E_i to the platform joint B_i = p + R c_i.
* {P}: platform joints c_i = (platform_x<i>, platform_y<i>, 0). Pose planar: ^B_P T =
  [Rot_z(phi), (x, y, 0)]; the inverse reads x = px, y = py, phi = atan2(r21, r11); passive x, y, phi.
* Inverse branches: sigma_i = +1 the elbow to the left of A_i -> B_i; branch 0 = all +1; validity
  ``leg<i>_reachable``. Type I ``leg<i>_links_aligned``, type II ``link_lines_concurrent_or_parallel``.
* Forward pose: the generator's polynomial form (``forward=None``).
* Defaults (illustrative): base joints on a circle of 0.5 m, platform joints on one of 0.3 m, at
  210, 330 and 90 deg; cranks 0.3 m, links 0.35 m; home p = 0, phi = 0 on branch 0. The cranks
  theta = (-54, 174, -105) deg admit 6 real assembly modes (``SIX_MODES``).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import (
    circle_points,
    home_from_pose,
    leg_parameters,
    parameter_fields,
    planar_pose_values,
    point_group,
)
from parakin.generator.model import Citation, Example, Mechanism

#: the default geometry (module docstring): joints at 210, 330 and 90 degrees on two circles
JOINT_ANGLES = (210.0, 330.0, 90.0)
BASE_RADIUS, PLATFORM_RADIUS, CRANK, LINK = 0.5, 0.3, 0.3, 0.35
base = point_group(
    "base", circle_points(BASE_RADIUS, angles_deg=JOINT_ANGLES, dims=2), "base joint A{k} (crank axis), in {B}"
)
platform = point_group(
    "platform", circle_points(PLATFORM_RADIUS, angles_deg=JOINT_ANGLES, dims=2), "platform joint c{k}, in {P}"
)
a = sp.symbols("a1:4", positive=True)
b = sp.symbols("b1:4", positive=True)
PARAMETERS = parameter_fields(
    base,
    platform,
    leg_parameters(a, CRANK, "crank {k} length |E{k} - A{k}|"),
    leg_parameters(b, LINK, "link {k} length |B{k} - E{k}|"),
)
theta = sp.symbols("theta1:4", real=True)
X, Z = sp.Matrix([1, 0, 0]), sp.Matrix([0, 0, 1])
#: the home pose (x, y, phi) and its branch (module docstring)
HOME_POSE = (0.0, 0.0, 0.0)
HOME_BRANCH = 0
pose_list = planar_pose_values


#: the model: three R-R-R legs (an actuated crank about z from the x axis, a link) on a planar
#: platform; closure, rates, singularity factors, inverse and drawing are derived from it
MODEL = joints.DistanceMechanism(
    joints.platform("planar"),
    [joints.crank_leg(base.points[i], Z, X, a[i], b[i], platform.points[i], theta[i]) for i in range(3)],
    parallel_name="link_lines_concurrent_or_parallel",
)


def defaults() -> dict[sp.Symbol, float]:
    return dict(PARAMETERS["parameters"])


def home() -> dict[sp.Symbol, float]:
    """The inverse of HOME_POSE on HOME_BRANCH at the default geometry."""
    return home_from_pose(MODEL, pose_list(*HOME_POSE), HOME_BRANCH, defaults())


def build() -> Mechanism:
    return Mechanism(
        name="planar_3rrr",
        title="Planar 3-RRR parallel manipulator (Gosselin & Angeles 1988): three actuated cranks",
        citation=Citation(
            ("C. Gosselin", "J. Angeles"),
            "The optimum kinematic design of a planar three-degree-of-freedom parallel manipulator",
            1988,
            "ASME Journal of Mechanisms, Transmissions, and Automation in Design 110(1), pp. 35-41",
        ),
        **PARAMETERS,
        **MODEL.fields(),
        forward=None,
        home=home(),
        examples=EXAMPLES,
    )


# Examples
#: crank angles with 6 real assembly modes at the defaults, and those modes (x, y, phi), found
#: by a scan over phi polished by Newton (tests/test_planar_3rrr.py repeats it independently)
SIX_MODES_INPUT = [math.radians(-54.0), math.radians(174.0), math.radians(-105.0)]
SIX_MODES = [
    (-0.0633914913184828, -0.247787436524072, -0.837992137130137),
    (0.238213420821159, -0.100651144776091, -0.113264983674809),
    (-0.341310190669869, -0.330965073705309, -0.0340015587181958),
    (-0.229881224647207, 0.108128382939028, 0.58075102844872),
    (0.169458684891306, -0.370815903618212, 0.661504482043328),
    (-0.0244549608248963, -0.0982334363585854, 1.38545159861974),
]


EXAMPLES = [
    Example(
        name="six_modes_pose",
        description="Mode 3 of the six real assembly modes of theta = (-54, 174, -105) deg at the "
        "defaults (SIX_MODES: found by a numerical search, confirmed by an independent scan over phi "
        "in tests/test_planar_3rrr.py): its inverse has a valid branch with these crank angles",
        pose=pose_list(*SIX_MODES[3]),
        expected={"actuated": SIX_MODES_INPUT, "passive": list(SIX_MODES[3])},
        tolerance=1e-9,
    ),
    Example(
        name="six_real_modes",
        description="theta = (-54, 174, -105) deg at the defaults has 6 real assembly modes (the most a "
        "3-RRR can have; an independent scan over phi in tests/test_planar_3rrr.py), all of them found from "
        "the polynomial form the generator derives from the closure",
        actuated=SIX_MODES_INPUT,
        expected={"mode_count": 6, "poses": [pose_list(*mode) for mode in SIX_MODES]},
        tolerance=1e-9,
    ),
]
