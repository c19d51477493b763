"""6-RUS rotary hexapod: six legs, each an actuated revolute joint on the base turning a crank, a
universal joint at the crank tip, a rod of fixed length and a spherical joint on the platform
(Hunt 1983, the rotary-actuated variant of the 6-SPS; Merlet, "Parallel Robots", 2006). With the
cranks locked the crank tips are fixed points and the rods legs of fixed length: the forward pose
is that of a general 6-6 Gough-Stewart platform on the crank tips (40 complex assembly modes,
all real for Dietmaier's geometry: example ``dietmaier_cranks``).

Frames and conventions (SI, radians):
* {B}: base frame. Motor i turns about the axis u_i (parameter group ``axis``, 6 x 3, unit
  vectors in {B}) through the shaft point A_i (group ``base``, in {B}). Its crank, of length a_i,
  points along e1_i (group ``crank_zero``, unit vectors normal to u_i) at theta_i = 0 and along
  e2_i = u_i x e1_i at theta_i = pi/2 (theta_i right-handed about u_i): crank tip
  E_i = A_i + a_i (cos theta_i e1_i + sin theta_i e2_i). The closure is polynomial in the
  parameters; e1_i . u_i = 0 and |u_i| = |e1_i| = 1 are the user's to keep (the defaults do).
* {P}: platform frame, platform joints c_i (group ``platform``, in {P}); B_i = R c_i + p with
  ^B_P T = (R, p). The rod (length b_i) joins E_i to B_i; d_i = B_i - E_i.
* Actuated variables: theta1..theta6 (revolute). Passive variables (the Newton unknowns), as in
  ``stewart``: the position p = (x, y, z) of the origin of {P} and the unit quaternion q = (q0,
  q1, q2, q3) of R (scalar first, R(q) v = q v q* / |q|^2). The closure is square: six rod
  residuals (d_i . d_i - b_i^2) / (2 b_i) (metres; |d_i| - b_i to first order), polynomial in
  (p, cos theta_i, sin theta_i) and rational in q, and the normalisation (q . q - 1) / 2; no
  false closure (alignment 1). q and -q are the same pose; the inverse returns q0 >= 0.
* Inverse: with v_i = B_i - A_i, leg i is E cos(theta_i) + F sin(theta_i) + G = 0, E = -2 a_i
  v_i . e1_i, F = -2 a_i v_i . e2_i, G = |v_i|^2 + a_i^2 - b_i^2 (a delta-robot leg), solved
  through its tan-half-angle quadratic: theta_i = angle_i - sigma_i gamma_i, angle_i the angle of
  the projection of v_i on the crank plane (from e1_i towards e2_i), gamma_i = acos(G / (2 a_i
  |v_i projected|)). sigma_i = +1 turns the crank from that projection backwards about u_i: in the
  default layout the crank below the line from its shaft to the platform joint, the usual
  working mode (home: every crank level). Branch k: signs (sigma1, ..., sigma6) of
  ``InversePose.branches[k]`` (64 combinations), branch 0 = all +1. Validity ``leg<i>_reachable``
  = (E^2 + F^2 - G^2) / (E^2 + F^2 + G^2), the discriminant made unitless.
* Rates: A twist = B theta_dot (twist = (v of the origin of {P}, w), both in {B}), from
  d_i . d_i = b_i^2: row i of A = (d_i ; (E_i - p) x d_i), the Pluecker coordinates of rod line i
  (moment about the origin of {P}); B = diag(u_i . ((E_i - A_i) x d_i)) (d_i . dE_i/dtheta_i).
  Type I (det B = 0): ``leg<i>_rod_in_crank_axis_plane``, the rod in the plane of the crank and
  the motor axis (its tip moves normal to the rod). Type II (det A = 0): ``rod_lines_dependent``.
* Model: six R-U-S legs (``parakin.generator.joints.crank_leg``); closure, rates, factors,
  inverse and drawing (shafts, crank tips ``elbow``, platform joints) are derived from them.
* Forward pose: none in closed form here (``forward=None``): Newton on the closure from a guess
  (``forward_pose``), or the generic all-modes stage built from the closure residual.
* Defaults (illustrative, not from a paper: a servo hexapod of the usual layout): three motor
  pairs centred at 0, 120 and 240 degrees about z, the shafts on a circle of radius 0.4 m at
  +-10 degrees from each pair's centre, horizontal axes along the pair's radial line (outwards for
  the second motor of a pair, inwards for the first), each crank level at theta = 0 pointing away
  from its pair's centre and rising for theta > 0 (e2_i = z); cranks a_i = 0.15 m, rods b_i =
  0.6 m; platform joints on a circle of radius 0.3 m at +-50 degrees from each pair's centre (in
  pairs about 60, 180 and 300 degrees). Home: R = I, p = (0, 0, HOME_Z) with every crank level
  (theta = 0, branch 0), HOME_Z = sqrt(b^2 - h^2) = 0.5652 m with h the horizontal distance from
  a level crank tip to its platform joint (example ``home_cranks_level``); the closure Jacobian
  there has a pivot ratio of about 0.11. Crank range: theta_i in [-pi/2, pi/2] (``limits``: from
  straight down to straight up, a servo's half turn about level).
* Dietmaier's geometry as a 6-RUS (example ``dietmaier_cranks``): platform joints, rods and the
  quoted pose of Dietmaier (1998) (``stewart``'s DIETMAIER_* constants), the default motor axes,
  crank directions and cranks, and the shafts placed at A_i = X_i - a_i (cos t e1_i + sin t e2_i)
  with t = DIETMAIER_THETA = pi/6 for every crank: at theta = (pi/6, ..., pi/6) the crank tips are
  Dietmaier's base points X_i, so the forward problem there is Dietmaier's 40-real-mode one
  (checked against ``stewart``'s forward_pose_all in tests/test_rus6.py).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import point_defaults, point_info, point_parameters
from parakin.generator.model import Citation, Example, Mechanism, ParameterInfo
from parakin.mechanisms.stewart import (
    DIETMAIER_BASE,
    DIETMAIER_LENGTHS,
    DIETMAIER_PLATFORM,
    DIETMAIER_POSITION,
    DIETMAIER_ROTATION,
)

BASE = point_parameters("base", 6)
AXIS = point_parameters("axis", 6)
CRANK_ZERO = point_parameters("crank_zero", 6)
PLATFORM = point_parameters("platform", 6)
a = sp.symbols("a1:7", positive=True)
b = sp.symbols("b1:7", positive=True)
theta = sp.symbols("theta1:7", real=True)
x, y, z = sp.symbols("x y z", real=True)
quaternion = sp.symbols("q0:4", real=True)

#: the default layout (module docstring): pair centres, shaft and platform-joint offsets
PAIR_CENTRES = (0.0, 120.0, 240.0)
SHAFT_RADIUS, SHAFT_OFFSET = 0.4, 10.0
PLATFORM_RADIUS, PLATFORM_OFFSET = 0.3, 50.0
CRANK, ROD = 0.15, 0.6
#: crank angle of the Dietmaier example (every leg), and the crank range of the defaults
DIETMAIER_THETA = math.pi / 6
CRANK_RANGE = (-math.pi / 2, math.pi / 2)


def _side(i: int) -> int:
    """-1 for the first motor of a pair, +1 for the second."""
    return -1 if i % 2 == 0 else 1


def _layout() -> dict[str, list[list[float]]]:
    """The default shafts, axes, crank directions at theta = 0 and platform joints."""
    shafts, axes, zeros, joints = [], [], [], []
    for i in range(6):
        centre, side = math.radians(PAIR_CENTRES[i // 2]), _side(i)
        shaft = centre + side * math.radians(SHAFT_OFFSET)
        joint = centre + side * math.radians(PLATFORM_OFFSET)
        shafts.append([SHAFT_RADIUS * math.cos(shaft), SHAFT_RADIUS * math.sin(shaft), 0.0])
        # e1 = side * (tangent of the pair's centre), u = e1 x z = side * (radial direction)
        zeros.append([-side * math.sin(centre), side * math.cos(centre), 0.0])
        axes.append([side * math.cos(centre), side * math.sin(centre), 0.0])
        joints.append([PLATFORM_RADIUS * math.cos(joint), PLATFORM_RADIUS * math.sin(joint), 0.0])
    return {"base": shafts, "axis": axes, "crank_zero": zeros, "platform": joints}


LAYOUT = _layout()
#: the home height: every crank level, R = I (module docstring)
HOME_Z = math.sqrt(
    ROD**2
    - sum((LAYOUT["platform"][0][k] - LAYOUT["base"][0][k] - CRANK * LAYOUT["crank_zero"][0][k]) ** 2 for k in range(2))
)


def row(points: sp.Matrix, i: int) -> sp.Matrix:
    return points.row(i).T


#: the model: six R-U-S legs (crank about u_i from e1_i, rod to c_i; branch sign +1 the crank
#: turned back about u_i) on a spatial platform; closure, rates, factors, inverse and drawing are
#: derived from it
MODEL = joints.DistanceMechanism(
    joints.platform("transform"),
    [
        joints.crank_leg(
            row(BASE, i),
            row(AXIS, i),
            row(CRANK_ZERO, i),
            a[i],
            b[i],
            row(PLATFORM, i),
            theta[i],
            sign=-1,
            serial_name="leg{k}_rod_in_crank_axis_plane",
        )
        for i in range(6)
    ],
    parallel_name="rod_lines_dependent",
)


def defaults() -> dict[sp.Symbol, float]:
    return {
        **point_defaults(BASE, LAYOUT["base"]),
        **point_defaults(AXIS, LAYOUT["axis"]),
        **point_defaults(CRANK_ZERO, LAYOUT["crank_zero"]),
        **dict.fromkeys(a, CRANK),
        **dict.fromkeys(b, ROD),
        **point_defaults(PLATFORM, LAYOUT["platform"]),
    }


def dietmaier_shafts() -> list[list[float]]:
    """A_i = X_i - a_i (cos t e1_i + sin t e2_i), t = DIETMAIER_THETA, default crank frames: the
    crank tips are Dietmaier's base points X_i at theta_i = t."""
    c, s = math.cos(DIETMAIER_THETA), math.sin(DIETMAIER_THETA)
    shafts = []
    for i in range(6):
        u, e1 = LAYOUT["axis"][i], LAYOUT["crank_zero"][i]
        e2 = [u[1] * e1[2] - u[2] * e1[1], u[2] * e1[0] - u[0] * e1[2], u[0] * e1[1] - u[1] * e1[0]]
        shafts.append([DIETMAIER_BASE[i][k] - CRANK * (c * e1[k] + s * e2[k]) for k in range(3)])
    return shafts


