"""A lower-mobility platform's inverse reads a pose onto the set it can reach (prs3: the height
and the tilt are controlled, the horizontal position and the turn about the vertical follow): the
configurations it returns must carry the pose they reach, not the pose asked for (a new-user
review found ``inverse_pose(pose).branch(k)`` pairing prs3's joint values with the requested
pose, 2.5e-3 rad and 2.5e-4 m away from where those joints put the platform)."""

from __future__ import annotations

import numpy as np
import pytest

import parakin
from parakin.errors import UnreachablePoseError


def test_prs3_configurations_carry_the_pose_they_reach():
    m = parakin.load("prs3", backend="numpy")
    home = m.platform_pose(m.home_actuated, m.home_passive)
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(12):
        offset = parakin.pose_from_xyz_euler(np.concatenate([rng.uniform(-0.02, 0.02, 3), rng.uniform(-0.1, 0.1, 3)]))
        asked = home @ offset
        inverse = m.inverse_pose(asked, strict=False)
        assert np.abs(inverse.pose - asked).max() > 1e-5  # off the reachable set: parasitic motion
        # what the actuators control is kept: the height and the tilt n = R^T k
        assert abs(inverse.pose[2, 3] - asked[2, 3]) < 1e-12
        assert np.abs(inverse.pose[2, :3] - asked[2, :3]).max() < 1e-12
        for k in np.flatnonzero(inverse.valid):
            state = inverse.branch(int(k))
            assert np.abs(m.platform_pose(state.actuated, state.passive) - state.pose).max() < 1e-12
            assert np.abs(m.loop_closure(state.actuated, state.passive)["residual"]).max() < 1e-12
            checked += 1
    assert checked >= 48


def test_a_platform_of_full_mobility_keeps_the_pose_asked_for():
    m = parakin.load("stewart", backend="numpy")
    asked = m.platform_pose(m.home_actuated, m.home_passive) @ parakin.pose_from_xyz_euler([0.01, 0, 0.02, 0, 0.05, 0])
    assert np.array_equal(m.inverse_pose(asked).pose, asked)


def test_a_pose_off_the_reachable_set_names_the_option_that_reads_it_on():
    m = parakin.load("rps3", backend="numpy")
    tilted = parakin.pose_from_xyz_euler([0.0, 0.0, 1.0, 0.0, 0.2, 0.0])
    with pytest.raises(UnreachablePoseError, match=r"onto_reachable=True\) \(--onto-reachable\)") as caught:
        m.inverse_pose(tilted)
    assert "joint limits" not in str(caught.value)  # no joint limit failed: not named
