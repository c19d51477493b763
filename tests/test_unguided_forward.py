"""``forward_pose`` without a guess starts from the assembly mode nearest the home by pose: at the
home's own actuated values that mode is the home itself, whatever the passive coordinates
(a quaternion and its negative, two Euler readings of one rotation are one pose)."""

import numpy as np
import pytest

import parakin

MECHANISMS = [n for n in parakin.available() if n not in ("sphere2r",)]


@pytest.mark.parametrize("name", MECHANISMS)
def test_forward_pose_without_a_guess_at_home_is_the_home_pose(name):
    m = parakin.load(name, backend="numpy")
    home = np.asarray(m.platform_pose(m.home_actuated, m.home_passive))
    solved = m.forward_pose(m.home_actuated)
    assert solved.converged
    size = max(1.0, float(np.abs(home[:3, 3]).max()))
    assert np.abs(solved.pose[:3, :3] - home[:3, :3]).max() < 1e-8, name
    assert np.abs(solved.pose[:3, 3] - home[:3, 3]).max() < 1e-8 * size, name
