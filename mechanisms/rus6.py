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

import itertools
import math

import sympy as sp
from parakin.generator.blocks import (
    TWIST,
    half_angle_solution,
    laplace_det,
    point_defaults,
    point_info,
    point_parameters,
)
from parakin.generator.frames import (
    homogeneous,
    quaternion_rotation,
    quaternion_rotation_unnormalised,
    sign_or_plus,
)
from parakin.generator.model import (
    POSE_POSITION,
    POSE_ROTATION,
    Citation,
    ClosureModel,
    Drawing,
    Example,
    InverseSolution,
    Mechanism,
    ParameterInfo,
    RateModel,
)
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


def crank_plane(i: int) -> tuple[sp.Matrix, sp.Matrix]:
    """(e1_i, e2_i = u_i x e1_i)."""
    e1 = row(CRANK_ZERO, i)
    return e1, row(AXIS, i).cross(e1)


def crank_tip(i: int, angle: sp.Expr) -> sp.Matrix:
    """E_i = A_i + a_i (cos theta_i e1_i + sin theta_i e2_i)."""
    e1, e2 = crank_plane(i)
    return row(BASE, i) + a[i] * (sp.cos(angle) * e1 + sp.sin(angle) * e2)


def platform_joint(i: int, rotation: sp.Matrix, position: sp.Matrix) -> sp.Matrix:
    """B_i = R c_i + p."""
    return rotation * row(PLATFORM, i) + position


def state_pose() -> tuple[sp.Matrix, sp.Matrix]:
    return quaternion_rotation(quaternion), sp.Matrix([x, y, z])


def rods() -> list[sp.Matrix]:
    """d_i = B_i - E_i(theta_i), in {B}."""
    rotation, position = state_pose()
    return [platform_joint(i, rotation, position) - crank_tip(i, theta[i]) for i in range(6)]


def inverse() -> InverseSolution:
    """Per leg the tan-half-angle quadratic of E cos + F sin + G = 0; p read off, q from R
    (q0 >= 0, branch-free) as in ``stewart``."""
    sigma = list(sp.symbols("sigma1:7", real=True))
    steps: list[tuple[sp.Symbol, sp.Expr]] = []
    validity = {}
    for i in range(6):
        e, f, g = sp.symbols(f"E{i + 1} F{i + 1} G{i + 1}", real=True)
        e1, e2 = crank_plane(i)
        v = platform_joint(i, POSE_ROTATION, POSE_POSITION) - row(BASE, i)
        steps += [(e, -2 * a[i] * v.dot(e1)), (f, -2 * a[i] * v.dot(e2)), (g, v.dot(v) + a[i] ** 2 - b[i] ** 2)]
        # sigma = +1 takes the root -F - sqrt(disc): the crank turned back from A_i -> B_i
        angle, discriminant = half_angle_solution(e, f, g, -sigma[i])
        steps.append((theta[i], angle))
        validity[f"leg{i + 1}_reachable"] = discriminant / (e**2 + f**2 + g**2)
    steps += [(x, POSE_POSITION[0]), (y, POSE_POSITION[1]), (z, POSE_POSITION[2])]
    steps += quaternion_steps(POSE_ROTATION)
    return InverseSolution(steps, sigma, validity)


def quaternion_steps(rotation: sp.Matrix) -> list[tuple[sp.Symbol, sp.Expr]]:
    """q0..q3 of R (q0 >= 0, branch-free) by the algorithm of ``frames.quaternion_from_rotation``
    (the columns k_c of K = 4 q q^T, each added to the running sum with the sign that makes it
    agree, then normalised), written as steps with the running sums as intermediate symbols:
    the same values, where the one expression of ``quaternion_from_rotation`` repeats each sum
    inside every later sign (2.7 MB of SymPy, 0.1 s per evaluation in the generator's checks)."""
    r = rotation
    k = sp.Matrix(
        [
            [1 + r[0, 0] + r[1, 1] + r[2, 2], r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]],
            [r[2, 1] - r[1, 2], 1 + r[0, 0] - r[1, 1] - r[2, 2], r[0, 1] + r[1, 0], r[0, 2] + r[2, 0]],
            [r[0, 2] - r[2, 0], r[0, 1] + r[1, 0], 1 - r[0, 0] + r[1, 1] - r[2, 2], r[1, 2] + r[2, 1]],
            [r[1, 0] - r[0, 1], r[0, 2] + r[2, 0], r[1, 2] + r[2, 1], 1 - r[0, 0] - r[1, 1] + r[2, 2]],
        ]
    )
    steps: list[tuple[sp.Symbol, sp.Expr]] = []
    total = k[:, 0]
    for column in range(1, 4):
        sign = sign_or_plus(total.dot(k[:, column]))
        running = sp.Matrix(sp.symbols(f"quaternion_sum{column}_0:4", real=True))
        steps += list(zip(running, total + sign * k[:, column], strict=True))
        total = running
    norm = sp.Symbol("quaternion_sum_norm", positive=True)
    steps.append((norm, sp.sqrt(total.dot(total))))
    return steps + [(q, total[j] / norm) for j, q in enumerate(quaternion)]


