"""InversePose.branch takes a branch index in [0, n_branches) and names any other (issue 36: every
bad input gets a named error in the user's terms; it was a bare IndexError or, for -1, silently
the last branch)."""

import numpy as np
import pytest

import parakin


def test_a_branch_index_out_of_range_is_named():
    m = parakin.load("five_bar", backend="numpy")
    branches = m.inverse_pose(m.platform_pose(m.home_actuated, m.home_passive))
    # the five-bar's two legs each have two elbow signs: four branches, 0 to 3
    assert branches.valid.shape[-1] == 4
    np.testing.assert_allclose(branches.branch(np.int64(3)).actuated, branches.actuated[3])
    for bad in (4, -1, 1.0, True):
        with pytest.raises(parakin.NoSuchModeError, match=r"branch index must be an integer in \[0, 4\)"):
            branches.branch(bad)
