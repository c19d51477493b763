"""Pictures people can read (issue 36, item 6): a grid of modes names its inputs with their units
(degrees for revolute ones, not radians in brackets labelled "axes in m"), says what its axes
measure, labels every panel's axes, and no panel's title touches the tick or axis labels of the
panel above it (checked on the rendered figure's text boxes)."""

import math

import matplotlib
import numpy as np
import pytest

import parakin

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def _grid(name):
    m = parakin.load(name, backend="numpy")
    axes = m.plot(m.forward_pose_all(m.home_actuated), all_modes=True)
    return m, axes, axes[0].figure


def _boxes(figure, artists):
    renderer = figure.canvas.get_renderer()
    return [a.get_window_extent(renderer) for a in artists if a.get_visible() and a.get_text()]


@pytest.mark.parametrize("name", ["planar_3rpr", "spm"])
def test_a_grid_names_its_inputs_units_and_axes(name):
    m, axes, figure = _grid(name)
    try:
        title = figure.get_suptitle().replace("\u00a0", " ")
        home = m.home_actuated
        for variable, value in zip(m.manifest.actuated, home, strict=True):
            shown = f"{math.degrees(value):.2f}°" if variable.revolute else f"{value:.4g} {variable.unit}"
            assert f"{variable.name} = {shown}" in title, title
        assert "[" not in title and "(axes in m)" not in title
        sphere = m.manifest.pose_kind == "rotation"
        assert ("on the unit sphere" in title) == sphere and ("in m" in title) == (not sphere), title
        for ax in axes:
            names = [ax.get_xlabel(), ax.get_ylabel()] + ([ax.get_zlabel()] if hasattr(ax, "get_zlabel") else [])
            assert names[:2] == ["x", "y"] and all(names), names
    finally:
        plt.close(figure)


def test_row_titles_do_not_touch_the_panels_above():
    """planar_3rpr's six modes in two rows: each title of the second row clears every tick label
    and axis label of the first row (once they touched)."""
    _, axes, figure = _grid("planar_3rpr")
    try:
        figure.canvas.draw()
        columns = 3
        above = [ax for ax in axes[:columns]]
        below = [ax for ax in axes[columns:]]
        assert below, "the premise: two rows"
        labels = []
        for ax in above:
            labels += _boxes(figure, ax.get_xticklabels() + [ax.xaxis.label])
        titles = [box for ax in below for box in _boxes(figure, [ax.title])]
        lowest = min(box.y0 for box in labels)  # pixels from the bottom of the figure
        highest_title = max(box.y1 for box in titles)
        assert highest_title + 2 < lowest, (highest_title, lowest)
        overlaps = [(t, b) for t in titles for b in labels if t.overlaps(b)]
        assert not overlaps
    finally:
        plt.close(figure)
    assert np.isfinite(lowest)


def test_a_single_3d_drawing_keeps_its_axis_labels_inside_the_figure():
    """A GIF frame or a single drawing once clipped its z label at the right edge."""
    m = parakin.load("stewart", backend="numpy")
    ax = m.plot(m.forward_pose(m.home_actuated))
    figure = ax.figure
    try:
        figure.canvas.draw()
        renderer = figure.canvas.get_renderer()
        frame = figure.bbox
        for label, text in ((ax.xaxis.label, "x [m]"), (ax.yaxis.label, "y [m]"), (ax.zaxis.label, "z [m]")):
            box = label.get_window_extent(renderer)
            assert label.get_text() == text
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, text
    finally:
        plt.close(figure)
