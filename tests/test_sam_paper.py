"""Claims and printed numbers of Williams & Poling (2000), section by section."""

import numpy as np
import pytest
import reference
from sam_walkthrough import (
    NOMINAL_ACTUATED_DEG,
    NOMINAL_PASSIVE,
    NOMINAL_POSE,
    PAPER_BRANCH,
    RATE_TWIST,
    nearest_branch,
    trajectory_poses,
)

import parakin
from parakin.pose import pose_from_xyz_euler


def test_eq15_nominal_inverse_pose_matches_printed_values(sam):
    """eq (15): printed to 3 digits; z = 0.664 is itself rounded (theta2 = -15 exactly gives
    z = 0.6636), so the tolerance is the printing precision."""
    config = sam.inverse_pose(pose_from_xyz_euler(NOMINAL_POSE)).branch(PAPER_BRANCH)
    assert np.rad2deg(config.actuated) == pytest.approx(NOMINAL_ACTUATED_DEG, abs=0.01)
    passive = config.passive.copy()
    passive[[1, 2, 4, 5]] = np.rad2deg(passive[[1, 2, 4, 5]])
    assert passive == pytest.approx(NOMINAL_PASSIVE, abs=0.01)


def test_eq15_printed_joints_reach_printed_pose_in_independent_model():
    actuated = np.deg2rad(NOMINAL_ACTUATED_DEG)
    passive = np.array(NOMINAL_PASSIVE, dtype=float)
    passive[[1, 2, 4, 5]] = np.deg2rad(passive[[1, 2, 4, 5]])
    left, right = reference.sam_poses(actuated, passive)
    target = pose_from_xyz_euler(NOMINAL_POSE)
    assert np.abs(left - target).max() < 5e-4  # printed to 3 decimals
    assert np.abs(right - target).max() < 5e-4


def test_table2_every_printed_row_reproduces_the_pose():
    """Table II's rows 2-4, written as functions of row 1 exactly as printed, reach the same
    pose in the independent model (the table has no typo)."""
    rng = np.random.default_rng(2)
    for _ in range(20):
        t1, t2, t3, length, p2, p3 = rng.uniform(-1.2, 1.2, 6)
        length = abs(length) + 0.3
        pi = np.pi
        rows = [
            [t1, t2, t3, length, p2, p3],
            [t1 + pi, pi - t2, t3 + pi, length, p2, p3],
            [t1 + pi, -t2, -t3, length, -p2, p3 + pi],
            [t1, pi + t2, pi - t3, length, -p2, p3 + pi],
        ]
        target = reference.leg_pose(rows[0])
        for row in rows[1:]:
            assert np.abs(reference.leg_pose(row) - target).max() < 1e-12


def test_table2_sixteen_branches_reproduce_the_pose(sam):
    from conftest import random_reachable_poses

    poses = random_reachable_poses(np.random.default_rng(3), 50)
    result = sam.inverse_pose(poses)
    assert result.actuated.shape == (50, 16, 6)
    assert result.valid.all()
    for k in range(16):
        left, right = zip(
            *(reference.sam_poses(result.actuated[i, k], result.passive[i, k]) for i in range(50)), strict=True
        )
        assert np.abs(np.array(left) - poses).max() < 1e-12
        assert np.abs(np.array(right) - poses).max() < 1e-12
    # the four left branches are distinct joint solutions, as Table II lists them
    left_sets = {tuple(np.round(result.actuated[0, k, :3], 9)) for k in range(16)}
    assert len(left_sets) == 4


def test_section42_trajectory_inverse_then_forward(sam):
    """Ten steps of {5 mm, 5 mm, 5 mm, 0, 0, 0.5 deg}: inverse pose, then Newton forward pose
    tracked from the previous step recovers the commanded pose. Step 0 is the nominal pose,
    which is a type II singularity (see test_nominal_pose_is_type2_singular)."""
    poses = trajectory_poses()
    previous = sam.inverse_pose(poses[0]).branch(PAPER_BRANCH)
    for pose in poses[1:]:
        branch = nearest_branch(sam.inverse_pose(pose), previous.actuated)
        forward = sam.forward_pose(branch.actuated, guess=previous)
        assert forward.converged and forward.residual < 1e-12
        assert np.abs(forward.pose - pose).max() < 1e-10
        assert np.abs(forward.passive - branch.passive).max() < 1e-10
        previous = forward


