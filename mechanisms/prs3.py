"""3-PRS parallel manipulator: three vertical rails, each carrying an actuated slider, a passive
revolute joint on the slider, a link of fixed length and a spherical joint on the platform. Three
degrees of freedom (the height and two tilts) with parasitic motion: the horizontal position and
the rotation about the vertical follow from them. The classical architecture of L.-W. Tsai,
"Robot Analysis" (1999), and of Carretero, Podhorodeski, Nahon & Gosselin (2000), "Kinematic
analysis and optimization of a new three degree-of-freedom spatial parallel manipulator", J. Mech.
Design 122(1); the formulas below are derived here (and checked by tests/test_prs3.py), not
copied from either text.

Frames and conventions (SI, radians):
* {B}: z = k along the rails; rail i stands at A_i = r_b (cos theta_i, sin theta_i, 0) with
  theta_i = 0, 120, 240 deg. Its radial direction e_i = (cos theta_i, sin theta_i, 0), its
  tangent u_i = (-sin theta_i, cos theta_i, 0).
* Actuated: the slider strokes d1..d3 (metres) along the rails, S_i = A_i + d_i k. Their ranges
  (``limits``) are the rails, 0 <= d_i <= RAIL_LENGTH.
* Leg i: a revolute joint at S_i with axis u_i (horizontal, tangent to the base circle), a link
  of length L from S_i to the spherical joint C_i = R c_i + p, c_i = r_p e_i in {P} (the same
  angles). The revolute joint keeps the link in the plane through S_i normal to u_i, the plane
  of the rail and the centre: (C_i - A_i) . u_i = 0; the link: |C_i - S_i| = L.
* Passive variables (the Newton unknowns) as in ``stewart``: the position p = (x, y, z) of the
  origin of {P} (the platform centre) and the unit quaternion q = (q0, q1, q2, q3) of R (scalar
  first, R(q) v = q v q* / |q|^2). The closure is square, 7 equations in 7 unknowns, rational in
  (p, q, d) (no trigonometric or piecewise function): the three plane constraints
  (C_i - A_i) . u_i (metres), the three link residuals (|C_i - S_i|^2 - L^2) / (2 L) (metres;
  |C_i - S_i| - L to first order) and (q . q - 1) / 2. q and -q are the same pose.
* Parasitic motion (derived here; tests/test_prs3.py checks it symbolically, and numerically in
  the Euler form): write n = R^T k = (r31, r32, r33), the base vertical seen from {P}, which fixes
  the tilt. Every rotation with that n is Rot_z(psi) R0, R0 the tilt about a horizontal axis (no
  torsion: Z-Y-Z Euler angles (alpha, beta, -alpha)); the sum of the three plane constraints is
  free of x and y (sum u_i = 0) and reads a cos psi + b sin psi = 0, so two rotations keep the
  joints in their planes: R0 itself (psi = 0), with the platform centre at
      x0 = -r_p (n_x^2 - n_y^2) / (2 (1 + n_z)),  y0 = r_p n_x n_y / (1 + n_z)
  (x0 = r_p (cos beta - 1) cos(2 alpha) / 2, y0 = r_p (1 - cos beta) sin(2 alpha) / 2 in Euler
  angles), and its half-turn about the vertical, Rot_z(pi) R0 at (-x0, -y0) (each platform joint
  on the far side of the centre from its rail; reachable only with long links). The height z is
  free. So the reachable poses are a 3-D set, parametrised by (z, n) and the half-turn, and
  every reachable rotation has q3 = 0 (R0) or q0 = 0 (its half-turn).
* Inverse pose (pose_kind 'transform', 8 branches): a pose of the platform has 6 coordinates but
  the mechanism reaches only a 3-D set of them, so ``inverse_pose`` reads what the actuators
  control, as sphere2r's inverse reads only the pointing axis: the height z = pz, the tilt
  n = (r31, r32, r33), and which of the two rotations above is nearer R (the sign of the cosine
  of the angle about the vertical from R0 to R, (R R0^T)_11; +1 where it is 0). x, y and the rotation about the
  vertical of the given pose are NOT read: the inverse returns the reachable pose with the given
  height and tilt (its passive values and ``platform_pose``), which is the given pose exactly
  when that pose is reachable. Compare ``m.platform_pose(ik.actuated[k], ik.passive[k])`` with
  your pose to see how far off the reachable set it was. Then per leg, with h_i the horizontal
  part of C_i - A_i: d_i = (C_i - A_i) . k - sigma_i sqrt(L^2 - |h_i|^2); branch sign
  sigma_i = +1 puts the slider below the platform joint (the link rises to the platform),
  -1 above it; validity ``leg<i>_reachable`` = (L^2 - |h_i|^2) / L^2 (the link reaches the
  joint's rail distance; 0: the link is horizontal, a serial singularity).
* Rates: no A/B rate model. The runtime's rate model is A twist = B d_dot with A and B square
  over the pose kind's whole twist (vx, vy, vz, wx, wy, wz), and the generator refuses any other
  twist ("the rate model's twist ['vz', 'wx', 'wy'] does not match pose_kind 'transform'"); this
  platform has 3 actuators and a 6 x 6 A (three actuation wrenches and three constraint wrenches)
  against a 6 x 3 B. So forward_rate, inverse_rate, rate_jacobians and statics are unsupported;
  ``passive_rates`` (from the loop closure) gives the (x, y, z, q) rates of slider rates.
  ``reduced_rate_model`` writes the 3 x 3 model over (vz, wx, wy) for the rate model to come.
* Singularity factors (``m.singularities``): ``leg<i>_link_horizontal`` = (C_i - S_i) . k / L
  (the link perpendicular to its rail: the stroke is stationary, a serial singularity), and
  ``platform_moves_with_sliders_locked`` = det(dg / dt) / (L r_p)^3, the Jacobian of the three
  platform-triangle equations g_ij = |C_i - C_j|^2 - 3 r_p^2 in the link angles t_i (forward pose
  below), with dC_i / dt_i = (C_i - S_i) x u_i: zero where the platform can move with the sliders
  locked, the type II singularity (where the loop-closure Jacobian is singular, and where the six
  wrenches the legs transmit, the force along each link and the constraint force along each
  revolute axis through C_i, are dependent: Joshi & Tsai 2002, "Jacobian analysis of limited-DOF
  parallel manipulators", J. Mech. Design 124(2)). A 3 x 3 determinant of small entries instead
  of that 6 x 6 one (a megabyte of expression).
* Forward pose: none (``forward=None``). By the parametrisation of the links in their planes,
  C_i = S_i + L (cos t_i e_i + sin t_i k), the forward problem is three equations
  |C_i - C_j|^2 = 3 r_p^2 of bidegree (2, 2) in the half-angle tangents of (t_i, t_j): at most
  16 assembly modes (the multihomogeneous Bezout number, reached over the complex numbers),
  32 solutions (p, q) with q ~ -q. ``MODE_COUNTS`` holds inputs whose real modes an independent
  solver (tests/test_prs3.py) has counted; at the input with 16 real modes, 8 have q3 = 0 and 8
  q0 = 0.
* Defaults (not from a paper: a compact design chosen here, links longer than r_b + r_p so that
  every kind of mode can occur): r_b = 0.2 m, r_p = 0.1 m, L = 0.35 m, rails of 1 m. Home: the
  platform level at z = 0.6 m (every stroke 0.6 - sqrt(L^2 - (r_b - r_p)^2) = 0.2646 m), links
  rising (branch 0), a regular configuration.
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator.blocks import laplace_det
from parakin.generator.frames import homogeneous, quaternion_rotation, rot_y, rot_z, sign_or_plus
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

r_b, r_p, L = sp.symbols("r_b r_p L", positive=True)
strokes = sp.symbols("d1:4", real=True)
x, y, z = sp.symbols("x y z", real=True)
quaternion = sp.symbols("q0:4", real=True)
sigma = sp.symbols("sigma1:4", real=True)
K = sp.Matrix([0, 0, 1])
#: rail angles theta_i: 0, 120, 240 deg, exactly (cos, sin)
ANGLES = [(sp.Integer(1), sp.Integer(0)), (-sp.Rational(1, 2), sp.sqrt(3) / 2), (-sp.Rational(1, 2), -sp.sqrt(3) / 2)]
RADIAL = [sp.Matrix([c, s, 0]) for c, s in ANGLES]
TANGENT = [sp.Matrix([-s, c, 0]) for c, s in ANGLES]

DEFAULTS = {r_b: 0.2, r_p: 0.1, L: 0.35}
#: the rails: 0 <= d_i <= RAIL_LENGTH (metres)
RAIL_LENGTH = 1.0
#: the home: the platform level at this height (metres), links rising
HOME_HEIGHT = 0.6

#: a constructed input: the strokes of the reachable pose with Z-Y-Z Euler angles (30, 10, -30) deg
#: at z = 0.55 m, links rising (branch 0), computed by tests/test_prs3.py's own geometry
CONSTRUCTED_EULER = (math.radians(30.0), math.radians(10.0), 0.55)
CONSTRUCTED_STROKES = [0.20000812689943637, 0.214364266713217, 0.23008487353552343]
#: actuated inputs and their number of real assembly modes (of 16 complex ones), counted by the
#: independent elimination of tests/test_prs3.py (two exact resultants leave a squarefree degree-16
#: polynomial; its real roots, isolated exactly, are the real modes; a multistart agrees), at the
#: default geometry. Not named Examples: the contract reproduces an actuated example's mode count
#: with forward_pose_all, which prs3 does not have yet (forward=None).
MODE_COUNTS: dict[str, tuple[list[float], int]] = {
    "constructed_tilt": (CONSTRUCTED_STROKES, 16),  # every complex mode real
    "twelve_real_modes": ([0.25, 0.3, 0.35], 12),
    "six_real_modes": ([0.4, 0.2, 0.25], 6),
}
#: two other real modes of CONSTRUCTED_STROKES, as the elimination found them (17 digits): the
#: links hanging below the sliders (branch 7), and the platform half-turned about the vertical
#: (q0 = 0: each joint on the far side of the centre from its rail), links rising
LINKS_DOWN_MODE = [
    [0.9892231642773259, -0.0069971726555918155, 0.1462483190740409, -0.0003116859380161129],
    [-0.00699717265559172, 0.9954568830376479, 0.0949559560417258, 0.0006997172655592252],
    [-0.14624831907404087, -0.09495595604172606, 0.9846800473149738, -0.12035987059448745],
    [0.0, 0.0, 0.0, 1.0],
]
HALF_TURN_MODE = [
    [-0.9897143199003277, 0.008575136118405201, -0.14280067235409544, 0.00015683093072584955],
    [0.008575136118405054, -0.9928509385148458, -0.11905242933573329, -0.0008575136118402679],
    [-0.14280067235409538, -0.11905242933573337, 0.9825652584151744, 0.39652384979467187],
    [0.0, 0.0, 0.0, 1.0],
]


def base_points() -> list[sp.Matrix]:
    """A_i = r_b e_i, in {B}."""
    return [r_b * e for e in RADIAL]


def sliders(values: tuple[sp.Expr, ...] = strokes) -> list[sp.Matrix]:
    """S_i = A_i + d_i k, in {B}."""
    return [a + d * K for a, d in zip(base_points(), values, strict=True)]


def platform_joints(rotation: sp.Matrix, position: sp.Matrix) -> list[sp.Matrix]:
    """C_i = R c_i + p with c_i = r_p e_i, in {B}."""
    return [rotation * (r_p * e) + position for e in RADIAL]


def state_pose() -> tuple[sp.Matrix, sp.Matrix]:
    """(R(q), p) of the passive variables."""
    return quaternion_rotation(quaternion), sp.Matrix([x, y, z])


def closure() -> ClosureModel:
    """Plane constraints (C_i - A_i) . u_i, links (|C_i - S_i|^2 - L^2) / (2 L), (q . q - 1) / 2."""
    rotation, position = state_pose()
    joints = platform_joints(rotation, position)
    planes = [(c - a).dot(u) for c, a, u in zip(joints, base_points(), TANGENT, strict=True)]
    links = [((c - s).dot(c - s) - L**2) / (2 * L) for c, s in zip(joints, sliders(), strict=True)]
    norm = (sum(q**2 for q in quaternion) - 1) / 2
    return ClosureModel(sp.Matrix([*planes, *links, norm]), sp.Matrix([1]), homogeneous(rotation, position))


def tilt(n: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """For a unit n = R^T k: the tilt R0 about a horizontal axis with R0^T k = n, its unit
    quaternion (q0 > 0) and the platform centre (x0, y0, 0) that the plane constraints give it
    (module docstring). R0 = I + [v]x + [v]x^2 / (1 + n_z), v = n x k; q = (1 + n_z, n x k)
    / sqrt(2 (1 + n_z))."""
    v = n.cross(K)
    skew = sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    rotation = sp.eye(3) + skew + (v * v.T - v.dot(v) * sp.eye(3)) / (1 + n[2])
    root = sp.sqrt(2 * (1 + n[2]))
    q = sp.Matrix([(1 + n[2]) / root, v[0] / root, v[1] / root, 0])
    centre = sp.Matrix([-r_p * (n[0] ** 2 - n[1] ** 2) / (2 * (1 + n[2])), r_p * n[0] * n[1] / (1 + n[2]), 0])
    return rotation, q, centre


def inverse() -> InverseSolution:
    """The reachable pose with the pose's height and tilt (module docstring), then per leg
    d_i = (C_i - A_i) . k - sigma_i sqrt(L^2 - |h_i|^2)."""
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    r0 = sp.Matrix(3, 3, sp.symbols("tilt11 tilt12 tilt13 tilt21 tilt22 tilt23 tilt31 tilt32 tilt33", real=True))
    centre = sp.Matrix(sp.symbols("x0 y0", real=True))
    turn = sp.Symbol("turn", real=True)  # +1: R0, -1: its half-turn Rot_z(pi) R0
    rotation, q, centre_expr = tilt(n)
    steps: list[tuple[sp.Symbol, sp.Expr]] = list(zip(n, POSE_ROTATION[2, :], strict=True))
    steps += list(zip(r0, rotation, strict=True))
    steps += list(zip(centre, centre_expr[:2], strict=True))
    # cos of the angle about the vertical from R0 to R: (R R0^T)_11
    steps.append((turn, sign_or_plus(POSE_ROTATION[0, :].dot(r0[0, :]))))
    half = [(1 + turn) / 2, (1 - turn) / 2]  # Rot_z(pi) q = (0, 0, 0, 1) q = (0, -q2, q1, q0)
    steps += [
        (x, turn * centre[0]),
        (y, turn * centre[1]),
        (z, POSE_POSITION[2]),
        (quaternion[0], half[0] * q[0]),
        (quaternion[1], half[0] * q[1] - half[1] * q[2]),
        (quaternion[2], half[0] * q[2] + half[1] * q[1]),
        (quaternion[3], half[1] * q[0]),
    ]
    turned = sp.diag(turn, turn, 1)
    joints = platform_joints(turned * r0, sp.Matrix([x, y, z]))
    validity = {}
    for i, (c, a) in enumerate(zip(joints, base_points(), strict=True)):
        disc = sp.Symbol(f"disc{i + 1}", real=True)
        steps.append((disc, L**2 - (c[0] - a[0]) ** 2 - (c[1] - a[1]) ** 2))
        steps.append((strokes[i], c[2] - a[2] - sigma[i] * sp.sqrt(sp.Max(0, disc))))
        validity[f"leg{i + 1}_reachable"] = disc / L**2
    return InverseSolution(steps, list(sigma), validity)


def factors() -> dict[str, sp.Expr]:
    """``leg<i>_link_horizontal`` = (C_i - S_i) . k / L, and ``platform_moves_with_sliders_locked``:
    det(dg / dt) / (L r_p)^3 for the link angles t_i and g_ij = |C_i - C_j|^2 - 3 r_p^2
    (module docstring), with dC_i / dt_i = (C_i - S_i) x u_i."""
    rotation, position = state_pose()
    joints = platform_joints(rotation, position)
    links = [c - s for c, s in zip(joints, sliders(), strict=True)]
    named = {f"leg{i + 1}_link_horizontal": link[2] / L for i, link in enumerate(links)}
    speeds = [link.cross(u) for link, u in zip(links, TANGENT, strict=True)]
    sides = [joints[i] - joints[(i + 1) % 3] for i in range(3)]  # C1 - C2, C2 - C3, C3 - C1
    # row (i, i + 1): 2 (C_i - C_j) . dC_i/dt_i in column i, -2 (C_i - C_j) . dC_j/dt_j in column j
    forward = sp.Mul(*(sides[i].dot(speeds[i]) for i in range(3)))
    backward = sp.Mul(*(sides[i].dot(speeds[(i + 1) % 3]) for i in range(3)))
    named["platform_moves_with_sliders_locked"] = 8 * (forward - backward) / (L * r_p) ** 3
    return named


def reduced_rate_model() -> RateModel:
    """The rates over the independent twist (vz, wx, wy), for the rate model of lower-mobility
    platforms that is still to come: NOT passed to ``Mechanism`` (the generator refuses a twist
    other than the pose kind's, module docstring). Each joint velocity is v + w x (C_i - p); the
    constraints u_i . (v + w x (C_i - p)) = 0 give the parasitic (vx, vy, wz) = -U_p^-1 U_i
    (vz, wx, wy) (U_p, U_i: the constraint rows' parasitic and independent columns) and the
    links (C_i - S_i) . (v + w x (C_i - p)) = (C_i - S_i) . k d_dot_i, so
    A = Lambda_i - Lambda_p U_p^-1 U_i (Lambda: the link rows, U_p^-1 = adj(U_p) / det(U_p))
    and B = diag((C_i - S_i) . k), det B the product of the serial factors. Checked against finite
    differences of Newton and of the inverse by tests/test_prs3.py."""
    rotation, position = state_pose()
    joints = platform_joints(rotation, position)
    links, constraints = [], []
    for c, s, u in zip(joints, sliders(), TANGENT, strict=True):
        links.append([*(c - s), *(c - position).cross(c - s)])
        constraints.append([*u, *(c - position).cross(u)])
    independent, parasitic = [2, 3, 4], [0, 1, 5]
    link_rows, constraint_rows = sp.Matrix(links), sp.Matrix(constraints)
    u_p = constraint_rows.extract([0, 1, 2], parasitic)
    coupling = u_p.adjugate() * constraint_rows.extract([0, 1, 2], independent) / laplace_det(u_p)
    a = link_rows.extract([0, 1, 2], independent) - link_rows.extract([0, 1, 2], parasitic) * coupling
    rises = [(c - s)[2] for c, s in zip(joints, sliders(), strict=True)]
    serial = {f"leg{i + 1}_link_rise": rise for i, rise in enumerate(rises)}
    return RateModel(["vz", "wx", "wy"], a, sp.diag(*rises), serial)


def drawing() -> Drawing:
    """Base triangle A_i, the rails A_i -> A_i + RAIL_LENGTH k, the sliders (a short block on
    the rail around S_i), the links S_i -> C_i and the platform triangle C_i."""
    rotation, position = state_pose()
    block = r_b / 8 * K
    slider = sliders()
    return Drawing(
        points={
            "base": sp.Matrix.hstack(*base_points()),
            "rail_top": sp.Matrix.hstack(*(a + RAIL_LENGTH * K for a in base_points())),
            "slider": sp.Matrix.hstack(*slider),
            "slider_ends": sp.Matrix.hstack(*(s + sign * block for s in slider for sign in (-1, 1))),
            "platform": sp.Matrix.hstack(*platform_joints(rotation, position)),
        },
        polylines={
            "base": [("base", i % 3) for i in range(4)],
            **{f"rail{i + 1}": [("base", i), ("rail_top", i)] for i in range(3)},
            **{f"slider{i + 1}": [("slider_ends", 2 * i), ("slider_ends", 2 * i + 1)] for i in range(3)},
            **{f"link{i + 1}": [("slider", i), ("platform", i)] for i in range(3)},
            "platform": [("platform", i % 3) for i in range(4)],
        },
    )


def level_stroke() -> float:
    """The stroke that holds the level platform at HOME_HEIGHT: its joints are r_b - r_p from
    the rails, so d = z - sqrt(L^2 - (r_b - r_p)^2) (geometry, independent of the inverse)."""
    return HOME_HEIGHT - math.sqrt(DEFAULTS[L] ** 2 - (DEFAULTS[r_b] - DEFAULTS[r_p]) ** 2)


LEVEL_POSE = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, HOME_HEIGHT], [0.0, 0.0, 0.0, 1.0]]


def home() -> dict[sp.Symbol, float]:
    """LEVEL_POSE on branch 0 (links rising): the inverse itself, evaluated at 17 digits."""
    pose = sp.Matrix(LEVEL_POSE)
    values = inverse().at(pose[:3, :3], pose[:3, 3], 0, DEFAULTS)
    return {v: values[v] for v in [*strokes, x, y, z, *quaternion]}


def euler_pose(alpha: float, beta: float, height: float) -> list[list[float]]:
    """The reachable pose with Z-Y-Z Euler angles (alpha, beta, -alpha) at ``height``: the
    centre (x0, y0) of the module docstring, in Euler angles (17 digits)."""
    rotation = rot_z(alpha) * rot_y(beta) * rot_z(-alpha)
    x0 = DEFAULTS[r_p] * (math.cos(beta) - 1) * math.cos(2 * alpha) / 2
    y0 = DEFAULTS[r_p] * (1 - math.cos(beta)) * math.sin(2 * alpha) / 2
    return [[float(v) for v in row] for row in homogeneous(rotation, [x0, y0, height]).evalf(17).tolist()]


def examples() -> list[Example]:
    return [
        Example(
            "sixteen_real_modes",
            "The strokes of 'constructed_tilt': all 16 complex solutions real (counted by an exact "
            "elimination in tests/test_prs3.py), every one found from the polynomial form the generator "
            "derives from the closure",
            actuated=CONSTRUCTED_STROKES,
            expected={"mode_count": 16},
            tolerance=1e-9,
        ),
        Example(
            "level_home",
            "The platform level at z = 0.6 m: every stroke z - sqrt(L^2 - (r_b - r_p)^2) (its joints are "
            "r_b - r_p from the rails), links rising (branch 0); no parasitic motion",
            pose=LEVEL_POSE,
            branch=0,
            expected={"actuated": [level_stroke()] * 3, "passive": [0.0, 0.0, HOME_HEIGHT, 1.0, 0.0, 0.0, 0.0]},
            tolerance=1e-12,
        ),
        Example(
            "constructed_tilt",
            "Z-Y-Z Euler angles (30, 10, -30) deg at z = 0.55 m with its parasitic centre, links rising: "
            "the strokes of the test's own geometry (an input with 16 real modes, MODE_COUNTS)",
            pose=euler_pose(*CONSTRUCTED_EULER),
            branch=0,
            expected={"actuated": CONSTRUCTED_STROKES},
            tolerance=1e-12,
        ),
        Example(
            "constructed_links_down",
            "Another real mode of the constructed strokes (independent elimination): the links hang below "
            "the sliders (branch 7), the platform under the base plane",
            pose=LINKS_DOWN_MODE,
            expected={"actuated": CONSTRUCTED_STROKES},
            tolerance=1e-12,
        ),
        Example(
            "constructed_half_turn",
            "Another real mode of the constructed strokes (independent elimination): the platform "
            "half-turned about the vertical (q0 = 0), links rising; the inverse reads the half-turn from R",
            pose=HALF_TURN_MODE,
            expected={"actuated": CONSTRUCTED_STROKES},
            tolerance=1e-12,
        ),
    ]


def build() -> Mechanism:
    return Mechanism(
        name="prs3",
        title="3-PRS parallel manipulator (vertical rails, 3 DOF with parasitic motion), no forward model yet",
        citation=Citation(
            ("M. Carretero", "R. P. Podhorodeski", "M. A. Nahon", "C. M. Gosselin"),
            "Kinematic analysis and optimization of a new three degree-of-freedom spatial parallel manipulator",
            2000,
            "Journal of Mechanical Design 122(1)",
        ),
        parameters=dict(DEFAULTS),
        actuated=list(strokes),
        passive=[x, y, z, *quaternion],
        legs=[],
        inverse=inverse(),
        forward=None,
        home=home(),
        limits={d: (0.0, RAIL_LENGTH) for d in strokes},
        dimensionless=list(quaternion),
        factors=factors(),
        closure=closure(),
        rates=None,
        pose_kind="transform",
        parameter_info={
            r_b: ParameterInfo("m", "radius of the circle of the rails A_i (base)", "positive"),
            r_p: ParameterInfo("m", "radius of the circle of the spherical joints c_i (platform)", "positive"),
            L: ParameterInfo("m", "length of each link, revolute joint S_i to spherical joint C_i", "positive"),
        },
        examples=examples(),
        drawing=drawing(),
    )
