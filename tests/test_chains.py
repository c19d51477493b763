"""Serial-chain legs (``parakin.generator.chains``): the inverse derived by decomposition, checked
against independent sources: the chain's own forward kinematics (every valid branch reproduces the
pose, one branch the sampled joints), Williams & Poling's eqs (3)-(8) and Table II written here in
NumPy (SAM's generated inverse), the determinant of the closed-loop matrix computed from the
generated leg Jacobians (the derived type II factors), and the structures it refuses.

SAM re-expressed with these legs was compared with its hand-derived package when it was (1000
poses, 16000 branch values within 9e-16 rad or m, the same validity, forward_rate and leg
Jacobians identical, every singularity factor in ratio +-1, the same assembly modes within 2e-14);
the tests below and the paper tests keep it so."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from parakin.generator import chains
from parakin.generator.errors import GenerationError
from parakin.generator.frames import ModifiedDHLink, homogeneous, rot_x, rot_z, translation
from parakin.generator.model import POSE_POSITION, POSE_ROTATION, SerialChain

import parakin

SAMPLES = 1000
HALF_PI = sp.pi / 2


def _value(expression: sp.Expr, values: dict) -> np.ndarray:
    symbols = sorted(expression.free_symbols, key=str)
    function = sp.lambdify(symbols, expression, "numpy")
    return np.broadcast_to(function(*(values[s] for s in symbols)), next(iter(values.values())).shape)


def _evaluate(steps, values: dict) -> dict:
    """Every step of an inverse on arrays (NumPy), branch symbols set in ``values``."""
    values = dict(values)
    for target, expression in steps:
        values[target] = _value(expression, values)
    return values


def _forward(chain: SerialChain, joints: dict) -> np.ndarray:
    """^B_P T of the chain at joint arrays (N,) -> (N, 4, 4), in NumPy from Craig's row
    transform Rot_x(alpha) Trans_x(a) Rot_z(theta) Trans_z(d)."""
    count = len(next(iter(joints.values())))
    result = np.broadcast_to(np.array(chain.base, float), (count, 4, 4))
    for link in chain.links:
        alpha, a, theta, d = (
            _value(sp.sympify(v), joints) if v.free_symbols else np.full(count, float(v))
            for v in (link.alpha, link.a, link.theta, link.d)
        )
        ca, sa, ct, st = np.cos(alpha), np.sin(alpha), np.cos(theta), np.sin(theta)
        zero, one = np.zeros(count), np.ones(count)
        rows = [
            [ct, -st, zero, a],
            [ca * st, ca * ct, -sa, -sa * d],
            [sa * st, sa * ct, ca, ca * d],
            [zero, zero, zero, one],
        ]
        result = result @ np.moveaxis(np.array(rows), (0, 1), (1, 2))
    return result @ np.array(chain.tool, float)


def _round_trip(chain: SerialChain, actuated, seed: int) -> tuple[int, int]:
    """Random joints -> pose (forward) -> every inverse branch: each valid branch gives joints
    whose forward pose is the pose (1e-9), and one of them is the sampled joints, except where
    that branch is within 1e-6 of a validity condition's zero (asserted: at most 1 % of the
    poses). Returns the checked (pose, branch) pairs and the poses whose sampled joints were
    found."""
    leg = chains.chain_leg(chain, actuated)
    model = chains.ChainMechanism([leg])
    inverse = model.inverse()
    rng = np.random.default_rng(seed)
    joints = {j: rng.uniform(-math.pi, math.pi, SAMPLES) for j in chain.joints}
    joints[leg.length] = rng.uniform(0.2, 1.0, SAMPLES)
    poses = _forward(chain, joints)
    base = {POSE_ROTATION[i, j]: poses[:, i, j] for i in range(3) for j in range(3)}
    base |= {POSE_POSITION[i]: poses[:, i, 3] for i in range(3)}
    checked, found, near = 0, np.zeros(SAMPLES, bool), np.zeros(SAMPLES, bool)
    for signs in [(1, 1), (1, -1), (-1, 1), (-1, -1)]:
        with np.errstate(all="ignore"):
            values = _evaluate(inverse.steps, base | dict(zip(inverse.branches, signs, strict=True)))
            valid = np.logical_and.reduce([_value(v, values) > 1e-6 for v in inverse.validity.values()])
        solved = {j: values[j] for j in chain.joints}
        again = _forward(chain, {j: np.where(valid, solved[j], 0.5) for j in chain.joints})
        assert np.abs(again - poses)[valid].max() < 1e-9
        wrapped = [np.abs(np.angle(np.exp(1j * (solved[j] - joints[j])))) for j in chain.joints if j != leg.length]
        same = np.logical_and.reduce([w < 1e-7 for w in wrapped]) & (
            np.abs(solved[leg.length] - joints[leg.length]) < 1e-9
        )
        found |= valid & same
        near |= ~valid & same
        checked += int(valid.sum())
    assert (found | near).all() and near.sum() <= SAMPLES // 100, (int(found.sum()), int(near.sum()))
    return checked, int(found.sum())


def test_an_s_p_u_leg_with_oblique_axes_and_offsets_inverts_its_own_forward_kinematics():
    """A spherical group with axes at 60 and 110 degrees, offsets on every revolute, a fixed row
    before the prismatic joint and a prismatic offset; a universal group at 75 degrees, whose
    pointing is not always possible (the reachable condition)."""
    q = sp.symbols("q1:7", real=True)
    links = [
        ModifiedDHLink(0.3, 0.1, 0.05, q[0] + 0.4, q[0]),
        ModifiedDHLink(sp.pi / 3, 0, 0, q[1] - 0.2, q[1]),
        ModifiedDHLink(sp.Rational(11, 18) * sp.pi, 0, 0, q[2] + 1.1, q[2]),
        ModifiedDHLink(-HALF_PI, 0, 0, 0.3),  # fixed: turns the prismatic's frame
        ModifiedDHLink(0, q[3] + 0.15, 0, 0, q[3]),
        ModifiedDHLink(0.2, 0, 0, q[4] - 0.7, q[4]),
        ModifiedDHLink(sp.Rational(5, 12) * sp.pi, 0, 0, q[5] + 0.25, q[5]),
    ]
    tool = homogeneous(rot_z(0.3) * rot_x(-0.4), [0.2, -0.1, 0.05])
    chain = SerialChain("oblique", translation(0.1, -0.3, 0.2), links, tool, list(q))
    checked, found = _round_trip(chain, q[:3], seed=1)
    assert checked >= 2 * SAMPLES and found >= 0.99 * SAMPLES, (checked, found)


def test_a_u_p_s_leg_inverts_its_own_forward_kinematics():
    """The universal group at the base (it points the leg line from the base), the spherical
    group at the platform (Euler), offsets and a tool."""
    q = sp.symbols("p1:7", real=True)
    links = [
        ModifiedDHLink(0, 0, 0.1, q[0], q[0]),
        ModifiedDHLink(HALF_PI, 0, 0, q[1] + HALF_PI, q[1]),
        ModifiedDHLink(HALF_PI, 0, q[2], 0, q[2]),  # the prismatic along z
        ModifiedDHLink(0, 0, 0, q[3], q[3]),
        ModifiedDHLink(-HALF_PI, 0, 0, q[4] - HALF_PI, q[4]),
        ModifiedDHLink(HALF_PI, 0, 0, q[5], q[5]),
    ]
    tool = homogeneous(rot_x(0.5), [0.05, 0.1, 0])
    chain = SerialChain("ups", translation(0, 0.4, 0), links, tool, list(q))
    checked, found = _round_trip(chain, q[:2], seed=2)
    assert checked >= 0.99 * 4 * SAMPLES and found >= 0.99 * SAMPLES, (checked, found)


def test_structures_outside_the_supported_ones_are_refused_with_what_was_found():
    q = sp.symbols("q1:7", real=True)

    def chain(links: list[ModifiedDHLink]) -> SerialChain:
        return SerialChain("leg", sp.eye(4), links, sp.eye(4), [link.joint for link in links if link.joint is not None])

    six_revolute = [ModifiedDHLink(HALF_PI, 0, 0, q[k], q[k]) for k in range(6)]
    with pytest.raises(GenerationError, match="joints RRRRRR; supported: a spherical group of 3"):
        chains.chain_leg(chain(six_revolute), q[:3])
    apart = [
        ModifiedDHLink(0, 0, 0, q[0], q[0]),
        ModifiedDHLink(HALF_PI, 0.1, 0, q[1], q[1]),  # a = 0.1: the axes do not meet
        ModifiedDHLink(HALF_PI, 0, 0, q[2], q[2]),
        ModifiedDHLink(-HALF_PI, q[3], 0, 0, q[3]),
        ModifiedDHLink(0, 0, 0, q[4], q[4]),
        ModifiedDHLink(HALF_PI, 0, 0, q[5], q[5]),
    ]
    with pytest.raises(GenerationError, match=r"axes of rows 1 and 2 do not meet .* a = 0\.1"):
        chains.chain_leg(chain(apart), q[:3])
    sideways = [*apart[:1], ModifiedDHLink(HALF_PI, 0, 0, q[1], q[1]), apart[2]]
    sideways += [ModifiedDHLink(-HALF_PI, q[3], 0.2, 0, q[3]), *apart[4:]]  # d = 0.2: off the line
    with pytest.raises(GenerationError, match="not along a line through the base-side centre"):
        chains.chain_leg(chain(sideways), q[:3])


def _paper_leg(pose: np.ndarray, side: int, epsilon: int, delta: int) -> np.ndarray:
    """Williams & Poling section 3.1 for one leg (side +1 left, -1 right: the signs of L1 and L4
    reversed), eqs (3)-(8), then Table II: epsilon -1 takes rows 3-4 (the other U-joint set),
    delta -1 the row with cos(theta2) < 0. Returns (theta_a, theta_b, theta_c, L, phi_a, phi_b)."""
    l1, l4 = 0.5334 * side, 0.3556 * side
    base = np.eye(4)
    base[1, 3] = -l1
    tool = np.array([[0, -1, 0, -l4], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    t06 = np.linalg.inv(base) @ pose @ np.linalg.inv(tool)  # eq (3)
    x1, y1, z1 = np.linalg.inv(t06)[:3, 3]
    length = math.sqrt(x1**2 + y1**2 + z1**2)  # eq (5)
    p3 = math.atan2(-y1, x1)
    p2 = math.atan2(x1 / math.cos(p3), -z1)
    s2, c2, s3, c3 = math.sin(p2), math.cos(p2), math.sin(p3), math.cos(p3)
    r36 = np.array([[-s2 * c3, s2 * s3, c2], [s3, c3, 0], [-c2 * c3, c2 * s3, -s2]])
    r = t06[:3, :3] @ r36.T  # eq (6)
    t1 = math.atan2(-r[0, 2], r[1, 2])  # eq (8)
    t2 = math.atan2(r[2, 2], r[1, 2] / math.cos(t1))
    t3 = math.atan2(-r[2, 1], r[2, 0])
    pi = math.pi
    rows = {
        (1, 1): [t1, t2, t3, length, p2, p3],
        (1, -1): [t1 + pi, pi - t2, t3 + pi, length, p2, p3],
        (-1, 1): [t1 + pi, -t2, -t3, length, -p2, p3 + pi],
        (-1, -1): [t1, pi + t2, pi - t3, length, -p2, p3 + pi],
    }
    return np.array(rows[epsilon, delta])


def test_sam_inverse_is_williams_and_poling_eqs_3_to_8_and_table_2():
    """Every generated branch k = 4 * left + right (leg branch 2 * (epsilon < 0) + (delta < 0))
    equals section 3.1 computed here, on 1000 poses around the home (16 branches each)."""
    m = parakin.load("sam", backend="numpy")
    rng = np.random.default_rng(20)
    coordinates = np.array([0.05, 0.05, 0.714, 0, 0, math.radians(5)]) + rng.uniform(-1, 1, (SAMPLES, 6)) * [
        0.15, 0.15, 0.15, 0.5, 0.5, 0.5
    ]  # fmt: skip
    poses = parakin.pose_from_xyz_euler(coordinates)
    result = m.inverse_pose(poses)
    signs = [(1, 1), (1, -1), (-1, 1), (-1, -1)]
    angular = np.array([True, True, True, False, True, True])
    checked, worst = 0, 0.0
    for n, pose in enumerate(poses):
        for k in range(16):
            left, right = (_paper_leg(pose, side, *signs[b]) for side, b in ((1, k // 4), (-1, k % 4)))
            paper = np.concatenate([left[:3], right[:3], left[3:], right[3:]])
            ours = np.concatenate([result.actuated[n, k], result.passive[n, k]])
            difference = paper - ours
            difference = np.where(
                np.r_[angular[:3], angular[:3], angular[3:], angular[3:]], np.angle(np.exp(1j * difference)), difference
            )
            assert result.valid[n, k]
            worst = max(worst, float(np.abs(difference).max()))
            checked += 1
    assert checked == 16 * SAMPLES and worst < 1e-9, (checked, worst)


def test_sam_closed_loop_factors_multiply_to_the_determinant_of_the_passive_twists():
    """det [J_left(passive columns), -J_right(passive columns)] from the generated leg Jacobians
    (eq 9) equals the product of the derived type II factors up to one sign, on 1000 poses."""
    m = parakin.load("sam", backend="numpy")
    rng = np.random.default_rng(21)
    coordinates = np.array([0.05, 0.05, 0.714, 0, 0, math.radians(5)]) + rng.uniform(-1, 1, (SAMPLES, 6)) * [
        0.15, 0.15, 0.15, 0.5, 0.5, 0.5
    ]  # fmt: skip
    poses = parakin.pose_from_xyz_euler(coordinates)
    ik = m.inverse_pose(poses)
    state = parakin.Configuration(ik.actuated[:, 2], ik.passive[:, 2], poses)
    jacobians = m.leg_jacobians(state)
    matrix = np.concatenate([jacobians["left"][..., 3:], -jacobians["right"][..., 3:]], axis=-1)
    factors = m.singularities(state)
    product = factors["u_joint_axes_parallel"] * factors["legs_coplanar_with_platform_x"] * factors["platform_span"]
    ratio = np.linalg.det(matrix) / product
    regular = np.abs(product) > 1e-6
    assert regular.sum() >= 0.9 * SAMPLES
    assert np.allclose(np.abs(ratio[regular]), 1, atol=1e-9) and len(set(np.sign(ratio[regular]))) == 1
