"""SAM, the Spherically-Actuated platform Manipulator (2-SPU, 6 dof): R. L. Williams II and
D. B. Poling, "Spherically-Actuated Platform Manipulator", Journal of Robotic Systems, 2000
(``shared/papers/000_0fd26f24943f9b56.txt``).

Conventions, as in the paper (metres, radians; derivation: ``docs/derivations/sam.md``):
* Frames: fixed base {B}; platform {P}; each leg is a modified-DH chain (Craig), Table I, from
  its actuator frame {0} (^B_0 T: {0} at y = -L1 in {B}) to the U-joint frame {6}, and
  ^6_P T places {P} with its origin at x6 = -L4 (eq 3). Both U joints lie on the Y_P axis.
* Left leg: active S joint (theta1 roll, theta2 yaw, theta3 pitch), passive prismatic L2 and
  U joint (phi2, phi3). Right leg: the same table with theta4..6, L3, phi5, phi6 and the signs of
  L1 and L4 reversed.
* Pose: ^B_P T, or {x, y, z, alpha, beta, gamma} with Z-Y-X Euler angles (eq 2). Leg Jacobians
  (eq 9): columns (theta, theta, theta, L, phi, phi); rows (v, w) of {P} in {B}.
* Inverse branches per leg, signs (epsilon, delta): epsilon = sign of sin(phi2) (eq 5), delta =
  sign of cos(theta2) (eq 8); branch 0 of a leg is (+, +), Table II's first row; SAM branch
  k = 4 * left branch + right branch.
* Forward pose: closed form (accelerator ``_sam_forward.py``), 2 x 2 modes.
* Home: section 4.2's last trajectory pose {0.05 0.05 0.714 0 0 5 deg} on the paper's branch 2
  (``SECTION42_HOME``, ``PAPER_BRANCH``), regular; eq (15)'s nominal pose is a type II
  singularity (a self-motion), the named example ``eq15_nominal``.
"""

from __future__ import annotations

import math

import sympy as sp
from parakin.generator import chains
from parakin.generator.frames import ModifiedDHLink, euler_zyx_rotation, homogeneous, translation
from parakin.generator.model import Citation, Example, Mechanism, ParameterInfo, SerialChain
from parakin.mechanisms._sam_forward import forward_elimination

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
        forward=forward_elimination(left, right, L4),
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
        examples=EXAMPLES,
    )


# Examples
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


EXAMPLES = examples()
