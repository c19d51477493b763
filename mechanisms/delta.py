"""The Delta robot (3-RUU, Clavel 1988): three actuated revolute joints on the base, each driving an
upper arm whose end is joined to the platform by a parallelogram forearm, so the platform only
translates. Closed forms as in the literature (e.g. R. L. Williams II, "The Delta parallel robot:
kinematics solutions", 2016; Zsombor-Murray 2004).

Conventions (SI, radians, textbook notation R, r, L, l; derivation: ``docs/derivations/delta.md``):
* {B}: origin at the base centre, z up; leg i at eta_i = 2 pi (i - 1) / 3, e_i = (cos eta_i,
  sin eta_i, 0), motor axis t_i = z x e_i through b_i = R e_i.
* Upper arm (length L) along u_i = cos(theta_i) e_i - sin(theta_i) z: theta_i = 0 horizontal and
  outward, theta_i > 0 down. Elbow c_i = b_i + L u_i.
* {P}: at the tool point, R = I always (pose_kind 'translation', p = (x, y, z)); platform joints
  P_i = p + r e_i; the forearm (length l, a parallelogram) joins c_i to P_i.
* Inverse branches: sigma_i = +1 the elbow outside (branch 0 = all +1, branch 7 = all -1);
  validity ``leg<i>_reachable``.
* Forward pose: the three-sphere intersection, a quadratic (accelerator ``_delta_forward.py``).
* Defaults (illustrative, a picking Delta): R = 0.2, r = 0.05, L = 0.35, l = 1.3 m; home p = (0, 0,
  -1.2) with every arm horizontal (a 5-12-13 triangle).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import pose_values, radial_directions
from parakin.generator.model import Citation, Example, Mechanism, ParameterInfo
from parakin.mechanisms._delta_forward import drawing, forward

R, r, L, ell = sp.symbols("R r L l", positive=True)  # ell: the forearm length, named l
theta = sp.symbols("theta1:4", real=True)
x, y, z = sp.symbols("x y z", real=True)
Z = sp.Matrix([0, 0, 1])
RADIAL = radial_directions(3)  # e_i = (cos eta_i, sin eta_i, 0), eta_i = 2 pi (i - 1) / 3

MODEL = joints.DistanceMechanism(
    joints.platform("translation"),
    [
        joints.crank_leg(
            R * e,
            Z.cross(e),
            e,
            L,
            ell,
            r * e,
            t,
            sign=-1,
            serial_name="leg{k}_forearm_in_arm_plane",
            parallelogram=Z.cross(e),
        )
        for e, t in zip(RADIAL, theta, strict=True)
    ],
    parallel_name="forearms_coplanar",
)


#: the home pose: arms horizontal, (R - r + L, -z, l) = (0.5, 1.2, 1.3), a 5-12-13 triangle
HOME_Z = -1.2


def build() -> Mechanism:
    return Mechanism(
        name="delta",
        title="Delta robot (3-RUU, Clavel 1988): translational platform, three-sphere forward pose",
        citation=Citation(
            ("R. Clavel",),
            "DELTA, a fast robot with parallel geometry",
            1988,
            "Proceedings of the 18th International Symposium on Industrial Robots, Lausanne, pp. 91-100",
        ),
        parameters={R: 0.2, r: 0.05, L: 0.35, ell: 1.3},
        **MODEL.fields() | {"drawing": drawing(MODEL.drawing(), sp.Matrix([x, y, z]))},
        forward=forward(RADIAL, R, r, L, ell, theta),
        home={**dict.fromkeys(theta, 0.0), x: 0.0, y: 0.0, z: HOME_Z},
        parameter_info={
            R: ParameterInfo("m", "base radius: distance from the base centre to each motor joint b_i", "positive"),
            r: ParameterInfo(
                "m", "platform radius: distance from the tool point to each platform joint P_i", "positive"
            ),
            L: ParameterInfo("m", "upper arm length |c_i - b_i| (the actuated link)", "positive"),
            ell: ParameterInfo("m", "forearm (parallelogram) length |P_i - c_i|", "positive"),
        },
        examples=EXAMPLES,
    )


# Examples
FOLDED = -2 * math.atan(8.0)
HOME_POSE = pose_values(sp.eye(3), [0.0, 0.0, HOME_Z])


EXAMPLES = [
    Example(
        name="home_elbows_out",
        description="p = (0, 0, -1.2) m at the defaults, branch 0: every arm horizontal, theta = 0 "
        "(by hand: R - r + L = 0.5, and 0.5^2 + 1.2^2 = 1.3^2 = l^2, a 5-12-13 triangle)",
        pose=HOME_POSE,
        branch=0,
        expected={"actuated": [0.0, 0.0, 0.0], "passive": [0.0, 0.0, HOME_Z]},
        tolerance=1e-12,
    ),
    Example(
        name="home_elbows_in",
        description="the same pose, branch 7 (every elbow in): by hand, leg 1 has a = (-0.15, 0, "
        "-1.2), E = 0.105, F = -0.84, G = -0.105, so the quadratic (G - E) tau^2 + 2 F tau + "
        "(G + E) = -0.21 tau^2 - 1.68 tau = 0 gives tau = 0 (branch 0) and tau = -8: theta = "
        "-2 atan(8) = -2.8929 rad on every leg (symmetry)",
        pose=HOME_POSE,
        branch=7,
        expected={"actuated": [FOLDED, FOLDED, FOLDED], "passive": [0.0, 0.0, HOME_Z]},
        tolerance=1e-12,
    ),
    Example(
        name="arms_horizontal",
        description="theta = (0, 0, 0): the shifted elbows lie on the circle of radius 0.5 m at z = 0, "
        "so p = (0, 0, -1.2) or its mirror (0, 0, 1.2) (by hand: 1.3^2 - 0.5^2 = 1.2^2); 2 modes",
        actuated=[0.0, 0.0, 0.0],
        expected={"mode_count": 2, "poses": [HOME_POSE, pose_values(sp.eye(3), [0.0, 0.0, -HOME_Z])]},
        tolerance=1e-12,
    ),
]