def closure() -> ClosureModel:
    rotation, position = state_pose()
    residual = sp.Matrix([(d.dot(d) - b[i] ** 2) / (2 * b[i]) for i, d in enumerate(rods())])
    norm = (sum(c**2 for c in quaternion) - 1) / 2
    return ClosureModel(sp.Matrix.vstack(residual, sp.Matrix([norm])), sp.Matrix([1]), homogeneous(rotation, position))


def rates() -> tuple[RateModel, dict[str, sp.Expr]]:
    """d_i . (v + w x (B_i - p)) = d_i . dE_i/dtheta_i theta_dot_i, with (B_i - p) x d_i =
    (E_i - p) x d_i and dE_i/dtheta_i = u_i x (E_i - A_i)."""
    _, position = state_pose()
    links = rods()
    rows, diagonal = [], []
    for i, d in enumerate(links):
        tip = crank_tip(i, theta[i])
        rows.append([*d, *(tip - position).cross(d)])
        diagonal.append(row(AXIS, i).dot((tip - row(BASE, i)).cross(d)))
    matrix = sp.Matrix(rows)
    # det A from polynomial rows: with n = q . q and R = R_u(q) / n (R_u quadratic in q), row i
    # of A is (n d_i ; n E_i x d_i) / n up to a column operation (the moment about the origin of
    # {B} instead of p: adding [p]x times the first three columns, the same in every row), and
    # n d_i = R_u c_i + n (p - E_i), n E_i x d_i = E_i x (R_u c_i + n p): det A = det P / n^6
    norm = sum(c**2 for c in quaternion)
    turned = quaternion_rotation_unnormalised(quaternion)
    polynomial = []
    for i in range(6):
        tip, joint = crank_tip(i, theta[i]), turned * row(PLATFORM, i) + norm * position
        polynomial.append([*(joint - norm * tip), *tip.cross(joint)])
    model = RateModel(
        twist=list(TWIST),
        a=matrix,
        b=sp.diag(*diagonal),
        serial_factors={f"leg{i + 1}_rod_in_crank_axis_plane": diagonal[i] for i in range(6)},
    )
    return model, {"rod_lines_dependent": block_laplace_det(sp.Matrix(polynomial)) / norm**6}


def block_laplace_det(matrix: sp.Matrix) -> sp.Expr:
    """det of a 6 x 6 matrix by Laplace's expansion along its first three columns: the sum over
    3-row subsets S of (-1)^(sum of S + 0 + 1 + 2) det(M[S, :3]) det(M[not S, 3:]) (0-based), 20
    products of 3 x 3 ``laplace_det``s. As written, a third of the size of the cofactor expansion
    along a row (600 entry occurrences instead of 1956)."""
    total = sp.Integer(0)
    for chosen in itertools.combinations(range(6), 3):
        rest = [k for k in range(6) if k not in chosen]
        sign = (-1) ** (sum(chosen) + 3)
        total += (
            sign * laplace_det(matrix.extract(list(chosen), [0, 1, 2])) * laplace_det(matrix.extract(rest, [3, 4, 5]))
        )
    return total


def drawing() -> Drawing:
    """Shafts A_i, crank tips E_i and platform joints B_i (in {B}): each leg A_i -> E_i -> B_i,
    the base and platform hexagons."""
    rotation, position = state_pose()
    return Drawing(
        points={
            "base": sp.Matrix.hstack(*(row(BASE, i) for i in range(6))),
            "crank": sp.Matrix.hstack(*(crank_tip(i, theta[i]) for i in range(6))),
            "platform": sp.Matrix.hstack(*(platform_joint(i, rotation, position) for i in range(6))),
        },
        polylines={
            **{f"leg{i + 1}": [("base", i), ("crank", i), ("platform", i)] for i in range(6)},
            "base": [("base", i % 6) for i in range(7)],
            "platform": [("platform", i % 6) for i in range(7)],
        },
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
    values = inverse().at(pose[:3, :3], pose[:3, 3], 0, defaults())
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
    rate_model, parallel = rates()
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
        actuated=list(theta),
        passive=[x, y, z, *quaternion],
        legs=[],
        inverse=inverse(),
        forward=None,
        home=home(),
        limits=dict.fromkeys(theta, CRANK_RANGE),
        angular=list(theta),
        dimensionless=list(quaternion),
        parallel_factors=parallel,
        closure=closure(),
        rates=rate_model,
        pose_kind="transform",
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
        drawing=drawing(),
    )
