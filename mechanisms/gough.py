"""6-SPS (Gough-Stewart) platform with linearly related planar base and platform (PMlpp), after
Kong & Gosselin, "Generation of architecturally singular 6-SPS parallel manipulators with linearly
related planar platforms" (``shared/papers/004_407e258733e8e5c8.txt``).

Conventions (paper section 2; SI, radians; derivation: ``docs/derivations/gough.md``):
* {B}: origin O = A1, base plane z = 0, A_i = (xA_i, yA_i, 0), i = 2..6. {P}: origin O_P = B1,
  platform plane z_P = 0, B_i^(P) = (t11 xA_i + t12 yA_i, t22 yA_i, 0) (eq 1), t11 t22 != 0.
* Pose: p = B1 = (x, y, z), R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma) (passive x, y, z, alpha,
  beta, gamma; singular at beta = +-pi/2, a singularity of the angles only); B_i = p + R B_i^(P).
* Actuated: the leg lengths l1..l6 = |B_i - A_i|; the closure unsquared (|B_i - A_i| - l_i).
* Forward pose: the paper's quartic (23) in i_y (accelerator ``_gough_forward.py``), 16 complex
  candidates, real ones in mirror pairs through the base plane.
* Architecture: det M (eq 14), normalised (|measure| <= 1), vanishes iff A1..A6 lie on a conic
  (self-motion; ``parakin.load`` warns below 1e-9; degeneracy ``base_points_on_a_conic``).
* Defaults: section 5.4's geometry with A4 moved off the conic to (13, 0) (the paper gives no
  unit: metres); home ``HOME_POSE`` = (5, 2, 5 m, -0.3, -0.5, 0.3 rad), tilted (level poses are
  type II singular for these platforms). Section 5.4's own singular geometry is the example
  ``section54_self_motion`` (``examples/gough_architecture.py``).
"""

from __future__ import annotations

from functools import partial

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import euler_platform, euler_pose, euler_pose_values, home_from_pose
from parakin.generator.model import Citation, Example, Mechanism, ParameterInfo
from parakin.mechanisms import _gough_forward as accelerator

XA = sp.symbols("xA2:7", real=True)
YA = sp.symbols("yA2:7", real=True)
t11, t12, t22 = sp.symbols("t11 t12 t22", real=True)
lengths = sp.symbols("l1:7", positive=True)
x, y, z = sp.symbols("x y z", real=True)
alpha, beta, gamma = sp.symbols("alpha beta gamma", real=True)
SECTION_54_T = (1.0, 1.0, 1.0)
DEFAULT_BASE = [(5.0, -5.0), (9.0, -3.0), (13.0, 0.0), (9.0, 3.0), (5.0, 5.0)]
HOME_POSE = (5.0, 2.0, 5.0, -0.3, -0.5, 0.3)
BASE = [sp.zeros(3, 1)] + [sp.Matrix([XA[k], YA[k], 0]) for k in range(5)]  # A_1..A_6 in {B}
PLATFORM = [sp.zeros(3, 1)] + [sp.Matrix([t11 * XA[k] + t12 * YA[k], t22 * YA[k], 0]) for k in range(5)]  # eq (1)
system8_matrix = partial(accelerator.system8_matrix, XA, YA)
conic_matrix = partial(accelerator.conic_matrix, XA, YA)

MOTION = euler_platform("zyx", (alpha, beta, gamma), (x, y, z))  # Z-Y-X Euler angles
MODEL = joints.DistanceMechanism(
    MOTION, [joints.prismatic_leg(a, b, lengths[k]) for k, (a, b) in enumerate(zip(BASE, PLATFORM, strict=True))]
)
DEFAULTS: dict[sp.Symbol, float] = {
    **{XA[k]: DEFAULT_BASE[k][0] for k in range(5)},
    **{YA[k]: DEFAULT_BASE[k][1] for k in range(5)},
    **dict(zip((t11, t12, t22), SECTION_54_T, strict=True)),
}
PARAMETER_INFO = {
    **{
        s: ParameterInfo("m", f"{c} of the base joint A{k + 2} in {{B}} (A1 = O), eq (1)")
        for k in range(5)
        for c, s in (("x", XA[k]), ("y", YA[k]))
    },
    t11: ParameterInfo("", "platform map, eq (1): x_B = t11 x_A + t12 y_A (t11 t22 != 0)", "nonzero"),
    t12: ParameterInfo("", "platform map, eq (1): shear term of x_B = t11 x_A + t12 y_A"),
    t22: ParameterInfo("", "platform map, eq (1): y_B = t22 y_A (t11 t22 != 0)", "nonzero"),
}


