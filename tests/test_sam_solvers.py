"""Solvers checked by residuals: round trips, finite differences, independent models."""

import numpy as np
import pytest
import reference
from conftest import random_reachable_poses
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import parakin
from parakin.pose import wrap_angle

pose_values = st.tuples(
    st.floats(-0.15, 0.15), st.floats(-0.15, 0.15), st.floats(0.5, 0.9),
    st.floats(-0.45, 0.45), st.floats(-0.45, 0.45), st.floats(-0.45, 0.45),
)  # fmt: skip


@settings(max_examples=60, deadline=None)
@given(pose_values, st.integers(0, 15))
def test_round_trip_inverse_then_newton_forward(values, branch):
    m = parakin.load("sam", backend="numpy")
    pose = parakin.pose_from_xyz_euler(values)
    config = m.inverse_pose(pose).branch(branch)
    factors = m.singularities(config)
    # near type II (level poses, see test_sam_paper) Newton is ill-conditioned and rightly refused
    assume(abs(factors["closed_loop_determinant"]) > 1e-2)
    rng = np.random.default_rng(branch)
    guess = config.passive + rng.normal(0, 0.01, 6)
    forward = m.forward_pose(config.actuated, guess=guess)
    assert np.abs(forward.pose - pose).max() < 1e-10


@settings(max_examples=60, deadline=None)
@given(pose_values, st.integers(0, 15))
def test_round_trip_inverse_then_all_modes_contains_the_pose(values, branch):
    m = parakin.load("sam", backend="numpy")
    pose = parakin.pose_from_xyz_euler(values)
    config = m.inverse_pose(pose).branch(branch)
    # parallel U-joint axes (level poses among them) are the self-motion case: no finite set
    assume(abs(m.singularities(config)["u_joint_axes_parallel"]) > 1e-3)
    modes = m.forward_pose_all(config.actuated)
    if not modes.real.any():
        pytest.fail("no real mode for a pose built by inverse pose")
    errors = np.abs(modes.poses - pose).max(axis=(-2, -1))
    assert errors[modes.valid].min() < 1e-10
    assert (modes.residual[modes.valid] < 1e-9).all()
    # every valid mode reproduces the actuated input through inverse pose
    for k in np.nonzero(modes.valid)[0]:
        back = m.inverse_pose(modes.poses[k], strict=False)
        assert np.abs(wrap_angle(back.actuated - config.actuated)).max(-1).min() < 1e-9


def test_all_modes_count_and_reflection_structure(sam):
    """Closed form: up to 2 roots x 2 signs of Z_P; the two signs give the same origin with the
    platform turned by pi about its Y axis."""
    rng = np.random.default_rng(5)
    poses = random_reachable_poses(rng, 200)
    config = sam.inverse_pose(poses).branch(2)
    modes = sam.forward_pose_all(config.actuated)
    assert modes.poses.shape == (200, 4, 4, 4)
    assert ((modes.count >= 1) & (modes.count <= 4)).all()
    pairs = modes.real[:, 0::2] & modes.real[:, 1::2]
    same_origin = np.abs(modes.poses[:, 0::2, :3, 3] - modes.poses[:, 1::2, :3, 3]).max(-1)
    assert (same_origin[pairs] < 1e-9).all()
    flipped_y = np.abs(modes.poses[:, 0::2, :3, 1] - modes.poses[:, 1::2, :3, 1]).max(-1)
    assert (flipped_y[pairs] < 1e-9).all()


