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
* The model (``MODEL``) is three P-R-S legs of the joint language (``generator/joints.py``):
  a slider on rail i, a revolute joint with axis u_i, a link of length L, a spherical joint at
  c_i; every derivation below comes from it, the inverse's reading of the pose (``motion``)
  aside.
* Rates (derived: Joshi & Tsai 2002, "Jacobian analysis of limited-DOF parallel manipulators",
  J. Mech. Design 124(2)): A twist = B d_dot over the whole twist (vx, vy, vz, wx, wy, wz), A's
  row i the actuation wrench of leg i, the force along the link (C_i - S_i, (C_i - p) x (C_i -
  S_i)), B = diag((C_i - S_i) . k); and three constraint wrenches, the force along each
  revolute axis through C_i, (u_i, (C_i - p) x u_i): every motion has constraints twist = 0.
  ``forward_rate`` returns the whole twist, parasitic (vx, vy, wz) included; ``inverse_rate``
  takes only twists the platform can make (BadInputError otherwise); ``actuator_forces`` and
  ``constraint_forces`` hold a wrench together; ``stiffness`` acts on the feasible motions.
* Singularity factors (``m.singularities``): ``leg<i>_link_horizontal`` = (C_i - S_i) . k
  (metres; the link perpendicular to its rail: the stroke is stationary, a serial singularity),
  and ``platform_moves_with_sliders_locked`` = det [A; constraints], the six wrenches the legs
  transmit dependent: zero where the platform can move with the sliders locked (the type II
  singularity, where the loop-closure Jacobian is singular), written by Laplace's expansion in
  3 x 3 blocks with polynomial entries in the quaternion.
* Forward pose: none written (``forward=None``): ``forward_pose_all`` tracks the polynomial
  form the generator derives from the closure. By the parametrisation of the links in their planes,
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
from dataclasses import replace

import sympy as sp
from parakin.generator import joints
from parakin.generator.frames import homogeneous, rot_y, rot_z, sign_or_plus
from parakin.generator.model import POSE_POSITION, POSE_ROTATION, Citation, Example, Mechanism, ParameterInfo

r_b, r_p, L = sp.symbols("r_b r_p L", positive=True)
strokes = sp.symbols("d1:4", real=True)
x, y, z = sp.symbols("x y z", real=True)
quaternion = sp.symbols("q0:4", real=True)
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


def motion() -> joints.Platform:
    """A spatial platform (x, y, z, unit quaternion) whose inverse reads the reachable pose with
    the pose's height and tilt (module docstring), not the pose's own x, y and turn."""
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    r0 = sp.Matrix(3, 3, sp.symbols("tilt11 tilt12 tilt13 tilt21 tilt22 tilt23 tilt31 tilt32 tilt33", real=True))
    centre = sp.Matrix(sp.symbols("x0 y0", real=True))
    turn = sp.Symbol("turn", real=True)  # +1: R0, -1: its half-turn Rot_z(pi) R0
    rotation, q, centre_expr = tilt(n)
    read = [*zip(n, POSE_ROTATION[2, :], strict=True), *zip(r0, rotation, strict=True)]
    read += [*zip(centre, centre_expr[:2], strict=True), (turn, sign_or_plus(POSE_ROTATION[0, :].dot(r0[0, :])))]
    half = [(1 + turn) / 2, (1 - turn) / 2]  # Rot_z(pi) q = (0, 0, 0, 1) q = (0, -q2, q1, q0)
    turned = [half[0] * q[0], half[0] * q[1] - half[1] * q[2], half[0] * q[2] + half[1] * q[1], half[1] * q[0]]
    read += [(x, turn * centre[0]), (y, turn * centre[1]), (z, POSE_POSITION[2]), *zip(quaternion, turned, strict=True)]
    pose = (sp.diag(turn, turn, 1) * r0, sp.Matrix([x, y, z]))
    return replace(joints.platform("transform"), read=tuple(read), pose=pose)


#: the model: three P-R-S legs (a slider on a vertical rail, a revolute joint tangent to the base
#: circle, a link to a spherical joint) on a spatial platform; closure, rates with the three
#: constraint wrenches, singularity factors, inverse and drawing are derived from it
MODEL = joints.DistanceMechanism(
    motion(),
    [
        joints.slider_leg(r_b * e, K, L, r_p * e, d, serial_name="leg{k}_link_horizontal", revolute_axis=u)
        for e, u, d in zip(RADIAL, TANGENT, strokes, strict=True)
    ],
    parallel_name="platform_moves_with_sliders_locked",
)


def level_stroke() -> float:
    """The stroke that holds the level platform at HOME_HEIGHT: its joints are r_b - r_p from
    the rails, so d = z - sqrt(L^2 - (r_b - r_p)^2) (geometry, independent of the inverse)."""
    return HOME_HEIGHT - math.sqrt(DEFAULTS[L] ** 2 - (DEFAULTS[r_b] - DEFAULTS[r_p]) ** 2)


LEVEL_POSE = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, HOME_HEIGHT], [0.0, 0.0, 0.0, 1.0]]


def home() -> dict[sp.Symbol, float]:
    """LEVEL_POSE on branch 0 (links rising): the inverse itself, evaluated at 17 digits."""
    pose = sp.Matrix(LEVEL_POSE)
    return MODEL.home_at(pose[:3, :3], pose[:3, 3], 0, DEFAULTS)


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
        title="3-PRS parallel manipulator (vertical rails, 3 DOF with parasitic motion)",
        citation=Citation(
            ("M. Carretero", "R. P. Podhorodeski", "M. A. Nahon", "C. M. Gosselin"),
            "Kinematic analysis and optimization of a new three degree-of-freedom spatial parallel manipulator",
            2000,
            "Journal of Mechanical Design 122(1)",
        ),
        parameters=dict(DEFAULTS),
        **MODEL.fields(),
        forward=None,
        home=home(),
        limits={d: (0.0, RAIL_LENGTH) for d in strokes},
        parameter_info={
            r_b: ParameterInfo("m", "radius of the circle of the rails A_i (base)", "positive"),
            r_p: ParameterInfo("m", "radius of the circle of the spherical joints c_i (platform)", "positive"),
            L: ParameterInfo("m", "length of each link, revolute joint S_i to spherical joint C_i", "positive"),
        },
        examples=examples(),
    )
