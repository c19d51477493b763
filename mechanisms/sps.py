"""The 3(SPS)-S spherical platform of Knapczyk and Tora (``shared/papers/002_91f1e7509f31240b.txt``):
an orienting platform on a central spherical joint Q, driven by three linear actuators A_i B_i.

Conventions (SI, radians; section 2 of the paper; derivation: ``docs/derivations/sps.md``):
* {B} and {P} at Q (pose_kind 'rotation'). x_b from Q to A1, y_b in the plane Q A1 A2 (A2 on its
  +y side): a1 = (a1x, 0, 0), a2 = (a2x, a2y, 0), a3 = (a3x, a3y, a3z). x_p from Q to B1, y_p in
  the plane Q B1 B2: the platform points b_ip follow from |QB_i| = b_i and |B_i B_j| = b_ij (eq 1c)
  up to the handedness chi = sign det[b1p b2p b3p] (chi = -1: the paper's printed b_3).
* Orientation R = Rx(alpha) Ry(beta) Rx(gamma) (eq 9, X'-Y'-X'); passive (alpha, beta, gamma);
  inverse branch sigma = sign(sin beta), sin beta = 0 a singularity of the Euler set only
  (validity ``euler_angles_regular``).
* Actuated: the leg lengths d_i = |a_i - R b_ip| (eq 7) within their strokes (section 5,
  ``STROKES``: the actuated ranges). k1..k3 (N/m): actuator stiffnesses, delta f_i = k_i delta d_i,
  f_i > 0 a compression (``actuator_stiffness``; statics: ``examples/sps_section5.py``).
* Forward pose: a degree-8 polynomial in t = tan(phi / 2) (accelerator ``_sps_forward.py``);
  its (root, branch) slot does not label a mode (``paper_labels`` of ``examples/sps_section5.py``).
* Defaults: section 5 (Baukema SHM4-120A) with a3x = +2.720 m (printed -2.720: no configuration
  exists with it; tests/test_sps.py), chi = -1, strokes and stiffnesses as printed.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import (
    distance_cosines,
    distance_points,
    euler_platform,
    frame_pose_values,
    leg_parameters,
    parameter_fields,
    scalar_parameter,
)
from parakin.generator.model import Citation, Example, Mechanism
from parakin.mechanisms._sps_forward import closure, drawing, forward

a1x, a2x, a2y, a3x, a3y, a3z = sp.symbols("a1x a2x a2y a3x a3y a3z", real=True)
b1, b2, b3, b12, b23, b13 = sp.symbols("b1 b2 b3 b12 b23 b13", positive=True)
chi = sp.Symbol("chi", real=True)
stiffness = sp.symbols("k1:4", real=True)
d = sp.symbols("d1:4", positive=True)
alpha, beta, gamma = sp.symbols("alpha beta gamma", real=True)
#: section 5 (Baukema SHM4-120A): (d_i_min, d_i_max) of legs 1..3, metres; the actuated ranges
STROKES = ((0.530, 1.780), (0.530, 1.780), (0.810, 2.060))
#: section 5: the machine's configuration (root v3), XYX Euler angles to full precision (residual 4e-16)
HOME_EULER = (0.38623430068232256, 0.32043813812493704, -0.2199222510816914)


#: a_i in {B} (A1 on x_b, A2 in the x_b y_b plane); b_ip in {P} from |QB_i| = b_i and |B_i B_j| = b_ij
#: (eq 1c), their cosines q12, q13, q23 (eq 1c) and Gram determinant D3 (eq 5)
BASE_POINTS = [sp.Matrix([a1x, 0, 0]), sp.Matrix([a2x, a2y, 0]), sp.Matrix([a3x, a3y, a3z])]
PLATFORM_POINTS = distance_points((b1, b2, b3), (b12, b23, b13), chi)
PLATFORM_COSINES = distance_cosines((b1, b2, b3), (b12, b23, b13))
MOTION = euler_platform("xyx", (alpha, beta, gamma))  # X'-Y'-X' Euler angles (eq 9), sigma = sign(sin beta)
MODEL = joints.DistanceMechanism(
    MOTION,
    [
        *(joints.prismatic_leg(a, bp, length) for a, bp, length in zip(BASE_POINTS, PLATFORM_POINTS, d, strict=True)),
        joints.central_joint(),
    ],
    parallel_name="leg_moments_coplanar",
)
#: section 5 (Baukema SHM4-120A), with a3x = +2.720 (module docstring)
PARAMETERS = parameter_fields(
    scalar_parameter(a1x, 2.470, "x of the base point A1 (on the x_b axis), section 5"),
    scalar_parameter(a2x, 2.250, "x of the base point A2 (in the x_b y_b plane)"),
    scalar_parameter(a2y, 1.020, "y of the base point A2 (> 0)", domain="positive"),
    scalar_parameter(a3x, 2.720, "x of the base point A3 (printed -2.720: a typo for +2.720)"),
    scalar_parameter(a3y, 0.130, "y of the base point A3"),
    scalar_parameter(a3z, -0.460, "z of the base point A3"),
    leg_parameters((b1, b2, b3), (2.400, 2.400, 2.635), "distance |Q B{k}| from the centre Q to the platform point"),
    scalar_parameter(b12, 1.030, "distance between the platform points B1 and B2", domain="positive"),
    scalar_parameter(b23, 0.240, "distance between the platform points B2 and B3", domain="positive"),
    scalar_parameter(b13, 1.070, "distance between the platform points B1 and B3", domain="positive"),
    scalar_parameter(chi, -1.0, "platform handedness, the sign of det[b1p b2p b3p] (+1 or -1)", "", "sign"),
    leg_parameters(
        stiffness,
        (-7.7292e6, -2.30083e8, -1.0165e7),
        "stiffness of actuator {k}, delta f = k delta d (section 4; f > 0 compresses)",
        "N/m",
        "nonzero",
    ),
)


def build() -> Mechanism:
    derived = MODEL.fields()
    derived |= {"closure": closure(BASE_POINTS, PLATFORM_POINTS, d, MOTION.rotation)}
    derived["drawing"] = drawing(derived["drawing"])  # type: ignore[arg-type]
    return Mechanism(
        name="sps",
        title="3(SPS)-S spherical platform with three linear actuators (Knapczyk & Tora)",
        citation=Citation(
            ("J. Knapczyk", "G. Tora"),
            "Displacement and force analysis of the spherical platform mechanism 3(SPS)-S with compliancies of linear actuators taken into account",
        ),
        **PARAMETERS,
        **derived,  # type: ignore[arg-type]
        forward=forward(BASE_POINTS, PLATFORM_POINTS, d, (b1, b2, b3), PLATFORM_COSINES, chi),
        home={
            **dict(zip(d, (0.780, 0.570, 1.320), strict=True)),
            **dict(zip(MOTION.coordinates, HOME_EULER, strict=True)),
        },
        limits=dict(zip(d, STROKES, strict=True)),
        examples=EXAMPLES,
        actuator_stiffness=list(stiffness),
    )


# Examples
#: section 5: the printed points agree with the configurations to 5.2e-3 m only (the paper's roots
#: are off at the 1e-3 level, F(v3) = -1.2e-3 on the printed data)
EXAMPLES = [
    Example(
        name="section5_starting_point",
        description="section 5 starting point d = (0.780, 0.570, 1.320) m (a3x = +2.720, the "
        "printed -2.720 is a typo): four real roots v1..v4 = 0.98004, 0.83904, 0.91463, 0.96707 "
        "(four assembly modes); the machine's configuration (v3) as the frame of the printed "
        "b_1 = (2.278, 0.290, -0.698), b_2 = (2.000, 1.250, -0.454) m, to 5e-3: the printed "
        "points are 5e-3 m off the data's configuration (the printed roots are off at 1e-3)",
        actuated=[0.780, 0.570, 1.320],
        expected={"mode_count": 4, "poses": [frame_pose_values([2.278, 0.290, -0.698], [2.000, 1.250, -0.454])]},
        tolerance=5e-3,
    )
]