def test_section42_trajectory_rotation_is_about_x_not_z(sam_numpy):
    """The text says both 'gamma = 0.5 deg about the X axis' and 'twisting 0.5 deg about the Z
    axis'. Only the X reading (gamma, eq 2) gives Fig. 5's description: joints 1 and 4 change
    most, in opposite directions; joints 3 and 6 least, in opposite directions; 2 and 5 move
    the same way. About Z, joints 3 and 6 would not move at all."""

    def changes(angle_index):
        start = sam_numpy.inverse_pose(pose_from_xyz_euler(NOMINAL_POSE)).branch(PAPER_BRANCH).actuated
        end = np.array(NOMINAL_POSE) + 10 * np.array([0.005, 0.005, 0.005, 0, 0, 0])
        end[angle_index] += np.deg2rad(5.0)
        return nearest_branch(sam_numpy.inverse_pose(pose_from_xyz_euler(end)), start).actuated - start

    d = changes(5)
    assert np.sign(d[0]) == -np.sign(d[3])
    assert set(np.argsort(np.abs(d))[-2:]) == {0, 3}
    assert np.sign(d[2]) == -np.sign(d[5])
    assert np.sign(d[1]) == np.sign(d[4])
    assert min(abs(d[2]), abs(d[5])) == np.abs(d).min()
    about_z = changes(3)
    assert abs(about_z[2]) < 1e-9 and abs(about_z[5]) < 1e-9


def test_section42_inverse_rate_claims(sam_numpy):
    """Fig. 6 description, for the constant twist {-0.1, -0.1, 0.1, 0.1, 0.1, 0.1}: all initial
    rates non-zero; joints 1 and 4 largest, opposite directions; over the motion joints 2 and
    3 switch direction while 5 and 6 stay positive. The paper prints no duration; this holds
    for 2 s of resolved-rate motion (200 steps of 10 ms)."""
    twist = np.array(RATE_TWIST)
    config = sam_numpy.inverse_pose(pose_from_xyz_euler(NOMINAL_POSE)).branch(PAPER_BRANCH)
    pose, history = config.pose.copy(), []
    for _ in range(201):
        config = nearest_branch(sam_numpy.inverse_pose(pose), config.actuated)
        rates = sam_numpy.inverse_rate(config, twist).actuated
        history.append(rates)
        pose = pose.copy()
        pose[:3, 3] += twist[:3] * 0.01
        angle = np.linalg.norm(twist[3:]) * 0.01
        axis = twist[3:] / np.linalg.norm(twist[3:])
        k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        pose[:3, :3] = (np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k) @ pose[:3, :3]
    history = np.array(history)
    first = history[0]
    assert (np.abs(first) > 1e-3).all()
    assert set(np.argsort(np.abs(first))[-2:]) == {0, 3} and np.sign(first[0]) == -np.sign(first[3])
    switched = [(np.sign(history[:, j]) != np.sign(first[j])).any() for j in range(6)]
    assert switched[1] and switched[2]
    assert (history[:, 4] > 0).all() and (history[:, 5] > 0).all()


def test_eq13_leg_determinants(sam_numpy):
    """eq (13): |J_L| = L2^2 c2 s(phi2), |J_R| = L3^2 c5 s(phi5). Checked on finite-difference
    Jacobians of the independent model at random joints: the paper's expression holds exactly
    (sign included) for Jacobians of (v of {P}'s origin, w) in {B}."""
    rng = np.random.default_rng(4)
    for _ in range(20):
        joints = rng.uniform(-1.2, 1.2, 6)
        joints[3] = rng.uniform(0.3, 1.0)
        for offsets in [(reference.L1, reference.L4), (-reference.L1, -reference.L4)]:
            numeric = np.linalg.det(reference.twist_jacobian(joints, *offsets))
            paper = joints[3] ** 2 * np.cos(joints[1]) * np.sin(joints[4])
            assert numeric == pytest.approx(paper, rel=1e-6, abs=1e-9)


