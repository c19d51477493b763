"""6-RUS rotary hexapod: six legs, each an actuated revolute joint on the base turning a crank, a
universal joint at the crank tip, a rod of fixed length and a spherical joint on the platform
(Hunt 1983, the rotary-actuated variant of the 6-SPS; Merlet, "Parallel Robots", 2006). With the
cranks locked the forward pose is that of a general 6-6 Gough-Stewart platform on the crank tips
(40 complex assembly modes, all real for Dietmaier's geometry: example ``dietmaier_cranks``).

Conventions (SI, radians; derivation: ``docs/derivations/rus6.md``):
* {B}: motor i turns about the unit axis u_i (group ``axis``) through the shaft point A_i (group
  ``base``); its crank a_i points along e1_i (group ``crank_zero``, normal to u_i) at theta_i = 0
  and along u_i x e1_i at pi/2: E_i = A_i + a_i (cos theta_i e1_i + sin theta_i u_i x e1_i).
* {P}: platform joints c_i (group ``platform``), B_i = R c_i + p; the rod b_i joins E_i to B_i.
* Actuated theta1..theta6 in [-pi/2, pi/2]; passive p = (x, y, z) and the unit quaternion q0..q3
  (scalar first, q0 >= 0 from the inverse).
* Inverse branches: sigma_i = +1 turns the crank back from the line to its platform joint (the
  usual working mode); 64 combinations, branch 0 = all +1; validity ``leg<i>_reachable``. Type I
  ``leg<i>_rod_in_crank_axis_plane``, type II ``rod_lines_dependent``.
* Defaults (illustrative, a servo hexapod): motor pairs at 0, 120, 240 deg, shafts on a circle of
  0.4 m at +-10 deg, cranks 0.15 m, rods 0.6 m, platform joints on a circle of 0.3 m at +-50 deg;
  home R = I, p = (0, 0, HOME_Z) with every crank level (branch 0).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import (
    crank_bases,
    home_from_pose,
    leg_parameters,
    pair_sides,
    paired_circle_points,
    parameter_fields,
    point_defaults,
    point_group,
    pose_values,
)
from parakin.generator.model import Citation, Example, Mechanism
from parakin.mechanisms.stewart import (
    DIETMAIER_BASE,
    DIETMAIER_LENGTHS,
    DIETMAIER_PLATFORM,
    DIETMAIER_POSITION,
    DIETMAIER_ROTATION,
)

#: the default layout (module docstring): pair centres, shaft and platform-joint offsets
PAIR_CENTRES = (0.0, 120.0, 240.0)
SHAFT_RADIUS, SHAFT_OFFSET = 0.4, 10.0
PLATFORM_RADIUS, PLATFORM_OFFSET = 0.3, 50.0
CRANK, ROD = 0.15, 0.6
#: the crank range of the defaults
CRANK_RANGE = (-math.pi / 2, math.pi / 2)
#: motor axis u_i = side * (radial direction of the pair's centre); crank at theta = 0 along
#: e1_i = u_i x z = side * (tangent of the pair's centre)
AXES = [
    [side * math.cos(centre), side * math.sin(centre), 0.0] for centre, side in pair_sides(centres_deg=PAIR_CENTRES)
]
ZEROS = [
    [-side * math.sin(centre), side * math.cos(centre), 0.0] for centre, side in pair_sides(centres_deg=PAIR_CENTRES)
]

SHAFTS = paired_circle_points(SHAFT_RADIUS, centres_deg=PAIR_CENTRES, offset_deg=SHAFT_OFFSET)
JOINTS = paired_circle_points(PLATFORM_RADIUS, centres_deg=PAIR_CENTRES, offset_deg=PLATFORM_OFFSET)

BASE = point_group("base", SHAFTS, "motor shaft point A{k} (on the motor axis), in {B}")
AXIS = point_group("axis", AXES, "motor axis u{k} (unit vector; theta{k} right-handed about it), in {B}", unit="")
CRANK_ZERO = point_group(
    "crank_zero", ZEROS, "crank direction e1_{k} at theta{k} = 0 (unit, normal to u{k}), in {B}", ""
)
PLATFORM = point_group("platform", JOINTS, "platform joint c{k}, in {P}")
a = sp.symbols("a1:7", positive=True)
b = sp.symbols("b1:7", positive=True)
PARAMETERS = parameter_fields(
    BASE,
    AXIS,
    CRANK_ZERO,
    leg_parameters(a, CRANK, "crank {k} length |E{k} - A{k}|"),
    leg_parameters(b, ROD, "rod {k} length |B{k} - E{k}|"),
    PLATFORM,
)
theta = sp.symbols("theta1:7", real=True)
#: the home height: every crank level, R = I (module docstring)
HOME_Z = math.sqrt(ROD**2 - sum((JOINTS[0][k] - SHAFTS[0][k] - CRANK * ZEROS[0][k]) ** 2 for k in range(2)))

#: the model: six R-U-S legs (crank about u_i from e1_i, rod to c_i; branch sign +1 the crank
#: turned back about u_i) on a spatial platform; closure, rates, factors, inverse and drawing are
#: derived from it
MODEL = joints.DistanceMechanism(
    joints.platform("transform"),
    [
        joints.crank_leg(*leg, sign=-1, serial_name="leg{k}_rod_in_crank_axis_plane")
        for leg in zip(BASE.points, AXIS.points, CRANK_ZERO.points, a, b, PLATFORM.points, theta, strict=True)
    ],
    parallel_name="rod_lines_dependent",
)
HOME_POSE = pose_values(sp.eye(3), [0.0, 0.0, HOME_Z])


def build() -> Mechanism:
    return Mechanism(
        name="rus6",
        title="6-RUS rotary hexapod (Hunt 1983): six actuated cranks with rods to a spherical-jointed platform",
        citation=Citation(
            ("K. H. Hunt",),
            "Structural kinematics of in-parallel-actuated robot-arms",
            1983,
            "ASME Journal of Mechanisms, Transmissions, and Automation in Design 105(4), pp. 705-712",
        ),
        **PARAMETERS,
        **MODEL.fields(),
        forward=None,
        home=home_from_pose(MODEL, HOME_POSE, 0, PARAMETERS["parameters"]),
        limits=dict.fromkeys(theta, CRANK_RANGE),
        examples=EXAMPLES,
    )


# Examples
#: crank angle of the Dietmaier example (every leg)
DIETMAIER_THETA = math.pi / 6


#: A_i = X_i - a_i (cos t e1_i + sin t e2_i), t = DIETMAIER_THETA: the shafts that put the default
#: cranks' tips on Dietmaier's base points X_i at theta_i = t
DIETMAIER_SHAFTS = crank_bases(DIETMAIER_BASE, AXES, ZEROS, CRANK, DIETMAIER_THETA)
#: example ``dietmaier_cranks``: the parameters that differ from the defaults, by name
DIETMAIER_PARAMETERS = {
    **{str(k): v for k, v in point_defaults(BASE.symbols, DIETMAIER_SHAFTS).items()},
    **{str(k): v for k, v in point_defaults(PLATFORM.symbols, DIETMAIER_PLATFORM).items()},
    **{str(b[i]): DIETMAIER_LENGTHS[i] for i in range(6)},
}
DIETMAIER_POSE = pose_values(DIETMAIER_ROTATION, DIETMAIER_POSITION)


EXAMPLES = [
    Example(
        name="home_cranks_level",
        description="R = I, p = (0, 0, HOME_Z) at the defaults, branch 0: every crank level, theta = 0 "
        "(by construction: HOME_Z = sqrt(b^2 - h^2) = 0.5652 m, h = 0.2014 m the horizontal distance "
        "from a level crank tip to its platform joint, the same for every leg by symmetry)",
        pose=HOME_POSE,
        branch=0,
        expected={"actuated": [0.0] * 6, "passive": [0.0, 0.0, HOME_Z, 1.0, 0.0, 0.0, 0.0]},
        tolerance=1e-12,
    ),
    Example(
        name="dietmaier_cranks",
        description="Dietmaier's (1998) platform, rods and quoted pose on shafts placed so that theta = "
        "pi/6 puts every crank tip on Dietmaier's base point: the inverse gives theta = pi/6 on one "
        "branch (the printed lengths agree with the quoted pose to 4e-13 m); at these cranks the "
        "forward problem is Dietmaier's, with 40 real assembly modes (tests/test_rus6.py)",
        pose=DIETMAIER_POSE,
        parameters=DIETMAIER_PARAMETERS,
        expected={"actuated": [DIETMAIER_THETA] * 6},
        tolerance=1e-9,
    ),
    Example(
        name="dietmaier_40_cranks",
        description="theta = pi/6 on every crank with Dietmaier's shafts, rods and platform: Dietmaier's "
        "forward problem, 40 real assembly modes (stewart's homotopy gives the same 40 poses: "
        "tests/test_rus6.py), found from the polynomial form the generator derives from the closure",
        actuated=[DIETMAIER_THETA] * 6,
        parameters=DIETMAIER_PARAMETERS,
        expected={"mode_count": 40, "poses": [DIETMAIER_POSE]},
        tolerance=5e-6,
    ),
]
