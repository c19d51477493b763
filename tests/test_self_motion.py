"""Generic solution sets: the self-motion traced by continuation where an elimination
degenerates, and the least-squares configuration for incompatible locked inputs."""

import numpy as np
import pytest

import parakin
from parakin.pose import wrap_angle


@pytest.fixture(scope="module")
def sam():
    return parakin.load("sam", backend="compiled")


def test_eq15_nominal_inputs_have_a_self_motion(sam):
    """Williams & Poling claim no type II singularity for SPU legs; at eq (15) the platform moves
    with the actuators locked. forward_pose_all raises SelfMotionError carrying the curve: every
    point closes the loop and inverse_pose maps it back to the locked inputs."""
    nominal = sam.inverse_pose(parakin.pose_from_xyz_euler([0, 0, 0.664, 0, 0, 0])).branch(2)
    with pytest.raises(parakin.SelfMotionError) as error:
        sam.forward_pose_all(nominal.actuated)
    motion = error.value.solution_set
    assert motion.count >= 200
    assert motion.residual.max() < 1e-9
    back = sam.inverse_pose(motion.poses, strict=False)
    mismatch = np.where(back.valid[..., None], np.abs(wrap_angle(back.actuated - nominal.actuated)), np.inf)
    assert mismatch.max(-1).min(-1).max() < 1e-8
    gamma = parakin.xyz_euler_from_pose(motion.poses)[:, 5]
    assert np.ptp(np.unwrap(gamma)) > 1.0  # a finite motion: the platform pitches about X
    assert np.abs(motion.poses - nominal.pose).max(axis=(-2, -1)).min() < 0.05


def test_least_squares_is_exact_for_compatible_inputs_and_measures_incompatibility(sam):
    pose = parakin.pose_from_xyz_euler([0.02, 0.03, 0.68, 0.1, 0.05, 0.08])
    config = sam.inverse_pose(pose).branch(2)
    exact = sam.least_squares(config.actuated, config.passive + 0.02)
    assert exact.norm < 1e-12 and np.abs(exact.pose - pose).max() < 1e-9
    # inputs with no real assembly mode: the loop cannot close; the optimum is a true local
    # minimum (zero gradient J^T r, and no nearby point has a smaller residual)
    locked = np.array([0.035, 1.351, -1.068, 1.346, -0.565, -0.23])
    assert sam.forward_pose_all(locked).count == 0
    fit = sam.least_squares(locked, sam.home_passive)
    assert fit.norm > 1e-3
    jacobian = sam.loop_closure(locked, fit.passive)["jacobian"]
    assert np.abs(jacobian.T @ fit.residual).max() < 1e-8 * max(1.0, fit.norm)
    rng = np.random.default_rng(3)
    nearby = fit.passive + rng.normal(0, 1e-4, (200, fit.passive.size))
    residuals = sam.loop_closure(np.broadcast_to(locked, (200, 6)), nearby)["residual"]
    assert (np.linalg.norm(residuals, axis=-1) >= fit.norm - 1e-12).all()
