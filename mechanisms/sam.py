"""SAM, the Spherically-Actuated platform Manipulator (2-SPU, 6 dof).

Reference: R. L. Williams II and D. B. Poling, "Spherically-Actuated Platform Manipulator",
Journal of Robotic Systems, 2000 (``shared/papers/000_0fd26f24943f9b56.txt``).

Conventions, as in the paper:
* Frames: fixed base {B}; platform {P}; each leg is a modified-DH chain (Craig), Table I, from
  its actuator frame {0} (^B_0 T: {0} at y = -L1 in {B}) to the U-joint frame {6}, and
  ^6_P T places {P} with its origin at x6 = -L4 (eq 3). Both U joints lie on the Y_P axis.
* Left leg: active S joint (theta1 roll, theta2 yaw, theta3 pitch), passive prismatic L2 and
  U joint (phi2, phi3). Right leg: the same table with theta4..6, L3, phi5, phi6 and the signs of
  L1 and L4 reversed.
* Pose: ^B_P T, or {x, y, z, alpha, beta, gamma} with Z-Y-X Euler angles (eq 2).
* Leg Jacobians (eq 9): columns (theta, theta, theta, L, phi, phi); rows (v, w) of {P}, the
  linear velocity of the origin of {P} and the angular velocity, both in {B}.
* Inverse branches per leg, signs (epsilon, delta): epsilon = sign of sin(phi2) (the two U-joint
  sets of eq 5), delta = sign of cos(theta2) (the two S-joint sets of eq 8). Branch 0 of a leg is
  (+, +), the first row of Table II; SAM branch k = 4 * left branch + right branch.
* Lengths in metres, angles in radians.

What is written here: Table I per leg with eq (3)'s fixed transforms (``spu_leg``), the actuated
S joints, the parameters, the home, the examples, and the closed-form forward pose
(``forward_elimination``, an accelerator). The generator (``parakin.generator.chains``) reads the
S-P-U structure from the table and derives the rest: the inverse of section 3.1 as subproblems
(L2 the distance of the S and U centres, eq 5; the U joint pointing the leg line, eq 5's two sets,
its sign the one above: sin(phi2) = sign * rho / L2; the S joint's Euler decomposition, eqs 6-8,
its sign that of cos(theta2) = sin(theta2 + 90 deg)), the validity conditions
``<leg>_u_joint_not_aligned`` (the leg along the U joint's platform axis Z_P: phi3 undetermined)
and ``<leg>_s_joint_not_locked`` (|cos(theta2)|: gimbal lock), the leg determinants' factors
(eq 13-14: ``<leg>_leg_length``, ``<leg>_s_joint_gimbal_lock``, ``<leg>_u_joint_aligned``), the
closed-loop factors (``u_joint_axes_parallel``: the axes z4 of both U joints and Z_P parallel to
one plane; ``legs_coplanar_with_platform_x``: both leg lines and X_P; ``platform_span`` = 2 L4),
the joint limits (L2, L3 >= 0) and the drawing (S centres, U centres as each leg reaches them,
the platform bar with a marker at L4 along X_P).
* Home (the default Newton guess, ``parakin plot sam``, exported C examples): the last pose of
  section 4.2's inverse-pose trajectory, {x y z alpha beta gamma} = {0.05 0.05 0.714 0 0 5 deg}
  (ten steps of {5 mm, 5 mm, 5 mm, 0, 0, 0.5 deg} from eq (15), ``SECTION42_HOME``), on the
  paper's branch 2 (``PAPER_BRANCH``): a regular configuration (closure Jacobian pivot ratio 0.50,
  four assembly modes). The paper's nominal pose eq (15) itself is a type II singularity (both
  U-joint axes z4 parallel to X_B, a self-motion; tests/test_sam_paper.py): it stays the named
  example ``eq15_nominal``, never the home.
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import chains
from parakin.generator.frames import ModifiedDHLink, euler_zyx_rotation, homogeneous, translation
from parakin.generator.model import (
    POSE_POSITION,
    Citation,
    Example,
    ForwardElimination,
    Mechanism,
    ParameterInfo,
    SerialChain,
)

L1, L4 = sp.symbols("L1 L4", positive=True)
theta = sp.symbols("theta1:7", real=True)
L2, L3 = sp.symbols("L2 L3", real=True)
phi2, phi3, phi5, phi6 = sp.symbols("phi2 phi3 phi5 phi6", real=True)

HALF_PI = sp.pi / 2
#: the inverse branch of eq (15): left leg (+, +), right leg (-, +) (module docstring)
PAPER_BRANCH = 2
#: section 4.2: the nominal pose plus ten steps of {5 mm, 5 mm, 5 mm, 0, 0, 0.5 deg} (m, rad)
SECTION42_HOME = (0.05, 0.05, 0.714, 0.0, 0.0, math.radians(5.0))


def spu_leg(name: str, thetas, length, phis, base_offset, platform_offset) -> SerialChain:
    """One SPU leg: Table I with the given variables; base_offset = L1, platform_offset = L4 for
    the left leg (both negated for the right leg, section 3.1)."""
    t1, t2, t3 = thetas
    p2, p3 = phis
    links = [
        ModifiedDHLink(0, 0, 0, t1 + HALF_PI, t1),
        ModifiedDHLink(HALF_PI, 0, 0, t2 + HALF_PI, t2),
        ModifiedDHLink(HALF_PI, 0, 0, t3, t3),
        ModifiedDHLink(-HALF_PI, length, 0, 0, length),
        ModifiedDHLink(0, 0, 0, p2 + HALF_PI, p2),
        ModifiedDHLink(HALF_PI, 0, 0, p3, p3),
    ]
    # eq (3): ^B_0 T and ^6_P T
    base = translation(0, -base_offset, 0)
    tool = homogeneous(sp.Matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]]), [-platform_offset, 0, 0])
    return SerialChain(name, base, links, tool, [t1, t2, t3, length, p2, p3])


def forward_elimination(left: SerialChain, right: SerialChain) -> ForwardElimination:
    """Closed-form forward pose (not in the paper, which uses Newton only).

    In Table I, z4 = z5 (alpha4 = 0) depends on the S-joint angles only, and z6 of both legs is the
    platform Z axis; the U joint makes z6 normal to z5. So Z_P = sign * (z4_L x z4_R) / |.|.
    The U joints are U_L = S_L + L2 x3_L and U_R = S_R + L3 x3_R (x3 is the leg line), and
    U_R - U_L = 2 L4 Y_P with Y_P normal to Z_P: one linear equation (dot with Z_P) and one
    quadratic (|U_R - U_L| = 2 L4). On the line (L2, L3) = p0 + t d of the linear equation the
    quadratic becomes a univariate quadratic in t. Both signs of Z_P give a pose: 2 x 2 modes.
    """
    frames_left, frames_right = left.frames(), right.frames()
    z4_left, z4_right = frames_left[4][:3, 2], frames_right[4][:3, 2]
    x3_left, x3_right = frames_left[3][:3, 0], frames_right[3][:3, 0]
    s_left, s_right = left.base[:3, 3], right.base[:3, 3]
    t, sign = sp.symbols("t sigma", real=True)
    normal = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    # the linear equation a L2 + b L3 + c = 0 (dot with the unnormalised normal)
    a_lin, b_lin, c_lin = sp.symbols("a_lin b_lin c_lin", real=True)
    line_norm2 = sp.Symbol("line_norm2", positive=True)
    normal_norm = sp.Symbol("normal_norm", positive=True)
    length_left, length_right = sp.symbols("L2_t L3_t", real=True)
    normal_expr = z4_left.cross(z4_right)
    span = (s_right - s_left) + length_right * x3_right - length_left * x3_left
    # coefficients of |span|^2 - (2 L4)^2 in t, with L2 = p0_2 + t d_2, L3 = p0_3 + t d_3
    base_point = sp.Matrix([-c_lin * a_lin, -c_lin * b_lin]) / line_norm2
    direction = sp.Matrix([b_lin, -a_lin])
    on_line = {length_left: base_point[0] + t * direction[0], length_right: base_point[1] + t * direction[1]}
    quadratic = sp.expand((span.dot(span) - (2 * L4) ** 2).subs(on_line))
    coefficients = [quadratic.coeff(t, k) for k in range(3)]
    auxiliary = [
        (normal[0], normal_expr[0]),
        (normal[1], normal_expr[1]),
        (normal[2], normal_expr[2]),
        (a_lin, -x3_left.dot(normal)),
        (b_lin, x3_right.dot(normal)),
        (c_lin, (s_right - s_left).dot(normal)),
        (line_norm2, a_lin**2 + b_lin**2),
        (normal_norm, sp.sqrt(normal.dot(normal))),
    ]
    # back substitution: pose from the root t and the sign of Z_P
    y_axis_sym = sp.Matrix(sp.symbols("yP_x yP_y yP_z", real=True))
    z_axis_sym = sp.Matrix(sp.symbols("zP_x zP_y zP_z", real=True))
    u_left_sym = sp.Matrix(sp.symbols("UL_x UL_y UL_z", real=True))
    back = [
        (length_left, on_line[length_left]),
        (length_right, on_line[length_right]),
    ]
    back += [(z_axis_sym[k], sign * normal[k] / normal_norm) for k in range(3)]
    u_left = s_left + length_left * x3_left
    back += [(u_left_sym[k], u_left[k]) for k in range(3)]
    back += [(y_axis_sym[k], span[k] / (2 * L4)) for k in range(3)]
    x_axis = y_axis_sym.cross(z_axis_sym)
    origin = u_left_sym + L4 * y_axis_sym  # left U joint sits at y = -L4 in {P}
    pose = homogeneous(sp.Matrix.hstack(x_axis, y_axis_sym, z_axis_sym), origin)
    return ForwardElimination(
        unknown=t,
        coefficients=coefficients,
        branches=[sign],
        auxiliary=auxiliary,
        back_substitution=back,
        pose=pose,
        degeneracies={"u_joint_axes_parallel": normal_norm, "legs_parallel_to_platform": line_norm2},
    )


def table2(row: int, t1: float, t2: float, t3: float, length: float, p2: float, p3: float) -> list[float]:
    """Table II: row ``row`` of one leg's four inverse solutions, from the first row (eqs 5, 8).
    Row r is leg branch r - 1 of the module docstring (signs of sin(phi2), cos(theta2))."""
    pi = math.pi
    return [
        [t1, t2, t3, length, p2, p3],
        [t1 + pi, pi - t2, t3 + pi, length, p2, p3],
        [t1 + pi, -t2, -t3, length, -p2, p3 + pi],
        [t1, pi + t2, pi - t3, length, -p2, p3 + pi],
    ][row - 1]


def examples() -> list[Example]:
    """Eq (15), the nominal configuration, printed to 3 decimals (m) and whole degrees, and the
    other Table II solutions of its left leg. The printed pose z = 0.664 is itself rounded:
    theta2 = -15 deg exactly gives z = 0.6636, and at z = 0.664 theta2 = -14.99 deg, L2 =
    0.6874 m (tests/test_sam_paper.py). Tolerance 5e-4 (m and rad): half a unit in the last
    printed digit of the lengths, well within the whole degrees of the angles (0.5 deg). The pose
    is a type II singularity (module docstring): forward_pose_all at its joint values raises
    SelfMotionError with the curve of poses (tests/test_self_motion.py)."""
    deg = math.pi / 180
    pose = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.664], [0.0, 0.0, 0.0, 1.0]]
    left = [0.0, -15 * deg, 0.0, 0.687, 15 * deg, 0.0]  # theta1..3, L2, phi2, phi3 of eq (15)
    right = [0.0, 15 * deg, 0.0, 0.687, -15 * deg, 0.0]  # theta4..6, L3, phi5, phi6
    result = []
    for row in (1, 2, 3, 4):
        joints = table2(row, *left)
        if row == 1:
            name, what = "eq15_nominal", "eq (15) nominal configuration (a type II singularity: a self-motion)"
        else:
            name, what = f"table2_row{row}", f"Table II row {row} applied to the left leg of eq (15)"
        result.append(
            Example(
                name=name,
                description=f"{what}: {{x y z alpha beta gamma}} = {{0 0 0.664 0 0 0}} (m, deg), inverse "
                f"branch {4 * (row - 1) + PAPER_BRANCH} (left leg branch {row - 1}, right leg (-, +)); the printed "
                "z = 0.664 is rounded (theta2 = -15 deg gives z = 0.6636), so tolerance 5e-4 m / rad, "
                "half a unit in the last printed digit of L2 = 0.687",
                pose=pose,
                branch=4 * (row - 1) + PAPER_BRANCH,
                expected={"actuated": joints[:3] + right[:3], "passive": joints[3:] + right[3:]},
                tolerance=5e-4,
            )
        )
    return result


def build() -> Mechanism:
    left = spu_leg("left", theta[:3], L2, (phi2, phi3), L1, L4)
    right = spu_leg("right", theta[3:], L3, (phi5, phi6), -L1, -L4)
    # the derived branch signs are (epsilon, delta) of the module docstring, in the paper's names
    model = chains.ChainMechanism(
        [
            chains.chain_leg(left, theta[:3], ("epsilon_left", "delta_left")),
            chains.chain_leg(right, theta[3:], ("epsilon_right", "delta_right")),
        ]
    )
    parameters = {L1: 0.5334, L4: 0.3556}  # section 4.1, metres
    x, y, z, alpha, beta, gamma = SECTION42_HOME
    return Mechanism(
        name="sam",
        title="Spherically-Actuated platform Manipulator (2-SPU), Williams & Poling (2000)",
        citation=Citation(
            ("R. L. Williams II", "D. B. Poling"),
            "Spherically-actuated platform manipulator",
            2000,
            "Journal of Robotic Systems (final manuscript, December 2000)",
        ),
        parameters=parameters,
        **model.fields(),
        forward=forward_elimination(left, right),
        # section 4.2's last trajectory pose (module docstring), not eq (15): that is singular
        home=model.home_at(euler_zyx_rotation(alpha, beta, gamma), sp.Matrix([x, y, z]), PAPER_BRANCH, parameters),
        parameter_info={
            L1: ParameterInfo(
                "m", "S-joint (actuator) centres at y = -L1 (left), +L1 (right) in {B}, eq (3)", "positive"
            ),
            L4: ParameterInfo(
                "m", "U-joint centres at y = -L4 (left), +L4 (right) on the platform's Y_P axis, eq (3)", "positive"
            ),
        },
        examples=examples(),
    )


__all__ = ["build", "POSE_POSITION"]