#: example ``dietmaier_cranks``: the parameters that differ from the defaults, by name
DIETMAIER_PARAMETERS = {
    **{str(k): v for k, v in point_defaults(BASE, dietmaier_shafts()).items()},
    **{str(k): v for k, v in point_defaults(PLATFORM, DIETMAIER_PLATFORM).items()},
    **{str(b[i]): DIETMAIER_LENGTHS[i] for i in range(6)},
}


def pose_list(rotation: list[list[float]], position: list[float]) -> list[list[float]]:
    return [[*map(float, r), float(t)] for r, t in zip(rotation, position, strict=True)] + [[0.0, 0.0, 0.0, 1.0]]


HOME_POSE = pose_list([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [0.0, 0.0, HOME_Z])
DIETMAIER_POSE = pose_list(DIETMAIER_ROTATION, DIETMAIER_POSITION)


def home() -> dict[sp.Symbol, float]:
    """The inverse of HOME_POSE on branch 0 at the defaults (theta = 0 to rounding)."""
    pose = sp.Matrix(HOME_POSE)
    values = MODEL.inverse().at(pose[:3, :3], pose[:3, 3], 0, defaults())
    return {v: values[v] for v in (*theta, x, y, z, *quaternion)}


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
        parameters=defaults(),
        **MODEL.fields(),
        forward=None,
        home=home(),
        limits=dict.fromkeys(theta, CRANK_RANGE),
        parameter_info={
            **point_info(BASE, "motor shaft point A{k} (on the motor axis), in {B}"),
            **point_info(AXIS, "motor axis u{k} (unit vector; theta{k} right-handed about it), in {B}", unit=""),
            **point_info(CRANK_ZERO, "crank direction e1_{k} at theta{k} = 0 (unit, normal to u{k}), in {B}", unit=""),
            **{a[i]: ParameterInfo("m", f"crank {i + 1} length |E{i + 1} - A{i + 1}|", "positive") for i in range(6)},
            **{b[i]: ParameterInfo("m", f"rod {i + 1} length |B{i + 1} - E{i + 1}|", "positive") for i in range(6)},
            **point_info(PLATFORM, "platform joint c{k}, in {P}"),
        },
        parameter_groups={"base": BASE, "axis": AXIS, "crank_zero": CRANK_ZERO, "platform": PLATFORM},
        examples=EXAMPLES,
    )
