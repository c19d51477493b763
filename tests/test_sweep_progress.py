"""A sweep's progress bar counts the grid's points, not dask's tasks or the store's chunks
(issue 36): a 7 x 5 grid cut into chunks of two rows ends at 35/35 points, in memory and into a
store, and a resumed store starts its bar at the points already recorded."""

import re

import numpy as np
import pytest

pytest.importorskip("dask")

from parakin.studies.sweep import sweep  # noqa: E402

AXES = {"x": np.linspace(-0.1, 0.1, 7), "y": np.linspace(0.2, 0.4, 5)}


def _final(err: str) -> str:
    """The bar's last state: tqdm redraws it with carriage returns."""
    return err.replace("\r", "\n").strip().splitlines()[-1]


def test_the_bar_of_a_sweep_in_memory_counts_points(capfd):
    done = sweep("five_bar", ["reachable"], AXES, chunk=10, progress=True, backend="numpy")
    last = _final(capfd.readouterr().err)
    assert done["reachable"].shape == (7, 5)
    assert "sweep of five_bar" in last and "35/35" in last and "point" in last, last


def test_the_bar_of_a_sweep_into_a_store_counts_points_and_resumes(capfd, tmp_path):
    store = tmp_path / "grid.zarr"
    first = sweep("five_bar", ["reachable"], AXES, chunk=10, progress=True, store=store, backend="numpy")
    last = _final(capfd.readouterr().err)
    assert first.attrs["chunks_computed"] == 4  # rows 2 + 2 + 2 + 1
    assert "35/35" in last and "point" in last and "chunk" not in last, last
    again = sweep("five_bar", ["reachable"], AXES, chunk=10, progress=True, store=store, backend="numpy")
    err = capfd.readouterr().err
    assert again.attrs["chunks_computed"] == 0
    # nothing left to compute: the bar goes at once to the points recorded, no chunk in between
    states = set(re.findall(r"(\d+)/35", err))
    assert states <= {"0", "35"} and "35/35" in _final(err), err
