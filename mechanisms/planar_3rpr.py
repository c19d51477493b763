"""Planar 3-RPR parallel manipulator: three legs, each a passive revolute joint on the base, an
actuated prismatic joint and a passive revolute joint on the platform. Forward pose after Gosselin,
Sefrioui & Richard (1992) (also Hunt 1983, Merlet's "Parallel Robots"): a polynomial of degree 6
in t = tan(phi / 2), so at most 6 assembly modes.

Conventions (SI, radians; derivation: ``docs/derivations/planar_3rpr.md``):
* {B}: the plane of motion z = 0, base joints A_i = (base_x<i>, base_y<i>, 0). {P}: platform joints
  b_i = (platform_x<i>, platform_y<i>, 0). Pose planar: ^B_P T = [Rot_z(phi), (x, y, 0)]; the
  inverse reads x = px, y = py, phi = atan2(r21, r11) and nothing else.
* Actuated: the leg lengths rho_i = |p + R b_i - A_i| (metres); passive x, y, phi. Inverse: one
  branch, validity ``leg<i>_length``. Type II: ``leg_lines_concurrent_or_parallel``.
* Forward pose: the degree-6 polynomial (accelerator ``_planar_3rpr_forward.py``); a mode with
  phi = pi exactly (t = infinity) or det M = 0 (Cramer fails) is not found.
* Defaults: the example attributed to Gosselin, Sefrioui & Richard (1992) in the literature,
  numbers as recalled, no unit (read as metres): A = (0, 0), (15.91, 0), (0, 10); b = (0, 0),
  (17.04, 0), 20.84 (cos 0.8824, sin 0.8824); rho = (14.98, 15.38, 12): 6 real assembly modes.
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import parameter_fields, point_group
from parakin.generator.model import Citation, Example, Mechanism
from parakin.mechanisms._planar_3rpr_forward import forward

rho = sp.symbols("rho1:4", positive=True)
x, y, phi = sp.symbols("x y phi", real=True)

#: the Gosselin-Sefrioui-Richard example (module docstring): base points, platform points, inputs
GSR_BASE = [(0.0, 0.0), (15.91, 0.0), (0.0, 10.0)]
GSR_PLATFORM = [(0.0, 0.0), (17.04, 0.0), (20.84 * math.cos(0.8824), 20.84 * math.sin(0.8824))]
base = point_group("base", GSR_BASE, "base joint A{k}, in {B}")
platform = point_group("platform", GSR_PLATFORM, "platform joint b{k}, in {P}")
PARAMETERS = parameter_fields(base, platform)
#: the home pose (x, y, phi): one of the example's assembly modes, rounded
HOME_POSE = (-14.9, 1.6, 0.245)


#: the model: three R-P-R legs on a planar platform; closure, rates, singularity factors,
#: inverse and drawing are derived from it (the forward elimination is the accelerator's)
MODEL = joints.DistanceMechanism(
    joints.platform("planar"),
    [joints.prismatic_leg(base.points[i], platform.points[i], rho[i]) for i in range(3)],
    parallel_name="leg_lines_concurrent_or_parallel",
)


def home() -> dict[sp.Symbol, float]:
    """HOME_POSE and its leg lengths at the default geometry."""
    values = PARAMETERS["parameters"]
    pose = dict(zip((x, y, phi), HOME_POSE, strict=True))
    steps = dict(MODEL.inverse().steps)
    lengths = [float(steps[r].subs(values).subs(pose)) for r in rho]
    return dict(zip(rho, lengths, strict=True)) | pose


def build() -> Mechanism:
    return Mechanism(
        name="planar_3rpr",
        title="Planar 3-RPR parallel manipulator (Gosselin, Sefrioui & Richard 1992: degree-6 forward polynomial)",
        citation=Citation(
            ("C. M. Gosselin", "J. Sefrioui", "M. J. Richard"),
            "Solutions polynomiales au probleme de la cinematique directe des manipulateurs paralleles plans "
            "a trois degres de liberte",
            1992,
            "Mechanism and Machine Theory 27(2)",
        ),
        **PARAMETERS,
        **MODEL.fields(),
        forward=forward(base.symbols, platform.symbols, rho),
        home=home(),
        limits={r: (0.0, math.inf) for r in rho},
        examples=EXAMPLES,
    )


# Examples
GSR_LENGTHS = [14.98, 15.38, 12.0]


EXAMPLES = [
    Example(
        name="six_real_modes",
        description="Gosselin, Sefrioui & Richard (1992) as reproduced in the 3-RPR literature (the "
        "default geometry, numbers recalled, not re-read from the paper): rho = (14.98, 15.38, 12) "
        "has 6 real assembly modes, the most a 3-RPR can have; confirmed by an independent sign-change "
        "scan of the leg-1 equation over phi (tests/test_planar_3rpr.py)",
        actuated=GSR_LENGTHS,
        expected={"mode_count": 6},
        tolerance=0.0,
    )
]