def test_forward_modes_agree_with_an_independent_solver():
    """scipy.optimize.root on the independent model's 12 equations, from many starts, finds no
    real mode that the closed form misses."""
    from scipy.optimize import root

    m = parakin.load("sam", backend="numpy")
    rng = np.random.default_rng(6)
    for pose in random_reachable_poses(rng, 5):
        actuated = m.inverse_pose(pose).branch(2).actuated
        modes = m.forward_pose_all(actuated)

        def equations(q, actuated=actuated):
            left, right = reference.sam_poses(actuated, q)
            return np.concatenate(
                [(left - right)[:3, 3], (left[:3, :3].T @ right[:3, :3] - np.eye(3))[[2, 0, 1], [1, 2, 0]]]
            )

        for _ in range(40):
            start = np.array(
                [
                    rng.uniform(0.2, 3.5),
                    *rng.uniform(-np.pi, np.pi, 2),
                    rng.uniform(0.2, 3.5),
                    *rng.uniform(-np.pi, np.pi, 2),
                ]
            )
            solution = root(equations, start, tol=1e-13)
            if not solution.success or np.abs(equations(solution.x)).max() > 1e-9:
                continue
            found, other = reference.sam_poses(actuated, solution.x)
            if solution.x[0] <= 0 or solution.x[3] <= 0 or np.abs(found - other).max() > 1e-9:
                continue  # outside the limits, or a half-turn between the legs (not a closure)
            assert np.abs(modes.poses[modes.valid] - found).max(axis=(-2, -1)).min() < 1e-7


def test_leg_jacobians_match_finite_differences(sam):
    rng = np.random.default_rng(7)
    config = sam.inverse_pose(random_reachable_poses(rng, 8)).branch(2)
    jacobians = sam.leg_jacobians(config)
    for i in range(8):
        left = reference.twist_jacobian([*config.actuated[i, :3], *config.passive[i, :3]])
        right = reference.twist_jacobian(
            [*config.actuated[i, 3:], *config.passive[i, 3:]], -reference.L1, -reference.L4
        )
        assert np.abs(jacobians["left"][i] - left).max() < 1e-7
        assert np.abs(jacobians["right"][i] - right).max() < 1e-7


def test_loop_closure_jacobian_matches_finite_differences(sam):
    rng = np.random.default_rng(8)
    actuated, passive = rng.uniform(-1, 1, 6), rng.uniform(0.3, 1.0, 6)
    analytic = sam.loop_closure(actuated, passive)["jacobian"]
    h = 1e-6
    numeric = np.column_stack(
        [
            (
                sam.loop_closure(actuated, passive + h * e)["residual"]
                - sam.loop_closure(actuated, passive - h * e)["residual"]
            )
            / (2 * h)
            for e in np.eye(6)
        ]
    )
    assert np.abs(analytic - numeric).max() < 1e-8


def test_inverse_and_forward_rate_against_finite_differences(sam_numpy):
    """forward_rate (eq 12) against differences of forward poses; inverse_rate (eq 10) inverts it."""
    rng = np.random.default_rng(9)
    pose = random_reachable_poses(rng, 1)[0]
    config = sam_numpy.inverse_pose(pose).branch(2)
    rates = rng.normal(0, 0.3, 6)
    twist = sam_numpy.forward_rate(config, rates)
    h = 1e-6
    plus = sam_numpy.forward_pose(config.actuated + h * rates, guess=config).pose
    minus = sam_numpy.forward_pose(config.actuated - h * rates, guess=config).pose
    v = (plus[:3, 3] - minus[:3, 3]) / (2 * h)
    dr = (plus[:3, :3] - minus[:3, :3]) / (2 * h) @ pose[:3, :3].T
    w = np.array([dr[2, 1], dr[0, 2], dr[1, 0]])
    assert np.abs(twist - np.concatenate([v, w])).max() < 1e-6
    back = sam_numpy.inverse_rate(config, twist)
    assert np.abs(back.actuated - rates).max() < 1e-9


def test_damped_inverse_rate_near_a_singular_leg(sam_numpy):
    """At phi2 = 0 (eq 14) the left leg Jacobian is singular: the exact solve refuses, the damped
    pseudo-inverse returns bounded rates whose twist error is small except about Y_P."""
    actuated = np.zeros(6)
    passive = np.array([0.7, 0.0, 0.0, 0.7, 0.3, 0.0])
    config = parakin.Configuration(actuated, passive, sam_numpy.platform_pose(actuated, passive))
    twist = np.array([0.01, 0.0, 0.0, 0.0, 0.0, 0.05])
    with pytest.raises(parakin.SingularConfigurationError, match="left leg"):
        sam_numpy.inverse_rate(config, twist)
    damped = sam_numpy.inverse_rate(config, twist, damping=1e-3)
    assert np.isfinite(damped.actuated).all() and np.abs(damped.actuated).max() < 10


