"""The planar five-bar linkage (RRRRR) with its two base joints actuated, the example of Gosselin &
Angeles (1990) for the three kinds of singularity: the output point P is where the two distal
links meet.

Conventions (SI, radians; derivation: ``docs/derivations/five_bar.md``):
* {B}: the plane of motion z = 0; base joints A1 = (-d, 0, 0), A2 = (d, 0, 0).
* Leg i: proximal (actuated) link a_i at the angle theta_i from the x axis (counter-clockwise),
  elbow C_i = A_i + a_i (cos theta_i, sin theta_i, 0); distal link b_i from C_i to P = (x, y, 0).
* {P}: at P, R = I (pose_kind 'planar_translation'); passive x, y.
* Inverse branches: sigma_i = +1 puts elbow i outside; branch 0 (+, +) both elbows out, branch k
  the signs ``InversePose.branches[k]``. Validity ``leg<i>_reachable``. Type I
  ``leg<i>_links_aligned``, type II ``distal_links_aligned``.
* Forward pose: the two-circle intersection, a quadratic (accelerator ``_five_bar_forward.py``).
* Defaults (illustrative): d = 0.15, a1 = a2 = 0.2, b1 = b2 = 0.25 m; home P = (0, 0.33) m with
  the elbows out; at P = (0, 0.4) both proximal links are vertical (a 3-4-5 triangle).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import home_from_pose, leg_parameters, parameter_fields, pose_values, scalar_parameter
from parakin.generator.model import Citation, Example, Mechanism
from parakin.mechanisms._five_bar_forward import forward

d = sp.Symbol("d", positive=True)
a = sp.symbols("a1 a2", positive=True)
b = sp.symbols("b1 b2", positive=True)
theta = sp.symbols("theta1 theta2", real=True)
x, y = sp.symbols("x y", real=True)
PARAMETERS = parameter_fields(
    scalar_parameter(d, 0.15, "half the base length: the base joints are A1 = (-d, 0), A2 = (d, 0)", domain="positive"),
    leg_parameters(a, 0.2, "proximal (actuated) link {k} length |C{k} - A{k}|"),
    leg_parameters(b, 0.25, "distal link {k} length |P - C{k}|"),
)
#: s_i of the module docstring: sigma_i = +1 is the elbow outside for both legs
OUTSIDE = (1, -1)


#: the model: two R-R-R legs (cranks about z from the x axis, distal links) meeting at the output
#: point P, a platform that only translates in the plane; closure, rates, factors, inverse and
#: drawing are derived from it (the forward elimination is the accelerator's)
MODEL = joints.DistanceMechanism(
    joints.platform("planar_translation"),
    [
        joints.crank_leg([(-d, d)[i], 0, 0], [0, 0, 1], [1, 0, 0], a[i], b[i], [0, 0, 0], theta[i], sign=OUTSIDE[i])
        for i in range(2)
    ],
    parallel_name="distal_links_aligned",
)
#: the home configuration: P = (0, 0.33) m, elbows out, where proximal and distal links are
#: nearly perpendicular (det B near its largest) and the distal links meet at about 50 degrees
HOME_POINT = (0.0, 0.33)


def build() -> Mechanism:
    return Mechanism(
        name="five_bar",
        title="Planar five-bar linkage (RRRRR), two actuated base joints (Gosselin & Angeles 1990)",
        citation=Citation(
            ("C. Gosselin", "J. Angeles"),
            "Singularity analysis of closed-loop kinematic chains",
            1990,
            "IEEE Transactions on Robotics and Automation 6(3), pp. 281-290",
        ),
        **PARAMETERS,
        **MODEL.fields(),
        forward=forward(d, a, b, theta),
        home=home_from_pose(MODEL, pose_values(sp.eye(3), [*HOME_POINT, 0.0]), 0, PARAMETERS["parameters"]),
        examples=EXAMPLES,
    )


# Examples
HOME_Y = 0.4


#: branch 3 at P = (0, 0.4), by reflecting the home elbows across the lines A_i -> P
ELBOW_IN = 2 * math.atan2(0.4, 0.15) - math.pi / 2


HOME_POSE = pose_values(sp.eye(3), [0.0, HOME_Y, 0.0])


EXAMPLES = [
    Example(
        name="home_elbows_out",
        description="P = (0, 0.4) m at the defaults, branch 0: both proximal links vertical, theta = "
        "(pi/2, pi/2) (by hand: C1 = (-0.15, 0.2), |P - C1| = |(0.15, 0.2)| = 0.25 = b1, a 3-4-5 "
        "triangle; leg 2 by symmetry)",
        pose=HOME_POSE,
        branch=0,
        expected={"actuated": [math.pi / 2, math.pi / 2], "passive": [0.0, HOME_Y]},
        tolerance=1e-12,
    ),
    Example(
        name="home_elbows_in",
        description="the same P, branch 3 (both elbows in): the elbows reflected across the lines "
        "A_i -> P, by hand theta1 = 2 atan2(0.4, 0.15) - pi/2 = 0.8532 rad and theta2 = pi - theta1",
        pose=HOME_POSE,
        branch=3,
        expected={"actuated": [ELBOW_IN, math.pi - ELBOW_IN], "passive": [0.0, HOME_Y]},
        tolerance=1e-12,
    ),
    Example(
        name="proximal_vertical",
        description="theta = (pi/2, pi/2): elbows (-0.15, 0.2) and (0.15, 0.2), circles of radius "
        "0.25 m meeting at P = (0, 0.4) and (0, 0) (by hand: 0.15^2 + 0.2^2 = 0.25^2); 2 modes",
        actuated=[math.pi / 2, math.pi / 2],
        expected={"mode_count": 2, "poses": [HOME_POSE, pose_values(sp.eye(3), [0.0, 0.0, 0.0])]},
        tolerance=1e-12,
    ),
]
