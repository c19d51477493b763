"""The 2R spherical serial chain of the ED5314 report, section 2 (eqs 1-13) and its typos."""

import numpy as np
import pytest

import parakin
from parakin.pose import wrap_angle

U, K = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])


def rotate(axis, angle, vector):
    """Rodrigues, written here independently of the generator."""
    return (
        np.cos(angle) * vector + np.sin(angle) * np.cross(axis, vector) + (1 - np.cos(angle)) * axis.dot(vector) * axis
    )


def chain(theta1, theta2, alpha1, alpha2):
    m = rotate(U, theta1, K)
    v = rotate(m, alpha1, U)  # eq 2 as it must read
    n = rotate(v, theta2, m)
    return m, v, n, rotate(n, alpha2, v)


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def arm(request):
    return parakin.load("sphere2r", backend=request.param, alpha1=1.1, alpha2=0.8)


def test_forward_matches_eqs_1_to_4(arm):
    rng = np.random.default_rng(40)
    angles = rng.uniform(-np.pi, np.pi, (50, 2))
    poses = arm.forward_pose(angles).pose
    for (t1, t2), pose in zip(angles, poses, strict=True):
        _, _, n, w = chain(t1, t2, 1.1, 0.8)
        assert np.abs(pose[:3, 2] - w).max() < 1e-14 and np.abs(pose[:3, 0] - n).max() < 1e-14


def test_both_inverse_branches_reach_the_point_and_one_is_the_input(arm):
    rng = np.random.default_rng(41)
    angles = rng.uniform(-np.pi, np.pi, (200, 2))
    poses = arm.forward_pose(angles).pose
    result = arm.inverse_pose(poses[..., :3, :3])
    assert result.valid.all()
    reached = arm.forward_pose(result.actuated).pose[..., :3, 2]
    assert np.abs(reached - poses[:, None, :3, 2]).max() < 1e-12
    assert (np.abs(wrap_angle(result.actuated - angles[:, None])).max(-1).min(-1) < 1e-12).all()


def test_unreachable_point_is_reported():
    arm = parakin.load("sphere2r", backend="numpy", alpha1=0.3, alpha2=0.3)
    sideways = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])  # w at 90 deg from u > alpha1 + alpha2
    result = arm.inverse_pose(sideways, strict=False)
    assert not result.valid.any() and np.isfinite(result.actuated).all()
    assert result.failures["reachable"].all()
    with pytest.raises(parakin.UnreachablePoseError):
        arm.inverse_pose(sideways)
    on_axis = arm.inverse_pose(np.diag([1.0, -1.0, -1.0]), strict=False)  # w = -u: singular
    assert on_axis.failures["w_off_the_base_axis"].all() and np.isfinite(on_axis.actuated).all()


def test_singular_factor_vanishes_when_the_links_are_coplanar(arm):
    stretched = arm.forward_pose([0.4, 0.0])
    bent = arm.forward_pose([0.4, 0.9])
    assert abs(float(arm.singularities(stretched)["links_coplanar"])) < 1e-14
    assert abs(float(arm.singularities(bent)["links_coplanar"])) > 0.1
    assert int(arm.forward_pose_all([0.4, 0.9]).count) == 1


def test_report_typos_in_eqs_2_5_6_8_to_11_and_13():
    rng = np.random.default_rng(42)
    wrong_sign = 0
    trials = 200
    for _ in range(trials):
        alpha1, alpha2 = rng.uniform(1.7, 2.9), rng.uniform(0.2, 2.9)  # alpha1 > 90 deg
        t1, t2 = rng.uniform(-3, 3, 2)
        m, v, n, w = chain(t1, t2, alpha1, alpha2)
        # eq 2 as printed, Rot(u, alpha1) u, is u itself, not v
        assert np.abs(rotate(U, alpha1, U) - U).max() < 1e-15 and np.abs(v - U).max() > 1e-3
        # eqs 5, 6 swap the angles: v.u = cos(alpha1), v.w = cos(alpha2)
        assert v.dot(U) == pytest.approx(np.cos(alpha1)) and v.dot(w) == pytest.approx(np.cos(alpha2))
        # eqs 8-11 lack the normalisation: k.(u x v) = sin(alpha1) cos(theta1)
        assert K.dot(np.cross(U, v)) == pytest.approx(np.sin(alpha1) * np.cos(t1))
        # eq 13 takes the sign about u; the rotation from m to n is about v
        m_hat, n_hat = np.cross(U, v) / np.sin(alpha1), np.cross(v, w) / np.sin(alpha2)
        printed = np.sign(np.cross(m_hat, n_hat).dot(U)) * np.arccos(np.clip(m_hat.dot(n_hat), -1, 1))
        corrected = np.arctan2(np.cross(m_hat, n_hat).dot(v), m_hat.dot(n_hat))
        assert abs(wrap_angle(corrected - t2)) < 1e-9
        wrong_sign += abs(wrap_angle(printed - t2)) > 1e-6
    assert wrong_sign == trials  # for alpha1 > 90 deg the printed sign is wrong every time
