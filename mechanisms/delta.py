"""The Delta robot (3-RUU, Clavel 1988): three actuated revolute joints on the base, each driving an
upper arm whose end is joined to the platform by a parallelogram forearm, so the platform only
translates. Closed forms as in the literature (e.g. R. L. Williams II, "The Delta parallel robot:
kinematics solutions", 2016; Zsombor-Murray 2004): per leg a tan-half-angle quadratic (inverse),
and the intersection of three spheres (forward).

Frames and conventions (SI, radians), textbook notation R, r, L, l:
* {B}: origin at the centre of the base, z up. Leg i sits at eta_i = 2 pi (i - 1) / 3 about z:
  radial unit e_i = (cos eta_i, sin eta_i, 0), motor axis along t_i = z x e_i through the motor
  joint b_i = R e_i (R: base radius).
* The upper arm (length L) points along u_i = cos(theta_i) e_i - sin(theta_i) z: theta_i = 0 is
  horizontal and outward, theta_i > 0 turns it down (a right-handed rotation about t_i). Elbow
  c_i = b_i + L u_i.
* {P}: origin at the centre of the platform (the tool point), R = I always (pose_kind
  'translation': ^B_P T = [I, p], p = (x, y, z); ``inverse_pose`` reads p and ignores R, and also
  takes p itself). Platform joints P_i = p + r e_i (r: platform radius). The forearm (length l)
  joins c_i to P_i; its parallelogram is drawn as one bar.
* Passive variables (the Newton unknowns): x, y, z. Residual: (|d_i|^2 - l^2) / (2 l) (metres;
  |d_i| - l to first order) with the forearm d_i = p + r e_i - c_i; no false closure (alignment
  1).
* Inverse: with a_i = p + (r - R) e_i (the platform joint seen from the motor joint), leg i is
  E cos(theta_i) + F sin(theta_i) + G = 0, E = -2 L a_i . e_i, F = 2 L a_i . z,
  G = |a_i|^2 + L^2 - l^2; with tau = tan(theta_i / 2) the quadratic (G - E) tau^2 + 2 F tau +
  (G + E) = 0, theta_i = 2 atan2(-F - sigma_i sqrt(E^2 + F^2 - G^2), G - E). sigma_i = +1 turns
  the arm from the line b_i -> P_i towards smaller theta_i: the elbow outside, the usual working
  mode with the platform below the base. Validity ``leg<i>_reachable`` = (E^2 + F^2 - G^2) /
  (E^2 + F^2 + G^2), the discriminant made unitless.
  Branch k: signs (sigma1, sigma2, sigma3) of ``InversePose.branches[k]``, branch 0 = all +1
  (every elbow out), branch 7 = all -1.
* Forward (three spheres): p is at distance l from the shifted elbows c'_i = c_i - r e_i =
  (R - r) e_i + L u_i. With n_a = c'_2 - c'_1, n_b = c'_3 - c'_1, n = n_a x n_b, the circumcentre
  of the c'_i is c'_1 + v0, v0 = (|n_a|^2 n_b x n + |n_b|^2 n x n_a) / (2 |n|^2), and
  p = c'_1 + v0 + mu n / |n| with mu^2 + |v0|^2 - l^2 = 0: the forward polynomial is this
  quadratic in mu (degree 2, two modes mirrored through the plane of the c'_i; the platform below
  them is the working one). No branch signs. Degeneracy ``elbow_centres_collinear``: |n| / l^2
  (then the spheres meet in a circle or not at all).
* Rates: A p_dot = B theta_dot (twist vx, vy, vz of the platform, in {B}) from d_i . d_i = l^2:
  rows of A are d_i^T, B = diag(L d_i . du_i/dtheta_i) = diag(t_i . ((c_i - b_i) x d_i)),
  du_i/dtheta_i = -sin(theta_i) e_i - cos(theta_i) z. Serial (type I): ``leg<i>_forearm_in_arm_plane``, L d_i . du_i/dtheta_i = 0,
  the forearm in the plane of the arm and the motor axis (arm and forearm stretched or folded as
  seen along the axis, the workspace boundary). Type II: ``forearms_coplanar``, det[d_1 d_2 d_3]
  = 0 (the three forearms parallel to one plane: the platform gains a motion).
* Model: three R-U-U legs (``parakin.generator.joints.crank_leg``: the crank about t_i from e_i,
  the forearm a distance; in the joint graph a parallelogram hinged about t_i, which the screw
  analysis finds holds the platform to three translations) on a translating platform; closure,
  rates, factors, inverse and drawing are derived from them, the forward three-sphere
  elimination is written here.
* Defaults (illustrative, of the size of a picking Delta): R = 0.2, r = 0.05, L = 0.35, l = 1.3 m.
  Then R - r + L = 0.5 and (0.5, 1.2, 1.3) is a 5-12-13 triangle: at p = (0, 0, -1.2) every arm
  is horizontal (theta = 0, the home configuration).
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import joints
from parakin.generator.frames import homogeneous, rot_z, translation
from parakin.generator.model import (
    Citation,
    Drawing,
    Example,
    ForwardElimination,
    Mechanism,
    ParameterInfo,
)

R, r, L, ell = sp.symbols("R r L l", positive=True)  # ell: the forearm length, named l
theta = sp.symbols("theta1:4", real=True)
x, y, z = sp.symbols("x y z", real=True)
ETA = [2 * sp.pi * i / 3 for i in range(3)]
Z = sp.Matrix([0, 0, 1])


def radial(i: int) -> sp.Matrix:
    """e_i = (cos eta_i, sin eta_i, 0)."""
    return rot_z(ETA[i]) * sp.Matrix([1, 0, 0])


def arm(i: int, angle: sp.Expr) -> sp.Matrix:
    """u_i(theta) = cos(theta) e_i - sin(theta) z."""
    return sp.cos(angle) * radial(i) - sp.sin(angle) * Z


MODEL = joints.DistanceMechanism(
    joints.platform("translation"),
    [
        joints.crank_leg(
            R * radial(i),
            Z.cross(radial(i)),
            radial(i),
            L,
            ell,
            r * radial(i),
            theta[i],
            sign=-1,
            serial_name="leg{k}_forearm_in_arm_plane",
            parallelogram=Z.cross(radial(i)),
        )
        for i in range(3)
    ],
    parallel_name="forearms_coplanar",
)


def forward() -> ForwardElimination:
    """The three-sphere intersection as a quadratic in mu (module docstring)."""
    mu = sp.Symbol("mu", real=True)
    centres = [sp.Matrix(sp.symbols(f"c{i + 1}_x c{i + 1}_y c{i + 1}_z", real=True)) for i in range(3)]
    n_a = sp.Matrix(sp.symbols("na_x na_y na_z", real=True))
    n_b = sp.Matrix(sp.symbols("nb_x nb_y nb_z", real=True))
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    v0 = sp.Matrix(sp.symbols("v0_x v0_y v0_z", real=True))
    n2, n_norm, v0_sq = sp.symbols("n_squared n_norm v0_squared", real=True)
    auxiliary: list[tuple[sp.Symbol, sp.Expr]] = []
    for i in range(3):
        shifted = (R - r) * radial(i) + L * arm(i, theta[i])
        auxiliary += [(centres[i][k], shifted[k]) for k in range(3)]
    auxiliary += [(n_a[k], centres[1][k] - centres[0][k]) for k in range(3)]
    auxiliary += [(n_b[k], centres[2][k] - centres[0][k]) for k in range(3)]
    auxiliary += [(n[k], n_a.cross(n_b)[k]) for k in range(3)]
    auxiliary += [(n2, n.dot(n)), (n_norm, sp.sqrt(n2))]
    circumcentre = (n_a.dot(n_a) * n_b.cross(n) + n_b.dot(n_b) * n.cross(n_a)) / (2 * sp.Max(n2, 1e-300))
    auxiliary += [(v0[k], circumcentre[k]) for k in range(3)]
    auxiliary.append((v0_sq, v0.dot(v0)))
    position = centres[0] + v0 + mu * n / sp.Max(n_norm, 1e-300)
    return ForwardElimination(
        unknown=mu,
        coefficients=[v0_sq - ell**2, sp.Integer(0), sp.Integer(1)],
        branches=[],
        auxiliary=auxiliary,
        back_substitution=[],
        pose=translation(*position),
        degeneracies={"elbow_centres_collinear": n_norm / ell**2},
    )


def drawing() -> Drawing:
    """The model's parts (motor joints b_i, elbows c_i, platform joints P_i; each leg b_i -> c_i
    -> P_i, the base and platform triangles) with the tool point p and the platform spokes."""
    parts = MODEL.drawing()
    position = sp.Matrix([x, y, z])
    points = parts.points | {"platform": sp.Matrix.hstack(parts.points["platform"], position)}
    spokes = [("platform", 0), ("platform", 3), ("platform", 1), ("platform", 3), ("platform", 2)]
    return Drawing(points=points, polylines=parts.polylines | {"tool": spokes})


#: the home pose: arms horizontal, (R - r + L, -z, l) = (0.5, 1.2, 1.3), a 5-12-13 triangle
HOME_Z = -1.2
FOLDED = -2 * math.atan(8.0)


def pose_list(px: float, py: float, pz: float) -> list[list[float]]:
    transform = homogeneous(sp.eye(3), [px, py, pz])
    return [[float(transform[i, j]) for j in range(4)] for i in range(4)]


EXAMPLES = [
    Example(
        name="home_elbows_out",
        description="p = (0, 0, -1.2) m at the defaults, branch 0: every arm horizontal, theta = 0 "
        "(by hand: R - r + L = 0.5, and 0.5^2 + 1.2^2 = 1.3^2 = l^2, a 5-12-13 triangle)",
        pose=pose_list(0.0, 0.0, HOME_Z),
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
        pose=pose_list(0.0, 0.0, HOME_Z),
        branch=7,
        expected={"actuated": [FOLDED, FOLDED, FOLDED], "passive": [0.0, 0.0, HOME_Z]},
        tolerance=1e-12,
    ),
    Example(
        name="arms_horizontal",
        description="theta = (0, 0, 0): the shifted elbows lie on the circle of radius 0.5 m at z = 0, "
        "so p = (0, 0, -1.2) or its mirror (0, 0, 1.2) (by hand: 1.3^2 - 0.5^2 = 1.2^2); 2 modes",
        actuated=[0.0, 0.0, 0.0],
        expected={"mode_count": 2, "poses": [pose_list(0.0, 0.0, HOME_Z), pose_list(0.0, 0.0, -HOME_Z)]},
        tolerance=1e-12,
    ),
]


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
        **MODEL.fields() | {"drawing": drawing()},
        forward=forward(),
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
