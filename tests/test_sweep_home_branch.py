"""A sweep's singularity distances are measured in the home's assembly mode by default (issue 32's
new-user review: a Hexaglide's sweep read branch 0, singular everywhere, as "the first valid"
branch, while its home is branch 21). The default must give the distance of the home
configuration itself (``parakin.singularity.type_ii_distance`` of the home's actuated and passive
values), here for a planar 3-RRR whose home is put in another assembly mode of the same pose."""

from __future__ import annotations

import numpy as np
import pytest

import parakin
from parakin.results import Configuration
from parakin.singularity import type_ii_distance
from parakin.studies.sweep import home_branch, sweep

pytest.importorskip("dask")
pytest.importorskip("xarray")


def test_the_default_branch_is_the_homes():
    m = parakin.load("planar_3rrr", backend="numpy")
    pose = m.platform_pose(m.home_actuated, m.home_passive)
    inverse = m.inverse_pose(pose, strict=False)
    assert inverse.valid.sum() >= 4
    # a home in another assembly mode of the same pose: the elbows of branch 5
    m.home_actuated, m.home_passive = inverse.actuated[5].copy(), inverse.passive[5].copy()
    assert home_branch(m) == 5
    expected = float(type_ii_distance(m, Configuration(m.home_actuated, m.home_passive, pose)))
    first = float(type_ii_distance(m, Configuration(inverse.actuated[0], inverse.passive[0], pose)))
    assert abs(first - expected) > 0.05 * expected  # the old default (the first valid) measured another mode
    coordinates = dict(
        zip(("x", "y", "phi"), (pose[0, -1], pose[1, -1], np.arctan2(pose[1, 0], pose[0, 0])), strict=True)
    )
    axes = {"x": [coordinates.pop("x")]}
    grid = sweep(m, ["type_ii_distance"], axes, fixed=coordinates, scheduler="synchronous", progress=False)
    assert grid["type_ii_distance"].values[0] == pytest.approx(expected, rel=1e-9)
    other = sweep(m, ["type_ii_distance"], axes, fixed=coordinates, branch=0, scheduler="synchronous", progress=False)
    assert other["type_ii_distance"].values[0] == pytest.approx(first, rel=1e-9)


def test_a_serial_chain_has_no_home_branch_to_prefer():
    assert home_branch(parakin.load("sphere2r", backend="numpy")) is None