def build() -> Mechanism:
    return Mechanism(
        name="gough",
        title="6-SPS platform with linearly related planar platforms (Kong & Gosselin)",
        citation=Citation(
            ("X. Kong", "C. M. Gosselin"),
            "Generation of architecturally singular 6-SPS parallel manipulators with linearly related planar platforms",
            2002,
            "Electronic Journal of Computational Kinematics",
        ),
        parameters=dict(DEFAULTS),
        **MODEL.fields() | {"closure": MODEL.closure(squared=False)},
        forward=accelerator.forward(XA, YA, (t11, t12, t22), PLATFORM, lengths),
        home=home_from_pose(MODEL, euler_pose("zyx", HOME_POSE[3:], HOME_POSE[:3]), 0, DEFAULTS),
        limits={length: (0.0, float("inf")) for length in lengths},
        architecture=accelerator.architecture(XA, YA),
        architecture_tolerance=1e-9,  # the normalised measure (|.| <= 1) below which the base lies on a conic
        parameter_info=PARAMETER_INFO,
        parameter_groups={"base": sp.Matrix([[XA[k], YA[k]] for k in range(5)])},
        examples=EXAMPLES,
    )


# Examples
#: section 5.4 (A2..A6, then t11, t12, t22): on the conic (x - 5)^2 + y^2 = 25, singular
SECTION_54_BASE = [(5.0, -5.0), (9.0, -3.0), (10.0, 0.0), (9.0, 3.0), (5.0, 5.0)]
#: section 5.4: the locked inputs, printed to two decimals
SECTION_54_LENGTHS = [33.17, 32.02, 35.12, 37.57, 39.01, 38.32]
SECTION_54_PARAMETERS = {
    **{f"xA{k + 2}": SECTION_54_BASE[k][0] for k in range(5)},
    **{f"yA{k + 2}": SECTION_54_BASE[k][1] for k in range(5)},
    **dict(zip(("t11", "t12", "t22"), SECTION_54_T, strict=True)),
}
#: a pose {x y z alpha beta gamma} (m, rad) on section 5.4's self-motion (the mode at i_x = 0.044) for
#: the compatible lengths nearest the printed ones: its lengths are the printed l1..l6 to 4.2e-3
SECTION_54_POSE = (11.100315736401, 24.869206220077, 18.934814882557, -1.110996974574, -1.471482307985, 0.496304779502)


def examples() -> list[Example]:
    """Section 5.4 prints a singular geometry and lengths locking a self-motion, no pose: the example
    is a pose of that self-motion whose lengths are the printed ones to their rounding (5e-3 m)."""
    return [
        Example(
            name="section54_self_motion",
            description="section 5.4's architecturally singular geometry (base A2..A6 = (5,-5) (9,-3) (10,0) "
            "(9,3) (5,5) on the conic (x - 5)^2 + y^2 = 25, t11 = t12 = t22 = 1; load warns): a pose on the "
            "self-motion of its locked inputs has the printed lengths l1..l6 = 33.17, 32.02, 35.12, 37.57, "
            "39.01, 38.32 to their rounding (5e-3 m); forward_pose_all at these lengths raises (a self-motion, "
            "not isolated modes: examples/gough_architecture.py)",
            pose=euler_pose_values("zyx", SECTION_54_POSE[3:], SECTION_54_POSE[:3]),
            parameters=dict(SECTION_54_PARAMETERS),
            expected={"actuated": list(SECTION_54_LENGTHS)},
            tolerance=5e-3,
        )
    ]


EXAMPLES = examples()