def test_batch_shapes(sam):
    rng = np.random.default_rng(10)
    poses = random_reachable_poses(rng, 6).reshape(2, 3, 4, 4)
    result = sam.inverse_pose(poses)
    assert result.actuated.shape == (2, 3, 16, 6) and result.valid.shape == (2, 3, 16)
    config = result.branch(2)
    forward = sam.forward_pose(config.actuated, guess=config)
    assert forward.pose.shape == (2, 3, 4, 4) and forward.iterations.shape == (2, 3)
    assert np.abs(forward.pose - poses).max() < 1e-10
    modes = sam.forward_pose_all(config.actuated)
    assert modes.poses.shape == (2, 3, 4, 4, 4)
    factors = sam.singularities(config)
    assert factors["closed_loop_determinant"].shape == (2, 3)


def test_tracker_follows_the_trajectory(sam):
    from sam_walkthrough import nearest_branch, trajectory_poses

    poses = trajectory_poses()
    start = sam.inverse_pose(poses[1]).branch(2)
    tracker = sam.tracker(sam.forward_pose(start.actuated, guess=start))
    previous = start
    for pose in poses[2:]:
        branch = nearest_branch(sam.inverse_pose(pose), previous.actuated)
        _, reached = tracker.solve(branch.actuated)
        assert reached.shape == (4, 4) and np.abs(reached - pose).max() < 1e-10
        previous = branch


def test_xyz_euler_round_trip():
    rng = np.random.default_rng(11)
    values = np.column_stack(
        [rng.normal(size=(100, 3)), rng.uniform(-3, 3, 100), rng.uniform(-1.5, 1.5, 100), rng.uniform(-3, 3, 100)]
    )
    back = parakin.xyz_euler_from_pose(parakin.pose_from_xyz_euler(values))
    assert np.abs(back - values).max() < 1e-9
    assert (
        np.abs(parakin.pose_from_xyz_euler_deg([0, 0, 0, 90, 0, 0])[:3, :3] - [[0, -1, 0], [1, 0, 0], [0, 0, 1]]).max()
        < 1e-15
    )


def test_one_actuated_set_with_a_batch_of_guesses(sam):
    """Broadcasting between actuated values and guesses: one input, several starts."""
    config = sam.inverse_pose(parakin.pose_from_xyz_euler([0.02, 0.03, 0.68, 0.1, 0.05, 0.08])).branch(2)
    guesses = config.passive + np.random.default_rng(13).normal(0, 0.01, (4, 6))
    result = sam.forward_pose(config.actuated, guess=guesses)
    assert result.pose.shape == (4, 4, 4)
    assert np.abs(result.pose - config.pose).max() < 1e-10


@pytest.mark.parametrize("backend", ["numpy", "compiled"])
def test_tracker_keeps_its_last_good_solution_after_a_failure(backend):
    """A failed solve must not leave a diverged iterate as the next start (review finding)."""
    m = parakin.load("sam", backend=backend)
    config = m.inverse_pose(parakin.pose_from_xyz_euler([0.02, 0.03, 0.68, 0.1, 0.05, 0.08])).branch(2)
    tracker = m.tracker(config, max_iterations=3)
    good = tracker.passive.copy()
    with pytest.raises((parakin.ConvergenceError, parakin.SingularConfigurationError)):
        tracker.solve(config.actuated + 1.5)  # a jump far beyond a tracking step
    assert np.array_equal(tracker.passive, good)
    passive, pose = tracker.solve(config.actuated)
    assert pose.shape == (4, 4) and np.abs(pose - config.pose).max() < 1e-10


def test_failed_forward_pose_entries_keep_the_guess(sam_numpy):
    config = sam_numpy.inverse_pose(parakin.pose_from_xyz_euler([0.02, 0.03, 0.68, 0.1, 0.05, 0.08])).branch(2)
    guess = config.passive + 0.7
    result = sam_numpy.forward_pose(config.actuated, guess=guess, max_iterations=1, strict=False)
    assert not result.converged
    assert np.abs(parakin.pose.wrap_angle(result.passive - guess)).max() < 1e-12