def test_eq13_generated_factors_are_the_papers(sam_numpy):
    names = sam_numpy.manifest.singularity_factors
    assert {"left_leg_length", "left_s_joint_gimbal_lock", "left_u_joint_aligned"} <= set(names)
    symbolic = parakin.symbolic("sam")
    import sympy as sp

    L2, theta2, phi2 = sp.symbols("L2 theta2 phi2", real=True)
    assert sp.simplify(symbolic["left_leg_determinant"] - L2**2 * sp.cos(theta2) * sp.sin(phi2)) == 0


def test_nominal_pose_is_type2_singular_with_a_self_motion(sam_numpy):
    """The paper (section 5) says the SPU design has no singularity like the SRU four-bar one at
    level poses. It does: at eq (15) both U-joint axes z4 are parallel to X_B, so the closed-loop
    determinant vanishes, and with the actuators locked the platform keeps moving: pitching it
    about X by psi while the passive legs slide reaches poses whose inverse pose returns the
    very same actuator angles."""
    nominal = sam_numpy.inverse_pose(pose_from_xyz_euler(NOMINAL_POSE)).branch(PAPER_BRANCH)
    factors = sam_numpy.singularities(nominal)
    assert abs(factors["u_joint_axes_parallel"]) < 1e-12
    assert abs(factors["closed_loop_determinant"]) < 1e-12
    with pytest.raises(parakin.SingularConfigurationError):
        sam_numpy.forward_pose(nominal.actuated, guess=nominal)
    # the self-motion, constructed independently: legs fixed in direction, platform pitched
    left, right = reference.sam_poses(nominal.actuated, nominal.passive)
    s_left, s_right = np.array([0, -reference.L1, 0]), np.array([0, reference.L1, 0])
    d_left = (left[:3, 3] + [0, -reference.L4, 0] - s_left) / nominal.passive[0]
    d_right = (right[:3, 3] + [0, reference.L4, 0] - s_right) / nominal.passive[3]
    for psi in np.deg2rad([2.0, 5.0, 10.0]):
        y_axis = np.array([0, np.cos(psi), np.sin(psi)])
        # s_left + L2 d_left + 2 L4 y = s_right + L3 d_right: two equations in the YZ plane
        lengths = np.linalg.solve(
            np.column_stack([d_left, -d_right])[1:], (s_right - s_left - 2 * reference.L4 * y_axis)[1:]
        )
        origin = s_left + lengths[0] * d_left + reference.L4 * y_axis
        pose = np.eye(4)
        pose[:3, :3] = np.column_stack([[1, 0, 0], y_axis, np.cross([1, 0, 0], y_axis)])
        pose[:3, 3] = origin
        branches = sam_numpy.inverse_pose(pose)
        assert np.abs(branches.actuated - nominal.actuated).max(-1).min() < 1e-12


def test_home_is_the_last_section42_trajectory_pose_and_regular(sam):
    """The home (default Newton guess, plot, C example) is the last pose of section 4.2's
    trajectory on the paper's branch, not eq (15): there the closed-loop determinant is 0 (a type
    II singularity) and forward_pose fails; at the home it is -0.250, forward_pose_all finds four
    modes with the home among them, and forward_pose without a guess lands on the home."""
    last = sam.inverse_pose(trajectory_poses(10)[-1]).branch(PAPER_BRANCH)
    np.testing.assert_allclose(sam.home_actuated, last.actuated, atol=1e-14)
    np.testing.assert_allclose(sam.home_passive, last.passive, atol=1e-14)
    home = parakin.Configuration(sam.home_actuated, sam.home_passive, last.pose)
    assert float(sam.singularities(home)["closed_loop_determinant"]) == pytest.approx(-0.250, abs=5e-4)
    nominal = sam.inverse_pose(pose_from_xyz_euler(NOMINAL_POSE)).branch(PAPER_BRANCH)
    assert abs(float(sam.singularities(nominal)["closed_loop_determinant"])) < 1e-12
    modes = sam.forward_pose_all(sam.home_actuated)
    assert modes.count == 4
    assert np.abs(modes.poses[modes.valid] - last.pose).max(axis=(-2, -1)).min() < 1e-12
    forward = sam.forward_pose(sam.home_actuated)
    assert forward.converged and np.abs(forward.pose - last.pose).max() < 1e-12
