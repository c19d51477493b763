"""The sweep maps say what they show (issue 36, item 3): every axis with its unit (from the
manifest for actuated variables and parameters), and a legend entry for every region and line:
the near-singularity contour, the grey of unreachable poses (drawn cell by cell in exactly the
grey of its legend entry: it was a translucent contour fill, 0.88 against the legend's 0.85),
reachable/unreachable of a boolean map, hatched status codes."""

import numpy as np
import pytest

pytest.importorskip("dask")
matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from parakin.studies.atlas import MISSING_GREY, plot_sweep  # noqa: E402
from parakin.studies.sweep import sweep  # noqa: E402

AXES = {"x": np.linspace(-0.5, 0.5, 41), "y": np.linspace(-0.4, 0.6, 41)}


@pytest.fixture(scope="module")
def five_bar_map():
    return sweep("five_bar", ["reachable", "type_ii_distance"], AXES, backend="numpy", progress=False)


def _legend(ax) -> list[str]:
    return [text.get_text() for text in ax.get_legend().get_texts()]


def test_every_unreachable_cell_is_grey_and_named(five_bar_map):
    ax = plot_sweep(five_bar_map, "type_ii_distance")
    try:
        figure = ax.get_figure()
        figure.canvas.draw()
        pixels = np.asarray(figure.canvas.buffer_rgba())[..., :3].astype(int)
        unreachable = ~five_bar_map["reachable"].values
        # the five-bar's reachable set has holes around the base joints (|P - A_i| < b - a): the
        # grid's unreachable cells are the outside and those islands
        assert 300 < unreachable.sum() < 41 * 41 - 300
        grey = round(float(MISSING_GREY) * 255)
        checked = 0
        for i, j in zip(*np.nonzero(unreachable), strict=True):
            px, py = ax.transData.transform((AXES["x"][i], AXES["y"][j]))
            row, column = pixels.shape[0] - 1 - int(round(py)), int(round(px))
            assert np.abs(pixels[row, column] - grey).max() <= 3, (AXES["x"][i], AXES["y"][j], pixels[row, column])
            checked += 1
        assert checked == unreachable.sum()
        assert ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
        assert _legend(ax) == [
            "type_ii_distance = 0.02 (near a singularity)",
            "unreachable pose (no valid inverse branch)",
        ]
    finally:
        plt.close("all")


def test_a_boolean_map_names_both_regions(five_bar_map):
    ax = plot_sweep(five_bar_map, "reachable")
    try:
        assert _legend(ax) == ["reachable: true", "reachable: false"]
    finally:
        plt.close("all")


def test_actuated_axes_carry_the_manifests_units():
    ds = sweep(
        "five_bar", ["modes"], {"theta1": np.linspace(1.7, 2.0, 4), "theta2": np.linspace(1.1, 1.4, 3)},
        backend="numpy", progress=False,
    )  # fmt: skip
    assert ds["theta1"].attrs["units"] == "rad"  # five_bar's actuators are revolute
    ax = plot_sweep(ds, "modes")
    try:
        assert (ax.get_xlabel(), ax.get_ylabel()) == ("theta1 [rad]", "theta2 [rad]")
        curve = plot_sweep(ds.isel(theta2=0), "modes")
        assert curve.get_xlabel() == "theta1 [rad]" and curve.get_ylabel() == "modes"
    finally:
        plt.close("all")
