"""Drawings on given axes: 2-D axes draw planar mechanisms in the x-y plane; a drawing that
leaves the plane z = const needs 3-D axes and says so (issue 18, item 17)."""

import matplotlib
import numpy as np
import pytest

import parakin

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def planar_names() -> list[str]:
    """Mechanisms whose pose kind keeps the platform in the plane z = 0 (and that can draw)."""
    kinds = ("planar", "planar_translation")
    return [
        n
        for n in parakin.available()
        if parakin.metadata(n).pose_kind in kinds and parakin.metadata(n).capabilities.drawing is not None
    ]


@pytest.mark.parametrize("name", planar_names())
def test_planar_mechanisms_draw_on_2d_axes(name):
    """`m.plot(state, ax=<2-D axes>)` once raised AttributeError (set_zlabel); each polyline is
    drawn with the x and y of the drawing kernel's points."""
    m = parakin.load(name, backend="numpy")
    state = m.forward_pose(m.home_actuated)
    figure, ax = plt.subplots()
    try:
        assert m.plot(state, ax=ax) is ax
        lines = ax.get_lines()
        drawing = m.capabilities.drawing
        assert len(lines) == len(drawing.polylines)
        points = m.drawing(state)
        for line, vertices in zip(lines, drawing.polylines.values(), strict=True):
            expected = np.stack([points[s][:, i] for s, i in vertices], axis=-1)
            np.testing.assert_allclose(line.get_xdata(), expected[0])
            np.testing.assert_allclose(line.get_ydata(), expected[1])
        assert ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    finally:
        plt.close(figure)


def test_a_spatial_drawing_on_2d_axes_is_refused_naming_3d_axes():
    m = parakin.load("spm", backend="numpy")
    state = m.forward_pose(m.home_actuated)
    figure, ax = plt.subplots()
    try:
        with pytest.raises(parakin.BadInputError, match=r"the drawing of spm spans .* m in z: it needs 3-D axes"):
            m.plot(state, ax=ax)
        assert ax.get_lines() == []  # refused before drawing anything
    finally:
        plt.close(figure)
    figure = plt.figure()
    try:
        ax3 = figure.add_subplot(projection="3d")
        assert m.plot(state, ax=ax3) is ax3 and len(ax3.get_lines()) == len(m.capabilities.drawing.polylines)
    finally:
        plt.close(figure)
