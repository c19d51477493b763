"""The 3-RRR spherical parallel manipulator (SPM), with the parametrisation of Bai, Hansen and
Angeles (2009), as analysed in the ED5314 report (``shared/papers/001_cec8c69b51cbfe6d.txt``).

Conventions (SI, radians; derivation: ``docs/derivations/spm.md``):
* {B} and {P} at the centre of rotation; the pose is a rotation R (pose_kind 'rotation').
* eta_i = 2 pi (i - 1) / 3. Actuated axes u_i = Rz(eta_i) (0, sin gamma, -cos gamma); intermediate
  axes w_i = cos(alpha1) u_i + sin(alpha1) (cos(theta_i) e1_i + sin(theta_i) e2_i), e1_i =
  Rz(eta_i) (0, -cos gamma, -sin gamma), e2_i = u_i x e1_i (theta_i right-handed about u_i);
  platform axes v_i = R v0_i, v0_i = Rz(eta_i) (0, sin beta, cos beta). Leg closure: w_i . v_i =
  cos(alpha2); alpha1 the proximal link angle, alpha2 the distal one.
* Passive: the unit quaternion q0..q3 of R (scalar first).
* Inverse branches: sigma_i = +-1 in theta_i = atan2(B, A) + sigma_i acos(-C / sqrt(A^2 + B^2)),
  8 combinations (branch 0 = all +).
* Forward pose: a degree-8 resultant in x = tan((phi1 - 1/2) / 2) (accelerator ``_spm_forward.py``).
* Defaults: the report's example (section 3.2.3) with alpha1 and alpha2 swapped, the only reading
  with its "8 independent solutions": alpha1 = 45, alpha2 = 90, beta = 60, gamma = 45 deg
  (tests/test_spm.py). Home: R = I on inverse branch 0, regular and symmetric.
"""

from __future__ import annotations

import math
from dataclasses import replace

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import home_from_pose
from parakin.generator.frames import rot_z
from parakin.generator.model import Citation, Example, Mechanism, ParameterInfo
from parakin.mechanisms._spm_forward import Geometry, forward

alpha1, alpha2, beta, gamma = sp.symbols("alpha1 alpha2 beta gamma", positive=True)
theta = sp.symbols("theta1:4", real=True)
ETA = [2 * sp.pi * i / 3 for i in range(3)]


def base_axes(i: int) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """u_i, e1_i, e2_i (module docstring)."""
    turn = rot_z(ETA[i])
    u = turn * sp.Matrix([0, sp.sin(gamma), -sp.cos(gamma)])
    e1 = turn * sp.Matrix([0, -sp.cos(gamma), -sp.sin(gamma)])
    e2 = turn * sp.Matrix([-1, 0, 0])  # u x e1
    return u, e1, e2


def platform_axis(i: int) -> sp.Matrix:
    return rot_z(ETA[i]) * sp.Matrix([0, sp.sin(beta), sp.cos(beta)])


#: three R-R-R legs whose axes meet at the centre, as crank legs on the unit sphere (docs/derivations/spm.md)
MODEL = joints.DistanceMechanism(
    joints.platform("rotation"),
    [
        joints.crank_leg(
            sp.cos(alpha1) * base_axes(i)[0],
            base_axes(i)[0],
            base_axes(i)[1],
            sp.sin(alpha1),
            2 * sp.sin(alpha2 / 2),
            platform_axis(i),
            theta[i],
            serial_name="leg{k}_axes_coplanar",
            spherical=True,
        )  # fmt: skip
        for i in range(3)
    ],
    parallel_name="distal_plane_normals_coplanar",
)


def build() -> Mechanism:
    deg = sp.pi / 180
    parameters = {alpha1: float(45 * deg), alpha2: float(90 * deg), beta: float(60 * deg), gamma: float(45 * deg)}
    fields = MODEL.fields()
    # the Agile Eye's folded poses (a leg's axes coplanar) do not depend on the inputs: flagged
    fields["rates"] = replace(fields["rates"], input_independent=[f"leg{i + 1}_axes_coplanar" for i in range(3)])
    # drawn on the unit sphere: each leg from its actuated axis u_i (not the centre of w_i's circle)
    axes = sp.Matrix.hstack(*(base_axes(i)[0] for i in range(3)))
    fields["drawing"] = replace(fields["drawing"], points={**fields["drawing"].points, "base": axes})
    return Mechanism(
        name="spm",
        title="3-RRR spherical parallel manipulator (Bai, Hansen & Angeles 2009 parametrisation)",
        citation=Citation(
            ("V. R. Ashtekar",),
            "Forward and inverse kinematics of three degrees of freedom spherical parallel manipulators",
            None,
            "ED5314 course project report",
        ),
        parameters=parameters,
        **fields,
        forward=forward(Geometry(base_axes, platform_axis, theta, alpha1, alpha2, beta)),
        # home: the platform at R = I on inverse branch 0 (all sigma_i = +1), symmetric and far from
        # both singularity kinds
        home=home_from_pose(MODEL, sp.eye(3), 0, parameters),
        parameter_info={
            alpha1: ParameterInfo(
                "rad", "proximal link angle, between the actuated axis u_i and the intermediate axis w_i", "positive"
            ),
            alpha2: ParameterInfo(
                "rad", "distal link angle, between the intermediate axis w_i and the platform axis v_i", "positive"
            ),
            beta: ParameterInfo(
                "rad", "platform pyramid half-angle, between Z_P and each platform axis v0_i", "nonnegative"
            ),
            gamma: ParameterInfo(
                "rad", "base pyramid half-angle, between -Z_B and each actuated axis u_i", "nonnegative"
            ),
        },
        examples=EXAMPLES,
    )


# Examples
#: The report prints no numbers for the Agile Eye (alpha1 = alpha2 = 90 deg, beta = gamma =
#: atan(sqrt 2)); its input-independent modes are checked in tests/test_spm.py, not as an example.
EXAMPLES = [
    Example(
        name="section323",
        description="section 3.2.3: theta = (105, 60, 105) deg, the report's 'eight independent "
        "solutions' (section 3.2.1, Fig. 3); with the printed link labels swapped (alpha1 = 45 "
        "proximal, alpha2 = 90 deg distal, the defaults), the only reading with 8 real modes",
        actuated=[math.radians(105.0), math.radians(60.0), math.radians(105.0)],
        expected={"mode_count": 8},
        tolerance=0.0,
    )
]
